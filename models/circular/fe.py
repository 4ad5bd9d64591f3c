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
:meth:`~debench.models.materials.membrane.GentMembrane.free_energy` in units mu = 1,
eps_bar = 1, ``I4 = Phibar^2``: the same expressions
(:mod:`debench.models.materials.energies`) evaluated as NGSolve CoefficientFunctions
(:func:`energy_cf`, tested equal to the numpy evaluation).

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
Newton stops when the update satisfies ``|dx|_inf <= NEWTON_RTOL (1 + |x|_inf)`` (after
quadratic convergence the residual is at round-off). The discretisation error is that of
the mesh (``n_a`` elements in circle A, ``n_b`` elements in annulus B uniform in ln R,
order ``order``); its observed order is measured in ``verification/test_ch3_fe.py``.
The model is the membrane limit (thickness t -> 0): the film thickness does not enter.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import ngsolve as ng
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from debench.models import validation as v
from debench.models.errors import ConvergenceError
from debench.models.materials import energies as E
from debench.models.materials import ngsolve_forms as ngf
from debench.models.materials.membrane import GentMembrane, ZhaoSuoPermittivity
from debench.models.numerics.roots import checked_brentq
from netgen.meshing import Element0D, Element1D, MeshPoint, Pnt
from netgen.meshing import Mesh as NetgenMesh
from scipy.optimize import brentq, minimize_scalar

from .params import JM_VHB, locking_stretch_equibiaxial

#: Newton stops on a relative update below this (quadratic convergence: the next update
#: would be ~1e-20; the bordered system has condition ~1e8 on the finest meshes, so a
#: relative round-off floor ~1e-12 leaves a margin of 100)
NEWTON_RTOL = 1e-10
NEWTON_MAXITER = 40
#: a Newton step is taken when the simplified correction at the trial state is smaller
#: than the update by this factor (contraction, theta < 1): an update that does not
#: contract has left the region where Newton converges to the solution next to its start
NEWTON_THETA_MAX = 1.0
#: smallest damping factor of a continuation's Newton step
#: (:meth:`BorderedContinuation._newton`): below it the predictor is too far from a
#: solution for Newton to contract towards one, and a shorter continuation step (a
#: predictor error 4x smaller) is cheaper than more damping
NEWTON_DAMPING_MIN = 2.0**-3
#: smallest damping factor that keeps a state admissible when no shorter step exists
ADMISSIBLE_DAMPING_MIN = 2.0**-30
#: continuation step in lam (halved on a Newton failure, at most MAX_HALVINGS times)
LAM_STEP = 0.05
MAX_HALVINGS = 12
#: root location (pull-in, loss of tension) to this tolerance in lam; far below the
#: discretisation error of any mesh used (>= 1e-7, test_ch3_fe)
ROOT_XTOL = 1e-11
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


