"""Scalar roots, every method returning a :class:`RootResult` that states what was
achieved (the steps excepted), every failure a
:class:`~debench.models.errors.ConvergenceError`:

* :func:`bracketed_root` -- one zero in a bracket with a sign change, by Brent's method
  (:func:`scipy.optimize.brentq`);
* :func:`secant` -- the secant iteration from two starting points (no bracket needed);
  :func:`secant_step` its one step, :func:`inverse_quadratic_root` the root through three
  points;
* :func:`zero_near` -- a zero near an estimate: secant steps from it supply a certified
  narrow bracket, which :func:`bracketed_root` finishes;
* :func:`regula_falsi_many` -- many brackets refined at once by the Illinois variant of
  regula falsi (one vectorised evaluation per iteration for all of them);
* :func:`scan_roots` -- every zero on a grid: the sign changes of the sampled values
  (:func:`~debench.models.numerics.scan.sign_change_brackets`) refined by
  :func:`regula_falsi_many` or :func:`bracketed_root`;
* :func:`bisect_boundary` -- the boundary of the set where a predicate holds (a yes/no
  question has no value to interpolate), by bisection.

The bracketing methods share the contract of :func:`scipy.optimize.brentq`: a sign change
across an interval no wider than ``xtol + rtol |x|`` (``rtol = 4 eps`` unless given), and
the returned root is an evaluated end of it. Adaptive scans that do not lose two close
zeros in one grid interval are in :mod:`debench.models.numerics.scan`; the secant drivers
of expensive functions with a state per evaluation in :mod:`debench.models.numerics.secants`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from debench.models.errors import ConvergenceError, require
from debench.models.numerics.scan import sign_change_brackets
from scipy.optimize import brentq

#: brentq's default relative tolerance, 4 eps: a bracket narrower than a few ulps of the
#: root cannot be halved further
RTOL = 4 * np.finfo(float).eps
#: iterations of :func:`bracketed_root` (brentq's default; superlinear convergence needs
#: far fewer, bisection of a double interval at most ~1100)
MAXITER = 100
#: iterations of :func:`regula_falsi_many` (Illinois: superlinear, ~10-20 per bracket on
#: the scans of the models; the limit guards against a function that is not continuous)
MAXITER_MANY = 200
#: iterations of :func:`secant` (superlinear: ~6-10 from a start within a few % of a
#: simple zero)
MAXITER_SECANT = 50
#: halvings :func:`bisect_boundary` allows before it reports no convergence: halving a
#: double interval reaches the spacing of doubles in at most ~1100 steps
MAXITER_BISECT = 1100
#: first secant step of :func:`zero_near` from the estimate, relative: of the order of the
#: distance between an estimate from a cheaper method and the root (the Chapter 4
#: determinant roots lie within ~1e-4 relative of the finite-element ones, measured), so
#: that the first secant step is already close to the zero
SECANT_STEP = 1e-4
#: secant steps of :func:`zero_near` before the whole bracket is searched (superlinear:
#: ~4 suffice from an estimate within ~1e-4)
SECANT_MAXITER = 8
#: :func:`zero_near` stops its secant steps below this fraction of ``xtol`` and evaluates
#: this fraction of ``xtol`` beyond the predicted zero: a sign change across that step
#: certifies the zero in an interval narrower than ``xtol``
CERTIFY_FRACTION = 0.9


@dataclass(frozen=True)
class RootResult:
    """What a root finder achieved (after :class:`scipy.optimize.RootResults`).

    ``root`` the zero (a float; an array for the methods that refine many brackets at
    once); ``iterations`` and ``function_calls`` (for the vectorised methods: the
    iterations of the slowest bracket and the vectorised calls of ``f``); ``converged``
    always true on return (a method that does not converge raises ConvergenceError);
    ``flag`` how it converged (``"bracket below xtol"``, ``"exact zero"``, ``"step below
    xtol"``); ``bracket`` ``(a, b)``, the narrowest evaluated interval across which ``f``
    changes sign (None when the method saw none: a secant that converged on one side);
    ``error`` what the root is certified to: the bracket's width, or for the secant
    without a bracket the size of its last step (an estimate, not a bound); ``method``
    the method's name; ``next_iterate`` the step
    :func:`~debench.models.numerics.secants.secant_until` stopped before evaluating (None
    for the other methods)."""

    root: float | np.ndarray
    iterations: int
    function_calls: int
    converged: bool
    flag: str
    bracket: tuple | None
    error: float | np.ndarray
    method: str
    next_iterate: float | None = None


def _finite_value(fx, x, what: str) -> float:
    """``fx`` as a float; ConvergenceError naming ``what`` and ``x`` when not finite."""
    fx = float(fx)
    if not math.isfinite(fx):
        raise ConvergenceError(f"{what}: the function is {fx} at x = {x!r}")
    return fx


def _narrowest_sign_change(points) -> tuple[float, float] | None:
    """The narrowest interval between two neighbouring evaluated points ``(x, f(x))``
    across which ``f`` changes sign or vanishes at an end (``f(a) f(b) <= 0``)."""
    pts = sorted(points)
    best = None
    for (a, fa), (b, fb) in zip(pts, pts[1:], strict=False):
        if fa * fb <= 0 and (best is None or b - a < best[1] - best[0]):
            best = (a, b)
    return best


def bracketed_root(f: Callable[[float], float], a: float, b: float, *, xtol: float,
                   rtol: float = RTOL, maxiter: int = MAXITER,
                   what: str = "root") -> RootResult:
    """The zero of ``f`` in ``[a, b]`` by Brent's method (:func:`scipy.optimize.brentq`
    with these ``xtol``, ``rtol``, ``maxiter``): converged when the bracket is narrower
    than ``xtol + rtol |x|``; the root is an evaluated point.

    ``f`` is called exactly as brentq calls it (no memo: a stateful ``f`` sees the same
    sequence of arguments). ConvergenceError naming ``what`` and the bracket when ``f``
    does not change sign on it, returns a value that is not finite, or brentq does not
    converge in ``maxiter`` iterations. ValueError for a bracket or tolerances that are
    not finite, ``xtol <= 0``, ``rtol < 4 eps`` (brentq's floor) or ``maxiter < 1``.
    """
    a, b = float(a), float(b)
    require(math.isfinite(a) and math.isfinite(b), f"a and b must be finite, got {a}, {b}")
    require(math.isfinite(xtol) and xtol > 0, f"xtol must be finite and > 0, got {xtol}")
    require(math.isfinite(rtol) and rtol >= RTOL, f"rtol must be >= 4 eps, got {rtol}")
    require(int(maxiter) == maxiter and maxiter >= 1, f"maxiter must be >= 1, got {maxiter}")
    seen = []

    def g(x):
        fx = _finite_value(f(x), x, what)
        seen.append((float(x), fx))
        return fx

    try:
        root, info = brentq(g, a, b, xtol=xtol, rtol=rtol, maxiter=int(maxiter),
                            full_output=True)
    except (ValueError, RuntimeError) as exc:
        if isinstance(exc, ConvergenceError):
            raise
        raise ConvergenceError(f"{what}: brentq failed on [{a}, {b}]: {exc}") from exc
    if not info.converged:
        raise ConvergenceError(f"{what}: brentq did not converge on [{a}, {b}] "
                               f"({info.iterations} iterations, {info.flag})")
    zeros = [x for x, fx in seen if fx == 0.0]      # the bracket shrinks to an exact zero
    bracket = (zeros[0], zeros[0]) if zeros else _narrowest_sign_change(seen)
    exact = bool(zeros)
    # brentq returns at once when f vanishes at an end, leaving its iteration count unset
    iterations = 0 if info.function_calls <= 2 else int(info.iterations)
    return RootResult(float(root), iterations, int(info.function_calls), True,
                      "exact zero" if exact else "bracket below xtol", bracket,
                      bracket[1] - bracket[0] if bracket else float("nan"), "brentq")


class Memo:
    """``f`` evaluated at most once per abscissa (brentq re-reads bracket ends)."""

    def __init__(self, f: Callable[[float], float]):
        self.f, self.values = f, {}

    def __call__(self, x: float) -> float:
        x = float(x)
        if x not in self.values:
            self.values[x] = float(self.f(x))
        return self.values[x]

    def narrowest_sign_change(self) -> tuple[float, float] | None:
        """The narrowest interval between two neighbouring evaluated points across which
        ``f`` changes sign or vanishes at an end."""
        return _narrowest_sign_change(self.values.items())


def _starts(x0, x1, bounds) -> tuple[float, float]:
    x0, x1 = float(x0), float(x1)
    require(bounds[0] < x0 < bounds[1] and bounds[0] < x1 < bounds[1] and x0 != x1,
            f"x0 and x1 must be distinct points inside bounds {bounds}, got {x0}, {x1}")
    return x0, x1


def secant(f: Callable[[float], float], x0: float, x1: float, *, xtol: float,
           maxiter: int = MAXITER_SECANT, bounds: tuple[float, float] = (-math.inf, math.inf),
           bracket_xtol: float | None = None, certify: bool = False,
           what: str = "root") -> RootResult:
    """A zero of ``f`` by the secant iteration from ``x0`` and ``x1`` (no bracket needed).

    Each step ``x2 = x1 - f1 (x1 - x0) / (f1 - f0)``. Converged when a step is below
    ``xtol`` (root: the predicted zero ``x1 + step``; with ``certify``, ``f`` is also
    evaluated ``xtol`` beyond it, inside ``bounds``, so that a sign change can bracket the
    zero), when ``f`` vanishes at an iterate, or when two evaluated points straddle the
    zero closer than ``bracket_xtol`` (default ``xtol``; root: the end of that bracket
    with the smaller ``|f|``). ``f`` is evaluated through a :class:`Memo` (pass one to
    keep the evaluations). ConvergenceError naming ``what`` when ``f`` is not finite at an
    iterate, the secant is flat (``f1 == f0``), a step leaves the open interval ``bounds``
    (not evaluated there) or ``maxiter`` steps do not converge.
    """
    fm = f if isinstance(f, Memo) else Memo(f)
    lo, hi = bounds
    x0, x1 = _starts(x0, x1, bounds)
    require(math.isfinite(xtol) and xtol > 0, f"xtol must be finite and > 0, got {xtol}")
    bracket_xtol = xtol if bracket_xtol is None else bracket_xtol
    calls0 = len(fm.values)
    f0, f1 = _finite_value(fm(x0), x0, what), _finite_value(fm(x1), x1, what)

    def done(root, flag, it, err):
        near = fm.narrowest_sign_change()
        return RootResult(float(root), it, len(fm.values) - calls0, True, flag, near,
                          (near[1] - near[0]) if near is not None else err, "secant")

    for it in range(int(maxiter)):
        if f1 == 0.0:
            return done(x1, "exact zero", it, 0.0)
        if f1 == f0:
            raise ConvergenceError(f"{what}: flat secant (f = {f1:.3e} at {x0} and {x1})")
        step = -f1 * (x1 - x0) / (f1 - f0)
        if abs(step) < xtol:
            if certify:
                x2 = x1 + math.copysign(xtol, step)
                if lo < x2 < hi:
                    _finite_value(fm(x2), x2, what)
            return done(x1 + step, "step below xtol", it + 1, abs(step))
        x2 = x1 + step
        if not lo < x2 < hi:
            raise ConvergenceError(f"{what}: the secant step to {x2} leaves {bounds}")
        x0, f0, x1, f1 = x1, f1, x2, _finite_value(fm(x2), x2, what)
        near = fm.narrowest_sign_change()
        if near is not None and near[1] - near[0] < bracket_xtol:
            a, b = near
            return done(a if abs(fm(a)) < abs(fm(b)) else b, "bracket below xtol", it + 1,
                        b - a)
    raise ConvergenceError(f"{what}: the secant did not converge to xtol = {xtol} in "
                           f"{maxiter} steps (last step {x1 - x0:.3g})")


def secant_step(x0: float, f0: float, x1: float, f1: float, *, what: str = "secant",
                bounds: tuple[float, float] = (-math.inf, math.inf)) -> float:
    """The secant iterate ``x1 - f1 (x1 - x0) / (f1 - f0)`` through (x0, f0), (x1, f1).
    ConvergenceError naming ``what`` on a flat secant (``f1 == f0``) or when the iterate
    is not finite or leaves the open interval ``bounds``."""
    if f1 == f0:
        raise ConvergenceError(f"{what}: flat secant (f = {f1!r} at {x0!r} and {x1!r})")
    x2 = x1 - f1 * (x1 - x0) / (f1 - f0)
    if not (math.isfinite(x2) and bounds[0] < x2 < bounds[1]):
        raise ConvergenceError(f"{what}: the secant step to {x2!r} leaves {bounds}")
    return x2


def inverse_quadratic_root(xs, fs) -> float:
    """The zero of the quadratic x(f) through three points (Lagrange in f at f = 0);
    ConvergenceError when two values of f are equal."""
    (x0, x1, x2), (f0, f1, f2) = xs, fs
    if len({f0, f1, f2}) < 3:
        raise ConvergenceError("inverse quadratic interpolation: repeated values of f")
    return (x0 * f1 * f2 / ((f0 - f1) * (f0 - f2)) + x1 * f0 * f2 / ((f1 - f0) * (f1 - f2))
            + x2 * f0 * f1 / ((f2 - f0) * (f2 - f1)))


def zero_near(f: Callable[[float], float], guess: float | None, lo: float, hi: float,
              xtol: float, what: str = "the eigenvalue", *,
              maxiter: int = MAXITER) -> RootResult:
    """A zero of ``f`` in [lo, hi] located by brentq to ``xtol``; with ``guess``, secant
    steps from it first supply a narrow bracket (each evaluation of ``f`` may be an
    eigen-solve: a bracket of +-0.1-0.5 % needs 9-16 of them, secant steps from an estimate
    within ~1e-4 converge superlinearly in 4-6).

    The secant (:func:`secant` from ``guess`` and ``guess (1 + SECANT_STEP)``, at most
    :data:`SECANT_MAXITER` steps inside (lo, hi), stopped below
    ``CERTIFY_FRACTION xtol`` with the certifying evaluation beyond its zero, or when two
    iterates straddle the zero closer than ``xtol``) only supplies evaluations: its
    estimate is never returned as such, and its failures (a flat secant, a step out of
    (lo, hi), no convergence in its steps) only mean the whole bracket is searched.
    :func:`bracketed_root` gets the narrowest interval on which ``f`` was seen to change
    sign (else [lo, hi]), so the contract is brentq's (``maxiter`` its iterations). ``f``
    is evaluated at most once per point (a :class:`Memo`; pass one to keep the
    evaluations). ConvergenceError when ``f`` does not change sign on the bracket brentq is
    given or brentq fails.
    """
    fm = f if isinstance(f, Memo) else Memo(f)
    calls0 = len(fm.values)
    secant_iterations = 0
    if guess is not None:
        x0, x1 = float(guess), float(guess) * (1 + SECANT_STEP)
        if lo < x0 < hi and lo < x1 < hi and x0 != x1:
            try:
                secant_iterations = secant(
                    fm, x0, x1, xtol=CERTIFY_FRACTION * xtol, maxiter=SECANT_MAXITER,
                    bounds=(lo, hi), bracket_xtol=xtol, certify=True, what=what).iterations
            except ConvergenceError:    # one evaluation per step after the first two
                secant_iterations = max(len(fm.values) - calls0 - 2, 0)
        for x, fx in fm.values.items():
            if fx == 0.0:
                return RootResult(x, secant_iterations, len(fm.values) - calls0, True,
                                  "exact zero", (x, x), 0.0, "secant + brentq")
    a, b = fm.narrowest_sign_change() or (lo, hi)
    fa, fb = fm(a), fm(b)
    if fa == 0.0 or fb == 0.0:
        x = a if fa == 0.0 else b
        return RootResult(x, secant_iterations, len(fm.values) - calls0, True, "exact zero",
                          (x, x), 0.0, "secant + brentq")
    if not fa * fb < 0:
        raise ConvergenceError(f"{what} does not change sign on [{a}, {b}]: {fa:.3e}, "
                               f"{fb:.3e}")
    res = bracketed_root(fm, a, b, xtol=xtol, maxiter=maxiter, what=what)
    return RootResult(res.root, secant_iterations + res.iterations,
                      len(fm.values) - calls0, True, res.flag, res.bracket, res.error,
                      "secant + brentq")


def regula_falsi_many(f, a, b, fa, fb, xtol, maxiter=MAXITER_MANY) -> RootResult:
    """Zeros of ``f`` in the brackets [a, b] (arrays, sign change fa fb < 0), all at once.

    ``f(x, active)`` evaluates the function at the points ``x`` of the brackets selected
    by the boolean mask ``active``. Illinois variant of regula falsi (bisection where
    rounding puts the secant point outside the bracket); converged when
    ``|b - a| <= xtol + 4 eps |b|`` (the stopping rule of :func:`scipy.optimize.brentq`
    with the same ``xtol``) or ``f`` vanishes exactly. The root of each bracket is its end
    with the smaller ``|f|``; ``bracket`` the final ``(a, b)`` arrays (unordered ends; both
    the root where ``f`` vanished there), ``error`` their widths; each iteration is one
    vectorised call of ``f``. ConvergenceError when a bracket has no sign change, ``f`` is
    not finite inside a bracket or ``maxiter`` iterations do not suffice.
    """
    a, b = np.array(a, float), np.array(b, float)
    fa, fb = np.array(fa, float), np.array(fb, float)
    if not np.all(fa * fb <= 0):
        bad = int(np.flatnonzero(~(fa * fb <= 0))[0])
        raise ConvergenceError(f"root refinement: bracket {bad} [{a.flat[bad]}, "
                               f"{b.flat[bad]}] has no sign change ({fa.flat[bad]:.3e}, "
                               f"{fb.flat[bad]:.3e})")
    side = np.zeros(a.shape, int)
    eps = np.finfo(float).eps
    calls = 0
    for _ in range(maxiter):
        active = (np.abs(b - a) > xtol + 4 * eps * np.abs(b)) & (fa != 0) & (fb != 0)
        if not active.any():
            break
        x = b - fb * (b - a) / (fb - fa)
        lo, hi = np.minimum(a, b), np.maximum(a, b)
        x = np.where((x > lo) & (x < hi), x, 0.5 * (a + b))   # rounding: bisect
        fx = np.zeros_like(x)
        fx[active] = f(x[active], active)
        calls += 1
        if not np.all(np.isfinite(fx[active])):
            raise ConvergenceError("root refinement: the function is not finite inside a "
                                   "bracket (the model is not strongly elliptic there)")
        same = np.sign(fx) == np.sign(fb)
        # Illinois: keep the bracket, halve the stale end's value when it is kept twice
        new_a = np.where(same, a, b)
        new_fa = np.where(same, np.where(side == 1, 0.5 * fa, fa), fb)
        a = np.where(active, new_a, a)
        fa = np.where(active, new_fa, fa)
        b = np.where(active, x, b)
        fb = np.where(active, fx, fb)
        side = np.where(active, np.where(same, 1, 0), side)
    else:
        raise ConvergenceError(f"root refinement did not reach xtol = {xtol} in {maxiter} "
                               f"iterations (widest bracket {np.max(np.abs(b - a)):.3g})")
    root = np.where(np.abs(fa) < np.abs(fb), a, b)
    exact = (fa == 0) | (fb == 0)           # the bracket shrinks to the zero
    a, b = np.where(exact, root, a), np.where(exact, root, b)
    return RootResult(root, calls, calls, True, "bracket below xtol or exact zero", (a, b),
                      np.abs(b - a), "regula falsi (Illinois)")


@dataclass(frozen=True)
class ScanRoots:
    """The zeros :func:`scan_roots` found on a grid.

    ``root`` the zeros, in scan order (row by row for several rows); ``row`` the row of
    each (all 0 for one function); ``interval`` the index i of the grid interval
    ``(x[i], x[i + 1])`` that bracketed it; ``refined`` the :class:`RootResult` of the
    refinement (None when no bracket was refined), whose ``error`` bounds each root."""

    root: np.ndarray
    row: np.ndarray
    interval: np.ndarray
    refined: RootResult | None


#: the refinement methods of :func:`scan_roots`
SCAN_METHODS = ("regula_falsi", "brentq")
#: which zeros of a scan :func:`scan_roots` refines
SCAN_SELECT = ("all", "first", "last")


def scan_roots(f, x, values=None, *, xtol: float, method: str = "regula_falsi",
               select: str = "all", rtol: float = RTOL, maxiter: int | None = None,
               what: str = "root") -> ScanRoots:
    """Every zero of ``f`` on the grid ``x``: the sign changes of the sampled values,
    refined.

    ``x`` a monotone 1-D grid; ``values`` the samples of ``f`` on it (default ``f(x)``),
    shape ``(n,)`` or ``(rows, n)`` for several functions on one grid. Brackets are the
    intervals of :func:`~debench.models.numerics.scan.sign_change_brackets` (both ends
    finite, a strict sign change or a zero at an end); a zero at a grid point brackets
    both intervals beside it and is returned once. ``select`` refines ``"all"`` brackets,
    or only the ``"first"`` or ``"last"`` of each row along ``x``.

    ``method="regula_falsi"``: all brackets at once by :func:`regula_falsi_many`, ``f(p)``
    (one row) or ``f(p, rows)`` (several) evaluating the points ``p`` of the brackets of
    rows ``rows``; ``method="brentq"``: one bracket at a time by :func:`bracketed_root`,
    ``f(p)`` or ``f(p, row)`` at a scalar ``p``. The bracket is passed with its lower end
    first. ConvergenceError from the refinement.
    """
    require(method in SCAN_METHODS, f"method must be one of {SCAN_METHODS}, got {method!r}")
    require(select in SCAN_SELECT, f"select must be one of {SCAN_SELECT}, got {select!r}")
    x = np.asarray(x, float)
    vals = np.asarray(f(x) if values is None else values, float)
    require(x.ndim == 1 and x.size >= 2, f"x must be a 1-D grid of >= 2 points, got {x.shape}")
    require(vals.shape[-1:] == x.shape and vals.ndim in (1, 2),
            f"values must have shape (n,) or (rows, n) with n = {x.size}, got {vals.shape}")
    rows_f = vals.ndim == 2
    vals2 = vals if rows_f else vals[None]
    ascending = x[-1] > x[0]
    xs = x if ascending else x[::-1]
    rows, idx = [], []
    for r, fr in enumerate(vals2):
        fs = fr if ascending else fr[::-1]
        i = sign_change_brackets(xs, fs)
        if not ascending:
            i = (x.size - 2 - i)[::-1]
        if select == "first":
            i = i[:1]
        elif select == "last":
            i = i[-1:]
        rows += [r] * i.size
        idx += list(i)
    rows, idx = np.asarray(rows, int), np.asarray(idx, int)
    if not idx.size:
        empty = np.zeros(0, int)
        return ScanRoots(np.zeros(0), empty, empty, None)
    ia, ib = np.where(ascending, idx, idx + 1), np.where(ascending, idx + 1, idx)
    a, b = x[ia], x[ib]
    fa, fb = vals2[rows, ia], vals2[rows, ib]
    if method == "regula_falsi":
        if rows_f:
            def g(p, active):
                return f(p, rows[active])
        else:
            def g(p, active):
                return f(p)
        kw = {} if maxiter is None else {"maxiter": maxiter}
        refined = regula_falsi_many(g, a, b, fa, fb, xtol, **kw)
        root = np.asarray(refined.root, float)
    else:
        kw = {} if maxiter is None else {"maxiter": maxiter}
        results = [bracketed_root((lambda p, r=r: f(p, r)) if rows_f else f, lo, hi,
                                  xtol=xtol, rtol=rtol, what=what, **kw)
                   for r, lo, hi in zip(rows, a, b, strict=True)]
        root = np.array([res.root for res in results])
        refined = RootResult(root, max(res.iterations for res in results),
                             sum(res.function_calls for res in results), True,
                             "bracket below xtol or exact zero",
                             tuple(np.array([res.bracket[k] for res in results])
                                   for k in (0, 1)),
                             np.array([res.error for res in results]), "brentq")
    # a zero at a grid point brackets both intervals beside it: return it once
    keep = np.ones(root.size, bool)
    keep[1:] = ~((rows[1:] == rows[:-1]) & (root[1:] == root[:-1])
                 & ((fa[1:] == 0) | (fb[1:] == 0)))
    return ScanRoots(root[keep], rows[keep], idx[keep], refined)


def bisect_boundary(inside: Callable[[float], bool], a: float, b: float, *,
                    xtol: float | None = None, halvings: int | None = None,
                    what: str = "boundary") -> RootResult:
    """The boundary between ``a``, where the predicate ``inside`` is false, and ``b``,
    where it holds (neither end is evaluated: the caller knows them from its scan), by
    bisection: ``m = (a + b) / 2`` replaces ``b`` where ``inside(m)``, else ``a``.

    Stops when ``|b - a| <= xtol``, or after exactly ``halvings`` halvings (give one of
    the two). ``root`` is the final ``b`` (where the predicate holds), ``bracket`` the
    final ``(a, b)`` and ``error`` its width. ConvergenceError naming ``what`` when the
    midpoint no longer moves (``xtol`` below the spacing of doubles there) or
    :data:`MAXITER_BISECT` halvings do not reach ``xtol``. ValueError unless exactly one of
    ``xtol`` (finite, >= 0) and ``halvings`` (>= 0) is given and ``a``, ``b`` are finite
    and distinct.
    """
    require((xtol is None) != (halvings is None),
            f"give exactly one of xtol and halvings, got {xtol}, {halvings}")
    require(xtol is None or (math.isfinite(xtol) and xtol >= 0),
            f"xtol must be finite and >= 0, got {xtol}")
    require(halvings is None or (int(halvings) == halvings and halvings >= 0),
            f"halvings must be an integer >= 0, got {halvings}")
    a, b = float(a), float(b)
    require(math.isfinite(a) and math.isfinite(b) and a != b,
            f"a and b must be finite and distinct, got {a}, {b}")
    n = 0
    while (n < halvings) if halvings is not None else (abs(b - a) > xtol):
        if halvings is None and n >= MAXITER_BISECT:
            raise ConvergenceError(f"{what}: bisection did not reach xtol = {xtol} in "
                                   f"{MAXITER_BISECT} halvings ([{a}, {b}])")
        m = 0.5 * (a + b)
        if m in (a, b):
            raise ConvergenceError(f"{what}: bisection stalled at [{a}, {b}] (the spacing "
                                   "of doubles)")
        a, b = (a, m) if inside(m) else (m, b)
        n += 1
    return RootResult(b, n, n, True, "bracket below xtol" if halvings is None
                      else "halvings done", (a, b), abs(b - a), "bisection")
