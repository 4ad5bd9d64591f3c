"""Load-controlled continuation with a bordered Newton system, shared by the Chapter 3 FE
models (the membrane :mod:`~debench.models.circular.fe` and the thin solid
:mod:`~debench.models.circular.fe_solid`), and its linear algebra.

The load is one prescribed unknown (a stretch); Phibar^2 is an unknown of the bordered
system, so that a branch is followed through the pull-in maximum of Phibar. Newton is
damped by the natural monotonicity test (a step is taken only when it contracts), the
continuation halves a step that Newton cannot contract from, and pull-in and loss of
tension are located by brentq on the solved states. The bordered tangent is solved
dense (the membrane) or, sparse (the thin solid's saddle-point tangent), after a
power-of-two equilibration that makes the solve independent of round-off.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from debench.models import validation as v
from debench.models.errors import ConvergenceError
from debench.models.numerics.newton import STEP_RTOL
from debench.models.numerics.roots import bracketed_root

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


class BorderedContinuation:
    """Load-controlled continuation with a bordered Newton system (shared by the membrane
    and the solid models).

    The load is one prescribed unknown ``x[_i] = lam``; ``Phibar^2`` is an unknown, so that
    the branch is followed through the pull-in maximum of Phibar. A subclass provides
    ``lamP``, ``lam_step``, ``_states``, the index sets ``_E`` (equations), ``_F`` (free
    unknowns), ``_i`` (the load), and ``_system(x, p) -> (residual, d residual/dp)``,
    ``bordered(x, p) -> (M, J)`` (public: the bordered matrix ``M = [J[E, F],
    dR/dPhibar^2[E]]`` that Newton and the tangent solve, and the tangent ``J`` or its
    load column, whose solve the round-off tests perturb), ``_admissible(x)``,
    ``_finish(x, p, it, resid)`` (and ``gf``, ``_tmp`` for :meth:`_vec`); states
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
        STEP_RTOL relative (the package's Newton policy,
        :mod:`debench.models.numerics.newton`); no admissible, contracting step down to s =
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
            M, _ = self.bordered(x, p)
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
                if ok and scale == 1.0 and step <= STEP_RTOL * (1 + np.max(np.abs(xt))
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
        M, J = self.bordered(x, p)
        return solve_bordered(M, -self._load_column(J), float(x[self._i]))

    def solve(self, lam: float):
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

    def _step(self, base, lam: float):
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

    def pullin(self, lam_hi: float):
        """First local maximum of Phibar along lam in (lamP, lam_hi]: dPhibar^2/dlam = 0
        located by brentq on FE states. Raises ValueError when there is none."""
        lam_hi = v.at_least("lam_hi", lam_hi, self.lamP)
        return self._first_root(lambda s: s.dphibar2_dlam, lam_hi, "pull-in")

    def loss_of_tension(self, lam_hi: float):
        """First zero of sigma1 in circle A along lam in (lamP, lam_hi]."""
        lam_hi = v.at_least("lam_hi", lam_hi, self.lamP)
        return self._first_root(lambda s: s.sigma1A, lam_hi, "loss of tension")

    def _first_root(self, g, lam_hi, what):
        lams = np.arange(self.lamP, lam_hi + 0.5 * self.lam_step, self.lam_step)
        prev = self.solve(float(lams[0]))
        for lam in lams[1:]:
            cur = self.solve(float(lam))
            if g(prev) > 0 >= g(cur):
                root = bracketed_root(lambda t: g(self.solve(t)), prev.lam, cur.lam,
                                      xtol=ROOT_XTOL, what=f"FE {what}").root
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


def solve_bordered(M, b, lam):
    """The solution z of the bordered system ``M z = b`` at the load ``lam`` (used in the
    error message): ``M`` sparse is equilibrated by powers of two (:func:`equilibrate`)
    before its LU solve, so that z does not depend on round-off in ``M`` (explicit zeros,
    the order of the unknowns, perturbed values: forward error ~ condition 1e6 x the
    perturbation, ``verification/test_ch3_fe_roundoff.py``); ``M`` dense is solved as it
    is. A singular ``M`` is a ConvergenceError."""
    return _factor(M, lam)[0](b)
