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
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp
from debench.models import validation as val
from debench.models.buckling.eigen import negative_pivots
from debench.models.buckling.parameters import MU_REF, NeoHookean, Ogden, Plate
from debench.models.errors import ConvergenceError, require
from debench.models.materials import ngsolve_forms as ngf
from netgen.meshing import Element1D, Element2D, FaceDescriptor, MeshPoint, Pnt
from netgen.meshing import Mesh as NGMesh
from scipy.sparse.linalg import LinearOperator, eigsh, splu

NEWTON_RTOL = 1e-11
"""Newton stops when the residual norm is below NEWTON_RTOL times its reference (the larger
of the first residual and the load residual of the undeformed section at the same voltage),
or below its round-off floor (NEWTON_FLOOR_FACTOR eps_mach || |K| |x| ||)."""
NEWTON_FLOOR_FACTOR = 100.0
NEWTON_STAGNATION_RTOL = 1e-8
"""A Newton step that cannot reduce the residual is accepted as converged only below this
residual relative to its reference: next to a singular tangent (the critical voltage of the
flat film) the correction is dominated by round-off along the near-null mode and the
residual stagnates at ~1e-10 .. 1e-9 of the load (measured); above it the step raises."""
NEWTON_MAXIT = 40
NEWTON_LOCAL_RTOL = 1e-4
"""Below this residual (relative to its reference) Newton takes full steps without the
descent test: inside the region of quadratic convergence a step may raise the residual at
round-off-affected levels and the next one still converges (measured for Ogden: 1.4e-7,
5.8e-5, 3.3e-9, 1.3e-8, 2.9e-15)."""
DV_MAX_REL = 0.05
"""Largest voltage correction of one deflection-controlled Newton step, relative to the
voltage (damped Newton)."""
EIG_RTOL = 1e-10
"""Backward error ``||S x - lam M x|| / (||K_uu||_inf ||x|| + |lam| ||M x||)`` every returned
eigenpair must reach (its round-off floor is ~1e-16; ARPACK's shift-invert iteration gives
1e-15 .. 1e-13 here)."""
EIG_COUNT_MARGIN = 1e-6
"""Relative margin (to the largest computed |lambda|; at least two are computed, so the scale
is a separated eigenvalue even when the lowest is at zero) below the lowest computed
eigenvalue at which the inertia count certifies it: far above the eigenvalue error (1e-13 of
the scale) and far below the gaps between the modes (1e-1 of the scale)."""
SHIFT_BENDING = 0.1
"""Default eigen-shift, in units of the bending scale (t0/a)^2 of the pencil, below zero."""
EIG_ARPACK_TOL = 1e-13
"""ARPACK's convergence tolerance of the Ritz values (relative)."""
EIG_MAXIT = 3000
EIG_NCV = 12
"""Lanczos basis size of ARPACK (its default 2k+1 restarts often: 80 operator applications
for one eigenvalue against ~25 with 12, measured)."""
DIRECT_RTOL = 1e-3
"""A Newton solve whose relative residual exceeds this after iterative refinement raises
(breakdown: a zero pivot gives O(1) or non-finite residuals). The sparse LU gives 1e-15 ..
1e-12 on these matrices, but loses digits next to the critical voltage, where the tangent is
singular by definition (measured 4e-8): an inexact Newton correction that still converges,
which the nonlinear residual decides."""
REFINEMENTS = 4
REFINE_RTOL = 1e-13
"""Iterative refinement stops below this relative residual (two orders above round-off)."""
MAX_ORDER = 12
TANGENTS = ("coupled", "frozen_potential", "initial_stress")
MAX_LAYERS = 30


@dataclass(frozen=True)
class AxisymDiscretisation:
    """Tensor-product mesh of the meridian section and its polynomial order.

    In R: ``n_r`` equal elements on ``[0, a - edge_zone t0]`` and ``edge_layers`` geometric
    layers (ratio ``grading``) on the rim zone ``[a - edge_zone t0, a]``, the smallest next to
    the rim. Through the thickness: ``n_z`` elements, whose two outer ones are split into
    ``face_layers`` geometric layers (ratio ``grading``) towards each face, so that the
    elements next to the two clamped corners (R, Z) = (a, 0), (a, t0) shrink geometrically in
    both directions (the hp-refinement of corner singularities, Babuska & Guo 1986).
    ``order``: polynomial order of every field (H1, quadrilaterals). ``ogden_delta``: the
    numerical parameter of the library's Ogden evaluation (error O(delta^2)).
    """

    order: int = 6
    n_r: int = 10
    n_z: int = 2
    edge_zone: float = 1.0
    edge_layers: int = 6
    face_layers: int = 6
    grading: float = 0.25
    ogden_delta: float = 1e-3

    def __post_init__(self):
        val.integer_at_least("order", self.order, 1)
        require(self.order <= MAX_ORDER, f"order = {self.order} must be <= {MAX_ORDER}")
        val.integer_at_least("n_r", self.n_r, 1)
        val.integer_at_least("n_z", self.n_z, 1)
        val.in_range("edge_zone", self.edge_zone, 0.0, 100.0, lo_open=True)
        for name in ("edge_layers", "face_layers"):
            v = getattr(self, name)
            val.integer_at_least(name, v, 0)
            require(v <= MAX_LAYERS, f"{name} = {v} must be <= {MAX_LAYERS}")
        val.in_range("grading", self.grading, 0.0, 1.0, lo_open=True, hi_open=True)
        val.in_range("ogden_delta", self.ogden_delta, 0.0, 0.1, lo_open=True, hi_open=True)


def _graded(length: float, layers: int, ratio: float) -> np.ndarray:
    """Offsets ``length * ratio^k`` (k = layers .. 0) and 0, ascending: geometric layers
    towards 0 (the last element [0, length ratio^layers])."""
    return np.concatenate([[0.0], length * ratio ** np.arange(layers, -1, -1)])


def section_nodes(plate: Plate, disc: AxisymDiscretisation) -> tuple[np.ndarray, np.ndarray]:
    """Node coordinates in R and Z of the tensor-product mesh (m)."""
    a, t0 = plate.radius, plate.thickness
    zone = min(disc.edge_zone * t0, 0.5 * a)
    r_in = np.linspace(0.0, a - zone, disc.n_r + 1)
    r_edge = a - _graded(zone, disc.edge_layers, disc.grading)[::-1]
    r = np.unique(np.concatenate([r_in, r_edge]))
    hz = t0 / disc.n_z
    z_mid = np.linspace(hz, t0 - hz, max(disc.n_z - 1, 0)) if disc.n_z > 1 else np.zeros(0)
    if disc.n_z == 1:
        hz = 0.5 * t0
    z_bot = _graded(hz, disc.face_layers, disc.grading)
    z = np.unique(np.round(np.concatenate([z_bot, z_mid, t0 - z_bot]) / t0, 15) * t0)
    return r, z


