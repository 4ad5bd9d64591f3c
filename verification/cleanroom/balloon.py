"""Clean-room lit_balloon, written from its ``debench problems lit_balloon --markdown`` page
only (mpmath at :data:`DIGITS` digits; nothing from debench).

The page gives the energy, not the equilibrium equation, to start from: the potential
energy of the sphere per 4 pi R^2 H mu, at fixed voltage and fixed pressure,

    Pi(lam) = w(lam) - vbar^2 lam^4/2 - pbar lam^3/3,

with w = W/mu the strain energy per reference volume at in-plane stretches (lam, lam)
and thickness stretch lam^-2 (neo-Hookean (I1 - 3)/2, Gent -(Jm/2) ln(1 - (I1 - 3)/Jm)),
-vbar^2 lam^4/2 the electrical part (-(1/2) C Phi^2 with C = 4 pi eps R^2 lam^4/H) and
-pbar lam^3/3 the pressure's work (p V, V = (4/3) pi R^3 lam^3). Here every derivative is
taken numerically by ``mpmath.diff`` (no hand-derived derivative, no closed form of the
equilibrium): an equilibrium is dPi/dlam = 0, so the pressure that holds lam at vbar is

    pbar(lam) = d/dlam[w - vbar^2 lam^4/2] / d/dlam[lam^3/3],

and the voltage that holds lam at pbar is

    vbar^2(lam) = d/dlam[w - pbar lam^3/3] / d/dlam[lam^4/2].

Extrema (maximum, minimum of pbar at fixed vbar; maximum of vbar at fixed pbar) are the
zeros of the numerical derivative of these functions, bracketed by a scan of it on
:data:`N_SCAN` stretches geometric in [1, top] and refined by ``mpmath.findroot``
(Anderson's bracketing method) to :data:`DIGITS` digits.
"""

from __future__ import annotations

import mpmath

#: working digits (the reference is double precision: 30 digits are exact at its scale)
DIGITS = 30
#: points of the bracketing scan of a derivative
N_SCAN = 400
#: the neo-Hookean scan's top stretch (the page's extrema all lie below 2)
NH_TOP = 10


def _dps():
    """DIGITS, or more inside mpmath.diff (which raises the precision to difference)."""
    return max(DIGITS, mpmath.mp.dps)


def _w(lam, Jm):
    """Strain energy per reference volume over mu, equibiaxial (lam, lam, lam^-2)."""
    i1 = 2 * lam**2 + lam**-4
    if Jm is None:
        return (i1 - 3) / 2
    return -Jm / 2 * mpmath.log(1 - (i1 - 3) / Jm)


def _jm(Jm):
    return None if Jm is None or Jm == float("inf") else mpmath.mpf(Jm)


def pressure(lam, vbar, Jm=None):
    """pbar = p R/(mu H) that holds stretch ``lam`` at voltage ``vbar`` (mpf)."""
    with mpmath.workdps(_dps()):
        jm, lam, vbar = _jm(Jm), mpmath.mpf(lam), mpmath.mpf(vbar)
        energy = mpmath.diff(lambda x: _w(x, jm) - vbar**2 * x**4 / 2, lam)
        return energy / mpmath.diff(lambda x: x**3 / 3, lam)


def voltage_squared(lam, pbar, Jm=None):
    """vbar^2 that holds stretch ``lam`` at pressure ``pbar`` (mpf; < 0: no voltage)."""
    with mpmath.workdps(_dps()):
        jm, lam, pbar = _jm(Jm), mpmath.mpf(lam), mpmath.mpf(pbar)
        mech = mpmath.diff(lambda x: _w(x, jm) - pbar * x**3 / 3, lam)
        return mech / mpmath.diff(lambda x: x**4 / 2, lam)


def _top(jm):
    """Top of the scan: NH_TOP, or 0.999 of the way to the Gent lock, found here."""
    if jm is None:
        return mpmath.mpf(NH_TOP)
    lock = mpmath.findroot(lambda x: 2 * x**2 + x**-4 - 3 - jm, mpmath.sqrt((jm + 3) / 2))
    return 1 + mpmath.mpf("0.999") * (lock - 1)


def _zeros(f, jm):
    """Zeros of ``f`` in [1, top], with the sign of ``f`` before each."""
    top = _top(jm)
    grid = [top ** (mpmath.mpf(k) / (N_SCAN - 1)) for k in range(N_SCAN)]
    vals = [f(x) for x in grid]
    out = []
    for a, b, fa, fb in zip(grid, grid[1:], vals, vals[1:], strict=False):
        if fa * fb < 0:
            out.append((mpmath.findroot(f, (a, b), solver="anderson"), 1 if fa > 0 else -1))
    return out


def pressure_extrema(vbar, Jm=None):
    """{'max': (lam, pbar), 'min': (lam, pbar)} of pbar(lam) at fixed vbar (None: none)."""
    with mpmath.workdps(_dps()):
        jm = _jm(Jm)
        zeros = _zeros(lambda x: mpmath.diff(lambda y: pressure(y, vbar, Jm), x), jm)
        out = {"max": None, "min": None}
        seen_max = False
        for x, sign in zeros:
            if sign > 0 and not seen_max:
                out["max"], seen_max = (x, pressure(x, vbar, Jm)), True
            elif sign < 0 and seen_max and out["min"] is None:
                out["min"] = (x, pressure(x, vbar, Jm))
        return out


def voltage_limit(pbar, Jm=None):
    """(lam, vbar) at the first local maximum of vbar(lam) with vbar^2 > 0 (None: none)."""
    with mpmath.workdps(_dps()):
        jm = _jm(Jm)
        for x, sign in _zeros(lambda x: mpmath.diff(lambda y: voltage_squared(y, pbar, Jm),
                                                    x), jm):
            v2 = voltage_squared(x, pbar, Jm)
            if sign > 0 and v2 > 0:
                return x, mpmath.sqrt(v2)
        return None
