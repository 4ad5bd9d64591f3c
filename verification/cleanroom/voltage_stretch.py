"""Clean-room ch3_voltage_stretch and ch3_voltage_stretch_as_printed, written from their
``debench problems ID --markdown`` pages only (numpy + scipy; nothing from debench).

The pages: Gent annulus B (plane stress, incompressible) between R_A = 1 and R_B = 15, its
outer radius held at lamP R_B, its inner radius at lambda_a R_A; circle A homogeneous,
Phibar^2 = (s(lambda_a) - lambda_a T1_B(R_A)) / (lambda_a^4 K(lambda_a)). Annulus
equilibrium: the membrane balance d(R T1)/dR = T2 (default) or, as printed (3.33),
d sigma1/dr = (sigma2 - sigma1)/r. Here the annulus is shot inward from R_B with the
radial stretch q = l1(R_B) as the unknown, by classical RK4 on (l1, l2) in R, all
trajectories of a pre-stretch at once; q is found for each requested lambda_a by
interpolating a sweep, then Newton steps with a finite-difference slope.
"""

from __future__ import annotations

import numpy as np
from scipy.interpolate import PchipInterpolator

JM = 120.0
RADIUS_RATIO = 15.0
#: RK4 steps over R_A <= R <= R_B: the pages state 2.3e-6 (worst) for 200 steps and the
#: error is O(h^4), so 1000 steps err by ~ 2.3e-6 / 625 ~ 4e-9 in Phibar
STEPS = 1000
#: Newton on q stops when lambda_a is hit to this relative accuracy (Phibar moves by
#: dPhibar/dlambda x 1e-12 ~ 1e-11: far below the RK4 error)
HIT_RTOL = 1e-12
MAX_NEWTON = 8
#: |Phibar^2| below this is zero: s - lam T1 cancels at lambda_a = lamP to ~ 100 eps
ROUND_OFF = 1e-12


def _gent(l1, l2):
    """Nominal stresses T1, T2 of the plane-stress Gent membrane per mu and the
    derivatives dT1/dl1, dT1/dl2."""
    i1 = l1**2 + l2**2 + l1**-2 * l2**-2
    g = 1 - (i1 - 3) / JM
    wi, wii = 0.5 / g, 0.5 / (JM * g**2)
    d1 = 2 * (l1 - l1**-3 * l2**-2)
    d2 = 2 * (l2 - l1**-2 * l2**-3)
    t1, t2 = wi * d1, wi * d2
    t1_1 = wii * d1**2 + wi * 2 * (1 + 3 * l1**-4 * l2**-2)
    t1_2 = wii * d1 * d2 + wi * 4 * l1**-3 * l2**-3
    return t1, t2, t1_1, t1_2


def _rhs(R, l1, l2, printed: bool):
    t1, t2, t1_1, t1_2 = _gent(l1, l2)
    dl2 = (l1 - l2) / R
    if printed:   # d sigma1/dR = l1 (sigma2 - sigma1)/(l2 R), sigma_a = l_a T_a
        s1, s2 = l1 * t1, l2 * t2
        dl1 = (l1 * (s2 - s1) / (l2 * R) - l1 * t1_2 * dl2) / (t1 + l1 * t1_1)
    else:         # (R T1)' = T2
        dl1 = ((t2 - t1) / R - t1_2 * dl2) / t1_1
    return dl1, dl2


def shoot(q, lamP: float, printed: bool):
    """(lambda_a, T1_B(R_A)) for the radial stretches q = l1(R_B), vectorised; NaN where a
    trajectory leaves the admissible range (Gent lock or l <= 0)."""
    q = np.asarray(q, dtype=float)
    l1, l2 = q.copy(), np.full_like(q, lamP)
    R, h = RADIUS_RATIO, (1.0 - RADIUS_RATIO) / STEPS
    with np.errstate(all="ignore"):
        for _ in range(STEPS):
            a1, a2 = _rhs(R, l1, l2, printed)
            b1, b2 = _rhs(R + h / 2, l1 + h / 2 * a1, l2 + h / 2 * a2, printed)
            c1, c2 = _rhs(R + h / 2, l1 + h / 2 * b1, l2 + h / 2 * b2, printed)
            d1, d2 = _rhs(R + h, l1 + h * c1, l2 + h * c2, printed)
            l1 = l1 + h / 6 * (a1 + 2 * b1 + 2 * c1 + d1)
            l2 = l2 + h / 6 * (a2 + 2 * b2 + 2 * c2 + d2)
            R += h
        bad = ~((l1 > 0) & (l2 > 0) & (1 - (l1**2 + l2**2 + l1**-2 * l2**-2 - 3) / JM > 0))
        t1 = _gent(l1, l2)[0]
    return np.where(bad, np.nan, l2), np.where(bad, np.nan, t1)


