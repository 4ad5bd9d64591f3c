"""ch4_plate_voltage_control at xi = 0 against its closed-form limits, derived here from the
problem's page alone (sympy; nothing from debench.models.plate).

The isotropic plate (xi = 0, alpha = 0, beta = 1/2, units mu = eps = 1) at fixed voltage
Vhat carries the true displacement Dhat = Vhat lam^2/beta, so the Maxwell stress is
beta Dhat^2 = 2 Vhat^2 lam^4. With the page's coefficients the quartic of the exponents is
lam^-4 s^4 - (lam^2 + lam^-4) s^2 + lam^2 = 0: s = +-1, +-lam^3, independent of the field.

Thin plate, kh -> 0 (h = H lam^-2 the current thickness, kh = kH lam^-2)
    The membrane limit (Su, Conroy Broderick, Chen & Destrade 2018, Wrinkles in soft
    dielectric plates, JMPS 119:298-318, give both limits in closed form; re-derived here): a
    long flexural wave bifurcates where the in-plane true stress of the membrane vanishes
    (Euler buckling with vanishing bending stiffness),
        S(lam) = lam^2 - lam^-4 - 2 Vhat^2 lam^4 = 0;                                 (T1)
    a long extensional wave where the plane-strain tangent of the nominal in-plane stress at
    fixed voltage vanishes: T1(l1) = l1 - l1^-3 l3^-2 - 2 Vhat^2 l1 l3^2 (free energy
    W - Vhat^2 l1^2 l3^2 / (2 beta) per reference volume), dT1/dl1 = 0 at l1 = l3 = lam:
        1 + 3 lam^-6 - 2 Vhat^2 lam^2 = 0.                                           (T2)
    Beyond the leading order, the series in t = kh of each parity's 3 x 3 determinant (the
    page's boundary rows, columns c(s) +- c(-s)) is F = t^m [P0(lam) + P1(lam) t^2 +
    P2(lam) t^4 + O(t^6)] (m = 1 flexural, 2 extensional); P0 is (T1) or (T2) times a factor
    free of Vhat (checked), and its root lam0 moves as lam0 + a t^2 + b t^4 with
    a = -P1/P0', b = -(P0'' a^2/2 + P1' a + P2)/P0'. In kH (t = kH lam^-2 at the root):
        lam_cr(kH) = lam0 + C2 kH^2 + C4 kH^4 + O(kH^6),
        C2 = a lam0^-4,  C4 = b lam0^-8 - 4 a^2 lam0^-9.

Thick plate, kh -> infinity
    Each face becomes an electroded half-space; with the three decaying exponentials
    (quartic s = 1, s = lam^3 with B = (d/f) s A; electric s = 1) the half-space
    determinant is (derived by hand, checked symbolically below)
        (r - 1) [r^3 + r^2 + 3 r - 1 - 2 Vhat^2 lam^8 (r + 1)] / (2 lam^8),  r = lam^3,
    whose bracket is Biot's equibiaxial surface instability r^3 + r^2 + 3r - 1 = 0 at
    Vhat = 0 (the factor r - 1 is the coincidence of the exponents s = 1 and lam^3, no mode).
    The plate's flexural and extensional roots split about each half-space root lam_inf by
    +-delta: each column for exponent s couples the faces through exp(-s kh), so
    delta ~ K exp(-s_min kh), s_min = min(1, lam_inf^3), to relative order
    eps_next = max(exp(-s_min kh), exp(-(s_2 - s_min) kh)) (s_2 the next exponent).
"""

from __future__ import annotations

import mpmath
import numpy as np
import pytest
import sympy as sp
from debench.reference.datasets import read_dataset

#: the stored roots' own error: regula falsi to 1e-13, confirmed against 40-digit roots to
#: 1e-12 relative (verification/test_problems_specs.py, MP_ROOT_RTOL)
ROOT_RTOL = 1e-12
#: the O(kH^6) remainder of the three-term expansion is bounded by the next term's size:
#: the two-term expansion's error is C4 kH^4 (1 + O(kH^2)); a factor 2 covers the O(kH^2)
#: relative correction at kH <= 0.0121 by far
C4_FACTOR = 2.0
#: the decay rate of the split is checked to this multiple of the first neglected relative
#: order eps_next (the coefficient of that order is O(1))
EPS_NEXT_FACTOR = 3.0
#: the stretch window of the reference (roots are counted inside it)
WINDOW = (0.4, 8.0)
#: sympy digits of the roots and coefficients
DIGITS = 40
#: terms kept in the exponentials' series: coefficients up to t^7 of the determinant are
#: exact (the extensional family needs t^6)
N_EXP = 7

