"""Mesh-convergence and limit fits: the limit ``v_inf`` of a sequence ``v(h) = v_inf +
C h^p`` of levels ``h`` (mesh sizes, or any parameter that tends to 0), with an error
estimate, and Roache's grid convergence index.

* :func:`richardson` -- the exact three-point fit (free rate);
* :func:`convergence_fit` -- free rate, least squares over all levels, an error estimate
  from the fit's redundancy (and, with the expected order, from the two finest levels);
* :func:`asymptotic_fit` -- at a known order over the finest three levels;
* :func:`reference_fit` -- the asymptotic fit when the finest three show the expected
  order, else the free-rate fit;
* :func:`level_fit` -- any number of levels: the free-rate fit with three or more, else
  the finest level and its last change;
* :func:`gci` -- Roache's grid convergence index (observed order and safety factor 1.25,
  or 3 with the theoretical order when the observed one is off);
* :func:`p_grading_estimate` -- the value on the top discretisation of a plan of
  polynomial orders and geometric gradings, with its error estimate from the last p-step
  and the last grading change;
* :func:`propagated_accuracy` -- how far a derived value moves when its inputs move;
* :func:`two_term_limits` -- the limits of two-term expansions ``v_inf + C1 h^q1 + C2 h^q``
  over a range of second exponents q: what a single-term fit's assumption costs;
* :func:`loglog_order` -- the observed order of errors ``e(h) ~ C h^p`` of known size (or
  of remainders, jumps): the least-squares slope of log|e| against log h.

The fits return :class:`LimitFit` (:func:`richardson`: :class:`ThreePointFit`;
:func:`gci`: :class:`GCI`; :func:`p_grading_estimate`: :class:`PGradingEstimate`), which
state what was achieved.

Roache, P. J. (1994), "Perspective: a method for uniform reporting of grid refinement
studies", J. Fluids Eng. 116, 405-413 (doi:10.1115/1.2910291); Roache (1998),
*Verification and Validation in Computational Science and Engineering*, ch. 5.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import NamedTuple

import numpy as np
from debench.models.errors import ConvergenceError, require
from debench.models.numerics.roots import bracketed_root
from scipy.optimize import least_squares

#: rates a free-rate fit may find (a rate at a bound is not a fit: ConvergenceError)
RATE_BOUNDS = (0.05, 8.0)
#: absolute tolerance of the three-point rate (brentq's default, 2e-12: the rate enters
#: the limit through h^p, whose relative change is ~1e-12 |ln h|, far below the level
#: differences the fits resolve)
RATE_XTOL = 2e-12

#: On synthetic sequences v_inf + C h^1.7 + D h^3 with the h^3 term 1-4 % of the leading
#: one at the coarsest level (5 levels, h = 3 ... 0.7), the true error of the fitted limit
#: was up to 2x the larger of (drop-a-level change, fit residual); 3x covers it.
FIT_SAFETY = 3.0

#: levels of the asymptotic fit: the finest three (two unknowns at the known order, one
#: level of redundancy for the residual)
ASYMPTOTIC_LEVELS = 3

#: the observed order of the finest three levels agrees with the expected order when within
#: this distance: the three-point rate of a sequence v_inf + C h^q + D h^(2q) with the
#: second term below ~20 % of the first at the coarsest of the three stays within 0.25 of
#: q; the secant tolerance 1e-6 is 0.1 % of the level differences (~1e-3) and moves it by
#: far less
ORDER_TOL = 0.25

#: Roache's safety factors of the grid convergence index: 1.25 with three or more levels
#: whose observed order is trusted, 3 with the theoretical order (two levels, or an
#: observed order off the theoretical one)
GCI_SAFETY_OBSERVED = 1.25
GCI_SAFETY_THEORETICAL = 3.0
GCI_MIN_LEVELS = 3
"""Levels a sequence needs for its convergence to count as observed (:func:`gci_safety`)."""

#: exponents q of the second term of the two-term expansion v_h = v + C1 h^q1 + C2 h^q that
#: :func:`two_term_limits` tries: the regular h^2 and values on either side (the
#: discretisation theory of a corner singularity gives the leading q1 = 2 s, not q)
SECOND_EXPONENTS = (1.6, 2.0, 2.4, 3.0)
#: finest levels the two-term fits use (three unknowns, one redundant level)
TWO_TERM_LEVELS = 4


def gci_safety(n_levels: int) -> float:
    """Roache's safety factor for a refinement sequence of ``n_levels`` levels whose
    changes are taken as the error estimate: ``GCI_SAFETY_OBSERVED`` (1.25) with at least
    ``GCI_MIN_LEVELS`` (3) levels (the convergence is observed), else
    ``GCI_SAFETY_THEORETICAL`` (3)."""
    return GCI_SAFETY_OBSERVED if n_levels >= GCI_MIN_LEVELS else GCI_SAFETY_THEORETICAL


class ThreePointFit(NamedTuple):
    """The exact fit through three levels: limit ``v_inf`` and rate ``p``."""

    v_inf: float
    p: float


@dataclass(frozen=True)
class LimitFit:
    """A mesh limit and what supports it.

    ``v_inf`` the limit; ``p`` the rate (observed; NaN where none is fitted); ``error`` the
    error estimate of the limit (NaN with one level); ``residual`` the largest |fit - v|
    (0 for an exact fit); ``kind`` which fit; ``v_inf_expected_order`` the two-finest-level
    limit at the expected order (:func:`convergence_fit` with ``expected_order``);
    ``error_residual``, ``error_free_order``, ``error_added_level`` the three terms of the
    asymptotic fit's estimate (:func:`asymptotic_fit`)."""

    v_inf: float
    p: float
    error: float
    residual: float = 0.0
    kind: str = ""
    v_inf_expected_order: float | None = None
    error_residual: float | None = None
    error_free_order: float | None = None
    error_added_level: float | None = None