def section_mesh(plate: Plate, disc: AxisymDiscretisation) -> ngs.Mesh:
    """NGSolve mesh of the meridian section, x = R, y = Z (flat: the imperfection enters
    through the map G0). Boundaries ``axis``, ``rim``, ``bottom``, ``top``."""
    r, z = section_nodes(plate, disc)
    m = NGMesh(dim=2)
    ids = np.empty((len(r), len(z)), dtype=object)
    for i, ri in enumerate(r):
        for j, zj in enumerate(z):
            ids[i, j] = m.Add(MeshPoint(Pnt(float(ri), float(zj), 0.0)))
    m.Add(FaceDescriptor(surfnr=1, domin=1, bc=1))
    m.SetMaterial(1, "film")
    for i in range(len(r) - 1):
        for j in range(len(z) - 1):
            m.Add(Element2D(1, [ids[i, j], ids[i + 1, j], ids[i + 1, j + 1], ids[i, j + 1]]))
    names = {1: "bottom", 2: "rim", 3: "top", 4: "axis"}
    for i in range(len(r) - 1):
        m.Add(Element1D([ids[i, 0], ids[i + 1, 0]], index=1))
        m.Add(Element1D([ids[i + 1, -1], ids[i, -1]], index=3))
    for j in range(len(z) - 1):
        m.Add(Element1D([ids[-1, j], ids[-1, j + 1]], index=2))
        m.Add(Element1D([ids[0, j + 1], ids[0, j]], index=4))
    for k, name in names.items():
        m.SetBCName(k - 1, name)
    return ngs.Mesh(m)


class _Factor:
    """Sparse symmetric-indefinite factorisation with iterative refinement.

    SuperLU in symmetric mode (minimum degree on A + A^T, diagonal pivots): 5-10x faster
    than its default column ordering on these saddle-point matrices (measured 0.46 s
    against 3.4 s at 24k DOFs), at the price of a first solve of relative residual ~1e-8
    that :data:`REFINEMENTS` steps of iterative refinement bring to round-off. A solve whose
    residual stays above :data:`DIRECT_RTOL` raises ConvergenceError (breakdown)."""

    def __init__(self, A: sp.spmatrix, what: str):
        self.A = sp.csc_matrix(A)
        self.what = what
        try:
            self.lu = splu(self.A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                           options={"SymmetricMode": True})
        except RuntimeError as exc:
            raise ConvergenceError(f"{what}: factorisation failed ({exc})") from exc

    def solve(self, b: np.ndarray, *, check: bool = True) -> np.ndarray:
        """``A^-1 b`` refined to REFINE_RTOL; ``check=False`` skips the breakdown test (for
        a caller that refines a larger system itself)."""
        b = np.asarray(b, dtype=float)
        x = self.lu.solve(b)
        nb = max(float(np.linalg.norm(b)), 1e-300)
        res = float(np.linalg.norm(self.A @ x - b)) / nb
        for _ in range(REFINEMENTS):
            if not (np.isfinite(res) and res > REFINE_RTOL):
                break
            x = x + self.lu.solve(b - self.A @ x)
            res = float(np.linalg.norm(self.A @ x - b)) / nb
        if not np.all(np.isfinite(x)) or (check and not res < DIRECT_RTOL):
            raise ConvergenceError(f"{self.what}: direct solve broke down (relative residual "
                                   f"{res:.2e}): singular matrix")
        return x


def _require_finite(r: np.ndarray, K: sp.spmatrix, what: str) -> None:
    """Raise ConvergenceError when the residual ``r`` or the tangent ``K`` of a Newton step
    is not finite: the iterate left the material's domain (e.g. an inverted element, where
    the energy is NaN), and no step from it can converge. Checked
    before any factorisation: SuperLU's pivot search does not see NaN entries, builds
    inconsistent supernodes and calls BLAS with negative sizes (OpenBLAS prints "On entry to
    DGEMV parameter number 2 had an illegal value" and skips the call) before it fails."""
    if not (np.all(np.isfinite(r)) and np.all(np.isfinite(K.data))):
        raise ConvergenceError(f"{what}: non-finite residual or tangent (the state left the "
                               f"material's domain)")


def _mat3(rows) -> ngs.CoefficientFunction:
    return ngs.CoefficientFunction(tuple(c for row in rows for c in row), dims=(3, 3))


def _vec3(c) -> ngs.CoefficientFunction:
    return ngs.CoefficientFunction(tuple(c))


def _coo(mat, n: int) -> sp.csr_matrix:
    r, c, v = mat.COO()
    return sp.csr_matrix((np.asarray(v), (np.asarray(r), np.asarray(c))), shape=(n, n))


@dataclass(frozen=True)
class ModeSpectrum:
    """Lowest eigenvalues of the condensed tangent of wavenumber ``n`` at one state.

    ``lam`` ascending; ``residual``: the largest relative eigen-residual; ``below``: the
    inertia count of eigenvalues below ``lam[0] - margin`` (zero: certified lowest);
    ``ndof``: unknowns of the perturbation problem; ``modes``: eigenvectors (free
    displacement DOFs, columns)."""

    n: int
    lam: np.ndarray
    residual: float
    below: int
    margin: float
    ndof: int
    modes: np.ndarray = field(repr=False, default_factory=lambda: np.zeros((0, 0)))


