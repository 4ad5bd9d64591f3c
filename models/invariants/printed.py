"""The invariant-derivative and closed-form stress formulas transcribed AS PRINTED.

These are the object under test: each function is the thesis formula with its indices
exactly as printed (re-read from the PDF; ``c = C``, ``b = B``, ``a = A``), *including*
errors. Do not fix them here - fixes live in :mod:`debench.models.invariants.closed_form` and the
catalogue (``reference/catalogue/ch2_appendix.toml``) records which differ.

:data:`PRINTED_DERIVATIVES` maps an equation label to ``(numbering, kind, n, func)``:
``kind`` in ``{"F", "D", "FF", "FD", "DD"}`` (derivative w.r.t. F and/or D_L), ``n`` the
invariant number (1..6) and ``func(F, D_L, A) -> ndarray`` in the index layout of
:mod:`debench.models.invariants` (``[i, a]``, ``[a]``, ``[i, a, j, b]``, ``[i, a, b]``, ``[a, b]``).
Formulas printed twice (Ch. 2 and App. A.2, Ch. 4 and App. A.1) appear under both labels.
"""

from __future__ import annotations

import functools
import inspect

import numpy as np
from debench.models import validation as _v

_d = np.eye(3)

#: argument name -> check at the public boundary (every formula below is decorated)
_CHECKS = {
    "F": lambda x: _v.deformation_gradient("F", x),
    "D": lambda x: _v.vector("D", x),
    "D_L": lambda x: _v.vector("D_L", x),
    "E_L": lambda x: _v.vector("E_L", x),
    "A": lambda x: None if x is None else _v.unit_vector("A", x),
    "W": lambda x: _v.vector("W", x, 6),
    "p": lambda x: _v.finite("p", x),
    "C10": lambda x: _v.positive("C10", x),
    "D1": lambda x: _v.positive("D1", x),
    "eps": lambda x: _v.positive("eps", x),
    "k": lambda x: _v.positive("k", x),
    "lam": lambda x: _v.positive("lam", _v.vector("lam", x)),
    "alphas": lambda x: [_v.finite("alphas", a) for a in x],
    "mus": lambda x: [_v.finite("mus", m) for m in x],
}


def _checked(f):
    """Validate the arguments of a transcribed formula by name (:data:`_CHECKS`)."""
    sig = inspect.signature(f)

    @functools.wraps(f)
    def wrapper(*args, **kwargs):
        bound = sig.bind(*args, **kwargs)
        bound.apply_defaults()
        for name, value in bound.arguments.items():
            if name in ("alphas", "mus") and (isinstance(value, str | bytes)
                                              or not hasattr(value, "__len__")):
                raise TypeError(f"{name} must be a sequence of numbers, got {value!r}")
            checked = _CHECKS[name](value)
            if checked is not None and name not in ("alphas", "mus"):
                bound.arguments[name] = np.asarray(checked, dtype=float)
        if "alphas" in bound.arguments and len(bound.arguments["alphas"]) != len(
                bound.arguments["mus"]):
            raise ValueError("alphas and mus must have equal length")
        out = _v.finite_result(f)(*bound.args, **bound.kwargs)
        if not np.all(np.isfinite(out)):
            raise ValueError(f"{f.__name__}: non-finite result at this state (overflow)")
        return out

    return wrapper


def _C(F):
    return F.T @ F


def _b(F):
    return F @ F.T


# ---------------------------------------------------------------- first derivatives
@_checked
def dI1_dF(F, D, A=None):
    """(2.75)/(4.35)/(A.1)/(A.18): ``2 F_ia``."""
    return 2 * F


@_checked
def dI2_dF(F, D, A=None):
    """(2.76)/(4.36)/(A.2)/(A.19): ``2 (c_gg F_ia - c_ag F_ig)``."""
    c = _C(F)
    return 2 * (np.trace(c) * F - np.einsum("ag,ig->ia", c, F))


@_checked
def dI3_dF(F, D, A=None):
    """(2.77)/(4.37)/(A.3)/(A.20): ``2 I3 Finv_ai``."""
    I3 = np.linalg.det(_C(F))
    return 2 * I3 * np.linalg.inv(F).T