NO_FIT = LimitFit(float("nan"), float("nan"), float("nan"), float("nan"), "no fit")


def richardson(h, v) -> ThreePointFit:
    """Fit v = v_inf + C h^p through the last three levels; returns (v_inf, p).
    ConvergenceError when they do not converge monotonically at a rate in
    :data:`RATE_BOUNDS`."""
    h1, h2, h3 = h[-3:]
    v1, v2, v3 = v[-3:]
    ratio = (v1 - v2) / (v2 - v3)
    lo, hi = RATE_BOUNDS

    def f(p):
        return (h1**p - h2**p) / (h2**p - h3**p) - ratio

    if not (math.isfinite(ratio) and ratio > 0 and f(lo) * f(hi) < 0):
        raise ConvergenceError(f"richardson: levels {list(v[-3:])} at h = {list(h[-3:])} do "
                               f"not converge monotonically at a rate in [{lo}, {hi}]")
    p = bracketed_root(f, lo, hi, xtol=RATE_XTOL, what="richardson: the rate").root
    c = (v2 - v3) / (h2**p - h3**p)
    return ThreePointFit(float(v3 - c * h3**p), float(p))


def propagated_accuracy(f, x, dx) -> np.ndarray:
    """Bound on the change of ``f(x)`` (an array function of an array) when each input
    ``x[i]`` moves by up to ``dx[i]``: the sum over inputs of the change each causes alone
    (first order, one input at a time), elementwise. Regenerated derived values (ratios,
    extrapolations, error estimates) may differ from the curated ones by this much when
    their inputs are iterates converged only to ``dx``."""
    x = np.asarray(x, float)
    dx = np.broadcast_to(np.asarray(dx, float), x.shape)
    base = np.asarray(f(x), float)
    out = np.zeros_like(base)
    for i in np.ndindex(x.shape):
        xi = x.copy()
        xi[i] += dx[i]
        out += np.abs(np.asarray(f(xi), float) - base)
    return out


