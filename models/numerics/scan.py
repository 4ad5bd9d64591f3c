"""Sign-change scans that do not lose a root to its neighbour: adaptive refinement.

A scan of f on a grid brackets a zero only where f changes sign across one grid interval;
two zeros in one interval cancel. Such pairs occur where a function has a spurious zero
beside a genuine one (the boundary determinant of
:func:`debench.models.plate.inplane.det_function`: a bifurcation beside a zero of its
normalisation) or two genuine zeros close together (the two close modes of a thick plate,
a pair ~exp(-kH) apart).

The remedy needs a measure m >= 0 of nearness to a zero that the grid samples: |f| for a
plain function, or, for that determinant, the singularity ratio sigma_min/sigma_max of the
boundary matrix with unit columns (:func:`debench.models.plate.inplane.boundary_singularity`),
which is free of the spurious zeros (they scale a column, which the normalisation undoes).
Near a simple zero m is V-shaped, m ~ c |x - x0|; near a minimum that is not a zero it is
smooth, m ~ m0 + k (x - xm)^2. The scan is refined where m has a local minimum on the sampled
points (ends of the window included, against their one neighbour): both intervals beside it
are halved (:func:`refinement_points`), round after round, until

* the minimum is *resolved*: every neighbour exceeds it by at most the fraction
  :data:`RESOLVED` (a smooth minimum away from zero: m0 > 0 is sampled finely enough), or
* the intervals beside it are narrower than ``width`` x (a zero of m, or a tangency, which
  does not resolve: on a V with equal spacings h beside the sampled minimum, at distance
  delta <= h/2 from the zero, the neighbour away from the zero is at h + delta >= 3 delta).

The sign changes of f on the refined points (:func:`sign_change_brackets`, also the bracket
test of every grid scan, :func:`debench.models.numerics.roots.scan_roots`) are the brackets;
a zero of f exactly at a sampled point brackets both intervals beside it. A tangency (even
multiplicity: f touches zero without changing sign) gives no bracket: it is located by the
refinement, but it is no crossing. :func:`scan_brackets` runs the whole scan for one
function; :func:`refine_samples` runs the same rounds for many scans at once (one call of
the function per round for all of them, as
:func:`debench.models.plate.inplane.critical_stretches_det_many` does).
"""
from __future__ import annotations

import numpy as np
from debench.models import validation as v
from debench.models.errors import ConvergenceError

#: a local minimum of the measure is resolved (not refined further) when each neighbour
#: exceeds it by at most this fraction. Smooth minima resolve within a few halvings
#: (m0 + k h^2 <= 1.25 m0 once h <= sqrt(m0 / 4k)). A V-shaped zero would need spacings
#: beside its sampled minimum 9x apart (h1 <= delta/4 on the far side, h2 <= 2.25 delta);
#: halving both sides keeps them <= 4x apart (measured beside every minimum below 1e-6 in
#: the full sweep). The square-root cusp of two colliding characteristic roots may resolve
#: near the width; it is no bifurcation (COLLISION_TOL of the determinant scan)
RESOLVED = 0.25
#: refinement rounds of one scan (each halves the intervals beside every unresolved
#: minimum): from a grid interval of 1.3 % to a width of 1e-8 takes 21; the limit only
#: guards against a measure that is minimal everywhere (a plateau)
MAX_ROUNDS = 80


def _local_minima(m, usable, f=None):
    """Indices of the unresolved local minima of ``m`` (NaN: not sampled) over the usable
    intervals (``usable[i]``: the interval (x[i], x[i + 1]) may be refined); with the
    sampled real function ``f``, minima at an end of an interval where it changes sign
    are resolved (a bracket holds the zero they approach)."""
    return np.flatnonzero(_minimum_mask(m, usable, f))


def _minimum_mask(m, usable, f=None):
    """:func:`_local_minima` as a mask along the last axis (rows of scans on one grid:
    ``m`` (..., n), ``usable`` and the sign changes of ``f`` (..., n - 1))."""
    mm = np.where(np.isnan(m), np.inf, m)
    inf = np.full(mm.shape[:-1] + (1,), np.inf)
    no = np.zeros(mm.shape[:-1] + (1,), bool)
    left = np.concatenate([inf, np.where(usable, mm[..., :-1], np.inf)], axis=-1)
    right = np.concatenate([np.where(usable, mm[..., 1:], np.inf), inf], axis=-1)
    has = np.concatenate([no, usable], axis=-1) | np.concatenate([usable, no], axis=-1)
    nb = np.maximum(np.where(np.isfinite(left), left, -np.inf),
                    np.where(np.isfinite(right), right, -np.inf))
    is_min = has & np.isfinite(mm) & (mm <= left) & (mm <= right)
    if f is not None:
        change = _change_mask(f, usable)
        is_min &= ~(np.concatenate([no, change], axis=-1)
                    | np.concatenate([change, no], axis=-1))
    return is_min & (nb > (1.0 + RESOLVED) * mm)