@_checked
def dI4ti_dF(F, D, A):
    """(4.38)/(A.4) as printed: ``a_a (F_ik a_k - F_im a_m)`` - identically zero."""
    return np.einsum("a,i->ia", A, np.einsum("ik,k->i", F, A) - np.einsum("im,m->i", F, A))


@_checked
def dI5_dF(F, D, A=None):
    """(2.78)/(4.39)/(A.5)/(A.21): ``2 D_a F_ig D_g``."""
    return 2 * np.einsum("a,ig,g->ia", D, F, D)


@_checked
def dI6iso_dF(F, D, A=None):
    """(2.79)/(A.22): ``2 (c_ab D_b F_ig D_g + D_a F_ig c_gb D_b)``."""
    c = _C(F)
    return 2 * (np.einsum("ab,b,ig,g->ia", c, D, F, D) + np.einsum("a,ig,gb,b->ia", D, F, c, D))


@_checked
def dI6ti_dF(F, D, A=None):
    """(4.40)/(A.6): ``0``."""
    return np.zeros((3, 3))


@_checked
def dI4iso_dD(F, D, A=None):
    """(2.80)/(A.23): ``2 D_a``."""
    return 2 * D


@_checked
def dI5_dD(F, D, A=None):
    """(2.81)/(4.41)/(A.7)/(A.24): ``2 c_ab D_b``."""
    return 2 * _C(F) @ D


@_checked
def dI6iso_dD(F, D, A=None):
    """(2.82)/(A.25): ``2 c^2_ab D_b``."""
    c = _C(F)
    return 2 * c @ c @ D


@_checked
def dI6ti_dD(F, D, A=None):
    """(4.42)/(A.8): ``2 D_a``."""
    return 2 * D


# --------------------------------------------------------------- second derivatives
@_checked
def d2I1_dFdF(F, D, A=None):
    """(2.83)/(4.43)/(A.9)/(A.26): ``2 d_ij d_ab``."""
    return 2 * np.einsum("ij,ab->iajb", _d, _d)


@_checked
def d2I2_dFdF(F, D, A=None):
    """(2.84)/(4.44)/(A.10)/(A.27):
    ``2 (2 F_ia F_jb - F_ib F_ja + c_gg d_ij d_ab - b_ij d_ab - c_ab d_ij)``."""
    c, b = _C(F), _b(F)
    return 2 * (2 * np.einsum("ia,jb->iajb", F, F) - np.einsum("ib,ja->iajb", F, F)
                + np.trace(c) * np.einsum("ij,ab->iajb", _d, _d)
                - np.einsum("ij,ab->iajb", b, _d) - np.einsum("ab,ij->iajb", c, _d))


@_checked
def d2I3_dFdF(F, D, A=None):
    """(2.85)/(4.45)/(A.11)/(A.28): ``2 I3 (2 Finv_ai Finv_bj - Finv_aj Finv_bi)``."""
    Fi = np.linalg.inv(F)
    I3 = np.linalg.det(_C(F))
    return 2 * I3 * (2 * np.einsum("ai,bj->iajb", Fi, Fi) - np.einsum("aj,bi->iajb", Fi, Fi))


@_checked
def d2I4ti_dFdF(F, D, A):
    """(4.46)/(A.12): ``2 a_a a_b d_ij``."""
    return 2 * np.einsum("a,b,ij->iajb", A, A, _d)


@_checked
def d2I5_dFdF(F, D, A=None):
    """(2.86)/(4.47)/(A.13)/(A.29): ``2 d_ij D_a D_b``."""
    return 2 * np.einsum("ij,a,b->iajb", _d, D, D)


@_checked
def d2I6iso_dFdF(F, D, A=None):
    """(2.87)/(A.30): ``2 [d_ij (c_ag D_g D_b + c_bg D_g D_a) + d_ab F_ig D_g F_jd D_d
    + F_ig D_g F_ja D_b + F_jg D_g F_ib D_a + b_ij D_a D_b]``."""
    c, b = _C(F), _b(F)
    FD = F @ D
    return 2 * (np.einsum("ij,ag,g,b->iajb", _d, c, D, D)
                + np.einsum("ij,bg,g,a->iajb", _d, c, D, D)
                + np.einsum("ab,i,j->iajb", _d, FD, FD) + np.einsum("i,ja,b->iajb", FD, F, D)
                + np.einsum("j,ib,a->iajb", FD, F, D) + np.einsum("ij,a,b->iajb", b, D, D))