def convergence_fit(h, v, expected_order: float | None = None) -> LimitFit:
    """Mesh limit of ``v(h) = v_inf + C h^p`` with an error estimate.

    Three levels: the exact three-point fit (:func:`richardson`); its error estimate is
    the distance of the limit from the finest level (no redundancy to do better). Four or
    more levels (more levels than unknowns): least squares over all levels (log-spaced
    start from the three-point fit); the error estimate is :data:`FIT_SAFETY` times the
    larger of the change of the limit when the coarsest level is dropped and the largest
    fit residual.

    ``expected_order``: the asymptotic rate the discretisation theory predicts (for the
    critical voltage, twice the edge-singularity exponent,
    :func:`debench.models.buckling.singularity.expected_eigenvalue_order`). A sequence that
    is not yet in the asymptotic range fits a faster, pre-asymptotic rate, and the fit's own
    redundancy cannot see that its limit is then too close to the finest level. With it the
    error estimate also covers the limit extrapolated from the two finest levels at the
    expected rate, ``v_exp``: the error is the larger of the estimate above and
    :data:`FIT_SAFETY` times ``|v_inf - v_exp|`` (``v_inf_expected_order``).
    """
    h, v = np.asarray(h, float), np.asarray(v, float)
    if h.size < 3:
        raise ValueError(f"convergence_fit needs >= 3 levels, got {h.size}")
    if expected_order is not None and not (math.isfinite(expected_order)
                                           and 0 < expected_order <= RATE_BOUNDS[1]):
        raise ValueError(f"expected_order = {expected_order!r} must lie in "
                         f"(0, {RATE_BOUNDS[1]:g}]")

    def with_expected(out: LimitFit) -> LimitFit:
        if expected_order is None:
            return out
        v_exp = float(v[-1] + (v[-1] - v[-2]) / ((h[-2] / h[-1]) ** expected_order - 1.0))
        return replace(out, v_inf_expected_order=v_exp,
                       error=max(out.error, FIT_SAFETY * abs(out.v_inf - v_exp)))

    if h.size == 3:
        v3, p3 = richardson(h, v)
        return with_expected(LimitFit(v3, p3, float(abs(v3 - v[-1])), 0.0,
                                      "free rate, three levels (exact)"))
    try:
        v3, p3 = richardson(h, v)
    except ConvergenceError:  # the finest three are not monotone: start from the data
        v3, p3 = float(v[-1]), 1.0
    scale = abs(v[-1] - v[-2]) or 1.0
    lo, hi = RATE_BOUNDS

    def fit(hh, vv, start):
        c0 = (vv[-1] - start[0]) / hh[-1] ** start[1]
        res = least_squares(lambda x: (x[0] + x[1] * hh**x[2] - vv) / scale,
                            [start[0], c0, start[1]], bounds=([-np.inf, -np.inf, lo],
                                                              [np.inf, np.inf, hi]))
        if not res.success:
            raise ConvergenceError(f"convergence_fit: least squares failed ({res.message})")
        return res.x, float(np.max(np.abs(res.fun))) * scale

    (vi, _, p), resid = fit(h, v, (v3, p3))
    if not lo + 1e-6 < p < hi - 1e-6:
        raise ConvergenceError(f"convergence_fit: the fitted rate {p:.4g} is at a bound of "
                               f"[{lo}, {hi}]: levels {v.tolist()} at h = {h.tolist()} are "
                               "not in the asymptotic range")
    dropped = fit(h[1:], v[1:], (v3, p3))[0][0]
    return with_expected(LimitFit(float(vi), float(p),
                                  FIT_SAFETY * float(max(abs(vi - dropped), resid)),
                                  float(resid), "free rate, all levels (least squares)"))


def asymptotic_fit(h, v, order: float) -> LimitFit:
    """Mesh limit at the known asymptotic order: ``v(h) = v_inf + C h^order`` by least
    squares over the finest :data:`ASYMPTOTIC_LEVELS` levels.

    The finest levels are the asymptotic range (their observed order, ``p``, is the
    three-point rate of :func:`richardson`). The error estimate is :data:`FIT_SAFETY` times
    the largest of: the fit residual; the distance from the three-point limit with a free
    rate (a sequence not yet at the expected order); and, when a coarser level exists, the
    change of the limit when it is added to the fit (what is left of pre-asymptotic
    terms). The three terms are ``error_residual``, ``error_free_order`` and
    ``error_added_level``.
    """
    h, v = np.asarray(h, float), np.asarray(v, float)
    if h.size < ASYMPTOTIC_LEVELS:
        raise ValueError(f"asymptotic_fit needs >= {ASYMPTOTIC_LEVELS} levels, got {h.size}")
    if not (math.isfinite(order) and 0 < order <= RATE_BOUNDS[1]):
        raise ValueError(f"order = {order!r} must lie in (0, {RATE_BOUNDS[1]:g}]")

    def fixed(n):
        a = np.column_stack([np.ones(n), h[-n:] ** order])
        x = np.linalg.lstsq(a, v[-n:], rcond=None)[0]
        return float(x[0]), float(np.max(np.abs(a @ x - v[-n:])))

    n = ASYMPTOTIC_LEVELS
    v_inf, resid = fixed(n)
    try:
        v_free, p_obs = richardson(h[-n:], v[-n:])
        free = abs(v_free - v_inf)
    except ConvergenceError:   # not monotone: no rate; the spread of the levels bounds it
        p_obs, free = float("nan"), float(np.max(np.abs(v[-n:] - v[-1])))
    added = abs(fixed(n + 1)[0] - v_inf) if h.size > n else 0.0
    return LimitFit(v_inf, float(p_obs), FIT_SAFETY * max(resid, free, added), resid,
                    "expected order, three finest levels", error_residual=resid,
                    error_free_order=free, error_added_level=added)