class AxisymModel:
    """The axisymmetric film: nonlinear state on the section, spectra per wavenumber.

    ``plate``, ``material`` (library neo-Hookean or Ogden), ``disc``; ``with_imperfection``
    lifts the reference body by the plate's axisymmetric imperfection (the non-axisymmetric
    ``wrinkle_imperfection`` of :class:`Plate` has no place in this model and is refused).
    ``mu_ref``: the normalising modulus.
    """

    def __init__(self, plate: Plate, material: NeoHookean | Ogden,
                 disc: AxisymDiscretisation | None = None, *, with_imperfection: bool = True,
                 mu_ref: float = MU_REF):
        val.instance("plate", plate, Plate)
        val.instance("material", material, (NeoHookean, Ogden))
        disc = AxisymDiscretisation() if disc is None else disc
        val.instance("disc", disc, AxisymDiscretisation)
        require(plate.wrinkle_imperfection == 0.0,
                "plate.wrinkle_imperfection must be 0 for the axisymmetric model (a "
                "non-axisymmetric seed is no body of revolution)")
        self.plate, self.material, self.disc = plate, material, disc
        self.mu_ref = float(val.positive("mu_ref", mu_ref))
        self.with_imperfection = bool(with_imperfection)
        self.mesh = section_mesh(plate, disc)
        self.R = ngs.x
        a, t0 = plate.radius, plate.thickness
        amp = plate.imperfection * t0 if with_imperfection else 0.0
        # G0^-1 of the lift: (R, Z) -> (R, Z + w0(R)), w0' = -4 amp R/a^2 (1 - R^2/a^2)
        self.w0p = -4.0 * amp * ngs.x / a**2 * (1.0 - ngs.x**2 / a**2)
        self._amp = amp
        p = disc.order
        Ur = ngs.H1(self.mesh, order=p, dirichlet="axis|rim")
        Uz = ngs.H1(self.mesh, order=p, dirichlet="rim")
        P = ngs.H1(self.mesh, order=p, dirichlet="top|bottom")
        self.X = Ur * Uz * P
        (ur, uz, pp), _ = self.X.TnT()
        F, E = self._state_kinematics(ur, uz, pp)
        self.a = ngs.BilinearForm(self.X, symmetric=False)
        self.a += ngs.Variation((self._enthalpy(F, E) * self.R).Compile() * ngs.dx)
        self.gf = ngs.GridFunction(self.X)
        self.free = np.array(self.X.FreeDofs(), dtype=bool)
        nu = Ur.ndof + Uz.ndof
        self.is_u = np.zeros(self.X.ndof, dtype=bool)
        self.is_u[:nu] = True
        lift = ngs.GridFunction(self.X)
        lift.components[2].Set(ngs.y)
        self._linear = np.array(lift.vec.FV(), copy=True)   # p = Z, u = 0: uniform field
        self.v = 0.0
        self.stats = {"newton_steps": 0, "assemble_s": 0.0, "solve_s": 0.0, "eig_s": 0.0,
                      "eigen_analyses": 0}
        self.last_newton = {"iterations": 0, "residual": float("nan"),
                            "residual_rel": float("nan")}
        self._forms: dict[int, tuple] = {}

    # --------------------------------------------------------------- kinematics
    def _ginv(self):
        w = self.w0p
        return _mat3([[1, 0, 0], [0, 1, 0], [-w, 0, 1]])

    def _state_kinematics(self, ur, uz, pp):
        """F and E_L (scaled) of an axisymmetric state (module docstring)."""
        R = self.R
        Gx = _mat3([[1 + ngs.grad(ur)[0], 0, ngs.grad(ur)[1]],
                    [0, 1 + ur / R, 0],
                    [self.w0p + ngs.grad(uz)[0], 0, 1 + ngs.grad(uz)[1]]])
        F = Gx * self._ginv()
        E = -(self._ginv().trans * _vec3((ngs.grad(pp)[0], 0, ngs.grad(pp)[1])))
        return F, E

    def _enthalpy(self, F, E):
        mat = self.material
        kw = {"delta": self.disc.ogden_delta} if isinstance(mat, Ogden) else {}
        return (ngf.mechanical_energy_cf(mat, F, **kw) / self.mu_ref
                + ngf.ideal_dielectric_enthalpy(F, E, eps=1.0))

    # --------------------------------------------------------------- state
    @property
    def ndof(self) -> int:
        return self.X.ndof

    def set_voltage(self, v: float) -> None:
        """Impose the normalised voltage ``v`` on the top electrode (bottom grounded); the
        potential changes by the uniform field of the voltage change (the predictor)."""
        v = float(val.finite("v", v))
        x = self.gf.vec.FV().NumPy()
        x += (v - self.v) * self._linear
        self.v = v

    def reset(self) -> None:
        """The undeformed film at zero voltage."""
        self.gf.vec[:] = 0.0
        self.v = 0.0

    def state(self) -> np.ndarray:
        return np.array(self.gf.vec.FV(), copy=True)

    def set_state(self, x: np.ndarray) -> None:
        self.gf.vec.FV().NumPy()[:] = x

    def residual_norm(self) -> float:
        """Euclidean norm of the residual on the free DOFs at the current state."""
        return float(np.linalg.norm(self._residual()[self.free]))

    def _residual(self) -> np.ndarray:
        r = self.gf.vec.CreateVector()
        self.a.Apply(self.gf.vec, r)
        return np.array(r.FV(), copy=True)

    def _tangent(self) -> sp.csr_matrix:
        t = time.perf_counter()
        self.a.AssembleLinearization(self.gf.vec)
        K = _coo(self.a.mat, self.ndof)
        self.stats["assemble_s"] += time.perf_counter() - t
        return K

    def _load_scale(self) -> float:
        """Residual of the undeformed section at the current voltage (scale of the load)."""
        x = self.state()
        y = np.where(self.free, 0.0, x)
        self.set_state(y)
        r0 = float(np.linalg.norm(self._residual()[self.free]))
        self.set_state(x)
        return r0

    def newton(self, *, rtol: float = NEWTON_RTOL, maxit: int = NEWTON_MAXIT,
) -> int:
        """Equilibrate the state at the current voltage (full Newton with the exact tangent,
        damped by halving when a step does not reduce the residual). Stops on the residual
        relative to its reference or at its round-off floor; raises ConvergenceError when
        neither is reached in ``maxit`` steps."""
        rtol = val.tolerance("rtol", rtol)
        maxit = val.integer_at_least("maxit", maxit, 1)
        fr = self.free
        ref = max(self._load_scale(), 1e-300)
        r = self._residual()
        rn = float(np.linalg.norm(r[fr]))
        ref = max(ref, rn)
        for it in range(maxit + 1):
            K = self._tangent()
            _require_finite(r[fr], K, f"AxisymModel.newton at v = {self.v:.8g} (step {it})")
            x = self.state()
            floor = NEWTON_FLOOR_FACTOR * np.finfo(float).eps * float(
                np.linalg.norm((abs(K) @ np.abs(x))[fr]))
            if rn <= rtol * ref or rn <= floor:
                self.last_newton = {"iterations": it, "residual": rn,
                                    "residual_rel": rn / ref}
                return it
            if it == maxit:
                break
            dx = self._solve(K[fr][:, fr], -r[fr])
            step = 1.0
            for _ in range(12):
                y = x.copy()
                y[fr] += step * dx
                self.set_state(y)
                rt = self._residual()
                rtn = float(np.linalg.norm(rt[fr]))
                # full steps in the local phase (the residual non-monotone there at
                # the 1e-7 level, measured for the Ogden evaluation); halving before it
                if np.isfinite(rtn) and (rtn < rn * (1.0 - 1e-4 * step) or rtn <= floor
                                         or rn <= NEWTON_LOCAL_RTOL * ref):
                    break
                step *= 0.5
            else:
                self.set_state(x)
                if rn <= NEWTON_STAGNATION_RTOL * ref:
                    self.last_newton = {"iterations": it, "residual": rn,
                                        "residual_rel": rn / ref}
                    return it
                raise ConvergenceError(
                    f"AxisymModel.newton: no descent at v = {self.v:.8g} (residual {rn:.3e}, "
                    f"relative {rn / ref:.3e})")
            r, rn = rt, rtn
            self.stats["newton_steps"] += 1
        raise ConvergenceError(f"AxisymModel.newton: residual {rn:.3e} (relative "
                               f"{rn / ref:.3e}) after {maxit} steps at v = {self.v:.8g}")

    def _solve(self, A: sp.spmatrix, b: np.ndarray) -> np.ndarray:
        t = time.perf_counter()
        x = _Factor(A, f"AxisymModel.newton at v = {self.v:.8g}").solve(b)
        self.stats["solve_s"] += time.perf_counter() - t
        return x

    # --------------------------------------------------------------- deflection control
    def _centre_dof(self) -> int:
        """DOF of u_z at the top-surface centre (R, Z) = (0, t0): a mesh vertex, where the
        hierarchical H1 basis has only its vertex function non-zero."""
        t0 = self.plate.thickness
        for k, vert in enumerate(self.mesh.vertices):
            x, y = vert.point
            if abs(x) < 1e-12 * t0 and abs(y - t0) < 1e-12 * t0:
                return self.X.components[0].ndof + k
        raise RuntimeError("no mesh vertex at the top-surface centre")

    def newton_deflection(self, c: float, *, rtol: float = NEWTON_RTOL,
                          maxit: int = NEWTON_MAXIT) -> int:
        """Equilibrate at the prescribed centre deflection ``c`` (units of t0, the top-surface
        centre, :meth:`centre_deflection`), the voltage an unknown: Newton on the bordered
        system ``[[K_ff, K_fd dx_d/dv], [e_c^T, 0]]`` (regular at a voltage maximum, where
        K_ff is singular), solved by block elimination with iterative refinement of the
        bordered residual. Stops as :meth:`newton`; raises ConvergenceError otherwise."""
        c = float(val.finite("c", c))
        rtol = val.tolerance("rtol", rtol)
        maxit = val.integer_at_least("maxit", maxit, 1)
        fr = self.free
        k = self._centre_dof()
        kf = int(np.count_nonzero(fr[:k]))
        t0 = self.plate.thickness
        dirv = np.where(fr, 0.0, self._linear)       # d x / d v: the electrode values
        ref = max(self._load_scale(), 1e-300)
        for it in range(maxit + 1):
            r = self._residual()
            g = self.state()[k] - c * t0
            rn = float(np.linalg.norm(r[fr]))
            ref = max(ref, rn) if it == 0 else ref
            K = self._tangent()
            _require_finite(r[fr], K, f"AxisymModel.newton_deflection at c = {c:.6g} "
                                      f"(step {it})")
            floor = NEWTON_FLOOR_FACTOR * np.finfo(float).eps * float(
                np.linalg.norm((abs(K) @ np.abs(self.state()))[fr]))
            if (rn <= rtol * ref or rn <= floor) and abs(g) <= 1e-12 * t0:
                self.last_newton = {"iterations": it, "residual": rn, "residual_rel": rn / ref}
                return it
            if it == maxit:
                break
            Kff = K[fr][:, fr]
            b = (K @ dirv)[fr]
            rhs_x, rhs_g = -r[fr], -g
            try:
                dx, dv = self._bordered_by_blocks(Kff, b, kf, rhs_x, rhs_g, c)
            except ConvergenceError:
                # K_ff singular to working precision: at the voltage maximum itself, where
                # the bordered system is regular -- factorise it whole, with pivoting
                nf = Kff.shape[0]
                e = sp.csr_matrix(([1.0], ([0], [kf])), shape=(1, nf))
                B = sp.bmat([[Kff, sp.csr_matrix(b[:, None])], [e, None]]).tocsc()
                try:
                    sol = splu(B).solve(np.concatenate([rhs_x, [rhs_g]]))
                except RuntimeError as exc:
                    raise ConvergenceError(f"AxisymModel.newton_deflection at c = {c:.6g}: "
                                           f"bordered system singular ({exc})") from exc
                res = float(np.linalg.norm(B @ sol - np.concatenate([rhs_x, [rhs_g]])))
                if not (np.all(np.isfinite(sol))
                        and res <= DIRECT_RTOL * max(float(np.linalg.norm(rhs_x)), 1e-300)):
                    raise
                dx, dv = sol[:nf], float(sol[nf])
            # damping: a voltage correction above DV_MAX_REL of the voltage is a step
            # outside the linearisation's reach (the deflection responds to the voltage
            # steeply near the critical voltage): take the part of it that stays inside
            damp = min(1.0, DV_MAX_REL * max(abs(self.v), 1e-3) / max(abs(dv), 1e-300))
            dx, dv = damp * dx, damp * dv
            x = self.state()
            x[fr] += dx
            x[~fr] += dv * self._linear[~fr]
            self.set_state(x)
            self.v += dv
            self.stats["newton_steps"] += 1
        raise ConvergenceError(f"AxisymModel.newton_deflection: residual {rn:.3e} (relative "
                               f"{rn / ref:.3e}) after {maxit} steps at c = {c:.6g}")

    @staticmethod
    def _bordered_by_blocks(Kff, b, kf, rhs_x, rhs_g, c):
        """Solve ``[[Kff, b], [e_kf^T, 0]] (dx, dv) = (rhs_x, rhs_g)`` by block elimination
        with one factorisation of Kff and iterative refinement of the bordered residual."""
        fac = _Factor(Kff, f"AxisymModel.newton_deflection at c = {c:.6g}")
        dx, dv = np.zeros(Kff.shape[0]), 0.0
        y2 = fac.solve(b, check=False)
        for _ in range(REFINEMENTS + 1):
            ex = rhs_x - (Kff @ dx + b * dv)
            eg = rhs_g - dx[kf]
            y1 = fac.solve(ex, check=False)
            ddv = (y1[kf] - eg) / y2[kf]
            dx += y1 - ddv * y2
            dv += ddv
            if np.linalg.norm(ex) <= REFINE_RTOL * max(np.linalg.norm(rhs_x), 1e-300):
                break
        return dx, dv

    # --------------------------------------------------------------- point values
    def _at(self, comp: int, r: float, z: float) -> float:
        return float(self.gf.components[comp](self.mesh(r, z)))

    def centre_deflection(self) -> float:
        """Vertical displacement of the top-surface centre / t0 (as the 3D model's)."""
        t0 = self.plate.thickness
        return self._at(1, 0.0, t0) / t0

    def centre_thickness(self) -> float:
        """Current thickness at the centre / t0."""
        t0 = self.plate.thickness
        return 1.0 + (self._at(1, 0.0, t0) - self._at(1, 0.0, 0.0)) / t0

    def centre_field(self) -> float:
        """Normalised nominal-thickness-free true field v t0 / (current centre thickness):
        the field of a uniform film with the centre's thickness."""
        return self.v / self.centre_thickness()

    # --------------------------------------------------------------- perturbations
    def _mode_space(self, n: int):
        p = self.disc.order
        if n == 0:
            dirs = ("axis|rim", "axis|rim", "rim", "top|bottom")        # U, V, W, Q
        elif n == 1:
            dirs = ("axis|rim", "rim", "axis|rim", "axis|top|bottom")   # S, D, W, Q
        else:
            dirs = ("axis|rim", "axis|rim", "axis|rim", "axis|top|bottom")
        spaces = [ngs.H1(self.mesh, order=p, dirichlet=d) for d in dirs]
        Y = spaces[0] * spaces[1] * spaces[2] * spaces[3]
        return Y, [s.ndof for s in spaces]

    def _mode_forms(self, n: int, tangent: str = "coupled"):
        """Bilinear forms (Hessian at the state, mass) of wavenumber n: of the enthalpy
        (``"coupled"``, ``"frozen_potential"``), or the initial-stress form (:meth:`spectrum`)."""
        if (n, tangent) in self._forms:
            return self._forms[(n, tangent)]
        Y, sizes = self._mode_space(n)
        (a1, a2, W, Q), (b1, b2, bw, _) = Y.TnT()
        g = ngs.grad
        if n == 1:       # S = U + V, D = U - V
            U, V = 0.5 * (a1 + a2), 0.5 * (a2 - a1)
            gU, gV = 0.5 * (g(a1) + g(a2)), 0.5 * (g(a2) - g(a1))
            Ut, Vt = 0.5 * (b1 + b2), 0.5 * (b2 - b1)
        else:
            U, V, gU, gV, Ut, Vt = a1, a2, g(a1), g(a2), b1, b2
        R = self.R
        ur, uz, pp = self.gf.components
        Gx0 = _mat3([[1 + g(ur)[0], 0, g(ur)[1]], [0, 1 + ur / R, 0],
                     [self.w0p + g(uz)[0], 0, 1 + g(uz)[1]]])
        gi = self._ginv()
        E0 = -(gi.trans * _vec3((g(pp)[0], 0, g(pp)[1])))
        dGc = _mat3([[gU[0], 0, gU[1]], [0, (U + n * V) / R, 0], [g(W)[0], 0, g(W)[1]]])
        dGs = _mat3([[0, -(n * U + V) / R, 0], [gV[0], 0, gV[1]], [0, -n * W / R, 0]])
        dEc = -(gi.trans * _vec3((g(Q)[0], 0, g(Q)[1])))
        dEs = _vec3((0, n * Q / R, 0))
        if tangent == "initial_stress":
            # material stiffness of the unloaded film + the stress stiffness of the total
            # second Piola-Kirchhoff stress S = F^-1 dOmega/dF of the state
            F0 = (Gx0 * gi).MakeVariable()
            S0 = ngs.Inv(F0) * self._enthalpy(F0, E0).Diff(F0)
            mat = self.material
            kw = {"delta": self.disc.ogden_delta} if isinstance(mat, Ogden) else {}
            energy = 0
            for dG in (dGc, dGs):
                dF = dG * gi
                energy = energy + (ngf.mechanical_energy_cf(mat, ngs.Id(3) + dF, **kw)
                                   / self.mu_ref
                                   + 0.5 * ngs.InnerProduct(S0, dF.trans * dF))
            energy = energy + 0 * Q * Q         # the potential block is unused
        else:
            energy = (self._enthalpy((Gx0 + dGc) * gi, E0 + dEc)
                      + self._enthalpy((Gx0 + dGs) * gi, E0 + dEs))
        k = ngs.BilinearForm(Y, symmetric=False)
        k += ngs.Variation((energy * R).Compile() * ngs.dx)
        m = ngs.BilinearForm(Y, symmetric=False)
        m += (U * Ut + V * Vt + W * bw) / self.plate.thickness**2 * R * ngs.dx
        m.Assemble()
        free = np.array(Y.FreeDofs(), dtype=bool)
        is_u = np.zeros(Y.ndof, dtype=bool)
        is_u[: sum(sizes[:3])] = True
        out = (Y, k, _coo(m.mat, Y.ndof), free, is_u)
        self._forms[(n, tangent)] = out
        return out

    def mode_blocks(self, n: int) -> np.ndarray:
        """Block index (0: U or S, 1: V or D, 2: W, 3: Q) of each free DOF of the
        wavenumber-n perturbation problem, in the order of :meth:`mode_matrices`."""
        Y, _, _, free, _ = self._mode_forms(val.integer_at_least("n", n, 0))
        sizes = [Y.components[k].ndof for k in range(4)]
        return np.repeat(np.arange(4), sizes)[free]

    def axis_fixed_blocks(self, n: int) -> set[int]:
        """The blocks of the wavenumber-n perturbation whose every DOF on the axis is fixed
        (the axis regularity conditions, module docstring)."""
        Y, _, _, free, _ = self._mode_forms(val.integer_at_least("n", n, 0))
        out, start = set(), 0
        for k in range(4):
            sp_k = Y.components[k]
            on_axis = np.array(sp_k.GetDofs(self.mesh.Boundaries("axis")), dtype=bool)
            if not np.any(free[start:start + sp_k.ndof][on_axis]):
                out.add(k)
            start += sp_k.ndof
        return out

    def mode_matrices(self, n: int, tangent: str = "coupled"):
        """(K, M, iu, ip): the saddle-point tangent of wavenumber ``n`` at the current state
        on its free DOFs, the mass on the displacement DOFs, and the masks of the
        displacement and potential DOFs among the free ones (``tangent``: see
        :meth:`spectrum`)."""
        n = val.integer_at_least("n", n, 0)
        val.choice("tangent", tangent, TANGENTS)
        Y, k, M, free, is_u = self._mode_forms(n, tangent)
        t = time.perf_counter()
        zero = ngs.GridFunction(Y)
        k.AssembleLinearization(zero.vec)
        K = _coo(k.mat, Y.ndof)
        self.stats["assemble_s"] += time.perf_counter() - t
        K, M = K[free][:, free].tocsc(), M[free][:, free].tocsc()
        iu = is_u[free]
        return K, M, iu, ~iu

    def spectrum(self, n: int, nev: int = 3, *, sigma: float | None = None,
                 tangent: str = "coupled") -> ModeSpectrum:
        """Lowest ``nev`` eigenvalues of ``S_n x = lam M_n x`` at the current state.

        ``tangent``: ``"coupled"`` -- the condensed tangent at fixed electrode voltage
        ``S = K_uu - K_up K_pp^-1 K_pu``; ``"frozen_potential"`` -- ``K_uu``, the tangent at
        fixed potential (the field does not redistribute with the mode); ``"initial_stress"``
        -- the classical linear buckling operator: the material stiffness of the unloaded
        film plus the stress stiffness ``int S : (dF^T dF)`` of the state's total second
        Piola-Kirchhoff stress (mechanical + Maxwell).

        Shift-invert Lanczos (ARPACK) about ``sigma`` (default: a shift below the spectrum
        found by inertia counts, so the returned eigenvalues are the algebraically lowest);
        each solve ``(S - sigma M)^-1`` is one solve with the shifted saddle-point tangent.
        Certified by an inertia count: no eigenvalue lies below ``lam[0] - margin``
        (ConvergenceError otherwise, and when an eigen-residual exceeds EIG_RTOL)."""
        nev = val.integer_at_least("nev", nev, 1)
        t = time.perf_counter()
        K, M, iu, ip = self.mode_matrices(n, tangent)
        Mu = M[iu][:, iu]
        nu = int(iu.sum())
        require(nev < nu - 1, f"nev = {nev} must be < {nu - 1} (displacement DOFs)")
        Kuu = K[iu][:, iu]
        if tangent == "coupled":
            Kup, Kpp = K[iu][:, ip], K[ip][:, ip].tocsc()
            lu_pp = _Factor(Kpp, "AxisymModel.spectrum (potential block)")
            npp = negative_pivots(Kpp)
            require(npp == Kpp.shape[0], "AxisymModel.spectrum: the potential block is not "
                                         "negative definite (no dielectric saddle point)")

            def S(x):
                x = np.asarray(x).reshape(nu, -1)
                return Kuu @ x - Kup @ np.column_stack(
                    [lu_pp.solve(c) for c in np.asarray(Kup.T @ x).T])
        else:
            K, M, npp = Kuu.tocsc(), Mu, 0
            iu = np.ones(nu, dtype=bool)

            def S(x):
                return Kuu @ np.asarray(x).reshape(nu, -1)

        def count_below(s):
            return negative_pivots((K - s * _embed(Mu, iu)).tocsc()) - npp

        idx_u = np.flatnonzero(iu)
        nf = K.shape[0]
        rng = np.random.default_rng(0)
        A = LinearOperator((nu, nu), matvec=lambda x: S(x).ravel(), dtype=float)

        def solve_about(s):
            lu = _Factor(K - s * _embed(Mu, iu), "AxisymModel.spectrum (shifted tangent)")

            def opinv(b):
                rhs = np.zeros(nf)
                rhs[idx_u] = np.asarray(b).ravel()
                return lu.solve(rhs)[idx_u]

            OP = LinearOperator((nu, nu), matvec=opinv, dtype=float)
            w, V = eigsh(A, k=max(nev, 2), M=Mu, sigma=s, OPinv=OP, which="LM",
                         v0=rng.standard_normal(nu), tol=EIG_ARPACK_TOL, maxiter=EIG_MAXIT,
                         ncv=max(2 * nev + 1, EIG_NCV))
            order = np.argsort(w)
            return w[order], V[:, order]

        user = sigma is not None
        # default shift: below zero by a tenth of the bending scale (t0/a)^2 of the
        # normalised pencil (the lowest bending eigenvalues of the unloaded film are
        # ~0.3 (t0/a)^2), so that the shifted tangent stays regular at a critical state
        sigma = (-SHIFT_BENDING * (self.plate.thickness / self.plate.radius) ** 2
                 if sigma is None else float(val.finite("sigma", sigma)))
        w, V = solve_about(sigma)
        margin = EIG_COUNT_MARGIN * max(float(np.max(np.abs(w))), 1e-300)
        below = count_below(float(w[0]) - margin)
        if below and not user:
            # eigenvalues below the ones nearest zero: shift below the whole spectrum (found
            # by inertia counts) and take the lowest from there
            step = max(abs(float(w[0])), margin)
            sigma = float(w[0])
            for _ in range(80):
                sigma -= step
                if count_below(sigma) == 0:
                    break
                step *= 2.0
            else:
                raise ConvergenceError("AxisymModel.spectrum: no shift below the spectrum")
            w, V = solve_about(sigma)
            margin = EIG_COUNT_MARGIN * max(float(np.max(np.abs(w))), 1e-300)
            below = count_below(float(w[0]) - margin)
        SV, MV = S(V), Mu @ V
        norm_s = float(sp.linalg.norm(Kuu, np.inf))
        res = np.linalg.norm(SV - MV * w, axis=0) / (
            norm_s * np.linalg.norm(V, axis=0) + np.abs(w) * np.linalg.norm(MV, axis=0))
        if not np.all(res < EIG_RTOL):
            raise ConvergenceError(f"AxisymModel.spectrum(n={n}): eigen-residuals {res}")
        if below:
            raise ConvergenceError(f"AxisymModel.spectrum(n={n}): {below} eigenvalue(s) below "
                                   f"the lowest computed {w[0]:.6g}")
        w, V, res = w[:nev], V[:, :nev], res[:nev]
        self.stats["eig_s"] += time.perf_counter() - t
        self.stats["eigen_analyses"] += 1
        return ModeSpectrum(n=n, lam=w, residual=float(np.max(res)), below=below,
                            margin=margin, ndof=K.shape[0], modes=V)