def interface(lam_a, lamP: float, printed: bool):
    """T1_B(R_A) holding the annulus at the inner stretches ``lam_a`` (>= lamP)."""
    lam_a = np.asarray(lam_a, dtype=float)
    delta = np.concatenate([[0.0], np.geomspace(1e-9, 0.95, 400)]) * lamP
    sweep_l, _ = shoot(lamP - delta, lamP, printed)
    ok = np.isfinite(sweep_l)
    n = int(np.argmin(ok)) if not ok.all() else ok.size
    sweep_l, qs = sweep_l[:n], (lamP - delta)[:n]
    if np.any(np.diff(sweep_l) <= 0) or lam_a.max() > sweep_l[-1]:
        raise RuntimeError("the annulus branch is not monotone or too short")
    q = PchipInterpolator(sweep_l, qs)(lam_a)
    for _ in range(MAX_NEWTON):
        got, t1 = shoot(q, lamP, printed)
        miss = got - lam_a
        if np.all(np.abs(miss) <= HIT_RTOL * lam_a):
            return t1
        dq = 1e-7 * q
        slope = (shoot(q + dq, lamP, printed)[0] - got) / dq
        q = q - np.where(np.abs(miss) > HIT_RTOL * lam_a, miss / slope, 0.0)
    raise RuntimeError(f"Newton on the shooting parameter did not converge in {MAX_NEWTON}")


def phibar_from_interface(lam_a, t1_b, c: float):
    """Phibar from the interface balance, given T1_B(R_A) at the stretches lam_a; NaN where
    K = 1 + c (5 lam/2 - 2) <= 0 (the page's exclusion)."""
    lam_a = np.asarray(lam_a, dtype=float)
    s = (lam_a**2 - lam_a**-4) / (1 - (2 * lam_a**2 + lam_a**-4 - 3) / JM)
    K = 1 + c * (2.5 * lam_a - 2)
    with np.errstate(all="ignore"):
        p2 = (s - lam_a * t1_b) / (lam_a**4 * K)
    # at lambda_a = lamP Phibar^2 = 0 up to the round-off of s - lam T1 (~1e-13)
    p2 = np.where(np.abs(p2) < ROUND_OFF, 0.0, p2)
    return np.where((K > 0) & (p2 >= 0), np.sqrt(np.abs(p2)), np.nan)


def phibar(lam_a, lamP: float, c: float, printed: bool = False):
    """Phibar at the stretches lam_a of circle A (membrane balance, or (3.33) as printed)."""
    return phibar_from_interface(lam_a, interface(lam_a, lamP, printed), c)


#: stretches per pre-stretch on which the events are bracketed (spacing <= 0.012: the
#: cubic spline of T1_B through them errs by ~ h^4 ~ 2e-8 relative)
EVENT_POINTS = 600
#: breakdown: Phibar_B = sqrt(eps_r eps0/mu) E_B(lam)/lam^2, E_B = 51e6 lam^1.13 V/m
EPS_R, EPS0, MU = 4.7, 8.85e-12, 51e3


def locking_stretch() -> float:
    """lam_lock: 2 lam^2 + lam^-4 - 3 = Jm (equibiaxial Gent lock of circle A)."""
    from scipy.optimize import brentq

    return brentq(lambda x: 2 * x**2 + x**-4 - 3 - JM, 1.0, 100.0, xtol=1e-15)


def events(lamP: float, cs, printed: bool = False) -> dict:
    """{(c, kind): (lambda_a, Phibar)} of the pages' events on each curve: pull-in (first
    local maximum of Phibar), loss of tension (first T1_B(R_A) = 0), breakdown (first
    Phibar = Phibar_B from below); absent when the curve has none. The interface stress
    is computed on EVENT_POINTS stretches and splined; each event is the root of the
    spline-based function in its first bracketing interval (brentq)."""
    from scipy.interpolate import CubicSpline
    from scipy.optimize import brentq

    top = 0.999 * locking_stretch() * (1 - 1e-6)
    lam = np.linspace(lamP, top, EVENT_POINTS)
    t1 = CubicSpline(lam, interface(lam, lamP, printed))

    def s(x):
        return (x**2 - x**-4) / (1 - (2 * x**2 + x**-4 - 3) / JM)

    def p2(x, c):
        return (s(x) - x * t1(x)) / (x**4 * (1 + c * (2.5 * x - 2)))

    def dp2(x, c, h=1e-6):
        return (p2(x + h, c) - p2(x - h, c)) / (2 * h)

    def pb2(x):
        return EPS_R * EPS0 / MU * (51e6 * x**1.13 / x**2) ** 2

    def first_root(f, x, sign):
        v = f(x)
        k = np.flatnonzero((sign * v[:-1] > 0) & (sign * v[1:] <= 0))
        if not k.size:
            return None
        return brentq(f, x[k[0]], x[k[0] + 1], xtol=1e-14, rtol=1e-14)

    out = {}
    for c in cs:
        end = top if c >= 0 else min(top, (4 - 2 / c) / 5 * (1 - 1e-9))
        x = lam[lam < end]
        funcs = {"pullin": (lambda y, c=c: dp2(y, c), 1, x[1:-1]),
                 # the page: on the annulus branch, for every c (K may be <= 0 there)
                 "loss_of_tension": (lambda y: t1(y), 1, lam),
                 "breakdown": (lambda y, c=c: p2(y, c) - pb2(y), -1, x[1:])}
        for kind, (f, sign, xs) in funcs.items():
            r = first_root(f, xs, sign)
            if r is not None:
                # the page's convention: Phibar 0 where K <= 0 (no curve reaches r)
                ph = np.sqrt(p2(r, c)) if 1 + c * (2.5 * r - 2) > 0 else 0.0
                out[(c, kind)] = (r, float(ph))
    return out
