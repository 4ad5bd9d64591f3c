"""Clean-room ch4_plate_critical_stretch, written from ``debench problems
ch4_plate_critical_stretch --markdown`` only (mpmath; nothing from debench).

The page's model.equations: coefficients a, 2b, c, d, e, f, g of the incremental energy of
(4.22) at fixed true D2 (variant 'derived', alpha = 0, beta = 1/2, mu = eps = 1), the six
exponentials exp(-k s x2) (s = +-1 electric, +-s of the reduced quartic with B = (d/f) s A)
and the three boundary rows on each face x2 = +-h/2, k h = kH lam^-2. Here the determinant is
formed per mode family (the page's branch: flexural psi even, extensional psi odd; their
roots can be 3e-7 apart), with no special treatment of close quartic roots but the
division by their difference (the working precision absorbs the cancellation), and its
zeros are found by a sign scan in lam
followed by the Illinois bracketing iteration, both in 40 digits; as the page says, the
determinant is divided by the difference of the two quartic roots.

The variants (the page's selector ``variant``), each from its definition on the page and in
the errata its thesis note names (reference/catalogue/ch4.toml: ch4.erratum.eq4_55_b,
eq4_56_c, eq4_75_80_beta, eq4_76_xi_term, eq4_81_amplitude):

* ``derived``: the coefficients of model.equations;
* ``printed``: the printed (4.55), (4.56), i.e. 2b and c without their -2 xi lam^-4 terms,
  used consistently (rows, quartic, modes as on the page); c - d^2/f = lam^-4 + 2 xi lam^-8
  > 0, so the whole window is strongly elliptic (no lam_E);
* ``literal``: the printed rows (4.75)-(4.82) as printed: the printed coefficients with
  beta = 1 in the rows (eq4_75_80_beta; with alpha = 0 the quartic and B = (d/f) s A do not
  depend on beta), the normal-traction row with 6 xi lam^-8 where 2b + c has 8 xi lam^-8
  (eq4_76_xi_term: lam^2 + 2 lam^-4 + 2 Dhat^2 + 6 xi lam^-8 - c s^2), and the modes s = +-1
  purely mechanical, (A, B) = (1, 0) (eq4_81_amplitude as printed), except at Dhat = 0, where
  the rows are then singular for every lam and the electric mode (0, 1) is substituted
  (that entry's note).
"""

from __future__ import annotations

import mpmath as mp
import numpy as np

#: working digits: the determinant loses up to ~12 digits where two quartic roots nearly
#: coincide (lam -> 1, xi = 0: separation ~ 1e-4) and the columns scale as exp(s kH)
DIGITS = 40
#: the stretch window of the page's domain
WINDOW = (mp.mpf("0.4"), mp.mpf(8))
BETA = mp.mpf("0.5")
#: sign-scan points over the window (geometric, double precision, per mode family): roots
#: of one family are >= 0.8 % apart on these curves (measured on the reference), 2000
#: points are 0.15 % apart
N_SCAN = 2000
#: a cheaper scan (2.5 % apart) for single checks where the roots are known to be far apart
N_SCAN_FAST = 120


VARIANTS = ("derived", "printed", "literal")


def ellipticity_limit(xi, variant="derived"):
    """lam_E = (2 xi/(2 xi - 1))^(1/4) for xi > 1/2 (the page's exclusion; variant
    'derived'), else inf (the printed coefficients: c - d^2/f = lam^-4 + 2 xi lam^-8 > 0)."""
    xi = mp.mpf(xi)
    if variant != "derived":
        return mp.inf
    return (2 * xi / (2 * xi - 1)) ** mp.mpf("0.25") if xi > mp.mpf("0.5") else mp.inf


def coefficients(lam, xi, D, variant="derived", beta=None):
    """(a, 2b, c, d, e, f, g) of the page, alpha = 0 (``lam`` an mpf or a numpy array):
    'derived' as on the page, 'printed' and 'literal' without the -2 xi lam^-4 terms
    (printed (4.55), (4.56)), 'literal' with beta = 1 (the printed rows)."""
    if beta is None:
        beta = 1 if variant == "literal" else BETA
    iso = 1 if variant == "derived" else 0       # the -2 xi lam^-4 terms
    a = lam**2
    b2 = lam**2 + (1 - 2 * iso * xi) * lam**-4 + 6 * xi * lam**-8 + beta * D**2
    c = (1 - 2 * iso * xi) * lam**-4 + 2 * xi * lam**-8 + beta * D**2
    d, e, f, g = beta * D, 2 * beta * D, beta, beta
    return a, b2, c, d, e, f, g