def _embed(Mu: sp.spmatrix, iu: np.ndarray) -> sp.csc_matrix:
    """``Mu`` (displacement DOFs) placed in the free-DOF matrix (zero potential block)."""
    P = sp.csr_matrix((np.ones(int(iu.sum())), (np.flatnonzero(iu), np.arange(int(iu.sum())))),
                      shape=(len(iu), int(iu.sum())))
    return (P @ Mu @ P.T).tocsc()


__all__ = ["AxisymCritical", "AxisymDiscretisation", "AxisymModel", "Crossing", "ModeSpectrum",
           "PathPoint", "TANGENTS", "critical_voltage", "follow_path", "section_mesh",
           "section_nodes", "zero_crossing"]


CRITICAL_STEP = 1e-6
"""The secant on lambda_1(v^2) = 0 stops evaluating when its next step would be below
CRITICAL_STEP relative (closer to the singular tangent than that, the Newton solves of the
flat state lose digits); the root is then the inverse quadratic interpolation through the
last three evaluations, whose error is of the order of the product of their distances to
the root (< 1e-12 here) and is estimated by its difference from the secant root."""


@dataclass(frozen=True)
class AxisymCritical:
    """Bifurcation of the perfect flat film in wavenumber ``n``: lambda_1(S_n(v)) = 0.

    ``v``: normalised critical voltage of this discretisation (to ``vtol``); ``thickness``:
    centre thickness / t0 of the flat state at ``v``; ``e``: normalised true field at the
    centre; ``lam``: the lowest eigenvalue at ``v`` (zero to the secant's accuracy);
    ``eig_residual``: its backward error; ``newton_residual_rel``: the last Newton residual
    relative to its reference; ``iterations``: secant steps; ``ndof`` (state) and
    ``ndof_mode`` (perturbation problem); ``order``; ``cpu_s``: process CPU time of the
    solve; ``history``: the (v, lambda_1) evaluated.
    """

    n: int
    v: float
    tangent: str
    thickness: float
    e: float
    lam: float
    eig_residual: float
    newton_residual_rel: float
    iterations: int
    ndof: int
    ndof_mode: int
    order: int
    cpu_s: float
    vtol: float
    history: tuple = field(default=())


