r"""The dielectric-elastomer balloon: a thin spherical ideal-dielectric membrane under
internal pressure and a voltage through its thickness (Zhu, Cai & Suo 2010), in closed
form.

Problem
-------
A spherical membrane of reference radius R and reference thickness H << R, an
incompressible neo-Hookean or Gent elastomer (shear modulus mu, locking parameter Jm)
with constant permittivity eps, carries compliant electrodes on both faces at a
potential difference Phi and an internal pressure p (no external pressure). The
deformation is a uniform inflation: radius r = lam R, equibiaxial in-plane stretch
lam, current thickness h = H lam^-2 (incompressibility). Thin-membrane assumptions:
the field is uniform through the thickness, E = Phi/h, fringing fields are neglected,
the stress is plane (zero through the thickness) and bending is absent.

Derivation (free energy of the sphere)
--------------------------------------
With the voltage Phi held by a battery and the pressure p held by a reservoir, the
potential energy of the system as a function of lam is

.. math::

    \Pi(\lambda) = 4\pi R^2 H\,W(\lambda) - \tfrac12 C(\lambda)\,\Phi^2
                   - p\,\tfrac43\pi R^3\lambda^3 ,
    \qquad C(\lambda) = \frac{\varepsilon\,4\pi r^2}{h}
                      = \frac{4\pi\varepsilon R^2\lambda^4}{H}      (1)

where W(lam) is the strain energy per reference volume at in-plane stretches (lam, lam)
and thickness stretch lam^-2,

.. math::

    W_{nH} = \frac{\mu}{2}\,(2\lambda^2 + \lambda^{-4} - 3), \qquad
    W_{G} = -\frac{\mu J_m}{2}\ln\Bigl(1 - \frac{2\lambda^2 + \lambda^{-4} - 3}{J_m}
            \Bigr),                                                 (2)

and -(1/2) C Phi^2 is the capacitor's energy (1/2) C Phi^2 minus the battery's work
C Phi^2 at fixed voltage. An equilibrium is a stationary point, dPi/dlam = 0:

.. math::

    4\pi R^2 H\Bigl[W'(\lambda) - 2\varepsilon\frac{\Phi^2}{H^2}\lambda^3\Bigr]
    = 4\pi R^3 p\,\lambda^2 .                                      (3)

Dividing by 4 pi R^3 mu lam^2 and writing vbar = (Phi/H) sqrt(eps/mu) (reference
thickness) gives the normalised pressure

.. math::

    \bar p \equiv \frac{pR}{\mu H}
           = \frac{W'(\lambda)}{\mu\lambda^2} - 2\bar v^2\lambda
           = s(\lambda) - 2\bar v^2\lambda, \qquad
    s(\lambda) = \frac{2(\lambda^{-1} - \lambda^{-7})}{G(\lambda)}, \qquad
    G(\lambda) = 1 - \frac{2\lambda^2 + \lambda^{-4} - 3}{J_m}       (4)

(G = 1 for neo-Hookean, J_m -> infinity). It is Laplace's law of the membrane,
p r/(2h) = sigma - eps E^2 with sigma = (lam/2) W'(lam) the mechanical true stress in
the plane and eps E^2 = eps Phi^2 lam^4/H^2 the Maxwell stress: multiply by 2h/r =
2H/(R lam^3). For the neo-Hookean balloon (4) is
pbar = 2(lam^-1 - lam^-7) - 2 vbar^2 lam (Zhu, Cai & Suo 2010).

Derived quantities
------------------
* pressure extrema at fixed voltage: the zeros of dpbar/dlam = s'(lam) - 2 vbar^2,

  .. math::

      s'(\lambda) = \frac{2(7\lambda^{-8} - \lambda^{-2})}{G}
                  + \frac{8(\lambda^{-1} - \lambda^{-7})(\lambda - \lambda^{-5})}{J_m G^2};
                                                                    (5)

  the first (in increasing lam >= 1) where it changes sign from + to - is the local
  maximum (the snap-through pressure under pressure control), the next, from - to +, the
  local minimum (Gent only: strain stiffening; none for neo-Hookean);
* voltage at fixed pressure: vbar^2(lam) = (s(lam) - pbar)/(2 lam) from (4); its
  extrema are the zeros of

  .. math::

      g(\lambda) = \lambda s'(\lambda) - s(\lambda) + \bar p           (6)

  (d vbar^2/dlam = g/(2 lam^2)); the first zero with vbar^2 > 0 where g changes sign
  from + to - is the voltage limit point (pull-in of the pressurised balloon).

Roots of (5) and (6) are bracketed by a sign scan in log lam on [1, lam_top] and refined
by Brent's method to :data:`XTOL` (:func:`debench.models.numerics.roots.bracketed_root`);
the values at a root are the closed forms (4) evaluated there.

References
----------
Zhu J, Cai S, Suo Z (2010) Nonlinear oscillation of a dielectric elastomer balloon.
Polymer International 59:378-383, doi:10.1002/pi.2767.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from debench.models import validation as v
from debench.models.numerics.roots import bracketed_root

#: Brent's absolute step tolerance on lam at an extremum: the roots of (5) and (6) are
#: simple, so lam is then exact to ~1e-15 relative (a few ulp of lam ~ 1..8)
XTOL = 1e-15
#: points of the sign scan in log lam on [1, lam_top] that brackets the zeros of (5) and
#: (6): their zeros are >= 0.3 apart in log lam on the stored grids (a double zero only at
#: the voltage where the maximum and minimum merge, which the stored grids avoid)
N_SCAN = 4000
#: the scan stops at this fraction of the Gent locking stretch (s and s' diverge there)
LOCK_FRACTION = 0.999
#: the neo-Hookean scan's top stretch: (5), 2(7 lam^-8 - lam^-2) - 2 vbar^2, has no zero
#: beyond 7^(1/6), and the first zero of (6), g = pbar - 4/lam + 16/lam^7, that changes
#: sign from + to - lies below 28^(1/6) = 1.74 (where 4/lam - 16/lam^7 is largest): 40 is
#: far beyond both
NH_TOP = 40.0


def _jm(Jm) -> float:
    """``Jm`` > 0, finite or inf (neo-Hookean)."""
    if isinstance(Jm, int | float) and Jm == math.inf:
        return math.inf
    return float(v.positive("Jm", Jm))


def locking_stretch(Jm: float) -> float:
    """The Gent locking stretch of the balloon: the root lam > 1 of
    2 lam^2 + lam^-4 - 3 = Jm (inf for Jm = inf, neo-Hookean)."""
    jm = _jm(Jm)
    if math.isinf(jm):
        return math.inf
    return bracketed_root(lambda x: 2 * x * x + x**-4 - 3 - jm, 1.0,
                          math.sqrt((jm + 3) / 2) + 1.0, xtol=XTOL,
                          what="Gent locking stretch").root


def _lam(lam, Jm: float):
    top = locking_stretch(Jm)
    bound = None if math.isinf(top) else (f"at or past the Gent locking stretch {top:.6g} "
                                          f"(Jm = {Jm:g})")
    return np.asarray(v.in_range("lam", lam, 1.0, top, hi_open=True, bound=bound),
                      dtype=float)


def _s(lam, jm):
    g = 1.0 if math.isinf(jm) else 1 - (2 * lam**2 + lam**-4 - 3) / jm
    return 2 * (lam**-1 - lam**-7) / g


def _ds(lam, jm):
    a = 2 * (7 * lam**-8 - lam**-2)
    if math.isinf(jm):
        return a
    g = 1 - (2 * lam**2 + lam**-4 - 3) / jm
    return a / g + 8 * (lam**-1 - lam**-7) * (lam - lam**-5) / (jm * g * g)


@v.finite_result
def pressure(lam, vbar, Jm: float = math.inf):
    """Normalised pressure pbar = p R/(mu H) of the balloon in equilibrium at stretch
    ``lam`` under the normalised voltage ``vbar`` = (Phi/H) sqrt(eps/mu), Eq. (4).

    ``lam`` (number or array) in [1, lam_lock); ``vbar >= 0``; ``Jm > 0`` or inf
    (neo-Hookean).
    """
    jm = _jm(Jm)
    lam = _lam(lam, jm)
    vb = v.nonnegative("vbar", vbar)
    return _s(lam, jm) - 2 * vb**2 * lam


@v.finite_result
def pressure_slope(lam, vbar, Jm: float = math.inf):
    """d pbar/d lam = s'(lam) - 2 vbar^2, Eq. (5) (same arguments as :func:`pressure`)."""
    jm = _jm(Jm)
    lam = _lam(lam, jm)
    vb = v.nonnegative("vbar", vbar)
    return _ds(lam, jm) - 2 * vb**2