def normal_row_coefficient(lam, xi, b2, c, variant="derived"):
    """The s-independent coefficient of the normal-traction row T22 (2b + c on the page;
    'literal': the printed (4.76) with 6 xi lam^-8 where 2b + c has 8 xi lam^-8)."""
    return b2 + c - (2 * xi * lam**-8 if variant == "literal" else 0)


def unit_mode(D, variant="derived"):
    """Amplitudes (A, B) of the modes s = +-1: the electric mode (0, 1) of the page, or
    ('literal', Dhat != 0) the printed mechanical mode (1, 0) of (4.81)."""
    return (1, 0) if variant == "literal" and D != 0 else (0, 1)


def dhat(lam, D, voltage: bool, beta=None):
    """The true displacement: D itself, or at fixed voltage Vhat = D the page's
    Dhat(lam) = Vhat lam^2/(alpha lam^4 + beta) with alpha = 0."""
    beta = BETA if beta is None else beta
    return D * lam**2 / beta if voltage else D


def determinant(lam, kH, xi, D, parity=None, voltage=False, variant="derived"):
    """The 6 x 6 determinant of the six exponentials' boundary rows on both faces
    (``parity`` None), or the 3 x 3 determinant of one mode family on the face x2 = +h/2:
    "E" (psi even: the modes s and -s with equal A, opposite B) or "O" (psi odd), divided
    by the difference of the quartic roots (the page's note)."""
    with mp.workdps(DIGITS):
        lam, kH, xi, D = (mp.mpf(x) for x in (lam, kH, xi, D))
        D = dhat(lam, D, voltage)
        a, b2, c, d, e, f, g = coefficients(lam, xi, D, variant)
        k22 = normal_row_coefficient(lam, xi, b2, c, variant)
        qa, qb, qc = a, b2 - d**2 / f, c - d**2 / f
        disc = mp.sqrt(mp.mpc(qb**2 - 4 * qa * qc))
        pair = [mp.sqrt((qb + disc) / (2 * qc)), mp.sqrt((qb - disc) / (2 * qc))]
        t = kH * lam**-2        # k h

        def column(s, A, B, w):
            rows = (c * (1 + s**2) * A - d * s * B,
                    (k22 - c * s**2) * s * A - (e - d * s**2) * B,
                    d * (1 + s**2) * A - f * s * B)
            return ([r * mp.exp(-s * t / 2 - w) for r in rows]      # face x2 = +h/2
                    + [r * mp.exp(s * t / 2 - w) for r in rows])    # face x2 = -h/2

        # each column divided by exp(|Re s| t/2) (zeros unchanged): bounded entries also
        # where a quartic root grows without bound (lam -> lam_E)
        cols = []
        for s in pair:
            w = abs(mp.re(s)) * t / 2
            cols.append((column(s, 1, d / f * s, w), column(-s, 1, -d / f * s, w)))
        one = mp.mpf(1)
        A1, B1 = unit_mode(D, variant)
        cols.append((column(one, A1, B1, t / 2), column(-one, A1, -B1, t / 2)))
        if parity is None:
            M = mp.matrix(6, 6)
            flat = [c_ for p_ in cols for c_ in p_]
            for j, col in enumerate(flat):
                for i in range(6):
                    M[i, j] = col[i]
        else:
            # the modes (s, A, B), (-s, A, -B) map onto each other under x2 -> -x2: psi
            # even takes their sum, psi odd the difference (for the electric mode the
            # page's c(1) - c(-1) of (0, 1) for psi even)
            sign = 1 if parity == "E" else -1
            M = mp.matrix(3, 3)
            for j, (cp, cm) in enumerate(cols):
                for i in range(3):
                    M[i, j] = cp[i] + sign * cm[i]
        return mp.re(mp.det(M) / (pair[0] - pair[1]))


