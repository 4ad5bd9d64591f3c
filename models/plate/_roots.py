"""Root location from a close estimate: secant steps, then a certified bracket.

The critical stretches of methods 2 and 3 are zeros, in lam, of one eigenvalue of a
finite-element tangent; each costs an eigen-solve. The determinant root (method 1) is
within ~1e-4 relative of them, so secant steps started there converge superlinearly in
4-6 solves, where a bracketed search from a bracket of +-0.1-0.5 % needs 9-16. The secant
estimate is never returned as such: :func:`zero_near` hands brentq the narrowest interval
on which the eigenvalue was seen to change sign, so the contract (a sign change across an
interval of width <= xtol) is brentq's.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from debench.models.errors import ConvergenceError, checked_brentq

#: first secant step from the estimate, relative: of the order of the distance between the
#: determinant and FE roots (<= ~1e-4 relative on the coarse meshes, measured), so that
#: the first secant step is already close to the zero
SECANT_STEP = 1e-4
#: secant steps before the whole bracket is searched (superlinear: ~4 suffice)
SECANT_MAXITER = 8


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
    steps from it first supply a narrow bracket. Returns the zero (an evaluated point) and
    the memoised ``f`` (its evaluations). ConvergenceError when ``f`` does not change sign
    on the bracket brentq is given or brentq fails."""
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