def _change_mask(f, usable):
    """Usable intervals along the last axis whose finite ends differ in sign or include
    a zero."""
    with np.errstate(invalid="ignore"):
        lo, hi = f[..., :-1], f[..., 1:]
        return (usable & np.isfinite(lo) & np.isfinite(hi)
                & ((lo == 0.0) | (hi == 0.0) | (np.sign(lo) != np.sign(hi))))


def _refinement_points(x, m, width, usable, f=None):
    """:func:`refinement_points` without the checks (``usable`` a boolean array)."""
    pts = []
    for i in _local_minima(m, usable, f):
        for j in (i - 1, i):
            if 0 <= j < len(x) - 1 and usable[j] and x[j + 1] - x[j] > width * abs(x[j + 1]):
                pts.append(0.5 * (x[j] + x[j + 1]))
    return np.unique(np.asarray(pts, float))


def refinement_points(x, m, *, width: float, usable=None) -> np.ndarray:
    """The points one refinement round adds to a scan (sorted, possibly none).

    ``x``: the sampled abscissae (strictly increasing, finite); ``m``: the measure of
    nearness to a zero at each (>= 0; NaN where not sampled, never a minimum); ``width``:
    relative width below which an interval is not halved (interval x[j + 1] - x[j] <=
    width |x[j + 1]|); ``usable``: per interval, whether it may be refined and its ends
    compared (default all). Returns the midpoints of the intervals beside every local
    minimum of ``m`` that is not resolved (:data:`RESOLVED`).
    """
    x, m, width, usable = _checked(x, m, width, usable)
    return _refinement_points(x, m, width, usable)


def _checked(x, m, width, usable):
    x = v.array("x", x)
    if x.ndim != 1 or x.size < 2 or not np.all(np.diff(x) > 0):
        raise ValueError(f"x must be a strictly increasing 1-D array of >= 2 points, got {x!r:.80}")
    m = _real_array("m", m)
    if m.shape != x.shape or np.any(m < 0) or np.any(np.isinf(m)):
        raise ValueError(f"m must have the shape of x with entries >= 0 or NaN, got {m!r:.80}")
    width = v.in_range("width", width, 0.0, 1.0, lo_open=True)
    if usable is None:
        usable = np.ones(x.size - 1, bool)
    usable = np.asarray(usable)
    if usable.dtype != bool or usable.shape != (x.size - 1,):
        raise ValueError(f"usable must be a boolean array of len(x) - 1 = {x.size - 1}, "
                         f"got {usable!r:.80}")
    return x, m, float(width), usable


def _sign_change_brackets(f, usable):
    """:func:`sign_change_brackets` without the checks."""
    return np.flatnonzero(_change_mask(f, usable))


def sign_change_brackets(x, f, *, usable=None) -> np.ndarray:
    """Indices i of the usable intervals (x[i], x[i + 1]) where the real ``f`` changes sign
    or vanishes at an end (so a zero at a sampled point brackets both intervals beside it;
    ``f`` NaN: not sampled, no bracket)."""
    x, _, _, usable = _checked(x, np.zeros(np.shape(x)), 0.5, usable)
    f = _real_array("f", f)
    if f.shape != x.shape:
        raise ValueError(f"f must have the shape of x {x.shape}, got {f.shape}")
    return _sign_change_brackets(f, usable)


def _real_array(name, a):
    """``a`` as a float array (NaN and inf kept for the caller to judge); TypeError when
    it is not a real numeric array."""
    if a is None or isinstance(a, str | bytes):
        raise TypeError(f"{name} must be a real array, got {a!r:.60}")
    try:
        a = np.asarray(a)
    except (ValueError, TypeError) as exc:
        raise TypeError(f"{name} must be a real array, got {a!r:.60}") from exc
    if a.dtype.kind not in "iuf":
        raise TypeError(f"{name} must be a real array, got dtype {a.dtype}")
    return a.astype(float)


def _merge(x, vals, new_x, new_vals):
    """The samples ``x`` (sorted) with ``vals`` (arrays along the last axis, one per
    sampled quantity) and the new ones merged, sorted by abscissa: ``(x, vals)``."""
    order = np.argsort(np.concatenate([x, new_x]), kind="stable")
    return (np.concatenate([x, new_x])[order],
            [np.concatenate([a, b], axis=-1)[..., order] for a, b in
             zip(vals, new_vals, strict=True)])


