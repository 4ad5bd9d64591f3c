"""Parameters of the Chapter 3 circular actuator and the thesis' material data.

Zeng (2020), Chapter 3: a membrane of reference radius R_B, pre-stretched equibiaxially by
``lamP`` and fixed to a rigid frame (3.38); circle A (R < R_A) carries electrodes, annulus
B (R_A < R < R_B) is passive. VHB 4910: Gent (3.23) with mu = 51 kPa, Jm = 120; Zhao-Suo
permittivity (3.27) eps = eps_bar [1 + c (l1 + l2 - 2)]; breakdown field
E_B = 51 lam^1.13 MV/m (Huang et al., Sec. 3.5.5). Any library elastomer may replace Gent
(``Annulus(elastomer=...)``, :mod:`debench.models.circular.law`).
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np
from debench.models import validation as v
from debench.models.errors import require
from debench.models.materials import constants
from debench.models.materials.constants import (
    VACUUM_PERMITTIVITY,
    VHB_GENT_JM,
    VHB_SHEAR_MODULUS,
)
from debench.models.materials.library import GentIdealDielectric
from debench.models.materials.protocol import Material

from .law import ElastomerLaw, GentLaw, _check_Jm
from .law import locking_stretch_equibiaxial as locking_stretch_equibiaxial  # its old home

MU_VHB = VHB_SHEAR_MODULUS  # Pa, shear modulus, Sec. 3.3.3
JM_VHB = VHB_GENT_JM        # Gent locking parameter, Sec. 3.3.3
EPS0 = VACUUM_PERMITTIVITY  # F/m, vacuum permittivity as printed below (3.27)
EB_COEFF = 51e6          # V/m, E_B = 51 lam^1.13 MV/m (Huang et al. [63], Sec. 3.5.5)
EB_EXPONENT = 1.13
EPS_R_ASSUMED = constants.EPS_R_ASSUMED  # NOT stated in the thesis: assumption ch3.assumption.eps_r
#: Table 3.1: (experimental-data reference number, c)
TABLE_3_1 = constants.TABLE_3_1
C_WISSLER_MAZZA = dict(TABLE_3_1)[56]  # c = -0.053, Sec. 3.5, Wissler & Mazza [56]

EQUILIBRIUM_VARIANTS = ("printed", "membrane")


@dataclass(frozen=True)
class Annulus:
    """The passive annulus B: what the annulus boundary-value problem depends on.

    Parameters
    ----------
    lamP
        Equibiaxial pre-stretch, imposed as lambda_2(R_B) = lamP (3.38). Must be >= 1.
    radius_ratio
        R_B / R_A (thesis: 5, 10, 15; 15 in all figures). Must be > 1.
    Jm
        Gent parameter (3.23) of the thesis' material law (None: ``JM_VHB`` = 120, unless
        ``elastomer`` is given); ``math.inf`` gives neo-Hookean. Must be > 0. The model
        then uses the Gent closed forms (3.36)-(3.37) in fused kernels.
    equilibrium
        ``"printed"``: Eq. (3.33) d sigma1/dr = (sigma2 - sigma1)/r, hence ODE (3.34), as
        the thesis solves it. ``"membrane"``: thin-membrane force balance
        d(R T1)/dR = T2 (T_i = sigma_i/lambda_i), which adds the thickness-gradient term
        -sigma1 (r/h) dh/dr that (3.33) omits (erratum ch3.erratum.eq_3_33).
    elastomer
        Any library material instead of Gent (give ``Jm`` or ``elastomer``, not both): the
        membrane stretching energy is its strain energy on ``J = 1`` divided by its shear
        modulus (:class:`~debench.models.circular.law.ElastomerLaw`), the pre-stretched
        film must be an admissible state of it. ``Jm`` is then None.

    The material enters through :attr:`law` (:mod:`debench.models.circular.law`).
    """

    lamP: float
    radius_ratio: float = 15.0
    Jm: float | None = None
    equilibrium: str = "printed"
    elastomer: Material | None = None

    def __post_init__(self):
        if self.elastomer is None and self.Jm is None:
            object.__setattr__(self, "Jm", JM_VHB)
        for name in ("lamP", "radius_ratio") + (("Jm",) if self.Jm is not None else ()):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, numbers.Real):
                raise TypeError(f"{name} must be a real number, got {value!r}")
            require(not math.isnan(value), f"{name} must be a real number, got {value!r}")
        v.at_least("lamP", self.lamP, 1.0)
        require(self.radius_ratio > 1.0,
                f"radius_ratio RB/RA must be > 1, got {self.radius_ratio}")
        require(math.isfinite(self.radius_ratio),
                f"radius_ratio RB/RA must be finite, got {self.radius_ratio}")
        if self.elastomer is None:
            _check_Jm(self.Jm)
        v.choice("equilibrium", self.equilibrium, EQUILIBRIUM_VARIANTS)
        law = membrane_law(self.Jm, self.elastomer, lamP=self.lamP)
        object.__setattr__(self, "_law", law)
        if self.elastomer is None:
            lock = law.locking_stretch()
            if not self.lamP < lock:
                raise ValueError(f"lamP = {self.lamP:.6g} is past the Gent locking stretch "
                                 f"{lock:.6g} (Jm = {self.Jm:.6g})")

    def __repr__(self) -> str:
        extra = "" if self.elastomer is None else f", elastomer={self.elastomer!r}"
        return (f"Annulus(lamP={self.lamP!r}, radius_ratio={self.radius_ratio!r}, "
                f"Jm={self.Jm!r}, equilibrium={self.equilibrium!r}{extra})")

    @property
    def law(self):
        """The membrane law of the annulus and circle A:
        :class:`~debench.models.circular.law.GentLaw` of ``1/Jm`` or
        :class:`~debench.models.circular.law.ElastomerLaw` of the elastomer."""
        return self._law

    @property
    def kappa(self) -> float:
        """1/Jm (0 for the neo-Hookean limit); ValueError for an annulus of another
        elastomer (its law is :attr:`law`)."""
        if self.elastomer is not None:
            raise ValueError(f"kappa = 1/Jm is the Gent annulus' parameter; this annulus "
                             f"has elastomer={self.elastomer!r:.60}")
        return 0.0 if math.isinf(self.Jm) else 1.0 / self.Jm


@dataclass(frozen=True)
class CircularActuator:
    """Full Chapter 3 actuator: the annulus plus circle A's electrical data.

    Parameters
    ----------
    annulus
        :class:`Annulus` (pre-stretch, geometry, material law: Gent of Jm or a library
        elastomer, equilibrium variant).
    c
        Zhao-Suo electrostrictive factor (3.27), thesis range -0.1 <= c <= 0.
    eps_r
        Relative permittivity (enters only the breakdown line; assumption, thesis silent).
    mu
        Shear modulus in Pa (enters only the breakdown line).
    """

    annulus: Annulus
    c: float = 0.0
    eps_r: float = EPS_R_ASSUMED
    mu: float = MU_VHB

    def __post_init__(self):
        v.instance("annulus", self.annulus, Annulus)
        for name in ("c", "eps_r", "mu"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, numbers.Real):
                raise TypeError(f"{name} must be a real number, got {value!r}")
        v.finite("c", self.c)
        v.positive("eps_r", self.eps_r)
        v.positive("mu", self.mu)
        # permittivity (3.27) and the factor K of (3.30) must be positive at the
        # pre-stretched state (where every curve starts); along a curve the stretch at
        # which K reaches 0 ends it (failure kind "permittivity", see actuator.curves)
        lamP = self.annulus.lamP
        require(1 + self.c * (2 * lamP - 2) > 0,
                f"c = {self.c} makes the permittivity (3.27) non-positive at "
                f"lamP = {lamP}: need 1 + c(2 lamP - 2) > 0")
        require(1 + self.c * (2.5 * lamP - 2) > 0,
                f"c = {self.c} makes the factor K = 1 + c(5 lam/2 - 2) of (3.30) "
                f"non-positive at lamP = {lamP}: need K(lamP) > 0")


def film_elastomer(lamP: float, Jm: float | None, elastomer: Material | None) -> Material:
    """The elastomer of a Chapter 3 finite-element model: ``elastomer``, or the Gent
    (3.23) of ``Jm`` (``JM_VHB`` when neither is given) in units mu = 1; ValueError when
    both are given, or when the film pre-stretched by ``lamP`` is not an admissible state
    of it (past a Gent lock) or ``lamP < 1``."""
    lamP = v.at_least("lamP", lamP, 1.0)
    if elastomer is None:
        elastomer = GentIdealDielectric(mu=1.0, Jm=v.positive(
            "Jm", JM_VHB if Jm is None else Jm), eps=1.0)
    elif Jm is not None:
        raise ValueError("give Jm (the Gent elastomer's) or elastomer, not both")
    elif not all(callable(getattr(elastomer, name, None))
                 for name in ("mechanical_energy", "response", "check_admissible")):
        raise TypeError(f"elastomer must be a library material, got "
                        f"{type(elastomer).__name__} {elastomer!r:.40}")
    try:
        elastomer.check_admissible(np.diag([lamP, lamP, lamP**-2]))
    except ValueError as e:
        raise ValueError(f"lamP = {lamP:.6g}: the pre-stretched film is not an admissible "
                         f"state of the elastomer ({e})") from e
    return elastomer


def membrane_law(Jm=None, elastomer=None, *, lamP: float = 1.0):
    """The membrane law of the Jm or the elastomer given (``Jm`` None and no elastomer:
    ``JM_VHB``): :class:`~debench.models.circular.law.GentLaw` of ``1/Jm`` (``Jm > 0``,
    ``math.inf`` neo-Hookean) or :class:`~debench.models.circular.law.ElastomerLaw`. The
    elastomer is checked by :func:`film_elastomer` (ValueError when both are given or the
    film pre-stretched by ``lamP`` is not admissible, TypeError when it is not a library
    material)."""
    if elastomer is None:
        return GentLaw.of_Jm(JM_VHB if Jm is None else Jm)
    return ElastomerLaw(film_elastomer(lamP, Jm, elastomer))
