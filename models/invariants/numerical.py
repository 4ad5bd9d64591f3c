"""Numerical derivatives of the invariants: complex step and central differences.

First derivatives by the complex step ``Im f(x + i h e)/h`` (no subtractive cancellation,
exact to rounding for h = 1e-30); second derivatives by central differences (step
``h2``) of the complex-step gradient, error ``O(h2^2)`` - the invariants are polynomials of
degree <= 6 in F, so the truncation term is ``h2^2/6`` times a bounded third derivative.
Independent of the closed forms and of sympy: only :func:`~debench.models.invariants.invariants`
is used.
"""

from __future__ import annotations

import numpy as np
from debench.models.invariants.closed_form import invariants, validate_state
from debench.models.validation import deformation_gradient, tolerance

CS_STEP = 1e-30
FD_STEP = 1e-4


def complex_step_gradients(F, D_L, A=None, *, numbering: str = "iso"):
    """``(dI/dF (6,3,3), dI/dD (6,3))``, the first derivatives of the invariants by the
    complex step (step ``CS_STEP`` = 1e-30: exact to rounding, no subtractive cancellation);
    layout of :mod:`debench.models.invariants`."""
    F, D_L, A = validate_state(F, D_L, A, numbering=numbering)
    F = np.asarray(F, dtype=complex)
    D_L = np.asarray(D_L, dtype=complex)
    dF = np.zeros((6, 3, 3))
    dD = np.zeros((6, 3))
    for i in range(3):
        for a in range(3):
            Fp = F.copy()
            Fp[i, a] += 1j * CS_STEP
            dF[:, i, a] = invariants(Fp, D_L, A, numbering=numbering).imag / CS_STEP
    for a in range(3):
        Dp = D_L.copy()
        Dp[a] += 1j * CS_STEP
        dD[:, a] = invariants(F, Dp, A, numbering=numbering).imag / CS_STEP
    return dF, dD


def derivatives(F, D_L, A=None, *, numbering: str = "iso", h2: float = FD_STEP) -> dict:
    """Dict ``I, dF, dD, dFF, dFD, dDD`` (layout of :mod:`debench.models.invariants`).

    ``h2`` is the central-difference step, a finite number in (0, 1).
    """
    tolerance("h2", h2)
    F, D_L, A = validate_state(F, D_L, A, numbering=numbering)
    F = np.asarray(F, dtype=float)
    D_L = np.asarray(D_L, dtype=float)
    I = invariants(F, D_L, A, numbering=numbering)
    dF, dD = complex_step_gradients(F, D_L, A, numbering=numbering)
    dFF = np.zeros((6, 3, 3, 3, 3))
    dFD = np.zeros((6, 3, 3, 3))
    dDD = np.zeros((6, 3, 3))
    for j in range(3):
        for b in range(3):
            e = np.zeros((3, 3))
            e[j, b] = h2
            gp, _ = complex_step_gradients(F + e, D_L, A, numbering=numbering)
            gm, _ = complex_step_gradients(F - e, D_L, A, numbering=numbering)
            dFF[:, :, :, j, b] = (gp - gm) / (2 * h2)
    for b in range(3):
        e = np.zeros(3)
        e[b] = h2
        gpF, gpD = complex_step_gradients(F, D_L + e, A, numbering=numbering)
        gmF, gmD = complex_step_gradients(F, D_L - e, A, numbering=numbering)
        dFD[:, :, :, b] = (gpF - gmF) / (2 * h2)
        dDD[:, :, b] = (gpD - gmD) / (2 * h2)
    return {"I": I, "dF": dF, "dD": dD, "dFF": dFF, "dFD": dFD, "dDD": dDD}


def central_difference_F(fun, F, h: float = FD_STEP) -> np.ndarray:
    """Central difference of a tensor function of F: ``out[..., k, l] = d fun / dF_kl``.

    ``fun(F)`` may return any array shape S; the result has shape ``S + (3, 3)``.
    Truncation error ``O(h^2)``. ``h`` is a finite step in (0, 1); ``F`` a finite (3, 3)
    array with ``det F > 0``; a non-finite value of ``fun`` raises ValueError.
    """
    if not callable(fun):
        raise TypeError(f"fun must be callable, got {fun!r}")
    tolerance("h", h)
    F = np.asarray(deformation_gradient("F", F), dtype=float)
    cols = []
    for k in range(3):
        for l_ in range(3):
            e = np.zeros((3, 3))
            e[k, l_] = h
            cols.append((np.asarray(fun(F + e)) - np.asarray(fun(F - e))) / (2 * h))
    arr = np.array(cols).reshape((3, 3) + np.shape(cols[0]))
    if not np.all(np.isfinite(arr)):
        raise ValueError("central_difference_F: fun returned non-finite values near F")
    return np.moveaxis(arr, (0, 1), (-2, -1))