def determinant_double(lam, kH, xi, D, parity, voltage=False, variant="derived"):
    """:func:`determinant` of one mode family in double precision, vectorised over
    ``lam`` (for the sign scan only: it loses up to ~12 digits where the quartic roots
    nearly coincide, which moves a sign change by far less than a scan interval)."""
    lam = np.asarray(lam, dtype=float)
    D0, D = D, dhat(lam, D, voltage, float(BETA))
    a, b2, c, d, e, f, _ = coefficients(lam, xi, D, variant,
                                        1.0 if variant == "literal" else float(BETA))
    k22 = normal_row_coefficient(lam, xi, b2, c, variant)
    d = d * np.ones_like(lam)
    qa, qb, qc = a, b2 - d**2 / f, c - d**2 / f
    disc = np.sqrt((qb**2 - 4 * qa * qc).astype(complex))
    pair = [np.sqrt((qb + disc) / (2 * qc)), np.sqrt((qb - disc) / (2 * qc))]
    t = kH * lam**-2
    one = np.ones_like(pair[0])

    def top(sv, A, B, w):
        rows = (c * (1 + sv**2) * A - d * sv * B,
                (k22 - c * sv**2) * sv * A - (e - d * sv**2) * B,
                d * (1 + sv**2) * A - f * sv * B)
        return np.stack([r * np.exp(-sv * t / 2 - w) for r in rows], axis=-1)

    sign = 1 if parity == "E" else -1
    cols = []
    for sv in pair:
        w = np.abs(sv.real) * t / 2
        cols.append(top(sv, one, d / f * sv, w) + sign * top(-sv, one, -d / f * sv, w))
    A1, B1 = unit_mode(D0, variant)    # Dhat(lam) = 0 where the given D = 0
    cols.append(top(one, A1 * one, B1 * one, t / 2)
                + sign * top(-one, A1 * one, -B1 * one, t / 2))
    M = np.stack(cols, axis=-1)
    with np.errstate(all="ignore"):
        return np.real(np.linalg.det(M) / (pair[0] - pair[1]))


def roots(kH, xi, D, n_scan=N_SCAN, voltage=False, variant="derived"):
    """Every zero in the window (below lam_E), ascending (``voltage``: D is the fixed
    voltage Vhat, ch4_plate_voltage_control; ``variant``: 'derived', 'printed' or
    'literal'): geometric sign scan of ``n_scan``
    points plus points approaching lam_E (double precision), each sign change confirmed
    and refined to 30 digits in 40-digit arithmetic."""
    with mp.workdps(DIGITS):
        lo, hi = WINDOW
        lam_e = ellipticity_limit(xi, variant)
        top = min(hi, lam_e)
        grid = [lo * (top / lo) ** (mp.mpf(i) / n_scan) for i in range(n_scan)]
        if lam_e < hi:
            grid += [lam_e * (1 - mp.mpf(10) ** -k) for k in range(2, 12)]
        grid = sorted(x for x in grid if x < top)
        out = []
        for parity in ("E", "O"):   # the families separately: their roots can nearly meet
            signs = np.sign(determinant_double(np.array([float(x) for x in grid]),
                                               float(kH), float(xi), float(D), parity,
                                               voltage, variant))
            for k in np.flatnonzero(signs[:-1] * signs[1:] < 0):
                x0, x1 = grid[k], grid[k + 1]

                def det(x, parity=parity):
                    return determinant(x, kH, xi, D, parity, voltage, variant)

                f0, f1 = det(x0), det(x1)
                if f0 * f1 < 0:   # the sign change confirmed in 40 digits
                    out.append(_bracketed(det, x0, x1, f0, f1))
        return sorted(out)


def _bracketed(f, a, b, fa, fb, rtol=None, maxiter=400):
    """The zero of ``f`` in [a, b] (fa fb < 0) by the Illinois variant of regula falsi, to
    a bracket of ``rtol`` relative (default 1e-30); RuntimeError if it does not get there."""
    rtol = mp.mpf(10) ** -30 if rtol is None else rtol
    side = 0
    for _ in range(maxiter):
        if abs(b - a) <= rtol * abs(b):
            return (a + b) / 2
        x = b - fb * (b - a) / (fb - fa)
        if not (min(a, b) < x < max(a, b)):
            x = (a + b) / 2
        fx = f(x)
        if fx == 0:
            return x
        if fx * fb < 0:
            a, fa = b, fb
            side = 0
        else:
            fa = fa / 2 if side == 1 else fa
            side = 1
        b, fb = x, fx
    raise RuntimeError(f"regula falsi did not reach rtol {rtol} in {maxiter} iterations")


def root_near(kH, xi, D, guess, rel=None, variant="derived"):
    """The zero bracketed by guess (1 -+ rel) (ValueError when no sign change brackets
    it; ``rel`` default 1e-4): a cheap refinement where the sign scan of :func:`roots` is
    not needed."""
    with mp.workdps(DIGITS):
        rel = mp.mpf("1e-4") if rel is None else mp.mpf(rel)
        g = mp.mpf(guess)
        a, b = g * (1 - rel), g * (1 + rel)
        fa, fb = (determinant(a, kH, xi, D, variant=variant),
                  determinant(b, kH, xi, D, variant=variant))
        if fa * fb > 0:
            raise ValueError(f"no sign change of the determinant in [{a}, {b}]")
        return _bracketed(lambda x: determinant(x, kH, xi, D, variant=variant), a, b, fa,
                          fb)
