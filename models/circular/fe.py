"""The whole circular actuator by axisymmetric finite elements (NGSolve), circle A + annulus B.

Formulation
-----------
An incompressible, axisymmetric, finite-strain membrane of reference radius R_B (lengths
in units of R_A), pre-stretched equibiaxially by ``lamP`` and held by a rigid frame
(3.38): ``r(R_B) = lamP R_B``, ``r(0) = 0``. The only unknown is the current radius
``r(R)`` on [0, R_B], discretised by continuous Lagrange elements of order ``order``; the
stretches are ``lambda1 = dr/dR``, ``lambda2 = r/R``, ``lambda3 = 1/(lambda1 lambda2)``.
Electrodes cover circle A (R < R_A) only: there the Lagrangian field through the thickness
is ``E_L = Phi/H``. The voltage-controlled equilibrium is a stationary point of the
potential energy per unit mu H::

    Pi[r] = int_0^R_B w(lambda1, lambda2; Phibar^2 chi_A) R dR,                   (3.20)
    w = Ws/mu - 1/2 (eps/eps_bar) lambda1^2 lambda2^2 Phibar^2,                   (3.23, 3.27)

with ``Phibar^2 = eps_bar Phi^2/(mu H^2)`` (Sec. 3.5) and ``chi_A`` the indicator of the
electrode. ``w`` is the library energy
:meth:`~debench.models.materials.membrane.ElastomerMembrane.free_energy` in units mu = 1,
eps_bar = 1, ``I4 = Phibar^2``: ``Ws`` is the elastomer's own ``mechanical_energy`` on
``J = 1`` (Gent (3.23) by default, any library material with ``elastomer``), evaluated as
NGSolve CoefficientFunctions (:func:`energy_cf`, tested equal to the numpy evaluation).

Why it is independent of (3.31)-(3.34)
--------------------------------------
No balance equation is written: NGSolve differentiates the discretised energy
symbolically (residual and tangent), and Newton's method finds its stationary points. No
ODE (neither the printed (3.33)-(3.34) nor the membrane balance d(R T1)/dR = T2) is formed
or integrated, circle A is not assumed homogeneous (it is meshed like annulus B; the closed
forms (3.28)-(3.30) are not used) and the interface R = R_A is only a mesh node where the
electrode ends: neither (3.31) nor (3.32) is imposed. Continuity of r gives (3.31); whether
the one-sided forces T1 agree, whether circle A stays homogeneous and which annulus
equilibrium the solutions obey are outputs.

Load control
------------
The stretch at R_A, ``lam = r(R_A)/R_A``, is the load parameter; ``Phibar^2`` is an
unknown (bordered Newton system), so that the rising branch is followed through the
pull-in maximum of Phibar. ``dPhibar^2/dlam`` comes from the same bordered tangent.

Accuracy contract
-----------------
Newton (:mod:`~debench.models.circular.fe_continuation`) stops when the update satisfies
``|dx|_inf <= STEP_RTOL (1 + |x|_inf)`` (:mod:`debench.models.numerics.newton`; after
quadratic convergence the residual is at round-off). The discretisation error is that of
the mesh (``n_a`` elements in circle A, ``n_b`` elements in annulus B uniform in ln R,
order ``order``); its observed order is measured in ``verification/test_ch3_fe.py``.
The model is the membrane limit (thickness t -> 0): the film thickness does not enter.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import ngsolve as ng
import numpy as np
from debench.models import validation as v
from debench.models.errors import ConvergenceError
from debench.models.materials import energies as E
from debench.models.materials import ngsolve_forms as ngf
from debench.models.materials.membrane import ElastomerMembrane, ZhaoSuoPermittivity
from debench.models.materials.protocol import Material
from debench.models.numerics.roots import bracketed_root
from netgen.meshing import Element0D, Element1D, MeshPoint, Pnt
from netgen.meshing import Mesh as NetgenMesh
from scipy.optimize import minimize_scalar

from .fe_continuation import LAM_STEP, BorderedContinuation
from .params import film_elastomer

#: the minimum of dPhibar^2/dlam (suppression search) is located to this in lam: at a
#: smooth minimum the value is then exact to ~(d3/dlam3) xtol^2 ~ 1e-12, far below the
#: Newton floor of the slope (~1e-10)
MIN_XTOL = 1e-6


@dataclass(frozen=True)
class FEMesh:
    """Mesh of [0, R_B] (units of R_A): ``n_a`` uniform elements in circle A, ``n_b``
    elements in annulus B uniform in ln R (graded towards the interface), Lagrange order
    ``order``."""

    n_a: int = 4
    n_b: int = 40
    order: int = 2

    def __post_init__(self):
        v.integer_at_least("n_a", self.n_a, 1)
        v.integer_at_least("n_b", self.n_b, 2)
        v.integer_at_least("order", self.order, 1)


@dataclass(frozen=True)
class FEState:
    """An equilibrium state on the rising branch.

    ``lam`` is r(R_A)/R_A; ``phibar2`` = Phibar^2 (negative: no real voltage holds it);
    ``dphibar2_dlam`` from the bordered tangent; ``T1A``, ``T1B`` the nominal radial stress
    per unit mu just inside and just outside R_A (one-sided element values, (3.17));
    ``sigma1A`` = lambda1 T1 at the centre of circle A; ``x`` the nodal values of r.
    """

    lam: float
    phibar2: float
    dphibar2_dlam: float
    T1A: float
    T1B: float
    sigma1A: float
    iterations: int
    residual: float
    x: np.ndarray = field(repr=False)
    #: d(free unknowns, Phibar^2)/dlam from the bordered tangent at this state (its last
    #: entry is ``dphibar2_dlam``): the Euler predictor of a continuation step from it
    tangent: np.ndarray | None = field(default=None, repr=False, compare=False)

    @property
    def phibar(self) -> float:
        return math.sqrt(self.phibar2) if self.phibar2 >= 0 else math.nan



class CircularFE(BorderedContinuation):
    """Finite-element model of the Chapter 3 actuator at one pre-stretch and one c.

    Parameters
    ----------
    lamP
        Equibiaxial pre-stretch (3.38), >= 1 and below the Gent locking stretch.
    c
        Zhao-Suo factor (3.27); 1 + c(2 lamP - 2) > 0 required.
    radius_ratio
        R_B/R_A > 1 (thesis: 15).
    Jm
        Gent parameter (3.23), > 0, of the default elastomer (VHB 4910's Gent, 120 when
        neither is given).
    elastomer
        Any library material instead of Gent (give ``Jm`` or ``elastomer``, not both): its
        strain energy on ``J = 1``
        (:class:`~debench.models.materials.membrane.ElastomerMembrane`) per unit its shear
        modulus is ``Ws/mu``; its permittivity is
        not used (the membrane's is (3.27) with ``c``).
    mesh
        :class:`FEMesh`.
    lam_step
        Continuation step in lam and the grid on which events are bracketed (> 0; halved
        automatically on a Newton failure). Events are located exactly on any grid; a
        grid coarser than the spacing of two events of the same kind may miss both.
    """

    def __init__(self, lamP: float, c: float = 0.0, *, radius_ratio: float = 15.0,
                 Jm: float | None = None, elastomer: Material | None = None,
                 mesh: FEMesh = FEMesh(), lam_step: float = LAM_STEP):
        self.lam_step = v.positive("lam_step", lam_step)
        self.lamP = v.at_least("lamP", lamP, 1.0)
        self.c = v.finite("c", c)
        self.radius_ratio = v.positive("radius_ratio", radius_ratio)
        if not (self.radius_ratio > 1 and math.isfinite(self.radius_ratio)):
            raise ValueError(f"radius_ratio RB/RA must be finite and > 1, got {radius_ratio}")
        elastomer = film_elastomer(self.lamP, Jm, elastomer)
        if not 1 + self.c * (2 * self.lamP - 2) > 0:
            raise ValueError(f"c = {self.c} makes the permittivity (3.27) non-positive at "
                             f"lamP = {self.lamP}: need 1 + c(2 lamP - 2) > 0")
        self.mesh_spec = v.instance("mesh", mesh, FEMesh)
        #: the membrane of the library elastomer (any units: the energy is divided by its
        #: shear modulus) with eps_bar = 1, so that I4 = Phibar^2
        self.material = ElastomerMembrane(
            elastomer, permittivity=ZhaoSuoPermittivity(eps_bar=1.0, c=self.c))
        ng.SetNumThreads(1)
        self._build()
        self._states: list[FEState] = [self._reference_state()]

    # ------------------------------------------------------------------ set-up
    def _build(self):
        m = self.mesh_spec
        RB = self.radius_ratio
        xa = np.linspace(0.0, 1.0, m.n_a + 1)
        xb = np.exp(np.linspace(0.0, math.log(RB), m.n_b + 1))
        xb[-1] = RB
        nodes = np.concatenate([xa, xb[1:]])
        self.nodes = nodes
        ngm = NetgenMesh(dim=1)
        pids = [ngm.Add(MeshPoint(Pnt(float(x), 0, 0))) for x in nodes]
        ia = ngm.AddRegion("A", dim=1)
        ib = ngm.AddRegion("B", dim=1)
        for k in range(len(nodes) - 1):
            ngm.Add(Element1D([pids[k], pids[k + 1]], index=ia if k < m.n_a else ib))
        ngm.Add(Element0D(pids[0], index=1))
        ngm.Add(Element0D(pids[-1], index=2))
        ngm.SetBCName(0, "center")
        ngm.SetBCName(1, "frame")
        self.mesh = ng.Mesh(ngm)
        self.fes = ng.H1(self.mesh, order=m.order, dirichlet="center|frame")
        self.gf = ng.GridFunction(self.fes)
        u = self.fes.TrialFunction()
        R = ng.x
        l1 = ng.grad(u)[0]
        l2 = u / R
        wm, we = energy_cf(l1, l2, self.material)
        #: the stretching energy of the current state (admissible where it is finite)
        self._ws_state = energy_cf(ng.grad(self.gf)[0], self.gf / R, self.material)[0]
        self._am = ng.BilinearForm(self.fes, symmetric=False)
        self._am += ng.Variation(wm * R * ng.dx)
        self._ae = ng.BilinearForm(self.fes, symmetric=False)
        self._ae += ng.Variation(we * R * ng.dx(definedon=self.mesh.Materials("A")))
        free = np.array(list(self.fes.FreeDofs()), dtype=bool)
        self._i = self.fes.GetDofNrs(ng.NodeId(ng.VERTEX, self.mesh_spec.n_a))[0]
        assert abs(self.mesh.vertices[self._i].point[0] - 1.0) < 1e-14
        self._E = np.nonzero(free)[0]                      # equations
        self._F = self._E[self._E != self._i]               # unknown displacements
        self._frame = self.fes.GetDofNrs(ng.NodeId(ng.VERTEX, len(nodes) - 1))[0]
        self._tmp = self.gf.vec.CreateVector()

    def _reference_state(self) -> FEState:
        """The pre-stretched film at zero voltage: r = lamP R (interpolated exactly)."""
        self.gf.Set(self.lamP * ng.x)
        x = self.gf.vec.FV().NumPy().copy()
        return self._finish(x, 0.0, 0, 0.0)

    # ------------------------------------------------------------------ assembly
    def _mat(self, form, x):
        """The tangent as a dense array (a 1-D mesh: at most a few hundred unknowns, where
        dense LU is faster than any sparse overhead)."""
        self.gf.vec.FV().NumPy()[:] = x
        form.AssembleLinearization(self.gf.vec)
        rows, cols, vals = form.mat.COO()
        n = self.fes.ndof
        out = np.zeros((n, n))
        np.add.at(out, (np.asarray(rows), np.asarray(cols)), np.asarray(vals))
        return out

    def _system(self, x, p):
        return self._cached_system(x, p, self._assemble_system)

    def _assemble_system(self, x, p):
        with np.errstate(all="ignore"):
            rm = self._vec(self._am, x)
            re = self._vec(self._ae, x)
        res = rm + p * re
        return res, re

    def bordered(self, x, p):
        """The bordered matrix ``[J[E, F], dR/dPhibar^2[E]]`` (dense) and the tangent ``J``
        (``J_m + Phibar^2 J_e``) at the nodal values ``x`` and ``p`` = Phibar^2."""
        J = self._mat(self._am, x) + p * self._mat(self._ae, x)
        _, re = self._system(x, p)
        E, F = self._E, self._F
        M = np.column_stack([J[np.ix_(E, F)], re[E]])
        return M, J

    # ------------------------------------------------------------------ solve

    def _admissible(self, x) -> bool:
        """Positive stretches at the element centres and a finite stretching energy there
        (Gent: short of its lock, where its logarithm is finite)."""
        l1, l2 = self._stretches_at_nodes(x)
        if not (np.all(l1 > 0) and np.all(l2 > 0)):
            return False
        R = 0.5 * (self.nodes[1:] + self.nodes[:-1])
        with np.errstate(invalid="ignore"):
            return bool(np.all(np.isfinite(self._ws_state(self.mesh(R)))))

    def _finish(self, x, p, it, resid) -> FEState:
        lam = float(x[self._i])
        t = self._tangent(x, p)
        dp = float(t[-1])
        # one-sided T1 at R_A and sigma1 = lambda1 T1 at the centre of the first element
        self._set(x)
        R = np.array([1.0 - 1e-9, 1.0 + 1e-9, 0.5 / self.mesh_spec.n_a])
        pts = self.mesh(R)
        l1 = ng.grad(self.gf)[0](pts).ravel()
        l2 = self.gf(pts).ravel() / R
        T1A, T1B, T1c = _T1(self.material, l1, l2, np.array([p, 0.0, p]))
        sig = l1[2] * T1c
        return FEState(lam=lam, phibar2=float(p), dphibar2_dlam=dp, T1A=float(T1A),
                       T1B=float(T1B),
                       sigma1A=float(sig), iterations=it, residual=resid, x=x, tangent=t)

    # ------------------------------------------------------------------ post-processing
    def _set(self, x):
        self.gf.vec.FV().NumPy()[:] = x

    def _stretch_at(self, x, R):
        self._set(x)
        mp = self.mesh(float(R))
        return float(ng.grad(self.gf)[0](mp)), float(self.gf(mp)) / float(R)

    def _stretches_at_nodes(self, x):
        self._set(x)
        R = 0.5 * (self.nodes[1:] + self.nodes[:-1])
        pts = self.mesh(R)
        l1 = ng.grad(self.gf)[0](pts).ravel()
        l2 = self.gf(pts).ravel() / R
        return l1, l2

    def _T1(self, x, p, R) -> float:
        """Nominal radial stress dw/dlambda1 per unit mu at R (3.17), from the library
        energy by complex step; the electric term only inside the electrode (R < R_A)."""
        l1, l2 = self._stretch_at(x, R)
        return _T1(self.material, l1, l2, p if R < 1.0 else 0.0)

    def profile(self, state: FEState, R) -> dict:
        """lambda1, lambda2, lambda3 at radii R (units of R_A, 0 < R <= R_B)."""
        R = np.atleast_1d(np.asarray(v.positive("R", R), dtype=float))
        if np.any(R > self.radius_ratio):
            raise ValueError(f"R must be <= R_B/R_A = {self.radius_ratio}, got max {R.max()}")
        l1, l2 = np.array([self._stretch_at(state.x, r) for r in R]).T
        return {"lam1": l1, "lam2": l2, "lam3": 1 / (l1 * l2)}

    # ------------------------------------------------------------------ events

    def min_slope_before_loss_of_tension(self, lam_hi: float = 8.0) -> tuple[float, float]:
        """``(min dPhibar^2/dlam, lam at the minimum)`` over (lamP, lam_LoT].

        Pull-in is suppressed (Sec. 3.5.2; definition ``before_loss_of_tension`` of
        ``ch3.assumption.pullin_suppressed``) when this minimum is >= 0: no interior maximum
        of Phibar before loss of tension. The slope comes from the bordered FE tangent; the
        minimum is bracketed on the solved states (grid ``lam_step`` plus the loss-of-tension
        root) and an interior one is refined by bounded Brent to :data:`MIN_XTOL` in lam.
        ValueError when there is no loss of tension up to ``lam_hi``.
        """
        lot = self.loss_of_tension(lam_hi)
        sts, last = [], -math.inf
        for s in sorted((s for s in self._states if self.lamP < s.lam <= lot.lam),
                        key=lambda s: s.lam):
            if s.lam > last + MIN_XTOL:     # one state per distinct stretch
                sts.append(s)
                last = s.lam
        d = np.array([s.dphibar2_dlam for s in sts])
        k = int(np.argmin(d))
        if k in (0, len(sts) - 1):          # at an end of the window: no interior minimum
            return float(d[k]), sts[k].lam
        res = minimize_scalar(lambda t: self.solve(t).dphibar2_dlam, method="bounded",
                              bounds=(sts[k - 1].lam, sts[k + 1].lam),
                              options={"xatol": MIN_XTOL})
        if not res.success:
            raise ConvergenceError(f"FE minimum slope: {res.message} (lamP = {self.lamP})")
        if res.fun > d[k]:                  # never worse than the bracketing grid point
            return float(d[k]), sts[k].lam
        return float(res.fun), float(res.x)


@dataclass(frozen=True)
class Suppression:
    """Result of :func:`pullin_suppression_prestretch`: the pre-stretch ``lamP``, the
    stretch ``lam_cusp`` at which the minimum slope of Phibar^2 vanishes there, the
    bracket ``[lo, hi]`` it lies in and the number of FE branches traced."""

    lamP: float
    lam_cusp: float
    lo: float
    hi: float
    evaluations: int


def pullin_suppression_prestretch(c: float = 0.0, *, radius_ratio: float = 15.0,
                                  Jm: float | None = None, elastomer: Material | None = None,
                                  mesh: FEMesh = FEMesh(),
                                  bracket=(2.0, 3.2), xtol: float = 1e-8,
                                  lam_step: float = 0.1, guess: float | None = None,
                                  width: float = 1e-3) -> Suppression:
    """The pre-stretch above which pull-in is suppressed (Sec. 3.5.2), by FE alone.

    Root in lamP of ``g(lamP)`` = min of dPhibar^2/dlam over (lamP, lam_LoT]
    (:meth:`CircularFE.min_slope_before_loss_of_tension`), each ``g`` from a fresh FE
    branch; brentq to ``xtol`` in lamP on a sign change of ``g`` (< 0 below, > 0 above)
    inside ``bracket`` (a window of pre-stretches; none: ConvergenceError). Without
    ``guess`` the sign change is that of the window's ends. With a ``guess`` inside the
    window (a search hint only, e.g. an analytic value), the search starts on
    ``[guess - width, guess + width]`` and widens towards the side that ``g``'s signs
    point to, 8 times the width each time, up to the window: a root far from the guess
    costs a few evaluations more and is found the same way. The root is where the FE's
    ``g`` changes sign; no analytic equation (ODE, closed forms of circle A) is used.
    """
    v.finite("c", c)
    lo, hi = v.window("bracket", bracket, lo=1.0)
    v.tolerance("xtol", xtol)
    seen = {}

    def g(lamP):
        if lamP not in seen:
            model = CircularFE(lamP, c, radius_ratio=radius_ratio, Jm=Jm,
                               elastomer=elastomer, mesh=mesh, lam_step=lam_step)
            seen[lamP] = model.min_slope_before_loss_of_tension()
        return seen[lamP][0]

    if guess is None:
        a, b = lo, hi
    else:
        v.in_range("guess", guess, lo, hi)
        w = v.positive("width", width)
        a, b = max(lo, guess - w), min(hi, guess + w)
    ga, gb = g(a), g(b)
    while not (ga < 0 < gb):
        if (a, b) == (lo, hi) or (ga >= 0 and a == lo) or (gb <= 0 and b == hi):
            raise ConvergenceError(f"FE suppression pre-stretch not bracketed in "
                                   f"{bracket}: min slopes {ga:.3g} at {a:.6g}, "
                                   f"{gb:.3g} at {b:.6g}")
        w *= 8.0
        if ga >= 0:                 # the sign change lies below a
            a, b, gb = max(lo, a - w), a, ga
            ga = g(a)
        else:                       # g(b) <= 0: it lies above b
            a, b, ga = b, min(hi, b + w), gb
            gb = g(b)
    root = bracketed_root(g, a, b, xtol=xtol, what="FE suppression pre-stretch").root
    neg = [x for x in seen if seen[x][0] < 0]
    pos = [x for x in seen if seen[x][0] >= 0]
    if root not in seen:
        g(root)
    return Suppression(lamP=float(root), lam_cusp=float(seen[root][1]), lo=float(max(neg)),
                       hi=float(min(pos)), evaluations=len(seen))



def _T1(material: ElastomerMembrane, l1, l2, I4):
    """dw/dl1 of the energy (3.20) per unit mu at I4 = Phibar^2: the elastomer's stress
    and the electric term (any sign of I4: w is linear in it)."""
    l1, l2 = np.asarray(l1, dtype=float), np.asarray(l2, dtype=float)
    out = (material.stretching_energy_derivative(l1, l2)[0] / material.shear_modulus
           + I4 * material.electric_energy_derivative(l1, l2))
    return float(out) if np.ndim(out) == 0 else out


def energy_cf(l1, l2, material: ElastomerMembrane):
    """The energy (3.20) of an :class:`~debench.models.materials.membrane.ElastomerMembrane`
    with Zhao-Suo permittivity as NGSolve CoefficientFunctions, per unit the elastomer's
    shear modulus: ``(Ws/mu, dW/dI4)`` so that ``w = Ws/mu + I4 dW/dI4`` (w is linear in
    ``I4 = E_L^2``; eps in units of the permittivity's eps_bar). ``Ws`` is the elastomer's
    own ``mechanical_energy`` at ``F = diag(l1, l2, 1/(l1 l2))``, evaluated by NGSolve."""
    perm = material.permittivity
    if not isinstance(perm, ZhaoSuoPermittivity):
        raise NotImplementedError("energy_cf: Zhao-Suo permittivity only")
    F = ng.CoefficientFunction((l1, 0, 0, 0, l2, 0, 0, 0, 1 / (l1 * l2)), dims=(3, 3))
    ws = material.elastomer.mechanical_energy(F, xp=ngf.NGSOLVE) / material.shear_modulus
    eps = E.zhao_suo_permittivity(l1, l2, eps_bar=perm.eps_bar, c=perm.c)
    return ws, E.membrane_electric(l1, l2, 1.0, eps=eps)
