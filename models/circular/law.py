"""The membrane law of the Chapter 3 ODE model: how the material enters circle A and annulus B.

With ``l3 = 1/(l1 l2)`` the membrane equations of state (3.14)-(3.15), (3.21)-(3.22) give
the true in-plane stresses per unit shear modulus (``sigma3 = 0`` on the faces, no field in
the annulus) from the stretching energy ``Ws(l1, l2)``::

    s1 = l1 dWs/dl1 / mu,   s2 = l2 dWs/dl2 / mu

The annulus ODE (3.34)-(3.35) also needs ``ds1/dl1`` and ``ds1/dl2``; circle A (3.30) needs
the equibiaxial ``s(lam) = s1(lam, lam)``. A law provides them for arrays of stretches, real
or complex (the complex-step sensitivities of the shooting method go through it):

* :class:`GentLaw`: the thesis' Gent closed forms (3.36)-(3.37) with ``kappa = 1/Jm``
  (:func:`gent_stresses`, :func:`~debench.models.circular.circle_a.gent_equibiaxial_stress`;
  the locking stretch :func:`locking_stretch_equibiaxial`); the integrator runs its fused
  kernels for it;
* :class:`ElastomerLaw`: any library elastomer, from its one energy expression by
  second-order forward differentiation
  (:meth:`~debench.models.materials.membrane.ElastomerMembrane.stretching_energy_jet`), no
  derivative written by hand; the integrator runs the plain RK4 loop over it.

``GentLaw(1/Jm)`` and ``ElastomerLaw(GentIdealDielectric(mu=1, Jm=Jm, eps=1))`` are the
same model; the tests compare them (the closed forms against the library expression).
"""

from __future__ import annotations

import functools
import math
import numbers
from dataclasses import dataclass

import numpy as np
from debench.models import validation as v
from debench.models.materials import energies as E
from debench.models.materials.membrane import ElastomerMembrane
from debench.models.materials.protocol import Material

#: above this Jm the cubic of the locking condition would overflow in double precision
_JM_HUGE = 1e100


def _check_Jm(Jm) -> float:
    """Jm > 0; ``math.inf`` (neo-Hookean) allowed."""
    if isinstance(Jm, bool) or not isinstance(Jm, numbers.Real):
        raise TypeError(f"Jm must be a real number, got {Jm!r}")
    if math.isinf(Jm) and Jm > 0:
        return math.inf
    return v.positive("Jm", Jm)


def locking_stretch_equibiaxial(Jm: float) -> float:
    """Equibiaxial stretch at which the Gent energy (3.23) locks: 2 l^2 + l^-4 - 3 = Jm.

    ``Jm > 0`` (``math.inf``: neo-Hookean, no lock).
    """
    Jm = _check_Jm(Jm)
    if math.isinf(Jm):
        return math.inf
    # x = l^2: 2 x^3 - (Jm + 3) x^2 + 1 = 0, largest root
    lo, hi = 1.0, math.sqrt((Jm + 3) / 2) + 1.0
    f = lambda x: 2 * x**3 - (Jm + 3) * x**2 + 1  # noqa: E731
    if Jm > _JM_HUGE:  # same sign, divided by x^2 > 0, so that x^3 cannot overflow
        f = lambda x: 2 * x - (Jm + 3) + 1 / x / x  # noqa: E731
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if f(mid * mid) > 0:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


def gent_stresses(l1, l2, kappa):
    """sigma1, sigma2, d sigma1/d l1, d sigma1/d l2 (3.36)-(3.37) per mu, and 1 - (I1-3)/Jm:
    the Gent closed forms, ``kappa = 1/Jm`` (no checks; the kernel of the integrator)."""
    l1s = l1 * l1
    l2s = l2 * l2
    J = 1.0 / (l1s * l2s)                    # lambda_3^2
    den = E.gent_lock_margin(l1s + l2s + J, kappa=kappa)
    g = 1.0 / den
    a1 = l1s - J
    s1 = g * a1
    s2 = g * (l2s - J)
    Jl1 = J / l1
    Jl2 = J / l2
    if kappa:
        ga = kappa * g * s1                  # a1 kappa g^2
        s1_1 = 2 * (g * (l1 + Jl1) + ga * (l1 - Jl1))
        s1_2 = 2 * (g * Jl2 + ga * (l2 - Jl2))
    else:
        s1_1 = 2 * (l1 + Jl1)
        s1_2 = 2 * Jl2
    return s1, s2, s1_1, s1_2, den


def _equibiaxial_margin(lam, kappa):
    """The library's Gent lock margin
    (:func:`~debench.models.materials.energies.gent_lock_margin`) at the equibiaxial
    ``I1 = 2 lam^2 + lam^-4``."""
    return E.gent_lock_margin(2 * lam**2 + lam**-4, kappa=kappa)