@_checked
def d2I6ti_dFdF(F, D, A=None):
    """(4.48)/(A.14): ``0``."""
    return np.zeros((3, 3, 3, 3))


@_checked
def d2I4iso_dDdD(F, D, A=None):
    """(2.88)/(A.31): ``2 d_ab``."""
    return 2 * _d


@_checked
def d2I5_dDdD(F, D, A=None):
    """(2.89)/(4.49)/(A.15)/(A.32): ``2 c_ab``."""
    return 2 * _C(F)


@_checked
def d2I6iso_dDdD(F, D, A=None):
    """(2.90)/(A.33): ``2 c^2_ab``."""
    c = _C(F)
    return 2 * c @ c


@_checked
def d2I6ti_dDdD(F, D, A=None):
    """(4.50)/(A.16): ``2 d_ab``."""
    return 2 * _d


@_checked
def d2I5_dFdD(F, D, A=None):
    """(2.91)/(4.51)/(A.17)/(A.34): ``2 d_ab F_ig D_g + 2 D_a F_ib``."""
    return 2 * np.einsum("ab,ig,g->iab", _d, F, D) + 2 * np.einsum("a,ib->iab", D, F)


@_checked
def d2I6iso_dFdD(F, D, A=None):
    """(2.92)/(A.35): ``2 F_ib c_ag D_g + 2 F_ig D_g c_ab + 2 F_ig c_gb D_a
    + 2 d_ab F_ig c_gd D_d``."""
    c = _C(F)
    return (2 * np.einsum("ib,ag,g->iab", F, c, D) + 2 * np.einsum("ig,g,ab->iab", F, D, c)
            + 2 * np.einsum("ig,gb,a->iab", F, c, D)
            + 2 * np.einsum("ab,ig,gd,d->iab", _d, F, c, D))


_ISO = [  # (Ch. 2 label, App. A.2 label, kind, n, func)
    ("2.75", "A.18", "F", 1, dI1_dF), ("2.76", "A.19", "F", 2, dI2_dF),
    ("2.77", "A.20", "F", 3, dI3_dF), ("2.78", "A.21", "F", 5, dI5_dF),
    ("2.79", "A.22", "F", 6, dI6iso_dF), ("2.80", "A.23", "D", 4, dI4iso_dD),
    ("2.81", "A.24", "D", 5, dI5_dD), ("2.82", "A.25", "D", 6, dI6iso_dD),
    ("2.83", "A.26", "FF", 1, d2I1_dFdF), ("2.84", "A.27", "FF", 2, d2I2_dFdF),
    ("2.85", "A.28", "FF", 3, d2I3_dFdF), ("2.86", "A.29", "FF", 5, d2I5_dFdF),
    ("2.87", "A.30", "FF", 6, d2I6iso_dFdF), ("2.88", "A.31", "DD", 4, d2I4iso_dDdD),
    ("2.89", "A.32", "DD", 5, d2I5_dDdD), ("2.90", "A.33", "DD", 6, d2I6iso_dDdD),
    ("2.91", "A.34", "FD", 5, d2I5_dFdD), ("2.92", "A.35", "FD", 6, d2I6iso_dFdD),
]
_TI = [  # (Ch. 4 label, App. A.1 label, kind, n, func)
    ("4.35", "A.1", "F", 1, dI1_dF), ("4.36", "A.2", "F", 2, dI2_dF),
    ("4.37", "A.3", "F", 3, dI3_dF), ("4.38", "A.4", "F", 4, dI4ti_dF),
    ("4.39", "A.5", "F", 5, dI5_dF), ("4.40", "A.6", "F", 6, dI6ti_dF),
    ("4.41", "A.7", "D", 5, dI5_dD), ("4.42", "A.8", "D", 6, dI6ti_dD),
    ("4.43", "A.9", "FF", 1, d2I1_dFdF), ("4.44", "A.10", "FF", 2, d2I2_dFdF),
    ("4.45", "A.11", "FF", 3, d2I3_dFdF), ("4.46", "A.12", "FF", 4, d2I4ti_dFdF),
    ("4.47", "A.13", "FF", 5, d2I5_dFdF), ("4.48", "A.14", "FF", 6, d2I6ti_dFdF),
    ("4.49", "A.15", "DD", 5, d2I5_dDdD), ("4.50", "A.16", "DD", 6, d2I6ti_dDdD),
    ("4.51", "A.17", "FD", 5, d2I5_dFdD),
]

