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

The material law is Gent (3.23) with ``kappa = 1/Jm`` in the closed form above, or any
library elastomer (``elastomer=``, give ``kappa`` or ``elastomer``): ``s(lam)`` is then
``lam dWs/dl1`` at ``l1 = l2 = lam`` per unit its shear modulus, from its energy
expression (:class:`~debench.models.circular.law.ElastomerLaw`); K and the interface
balance do not depend on the material.

Every function is complex-safe (used with complex-step sensitivities). Public functions
validate their arguments (ValueError naming the bound: lam <= 0, past the locking
stretch, K <= 0; :func:`phibar_squared_where_defined` marks K <= 0 NaN instead); the models
call the private kernels ``_s`` (Gent), ``_K``, ``_p2`` (any law).
"""

from __future__ import annotations

import numpy as np
from debench.models import validation as v

from .law import ElastomerLaw, GentLaw, locking_stretch_equibiaxial
from .law import _equibiaxial_margin as _margin
from .law import _equibiaxial_stress as _s
from .params import EB_COEFF, EB_EXPONENT, EPS0, film_elastomer


def _K(lam, c):
    return 1 + c * (2.5 * lam - 2)


def _p2(lam, T1B, c, law):
    """Phibar^2 of (3.30)-(3.32) with the equibiaxial stress of the membrane ``law``
    (:mod:`debench.models.circular.law`)."""
    return (law.equibiaxial_stress(lam) - lam * T1B) / (lam**4 * _K(lam, c))


def _law(kappa, elastomer):
    """The membrane law of ``kappa = 1/Jm >= 0`` (Gent) or of the library ``elastomer``
    (ValueError when both or neither is given, TypeError for a non-material)."""
    if elastomer is None:
        if kappa is None:
            raise ValueError("give kappa (= 1/Jm of the Gent elastomer) or elastomer")
        return GentLaw.of_kappa(v.nonnegative("kappa", kappa))
    if kappa is not None:
        raise ValueError("give kappa (= 1/Jm of the Gent elastomer) or elastomer, not both")
    return ElastomerLaw(film_elastomer(1.0, None, elastomer))


def _check_lam(lam, law=None):
    """lam finite and > 0 (complex allowed); below the locking stretch of ``law``."""
    lam = np.asarray(v.positive("lam", lam, complex_ok=True))
    if law is not None:
        lr = np.real(lam)
        if getattr(law, "fused", False):
            kappa = law.kappa
            if not np.all(_margin(lr, kappa) > 0):
                lock = locking_stretch_equibiaxial(1 / kappa)
                raise ValueError(f"lam = {v._show(lr)} is past the Gent locking stretch "
                                 f"{lock:.6g} (Jm = {1 / kappa:.6g})")
        elif not np.all(lr < law.locking_stretch()):
            raise ValueError(f"lam = {v._show(lr)} is past the locking stretch "
                             f"{law.locking_stretch():.6g} of {law.elastomer!r:.60}")
    return lam


def _check_K(lam, c):
    K = _K(np.real(lam), c)
    if not np.all(K > 0):
        raise ValueError(f"c = {c} makes the permittivity factor K = 1 + c(5 lam/2 - 2) of "
                         f"(3.30) non-positive at lam = {v._show(np.real(lam))}: need K > 0")


@v.finite_result
def gent_equibiaxial_stress(lam, kappa: float):
    """Mechanical part of (3.30), ``s(lam)`` per unit mu; kappa = 1/Jm.

    ``lam`` finite, > 0 and below the Gent locking stretch; ``kappa >= 0``.
    """
    law = _law(kappa, None)
    return _s(_check_lam(lam, law), law.kappa)


@v.finite_result
def electrostriction_factor(lam, c: float):
    """``K(lam) = 1 + c (5 lam/2 - 2)``, the coefficient of -eps_bar E^2 in (3.30)."""
    return _K(_check_lam(lam), v.finite("c", c))


@v.finite_result
def permittivity_ratio(lam, c: float):
    """``eps/eps_bar = 1 + c (2 lam - 2)`` (3.27) at l1 = l2 = lam."""
    return 1 + v.finite("c", c) * (2 * _check_lam(lam) - 2)


@v.finite_result
def phibar_squared(lam, T1B, c: float, kappa: float | None = None, *, elastomer=None):
    """Normalised voltage squared that holds circle A at ``lam`` against ``T1B``, (3.30)
    with (3.32).

    Parameters
    ----------
    lam
        Stretch of circle A (= hoop stretch of B at R_A, Eq. 3.31); finite, > 0, below
        the Gent locking stretch.
    T1B
        Nominal radial stress of annulus B at R_A per unit mu (3.17, 3.32); 0 for a free
        membrane.
    c, kappa
        Zhao-Suo factor (3.27) (the factor K of (3.30) must stay > 0) and 1/Jm >= 0 of
        the Gent law (3.23).
    elastomer
        Any library material instead of Gent (give ``kappa`` or ``elastomer``); Phibar is
        normalised by its shear modulus.

    A negative value means no real voltage holds circle A at ``lam``.
    """
    law = _law(kappa, elastomer)
    lam = _check_lam(lam, law)
    v.finite("T1B", T1B, complex_ok=True)
    _check_K(lam, v.finite("c", c))
    return _p2(lam, T1B, c, law)


def phibar_squared_where_defined(lam, T1B, c: float, kappa: float | None = None, *,
                                 elastomer=None):
    """:func:`phibar_squared` where the factor K = 1 + c(5 lam/2 - 2) of (3.30) is
    positive, NaN where K <= 0.

    Where K <= 0 no voltage holds circle A: Phibar is undefined there (a voltage-stretch
    curve ends at its ``permittivity`` event and its ``phibar`` is NaN beyond it). This
    function marks those stretches NaN instead of refusing them, so that Phibar^2 can be
    evaluated along a whole traced branch. The arguments are those of
    :func:`phibar_squared` and checked as there (``lam`` finite, > 0 and below the Gent
    locking stretch, ``T1B`` and ``c`` finite, ``kappa >= 0``), except that K may be
    <= 0; every value where K > 0 is finite (ValueError otherwise). ``elastomer``: any
    library material instead of Gent, as in :func:`phibar_squared`.
    """
    law = _law(kappa, elastomer)
    lam = _check_lam(lam, law)
    v.finite("T1B", T1B, complex_ok=True)
    v.finite("c", c)
    defined = _K(np.real(lam), c) > 0
    with np.errstate(all="ignore"):  # K <= 0: replaced by NaN below
        p2 = np.where(defined, _p2(lam, T1B, c, law), np.nan)
    if not np.all(np.isfinite(p2[defined])):
        raise ValueError("phibar_squared_where_defined: the result overflows (NaN or inf) "
                         "at these arguments; they are outside the representable range")
    return p2


@v.finite_result
def sigma1_circle_a(lam, phibar, c: float, kappa: float | None = None, *, elastomer=None):
    """True radial stress of circle A per unit mu, Eq. (3.30) with E^2 = (Phi/H)^2 lam^4:
    Gent (3.23) with ``kappa = 1/Jm``, or any library ``elastomer`` (give one; mu is then
    its shear modulus)."""
    law = _law(kappa, elastomer)
    lam = _check_lam(lam, law)
    phibar = v.finite("phibar", phibar)
    v.finite("c", c)
    return law.equibiaxial_stress(lam) - np.asarray(phibar) ** 2 * lam**4 * _K(lam, c)


@v.finite_result
def breakdown_phibar(lam, eps_r: float, mu: float):
    """Normalised voltage at breakdown, ``sqrt(eps_bar/mu) E_B(lam) / lam^2`` (Sec. 3.5.5).

    E_B = 51 lam^1.13 MV/m (Huang et al.), eps_bar = eps_r eps0 (3.27).
    """
    lam = _check_lam(lam)
    v.positive("eps_r", eps_r)
    v.positive("mu", mu)
    return _breakdown(lam, eps_r, mu)


def _breakdown(lam, eps_r, mu):
    return np.sqrt(np.asarray(eps_r) * EPS0 / mu) * EB_COEFF * lam**EB_EXPONENT / lam**2


@v.finite_result
def free_membrane_phibar(lam, c: float, kappa: float | None = None, *, elastomer=None):
    """Free equibiaxial membrane (annulus removed, T1B = 0): Phibar(lam), lam >= 1, (3.30)
    with ``sigma1 = 0``: Gent (3.23) with ``kappa = 1/Jm``, or any library ``elastomer``.

    Neo-Hookean ideal dielectric: ``sqrt(lam^-2 - lam^-8)``, maximum at lam = 2^(1/3)
    (Zhao & Suo 2007).
    """
    v.at_least("lam", lam, 1.0)
    return np.sqrt(phibar_squared(lam, 0.0, c, kappa, elastomer=elastomer))


@v.finite_result
def voltage_weight(lam, c: float, kappa: float):
    """``w(lam) = lam^4 K(lam) (1 - kappa (2 lam^2 + lam^-4 - 3))`` with K of (3.30).

    By the interface balance, ``Phibar^2 w = (lam^2 - lam^-4) - lam T1B (1 - kappa (2 lam^2
    + lam^-4 - 3))``: smooth in lam up to the Gent locking stretch of circle A and through
    K = 0, where Phibar^2 itself has poles. Interpolating Phibar^2 w instead of Phibar
    keeps a spline accurate there. ``lam`` finite and > 0; ``c`` finite, ``kappa >= 0``.
    """
    lam = np.asarray(v.positive("lam", lam), dtype=float)
    c = v.finite("c", c)
    kappa = v.nonnegative("kappa", kappa)
    return lam**4 * _K(lam, c) * _margin(lam, kappa)