def critical_voltage(plate: Plate, material: NeoHookean | Ogden,
                     disc: AxisymDiscretisation | None = None, *, n: int = 0,
                     v_start: float | None = None, maxit: int = 30,
                     tangent: str = "coupled") -> AxisymCritical:
    """Critical normalised voltage of the perfect clamped film in wavenumber ``n``.

    The flat state (rim clamped, the nonlinear pre-buckling state with the rim's
    constraint of the thickness change) is equilibrated at each trial voltage; the
    algebraically smallest eigenvalue of the condensed tangent of wavenumber ``n`` is
    driven to zero by the secant method in ``v^2`` (the prestress grows as v^2), started at
    0.9 and 1.0 times ``v_start`` (default: the Kirchhoff plate estimate
    :func:`~debench.models.buckling.analytic.critical_voltage_plate`). The final state is
    certified: no eigenvalue of wavenumber ``n`` below the one driven to zero (so ``v`` is
    the first crossing of that wavenumber, not a higher mode's).

    Accuracy contract: ``v`` is the zero of this discretisation's lowest eigenvalue to within
    ``tangent`` (:meth:`AxisymModel.spectrum`) chooses the stability operator: the coupled
    tangent at fixed voltage (the definition of the critical voltage), or the frozen-potential
    or initial-stress operator (the classical methods it is compared with).

    ``vtol``, the difference between the inverse-quadratic and the secant roots of the last
    evaluations (:data:`CRITICAL_STEP`). The final state is certified by the inertia count
    of every spectrum (:meth:`AxisymModel.spectrum`). The discretisation error
    is measured by the p- and grading-sequences of the studies, not here. Raises
    ConvergenceError when the secant does not converge in ``maxit`` steps.
    """
    from debench.models.buckling.analytic import critical_voltage_plate

    n = val.integer_at_least("n", n, 0)
    maxit = val.integer_at_least("maxit", maxit, 1)
    val.choice("tangent", tangent, TANGENTS)
    t_cpu = time.process_time()
    model = AxisymModel(plate, material, disc, with_imperfection=False)
    v0 = critical_voltage_plate(material, plate.aspect) if v_start is None else float(
        val.positive("v_start", v_start))
    hist: list[tuple[float, float]] = []

    last: dict = {}

    def lam_at(x):
        # each trial voltage from the undeformed film: continuing from the previous state
        # carries its round-off along the near-null buckling mode into the next state
        # (measured: lambda_1 of +-2e-6 at one voltage), while Newton from the undeformed
        # film reaches the symmetric flat state in one or two steps
        model.reset()
        model.set_voltage(math.sqrt(x))
        model.newton()
        spec = model.spectrum(n, nev=1, tangent=tangent)
        hist.append((math.sqrt(x), float(spec.lam[0])))
        last.update(residual=spec.residual, ndof=spec.ndof,
                    newton=model.last_newton["residual_rel"])
        return spec

    xs = [(0.9 * v0) ** 2, v0**2]
    ls = [float(lam_at(x).lam[0]) for x in xs]
    for it in range(maxit):
        if ls[-1] == ls[-2]:
            raise ConvergenceError(f"critical_voltage(n={n}): flat secant: {hist}")
        x_new = xs[-1] - ls[-1] * (xs[-1] - xs[-2]) / (ls[-1] - ls[-2])
        if not (x_new > 0 and math.isfinite(x_new)):
            raise ConvergenceError(f"critical_voltage(n={n}): secant left the domain: {hist}")
        if abs(x_new - xs[-1]) < CRITICAL_STEP * xs[-1] and len(xs) >= 3:
            x_iqi = _inverse_quadratic_root(xs[-3:], ls[-3:])
            return AxisymCritical(
                n=n, v=math.sqrt(x_iqi), tangent=tangent, thickness=model.centre_thickness(),
                e=model.centre_field(), lam=ls[-1], eig_residual=last["residual"],
                newton_residual_rel=last["newton"], iterations=it + 2,
                ndof=model.ndof, ndof_mode=last["ndof"], order=model.disc.order,
                cpu_s=time.process_time() - t_cpu,
                vtol=abs(math.sqrt(x_iqi) - math.sqrt(x_new)), history=tuple(hist))
        xs.append(x_new)
        ls.append(float(lam_at(x_new).lam[0]))
    raise ConvergenceError(f"critical_voltage(n={n}): no convergence in {maxit} steps: {hist}")