class BorderedContinuation:
    """Load-controlled continuation with a bordered Newton system (shared by the membrane
    and the solid models).

    The load is one prescribed unknown ``x[_i] = lam``; ``Phibar^2`` is an unknown, so that
    the branch is followed through the pull-in maximum of Phibar. A subclass provides
    ``lamP``, ``lam_step``, ``_states``, the index sets ``_E`` (equations), ``_F`` (free
    unknowns), ``_i`` (the load), and ``_system(x, p) -> (residual, d residual/dp)``,
    ``_bordered(x, p) -> (M, J)``, ``_admissible(x)``, ``_finish(x, p, it, resid)`` (and
    ``gf``, ``_tmp`` for :meth:`_vec`); states
    have ``lam``, ``phibar2``, ``dphibar2_dlam``, ``sigma1A``, ``x`` and ``tangent`` (the
    bordered tangent at the state, computed once by ``_finish`` and reused as the
    predictor of every step from it).
    """

    def _newton(self, x, p, lam, monotone: bool = True):
        """Damped Newton at the load ``lam`` from ``(x, p)`` with the natural monotonicity
        test (Deuflhard, affine covariant): a step ``s dz`` (s = 1, 1/2, ...) is taken when
        the trial state is admissible and the simplified correction there, ``dz_bar`` =
        -J(x)^-1 R(x + s dz) (the same factorisation), satisfies ``|dz_bar| <
        NEWTON_THETA_MAX |dz|`` (2-norm of :func:`_factor`'s weighted unknowns): each
        accepted step contracts towards the solution next to the start, and a start from
        which Newton would wander (|dz| growing, landing after tens of iterations on a
        state that depends on round-off) is refused. Converged when a full update is below
        NEWTON_RTOL relative; no admissible, contracting step down to s =
        NEWTON_DAMPING_MIN, or no convergence in NEWTON_MAXITER steps: ConvergenceError
        (the continuation then takes a shorter step).
        ``monotone=False`` (a first state from an inconsistent start, where no shorter step
        exists): full steps, damped only to stay admissible."""
        x = x.copy()
        x[self._i] = self._load_value(lam)
        E, F = self._E, self._F
        res, _ = self._system(x, p)
        for it in range(1, NEWTON_MAXITER + 1):
            if not np.all(np.isfinite(res[E])):
                raise ConvergenceError(f"FE Newton: inadmissible state at lam = {lam:.6g} "
                                       f"(Gent locking or lambda <= 0), lamP = {self.lamP}")
            M, _ = self._bordered(x, p)
            solve, w = _factor(M, lam)
            dz = solve(-res[E])
            size = float(np.linalg.norm(dz * w))
            step = float(np.max(np.abs(dz)))
            scale = 1.0
            while True:             # s = 1, 1/2, ...
                xt = x.copy()
                xt[F] += scale * dz[:-1]
                pt = p + scale * dz[-1]
                rt, _ = self._system(xt, pt)
                ok = bool(np.all(np.isfinite(rt[E])) and self._admissible(xt))
                if ok and scale == 1.0 and step <= NEWTON_RTOL * (1 + np.max(np.abs(xt))
                                                                 + abs(pt)):
                    return xt, pt, it, float(np.max(np.abs(rt[E])))
                if ok and (not monotone or np.linalg.norm(solve(-rt[E]) * w)
                           < NEWTON_THETA_MAX * size):
                    break
                scale *= 0.5
                if scale < (NEWTON_DAMPING_MIN if monotone else ADMISSIBLE_DAMPING_MIN):
                    raise ConvergenceError(
                        f"FE Newton: no admissible contracting step at lam = {lam:.6g} "
                        f"(|dz| = {size:.3g}), lamP = {self.lamP}")
            x, p, res = xt, pt, rt
        raise ConvergenceError(f"FE Newton: |dz| = {step:.3g} after {NEWTON_MAXITER} "
                               f"iterations at lam = {lam:.6g}, lamP = {self.lamP}")

    def _tangent(self, x, p):
        """d(x_F, p)/dlam from the bordered tangent (x_i = lam fixed by the load)."""
        M, J = self._bordered(x, p)
        return _solve(M, -self._load_column(J), float(x[self._i]))

    def solve(self, lam: float) -> FEState:
        """Equilibrium with r(R_A) = lam R_A on the rising branch (continuation from the
        nearest solved state with an Euler predictor; steps halved on a Newton failure).

        ``lam`` >= lamP; raises ConvergenceError when no admissible state is reached.
        """
        lam = v.at_least("lam", lam, self.lamP)
        base = min(self._states, key=lambda s: abs(s.lam - lam))
        while abs(base.lam - lam) > 0:
            target = base.lam + math.copysign(min(self.lam_step, abs(lam - base.lam)),
                                              lam - base.lam)
            for _ in range(MAX_HALVINGS + 1):
                try:
                    state = self._step(base, target)
                    break
                except ConvergenceError:
                    target = base.lam + 0.5 * (target - base.lam)
            else:
                raise ConvergenceError(f"FE continuation stalled at lam = {base.lam:.6g} "
                                       f"towards {lam:.6g}, lamP = {self.lamP}")
            self._states.append(state)
            base = state
        return base

    def _step(self, base: FEState, lam: float) -> FEState:
        """Newton from the Euler predictor at ``lam`` (the tangent kept with ``base``);
        a step that Newton cannot contract from is refused (ConvergenceError) and
        :meth:`solve` halves it, so that no step crosses a fold of the branch."""
        t = base.tangent if base.tangent is not None else self._tangent(base.x, base.phibar2)
        d = lam - base.lam
        x0 = base.x.copy()
        x0[self._F] += d * t[:-1]
        p0 = base.phibar2 + d * t[-1]
        x, p, it, resid = self._newton(x0, p0, lam)
        return self._finish(x, p, it, resid)

    def pullin(self, lam_hi: float) -> FEState:
        """First local maximum of Phibar along lam in (lamP, lam_hi]: dPhibar^2/dlam = 0
        located by brentq on FE states. Raises ValueError when there is none."""
        lam_hi = v.at_least("lam_hi", lam_hi, self.lamP)
        return self._first_root(lambda s: s.dphibar2_dlam, lam_hi, "pull-in")

    def loss_of_tension(self, lam_hi: float) -> FEState:
        """First zero of sigma1 in circle A along lam in (lamP, lam_hi]."""
        lam_hi = v.at_least("lam_hi", lam_hi, self.lamP)
        return self._first_root(lambda s: s.sigma1A, lam_hi, "loss of tension")

    def _first_root(self, g, lam_hi, what) -> FEState:
        lams = np.arange(self.lamP, lam_hi + 0.5 * self.lam_step, self.lam_step)
        prev = self.solve(float(lams[0]))
        for lam in lams[1:]:
            cur = self.solve(float(lam))
            if g(prev) > 0 >= g(cur):
                root = brentq(lambda t: g(self.solve(t)), prev.lam, cur.lam,
                              xtol=ROOT_XTOL, rtol=4 * np.finfo(float).eps)
                return self.solve(root)
            prev = cur
        raise ValueError(f"no {what} for lam in [{self.lamP}, {lam_hi}] (lamP = {self.lamP},"
                         f" c = {self.c})")

    def _cached_system(self, x, p, assemble):
        """``assemble(x, p)`` (residual and its derivative in Phibar^2), remembered for the
        last (x, p): Newton evaluates the system at its accepted iterate and the bordered
        tangent needs it again at the same point. Returns copies."""
        last = getattr(self, "_last_system", None)
        if last is not None and last[1] == p and np.array_equal(last[0], x):
            return last[2].copy(), last[3].copy()
        res, d = assemble(x, p)
        self._last_system = (np.array(x, copy=True), p, res.copy(), d.copy())
        return res, d

    def _vec(self, form, x):
        """The form applied at the nodal values ``x`` (the subclass's NGSolve GridFunction
        ``gf`` and work vector ``_tmp``), as a new array."""
        self.gf.vec.FV().NumPy()[:] = x
        form.Apply(self.gf.vec, self._tmp)
        return self._tmp.FV().NumPy().copy()

    def _load_value(self, lam):
        """The prescribed value of the load unknown at stretch ``lam`` (here r(R_A))."""
        return lam

    def _load_column(self, J):
        """The tangent's column of the load unknown, restricted to the equations."""
        return J[self._E, self._i]


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
        Gent parameter (3.23), > 0.
    mesh
        :class:`FEMesh`.
    lam_step
        Continuation step in lam and the grid on which events are bracketed (> 0; halved
        automatically on a Newton failure). Events are located exactly on any grid; a
        grid coarser than the spacing of two events of the same kind may miss both.
    """

    def __init__(self, lamP: float, c: float = 0.0, *, radius_ratio: float = 15.0,
                 Jm: float = JM_VHB, mesh: FEMesh = FEMesh(), lam_step: float = LAM_STEP):
        self.lam_step = v.positive("lam_step", lam_step)
        self.lamP = v.at_least("lamP", lamP, 1.0)
        self.c = v.finite("c", c)
        self.radius_ratio = v.positive("radius_ratio", radius_ratio)
        if not (self.radius_ratio > 1 and math.isfinite(self.radius_ratio)):
            raise ValueError(f"radius_ratio RB/RA must be finite and > 1, got {radius_ratio}")
        self.Jm = v.positive("Jm", Jm)
        lock = locking_stretch_equibiaxial(self.Jm)
        if not self.lamP < lock:
            raise ValueError(f"lamP = {self.lamP:.6g} is past the Gent locking stretch "
                             f"{lock:.6g} (Jm = {self.Jm:.6g})")
        if not 1 + self.c * (2 * self.lamP - 2) > 0:
            raise ValueError(f"c = {self.c} makes the permittivity (3.27) non-positive at "
                             f"lamP = {self.lamP}: need 1 + c(2 lamP - 2) > 0")
        self.mesh_spec = v.instance("mesh", mesh, FEMesh)
        #: the library material in units mu = 1, eps_bar = 1 (so that I4 = Phibar^2)
        self.material = GentMembrane(mu=1.0, Jm=self.Jm,
                                     permittivity=ZhaoSuoPermittivity(eps_bar=1.0, c=self.c))
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

    def _bordered(self, x, p):
        J = self._mat(self._am, x) + p * self._mat(self._ae, x)
        _, re = self._system(x, p)
        E, F = self._E, self._F
        M = np.column_stack([J[np.ix_(E, F)], re[E]])
        return M, J

    # ------------------------------------------------------------------ solve

    def _admissible(self, x) -> bool:
        l1, l2 = self._stretches_at_nodes(x)
        if not (np.all(l1 > 0) and np.all(l2 > 0)):
            return False
        return bool(np.all(l1**2 + l2**2 + (l1 * l2) ** -2 - 3 < self.Jm))

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
                                  Jm: float = JM_VHB, mesh: FEMesh = FEMesh(),
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
            model = CircularFE(lamP, c, radius_ratio=radius_ratio, Jm=Jm, mesh=mesh,
                               lam_step=lam_step)
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
    root = checked_brentq(g, a, b, xtol, "FE suppression pre-stretch")
    neg = [x for x in seen if seen[x][0] < 0]
    pos = [x for x in seen if seen[x][0] >= 0]
    if root not in seen:
        g(root)
    return Suppression(lamP=float(root), lam_cusp=float(seen[root][1]), lo=float(max(neg)),
                       hi=float(min(pos)), evaluations=len(seen))


#: sweeps of the power-of-two equilibration of a sparse bordered matrix
#: (:func:`equilibrate`); each halves the log of the row and column max spreads, and
#: the solid's tangent reaches a condition ~1e6 after a few (measured, module test)
EQUILIBRATION_SWEEPS = 8


def equilibrate(M):
    """Row and column scalings ``(r, c)``, integer powers of two, such that
    ``diag(r) M diag(c)`` has every row and column max-abs entry within a factor ~2 of 1
    (Ruiz sweeps of 1/sqrt(max |.|), rounded to powers of two so that the scaling itself
    is exact in floating point). ``M``: scipy sparse, no empty row or column."""
    A = sp.csc_matrix(M)
    vals = np.abs(A.data)
    rows = A.indices
    cols = np.repeat(np.arange(A.shape[1]), np.diff(A.indptr))
    by_row = np.argsort(rows, kind="stable")
    row_start = np.searchsorted(rows[by_row], np.arange(A.shape[0]))
    col_start = A.indptr[:-1]
    if (np.any(np.diff(A.indptr) == 0) or len(np.unique(rows)) != A.shape[0]
            or not np.all(np.isfinite(vals))):
        raise ConvergenceError("FE: the bordered tangent has an empty row or column or a "
                               "non-finite entry")
    r = np.ones(A.shape[0])
    c = np.ones(A.shape[1])
    for _ in range(EQUILIBRATION_SWEEPS):
        v = vals * r[rows] * c[cols]
        rmax = np.maximum.reduceat(v[by_row], row_start)
        cmax = np.maximum.reduceat(v, col_start)
        if not (np.all(rmax > 0) and np.all(cmax > 0)):
            raise ConvergenceError("FE: the bordered tangent has a zero row or column")
        dr = np.exp2(np.round(-0.5 * np.log2(rmax)))
        dc = np.exp2(np.round(-0.5 * np.log2(cmax)))
        if np.all(dr == 1.0) and np.all(dc == 1.0):
            break
        r *= dr
        c *= dc
    return r, c


def _factor(M, lam):
    """Factorisation of the bordered matrix ``M``: ``(solve, weights)``, ``solve(b)`` the
    solution of ``M z = b`` and ``weights`` those of the unknowns in the norm of a Newton
    update. A sparse ``M`` (the thin solid's saddle-point tangent) is equilibrated first
    (:func:`equilibrate`): its pressure block is the mass matrix over the penalty (~1e-8
    beside displacement entries ~1e9 at the default penalty), a condition ~1e18 unscaled,
    at which the pressure part of an unscaled LU solve is round-off (its value then
    depends on the pivot order); scaled, ~1e6. Its weights are 1/(column scaling): the
    update measured in the unknowns of the equilibrated system, where every column has
    unit size. A dense ``M`` (the membrane) is solved as it is, weights 1. A singular
    ``M`` is a ConvergenceError."""
    def singular(exc):
        return ConvergenceError(f"FE: singular bordered tangent at lam = {lam:.6g}")

    try:
        if sp.issparse(M):
            r, c = equilibrate(M)
            A = sp.csc_matrix(M, copy=True)
            A.data *= r[A.indices] * np.repeat(c, np.diff(A.indptr))
            with warnings.catch_warnings():
                warnings.simplefilter("error", spla.MatrixRankWarning)
                lu = spla.splu(A)
            return (lambda b: c * lu.solve(r * np.asarray(b, dtype=float))), 1.0 / c
    except (np.linalg.LinAlgError, RuntimeError, spla.MatrixRankWarning) as exc:
        raise singular(exc) from exc

    def dense(b):
        try:
            return np.linalg.solve(M, b)
        except np.linalg.LinAlgError as exc:
            raise singular(exc) from exc
    return dense, np.ones(M.shape[1])


def _solve(M, b, lam):
    """Solve of the bordered system (:func:`_factor`); a singular tangent is a
    ConvergenceError."""
    return _factor(M, lam)[0](b)


def _T1(material, l1, l2, I4):
    """dw/dl1 of the library energy (3.20) at I4 = Phibar^2 (any sign: w is linear in I4,
    so the two complex-step derivatives at I4 = 0 and 1 give it)."""
    h = 1e-30
    l1, l2 = np.asarray(l1, dtype=float), np.asarray(l2, dtype=float)
    both = np.imag(material.free_energy(np.stack([l1, l1]) + 1j * h, np.stack([l2, l2]),
                                        np.array([0.0, 1.0]).reshape((2,) + (1,) * l1.ndim))
                   ) / h
    w0, w1 = both[0], both[1]
    out = w0 + I4 * (w1 - w0)
    return float(out) if np.ndim(out) == 0 else out


def energy_cf(l1, l2, material: GentMembrane):
    """The energy (3.20) of :class:`GentMembrane` with Zhao-Suo permittivity as NGSolve
    CoefficientFunctions: ``(Ws, dW/dI4)`` so that ``w = Ws + I4 dW/dI4`` (w is linear in
    ``I4 = E_L^2``). Units follow ``material`` (mu, eps_bar). The expressions are those of
    the library (:mod:`debench.models.materials.energies`), evaluated by NGSolve."""
    perm = material.permittivity
    if not isinstance(perm, ZhaoSuoPermittivity):
        raise NotImplementedError("energy_cf: Zhao-Suo permittivity only")
    ws = E.gent(E.membrane_first_invariant(l1, l2), mu=material.mu, Jm=material.Jm,
                xp=ngf.NGSOLVE)
    eps = E.zhao_suo_permittivity(l1, l2, eps_bar=perm.eps_bar, c=perm.c)
    return ws, E.membrane_electric(l1, l2, 1.0, eps=eps)