#: equation label -> ``(numbering, kind, n, func)`` of every printed derivative formula
PRINTED_DERIVATIVES: dict[str, tuple[str, str, int, object]] = {}
for _numbering, _table in (("iso", _ISO), ("ti", _TI)):
    for _lab1, _lab2, _kind, _n, _f in _table:
        PRINTED_DERIVATIVES[_lab1] = (_numbering, _kind, _n, _f)
        PRINTED_DERIVATIVES[_lab2] = (_numbering, _kind, _n, _f)

SAME_FORMULA = {lab2: lab1 for _t in (_ISO, _TI) for lab1, lab2, *_ in _t}
"""App. A label -> the Ch. 2/Ch. 4 label printing the same formula."""


# ----------------------------------------------------------- closed-form stresses
@_checked
def cauchy_2_42(W, F, D_L, p):
    """(2.42) as printed, incompressible, ``W = (W1, ..., W6)``::

        sigma = 2 W1 B + 2 W2 (I1 B - B^2) - p I + 2 W6 (D (x) BD - BD (x) D)

    with the Eulerian ``D = F D_L`` (J = 1).
    """
    B = _b(F)
    D = F @ D_L
    I1 = np.trace(B)
    return (2 * W[0] * B + 2 * W[1] * (I1 * B - B @ B) - p * np.eye(3)
            + 2 * W[5] * (np.outer(D, B @ D) - np.outer(B @ D, D)))


@_checked
def cauchy_2_42_corrected(W, F, D_L, p):
    """(2.42) re-derived from (2.33) with (2.78)-(2.79) (Dorfmann & Ogden 2005):

    ::

        sigma = 2 W1 B + 2 W2 (I1 B - B^2) - p I + 2 W5 D (x) D + 2 W6 (D (x) BD + BD (x) D)
    """
    B = _b(F)
    D = F @ D_L
    I1 = np.trace(B)
    return (2 * W[0] * B + 2 * W[1] * (I1 * B - B @ B) - p * np.eye(3)
            + 2 * W[4] * np.outer(D, D) + 2 * W[5] * (np.outer(D, B @ D) + np.outer(B @ D, D)))


@_checked
def electric_2_43(W, F, D_L):
    """(2.43) as printed: ``E = 2 (W4 B^{-1} D + W5 D + W6 B D)``, D = F D_L (J = 1)."""
    B = _b(F)
    D = F @ D_L
    return 2 * (W[3] * np.linalg.solve(B, D) + W[4] * D + W[5] * B @ D)


@_checked
def pk2_5_18(C10, D1, eps, F, D_L):
    """(5.18) as printed:

    ::

        S = 2 (C10 J^{-2/3} (I - 1/3 I1bar Cdis^{-1}) + 1/D1 J (J - 1) C^{-1})
            - 1/(2 eps) J^{-1} C^{-1} (D_L . C D_L) + 1/eps J^{-1} D_L (x) D_L
    """
    C = _C(F)
    J = np.linalg.det(F)
    Cdis = J ** (-2 / 3) * C
    I1bar = np.trace(Cdis)
    Ci = np.linalg.inv(C)
    return (2 * (C10 * J ** (-2 / 3) * (np.eye(3) - I1bar / 3 * np.linalg.inv(Cdis))
                 + J * (J - 1) / D1 * Ci)
            - Ci * (D_L @ C @ D_L) / (2 * eps * J) + np.outer(D_L, D_L) / (eps * J))


