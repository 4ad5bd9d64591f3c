"""Closed-form invariants and their first/second derivatives (corrected where needed).

Re-derived by hand and checked against sympy and complex-step differences
(``verification/test_invariants_*.py``). Compared with the thesis:

* every Ch. 2 / App. A.2 formula (2.75)-(2.92) = (A.18)-(A.35) agrees;
* (4.38) = (A.4) as printed, ``a_alpha (F_ik a_k - F_im a_m)``, is identically zero; the
  derivative of ``I4 = A.CA`` is ``dI4/dF_{i alpha} = 2 a_alpha F_{ik} a_k`` (used here).

All functions accept real or complex arrays (complex step), shape ``(3, 3)`` for F and
``(3,)`` for D_L and A.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from debench.models.validation import (
    choice,
    deformation_gradient,
    finite_result,
    unit_vector,
    vector,
)

#: the two numberings of the invariants: isotropic (Ch. 2, I4 = D_L.D_L) and transversely
#: isotropic (Ch. 4, I4 = A.C A)
NUMBERINGS = ("iso", "ti")
_I3 = np.eye(3)


def validate_state(F, D_L, A=None, *, numbering: str = "iso") -> tuple[np.ndarray, ...]:
    """Check shapes, finiteness and det F > 0; return float (or complex) arrays.

    Complex arrays are accepted (complex-step derivatives); ``det F`` is checked on the
    real part.

    Raises
    ------
    ValueError
        naming the violated bound (shape, NaN/inf, ``det F > 0``, ``|A| = 1``).
    TypeError
        for non-numeric input.
    """
    choice("numbering", numbering, NUMBERINGS)
    F = deformation_gradient("F", F, complex_ok=True)
    D_L = vector("D_L", D_L, complex_ok=True)
    if numbering == "ti":
        if A is None:
            raise ValueError("numbering 'ti' needs the unit fibre vector A")
        A = unit_vector("A", A)
    return F, D_L, A


@finite_result
def invariants(F, D_L, A=None, *, numbering: str = "iso") -> np.ndarray:
    """``[I1, ..., I6]`` in the chosen numbering (eqs (2.35)-(2.40) or (4.12)-(4.17)).

    The state is checked by :func:`validate_state` (ValueError naming the bound).
    """
    F, D_L, A = validate_state(F, D_L, A, numbering=numbering)
    C = F.T @ F
    trC = np.trace(C)
    C2 = C @ C
    I1 = trC
    I2 = 0.5 * (trC**2 - np.trace(C2))
    I3 = np.linalg.det(C) if not np.iscomplexobj(C) else _det3(C)
    I5 = D_L @ C @ D_L
    if numbering == "iso":
        I4 = D_L @ D_L
        I6 = D_L @ C2 @ D_L
    else:
        I4 = A @ C @ A
        I6 = D_L @ D_L
    return np.array([I1, I2, I3, I4, I5, I6])


def _det3(M):
    """Determinant by cofactors (works for complex arrays in the complex step)."""
    return (M[0, 0] * (M[1, 1] * M[2, 2] - M[1, 2] * M[2, 1])
            - M[0, 1] * (M[1, 0] * M[2, 2] - M[1, 2] * M[2, 0])
            + M[0, 2] * (M[1, 0] * M[2, 1] - M[1, 1] * M[2, 0]))


@dataclass(frozen=True)
class InvariantDerivatives:
    """Invariants and derivatives at one state (index convention: module docstring)."""

    numbering: str
    I: np.ndarray      # (6,)
    dF: np.ndarray     # (6, 3, 3)         dI_n/dF_{i a}
    dD: np.ndarray     # (6, 3)            dI_n/dD_a
    dFF: np.ndarray    # (6, 3, 3, 3, 3)   d2I_n/dF_{ia} dF_{jb}
    dFD: np.ndarray    # (6, 3, 3, 3)      d2I_n/dF_{ia} dD_b
    dDD: np.ndarray    # (6, 3, 3)         d2I_n/dD_a dD_b


@finite_result
def derivatives(F, D_L, A=None, *, numbering: str = "iso",
                second: bool = True) -> InvariantDerivatives:
    """Invariants with first (and second) derivatives w.r.t. F and D_L.

    Component forms (re-derived; numbers of the thesis formulas they correspond to):

    * (2.75) ``dI1/dF_ia = 2 F_ia``; (2.83) ``2 d_ij d_ab``
    * (2.76) ``dI2/dF_ia = 2 (c_gg F_ia - c_ag F_ig)``; (2.84)
    * (2.77) ``dI3/dF_ia = 2 I3 Finv_ai``; (2.85) ``2 I3 (2 Finv_ai Finv_bj - Finv_aj Finv_bi)``
    * iso: (2.78)-(2.82), (2.86)-(2.92); ti: (4.38) corrected ``2 a_a F_ik a_k``,
      (4.46) ``2 a_a a_b d_ij``, (4.40)/(4.48) zero, (4.42)/(4.50) ``2 D_a``, ``2 d_ab``.
    """
    F, D_L, A = validate_state(F, D_L, A, numbering=numbering)
    I = invariants(F, D_L, A, numbering=numbering)
    dt = np.result_type(F, D_L, float)
    d = np.eye(3)
    C = F.T @ F
    b = F @ F.T
    trC = np.trace(C)
    Finv = np.linalg.inv(F)
    I3 = I[2]
    FD = F @ D_L
    CD = C @ D_L

    dF = np.zeros((6, 3, 3), dtype=dt)
    dD = np.zeros((6, 3), dtype=dt)
    dF[0] = 2 * F
    dF[1] = 2 * (trC * F - F @ C)
    dF[2] = 2 * I3 * Finv.T
    dF[4] = 2 * np.outer(FD, D_L)                  # (2.78): 2 D_a F_ig D_g
    dD[4] = 2 * CD                                 # (2.81)
    if numbering == "iso":
        dF[5] = 2 * (np.outer(F @ CD, D_L) + np.outer(FD, CD))   # (2.79)
        dD[3] = 2 * D_L                            # (2.80)
        dD[5] = 2 * C @ CD                         # (2.82)
    else:
        dF[3] = 2 * np.outer(F @ A, A)             # (4.38) corrected
        dD[5] = 2 * D_L                            # (4.42)
    if not second:
        z = np.zeros
        return InvariantDerivatives(numbering, I, dF, dD, z((6, 3, 3, 3, 3)), z((6, 3, 3, 3)),
                                    z((6, 3, 3)))

    dFF = np.zeros((6, 3, 3, 3, 3), dtype=dt)
    dFD = np.zeros((6, 3, 3, 3), dtype=dt)
    dDD = np.zeros((6, 3, 3), dtype=dt)
    dd = np.einsum("ij,ab->iajb", d, d)
    dFF[0] = 2 * dd                                                        # (2.83)
    dFF[1] = 2 * (2 * np.einsum("ia,jb->iajb", F, F) - np.einsum("ib,ja->iajb", F, F)
                  + trC * dd - np.einsum("ij,ab->iajb", b, d)
                  - np.einsum("ij,ab->iajb", d, C))                        # (2.84)
    dFF[2] = 2 * I3 * (2 * np.einsum("ai,bj->iajb", Finv, Finv)
                       - np.einsum("aj,bi->iajb", Finv, Finv))             # (2.85)
    dFF[4] = 2 * np.einsum("ij,a,b->iajb", d, D_L, D_L)                    # (2.86)
    dFD[4] = 2 * (np.einsum("ab,i->iab", d, FD) + np.einsum("a,ib->iab", D_L, F))  # (2.91)
    dDD[4] = 2 * C                                                         # (2.89)
    if numbering == "iso":
        dFF[5] = 2 * (np.einsum("ij,a,b->iajb", d, CD, D_L)
                      + np.einsum("ij,b,a->iajb", d, CD, D_L)
                      + np.einsum("ab,i,j->iajb", d, FD, FD)
                      + np.einsum("i,ja,b->iajb", FD, F, D_L)
                      + np.einsum("j,ib,a->iajb", FD, F, D_L)
                      + np.einsum("ij,a,b->iajb", b, D_L, D_L))            # (2.87)
        FC = F @ C
        dFD[5] = 2 * (np.einsum("ib,a->iab", F, CD) + np.einsum("i,ab->iab", FD, C)
                      + np.einsum("ib,a->iab", FC, D_L)
                      + np.einsum("ab,i->iab", d, F @ CD))                 # (2.92)
        dDD[3] = 2 * d                                                     # (2.88)
        dDD[5] = 2 * C @ C                                                 # (2.90)
    else:
        dFF[3] = 2 * np.einsum("a,b,ij->iajb", A, A, d)                    # (4.46)
        dDD[5] = 2 * d                                                     # (4.50)
    return InvariantDerivatives(numbering, I, dF, dD, dFF, dFD, dDD)