def reference_fit(h, v, order: float) -> LimitFit:
    """The mesh limit a dataset reports: :func:`asymptotic_fit` at the expected ``order``
    when the finest three levels show that order (observed within :data:`ORDER_TOL`: the
    asymptotic range), else -- a pre-asymptotic sequence -- :func:`convergence_fit` with a
    free rate over all levels and the expected-order bound on its error (``kind``
    ``"free rate, all levels (pre-asymptotic)"``). ``p`` is the observed order of the finest
    three."""
    fit = asymptotic_fit(h, v, order)
    if abs(fit.p - order) <= ORDER_TOL:
        return fit
    free = convergence_fit(h, v, expected_order=order)
    return replace(free, p=fit.p, kind="free rate, all levels (pre-asymptotic)")


def level_fit(h, v, *, spread_if_not_monotone: bool = True) -> LimitFit:
    """The limit of any number of levels: :func:`convergence_fit` with three or more;
    with two, the finest value and its change from the previous one as the error; with
    one, the finest value and a NaN error. Three or more levels that do not converge
    monotonically (``ConvergenceError``) give, with ``spread_if_not_monotone``, the finest
    value, no rate and the largest distance of a level from it as the error; without it
    the error propagates."""
    h, v = np.asarray(h, float), np.asarray(v, float)
    if h.size != v.size or h.size < 1:
        raise ValueError(f"level_fit needs as many levels as values (>= 1), got {h.size} "
                         f"and {v.size}")
    if h.size >= 3:
        try:
            return convergence_fit(h, v)
        except ConvergenceError:
            if not spread_if_not_monotone:
                raise
            return LimitFit(float(v[-1]), float("nan"), float(np.max(np.abs(v - v[-1]))),
                            0.0, "finest level, spread of the levels (not monotone)")
    err = float(abs(v[-1] - v[-2])) if h.size == 2 else float("nan")
    return LimitFit(float(v[-1]), float("nan"), err, 0.0, "finest level, last change")


@dataclass(frozen=True)
class GCI:
    """Roache's grid convergence index of the finest level.

    ``v_fine`` the finest value; ``v_inf`` the Richardson limit at the order used;
    ``p_observed`` the three-level order (NaN with two levels or a non-monotone triple);
    ``p`` the order used; ``safety`` the factor (1.25 or 3); ``ratio`` the refinement ratio
    h_coarse / h_fine of the two finest levels; ``gci`` the error band of the finest value,
    ``safety |v_fine - v_coarse| / (ratio^p - 1)``; ``gci_relative`` it divided by
    ``|v_fine|``; ``reason`` why this factor."""

    v_fine: float
    v_inf: float
    p_observed: float
    p: float
    safety: float
    ratio: float
    gci: float
    gci_relative: float
    reason: str