@v.finite_result
def voltage_squared(lam, pbar, Jm: float = math.inf):
    """vbar^2 = (s(lam) - pbar)/(2 lam) that holds stretch ``lam`` at the normalised
    pressure ``pbar`` (negative where no real voltage does), from Eq. (4)."""
    jm = _jm(Jm)
    lam = _lam(lam, jm)
    pb = v.finite("pbar", pbar)
    return (_s(lam, jm) - pb) / (2 * lam)


@dataclass(frozen=True)
class Extremum:
    """A local extremum of a closed-form curve: stretch ``lam`` and value ``value``
    (pbar for the pressure extrema, vbar for the voltage limit point) and the residual
    of its defining equation, (5) or (6), at ``lam``."""

    lam: float
    value: float
    residual: float


@dataclass(frozen=True)
class PressureExtrema:
    """The local maximum and minimum of pbar(lam) at fixed vbar (None where absent)."""

    maximum: Extremum | None
    minimum: Extremum | None


def _scan_top(jm: float) -> float:
    return NH_TOP if math.isinf(jm) else 1 + LOCK_FRACTION * (locking_stretch(jm) - 1)


def _zeros(f, jm: float, what: str) -> list[tuple[float, int]]:
    """Zeros of ``f`` on [1, top] by a sign scan in log lam and Brent: (lam, sign of f
    just before the zero)."""
    grid = np.exp(np.linspace(0.0, math.log(_scan_top(jm)), N_SCAN))
    fg = f(grid)
    out = []
    for i in np.flatnonzero(np.sign(fg[:-1]) * np.sign(fg[1:]) < 0):
        x = bracketed_root(lambda t: float(f(np.float64(t))), float(grid[i]),
                           float(grid[i + 1]), xtol=XTOL, what=what).root
        out.append((x, int(np.sign(fg[i]))))
    return out


