"""Parameters of the Chapter 5 buckling-membrane model (thesis Table 5.1, §5.2.3).

Frozen dataclasses, SI units, validated on construction. The materials are those of the
constitutive library (:mod:`debench.models.materials`), re-exported under their Chapter 5
names; their defaults are Table 5.1 (:mod:`debench.models.materials.constants`):

* ``NeoHookean`` = :class:`~debench.models.materials.NeoHookeanIdealDielectric`:
  mu = 156000 Pa, k = 7748003.92 Pa, energy (5.15)-(5.17) + ideal dielectric (5.9).
* ``Ogden`` = :class:`~debench.models.materials.OgdenIdealDielectric`:
  alpha = (1.293, 2.3252, 2.561), mu_p = (8580, 84300, -23300) Pa, energy (5.26) read as
  ``sum 2 mu_p / alpha_p**2 (lam1b**a + lam2b**a + lam3b**a - 3)`` (consistent with the
  Kirchhoff stress (5.27)); initial shear modulus ``shear_modulus = sum(mu_p)`` = 69580 Pa;
  bulk modulus of the neo-Hookean row (assumption ``ch5.assumption.ogden_bulk_modulus``).
* ``Plate``: radius/thickness = 10, t0 = 1 mm or 0.5 mm, imperfection amplitude
  1e-3 t0 (§5.2.3; axisymmetric), an optional non-axisymmetric imperfection of angular
  wavenumber n (not in the thesis: zero by default), relative permittivity 4.7
  (assumption: not stated in Ch. 5; it only converts normalised voltages to volts, the
  finite-element problem does not depend on it).
* ``Discretisation``: mesh size, layers, polynomial order and the numerical parameter of
  the Ogden spectral evaluation (``ogden_delta``, see
  :mod:`debench.models.materials.ngsolve_forms`).

The permittivity of the library materials (``eps``) does not enter the normalised
finite-element problem either (normalised voltage ``v = Phi/t0 sqrt(eps/mu_ref)``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from debench.models import validation as val
from debench.models.materials.constants import (
    EPS_R_ASSUMED,
    OGDEN_DELTA,
    TABLE_5_1_BULK_MODULUS,
    TABLE_5_1_NH_SHEAR_MODULUS,
    VACUUM_PERMITTIVITY,
)
from debench.models.materials.library import NeoHookeanIdealDielectric as NeoHookean
from debench.models.materials.library import OgdenIdealDielectric as Ogden

MU_REF = TABLE_5_1_NH_SHEAR_MODULUS
"""Pa, the normalising modulus: Table 5.1 shear modulus (assumption
``ch5.assumption.normalisation``)."""
K_TABLE = TABLE_5_1_BULK_MODULUS
"""Pa, Table 5.1 bulk modulus."""

__all__ = ["COARSE", "Discretisation", "K_TABLE", "MU_REF", "NeoHookean", "Ogden", "Plate"]

# Plate: an aspect below 2 is no plate; the imperfection lifts the reference geometry by
# w0 = imperfection t0 (1 - r^2/a^2)^2, which the prism mesh (vertical lines) represents
# without inverted elements for amplitudes well below the thickness; 0.1 t0 is 100x the
# thesis value 1e-3 t0 and still leaves the centre points locatable on coarse meshes.
MAX_IMPERFECTION = 0.1
# The non-axisymmetric imperfection cos(n theta) needs about four elements per wavelength
# around the rim to be represented at all; 32 is beyond every mesh the studies use.
MAX_WAVENUMBER = 32
# Discretisation: h_rel = 0.25 t0 with one layer of quadratic prisms is ~300k DOFs (the
# largest problem a sparse direct solve handles in minutes on one core); below that the
# mesher and the factorisation run for hours.
MIN_H_REL = 0.25
MAX_LAYERS = 16
MAX_ORDER = 4


@dataclass(frozen=True)
class Plate:
    """Clamped circular membrane, §5.2.3: radius = aspect * thickness.

    The reference geometry is lifted by the imperfection (:func:`imperfection_lift`)

        w0(r, theta) = imperfection t0 (1 - s^2)^2
                       + wrinkle_imperfection t0 s^n (1 - s^2)^2 cos(n theta) / c_n,

    s = r / radius, n = ``wrinkle_wavenumber``, c_n = max_s s^n (1 - s^2)^2 (so that
    ``wrinkle_imperfection`` t0 is the peak of the second term). The first term is the
    thesis' (§5.2.3, the clamped-plate polynomial close to the first buckling mode); the
    second seeds a non-axisymmetric mode of wavenumber n (not in the thesis; zero by default)
    for imperfection-sensitivity studies of a wrinkling bifurcation.
    """

    thickness: float = 1e-3
    aspect: float = 10.0
    imperfection: float = 1e-3
    eps_r: float = EPS_R_ASSUMED
    wrinkle_imperfection: float = 0.0
    wrinkle_wavenumber: int = 1

    def __post_init__(self):
        val.positive("thickness", self.thickness)
        val.in_range("aspect", self.aspect, 2.0, 1e3)
        val.in_range("imperfection", self.imperfection, 0.0, MAX_IMPERFECTION,
                     bound=f"above {MAX_IMPERFECTION} t0: the lifted prism mesh no longer "
                           "represents the plate (fraction of t0)")
        val.in_range("eps_r", self.eps_r, 1.0, 1e4)
        val.in_range("wrinkle_imperfection", self.wrinkle_imperfection, 0.0,
                     MAX_IMPERFECTION - self.imperfection,
                     bound=f"the two imperfections together above {MAX_IMPERFECTION} t0: "
                           "the lifted prism mesh no longer represents the plate")
        val.integer_at_least("wrinkle_wavenumber", self.wrinkle_wavenumber, 1)
        if self.wrinkle_wavenumber > MAX_WAVENUMBER:
            raise ValueError(f"wrinkle_wavenumber = {self.wrinkle_wavenumber} must be <= "
                             f"{MAX_WAVENUMBER}")

    def imperfection_lift(self, x, y):
        """Vertical lift w0(x, y) of the reference geometry (m; class docstring), for
        points of the disk (arrays broadcast)."""
        x, y = np.asarray(x, float), np.asarray(y, float)
        a, t0, n = self.radius, self.thickness, self.wrinkle_wavenumber
        s2 = (x * x + y * y) / a**2
        bubble = np.clip(1.0 - s2, 0.0, None) ** 2
        out = self.imperfection * t0 * bubble
        if self.wrinkle_imperfection:
            c_n = (n / (n + 4.0)) ** (n / 2) * (4.0 / (n + 4.0)) ** 2
            ring = ((x + 1j * y) / a) ** n           # s^n exp(i n theta)
            out = out + self.wrinkle_imperfection * t0 * bubble * ring.real / c_n
        return out

    @property
    def radius(self) -> float:
        return self.aspect * self.thickness

    @property
    def eps(self) -> float:
        return self.eps_r * VACUUM_PERMITTIVITY

    def volts(self, v: float, mu_ref: float = MU_REF) -> float:
        """Voltage of the normalised voltage ``v = Phi/t0 sqrt(eps/mu_ref)``."""
        v = val.finite("v", v)
        mu_ref = val.positive("mu_ref", mu_ref)
        return v * self.thickness * math.sqrt(mu_ref / self.eps)

    def field_V_per_um(self, e_hat: float, mu_ref: float = MU_REF) -> float:
        """True field in V/um of the normalised field ``e = E sqrt(eps/mu_ref)``."""
        e_hat = val.finite("e_hat", e_hat)
        mu_ref = val.positive("mu_ref", mu_ref)
        return e_hat * math.sqrt(mu_ref / self.eps) * 1e-6


@dataclass(frozen=True)
class Discretisation:
    """Extruded prism mesh: in-plane size ``h_rel * t0``, ``layers`` through thickness,
    polynomial ``order`` for displacement and potential; ``ogden_delta`` is the half-width
    of the averaged spectral perturbation of the Ogden energy (error O(delta^2))."""

    h_rel: float = 1.5
    layers: int = 2
    order: int = 2
    ogden_delta: float = OGDEN_DELTA

    def __post_init__(self):
        val.in_range("h_rel", self.h_rel, MIN_H_REL, 100.0)
        val.integer_at_least("layers", self.layers, 1)
        if self.layers > MAX_LAYERS:
            raise ValueError(f"layers = {self.layers} must be <= {MAX_LAYERS}")
        val.integer_at_least("order", self.order, 1)
        if self.order > MAX_ORDER:
            raise ValueError(f"order = {self.order} must be <= {MAX_ORDER}")
        val.in_range("ogden_delta", self.ogden_delta, 0.0, 0.1, lo_open=True, hi_open=True)


COARSE = Discretisation(h_rel=3.0, layers=1, order=2)
"""The coarsest mesh of the studies: in-plane size 3 t0, one layer of quadratic prisms
(1,644 DOFs); what ``debench verify`` recomputes."""
