"""The circular actuator as a thin axisymmetric SOLID in (r, z) (NGSolve): the film thickness.

The membrane models (the analytic Chapter 3 model and :mod:`debench.models.circular.fe`)
are the limit of a vanishing thickness. This model keeps the thickness ``H`` (undeformed,
in units of R_A) and resolves the displacement and the electric potential through it, so
that the difference from the membrane can be measured as H -> 0.

Formulation
-----------
Reference domain: the undeformed film, (R, Z) in [0, R_B] x [0, H/2] (the upper half: the
film is symmetric about its mid-plane, the potential antisymmetric), axisymmetric measure
``2 pi R dR dZ`` (the constant 2 pi is dropped). Unknowns (quadrilaterals, Taylor-Hood):

* displacement ``(u_R, u_Z)``, continuous Q2;
  ``F = [[1 + u_R,R, u_R,Z, 0], [u_Z,R, 1 + u_Z,Z, 0], [0, 0, 1 + u_R/R]]`` (R, Z, theta);
* pressure ``p``, continuous Q1: the Lagrange multiplier of exact incompressibility
  (``+ p (J - 1)``; no bulk penalty, hence no volumetric locking; the Q2/Q1 pair is
  inf-sup stable);
* scaled potential ``psi`` (Q2) with ``phi = Phi psi / H``: ``psi = 0`` on the mid-plane,
  ``psi = H/2`` on the electrode (the top face over circle A, R < R_A); elsewhere on the top
  face no surface charge; the field also fringes into annulus B (the film is the only
  dielectric: no surrounding air).

Energy per unit mu (library forms :mod:`debench.models.materials.ngsolve_forms`)::

    w = W(F)/mu + p (J - 1) + Phibar^2 w_e,                                    (3.23)
    w_e = -1/2 (eps/eps_bar) J C^-1 : (Grad psi x Grad psi),                   (3.20), (5.13)
    eps/eps_bar = 1 + c (lambda_R + lambda_theta - 2),                         (3.27)

``W`` = the elastomer's
:meth:`~debench.models.materials.protocol.Material.mechanical_energy` (Gent (3.23) by
default, any library material with ``elastomer``; its volumetric part vanishes with its
first derivative at J = 1, where ``p`` holds the film), ``mu`` its shear modulus,
``w_e`` = :func:`~debench.models.materials.ngsolve_forms.ideal_dielectric_enthalpy` with
eps = eps/eps_bar, ``Phibar^2 = eps_bar Phi^2/(mu H^2)`` (Sec. 3.5);
``lambda_R = sqrt(C_RR)``, ``lambda_theta = 1 + u_R/R``. In a homogeneous state
(``psi = Z``, J = 1) ``w`` is :meth:`~debench.models.materials.membrane.GentMembrane.free_energy`
with ``I4 = Phibar^2`` (tested). The equations are the stationarity of ``int w R dR dZ``
in (u, p) and, at fixed u, of ``int w_e R dR dZ`` in psi (the electrostatics, regular at
Phibar = 0).

Boundary conditions: axis ``u_R = 0``; mid-plane ``u_Z = 0, psi = 0``; frame (3.38)
``u_R(R_B, Z) = (lamP - 1) R_B`` (u_Z free); top face traction free.

Load: pre-stretch first (the homogeneous state ``u = ((lamP - 1) R, (lamP^-2 - 1) Z)``
at Phibar = 0), then the stretch ``lam = 1 + u_R(R_A, 0)`` of the mid-plane at the electrode
edge is prescribed and ``Phibar^2`` is an unknown (bordered Newton,
:class:`debench.models.circular.fe_continuation.BorderedContinuation`), so that pull-in can
be passed.
Reported stretch of circle A: ``lam_centre`` = lambda_theta at the axis (mid-plane), the
homogeneous stretch of the membrane theory (:meth:`CircularSolidFE.at_centre_stretch`
finds the state at a given one); loss of tension: the thickness-averaged radial Cauchy
stress at the centre of circle A vanishes.

Mesh: ``nz`` element rows through the half thickness; radially, square elements
(size H/(2 nz)) at the electrode edge R = R_A, growing linearly away from it by
``grading`` per unit distance, up to 1/n_a in circle A and to the membrane FE's
ln-uniform size ln(R_B/R_A)/n_b in annulus B.

Accuracy contract: Newton as :mod:`~debench.models.circular.fe` (relative update 1e-10);
the discretisation error is that of the mesh. It is dominated by the electrode edge, where
the potential switches from Dirichlet to natural on the top face (a singular field) and
the stretch lambda_R drops from the value in circle A to that of the annulus over a width
~H: at H = 0.2, lamP = 3, centre stretch 4, Phibar moves by 4.4e-4 from nz = 1 to 2 and by
2.7e-4 from 2 to 4 (order ~0.7 in the edge element size), by 4e-7 from n_b = 10 to 20
and by 0 from n_a = 2 to 4. Because the mesh scales with H, this error is an edge-layer
term of order H like the thickness effect itself: the limit H -> 0 on a fixed ``nz`` is
the membrane (``verification/test_ch3_fe_thickness.py``).

Linear solves and Newton: the bordered tangent is a saddle-point matrix whose pressure
block is the mass matrix over the penalty: unscaled its condition is ~1e18 (~kappa^2;
1.7e14, 1.7e18, 1.7e22 at kappa = 1e3, 1e5, 1e7, H = 0.2), so that the pressure part of
an LU solve would be round-off and depend on SuperLU's pivot order (explicit zeros kept
in the structure, another column ordering). It is equilibrated by powers of two before
the factorisation (condition ~1e6, :func:`debench.models.circular.fe_continuation._factor`), and
Newton takes only steps that pass the natural monotonicity test
(:meth:`~debench.models.circular.fe_continuation.BorderedContinuation._newton`), so that a step
converges to the solution next to its predictor or is refused and shortened.

Limits: on under-resolved edge layers the branch folds in the edge stretch before loss
of tension (lamP = 3: the smallest singular value of the equilibrated bordered tangent
falls like sqrt(lam* - lam), 1.1e-6 at lam = 4.96 to 2.2e-7 at 4.975, H = 0.05, fold at
lam* = 4.9754, centre stretch 5.000; a mode of the top-surface nodes at the electrode
edge, where J departs from 1 by up to 9 % and lambda_R < 1); the continuation then
raises ConvergenceError. Where it occurs depends on the mesh, not monotonically on H or
``nz``. Prescribing u_R at a mid-plane node inside circle A (R = 0.55) instead of at R_A
stalls at the same state (H = 0.1, nz = 1: centre stretch 5.0704 both ways). A full
Newton from a step across the fold can wander (|dz| ~ 1e4) and land on another state
after tens of iterations, a landing that depends on round-off: the monotonicity test
refuses such steps.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import ngsolve as ng
import numpy as np
import scipy.sparse as sp
from debench.models import validation as v
from debench.models.materials import energies as E
from debench.models.materials import ngsolve_forms as forms
from debench.models.materials.protocol import Material
from netgen.meshing import Element1D, Element2D, MeshPoint, Pnt
from netgen.meshing import Mesh as NetgenMesh

from .fe_continuation import LAM_STEP, BorderedContinuation
from .params import film_elastomer

#: augmented-Lagrangian factor kappa/mu of the consistent term kappa/2 (J - 1)^2 (zero with
#: its derivative at J = 1): the Q2/Q1 multiplier enforces J = 1 only weakly, and at fixed
#: potential the electric enthalpy has curvature ~ -3 Phibar^2 lambda^6 along pointwise
#: J-violating modes (~1e4 near loss of tension at lamP = 3), which the term must dominate.
#: Phibar at lamP = 3, centre stretch 4 spreads by 2.4e-5 (H = 0.1, nz = 1) and 1.0e-4
#: (H = 0.2, nz = 2) over kappa = 1e4 .. 1e6 (verification/test_ch3_fe_thickness.py)
PENALTY = 1e5


@dataclass(frozen=True)
class SolidMesh:
    """Mesh of [0, R_B] x [0, H/2]: ``nz`` rows through the half thickness; radial sizes
    H/(2 nz) at R_A growing by ``grading`` per unit distance, capped at 1/n_a (circle A)
    and R ln(R_B/R_A)/n_b (annulus B); ``order`` of the displacement and potential (the
    pressure one lower)."""

    n_a: int = 4
    n_b: int = 20
    nz: int = 2
    grading: float = 0.3
    order: int = 2

    def __post_init__(self):
        v.integer_at_least("n_a", self.n_a, 1)
        v.integer_at_least("n_b", self.n_b, 2)
        v.integer_at_least("nz", self.nz, 1)
        v.in_range("grading", self.grading, 0.0, 2.0, lo_open=True)
        v.integer_at_least("order", self.order, 2)


@dataclass(frozen=True)
class SolidState:
    """An equilibrium of the solid on the rising branch: ``lam`` the controlled mid-plane
    stretch at R_A, ``lam_centre`` lambda_theta at the axis, ``phibar2`` = Phibar^2,
    ``dphibar2_dlam`` along ``lam``, ``sigma1A`` the thickness-averaged radial Cauchy stress
    per mu at the centre of circle A, ``x`` all nodal values."""

    lam: float
    lam_centre: float
    phibar2: float
    dphibar2_dlam: float
    sigma1A: float
    iterations: int
    residual: float
    x: np.ndarray = field(repr=False)
    #: d(free unknowns, Phibar^2)/dlam from the bordered tangent at this state (the Euler
    #: predictor of a continuation step from it; last entry ``dphibar2_dlam``)
    tangent: np.ndarray | None = field(default=None, repr=False, compare=False)

    @property
    def phibar(self) -> float:
        return math.sqrt(self.phibar2) if self.phibar2 >= 0 else math.nan


def radial_nodes(H: float, radius_ratio: float, mesh: SolidMesh) -> np.ndarray:
    """Radial node positions (see :class:`SolidMesh`); R_A = 1 is a node."""
    h0 = 0.5 * H / mesh.nz
    g = mesh.grading
    right, r = [1.0], 1.0
    while r < radius_ratio:
        h = min(h0 + g * (r - 1.0), r * math.log(radius_ratio) / mesh.n_b)
        r = r + h
        right.append(r)
    right[-1] = radius_ratio
    if right[-1] - right[-2] < 0.5 * (right[-2] - right[-3]):
        del right[-2]
    left, r = [1.0], 1.0
    while r > 0.0:
        r = r - min(h0 + g * (1.0 - r), 1.0 / mesh.n_a)
        left.append(r)
    left[-1] = 0.0
    if left[-2] < 0.5 * (left[-3] - left[-2]):
        del left[-2]
    return np.array(left[::-1] + right[1:])


def energy_parts(F, grad_psi, c: float, elastomer: Material):
    """``(W(F)/mu, w_e(F, Grad psi))`` of the library ``elastomer`` (shear modulus mu) as
    NGSolve CFs (module docstring); ``F`` a 3x3 CF in (R, Z, theta), ``grad_psi`` a
    3-vector CF."""
    wm = elastomer.mechanical_energy(F, xp=forms.NGSOLVE) / elastomer.shear_modulus
    C = F.trans * F
    eps = E.zhao_suo_permittivity(ng.sqrt(C[0, 0]), F[2, 2], eps_bar=1.0, c=c)
    we = forms.ideal_dielectric_enthalpy(F, grad_psi, eps=eps)
    return wm, we


def _F(ur, uz, R):
    gr, gz = ng.grad(ur), ng.grad(uz)
    return ng.CoefficientFunction((1 + gr[0], gr[1], 0, gz[0], 1 + gz[1], 0, 0, 0, 1 + ur / R),
                                  dims=(3, 3))


class CircularSolidFE(BorderedContinuation):
    """Thin axisymmetric solid model of the Chapter 3 actuator.

    Parameters
    ----------
    lamP
        Equibiaxial pre-stretch (3.38), >= 1 and below the Gent locking stretch.
    thickness
        Undeformed film thickness H/R_A, in (0, 1].
    c
        Zhao-Suo factor (3.27); 1 + c(2 lamP - 2) > 0 required.
    radius_ratio
        R_B/R_A > 1 (thesis: 15).
    Jm, elastomer
        The Gent parameter (3.23) of the default elastomer (120 when neither is given), or
        any library material instead (not both).
    mesh
        :class:`SolidMesh`.
    lam_step
        Continuation step and event grid in ``lam`` (> 0).
    """

    def __init__(self, lamP: float, thickness: float, c: float = 0.0, *,
                 radius_ratio: float = 15.0, Jm: float | None = None,
                 elastomer: Material | None = None, mesh: SolidMesh = SolidMesh(),
                 lam_step: float = LAM_STEP, penalty: float = PENALTY):
        self.penalty = v.positive("penalty", penalty)
        self.lamP = v.at_least("lamP", lamP, 1.0)
        self.H = v.in_range("thickness", thickness, 0.0, 1.0, lo_open=True)
        self.c = v.finite("c", c)
        self.radius_ratio = v.positive("radius_ratio", radius_ratio)
        if not (self.radius_ratio > 1 and math.isfinite(self.radius_ratio)):
            raise ValueError(f"radius_ratio RB/RA must be finite and > 1, got {radius_ratio}")
        self.elastomer = film_elastomer(self.lamP, Jm, elastomer)
        #: the pre-stretched film in (R, Z, theta)
        self._F0 = np.diag([self.lamP, self.lamP**-2, self.lamP])
        if not 1 + self.c * (2 * self.lamP - 2) > 0:
            raise ValueError(f"c = {self.c} makes the permittivity (3.27) non-positive at "
                             f"lamP = {self.lamP}: need 1 + c(2 lamP - 2) > 0")
        self.mesh_spec = v.instance("mesh", mesh, SolidMesh)
        self.lam_step = v.positive("lam_step", lam_step)
        ng.SetNumThreads(1)
        self._build()
        self._states: list[SolidState] = [self._reference_state()]

    # ------------------------------------------------------------------ set-up
    def _build(self):
        m, H = self.mesh_spec, self.H
        Rn = radial_nodes(H, self.radius_ratio, m)
        Zn = np.linspace(0.0, 0.5 * H, m.nz + 1)
        self.nodes = Rn
        ngm = NetgenMesh(dim=2)
        pid = [[ngm.Add(MeshPoint(Pnt(float(r), float(z), 0))) for z in Zn] for r in Rn]
        ia, ib = ngm.AddRegion("A", dim=2), ngm.AddRegion("B", dim=2)
        bc = {n: ngm.AddRegion(n, dim=1) for n in ("axis", "mid", "electrode", "top", "frame")}
        nr, nz = len(Rn) - 1, m.nz
        for i in range(nr):
            dom = ia if Rn[i + 1] <= 1.0 + 1e-12 else ib
            for j in range(nz):
                ngm.Add(Element2D(dom, [pid[i][j], pid[i + 1][j], pid[i + 1][j + 1],
                                        pid[i][j + 1]]))
            ngm.Add(Element1D([pid[i][0], pid[i + 1][0]], index=bc["mid"]))
            top = bc["electrode"] if Rn[i + 1] <= 1.0 + 1e-12 else bc["top"]
            ngm.Add(Element1D([pid[i + 1][nz], pid[i][nz]], index=top))
        for j in range(nz):
            ngm.Add(Element1D([pid[0][j + 1], pid[0][j]], index=bc["axis"]))
            ngm.Add(Element1D([pid[nr][j], pid[nr][j + 1]], index=bc["frame"]))
        self.mesh = ng.Mesh(ngm)
        k = m.order
        VR = ng.H1(self.mesh, order=k, dirichlet="axis|frame")
        VZ = ng.H1(self.mesh, order=k, dirichlet="mid")
        Q = ng.H1(self.mesh, order=k - 1)
        S = ng.H1(self.mesh, order=k, dirichlet="mid|electrode")
        self.fes = ng.FESpace([VR, VZ, Q, S])
        self.gf = ng.GridFunction(self.fes)
        ur, uz, p, psi = self.fes.TrialFunction()
        R = ng.x
        F = _F(ur, uz, R)
        gpsi = ng.CoefficientFunction((ng.grad(psi)[0], ng.grad(psi)[1], 0.0))
        wm, we = energy_parts(F, gpsi, self.c, self.elastomer)
        self._am = ng.BilinearForm(self.fes, symmetric=False)
        J = ng.Det(F)
        self._am += ng.Variation((wm + p * (J - 1) + 0.5 * self.penalty * (J - 1) ** 2)
                                 * R * ng.dx)
        self._ae = ng.BilinearForm(self.fes, symmetric=False)
        self._ae += ng.Variation(we * R * ng.dx)
        free = np.array(list(self.fes.FreeDofs()), dtype=bool)
        # the load: u_R at the mid-plane vertex of the electrode edge
        iv = [k for k, vx in enumerate(self.mesh.vertices)
              if abs(vx.point[0] - 1.0) < 1e-12 and abs(vx.point[1]) < 1e-14]
        self._i = self.fes.Range(0).start + VR.GetDofNrs(ng.NodeId(ng.VERTEX, iv[0]))[0]
        self._psi = np.arange(self.fes.Range(3).start, self.fes.Range(3).stop)
        self._E = np.nonzero(free)[0]
        self._F = self._E[self._E != self._i]
        self._tmp = self.gf.vec.CreateVector()
        self._Fgf = _F(self.gf.components[0], self.gf.components[1], R)
        #: the strain energy of the current state (admissible where it is finite)
        self._wm_state = self.elastomer.mechanical_energy(self._Fgf, xp=forms.NGSOLVE)

    def _reference_state(self) -> SolidState:
        """The pre-stretched film at zero voltage (homogeneous), psi = Z; the electrostatics
        and the pressure are then solved at lam = lamP."""
        ur, uz, p, psi = self.gf.components
        lP = self.lamP
        ur.Set((lP - 1) * ng.x)
        uz.Set((lP**-2 - 1) * ng.y)
        # P_ZZ + p dJ/dF_ZZ = 0, dJ/dF_ZZ = lP^2 (traction-free faces)
        P = self.elastomer.response(self._F0, np.zeros(3), second=False).P
        p.Set(-P[1, 1] / (lP**2 * self.elastomer.shear_modulus))
        psi.Set(ng.y)
        x = self.gf.vec.FV().NumPy().copy()
        x, p2, it, resid = self._newton(x, 0.0, self.lamP, monotone=False)
        return self._finish(x, p2, it, resid)

    # ------------------------------------------------------------------ assembly
    def _mat(self, form, x):
        """The linearisation of ``form`` at ``x`` as COO arrays (rows, cols, values)."""
        self.gf.vec.FV().NumPy()[:] = x
        form.AssembleLinearization(self.gf.vec)
        rows, cols, vals = form.mat.COO()
        return np.asarray(rows), np.asarray(cols), np.asarray(vals)

    def _system(self, x, p):
        """Residual: mechanical rows ``r_m + Phibar^2 r_e``, potential rows ``r_e``;
        and its derivative in Phibar^2 (remembered for the last (x, p))."""
        return self._cached_system(x, p, self._assemble_system)

    def _assemble_system(self, x, p):
        with np.errstate(all="ignore"):
            rm = self._vec(self._am, x)
            re = self._vec(self._ae, x)
        res = rm + p * re
        res[self._psi] = re[self._psi]
        dp = re.copy()
        dp[self._psi] = 0.0
        return res, dp

    def bordered(self, x, p):
        """The bordered matrix ``[J[E, F], dR/dPhibar^2[E]]`` (sparse, CSC) and the load
        column ``J[E, i]`` of the tangent ``J`` (mechanical rows ``J_m + Phibar^2 J_e``,
        potential rows ``J_e``), scattered straight from the two forms' COO values into
        a structure fixed at the first call (the sparsity of a form does not change)."""
        Jm = self._mat(self._am, x)
        Je = self._mat(self._ae, x)
        plan = self._scatter_plan(Jm, Je)
        _, dp = self._system(x, p)
        vals = np.concatenate([Jm[2][plan["m"]], Je[2][plan["e"]] * np.where(
            plan["e_psi"], 1.0, p), dp[self._E]])
        data = np.bincount(plan["slot"], weights=vals[plan["keep"]], minlength=plan["nnz"])
        M = sp.csc_matrix((data, plan["indices"], plan["indptr"]), shape=plan["shape"])
        # zeros out (the forms' structural zeros, cancellations): a smaller factorisation
        M.eliminate_zeros()
        col = np.bincount(plan["load_row"], weights=vals[plan["load"]],
                          minlength=len(self._E))
        return M, col

    def _scatter_plan(self, Jm, Je) -> dict:
        """Where each COO value of the two forms goes in the bordered matrix (computed
        once; the COO structure is checked against it at every call)."""
        plan = getattr(self, "_plan", None)
        if plan is not None:
            if not (np.array_equal(plan["rc"][0], Jm[0]) and np.array_equal(plan["rc"][1], Jm[1])
                    and np.array_equal(plan["rc"][2], Je[0])
                    and np.array_equal(plan["rc"][3], Je[1])):
                raise RuntimeError("the sparsity of the solid's tangent changed")
            return plan
        n = self.fes.ndof
        E, F = self._E, self._F
        row_of = np.full(n, -1)
        row_of[E] = np.arange(len(E))
        col_of = np.full(n, -1)
        col_of[F] = np.arange(len(F))
        is_psi = np.zeros(n, dtype=bool)
        is_psi[self._psi] = True
        km = (row_of[Jm[0]] >= 0) & ~is_psi[Jm[0]]          # psi rows: J_e alone
        ke = row_of[Je[0]] >= 0
        r = np.concatenate([row_of[Jm[0][km]], row_of[Je[0][ke]], np.arange(len(E))])
        c = np.concatenate([col_of[Jm[1][km]], col_of[Je[1][ke]], np.full(len(E), len(F))])
        # the load column i: entries with c == i (col_of = -1 there)
        load = np.concatenate([Jm[1][km] == self._i, Je[1][ke] == self._i,
                               np.zeros(len(E), dtype=bool)])
        keep = c >= 0
        key = c * len(E) + r                                 # column-major: CSC order
        uniq, slot = np.unique(key[keep], return_inverse=True)
        full_slot = np.full(len(key), -1)
        full_slot[keep] = slot
        indptr = np.searchsorted(uniq // len(E), np.arange(len(F) + 2))
        self._plan = plan = {
            "rc": (Jm[0], Jm[1], Je[0], Je[1]), "m": km, "e": ke,
            "e_psi": is_psi[Je[0][ke]], "slot": full_slot[keep], "nnz": len(uniq),
            "indices": uniq % len(E), "indptr": indptr, "shape": (len(E), len(F) + 1),
            "keep": keep, "load": load, "load_row": r[load]}
        return plan

    def _load_value(self, lam):
        return lam - 1.0          # u_R(R_A, 0) = (lam - 1) R_A

    def _load_column(self, J):
        return J                  # bordered returns the load column itself

    def _admissible(self, x) -> bool:
        """det F > 0 and a finite strain energy at the element centres."""
        self.gf.vec.FV().NumPy()[:] = x
        pts = self._sample_points()
        F = np.asarray(self._Fgf(pts)).reshape(-1, 3, 3)
        J = np.linalg.det(F)
        if not np.all(J > 0):
            return False
        with np.errstate(invalid="ignore"):   # Gent past its lock: the logarithm's NaN
            return bool(np.all(np.isfinite(self._wm_state(pts))))

    def _sample_points(self):
        if not hasattr(self, "_pts"):
            Rc = 0.5 * (self.nodes[1:] + self.nodes[:-1])
            Zc = (np.arange(self.mesh_spec.nz) + 0.5) * 0.5 * self.H / self.mesh_spec.nz
            RR, ZZ = np.meshgrid(Rc, Zc)
            self._pts = self.mesh(RR.ravel(), ZZ.ravel())
        return self._pts

    def at_centre_stretch(self, lam_centre: float) -> SolidState:
        """The state on the rising branch whose centre stretch (lambda_theta at the axis,
        the homogeneous stretch of circle A in the membrane theories) is ``lam_centre``
        (> lamP): bracketed on the continuation grid in the edge stretch ``lam`` and
        located by brentq to ROOT_XTOL in ``lam``. Raises ConvergenceError when the branch
        cannot be followed that far."""
        target = v.at_least("lam_centre", lam_centre, self.lamP)
        if target == self.lamP:
            return self.solve(self.lamP)
        # lam <= lam_centre on the rising branch (circle A stretches most at its centre),
        # so the crossing lies below lam = target + lam_step
        return self._first_root(lambda s: target - s.lam_centre, target + self.lam_step,
                                "centre stretch")

    # ------------------------------------------------------------------ post-processing
    def _finish(self, x, p, it, resid) -> SolidState:
        lam = float(1.0 + x[self._i])
        t = self._tangent(x, p)
        dp = float(t[-1])
        self.gf.vec.FV().NumPy()[:] = x
        return SolidState(lam=lam, lam_centre=self._centre_stretch(),
                          phibar2=float(p), dphibar2_dlam=dp,
                          sigma1A=self._centre_stress(p), iterations=it, residual=resid,
                          x=x, tangent=t)

    def _centre_stretch(self) -> float:
        """lambda_theta = 1 + u_R/R at the axis, mid-plane (= 1 + du_R/dR there)."""
        mp = self.mesh(0.0, 0.0)
        return float(1.0 + ng.grad(self.gf.components[0])[0](mp))

    def _centre_stress(self, p2) -> float:
        """Thickness average (Gauss-Legendre, 4 points per element row) of the radial
        Cauchy stress sigma_RR per mu at the centre of the first element column."""
        _, _, p, psi = self.gf.components
        R0 = 0.5 * self.nodes[1]
        xg, wg = np.polynomial.legendre.leggauss(4)
        hz = 0.5 * self.H / self.mesh_spec.nz
        Z = np.concatenate([(j + 0.5 * (xg + 1)) * hz for j in range(self.mesh_spec.nz)])
        W = np.tile(wg, self.mesh_spec.nz)
        pts = self.mesh(np.full(Z.shape, R0), Z)
        Fs = np.asarray(self._Fgf(pts)).reshape(-1, 3, 3)
        Gs = np.asarray(ng.grad(psi)(pts)).reshape(-1, 2)
        ps = np.asarray(p(pts)).ravel()
        sig = [self._cauchy_rr(Fk, Gk, pk, p2) for Fk, Gk, pk in zip(Fs, Gs, ps, strict=True)]
        return float(np.dot(W, sig) / W.sum())

    def _cauchy_rr(self, Fk, Gk, pk, p2) -> float:
        ev = self._stress_evaluator()
        for par, val in zip(ev["F"], Fk.ravel(), strict=True):
            par.Set(float(val))
        ev["g"][0].Set(float(Gk[0]))
        ev["g"][1].Set(float(Gk[1]))
        ev["p"].Set(float(pk))
        ev["p2"].Set(float(p2))
        P = np.asarray(ev["P"](self.mesh(0.5, 0.25 * self.H))).reshape(3, 3)
        sigma = P @ Fk.T / np.linalg.det(Fk)
        return float(sigma[0, 0])

    def _stress_evaluator(self) -> dict:
        if not hasattr(self, "_ev"):
            Fp = [ng.Parameter(0.0) for _ in range(9)]
            gp = [ng.Parameter(0.0) for _ in range(2)]
            pp, p2 = ng.Parameter(0.0), ng.Parameter(0.0)
            F = ng.CoefficientFunction(tuple(Fp), dims=(3, 3)).MakeVariable()
            wm, we = energy_parts(F, ng.CoefficientFunction((gp[0], gp[1], 0.0)),
                                  self.c, self.elastomer)
            W = wm + pp * (ng.Det(F) - 1) + p2 * we
            self._ev = {"F": Fp, "g": gp, "p": pp, "p2": p2, "P": W.Diff(F)}
        return self._ev

    def profile(self, state: SolidState, R, Z: float = 0.0) -> dict:
        """lambda_R = sqrt(C_RR), lambda_theta, J at radii R (0 < R <= R_B) and height Z."""
        R = np.atleast_1d(np.asarray(v.positive("R", R), dtype=float))
        self.gf.vec.FV().NumPy()[:] = state.x
        F = np.asarray(self._Fgf(self.mesh(R, np.full(R.shape, float(Z))))).reshape(-1, 3, 3)
        return {"lam1": np.sqrt(np.einsum("kij,kij->k", F[:, :, :1], F[:, :, :1])),
                "lam2": F[:, 2, 2], "J": np.linalg.det(F)}


__all__ = ["CircularSolidFE", "SolidMesh", "SolidState", "energy_parts", "radial_nodes"]