def refine_samples(evaluate, samples, *, width: float, bracketed_resolved: bool = False
                   ) -> None:
    """Refine several scans together, in place, round by round.

    ``samples``: a list, per scan, of ``[x, vals, m, usable]``: the sampled abscissae
    (strictly increasing), the sampled quantities (an array whose last axis runs along
    ``x``), the measure of nearness to a zero (NaN where not sampled) and the usable
    intervals (:func:`refinement_points`). ``evaluate(scan_index, points)`` returns
    ``(vals, m)`` at the points of every round (both arrays, last axis along the points;
    ``scan_index[i]`` the scan of ``points[i]``), so that one call serves all scans.
    Each round adds :func:`refinement_points` to every scan; the halves of a usable
    interval are usable. ConvergenceError when a round still adds points after
    :data:`MAX_ROUNDS` rounds.

    ``bracketed_resolved``: ``vals`` is the real function itself (1-D along ``x``), and a
    minimum at an end of an interval where it changes sign is not refined: the bracket
    holds the zero the minimum approaches, so only minima between samples of one sign (two
    zeros that may share an interval, or a smooth minimum) are refined. Much cheaper (a
    simple zero costs no halvings), it does not look for two more zeros in an interval
    beside a bracketed one.
    """
    if not callable(evaluate):
        raise TypeError(f"evaluate must be callable, got {evaluate!r:.60}")
    if not isinstance(samples, list) or not all(
            isinstance(s, list) and len(s) == 4 for s in samples):
        raise TypeError("samples must be a list of [x, vals, m, usable] lists")
    for s in samples:
        s[0], s[2], width, s[3] = _checked(s[0], s[2], width, s[3])
        s[1] = np.asarray(s[1])
        if s[1].shape[-1:] != s[0].shape:
            raise ValueError(f"vals must run along x on its last axis, got {s[1].shape}")
        if bracketed_resolved and s[1].ndim != 1:
            raise ValueError(f"bracketed_resolved needs vals of one function (1-D), got "
                             f"shape {s[1].shape}")
    _refine(evaluate, samples, width, bracketed_resolved)


def _refine(evaluate, samples, width, bracketed_resolved=False):
    """:func:`refine_samples` without the checks."""
    # a scan that added no points in a round is unchanged and adds none later
    active = list(range(len(samples)))
    for _ in range(MAX_ROUNDS):
        new = [np.zeros(0)] * len(samples)
        for k in active:
            x, f, m, usable = samples[k]
            new[k] = _refinement_points(x, m, width, usable, f if bracketed_resolved else None)
        active = [k for k in active if new[k].size]
        if not active:
            return
        which = np.concatenate([np.full(p.size, k) for k, p in enumerate(new)])
        vals, m = evaluate(which, np.concatenate(new))
        at = 0
        for k, p in enumerate(new):
            if p.size:
                x, val, mk, usable = samples[k]
                halved = np.searchsorted(x, p) - 1          # the interval each point halves
                x, (val, mk) = _merge(x, [val, mk], p, [vals[..., at:at + p.size],
                                                        m[at:at + p.size]])
                samples[k] = [x, val, mk, _split_usable(usable, halved)]
            at += p.size
    raise ConvergenceError(f"scan refinement did not settle in {MAX_ROUNDS} rounds")


def scan_brackets(evaluate, x, *, width: float, usable=None):
    """Refine the scan ``x`` of one function and bracket its sign changes.

    ``evaluate(points)`` returns ``(f, m)`` at an array of points: the real function and the
    measure of nearness to its zeros (``m = |f|`` will do). Refined by
    :func:`refine_samples` (the rounds of the determinant scans) until no unresolved
    minimum has an interval wider than ``width`` beside it. Returns ``(brackets, x, f, m)``:
    the brackets ``(a, b, f(a), f(b))`` of :func:`sign_change_brackets` and the refined
    samples.
    """
    if not callable(evaluate):
        raise TypeError(f"evaluate must be callable, got {evaluate!r:.60}")
    x, _, width, usable = _checked(x, np.zeros(np.shape(x)), width, usable)
    f, m = (_real_array("evaluate(x)", a) for a in evaluate(x))
    samples = [[x, f, m, usable]]
    _refine(lambda _, p: tuple(_real_array("evaluate(x)", a) for a in evaluate(p)),
            samples, width)
    x, f, m, usable = samples[0]
    return ([(x[i], x[i + 1], f[i], f[i + 1]) for i in _sign_change_brackets(f, usable)],
            x, f, m)