@_checked
def piola_5_19(C10, D1, eps, F, D_L):
    """(5.19) as printed (``T_L = F S``, first Piola), D = J^{-1} F D_L:

    ::

        T_L = 2 (C10 J^{-2/3} (F - 1/3 (tr C) F^{-T}) + 1/D1 J (J - 1) F^{-T})
              - 1/(2 eps) J (D . D) F^{-T} + 1/eps D (x) D_L
    """
    C = _C(F)
    J = np.linalg.det(F)
    FiT = np.linalg.inv(F).T
    D = F @ D_L / J
    return (2 * (C10 * J ** (-2 / 3) * (F - np.trace(C) / 3 * FiT) + J * (J - 1) / D1 * FiT)
            - J * (D @ D) * FiT / (2 * eps) + np.outer(D, D_L) / eps)


@_checked
def cauchy_5_20(C10, D1, eps, F, D_L):
    """(5.20) as printed (the text shows no identity after ``tr B_dis`` and ``D . D``;
    a scalar added to a tensor, transcribed with numpy broadcasting):

    ::

        sigma = 2 C10/J (B_dis - 1/3 (tr B_dis)) + 2/D1 (J - 1) I - 1/(2 eps) (D . D)
                + 1/eps D (x) D
    """
    B = _b(F)
    J = np.linalg.det(F)
    Bdis = J ** (-2 / 3) * B
    D = F @ D_L / J
    return (2 * C10 / J * (Bdis - np.trace(Bdis) / 3) + 2 / D1 * (J - 1) * np.eye(3)
            - (D @ D) / (2 * eps) + np.outer(D, D) / eps)


@_checked
def cauchy_5_20_corrected(C10, D1, eps, F, D_L):
    """(5.20) with the identity tensors restored (``- 1/3 tr B_dis I``, ``- (D.D)/(2 eps) I``)."""
    B = _b(F)
    J = np.linalg.det(F)
    Bdis = J ** (-2 / 3) * B
    D = F @ D_L / J
    I = np.eye(3)
    return (2 * C10 / J * (Bdis - np.trace(Bdis) / 3 * I) + 2 / D1 * (J - 1) * I
            - (D @ D) / (2 * eps) * I + np.outer(D, D) / eps)


# ------------------------------------------------ Ch. 5 tangents (enthalpy form, (5.21)-(5.28))
# The FE model of Ch. 5 uses (F, E_L) as independent variables; E = F^-T E_L, D_L =
# eps J C^-1 E_L. Index layout as printed: T_L,ij (i spatial, j material), d/dF_kl.
@_checked
def tangent_5_21(C10, F):
    """(5.21) as printed, ``dT^mech_L,ij/dF_kl``::

        2 C10 J^-2/3 (-2/3 Finv_lk F_ij + 2/9 Finv_lk trc Finv_ji + d_ik d_jl
                      - 2/3 F_kl Finv_ji + 1/3 trc Finv_jk Finv_li)

    (no volumetric term). Array ``[i, j, k, l]``.
    """
    J = np.linalg.det(F)
    Fi = np.linalg.inv(F)
    trc = np.trace(F.T @ F)
    return 2 * C10 * J ** (-2 / 3) * (
        -2 / 3 * np.einsum("lk,ij->ijkl", Fi, F) + 2 / 9 * trc * np.einsum("lk,ji->ijkl", Fi, Fi)
        + np.einsum("ik,jl->ijkl", _d, _d) - 2 / 3 * np.einsum("kl,ji->ijkl", F, Fi)
        + 1 / 3 * trc * np.einsum("jk,li->ijkl", Fi, Fi))


@_checked
def tangent_5_21_volumetric(D1, F):
    """The volumetric tangent missing from (5.21): d/dF_kl of ``2/D1 J (J - 1) Finv_ji``
    = ``2/D1 [(2J - 1) J Finv_lk Finv_ji - J (J - 1) Finv_jk Finv_li]``."""
    J = np.linalg.det(F)
    Fi = np.linalg.inv(F)
    return 2 / D1 * ((2 * J - 1) * J * np.einsum("lk,ji->ijkl", Fi, Fi)
                     - J * (J - 1) * np.einsum("jk,li->ijkl", Fi, Fi))