def gci(h, v, theoretical_order: float | None = None, *,
        order_tol: float = ORDER_TOL) -> GCI:
    """Roache's grid convergence index of the finest of the levels ``h`` (decreasing) with
    values ``v``.

    With three or more levels the observed order is the three-point order of the finest
    three (:func:`richardson`; refinement ratios need not be constant). It is used with the
    safety factor :data:`GCI_SAFETY_OBSERVED` (1.25) when no ``theoretical_order`` is given
    or when it lies within ``order_tol`` of it; otherwise (observed order off, the triple
    not monotone, or two levels) the ``theoretical_order`` is used with
    ``GCI_SAFETY_THEORETICAL`` (3). ConvergenceError when neither order is available
    (two levels or a non-monotone triple without a theoretical order).
    """
    h, v = np.asarray(h, float), np.asarray(v, float)
    if h.size != v.size or h.size < 2:
        raise ValueError(f"gci needs >= 2 levels with a value each, got {h.size} and "
                         f"{v.size}")
    if not np.all(np.diff(h) < 0) or not np.all(h > 0):
        raise ValueError(f"gci needs positive, strictly decreasing levels h, got {h.tolist()}")
    if theoretical_order is not None and not (math.isfinite(theoretical_order)
                                              and theoretical_order > 0):
        raise ValueError(f"theoretical_order = {theoretical_order!r} must be > 0")
    p_obs = float("nan")
    if h.size >= 3:
        try:
            p_obs = richardson(h, v).p
        except ConvergenceError:
            p_obs = float("nan")
    if math.isfinite(p_obs) and (theoretical_order is None
                                 or abs(p_obs - theoretical_order) <= order_tol):
        p, safety, reason = p_obs, GCI_SAFETY_OBSERVED, "observed order (three levels)"
    elif theoretical_order is not None:
        p, safety = float(theoretical_order), GCI_SAFETY_THEORETICAL
        reason = ("theoretical order: two levels" if h.size == 2 else
                  "theoretical order: the observed order is off it" if math.isfinite(p_obs)
                  else "theoretical order: the finest three levels are not monotone")
    else:
        raise ConvergenceError(f"gci: no order: levels {v.tolist()} at h = {h.tolist()} give "
                               "no observed order and no theoretical order is given")
    r = float(h[-2] / h[-1])
    change = float(v[-1] - v[-2])
    band = safety * abs(change) / (r**p - 1.0)
    v_inf = float(v[-1] + change / (r**p - 1.0))
    rel = band / abs(v[-1]) if v[-1] != 0 else float("inf")
    return GCI(float(v[-1]), v_inf, p_obs, float(p), safety, r, float(band), float(rel),
               reason)


@dataclass(frozen=True)
class PGradingEstimate:
    """The converged value of a p- and grading-sequence and its error estimate.

    ``value`` the value on the top discretisation (highest order, then most layers);
    ``p_change`` its change from the order below at the same grading; ``grading_change``
    its change from the next coarser grading at the top order (0 when the plan has none);
    ``safety_factor`` Roache's factor of the p-sequence at the top grading
    (:func:`gci_safety`); ``error`` ``safety_factor x max(p_change, grading_change)``, at
    least the ``floor`` the estimate was asked for (what each value is reproducible to).
    Arrays over the leading axes of the values (floats for a single sequence); NaN where a
    value the estimate uses is NaN."""

    value: np.ndarray | float
    error: np.ndarray | float
    p_change: np.ndarray | float
    grading_change: np.ndarray | float
    safety_factor: float


def _p_grading_top(discs) -> tuple[int, int, int | None]:
    """Indices into the plan ``discs`` (``(order, layers)`` pairs) of the top
    discretisation (highest order, then most layers), of the order below it at the same
    grading, and of the next coarser grading at the top order (None when the plan has
    none). ValueError when the plan has no lower order at the top grading."""
    discs = [(int(p), int(L)) for p, L in discs]
    require(len(set(discs)) == len(discs) and len(discs) >= 2,
            f"discs must be >= 2 distinct (order, layers) pairs, got {discs}")
    p_top = max(p for p, _ in discs)
    l_top = max(L for p, L in discs if p == p_top)
    i_top = discs.index((p_top, l_top))
    lower = [p for p, L in discs if L == l_top and p < p_top]
    if not lower:
        raise ValueError(f"converged: the plan {discs} has no lower order at {l_top} layers")
    i_p = discs.index((max(lower), l_top))
    coarser = [L for p, L in discs if p == p_top and L < l_top]
    i_l = discs.index((p_top, max(coarser))) if coarser else None
    return i_top, i_p, i_l


def p_grading_safety(discs) -> float:
    """Roache's safety factor of the p-sequence at the top grading of the plan ``discs``
    (:func:`gci_safety` of its number of orders: 1.25 with >= 3, else 3)."""
    discs = [(int(p), int(L)) for p, L in discs]
    l_top = max(L for p, L in discs if p == max(q for q, _ in discs))
    return gci_safety(len({p for p, L in discs if L == l_top}))


