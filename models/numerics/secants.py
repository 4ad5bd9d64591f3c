"""Secant drivers for expensive functions with a state per evaluation (each evaluation a
Newton solve and an eigen-solve, say), whose evaluations degrade or turn noisy next to the
zero; every failure a :class:`~debench.models.errors.ConvergenceError`:

* :func:`secant_until` -- the secant stopped before a step it calls small, never
  evaluating there; the last evaluated point or the inverse-quadratic root answers, in a
  :class:`~debench.models.numerics.roots.RootResult`;
* :func:`secant_zero` -- a zero from two evaluated points, answering with the index of an
  *evaluated* point (its state is what the caller keeps): Illinois inside a starting
  bracket, else the secant with a stop at the round-off floor.

Their steps are :func:`~debench.models.numerics.roots.secant_step` and
:func:`~debench.models.numerics.roots.inverse_quadratic_root`.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from debench.models.errors import ConvergenceError, require
from debench.models.numerics.roots import (
    MAXITER_SECANT,
    RootResult,
    _finite_value,
    _narrowest_sign_change,
    _starts,
    inverse_quadratic_root,
    secant_step,
)


def secant_until(f: Callable[[float], float], x0: float, x1: float, *,
                 converged: Callable[[float, float], bool], finish: str = "evaluated",
                 maxiter: int = MAXITER_SECANT,
                 bounds: tuple[float, float] = (-math.inf, math.inf),
                 what: str = "root") -> RootResult:
    """A zero of ``f`` by the secant from ``x0``, ``x1``, stopped *before* the step that
    ``converged(x_last, x_next)`` calls small (after three evaluations at least), for an
    ``f`` that degrades next to its zero (Newton on a tangent singular there): ``x_next``
    is never evaluated. ``finish``: ``"evaluated"`` answers the last evaluated point (its
    error is the next step to higher order; a caller keeping a state per evaluation has it
    there), ``"inverse_quadratic"`` the :func:`inverse_quadratic_root` of the last three
    evaluations (error ~ the product of their distances to the zero). ``next_iterate`` is
    ``x_next``; ``error`` the narrowest evaluated sign change, else ``|x_next - root|`` (an
    estimate); an exact zero at an iterate ends there. ``function_calls`` counts the
    evaluations. ConvergenceError naming ``what`` when ``f`` is not finite at an iterate,
    the secant is flat, a step leaves the open ``bounds`` or in ``maxiter`` steps.
    """
    require(finish in ("evaluated", "inverse_quadratic"),
            f"finish must be 'evaluated' or 'inverse_quadratic', got {finish!r}")
    require(int(maxiter) == maxiter and maxiter >= 1, f"maxiter must be >= 1, got {maxiter}")
    x0, x1 = _starts(x0, x1, bounds)
    xs = [x0, x1]
    fs = [_finite_value(f(x0), x0, what), _finite_value(f(x1), x1, what)]
    for it in range(int(maxiter) + 1):
        x_next = xs[-1] if fs[-1] == 0.0 else secant_step(
            xs[-2], fs[-2], xs[-1], fs[-1], bounds=bounds,
            what=f"{what} {list(zip(xs, fs, strict=True))}")
        if len(xs) >= 3 and (x_next == xs[-1] or converged(xs[-1], x_next)):
            root = xs[-1] if finish == "evaluated" or fs[-1] == 0.0 else (
                inverse_quadratic_root(xs[-3:], fs[-3:]))
            near = _narrowest_sign_change(zip(xs, fs, strict=True))
            return RootResult(float(root), it, len(xs), True, "step below tolerance", near,
                              (near[1] - near[0]) if near is not None else abs(x_next - root),
                              "secant", next_iterate=float(x_next))
        if it < maxiter:
            xs.append(x_next)
            fs.append(_finite_value(f(x_next), x_next, what))
    raise ConvergenceError(f"{what}: no convergence in {maxiter} steps: "
                           f"{list(zip(xs, fs, strict=True))}")


def secant_zero(f: Callable[[float], float], xs: list[float], fs: list[float], *,
                xtol: float, stall_width: float, stall_count: int = 4, maxit: int = 30,
                what: str = "secant_zero") -> tuple[int, float]:
    """Zero of ``f`` from the two evaluated points (``xs``, ``fs``), appending every
    evaluation to them: returns (index of the answer in ``xs``, its tolerance). The
    answer is an evaluated point, for a caller whose evaluations carry a state.

    When the two starting values of f have opposite signs, the iterates stay inside the
    bracket they span: the Illinois variant of false position (Dowell and Jarratt 1971),
    whose retained end has its f halved when it is kept twice in a row, so that the bracket
    shrinks from both sides (plain false position can approach the root from one side
    only and stagnate). It stops when a step is below ``xtol`` (the last iterate,
    tolerance the step) or when the bracket is narrower than ``stall_width`` (the end
    with the smaller |f|, tolerance the bracket's width): at the round-off floor of f the
    computed signs still bound the root. Without a bracket it is the secant iteration, which
    stops on a step below ``xtol`` or when it has stagnated at the round-off floor (the
    last ``stall_count`` iterates within ``stall_width`` and f of both signs among them:
    the one with the smallest |f|, tolerance their spread). ConvergenceError after
    ``maxit`` evaluations, or on a flat secant."""
    require(len(xs) >= 2 and len(xs) == len(fs), "secant_zero needs two evaluated points")
    if fs[-2] * fs[-1] < 0:
        return _illinois(f, xs, fs, xtol=xtol, stall_width=stall_width, maxit=maxit,
                         what=what)
    for _ in range(maxit):
        x_new = secant_step(xs[-2], fs[-2], xs[-1], fs[-1],
                            what=f"{what} {list(zip(xs, fs, strict=True))}")
        step = abs(x_new - xs[-1])
        xs.append(x_new)
        fs.append(f(x_new))
        if step < xtol:
            return len(xs) - 1, step
        last, signs = xs[-stall_count:], np.sign(fs[-stall_count:])
        if (len(xs) >= stall_count + 2 and max(last) - min(last) < stall_width
                and signs.min() < 0 < signs.max()):
            tail = range(len(xs) - stall_count, len(xs))
            return min(tail, key=lambda i: abs(fs[i])), max(last) - min(last)
    raise ConvergenceError(f"{what}: no convergence in {maxit} steps: "
                           f"{list(zip(xs, fs, strict=True))}")


def _illinois(f, xs: list[float], fs: list[float], *, xtol: float, stall_width: float,
              maxit: int, what: str) -> tuple[int, float]:
    """The bracketed branch of :func:`secant_zero` (its last two points bracket a root)."""
    ends = [len(xs) - 2, len(xs) - 1]
    weights = [fs[-2], fs[-1]]
    kept = None
    for _ in range(maxit):
        (ia, ib), (fa, fb) = ends, weights
        x_new = xs[ia] - fa * (xs[ib] - xs[ia]) / (fb - fa)
        step = abs(x_new - xs[-1])
        fx = f(x_new)
        xs.append(x_new)
        fs.append(fx)
        if fx == 0 or step < xtol:
            return len(xs) - 1, step
        side = 0 if np.sign(fx) == np.sign(fs[ia]) else 1
        ends[side], weights[side] = len(xs) - 1, fx
        if kept == 1 - side:
            weights[1 - side] *= 0.5
        kept = 1 - side
        width = abs(xs[ends[1]] - xs[ends[0]])
        if width < stall_width:
            return min(ends, key=lambda i: abs(fs[i])), width
    raise ConvergenceError(f"{what}: no convergence in {maxit} steps: "
                           f"{list(zip(xs, fs, strict=True))}")
