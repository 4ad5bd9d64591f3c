"""Axisymmetric (body-of-revolution) finite-element model of the clamped buckling film (Ch. 5).

The film, its clamp, its electrodes and its imperfection are axisymmetric, so the
equilibrium path is a 2D problem on the meridian section ``0 <= R <= a``, ``0 <= Z <= t0``
and its stability about any state splits into angular wavenumbers ``n >= 0``: each a 2D
eigenproblem (Huang 1964, Fitch 1968, for clamped shallow caps). An independent second
discretisation of the 3D model of :mod:`debench.models.buckling.fem`: its own mesh
(tensor-product quadrilaterals, geometrically graded towards the rim and its two clamped
corners), its own kinematics and assembly, its own Newton and eigen-solver code; the
materials are those of the constitutive library (:mod:`debench.models.materials.ngsolve_forms`).

Kinematics (cylindrical components, re-derived). The reference body is the flat section
lifted by the imperfection, ``X = (R, Theta, Z + w0(R))`` with ``w0 = imperfection t0
(1 - R^2/a^2)^2`` (:class:`~debench.models.buckling.parameters.Plate`); the lift is the
exact map ``G0 = dX/d(R, Z)`` (a vertical shear, ``det G0 = 1``), so ``dV = R dR dTheta dZ``
exactly at every order. With axisymmetric displacements ``u_r(R, Z)``, ``u_z(R, Z)``, in
the order (r, theta, z):

    F = Gx G0^-1,   Gx = [[1 + u_r,R, 0, u_r,Z], [0, 1 + u_r/R, 0], [w0' + u_z,R, 0, 1 + u_z,Z]],

and the referential field ``E_L = -G0^-T (phi_R, 0, phi_Z)``. The state is the saddle point
of the electric enthalpy ``int Omega(F, E_L) R dR dZ`` (ideal dielectric (5.9) with the
partial Legendre transform, ``Omega = W_mech - eps/2 J C^-1 : E_L x E_L``), divided by
``mu_ref``, with the scaled potential ``p = phi sqrt(eps/mu_ref)``: the discrete problem
depends on eps only through the normalised voltage ``v = Phi/t0 sqrt(eps/mu_ref)``.

Boundary conditions: rim ``R = a`` clamped in every component (``u_r = u_z = 0`` and, in the
perturbations, ``u_theta = 0``); electrodes ``p = 0`` on ``Z = 0`` and ``p = v t0`` on
``Z = t0`` over the whole faces; the rim insulated (natural condition, zero normal
charge); the axis ``R = 0``: ``u_r = 0`` (regularity of the axisymmetric field).

Perturbations of wavenumber n (fixed voltage: the potential perturbation vanishes on both
electrodes)::

    u_r = U cos n theta,  u_theta = V sin n theta,  u_z = W cos n theta,  p = Q cos n theta.

``dF`` and ``dE_L`` are linear in (U, V, W, Q); their components split into a cos group
(rR, rZ, theta-theta, zR, zZ, E_R, E_Z) and a sin group (r-theta, theta-R, theta-Z,
z-theta, E_theta)::

    cos:  dGx_rR = U_R, dGx_rZ = U_Z, dGx_tt = (U + n V)/R, dGx_zR = W_R, dGx_zZ = W_Z,
          dE = -G0^-T (Q_R, ., Q_Z)
    sin:  dGx_rt = -(n U + V)/R, dGx_tR = V_R, dGx_tZ = V_Z, dGx_zt = -n W/R, dE_t = n Q/R

(``dF = dGx G0^-1``; ``Gx = dx/d(R, Z)`` is the gradient of the current position over the
flat section, so at u = 0 it is G0 and F = I). The second variation of the enthalpy,
integrated over theta, is
``pi (a(F0)[dF_c, dF_c] + a(F0)[dF_s, dF_s])`` for n >= 1 (cos^2 and sin^2 integrate to pi,
the cross terms to zero) and ``2 pi (...)`` for n = 0, with the mass ``pi (2 pi)
int (U^2 + V^2 + W^2) R dR dZ``; the common factor drops from the eigenvalues. The form
is assembled as the Hessian at zero of ``W(F0 + dF_c) + W(F0 + dF_s)``, so no cross term
between the groups can enter, whatever the material implementation's symmetry. For
n = 0 the cos group (U, W, Q) is the axisymmetric tangent and the sin group is torsion
(V alone): the two decouple exactly.

Axis regularity per n (single-valued, finite-energy fields at R = 0):

* n = 0: U = 0, V = 0 (W and Q free);
* n = 1: U + V = 0, W = 0, Q = 0 (the axis point may translate sideways): the unknowns
  are ``S = U + V`` (zero on the axis) and ``D = U - V`` (free);
* n >= 2: U = V = W = Q = 0.

Stability at fixed voltage is the sign of the lowest eigenvalue of the condensed tangent
``S_n = K_uu - K_up K_pp^-1 K_pu`` with the mass ``M_n`` (``K_pp`` is negative definite,
so the saddle-point tangent has ``dim p`` negative eigenvalues plus those of ``S_n``:
Haynsworth's inertia additivity, used to certify every eigenvalue by an inertia count).

The model in modules (this package re-exports the names a user calls, so
``from debench.models.buckling import axisym`` is the whole interface):

* :mod:`~debench.models.buckling.axisym.section` -- the discretisation and the mesh of
  the meridian section;
* :mod:`~debench.models.buckling.axisym.kinematics` -- the kinematics above as NGSolve
  coefficient functions;
* :mod:`~debench.models.buckling.axisym.linalg` -- the sparse factorisation with
  iterative refinement;
* :mod:`~debench.models.buckling.axisym.model` -- :class:`AxisymModel`: the state, Newton
  at a voltage and at a centre deflection, the point values;
* :mod:`~debench.models.buckling.axisym.spectra` -- the mode forms and the certified
  spectra per wavenumber;
* :mod:`~debench.models.buckling.axisym.critical` -- :func:`critical_voltage` of the flat
  film;
* :mod:`~debench.models.buckling.axisym.path` -- :func:`follow_path` and
  :func:`zero_crossing` along the path of the imperfect film.
"""

from debench.models.buckling.axisym.critical import AxisymCritical, critical_voltage
from debench.models.buckling.axisym.model import AxisymModel
from debench.models.buckling.axisym.path import (
    Crossing,
    PathPoint,
    follow_path,
    zero_crossing,
)
from debench.models.buckling.axisym.section import (
    AxisymDiscretisation,
    section_mesh,
    section_nodes,
)
from debench.models.buckling.axisym.spectra import TANGENTS, ModeSpectrum

__all__ = ["TANGENTS", "AxisymCritical", "AxisymDiscretisation", "AxisymModel", "Crossing",
           "ModeSpectrum", "PathPoint", "critical_voltage", "follow_path",
           "section_mesh", "section_nodes", "zero_crossing"]
