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