LAM, T, V = sp.symbols("lam t Vhat", positive=True)
BETA = sp.Rational(1, 2)


def _rows(s, A, B):
    """The page's boundary rows (T21, T22, E1) of one exponential (k = 1), xi = 0,
    alpha = 0, at fixed voltage (Dhat = Vhat lam^2/beta)."""
    D = V * LAM**2 / BETA
    two_b = LAM**2 + LAM**-4 + BETA * D**2
    c = LAM**-4 + BETA * D**2
    d, e, f = BETA * D, 2 * BETA * D, BETA
    return sp.Matrix([c * (1 + s**2) * A - d * s * B,
                      (two_b + c - c * s**2) * s * A - (e - d * s**2) * B,
                      d * (1 + s**2) * A - f * s * B])


def _exp(z):
    return sum(z**n / sp.factorial(n) for n in range(N_EXP + 1))


def _thin_series():
    """{family: (P0, P1, P2)}: the t-series of each parity's determinant on the face
    x2 = t/2, divided by the spurious factor lam^6 - 1."""
    d_over_f = V * LAM**2 / BETA   # d/f = Dhat
    x = T / 2

    def quartic(s, sign):   # psi even (sign +1): c(s) + c(-s)
        return (_rows(s, 1, d_over_f * s) * _exp(-s * x)
                + sign * _rows(-s, 1, -d_over_f * s) * _exp(s * x))

    def electric(sign):     # phi odd (sign -1) with psi even
        return _rows(1, 0, 1) * _exp(-x) + sign * _rows(-1, 0, 1) * _exp(x)

    out = {}
    for family, sq, se, m in (("flexural", 1, -1, 1), ("extensional", -1, 1, 2)):
        M = sp.Matrix.hstack(quartic(1, sq), quartic(LAM**3, sq), electric(se))
        poly = sp.Poly(sp.expand(M.det(method="berkowitz")), T)
        assert all(poly.coeff_monomial(T**k) == 0 for k in range(m))
        out[family] = tuple(sp.cancel(poly.coeff_monomial(T**(m + 2 * j)) / (LAM**6 - 1))
                            for j in range(3))
    return out


@pytest.fixture(scope="module")
def thin():
    return _thin_series()


@pytest.fixture(scope="module")
def reference():
    return read_dataset("ch4_voltage_control").sel(variant="derived", xi=0.0)


def _membrane_conditions():
    return {"flexural": LAM**2 - LAM**-4 - 2 * V**2 * LAM**4,
            "extensional": 1 + 3 * LAM**-6 - 2 * V**2 * LAM**2}


def test_thin_series_leading_order_is_the_membrane_conditions(thin):
    """P0 of each family is the membrane condition (T1) / (T2) times a factor free of the
    voltage: the long-wave roots are where the in-plane stress or its plane-strain tangent
    vanishes."""
    for family, cond in _membrane_conditions().items():
        ratio = sp.cancel(thin[family][0] / cond)
        assert V not in ratio.free_symbols, (family, ratio)
        assert ratio.free_symbols == {LAM}


def _thin_roots(thin, vhat):
    """[(family, lam0, C2, C4)] of the thin-plate expansion inside WINDOW."""
    out = []
    vr = sp.Rational(str(vhat))
    with mpmath.workdps(DIGITS):
        for family, (p0, p1, p2) in thin.items():
            p0, p1, p2 = (q.subs(V, vr) for q in (p0, p1, p2))
            f = {name: sp.lambdify(LAM, expr, "mpmath") for name, expr in (
                ("p0", p0), ("p1", p1), ("p2", p2), ("dp0", sp.diff(p0, LAM)),
                ("ddp0", sp.diff(p0, LAM, 2)), ("dp1", sp.diff(p1, LAM)))}
            cond = sp.Poly(sp.numer(sp.together(_membrane_conditions()[family].subs(V, vr))),
                           LAM)
            for z in cond.nroots(n=DIGITS):
                if not (z.is_real and WINDOW[0] <= z <= WINDOW[1]):
                    continue
                l0 = mpmath.findroot(f["p0"], mpmath.mpf(str(z)))
                a = -f["p1"](l0) / f["dp0"](l0)
                b = -(f["ddp0"](l0) * a**2 / 2 + f["dp1"](l0) * a + f["p2"](l0)) / f["dp0"](l0)
                out.append((family, float(l0), float(a * l0**-4),
                            float(b * l0**-8 - 4 * a**2 * l0**-9)))
    return out


