"""Exceptions shared by all models: solvers never fail silently."""

from __future__ import annotations


class ConvergenceError(RuntimeError):
    """A nonlinear solver, continuation or root bracketing did not converge.

    Raised instead of returning a number; the message names the solver, the last
    residual or bracket, and the parameters.
    """


def require(condition: bool, message: str) -> None:
    """Raise ``ValueError(message)`` unless ``condition``; message names the bound."""
    if not condition:
        raise ValueError(message)


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