def p_grading_estimate(values, discs, *, floor: float = 0.0) -> PGradingEstimate:
    """The converged value of ``values[..., k]``, computed on the discretisations
    ``discs[k] = (order, layers)`` of a p- and grading-sequence, and its error estimate
    (:class:`PGradingEstimate`): the value on the top discretisation, the larger of the
    last p-step and the last grading change times Roache's safety factor
    (:func:`p_grading_safety`), at least ``floor`` (>= 0).

    Regular p-convergence makes the p-step an upper bound of the remaining p-error to
    higher order; the grading change bounds what the geometric grading towards a singular
    corner leaves; the safety factor covers an unobserved rate (3 with two orders)."""
    x = np.asarray(values, float)
    discs = list(discs)
    require(x.ndim >= 1 and x.shape[-1] == len(discs),
            f"values must have a last axis of len(discs) = {len(discs)}, got shape {x.shape}")
    floor = float(floor)
    require(math.isfinite(floor) and floor >= 0.0, f"floor = {floor!r} must be finite and >= 0")
    i_top, i_p, i_l = _p_grading_top(discs)
    dp = np.abs(x[..., i_top] - x[..., i_p])
    dl = np.abs(x[..., i_top] - x[..., i_l]) if i_l is not None else np.zeros_like(dp)
    fs = p_grading_safety(discs)
    err = np.maximum(fs * np.maximum(dp, dl), floor)
    if x.ndim == 1:
        return PGradingEstimate(float(x[i_top]), float(err), float(dp), float(dl), fs)
    return PGradingEstimate(x[..., i_top], err, dp, dl, fs)


def two_term_limits(h, v, q1: float, correction: float = 0.0) -> dict[float, float]:
    """What a single-term fit's assumption costs: the limit of the sequence ``v(h)`` by the
    least-squares two-term expansion v + C1 h^q1 + C2 h^q on its :data:`TWO_TERM_LEVELS`
    finest levels (the last ones), for each second exponent q of :data:`SECOND_EXPONENTS`,
    plus ``correction`` (a known offset of every limit, such as a separately fitted layer
    correction): ``{q: limit}``. The spread over q is the uncertainty a single-term fit
    hides when the second term's exponent is unknown. ValueError when ``h`` and ``v``
    differ in length or hold fewer than :data:`TWO_TERM_LEVELS` levels."""
    h, v = np.asarray(h, float), np.asarray(v, float)
    require(h.shape == v.shape and h.ndim == 1,
            f"h and v must be 1D of one length, got shapes {h.shape} and {v.shape}")
    require(len(h) >= TWO_TERM_LEVELS,
            f"h must hold at least {TWO_TERM_LEVELS} levels, got {len(h)}")
    h, v = h[-TWO_TERM_LEVELS:], v[-TWO_TERM_LEVELS:]
    out = {}
    for q in SECOND_EXPONENTS:
        A = np.column_stack([np.ones_like(h), h**q1, h**q])
        out[q] = float(np.linalg.lstsq(A, v, rcond=None)[0][0]) + correction
    return out


class LogLogFit(NamedTuple):
    """The least-squares line ``log|e| = order log h + intercept`` (:func:`loglog_order`)."""

    order: float
    intercept: float


def loglog_order(h, e) -> LogLogFit:
    """The observed order of a sequence of errors ``e(h) ~ C h^p`` (``e`` known: the
    difference from an exact or reference value, a remainder, a jump): the least-squares
    slope of ``log|e|`` against ``log h`` over every level, and its intercept. ``h`` may
    be any positive parameter (an element count gives minus the order). ValueError naming
    the argument when ``h`` and ``e`` are not 1D of one length >= 2, ``h`` is not finite
    and > 0 with distinct values, or an error is zero or not finite."""
    h, e = np.asarray(h, float), np.asarray(e, float)
    require(h.shape == e.shape and h.ndim == 1 and h.size >= 2,
            f"h and e must be 1D of one length >= 2, got shapes {h.shape} and {e.shape}")
    require(bool(np.all(np.isfinite(h)) and np.all(h > 0)),
            f"h must be finite and > 0, got {h.tolist()}")
    require(np.unique(h).size == h.size, f"h must be distinct, got {h.tolist()}")
    require(bool(np.all(np.isfinite(e)) and np.all(e != 0)),
            f"e must be finite and nonzero (log-log fit), got {e.tolist()}")
    slope, intercept = np.polyfit(np.log(h), np.log(np.abs(e)), 1)
    return LogLogFit(float(slope), float(intercept))