def grid_brackets(evaluate, x, f, *, width: float, usable=None):
    """The sign changes of many real functions sampled on one grid, refined where two
    zeros may share an interval: ``(scan, a, b, fa, fb)`` arrays, in scan order then along
    ``x``.

    ``x`` the grid (strictly increasing), ``f`` the samples (rows, n) (NaN: not sampled),
    ``usable`` (rows, n - 1) the intervals that may be refined and bracket (default: both
    ends finite). The measure is m = |f|; only rows with an unresolved minimum of |f|
    between samples of one sign are refined (:func:`refine_samples` with
    ``bracketed_resolved``, ``evaluate(scan_index, points)`` returning ``f`` at the points
    of every round), so a simple zero costs nothing beyond the grid. The brackets of the
    other rows come from the grid directly.
    """
    if not callable(evaluate):
        raise TypeError(f"evaluate must be callable, got {evaluate!r:.60}")
    x, _, width, _ = _checked(x, np.zeros(np.shape(x)), width, None)
    f = _real_array("f", f)
    if f.ndim != 2 or f.shape[1] != x.size:
        raise ValueError(f"f must have shape (rows, {x.size}), got {f.shape}")
    if usable is None:
        usable = np.isfinite(f[:, :-1]) & np.isfinite(f[:, 1:])
    usable = np.asarray(usable)
    if usable.dtype != bool or usable.shape != (f.shape[0], x.size - 1):
        raise ValueError(f"usable must be a boolean array of shape "
                         f"{(f.shape[0], x.size - 1)}, got {usable!r:.80}")
    wide = np.diff(x) > width * np.abs(x[1:])
    minima = _minimum_mask(np.abs(f), usable, f)
    # a minimum is refined when an interval beside it may be halved
    # (the intervals beside sample i are i - 1 and i)
    refine = np.flatnonzero(((minima[:, 1:] | minima[:, :-1]) & wide & usable).any(axis=1))
    out = []
    change = _change_mask(f, usable)
    change[refine] = False
    k, i = np.nonzero(change)
    out.append((k, x[i], x[i + 1], f[k, i], f[k, i + 1]))
    if refine.size:
        samples = [[x, f[r], np.abs(f[r]), usable[r]] for r in refine]

        def ev(which, p):
            vals = _real_array("evaluate(x)", evaluate(refine[which], p))
            return vals, np.abs(vals)

        _refine(ev, samples, width, bracketed_resolved=True)
        kk, *rest = _sample_brackets(samples)
        out.append((refine[kk], *rest))
    cols = [np.concatenate(c) for c in zip(*out, strict=True)]
    order = np.lexsort((cols[1], cols[0]))
    return tuple(c[order] for c in cols)


def _sample_brackets(samples):
    """The sign changes of refined scans ``[x, f, m, usable]`` of one real function each,
    as arrays ``(scan, a, b, fa, fb)`` (:func:`sign_change_brackets`, in scan order then
    along ``x``)."""
    out = [], [], [], [], []
    for k, (x, f, _, usable) in enumerate(samples):
        i = _sign_change_brackets(f, usable)
        for col, val in zip(out, (np.full(i.size, k), x[i], x[i + 1], f[i], f[i + 1]),
                            strict=True):
            col.append(val)
    return tuple(np.concatenate(col) for col in out)


def _split_usable(usable, halved):
    """``usable`` after the intervals ``halved`` (indices, sorted, distinct) are split in
    two: both halves inherit the interval's flag."""
    return np.insert(usable, np.asarray(halved) + 1, usable[np.asarray(halved, int)])


def grid_samples(grids, oks, evaluate):
    """``[x, vals, m, usable]`` of each scan (:func:`refine_samples`) on its grid
    ``grids[k]``, evaluated where ``oks[k]`` (NaN elsewhere; an interval is usable where
    both ends are), every scan's points in one call ``evaluate(which, x)`` (as in
    :func:`refine_samples`)."""
    which = np.concatenate([np.full(int(ok.sum()), k) for k, ok in enumerate(oks)])
    vals, m = evaluate(which, np.concatenate([g[ok] for g, ok in zip(grids, oks, strict=True)]))
    samples, at = [], 0
    for g, ok in zip(grids, oks, strict=True):
        n = int(ok.sum())
        d = np.full(vals.shape[:-1] + g.shape, np.nan, vals.dtype)
        mk = np.full(g.size, np.nan)
        d[..., ok], mk[ok] = vals[..., at:at + n], m[at:at + n]
        samples.append([g, d, mk, ok[:-1] & ok[1:]])
        at += n
    return samples