def _equibiaxial_stress(lam, kappa):
    """``s(lam) = (lam^2 - lam^-4)/(1 - (2 lam^2 + lam^-4 - 3)/Jm)`` (3.30)."""
    return (lam**2 - lam**-4) / _equibiaxial_margin(lam, kappa)


@dataclass(frozen=True)
class GentLaw:
    """The Gent membrane (3.23) in its closed forms (3.36)-(3.37), ``kappa = 1/Jm >= 0``
    (0: neo-Hookean). Built by :meth:`of_Jm` or :meth:`of_kappa`, which keep the
    parameter given exactly (``1/(1/Jm)`` may differ from ``Jm`` in the last bit)."""

    kappa: float
    Jm: float
    #: the integrator's fused closed-form kernels apply
    fused = True

    def __post_init__(self):
        v.nonnegative("kappa", self.kappa)
        if not (self.Jm == math.inf or v.positive("Jm", self.Jm)):
            raise ValueError(f"Jm must be > 0, got {self.Jm}")

    @classmethod
    def of_Jm(cls, Jm: float) -> GentLaw:
        """The law of ``Jm > 0`` (``math.inf``: neo-Hookean)."""
        Jm = _check_Jm(Jm)
        return cls(0.0 if math.isinf(Jm) else 1.0 / Jm, Jm)

    @classmethod
    def of_kappa(cls, kappa: float) -> GentLaw:
        """The law of ``kappa = 1/Jm >= 0`` (0: neo-Hookean)."""
        return cls(kappa, math.inf if kappa == 0 else 1 / kappa)

    def stresses(self, l1, l2):
        """``(s1, s2, ds1/dl1, ds1/dl2, margin)`` per mu; ``margin = 1 - (I1 - 3)/Jm``
        (> 0 short of the lock)."""
        return gent_stresses(l1, l2, self.kappa)

    def equibiaxial_stress(self, lam):
        """``s(lam) = (lam^2 - lam^-4)/(1 - (2 lam^2 + lam^-4 - 3)/Jm)`` (3.30)."""
        return _equibiaxial_stress(lam, self.kappa)

    def locking_stretch(self) -> float:
        """The equibiaxial locking stretch, ``2 lam^2 + lam^-4 - 3 = Jm``."""
        return locking_stretch_equibiaxial(self.Jm)


@dataclass(frozen=True)
class ElastomerLaw:
    """The membrane of any library elastomer: ``Ws(l1, l2) = W_mech(diag(l1, l2,
    1/(l1 l2)))`` per unit its shear modulus
    (:class:`~debench.models.materials.membrane.ElastomerMembrane`), its stresses and their
    derivatives from the energy expression."""

    elastomer: Material
    fused = False

    def __post_init__(self):
        # ElastomerMembrane refuses what is not a library material (TypeError)
        v.positive("elastomer.shear_modulus", self.membrane.shear_modulus)

    @functools.cached_property
    def membrane(self) -> ElastomerMembrane:
        return ElastomerMembrane(self.elastomer)

    def stresses(self, l1, l2):
        """``(s1, s2, ds1/dl1, ds1/dl2, margin)`` per mu; ``margin`` 1 where the energy
        is defined, NaN where not (past a lock)."""
        W = self.membrane._stretching_energy_jet(l1, l2)
        s1 = l1 * W.d1
        margin = np.where(np.isfinite(np.real(W.v)), 1.0, np.nan)
        return s1, l2 * W.d2, W.d1 + l1 * W.d11, l1 * W.d12, margin

    def equibiaxial_stress(self, lam):
        """``s(lam) = s1(lam, lam)`` (NaN past a lock)."""
        W = self.membrane._stretching_energy_jet(lam, lam)
        return (lam * W.d1)[()]

    def locking_stretch(self) -> float:
        """The equibiaxial stretch at which ``diag(lam, lam, lam^-2)`` leaves the
        elastomer's admissible set (bisection to rounding; inf when it stays admissible
        up to :data:`LOCK_SEARCH`)."""
        return _locking_stretch(self.elastomer)


#: the largest equibiaxial stretch searched for the end of a material's admissible set
LOCK_SEARCH = 1e4


@functools.lru_cache(maxsize=64)
def _locking_stretch(elastomer) -> float:
    def admissible(lam):
        try:
            elastomer.check_admissible(np.diag([lam, lam, lam**-2]))
        except ValueError:
            return False
        return True

    if admissible(LOCK_SEARCH):
        return math.inf
    lo, hi = 1.0, LOCK_SEARCH
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        lo, hi = (mid, hi) if admissible(mid) else (lo, mid)
    return lo
