"""Clean-room ch4_plate_critical_stretch, written from ``debench problems
ch4_plate_critical_stretch --markdown`` only (mpmath; nothing from debench).

The page's model.equations: coefficients a, 2b, c, d, e, f, g of the incremental energy of
(4.22) at fixed true D2 (variant 'derived', alpha = 0, beta = 1/2, mu = eps = 1), the six
exponentials exp(-k s x2) (s = +-1 electric, +-s of the reduced quartic with B = (d/f) s A)
and the three boundary rows on each face x2 = +-h/2, k h = kH lam^-2. Here the full 6 x 6
determinant is formed directly (no parity split, no special treatment of close roots: the
working precision absorbs the cancellation) and its zeros are found by a sign scan in lam
followed by the Illinois bracketing iteration, both in 40 digits; as the page says, the
determinant is divided by the difference of the two quartic roots.
"""

from __future__ import annotations

import mpmath as mp

#: working digits: the determinant loses up to ~12 digits where two quartic roots nearly
#: coincide (lam -> 1, xi = 0: separation ~ 1e-4) and the columns scale as exp(s kH)
DIGITS = 40
#: the stretch window of the page's domain
WINDOW = (mp.mpf("0.4"), mp.mpf(8))
BETA = mp.mpf("0.5")
#: a cheaper sign scan: neighbouring roots of these curves are >= 5 % apart in lam and
#: 120 geometric points over the window are 2.5 % apart
N_SCAN_FAST = 120


def ellipticity_limit(xi):
    """lam_E = (2 xi/(2 xi - 1))^(1/4) for xi > 1/2 (the page's exclusion), else inf."""
    xi = mp.mpf(xi)
    return (2 * xi / (2 * xi - 1)) ** mp.mpf("0.25") if xi > mp.mpf("0.5") else mp.inf


def coefficients(lam, xi, D):
    """(a, 2b, c, d, e, f, g) of the page, variant 'derived', alpha = 0."""
    a = lam**2
    b2 = lam**2 + (1 - 2 * xi) * lam**-4 + 6 * xi * lam**-8 + BETA * D**2
    c = (1 - 2 * xi) * lam**-4 + 2 * xi * lam**-8 + BETA * D**2
    d, e, f, g = BETA * D, 2 * BETA * D, BETA, BETA
    return a, b2, c, d, e, f, g


def determinant(lam, kH, xi, D):
    """The 6 x 6 determinant of the six exponentials' boundary rows on both faces."""
    with mp.workdps(DIGITS):
        lam, kH, xi, D = (mp.mpf(x) for x in (lam, kH, xi, D))
        a, b2, c, d, e, f, g = coefficients(lam, xi, D)
        qa, qb, qc = a, b2 - d**2 / f, c - d**2 / f
        disc = mp.sqrt(mp.mpc(qb**2 - 4 * qa * qc))
        modes = []
        pair = [mp.sqrt((qb + disc) / (2 * qc)), mp.sqrt((qb - disc) / (2 * qc))]
        for s in pair:
            modes += [(s, 1, d / f * s), (-s, 1, -d / f * s)]
        modes += [(mp.mpf(1), 0, 1), (mp.mpf(-1), 0, 1)]
        t = kH * lam**-2        # k h
        M = mp.matrix(6, 6)
        for j, (s, A, B) in enumerate(modes):
            rows = (c * (1 + s**2) * A - d * s * B,
                    (b2 + c - c * s**2) * s * A - (e - d * s**2) * B,
                    d * (1 + s**2) * A - f * s * B)
            # each column divided by exp(|Re s| t/2) (zeros unchanged): bounded entries
            # also where a quartic root grows without bound (lam -> lam_E)
            w = abs(mp.re(s)) * t / 2
            for i, r in enumerate(rows):
                M[i, j] = r * mp.exp(-s * t / 2 - w)       # face x2 = +h/2
                M[i + 3, j] = r * mp.exp(s * t / 2 - w)    # face x2 = -h/2
        # the page's note: two quartic roots coincide at xi = 0, lam = 1 and the plain
        # determinant changes sign there (a spurious zero); divided by their difference it
        # does not (and it is real also for a complex-conjugate pair)
        return mp.re(mp.det(M) / (pair[0] - pair[1]))


def roots(kH, xi, D, n_scan=600):
    """Every zero in the window (below lam_E), ascending: geometric sign scan of ``n_scan``
    points plus points approaching lam_E, each sign change refined to 30 digits."""
    with mp.workdps(DIGITS):
        lo, hi = WINDOW
        lam_e = ellipticity_limit(xi)
        top = min(hi, lam_e)
        grid = [lo * (top / lo) ** (mp.mpf(i) / n_scan) for i in range(n_scan)]
        if lam_e < hi:
            grid += [lam_e * (1 - mp.mpf(10) ** -k) for k in range(2, 12)]
        grid = sorted(x for x in grid if x < top)
        vals = [determinant(x, kH, xi, D) for x in grid]
        out = []
        for x0, x1, f0, f1 in zip(grid, grid[1:], vals, vals[1:], strict=False):
            if f0 == 0:
                out.append(x0)
            elif f0 * f1 < 0:
                out.append(_bracketed(lambda x: determinant(x, kH, xi, D), x0, x1, f0, f1))
        return out


def _bracketed(f, a, b, fa, fb, rtol=mp.mpf(10) ** -30, maxiter=400):
    """The zero of ``f`` in [a, b] (fa fb < 0) by the Illinois variant of regula falsi, to
    a bracket of ``rtol`` relative; RuntimeError if it does not get there."""
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


def root_near(kH, xi, D, guess, rel=mp.mpf("1e-4")):
    """The zero bracketed by guess (1 -+ rel) (ValueError when no sign change brackets
    it): a cheap refinement where the sign scan of :func:`roots` is not needed."""
    with mp.workdps(DIGITS):
        g = mp.mpf(guess)
        a, b = g * (1 - rel), g * (1 + rel)
        fa, fb = determinant(a, kH, xi, D), determinant(b, kH, xi, D)
        if fa * fb > 0:
            raise ValueError(f"no sign change of the determinant in [{a}, {b}]")
        return _bracketed(lambda x: determinant(x, kH, xi, D), a, b, fa, fb)