@pytest.mark.parametrize("vhat", [0.25, 0.5, 0.75, 1.0])
@pytest.mark.parametrize("k", [0, 2])
def test_smallest_kH_roots_follow_the_thin_plate_expansion(thin, reference, vhat, k):
    """At the smallest stored kH (0.01) and the third (0.0121): the stored roots are the
    thin-plate roots, one each (flexural roots of (T1), extensional of (T2)), and each is
    lam0 + C2 kH^2 to within C4_FACTOR |C4| kH^4 plus the stored root's own error; the
    leading order alone misses by the O(kH^2) term."""
    kH = float(reference.kH.values[k])
    stored = reference.lam_cr.sel(Vhat=vhat).isel(kH=k).values
    stored = np.sort(stored[np.isfinite(stored)])
    limits = sorted(_thin_roots(thin, vhat), key=lambda r: r[1])
    assert stored.size == len(limits), (stored, limits)
    for lam, (family, l0, c2, c4) in zip(stored, limits, strict=True):
        two_term = l0 + c2 * kH**2
        bound = C4_FACTOR * abs(c4) * kH**4 + ROOT_RTOL * lam
        assert abs(lam - two_term) <= bound, (family, lam, two_term, bound)
        assert abs(lam - l0) > 0.5 * abs(c2) * kH**2, (family, lam, l0)


def test_half_space_determinant_is_biot_with_the_maxwell_stress():
    """The 3 x 3 determinant of the decaying exponentials on one face equals the closed
    form in the module docstring (Biot's cubic at Vhat = 0)."""
    r = LAM**3
    H = sp.Matrix.hstack(_rows(1, 1, V * LAM**2 / BETA),
                         _rows(r, 1, V * LAM**2 / BETA * r), _rows(1, 0, 1)).det()
    closed = (r - 1) * (r**3 + r**2 + 3 * r - 1 - 2 * V**2 * LAM**8 * (r + 1)) / (2 * LAM**8)
    assert sp.simplify(H - closed) == 0


def _half_space_roots(vhat):
    r = LAM**3
    cubic = sp.Poly(sp.expand(r**3 + r**2 + 3 * r - 1
                              - 2 * sp.Rational(str(vhat))**2 * LAM**8 * (r + 1)), LAM)
    return sorted(float(z) for z in cubic.nroots(n=DIGITS)
                  if z.is_real and WINDOW[0] <= z <= WINDOW[1])


@pytest.mark.parametrize("vhat", [0.25, 0.5, 0.75, 1.0])
def test_largest_kH_roots_straddle_the_half_space_roots_and_split_at_the_derived_rate(
        reference, vhat):
    """At kH = 20 the stored roots are one pair per half-space root, each pair straddling
    it; between the last two stored kH the pair's split decays as exp(-s_min kh), to
    EPS_NEXT_FACTOR x the first neglected relative order (not checked at lam_inf = 1, where
    the exponents 1 and lam^3 coincide and the split carries an algebraic factor)."""
    kH = reference.kH.values
    last, prev = (np.sort(v[np.isfinite(v)]) for v in (
        reference.lam_cr.sel(Vhat=vhat).isel(kH=-1).values,
        reference.lam_cr.sel(Vhat=vhat).isel(kH=-2).values))
    roots = _half_space_roots(vhat)
    assert last.size == prev.size == 2 * len(roots)
    for j, lam_inf in enumerate(roots):
        pair, pair_prev = last[2 * j:2 * j + 2], prev[2 * j:2 * j + 2]
        assert pair[0] < lam_inf < pair[1], (lam_inf, pair)
        assert pair_prev[0] < lam_inf < pair_prev[1], (lam_inf, pair_prev)
        if abs(lam_inf - 1) < 1e-9:
            continue
        exps = sorted({1.0, lam_inf**3})
        s_min, s_2 = exps[0], exps[1]
        kh = kH[-1] * lam_inf**-2
        predicted = np.exp(-s_min * (kH[-1] - kH[-2]) * lam_inf**-2)
        observed = (pair[1] - pair[0]) / (pair_prev[1] - pair_prev[0])
        eps_next = max(np.exp(-s_min * kh), np.exp(-(s_2 - s_min) * kh))
        noise = 4 * ROOT_RTOL * lam_inf / (pair[1] - pair[0])
        assert abs(observed / predicted - 1) <= EPS_NEXT_FACTOR * eps_next + noise, (
            lam_inf, observed, predicted, eps_next)
