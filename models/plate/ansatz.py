"""Method 1: exponential-ansatz determinant (thesis eqs 4.61-4.82), even/odd split.

The incremental fields psi = A exp(-k s x2 + i k x1), phi = k B exp(...) (4.61)-(4.62)
solve (4.52)-(4.53) iff det M(s) = 0, M(s) = [[a - 2b s^2 + c s^4, s(e - d - d s^2)],
[s(e - d - d s^2), f s^2 - g]]. With alpha = 0 (f = g, e = 2d) this is (4.63):
(s^2 - 1)[qc s^4 - qb s^2 + qa] = 0 (re-derived; see ``reduced_quartic``).

Modes (re-derived, cf. (4.81)-(4.82)):

* s = +-1: M(1) = diag(a - 2b + c, 0). a - 2b + c = -4 xi lam^-8 for both the derived and
  the printed coefficients, so for xi > 0 the only mode is the *electric* one
  (A, B) = (0, 1); the printed (4.81) "B = 0" is a solution only when xi = 0
  (erratum ``ch4.erratum.eq4_81_amplitude``).
* quartic roots s2, s3: B = (d/f) s A, i.e. B_hat = s Dhat A for beta-scaled rows (4.82).

Well-posedness at repeated roots: the two quartic roots enter through the symmetric
combinations (col(s2) + col(s3))/2 and (col(s2) - col(s3))/(s2 - s3), which span the same
space as col(s2), col(s3) while they are distinct and tend to col(s0), col'(s0) (the
x2 exp(-k s0 x2) solution) when they coincide (xi = 0, lam = 1). The same formulas are
real for a complex-conjugate pair. The electric mode stays independent of the quartic
modes even when a quartic root equals 1 (isotropic case). Hence results are continuous
in xi -> 0+ and there is no spurious root at lam = 1.

Even/odd split: with x2 measured from the mid-plane, the problem is invariant under
x2 -> -x2 combined with D -> -D, so modes with (psi even, phi odd) ["E", flexural:
u2 even] and (psi odd, phi even) ["O", extensional] decouple and the 6x6 determinant of
(4.75)-(4.80) factorises into two 3x3 determinants. Columns are divided by
cosh(k s h / 2) so nothing overflows for thick plates. h = H lam^-2, so k h = kH lam^-2.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
from debench.models import validation as v
from debench.models.errors import ConvergenceError, require
from debench.models.numerics.roots import regula_falsi_many
from debench.models.numerics.scan import grid_brackets
from debench.models.plate.coefficients import (
    PlateParams,
    _check_lam,
    _coefficients,
    _reduced_quartic,
    _strongly_elliptic,
    ellipticity_limit_stretch,
)

PARITIES = ("E", "O")
#: below this separation of the quartic roots the divided difference (rounding
#: ~ eps / |s2 - s3| <= 2e-11 relative) is replaced by the derivative of the column at the
#: midpoint (truncation |s2 - s3|^2 / 24 <= 4e-12 relative), taken by the five-point
#: stencil _STENCIL of step _DS (truncation ~ _DS^4 / 30 ~ 3e-14, rounding ~ eps / _DS
#: ~ 2e-13); both stay far below the 1e-7 relative accuracy stated for the roots
_CLOSE = 1e-5
_DS = 1e-3
_STENCIL = ((-2, 1 / 12), (-1, -8 / 12), (1, 8 / 12), (2, -1 / 12))
#: relative distances below the loss of strong ellipticity lam_E added to the scan grid,
#: so that a root between the last regular scan point and lam_E (where the scaled
#: determinant tends to 0) is bracketed
_ELLIPTIC_APPROACH = tuple(10.0**-k for k in range(2, 11))


@v.finite_result
def row_coefficients(lam, params: PlateParams):
    """Coefficients (c, 2b, d, e, f) of the boundary rows (4.69)-(4.71) at ``lam``.

    For ``"derived"`` and ``"printed"`` they are those of
    :func:`~debench.models.plate.coefficients.coefficients`; for ``"literal"`` the ones
    the rows (4.75)-(4.77) imply taken literally (beta absent, 6 xi lam^-8 in (4.76)).
    Vectorised over ``lam`` (finite, > 0); each coefficient has the shape of ``lam``.
    """
    return _row_coefficients(_check_lam(lam), v.instance("params", params, PlateParams))


def _row_coefficients(lam, p: PlateParams, coef=None):
    """Coefficients (c, 2b, d, e, f) entering the boundary rows (4.69)-(4.71); ``coef``:
    :func:`_coefficients` of ``(lam, p)`` when the caller holds them."""
    if p.variant == "literal":
        # (4.75)-(4.77) literally: beta absent, 6 xi lam^-8 in (4.76).
        C1 = lam**-4 + p.Dhat**2 + 2 * p.xi * lam**-8
        K2 = lam**2 + 2 * lam**-4 + 2 * p.Dhat**2 + 6 * p.xi * lam**-8
        one = np.ones_like(lam)
        return C1, K2 - C1, p.Dhat * one, 2 * p.Dhat * one, one
    a, b2, c, d, e, f, g = _coefficients(lam, p) if coef is None else coef
    return c, b2, d, e, f


def _column(s, t, parity, kind, rc, kappa):
    """Column of the parity-reduced 3x3 matrix for root s (complex arrays allowed).

    kind "quartic": (A, B) = (1, kappa s); "electric": (0, 1); "mechanical": (1, 0).
    With th = tanh(s t / 2) and the rows (4.69)-(4.71) split into their even (r1, r3) and
    odd (r2) parts in s (B odd in s for quartic/mechanical modes, even for the electric
    mode), the combinations [R(s) e^{-st/2} +- R(-s) e^{st/2}] / (2 cosh(st/2)) are

    * psi even ("E"):  quartic/mechanical (r1, -r2 th, r3);   electric (d, -(e-d) th, f)
    * psi odd  ("O"):  quartic/mechanical (r1 th, -r2, r3 th); electric (d th, -(e-d), f th)
    """
    return _stack(_column_parts(s, t, kind, rc, kappa), parity)


def _column_parts(s, t, kind, rc, kappa):
    """(r1, r2, r3, th) of :func:`_column`, before the parity combination: r1..r3 have
    the shape of ``s`` (they do not depend on t), th = tanh(s t / 2) the broadcast shape."""
    th = np.tanh(s * t / 2)
    r1, r2, r3 = _column_rows(s, kind, rc, kappa)
    return tuple(r * np.ones_like(th) for r in (r1, r2, r3)) + (th,)


def _column_rows(s, kind, rc, kappa):
    """(r1, r2, r3) of :func:`_column_parts`: the rows of root ``s``, independent of t."""
    c, b2, d, e, f = rc
    if kind == "electric":  # s = 1
        one = np.ones_like(s)
        return d * one, -(e - d) * one, f * one
    k = kappa if kind == "quartic" else 0.0
    s2 = s * s
    r1 = c * (1 + s2) - d * k * s2
    r2 = s * (b2 + c - c * s2 - e * k + d * k * s2)
    r3 = d * (1 + s2) - f * k * s2
    return r1, -r2, r3


def _stack(parts, parity):
    r1, r2, r3, th = parts
    if parity == "E":
        return np.stack(np.broadcast_arrays(r1, r2 * th, r3), axis=-1)
    return np.stack(np.broadcast_arrays(r1 * th, r2, r3 * th), axis=-1)


def _pair_det(ra, rb, r1, tha, thb, th1, parity):
    """det [c_a c_b c_1] of three parity columns (:func:`_column`) from their rows
    (:func:`_column_rows`) and th = tanh(s t / 2), expanded along the middle row.

    A column is (r1, r2 th, r3) for psi even ("E") and (r1 th, r2, r3 th) for psi odd
    ("O"), so the determinant is sum_j th_j W_j ("E") or sum_j W_j prod_{k != j} th_k
    ("O") with the same minors W_j = (-1)^(1+j) r2_j (r1 x r3 of the other two columns):
    the W_j depend on lam only and the t-dependence is in the th alone.
    """
    xa, ya, za = ra
    xb, yb, zb = rb
    x1, y1, z1 = r1
    wa = -ya * (xb * z1 - x1 * zb)
    wb = yb * (xa * z1 - x1 * za)
    w1 = -y1 * (xa * zb - xb * za)
    if parity == "E":
        return tha * wa + thb * wb + th1 * w1
    return thb * th1 * wa + tha * th1 * wb + tha * thb * w1


@v.finite_result
def quartic_roots(lam, params: PlateParams):
    """The two quartic roots (s2, s3) of the characteristic equation (4.63), Re s >= 0.

    With alpha = 0, (4.63) is (s^2 - 1) [qc s^4 - qb s^2 + qa] = 0
    (:func:`~debench.models.plate.coefficients.reduced_quartic`). s2^2 and s3^2 are the
    roots of qc sigma^2 - qb sigma + qa = 0, computed without cancellation:
    s2^2 = (qb +- sqrt(qb^2 - 4 qa qc)) / (2 qc) with the sign of Re qb, and
    s3^2 = qa / (qc s2^2); s2, s3 are their principal square roots. With s = 1 they are
    the decay rates s of the modes exp(-k s x2) of (4.61)-(4.62): real, or a
    complex-conjugate pair, and both 1 at xi = 0, lam = 1. Vectorised over ``lam``
    (finite, > 0); two complex arrays of the shape of ``lam``.
    """
    return _quartic_roots(_check_lam(lam), v.instance("params", params, PlateParams))


def _quartic_roots(lam, p, quartic=None):
    """The two quartic roots (s2, s3) with Re >= 0; ``quartic``: :func:`_reduced_quartic`
    of ``(lam, p)`` when the caller holds it."""
    qa, qb, qc = _reduced_quartic(lam, p) if quartic is None else quartic
    disc = np.asarray(qb**2 - 4 * qa * qc, dtype=complex)
    sq = np.sqrt(disc)
    # numerically stable pair: sigma+ sigma- = qa/qc
    big = np.where(np.real(qb) >= 0, (qb + sq) / (2 * qc), (qb - sq) / (2 * qc))
    small = qa / (qc * big)
    return np.sqrt(big + 0j), np.sqrt(small + 0j)


def determinant(lam, kH, params: PlateParams, parity: str):
    """Scaled 3x3 determinant of parity ``parity`` ("E" or "O"); zero at bifurcation.

    Vectorised over broadcastable ``lam`` (> 0) and ``kH`` (> 0). Raises ValueError where
    the model is not strongly elliptic (there the exponential solution does not describe
    a decaying mode and the bifurcation problem is ill-posed; mask such points with
    :func:`~debench.models.plate.coefficients.strongly_elliptic`).
    """
    v.choice("parity", parity, PARITIES)
    v.instance("params", params, PlateParams)
    lam = v.positive("lam", lam)
    kH = v.positive("kH", kH)
    det = _determinant(lam, kH, params, parity)
    bad = ~np.isfinite(det)
    if np.any(bad):
        lam_b = np.broadcast_to(lam, det.shape)[bad]
        raise ValueError(f"lam = {v._show(lam_b)} is outside the strongly elliptic range of "
                         f"{params}: the bifurcation problem is ill-posed there")
    return det


def _determinant(lam, kH, params, parity):
    """:func:`determinant` without checks: NaN where the model is not strongly elliptic."""
    require(parity in PARITIES, f"parity must be 'E' or 'O', got {parity!r}")
    return _determinants(lam, kH, params, (parity,))[0]


def determinants(lam, kH, params: PlateParams, parities=PARITIES) -> list[np.ndarray]:
    """The scaled determinant of each parity of ``parities`` (a sequence of "E", "O"),
    NaN where the model is not strongly elliptic, sharing the work the parities have in
    common: the scan of :func:`critical_stretches` and :func:`curves_vectorised`.

    The values are those of :func:`determinant`, which raises where this returns NaN.
    ``lam`` and ``kH`` (finite, > 0) broadcast against each other, and the result of each
    parity has their broadcast shape; on a tensor grid pass ``lam`` of shape (1, n) and
    ``kH`` of shape (m, 1) (the lam-only work is then done n times, not m n times).
    Method 1 is implemented for alpha = 0 (ValueError otherwise).
    """
    v.instance("params", params, PlateParams)
    lam = v.positive("lam", lam)
    kH = v.positive("kH", kH)
    return _determinants(lam, kH, params, _check_parities(parities))


def _check_parities(parities) -> tuple[str, ...]:
    """``parities`` as a tuple: a non-empty sequence of entries of :data:`PARITIES`."""
    if not isinstance(parities, Iterable):
        raise TypeError(f"parities must be a sequence of {PARITIES}, got {parities!r}")
    if isinstance(parities, str) or not all(
            isinstance(x, str) and x in PARITIES for x in parities) or not len(parities):
        raise ValueError(f"parities must be a non-empty sequence of {PARITIES}, "
                         f"got {parities!r}")
    return tuple(parities)


def _determinants(lam, kH, params, parities=PARITIES):
    """:func:`_determinant` for several parities, sharing the work they have in common.

    ``lam`` and ``kH`` broadcast against each other (their broadcast shape is the result's)
    but are not expanded: the coefficients, quartic roots and ellipticity depend on lam
    only and are evaluated on ``lam`` as given (on a tensor grid pass ``lam`` of shape
    (1, n) and ``kH`` of shape (m, 1): n evaluations instead of m n).
    """
    p = params
    require(p.alpha == 0, f"method 1 is implemented for alpha == 0 (thesis), got {p.alpha}")
    lam = np.asarray(lam, float)
    kH = np.asarray(kH, float)
    require(bool(np.all(kH > 0)), "kH must be > 0")
    t = kH * lam**-2
    # the coefficients once: boundary rows, quartic roots and ellipticity share them
    coef = None if p.variant == "literal" else _coefficients(lam, p)
    rc = _row_coefficients(lam, p, coef)
    quartic = _reduced_quartic(lam, p, coef)
    if p.variant == "literal":
        kappa = p.Dhat * np.ones_like(lam)
        # (4.81): the s = +-1 mode is (A, B) = (1, 0). Taken literally the 6x6 system is
        # singular for every lam when Dhat = 0 (row (4.77) vanishes identically) or
        # xi = 0 (the mode coincides with the quartic root s = 1); there the electric
        # mode (0, 1) is used instead, which is a solution in both cases.
        kind1 = "mechanical" if (p.xi > 0 and p.Dhat > 0) else "electric"
    else:
        kappa = rc[2] / rc[4]
        kind1 = "electric"
    s2, s3 = _quartic_roots(lam, p, quartic)
    rcx = tuple(np.asarray(r) for r in rc)
    # det [avg, dd, c1] with avg = (c2 + c3)/2, dd = (c2 - c3)/(s2 - s3) (module
    # docstring) is -det [c2, c3, c1]/(s2 - s3) by multilinearity; near a repeated root
    # dd is the central difference (c(m + _DS) - c(m - _DS))/(2 _DS) of the columns
    r2, r3 = _column_rows(s2, "quartic", rcx, kappa), _column_rows(s3, "quartic", rcx, kappa)
    r1 = _column_rows(np.ones_like(s2), kind1, rcx, kappa)
    th2, th3, th1 = np.tanh(s2 * (t / 2)), np.tanh(s3 * (t / 2)), np.tanh(t / 2)
    diff = s2 - s3
    close = np.abs(diff) < _CLOSE
    safe = np.where(close, 1.0, diff)
    if np.any(close):
        m = 0.5 * (s2 + s3)
        shifted = [(w, _column_rows(m + j * _DS, "quartic", rcx, kappa),
                    np.tanh((m + j * _DS) * (t / 2))) for j, w in _STENCIL]
    ell = (_strongly_elliptic(lam, p, quartic) if p.variant != "literal"
           else np.ones_like(lam, bool))
    out = []
    for parity in parities:
        det = -_pair_det(r2, r3, r1, th2, th3, th1, parity) / safe
        if np.any(close):
            # det [avg, dcol/ds(m), c1], linear in its second column: the stencil's sum
            dc = sum(w * (_pair_det(r2, rs, r1, th2, ths, th1, parity)
                          + _pair_det(r3, rs, r1, th3, ths, th1, parity))
                     for w, rs, ths in shifted) / (2 * _DS)
            det = np.where(close, dc, det)
        out.append(np.where(ell, np.real(det), np.nan))
    return out


@dataclass(frozen=True)
class Roots:
    """Critical stretches at one kH: ``lam`` sorted, ``parity`` of each root."""

    kH: float
    lam: np.ndarray
    parity: tuple[str, ...]


#: default lam window and scan density (geometric grid, only used to bracket roots)
LAM_WINDOW = (0.4, 8.0)
N_SCAN = 400
#: root tolerance of the scans: brackets refined to |b - a| <= XTOL + 4 eps |b| (a root's
#: round-off is ~1e-12 relative; the stated accuracy of the roots is 1e-7 relative)
XTOL = 1e-13
#: fewest scan points accepted: a coarser grid brackets no root of a typical curve (the
#: roots of Figs 4.2-4.5 are separated by ~10% in lam over LAM_WINDOW)
MIN_SCAN = 10


def scan_grid(window=LAM_WINDOW, n=N_SCAN, params: PlateParams | None = None):
    """Geometric grid of ``n >= 2`` stretches over ``window = (lo, hi)``, 0 < lo < hi.

    With ``params``, the stretches lam_E (1 - 10^-k), k = 2..10, below the loss of strong
    ellipticity lam_E of the model
    (:func:`~debench.models.plate.coefficients.ellipticity_limit_stretch`) inside the window
    are added, so that a root just below lam_E is bracketed although the next regular grid
    point is not elliptic.
    """
    lo, hi = v.window("window", window)
    n = v.integer_at_least("n", n, 2)
    grid = np.geomspace(lo, hi, n)
    if params is None:
        return grid
    lam_e = ellipticity_limit_stretch(params)
    extra = lam_e * (1.0 - np.asarray(_ELLIPTIC_APPROACH))
    extra = extra[(extra > lo) & (extra < hi)]
    return np.unique(np.concatenate([grid, extra])) if extra.size else grid


def _check_scan(kH, params, window, n_scan):
    v.positive("kH", kH)
    if not isinstance(kH, float):
        raise TypeError(f"kH must be a number, got {kH!r}")
    v.instance("params", params, PlateParams)
    v.window("window", window)
    v.integer_at_least("n_scan", n_scan, MIN_SCAN)


def critical_stretches(kH: float, params: PlateParams, *, window=LAM_WINDOW,
                       n_scan: int = N_SCAN, parities=PARITIES) -> Roots:
    """All lam in ``window`` at which a parity determinant vanishes, at fixed kH.

    The scan of :func:`curves_vectorised` at one kH: a geometric lam grid of ``n_scan``
    points (``>= MIN_SCAN``) refined around every local minimum of |det| down to
    :data:`W_SCAN` (:mod:`~debench.models.numerics.scan`), so that two roots closer than a
    grid interval are both bracketed; every sign change refined to :data:`XTOL`. Points
    where the model is not strongly elliptic are skipped (no bracket crosses them). Raises
    :class:`ConvergenceError` if the refinement fails on a bracket.
    """
    kH = v.finite("kH", kH)
    require(kH > 0, f"kH must be finite and > 0, got {kH}")
    _check_scan(kH, params, window, n_scan)
    rows, lams, pars = _refined_roots(np.array([kH]), params, window, n_scan,
                                      _check_parities(parities), XTOL)
    order = np.argsort(lams)
    return Roots(kH, lams[order], tuple(pars[i] for i in order))


#: relative width in lam to which the scan is refined around a local minimum of |det|
#: that does not resolve (:mod:`~debench.models.numerics.scan`): two roots closer than
#: W_SCAN lam may share a sampled interval and cancel. Roots are born in pairs at folds of
#: the curves lam_cr(kH), where they are arbitrarily close; at the published kH the
#: closest stored pair is 5.6e-3 apart. The refinement costs ~2 evaluations per halving
#: per root (from a grid interval of ~1.9 % to 1e-8: ~21 halvings)
W_SCAN = 1e-8


def _refined_roots(kH_values, params, window, n_scan, parities, xtol):
    """:func:`_scan_determinants` of the charge-controlled determinants of ``params`` on
    the scan grid of ``window`` and ``n_scan``."""
    grid = scan_grid(window, n_scan, params)
    # all parities on the (kH, lam) scan grid in one pass (lam-only work once per lam)
    dets = _determinants(grid[None, :], kH_values[:, None], params, parities)
    return _scan_determinants(
        lambda lam, kH, par: _determinant(lam, kH, params, par), kH_values, grid,
        dict(zip(parities, dets, strict=True)), xtol, what=str(params))


def _scan_determinants(det, kH_values, grid, sampled, xtol, *, what: str):
    """``(rows, lams, parities)`` of every zero in lam of the determinant of each parity
    at each kH of ``kH_values``.

    ``det(lam, kH, parity)`` evaluates it at arrays of points (NaN where the model is not
    strongly elliptic); ``sampled[parity]`` holds its values on the (kH, ``grid``) scan
    (shape (len(kH), len(grid))). The scans of all kH of one parity are refined together
    around the minima of |det| between samples of one sign (:data:`W_SCAN`,
    :func:`~debench.models.numerics.scan.grid_brackets`), every sign change refined by
    :func:`~debench.models.numerics.roots.regula_falsi_many` to ``|b - a| <= xtol + 4 eps
    |b|``; a zero at a sampled point is counted once. ConvergenceError naming ``what``
    when a refinement fails.
    """
    rows, lams, pars = [], [], []
    for par, dv in sampled.items():
        def evaluate(which, x, par=par):
            return det(x, kH_values[which], par)

        row, a, b, fa, fb = grid_brackets(evaluate, grid, dv, width=W_SCAN)
        if not row.size:
            continue

        def f(x, active, row=row, par=par):
            return det(x, kH_values[row[active]], par)

        try:
            r = regula_falsi_many(f, a, b, fa, fb, xtol).root
        except ConvergenceError as exc:
            raise ConvergenceError(f"root refinement failed for {what}: {exc}") from exc
        # a zero at a sampled point brackets both intervals beside it: count it once
        keep = np.ones(r.size, bool)
        keep[1:] = ~((row[1:] == row[:-1]) & (r[1:] == r[:-1]))
        rows.append(row[keep])
        lams.append(r[keep])
        pars += [par] * int(keep.sum())
    if not rows:
        return np.zeros(0, int), np.zeros(0), []
    return np.concatenate(rows), np.concatenate(lams), pars


def _pack_roots(kH_values, rows, lams, pars, max_roots: int, what: str):
    """The roots of :func:`_scan_determinants` as ``(lam, parity)`` arrays (len(kH_values),
    max_roots): per kH sorted ascending and padded with NaN, the parity codes 0 = "E",
    1 = "O", -1 = none. ConvergenceError naming ``what`` for more than ``max_roots`` roots
    at one kH."""
    codes = np.array([PARITIES.index(x) for x in pars], int)
    out = np.full((kH_values.size, max_roots), np.nan)
    par_out = np.full((kH_values.size, max_roots), -1, dtype=int)
    for r in range(kH_values.size):
        sel = np.flatnonzero(rows == r)
        if sel.size > max_roots:
            raise ConvergenceError(f"more than {max_roots} roots at kH = {kH_values[r]} "
                                   f"({what}): {np.sort(lams[sel])}")
        order = sel[np.argsort(lams[sel])]
        out[r, : order.size] = lams[order]
        par_out[r, : order.size] = codes[order]
    return out, par_out


def _check_kH_values(kH_values) -> np.ndarray:
    kH_values = np.asarray(v.positive("kH_values", kH_values), float)
    if kH_values.ndim != 1 or kH_values.size == 0:
        raise ValueError(f"kH_values must be a non-empty 1-D array, got shape "
                         f"{kH_values.shape}")
    return kH_values


def curves(kH_values, params: PlateParams, *, window=LAM_WINDOW, n_scan: int = N_SCAN,
           max_roots: int = 6):
    """Bifurcation curves lam_cr(kH): array (len(kH), max_roots) padded with NaN,
    plus the parity codes (0 = "E", 1 = "O", -1 = none): :func:`curves_vectorised` with
    its defaults but the scan density and the number of roots."""
    return curves_vectorised(kH_values, params, window=window, n_scan=n_scan,
                             max_roots=max_roots)


def curves_vectorised(kH_values, params: PlateParams, *, window=LAM_WINDOW,
                      n_scan: int = 160, max_roots: int = 8, xtol: float = XTOL):
    """lam_cr(kH) for many kH at once: the roots of :func:`critical_stretches` at each kH.

    The determinants are evaluated on the whole (kH, lam) scan grid in one call, the scans
    of all kH refined together around the minima of |det| (:data:`W_SCAN`), and every sign
    change refined simultaneously by the Illinois variant of regula falsi
    (:func:`~debench.models.numerics.roots.regula_falsi_many`) until its bracket is below
    ``xtol`` (absolute, plus 4 eps lam). Raises :class:`ConvergenceError` if any bracket
    fails to shrink or a kH has more than ``max_roots`` roots. Returns ``(lam, parity)``:
    arrays (len(kH), max_roots), lam sorted ascending and padded with NaN, parity 0 = "E",
    1 = "O", -1 = none. ``xtol`` a finite tolerance in (0, 1).
    """
    kH_values = _check_kH_values(kH_values)
    _check_scan(1.0, params, window, n_scan)
    v.integer_at_least("max_roots", max_roots, 1)
    v.tolerance("xtol", xtol)
    rows, lams, pars = _refined_roots(kH_values, params, window, n_scan, PARITIES, xtol)
    return _pack_roots(kH_values, rows, lams, pars, max_roots, str(params))