def _inverse_quadratic_root(xs, ls) -> float:
    """Root of x(lambda) by inverse quadratic interpolation through three (x, lambda) points
    (Lagrange in lambda at lambda = 0)."""
    (x0, x1, x2), (l0, l1, l2) = xs, ls
    if len({l0, l1, l2}) < 3:
        raise ConvergenceError("inverse quadratic interpolation: repeated eigenvalues")
    return (x0 * l1 * l2 / ((l0 - l1) * (l0 - l2)) + x1 * l0 * l2 / ((l1 - l0) * (l1 - l2))
            + x2 * l0 * l1 / ((l2 - l0) * (l2 - l1)))


@dataclass(frozen=True)
class PathPoint:
    """One converged state of the imperfect film: centre deflection ``w`` (top surface, t0),
    normalised voltage ``v``, centre thickness / t0, normalised true centre field ``e``, the
    lowest eigenvalue of each recorded wavenumber (``lam[n]``, fixed voltage), and the
    Newton residual relative to its reference."""

    w: float
    v: float
    thickness: float
    e: float
    lam: dict
    newton_residual_rel: float
    state: np.ndarray = field(repr=False, default_factory=lambda: np.zeros(0))


def _record(model: AxisymModel, wavenumbers) -> PathPoint:
    lam = {int(n): float(model.spectrum(int(n), nev=1).lam[0]) for n in wavenumbers}
    return PathPoint(w=model.centre_deflection(), v=model.v, thickness=model.centre_thickness(),
                     e=model.centre_field(), lam=lam,
                     newton_residual_rel=model.last_newton["residual_rel"],
                     state=model.state())


