"""Bracketed roots: one scalar root refined by Brent's method with its failures as
:class:`~debench.models.errors.ConvergenceError` (:func:`checked_brentq`), a close estimate
turned into a certified bracket by secant steps first (:func:`zero_near`), and many
brackets refined at once by the Illinois variant of regula falsi
(:func:`regula_falsi_many`).

Every method's contract is the one of :func:`scipy.optimize.brentq`: a sign change across
an interval no wider than ``xtol + 4 eps |x|`` (``zero_near`` and ``checked_brentq``:
``xtol + 4 eps |x|`` by brentq itself), and the returned point is an evaluated end of it.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from debench.models.errors import ConvergenceError

#: first secant step of :func:`zero_near` from the estimate, relative: of the order of the
#: distance between an estimate from a cheaper method and the root (the Chapter 4
#: determinant roots lie within ~1e-4 relative of the finite-element ones, measured), so
#: that the first secant step is already close to the zero
SECANT_STEP = 1e-4
#: secant steps of :func:`zero_near` before the whole bracket is searched (superlinear:
#: ~4 suffice from an estimate within ~1e-4)
SECANT_MAXITER = 8


def checked_brentq(f, lo: float, hi: float, xtol: float, what: str) -> float:
    """``scipy.optimize.brentq`` on [lo, hi] whose failures (no sign change, no
    convergence) become :class:`ConvergenceError` naming ``what`` and the bracket."""
    from scipy.optimize import brentq

    try:
        root, info = brentq(f, lo, hi, xtol=xtol, full_output=True)
    except (ValueError, RuntimeError) as exc:
        raise ConvergenceError(f"{what}: brentq failed on [{lo}, {hi}]: {exc}") from exc
    if not info.converged:
        raise ConvergenceError(f"{what}: brentq did not converge on [{lo}, {hi}] "
                               f"({info.iterations} iterations, {info.flag})")
    return float(root)


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
        """The narrowest interval between two evaluated points with opposite signs."""
        pts = sorted(self.values.items())
        best = None
        for (a, fa), (b, fb) in zip(pts, pts[1:], strict=False):
            if fa * fb <= 0 and (best is None or b - a < best[1] - best[0]):
                best = (a, b)
        return best


def secant_steps(f: Memo, guess: float, lo: float, hi: float, xtol: float) -> None:
    """Secant steps from ``guess`` inside (lo, hi) until a step is below ``xtol``, then one
    evaluation 0.9 xtol beyond the predicted zero (so that a sign change brackets it in an
    interval narrower than ``xtol``). Stops early when two iterates straddle the zero
    closer than ``xtol``, or when a step leaves (lo, hi) or stalls; the evaluations are
    kept in ``f``."""
    x0, x1 = guess, guess * (1 + SECANT_STEP)
    if not (lo < x0 < hi and lo < x1 < hi):
        return
    f0, f1 = f(x0), f(x1)
    for _ in range(SECANT_MAXITER):
        if f1 == 0.0 or f1 == f0:
            return
        step = -f1 * (x1 - x0) / (f1 - f0)
        if abs(step) < 0.9 * xtol:
            x2 = x1 + math.copysign(0.9 * xtol, step)
            if lo < x2 < hi:
                f(x2)
            return
        x2 = x1 + step
        if not lo < x2 < hi:
            return
        x0, f0, x1, f1 = x1, f1, x2, f(x2)
        near = f.narrowest_sign_change()
        if near is not None and near[1] - near[0] < xtol:
            return  # two iterates already straddle the zero closer than xtol


def zero_near(f: Callable[[float], float], guess: float | None, lo: float, hi: float,
              xtol: float, what: str = "the eigenvalue") -> tuple[float, Memo]:
    """A zero of ``f`` in [lo, hi] located by brentq to ``xtol``; with ``guess``, secant
    steps from it first supply a narrow bracket (each evaluation of ``f`` may be an
    eigen-solve: a bracket of +-0.1-0.5 % needs 9-16 of them, secant steps from an estimate
    within ~1e-4 converge superlinearly in 4-6). The secant estimate is never returned as
    such: brentq gets the narrowest interval on which ``f`` was seen to change sign, so the
    contract is brentq's. Returns the zero (an evaluated point) and the memoised ``f`` (its
    evaluations). ConvergenceError when ``f`` does not change sign on the bracket brentq is
    given or brentq fails."""
    fm = Memo(f)
    if guess is not None:
        secant_steps(fm, float(guess), lo, hi, xtol)
        for x, fx in fm.values.items():
            if fx == 0.0:
                return x, fm
    a, b = fm.narrowest_sign_change() or (lo, hi)
    fa, fb = fm(a), fm(b)
    if fa == 0.0 or fb == 0.0:
        return (a if fa == 0.0 else b), fm
    if not fa * fb < 0:
        raise ConvergenceError(f"{what} does not change sign on [{a}, {b}]: {fa:.3e}, "
                               f"{fb:.3e}")
    return checked_brentq(fm, a, b, xtol, what), fm


def regula_falsi_many(f, a, b, fa, fb, xtol, maxiter=200):
    """Zeros of ``f`` in the brackets [a, b] (arrays, sign change fa fb < 0), all at once.

    ``f(x, active)`` evaluates the function at the points ``x`` of the brackets selected
    by the boolean mask ``active``. Illinois variant of regula falsi (bisection where
    rounding puts the secant point outside the bracket); converged when
    ``|b - a| <= xtol + 4 eps |b|`` (the stopping rule of :func:`scipy.optimize.brentq`
    with the same ``xtol``) or ``f`` vanishes exactly. Returns the end with the smaller
    ``|f|``. ConvergenceError when a bracket has no sign change, ``f`` is not finite inside
    a bracket or ``maxiter`` iterations do not suffice.
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
    for _ in range(maxiter):
        active = (np.abs(b - a) > xtol + 4 * eps * np.abs(b)) & (fa != 0) & (fb != 0)
        if not active.any():
            break
        x = b - fb * (b - a) / (fb - fa)
        lo, hi = np.minimum(a, b), np.maximum(a, b)
        x = np.where((x > lo) & (x < hi), x, 0.5 * (a + b))   # rounding: bisect
        fx = np.zeros_like(x)
        fx[active] = f(x[active], active)
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
    return np.where(np.abs(fa) < np.abs(fb), a, b)
