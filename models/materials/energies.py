"""Every energy of the library, written once, for every backend.

Each function below is the one definition of an energy (or of the kinematic quantity an
energy is a function of). Functions that need more than arithmetic and powers take a math
namespace ``xp`` (a :class:`MathNamespace`): :data:`NUMPY` evaluates the expression on
floats, arrays and complex numbers (the complex-step derivatives of the membrane);
:data:`debench.models.materials.ngsolve_forms.NGSOLVE` builds the same expression as an
NGSolve ``CoefficientFunction``, which NGSolve differentiates symbolically (``.Diff``).
Arithmetic and ``**`` are the operators of both backends, so purely algebraic energies
need no namespace. The numpy library (:mod:`~debench.models.materials.library`,
:mod:`~debench.models.materials.membrane`, the closed forms of Chapter 5) and the NGSolve
forms call these functions; they write no energy of their own.

What stays separate, on purpose: the first and second derivatives ``W_n``, ``W_mn`` of the
numpy chain rule and the spectral derivatives of Ogden (hand-derived, checked against
NGSolve's symbolic derivative of the expressions here, against complex step and sympy),
and the independent checks (sympy derivations, generated code, clean-room and peer codes).

Arguments are the invariants by name, so that both numberings of the thesis read the same
(iso: ``I4 = D_L.D_L``, ``I5 = D_L.C D_L``, ``I3 = J^2``; ti: ``I4 = A.C A``,
``I5 = D_L.C D_L``, ``I6 = D_L.D_L``), see :func:`invariants`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class MathNamespace:
    """The operations the energies use beyond arithmetic and ``**``.

    ``det``, ``trace``, ``inv``, ``transpose`` of a 3x3 matrix; ``matmul(A, B)`` the matrix
    product (matrix or vector ``B``); ``inner(a, b)`` the full contraction of two equal-shaped
    tensors (``a.b`` for vectors, ``A:B`` for matrices); ``log1p(x) = log(1 + x)``;
    ``vector(values)`` a constant 3-vector (a material's fibre).

    ``spectral(M, energy)`` evaluates an isotropic function of the eigenvalues ``m_i`` of a
    symmetric 3x3 ``M`` that is written through their power sums: ``energy(power_sum)``
    with ``power_sum(b) = sum_i m_i^b`` (Ogden (5.26)). This is the one operation a backend
    may evaluate in its own way: numpy by the eigenvalues of ``M``; NGSolve, which has no
    symmetric eigen-decomposition, by the forms of
    :mod:`debench.models.materials.ngsolve_forms` (regularised, or exact on the
    axisymmetric states), each its own namespace.
    """

    name: str
    det: Callable
    trace: Callable
    inv: Callable
    transpose: Callable
    matmul: Callable
    inner: Callable
    log1p: Callable
    vector: Callable
    spectral: Callable


def _numpy_spectral(M, energy):
    """``energy(power_sum)`` at the eigenvalues of the symmetric (real) matrix ``M``."""
    eigenvalues = np.linalg.eigvalsh(M)
    return energy(lambda b: sum(m**b for m in eigenvalues))


NUMPY = MathNamespace(
    name="numpy", det=np.linalg.det, trace=np.trace, inv=np.linalg.inv,
    transpose=np.transpose, matmul=np.matmul,
    inner=lambda a, b: np.tensordot(a, b, axes=np.ndim(a)), log1p=np.log1p,
    vector=lambda values: np.asarray(values, dtype=float), spectral=_numpy_spectral)
"""The numpy namespace (real or complex scalars and arrays; ``spectral`` real only)."""


# ----------------------------------------------------------------------- kinematics
def right_cauchy_green(F, *, xp):
    """``C = F^T F``."""
    return xp.matmul(xp.transpose(F), F)


def invariants(F, D_L=None, A=None, *, xp) -> dict:
    """The arguments of the energies at ``(F, D_L[, A])``, by name (Ch. 2 (2.35)-(2.40),
    Ch. 4 (4.12)-(4.17), Ch. 5 (5.5)-(5.7))::

        I1 = tr C,  I2 = ((tr C)^2 - C:C)/2,  J = det F,
        DD = D_L.D_L,  DCD = D_L.C D_L,  ACA = A.C A

    ``DD``, ``DCD`` only with ``D_L``, ``ACA`` only with a fibre ``A``.
    """
    C = right_cauchy_green(F, xp=xp)
    I1 = xp.trace(C)
    out = {"I1": I1, "I2": 0.5 * (I1 * I1 - xp.inner(C, C)), "J": xp.det(F)}
    if D_L is not None:
        out["DD"] = xp.inner(D_L, D_L)
        out["DCD"] = xp.inner(D_L, xp.matmul(C, D_L))
    if A is not None:
        out["ACA"] = xp.inner(A, xp.matmul(C, A))
    return out


def isochoric_right_cauchy_green(C, J):
    """``Cbar = J^{-2/3} C`` (``J = det F``), whose eigenvalues are the squared deviatoric
    principal stretches ``lb_k^2 = J^{-2/3} lambda_k^2`` of (5.26)."""
    return J ** (-2 / 3) * C


def membrane_first_invariant(l1, l2):
    """``I1 = l1^2 + l2^2 + l1^-2 l2^-2`` of the incompressible membrane (l3 = 1/(l1 l2)),
    Sec. 3.3.2."""
    return l1 * l1 + l2 * l2 + 1 / (l1 * l2) ** 2


# ------------------------------------------------------------------ elastic energies
def gent(I1, *, mu, Jm, xp):
    """Gent (3.23): ``Ws = -mu Jm/2 ln(1 - (I1 - 3)/Jm)`` (defined for ``I1 - 3 < Jm``)."""
    return -0.5 * mu * Jm * xp.log1p(-(I1 - 3) / Jm)


def gent_lock_margin(I1, *, kappa):
    """``1 - kappa (I1 - 3)`` with ``kappa = 1/Jm``: the argument of the logarithm of Gent
    (3.23), positive short of the locking stretch; its inverse is the Gent stiffening
    ``(2/mu) dWs/dI1`` that multiplies the neo-Hookean stresses (``kappa = 0``:
    neo-Hookean, margin 1)."""
    return 1 - kappa * (I1 - 3)


def neo_hookean_isochoric(I1, J, *, mu):
    """The isochoric neo-Hookean part of (5.15): ``C10 (J^{-2/3} I1 - 3)``, ``C10 = mu/2``
    (5.16)."""
    return 0.5 * mu * (J ** (-2 / 3) * I1 - 3)


def mooney_rivlin_isochoric(I1, I2, J, *, C10, C01):
    """The isochoric compressible Mooney-Rivlin energy:
    ``C10 (J^{-2/3} I1 - 3) + C01 (J^{-4/3} I2 - 3)`` (the invariants of ``Cbar``;
    ``C01 = 0`` is :func:`neo_hookean_isochoric` with ``mu = 2 C10``)."""
    return C10 * (J ** (-2 / 3) * I1 - 3) + C01 * (J ** (-4 / 3) * I2 - 3)


def volumetric(J, *, k):
    """The volumetric part of (5.15) and of the Ogden energy: ``(J - 1)^2/D1 =
    k/2 (J - 1)^2`` with ``D1 = 2/k`` (5.17)."""
    return 0.5 * k * (J - 1) ** 2


def neo_hookean(I1, J, *, mu, k):
    """Compressible neo-Hookean (5.15)-(5.17): ``mu/2 (J^{-2/3} I1 - 3) + k/2 (J - 1)^2``."""
    return neo_hookean_isochoric(I1, J, mu=mu) + volumetric(J, k=k)


def ogden_isochoric_from_power_sums(power_sum, *, alphas, mus):
    """Ogden (5.26) ``sum_p 2 mu_p/alpha_p^2 (lb1^a_p + lb2^a_p + lb3^a_p - 3)`` from the
    power sums ``power_sum(b) = sum_i cbar_i^b`` (``b = alpha_p/2``) of the eigenvalues
    ``cbar_i = lb_i^2`` of ``Cbar``, however a backend evaluates them (the
    ``2 mu_p/alpha_p^2`` convention of (5.26), consistent with the Kirchhoff stress (5.27))."""
    return sum(2 * mu / alpha**2 * (power_sum(alpha / 2) - 3)
               for alpha, mu in zip(alphas, mus, strict=True))


def ogden_term(cbar, *, alpha, mu):
    """One term of (5.26) from the three eigenvalues ``cbar = (lb1^2, lb2^2, lb3^2)`` of
    ``Cbar`` (:func:`isochoric_right_cauchy_green`, :func:`ogden_isochoric_from_power_sums`)."""
    return ogden_isochoric_from_power_sums(lambda b: sum(c**b for c in cbar),
                                           alphas=(alpha,), mus=(mu,))


def ogden_isochoric(cbar, *, alphas, mus):
    """Ogden (5.26): the sum over p of :func:`ogden_term`."""
    return sum(ogden_term(cbar, alpha=a, mu=mu) for a, mu in zip(alphas, mus, strict=True))


def ti_neo_hookean_elastic(I1, ACA, *, mu, xi):
    """The elastic part of (4.22): ``mu/2 (I1 - 3) + mu xi/2 (A.CA - 1)^2``."""
    return 0.5 * mu * (I1 - 3) + 0.5 * mu * xi * (ACA - 1) ** 2


# ----------------------------------------------------------------- electric energies
def ideal_dielectric(DCD, J, *, eps):
    """Ideal dielectric (5.9): ``W_ele = J^{-1} D_L.C D_L/(2 eps) = I5/(2 eps J)``."""
    return DCD / (2 * eps * J)


def ideal_dielectric_enthalpy(F, E_L, *, eps, xp):
    """Partial Legendre transform of (5.9) in the referential field ``E_L``:
    ``min_D (I5/(2 eps J) - E_L.D_L) = -eps/2 J C^-1 : (E_L x E_L)``, attained at
    ``D_L = eps J C^-1 E_L`` (so that ``E_L = dW/dD_L``, eq. (5.13))."""
    C = right_cauchy_green(F, xp=xp)
    return -0.5 * eps * xp.det(F) * xp.inner(xp.matmul(xp.inv(C), E_L), E_L)


def dorfmann_ogden_electric(DD, DCD, *, alpha, beta, eps):
    """Dorfmann-Ogden (4.20): ``(alpha D_L.D_L + beta D_L.C D_L)/(2 eps)``."""
    return (alpha * DD + beta * DCD) / (2 * eps)


def zhao_suo_permittivity(l1, l2, *, eps_bar, c):
    """Zhao-Suo (3.27): ``eps = eps_bar [1 + c (l1 + l2 - 2)]``."""
    return eps_bar * (1 + c * (l1 + l2 - 2))


def membrane_electric(l1, l2, I4, *, eps):
    """The electric part of the membrane free energy (3.20): ``-eps/2 l1^2 l2^2 I4``,
    ``I4 = E_L^2`` (``eps`` the permittivity at ``(l1, l2)``)."""
    return -0.5 * eps * (l1 * l2) ** 2 * I4


# ----------------------------------------------------------------- material energies
def gent_ideal_dielectric(I1, DCD, *, mu, Jm, eps, xp):
    """Incompressible Gent (3.23) + ideal dielectric ``I5/(2 eps)`` (the D_L form of
    (3.20) with constant permittivity, (5.9) at J = 1)."""
    return gent(I1, mu=mu, Jm=Jm, xp=xp) + ideal_dielectric(DCD, 1.0, eps=eps)


def neo_hookean_ideal_dielectric(I1, J, DCD, *, mu, k, eps):
    """(5.15) + (5.9): ``mu/2 (J^{-2/3} I1 - 3) + k/2 (J - 1)^2 + I5/(2 eps J)``."""
    return neo_hookean(I1, J, mu=mu, k=k) + ideal_dielectric(DCD, J, eps=eps)


def ogden(cbar, J, *, alphas, mus, k):
    """The mechanical Ogden energy of Ch. 5: (5.26) + ``k/2 (J - 1)^2``."""
    return ogden_isochoric(cbar, alphas=alphas, mus=mus) + volumetric(J, k=k)


def ti_neo_hookean_dielectric(I1, ACA, DD, DCD, *, mu, xi, alpha, beta, eps):
    """Transversely isotropic neo-Hookean dielectric (4.22): ``mu/2 (I1 - 3) +
    mu xi/2 (A.CA - 1)^2 + (alpha D_L.D_L + beta D_L.C D_L)/(2 eps)`` (the electric part
    is (4.20))."""
    return (ti_neo_hookean_elastic(I1, ACA, mu=mu, xi=xi)
            + dorfmann_ogden_electric(DD, DCD, alpha=alpha, beta=beta, eps=eps))

