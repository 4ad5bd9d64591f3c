"""The membrane law of the Chapter 3 ODE model: how the material enters circle A and annulus B.

With ``l3 = 1/(l1 l2)`` the membrane equations of state (3.14)-(3.15), (3.21)-(3.22) give
the true in-plane stresses per unit shear modulus (``sigma3 = 0`` on the faces, no field in
the annulus) from the stretching energy ``Ws(l1, l2)``::

    s1 = l1 dWs/dl1 / mu,   s2 = l2 dWs/dl2 / mu

The annulus ODE (3.34)-(3.35) also needs ``ds1/dl1`` and ``ds1/dl2``; circle A (3.30) needs
the equibiaxial ``s(lam) = s1(lam, lam)``. A law provides them for arrays of stretches, real
or complex (the complex-step sensitivities of the shooting method go through it):

* :class:`GentLaw`: the thesis' Gent closed forms (3.36)-(3.37) with ``kappa = 1/Jm``
  (:func:`~debench.models.circular.integrator.stresses`,
  :func:`~debench.models.circular.circle_a.gent_equibiaxial_stress`); the integrator runs
  its fused kernels for it;
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
from dataclasses import dataclass

import numpy as np
from debench.models import validation as v
from debench.models.materials.membrane import ElastomerMembrane
from debench.models.materials.protocol import Material

from . import circle_a
from .integrator import stresses
from .params import _check_Jm, locking_stretch_equibiaxial


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
        return stresses(l1, l2, self.kappa)

    def equibiaxial_stress(self, lam):
        """``s(lam) = (lam^2 - lam^-4)/(1 - (2 lam^2 + lam^-4 - 3)/Jm)`` (3.30)."""
        return circle_a._s(lam, self.kappa)

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
        if not all(callable(getattr(self.elastomer, name, None))
                   for name in ("mechanical_energy", "response", "check_admissible")):
            raise TypeError(f"elastomer must be a library material, got "
                            f"{type(self.elastomer).__name__} {self.elastomer!r:.40}")
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


def membrane_law(Jm=None, elastomer=None, *, lamP: float = 1.0):
    """The law of the Jm or the elastomer given (``Jm`` None and no elastomer:
    ``params.JM_VHB``): :class:`GentLaw` of ``1/Jm`` (``Jm > 0``, ``math.inf``
    neo-Hookean) or :class:`ElastomerLaw`. The elastomer is checked by
    :func:`~debench.models.circular.params.film_elastomer` (ValueError when both are
    given or the film pre-stretched by ``lamP`` is not admissible, TypeError when it is
    not a library material)."""
    from .params import JM_VHB, film_elastomer
    if elastomer is None:
        return GentLaw.of_Jm(JM_VHB if Jm is None else Jm)
    return ElastomerLaw(film_elastomer(lamP, Jm, elastomer))