def _enthalpy_kinematics(F, E_L):
    J = np.linalg.det(F)
    Fi = np.linalg.inv(F)
    Ci = Fi @ Fi.T
    return J, Fi, Ci, Fi.T @ E_L, Ci @ E_L


@_checked
def tangent_5_22(eps, F, E_L):
    """(5.22) as printed, ``dT^elec_L,ij/dF_kl`` (E = F^-T E_L):

    ::

        eps J (-Finv_li Cinv_jm EL_m E_k - E_i Finv_jk Cinv_lm EL_m - E_i E_k Cinv_jl
               + Finv_ji E_k Cinv_lm EL_m + E_i Cinv_jm EL_m Finv_lk
               + 1/2 E_m E_m Finv_li Finv_jk - 1/2 E_m E_m Finv_ji Finv_lk)
    """
    J, Fi, Ci, E, CE = _enthalpy_kinematics(F, E_L)
    EE = E @ E
    return eps * J * (
        -np.einsum("li,j,k->ijkl", Fi, CE, E) - np.einsum("i,jk,l->ijkl", E, Fi, CE)
        - np.einsum("i,k,jl->ijkl", E, E, Ci) + np.einsum("ji,k,l->ijkl", Fi, E, CE)
        + np.einsum("i,j,lk->ijkl", E, CE, Fi) + 0.5 * EE * np.einsum("li,jk->ijkl", Fi, Fi)
        - 0.5 * EE * np.einsum("ji,lk->ijkl", Fi, Fi))


@_checked
def tangent_5_23(eps, F, E_L):
    """(5.23) as printed, ``dT^elec_L,ij/dEL_l = eps J (Finv_li Cinv_jm EL_m + Cinv_jl E_i
    - Finv_ji Cinv_lm EL_m)``, array ``[i, j, l]``."""
    J, Fi, Ci, E, CE = _enthalpy_kinematics(F, E_L)
    return eps * J * (np.einsum("li,j->ijl", Fi, CE) + np.einsum("jl,i->ijl", Ci, E)
                      - np.einsum("ji,l->ijl", Fi, CE))


@_checked
def tangent_5_24(eps, F, E_L):
    """(5.24) as printed, ``dD_L,j/dF_kl = eps J (Finv_lk Cinv_jm EL_m - Finv_jk Cinv_lm EL_m
    - Finv_mk Cinv_jl EL_m)``, array ``[j, k, l]``."""
    J, Fi, Ci, E, CE = _enthalpy_kinematics(F, E_L)
    return eps * J * (np.einsum("lk,j->jkl", Fi, CE) - np.einsum("jk,l->jkl", Fi, CE)
                      - np.einsum("mk,jl,m->jkl", Fi, Ci, E_L))


@_checked
def tangent_5_25(eps, F, E_L):
    """(5.25) as printed, ``dD_L,j/dEL_l = eps J Cinv_jl``."""
    J, _, Ci, _, _ = _enthalpy_kinematics(F, E_L)
    return eps * J * Ci


@_checked
def dtau_db_5_28(alphas, mus, k, lam):
    """(5.28) as printed, ``dtau_i/db_j`` (b_j = lambda_j^2) of the Ogden model:

    ::

        sum_p mu_p/(3 l_j^2) J^(-a_p/3) (1/3 sum_k l_k^a_p - l_i^a_p - l_j^a_p
                                         + 3 l_i^a_p d_ij) + k (2J - 1) J/(2 l_j^2)
    """
    lam = np.asarray(lam, dtype=float)
    J = np.prod(lam)
    out = np.zeros((3, 3))
    for a, m in zip(alphas, mus, strict=True):
        la = lam**a
        out += (m / (3 * lam[None, :] ** 2) * J ** (-a / 3)
                * (la.sum() / 3 - la[:, None] - la[None, :] + 3 * np.diag(la)))
    return out + k * (2 * J - 1) * J / (2 * lam[None, :] ** 2)
