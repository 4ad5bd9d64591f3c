"""Circle A: the homogeneous, equibiaxially stretched active region (Eqs. 3.28-3.32).

All stresses are per unit mu; voltages are the thesis' normalisation
``Phibar = sqrt(eps_bar/mu) Phi/H`` (Sec. 3.5). With ``l1 = l2 = lam``, ``l3 = lam^-2``,
the true field is ``E = Phi/(H l3) = (Phi/H) lam^2`` and Eq. (3.30) reads

    sigma1^(A)/mu = s(lam) - Phibar^2 lam^4 K(lam),
    s(lam) = (lam^2 - lam^-4) / (1 - (2 lam^2 + lam^-4 - 3)/Jm),
    K(lam) = 1 + c (5 lam/2 - 2).

K was re-derived from (3.20)-(3.21) with the Zhao-Suo permittivity (3.27):
``eps + (lam/2) d eps/d l1 = eps_bar [1 + c(2 lam - 2) + c lam/2]`` -- the printed
coefficient is the consistent one (``tools/derive_ch3.py``; entry ch3.erratum.eq_3_30).

Force balance at the interface (3.32) with T1 = sigma1/lambda1 (3.17) gives
``sigma1^(A) = lam T1^(B)(R_A)``, so that

    Phibar^2 = (s(lam) - lam T1B) / (lam^4 K(lam)).

Every function is complex-safe (used with complex-step sensitivities).
"""

from __future__ import annotations

import numpy as np

from .params import EB_COEFF, EB_EXPONENT, EPS0


def gent_equibiaxial_stress(lam, kappa: float):
    """Mechanical part of (3.30), ``s(lam)`` per unit mu; kappa = 1/Jm."""
    lam = np.asarray(lam)
    return (lam**2 - lam**-4) / (1 - kappa * (2 * lam**2 + lam**-4 - 3))


def electrostriction_factor(lam, c: float):
    """``K(lam) = 1 + c (5 lam/2 - 2)``, the coefficient of -eps_bar E^2 in (3.30)."""
    return 1 + c * (2.5 * np.asarray(lam) - 2)


def permittivity_ratio(lam, c: float):
    """``eps/eps_bar = 1 + c (2 lam - 2)`` (3.27) at l1 = l2 = lam."""
    return 1 + c * (2 * np.asarray(lam) - 2)


def phibar_squared(lam, T1B, c: float, kappa: float):
    """Normalised voltage squared that holds circle A at ``lam`` against ``T1B``.

    Parameters
    ----------
    lam
        Stretch of circle A (= hoop stretch of B at R_A, Eq. 3.31).
    T1B
        Nominal radial stress of annulus B at R_A per unit mu (3.17, 3.32); 0 for a free
        membrane.
    """
    lam = np.asarray(lam)
    return (gent_equibiaxial_stress(lam, kappa) - lam * T1B) / (
        lam**4 * electrostriction_factor(lam, c))


def sigma1_circle_a(lam, phibar, c: float, kappa: float):
    """True radial stress of circle A per unit mu, Eq. (3.30) with E^2 = (Phi/H)^2 lam^4."""
    lam = np.asarray(lam)
    return gent_equibiaxial_stress(lam, kappa) - np.asarray(phibar) ** 2 * lam**4 * (
        electrostriction_factor(lam, c))


def breakdown_phibar(lam, eps_r: float, mu: float):
    """Normalised voltage at breakdown, ``sqrt(eps_bar/mu) E_B(lam) / lam^2`` (Sec. 3.5.5).

    E_B = 51 lam^1.13 MV/m (Huang et al.), eps_bar = eps_r eps0 (3.27).
    """
    lam = np.asarray(lam)
    return np.sqrt(np.asarray(eps_r) * EPS0 / mu) * EB_COEFF * lam**EB_EXPONENT / lam**2


def free_membrane_phibar(lam, c: float, kappa: float):
    """Free equibiaxial membrane (annulus removed, T1B = 0): Phibar(lam).

    Neo-Hookean ideal dielectric: ``sqrt(lam^-2 - lam^-8)``, maximum at lam = 2^(1/3)
    (Zhao & Suo 2007).
    """
    return np.sqrt(phibar_squared(lam, 0.0, c, kappa))