ZERO_WTOL = 1e-9
"""The secant on lambda_n(w) = 0 stops when its step in the deflection is below ZERO_WTOL t0
(the voltage at a voltage maximum is stationary in w, so its error is second order)."""
ZERO_STALL_W = 1e-6
"""... or when it has stagnated at the eigenvalue's round-off floor: its last
ZERO_STALL_COUNT iterates all within ZERO_STALL_W t0 of each other without a step below
ZERO_WTOL. The floor: the Newton states carry round-off of ~1e-10 of the load next to the
near-singular tangent, which moves lambda_n by ~1e-11..1e-10; over its slope along the path
(1e-4..1e-3 per t0) that is 1e-7..1e-6 t0 in w (measured: an Ogden film at R/t0 = 20,
n = 6, iterates wandering within 1e-7 t0 at |lambda| ~ 5e-11). The crossing is then the
iterate with the smallest |lambda|, and ``wtol`` the spread of the stagnated iterates."""
ZERO_STALL_COUNT = 4
"""How many last iterates of the secant must lie within ZERO_STALL_W (and bracket the root)
for it to count as stagnated."""


@dataclass(frozen=True)
class Crossing:
    """Where the lowest eigenvalue of wavenumber ``n`` vanishes along the path: deflection
    ``w`` (t0), voltage ``v``, centre thickness; ``wtol`` the secant's last step. For n = 0
    this is the voltage maximum (pull-in)."""

    n: int
    w: float
    v: float
    thickness: float
    wtol: float