def _extremum(f, value, x: float) -> Extremum:
    return Extremum(lam=x, value=float(value(x)), residual=float(f(np.float64(x))))


@v.finite_result
def pressure_extrema(vbar: float, Jm: float = math.inf) -> PressureExtrema:
    """The local maximum and minimum of pbar(lam) at fixed ``vbar`` on lam >= 1, Eq. (5):
    the first zero of dpbar/dlam changing sign from + to - (maximum) and the next one
    from - to + (minimum); None where there is none on [1, 0.999 lam_lock]."""
    jm = _jm(Jm)
    vb = v.nonnegative("vbar", vbar)

    def f(x):
        return _ds(x, jm) - 2 * vb**2

    zeros = _zeros(f, jm, f"d pbar/d lam at vbar = {vb:g}, Jm = {jm:g}")
    mx = next(((x, i) for i, (x, s) in enumerate(zeros) if s > 0), None)
    mn = None
    if mx is not None:
        mn = next(((x, i) for i, (x, s) in enumerate(zeros) if s < 0 and i > mx[1]), None)

    def pval(x):
        return _s(x, jm) - 2 * vb**2 * x

    return PressureExtrema(
        maximum=None if mx is None else _extremum(f, pval, mx[0]),
        minimum=None if mn is None else _extremum(f, pval, mn[0]))


@v.finite_result
def voltage_limit(pbar: float, Jm: float = math.inf) -> Extremum | None:
    """The voltage limit point at fixed normalised pressure ``pbar``: the first local
    maximum of vbar(lam) (vbar^2 > 0) on lam >= 1, a zero of g, Eq. (6), changing sign
    from + to -; None where vbar(lam) has no maximum on [1, 0.999 lam_lock]."""
    jm = _jm(Jm)
    pb = v.finite("pbar", pbar)

    def g(x):
        return x * _ds(x, jm) - _s(x, jm) + pb

    def vb(x):
        return math.sqrt((_s(x, jm) - pb) / (2 * x))

    for x, s in _zeros(g, jm, f"d vbar^2/d lam at pbar = {pb:g}, Jm = {jm:g}"):
        if s > 0 and _s(x, jm) - pb > 0:
            return _extremum(g, vb, x)
    return None