def zero_crossing(model: AxisymModel, points: list[PathPoint], n: int,
                  *, maxit: int = 30) -> Crossing | None:
    """The first zero of the wavenumber-n eigenvalue along a recorded path (None if it does
    not change sign there): secant in the deflection between the two recorded states that
    bracket the sign change, each trial state by deflection control from the nearer one."""
    n = val.integer_at_least("n", n, 0)
    pts = [p for p in points if n in p.lam]
    for a, b in zip(pts, pts[1:], strict=False):
        if a.lam[n] >= 0 > b.lam[n]:
            break
    else:
        return None
    ws, ls, states = [a.w, b.w], [a.lam[n], b.lam[n]], [(a.state, a.v), (b.state, b.v)]

    def lam_at(w_new):
        near = min(range(len(ws)), key=lambda k: abs(ws[k] - w_new))
        model.set_state(states[near][0])
        model.v = states[near][1]
        model.newton_deflection(w_new)
        lam = float(model.spectrum(n, nev=1).lam[0])
        states.append((model.state(), model.v))
        return lam

    k, wtol = secant_zero(lam_at, ws, ls, maxit=maxit, what=f"zero_crossing(n={n})")
    model.set_state(states[k][0])
    model.v = states[k][1]
    return Crossing(n=n, w=ws[k], v=model.v, thickness=model.centre_thickness(), wtol=wtol)


def secant_zero(f, ws: list[float], ls: list[float], *, maxit: int = 30,
                what: str = "secant_zero") -> tuple[int, float]:
    """Secant iteration for f(w) = 0 from the two points (``ws``, ``ls``), appending every
    evaluation to ``ws`` and ``ls``: returns (index of the answer in ``ws``, its tolerance).
    Stops when a step is below :data:`ZERO_WTOL` (the last iterate, tolerance the step) or
    when the iteration has stagnated at the round-off floor of f (the last
    :data:`ZERO_STALL_COUNT` iterates within :data:`ZERO_STALL_W` and f of both signs among
    them, so that they bracket the root: the one with the smallest |f|, tolerance their
    spread). ConvergenceError after ``maxit`` evaluations, or when two
    values of f are equal (a flat secant)."""
    for _ in range(maxit):
        if ls[-1] == ls[-2]:
            raise ConvergenceError(f"{what}: flat secant: {list(zip(ws, ls, strict=True))}")
        w_new = ws[-1] - ls[-1] * (ws[-1] - ws[-2]) / (ls[-1] - ls[-2])
        step = abs(w_new - ws[-1])
        lam = f(w_new)
        ws.append(w_new)
        ls.append(lam)
        if step < ZERO_WTOL:
            return len(ws) - 1, step
        last, signs = ws[-ZERO_STALL_COUNT:], np.sign(ls[-ZERO_STALL_COUNT:])
        if (len(ws) >= ZERO_STALL_COUNT + 2 and max(last) - min(last) < ZERO_STALL_W
                and signs.min() < 0 < signs.max()):
            tail = range(len(ws) - ZERO_STALL_COUNT, len(ws))
            return min(tail, key=lambda i: abs(ls[i])), max(last) - min(last)
    raise ConvergenceError(f"{what}: no convergence in {maxit} steps: "
                           f"{list(zip(ws, ls, strict=True))}")


def follow_path(model: AxisymModel, w_end: float, *, v_switch: float, dv: float = 0.01,
                dw0: float = 0.02, dw_max: float = 0.5, wavenumbers=(0, 1),
                record_every: float = 0.0, max_points: int = 2000,
                stop_past_maximum: bool = True, all_from: float = math.inf,
                all_wavenumbers=()) -> list[PathPoint]:
    """Equilibrium path of the imperfect film: voltage control up to ``v_switch`` (steps
    ``dv``), then centre-deflection control (:meth:`AxisymModel.newton_deflection`) up to
    ``w_end`` with adaptive steps (from ``dw0``, doubled after an easy step up to
    ``dw_max``, halved after a failed one, which is undone) and a secant predictor. Every
    converged state of the deflection branch is recorded with the lowest eigenvalue of each
    of ``wavenumbers`` (``record_every`` > 0: only states at least that far in w apart),
    from the deflection ``all_from`` on with those of ``all_wavenumbers`` too.
    With ``stop_past_maximum`` the path ends at the first recorded state whose wavenumber-0
    eigenvalue is negative (past the voltage maximum, where the tangent at fixed voltage
    turns indefinite), or, when the step falls below 1e-6 t0 on a falling voltage (past the
    maximum), at its last converged state. Raises ConvergenceError when the step falls
    below 1e-6 t0 otherwise."""
    v_switch = val.positive("v_switch", v_switch)
    w_end = val.finite("w_end", w_end)
    require(0 in tuple(wavenumbers) or not stop_past_maximum,
            "stop_past_maximum needs wavenumber 0 among the recorded wavenumbers")
    model.reset()
    for v in np.arange(dv, v_switch + 0.5 * dv, dv):
        model.set_voltage(float(v))
        model.newton()
    points = [_record(model, wavenumbers)]
    prev = None
    w, dw = model.centre_deflection(), dw0
    last_w_rec = w
    while w < w_end and len(points) < max_points:
        x0, v0 = model.state(), model.v
        target = min(w + dw, w_end)
        if prev is not None:            # secant predictor in the deflection
            xp, vp, wp = prev
            f = (target - w) / (w - wp)
            model.set_state(x0 + f * (x0 - xp))
            model.v = v0 + f * (v0 - vp)
        try:
            its = model.newton_deflection(target)
        except ConvergenceError:
            model.set_state(x0)
            model.v = v0
            dw *= 0.5
            if dw < 1e-6:
                if stop_past_maximum and prev is not None and v0 < prev[1]:
                    # past the voltage maximum the deflection-controlled tangent turns
                    # singular again (a further eigenvalue crossing): the path ends at its
                    # last converged state, recorded, whose wavenumber-0 eigenvalue shows
                    # whether the maximum was passed
                    points.append(_record(model, wavenumbers))
                    break
                raise
            continue
        prev, w = (x0, v0, _w_of(x0, model)), target
        if its <= 4:
            dw = min(2.0 * dw, dw_max)
        if record_every <= 0 or w - last_w_rec >= record_every or w >= w_end:
            ns = sorted(set(wavenumbers) | (set(all_wavenumbers) if w >= all_from else set()))
            points.append(_record(model, ns))
            last_w_rec = w
            if stop_past_maximum and points[-1].lam[0] < 0:
                break
    return points


def _w_of(x: np.ndarray, model: AxisymModel) -> float:
    return float(x[model._centre_dof()]) / model.plate.thickness
