"""The reference values of a problem at a user's points, with their tolerances
(:func:`reference_at`), and all of them as plain data (:func:`reference_json`, what
``debench problems ID --json`` prints).

Selector coordinates are matched to the stored grid (:func:`grid_index`). Curves are
interpolated with a cubic spline in the abscissa (in its logarithm for
``along_scale = "log"``), piece by piece between gaps (NaN: no root, inadmissible state)
and jumps (a root number shifting as a root enters the stretch window; the pieces of
:func:`curve_pieces`); points in a gap, on a jump or outside the curve are rejected with
``ValueError`` naming the curve. The interpolation error at a point is estimated as the
distance between that spline and the spline through every other grid point (for a
resolved smooth curve the O(h^4) error of the coarse spline is about 16 times that of the
full one, so the estimate is conservative) and added to the tolerance; a stored grid point
carries none. A point a round-off (:data:`COORD_MATCH_RTOL`, relative) from a stored one
where no spline reaches (beyond an end of a piece, a curve of a single stored point) is
that stored point, with the change of the curve over that distance added to the
tolerance. A curve with a square-root end is splined in its square
(``interpolate_power = 2``), one with poles in its product with a weight that removes
them (``interpolate_weight``).

The matching, the pieces and the splined values are shared with
:mod:`debench.reference.problems_coverage`, so coverage asks for exactly the curves this
module interpolates.
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from debench.reference import confirmations
from debench.reference.problems import Problem, ProblemError, Quantity, quantity_dataset
from scipy.interpolate import CubicSpline

#: relative tolerance for matching a user's coordinate with a stored one: a selector
#: (lamP = 1.25) with its grid value, and an abscissa (kH) that no piece of the curve
#: covers (just beyond its ends, beside a gap or on a jump of the root numbering) with the
#: stored point at that end. Users' coordinates differ from the stored ones by rounding
#: to 12 significant digits (<= 5e-12), unit conversion (kH in %: a few 1e-16) or a grid
#: computed another way (0.01 * 2000**(i/80) for numpy.geomspace: a few ulp); 1e-9 is far
#: above all of these and far below the closest stored spacing (1.2e-3 relative, the
#: voltage-stretch curves; 1.9e-2 for kH)
COORD_MATCH_RTOL = 1e-9
#: an abscissa within this relative distance of a stored grid point takes the stored value
#: (no interpolation error): a few ulp, so only the grid printed by ``--json`` (17
#: significant digits, which round-trip exactly) and its round-off qualify; a point
#: farther off inside a piece of the curve is interpolated (at a square-root end a
#: distance of 1e-10 changes the value by 1e-5)
NODE_MATCH_RTOL = 1e-15


def _show(x) -> str:
    """A number as its shortest round-trip text (``repr`` of a plain float), so that a
    message shows by how much it differs from a limit."""
    return repr(float(x))


def _shown(xs) -> str:
    """The first three of ``xs`` as :func:`_show` numbers in brackets."""
    return "[" + ", ".join(_show(x) for x in np.ravel(xs)[:3]) + "]"


def _function(q: Quantity):
    module, _, name = q.function.partition(":")
    fn = getattr(importlib.import_module(module), name)
    return lambda x: np.asarray(fn(np.asarray(x, dtype=float), **q.function_args), float)



def _discretisation_error(ds, var, f: Mapping[str, Any]):
    """The discretisation error a dataset states for ``var``: ``{error = NAME}`` names a
    variable holding the error estimate; ``{variable, dim, index}`` bounds it by the
    distance of ``var`` from that level of ``variable`` (e.g. the finest mesh)."""
    if "error" in f:
        return np.abs(ds[f["error"]])
    fine = ds[f["variable"]].isel({f["dim"]: int(f["index"])})
    return np.abs(var - fine)



def grid_index(values: np.ndarray, wanted: Any, name: str) -> int:
    """Index of ``wanted`` in a coordinate (exact for text, COORD_MATCH_RTOL for numbers).

    ``values``: the stored grid of the coordinate ``name``; ``ValueError`` naming the grid
    when ``wanted`` is not on it exactly once, or is not a number for a numeric grid.
    """
    wanted = wanted.item() if isinstance(wanted, np.generic) else wanted
    if values.dtype.kind in "fiu":
        try:
            w = float(wanted)
        except (TypeError, ValueError):
            raise ValueError(f"coordinate {name} must be numeric, got {wanted!r}") from None
        hit = np.nonzero(np.isclose(values, w, rtol=COORD_MATCH_RTOL, atol=0.0))[0]
    else:
        hit = np.nonzero(values.astype(str) == str(wanted))[0]
    if hit.size != 1:
        raise ValueError(f"coordinate {name} = {wanted!r} is not on the reference grid; "
                         f"choose from {values.tolist()}")
    return int(hit[0])


@dataclass(frozen=True)
class Reference:
    """Reference values and tolerances at the user's points."""

    value: np.ndarray
    tolerance: np.ndarray
    interpolation: np.ndarray


def interpolation_weight(q: Quantity, sel_values: Mapping[str, Any]):
    """The interpolation weight w(x) of ``q`` at the selected curve (None: no weight).

    ``sel_values``: the selector values of the curve (name -> grid value); those the
    spec's ``interpolate_weight.selectors`` names are passed to the weight function with
    its ``args``.
    """
    if not q.interpolate_weight:
        return None
    module, _, name = q.interpolate_weight["function"].partition(":")
    fn = getattr(importlib.import_module(module), name)
    kw = {**q.interpolate_weight.get("args", {}),
          **{k: float(sel_values[k]) for k in q.interpolate_weight.get("selectors", ())}}
    return lambda x: np.asarray(fn(np.asarray(x, dtype=float), **kw), dtype=float)


#: an interval of a stored curve whose change exceeds this many times the larger change of
#: its two neighbours is a jump, not a resolved part of the curve: on these grids the
#: changes of neighbouring intervals of a smooth curve differ by a factor <= 3 (square-root
#: ends and turning points included); a root number that shifts because a root enters or
#: leaves the stretch window changes by 10-1000 times more
JUMP_FACTOR = 20.0
#: ... and exceeds this fraction of the curve's magnitude (round-off on flat parts is no jump)
JUMP_FLOOR = 1e-6


def spline_values(x, y, power: float = 1.0, weight=None):
    """The values a curve is splined in: ``y**power * weight(x)`` (``weight`` None: 1).

    Interpolation and coverage split these values, not ``y``, into
    :func:`curve_pieces`."""
    v = y**power
    if weight is not None:
        v = v * weight(x)
    return v


def curve_pieces(t: np.ndarray, v: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) indices of the runs of finite ``v`` (sorted abscissa ``t``) that hold
    no jump (:data:`JUMP_FACTOR`): the pieces a spline may cover.

    The pieces are disjoint and in order; a NaN (in ``t`` or ``v``) ends a piece and
    belongs to none, and a jump ends a piece at its left point, the next starting at its
    right one. A piece may be a single point."""
    ok = np.isfinite(v) & np.isfinite(t)
    d = np.abs(np.diff(v))
    nb = np.full(d.shape, np.nan)
    if d.size > 1:
        nb[1:] = d[:-1]
        nb[:-1] = np.fmax(nb[:-1], d[1:])
    scale = np.nanmax(np.abs(v[ok])) if ok.any() else 0.0
    with np.errstate(invalid="ignore"):
        jump = (d > JUMP_FACTOR * np.nan_to_num(nb, nan=np.inf)) & (d > JUMP_FLOOR * scale)
    out, start = [], None
    for k in range(v.size):
        if not ok[k]:
            if start is not None:
                out.append((start, k - 1))
            start = None
            continue
        if start is None:
            start = k
        if k < v.size - 1 and jump[k]:
            out.append((start, k))
            start = None
    if start is not None:
        out.append((start, v.size - 1))
    return out


def _curve_at(x: np.ndarray, y: np.ndarray, xq: np.ndarray, name: str, log: bool,
              power: float = 1.0, weight=None):
    """Cubic-spline value and its error estimate (distance to the half-grid spline).

    ``power`` p: interpolate ``y**p`` (a curve with a square-root end, such as Phibar near
    Phibar = 0, is smooth in Phibar^2), then return ``(.)**(1/p)``. ``weight`` w(x):
    interpolate ``y**p w`` (smooth where y^p has poles), then divide by w(xq). Each piece
    of the curve (:func:`curve_pieces`: between gaps and jumps) has its own spline. A
    point within :data:`COORD_MATCH_RTOL` of a stored point that no spline covers (beyond
    an end, beside a gap, on a jump, on a piece too short to spline, or a curve of one
    point) is that stored point; any other point in a gap, on a jump or outside the finite
    range is refused.
    """
    order = np.argsort(x)
    x, y = x[order], y[order]
    finite = np.isfinite(x)
    x, y = x[finite], y[finite]
    ok = np.isfinite(y)
    if not ok.any():
        raise ValueError(f"the reference curve has no value along {name}")
    xs = x[ok]
    lo, hi = xs.min(), xs.max()
    # the stored point nearest to each user point, and whether it is that point
    j = np.clip(np.searchsorted(xs, xq), 1, max(xs.size - 1, 1))
    j = np.where(np.abs(xq - xs[j - 1]) <= np.abs(xq - xs[np.minimum(j, xs.size - 1)]),
                 j - 1, np.minimum(j, xs.size - 1))
    dist = np.abs(xq - xs[j])
    near = dist <= COORD_MATCH_RTOL * np.abs(xs[j])
    outside = ((xq < lo) | (xq > hi) | ~np.isfinite(xq)) & ~near
    if outside.any():
        raise ValueError(f"{name} must lie in the reference range [{_show(lo)}, "
                         f"{_show(hi)}]; got {_shown(xq[outside])}")
    t = np.log(x) if log else x
    tq = np.log(xq) if log else xq
    v = spline_values(x, y, power, weight)
    pieces = curve_pieces(t, v)
    k = np.flatnonzero(ok)[j]             # the nearest stored point, indexed in x
    node = near & (dist <= NODE_MATCH_RTOL * np.abs(xs[j]))
    value, error = np.full(xq.size, np.nan), np.zeros(xq.size)
    value[node] = y[k[node]]
    todo = ~node
    for a, b in pieces:
        inside = todo & (xq >= x[a]) & (xq <= x[b])
        if not inside.any() or a == b:
            continue
        if b - a + 1 < 4:
            far = inside & ~near    # the others are stored points (below)
            if far.any():
                raise ValueError(f"{name} = {_shown(xq[far])} lies on a piece of the "
                                 f"reference curve too short to interpolate with an "
                                 f"error estimate ({b - a + 1} points)")
            continue
        tt, vv = t[a:b + 1], v[a:b + 1]
        half = np.unique(np.r_[np.arange(0, tt.size, 2), tt.size - 1])
        cubic = CubicSpline(tt, vv)(tq[inside])
        coarse = CubicSpline(tt[half], vv[half])(tq[inside])
        if weight is not None:
            wq = weight(xq[inside])
            cubic, coarse = cubic / wq, coarse / wq
        if power != 1.0:
            cubic, coarse = (np.maximum(cubic, 0.0) ** (1 / power),
                             np.maximum(coarse, 0.0) ** (1 / power))
        value[inside], error[inside] = cubic, np.abs(cubic - coarse)
        todo &= ~inside
    # what no spline covers but lies a round-off (COORD_MATCH_RTOL) from a stored point
    # is that point: its stored value, with the change of the curve over that distance
    # (the slope of the stored interval beside it, within its piece, on the point's side
    # if there is one) as the error estimate; a piece of one point has no slope: none
    snap = todo & near
    for i in np.flatnonzero(snap):
        n = k[i]
        value[i] = y[n]
        a, b = next(((a, b) for a, b in pieces if a <= n <= b), (n, n))
        if b > a:
            m = n + 1 if n == a or (xq[i] > x[n] and n < b) else n - 1
            dt = abs(np.log(xq[i] / x[n])) if log else abs(xq[i] - x[n])
            error[i] = abs((y[m] - y[n]) / (t[m] - t[n])) * dt
    todo &= ~snap
    if todo.any():
        raise ValueError(f"{name} = {_shown(xq[todo])} falls in a gap of the reference "
                         "curve (no reference value there: no root or inadmissible state) "
                         "or on a jump of it (a root enters or leaves the stretch window "
                         "and the root numbers shift)")
    return value, error


def describe_curve(chosen: Mapping[str, Any]) -> str:
    """``xi = 5, Dhat = 5, root = 0``: the curve a message is about (``chosen``: selector
    name -> grid value; "the curve" when there are no selectors)."""
    def show(v):
        v = v.item() if isinstance(v, np.generic) else v
        return f"{v:g}" if isinstance(v, float) else str(v)
    return ", ".join(f"{k} = {show(v)}" for k, v in chosen.items()) or "the curve"


def reference_at(problem: Problem, quantity: Quantity,
                 coords: Mapping[str, Any]) -> Reference:
    """Reference values, tolerances (stated accuracy) and interpolation error estimates at
    the user's points; ``coords`` maps coordinate names to scalars or arrays (broadcast)."""
    names = quantity.coordinates
    given = {**quantity.defaults, **dict(coords)}
    missing = [n for n in names if n not in given]
    if missing:
        raise ValueError(f"coords lack {missing} (problem {problem.id}, quantity "
                         f"{quantity.name} needs {list(names)})")
    extra = sorted(set(coords) - set(names))
    if extra:
        raise ValueError(f"coords has unknown names {extra}; {quantity.name} takes {list(names)}")
    arrays = np.broadcast_arrays(*[np.asarray(given[n]) for n in names])
    arrays = [a.ravel() for a in arrays]
    n = arrays[0].size if arrays else 1
    if quantity.source == "function":
        xq = np.asarray(arrays[-1], dtype=float)
        lo, hi = float(quantity.grid["start"]), float(quantity.grid["stop"])
        # a round-off beyond an end of the range is that end (COORD_MATCH_RTOL)
        xq = np.where(np.isclose(xq, lo, rtol=COORD_MATCH_RTOL, atol=0.0), np.maximum(xq, lo),
                      np.where(np.isclose(xq, hi, rtol=COORD_MATCH_RTOL, atol=0.0),
                               np.minimum(xq, hi), xq))
        outside = ~((xq >= lo) & (xq <= hi))
        if outside.any():
            raise ValueError(f"{quantity.along} must lie in the reference range "
                             f"[{_show(lo)}, {_show(hi)}] (problem {problem.id}); got "
                             f"{_shown(xq[outside])}")
        ref = _function(quantity)(xq)
        zeros = np.zeros(n)
        return Reference(ref, quantity.accuracy.tolerance(ref), zeros)
    ds = quantity_dataset(quantity)
    var = ds[quantity.variable]
    disc_var = None
    if quantity.discretisation_from:
        disc_var = _discretisation_error(ds, var, quantity.discretisation_from)
    value, interp, disc = np.empty(n), np.zeros(n), np.zeros(n)
    keys = list(zip(*arrays[:len(quantity.select)], strict=True)) if quantity.select else [()] * n
    groups: dict[tuple, list[int]] = {}
    for i, k in enumerate(keys):
        groups.setdefault(tuple(str(v) for v in k), []).append(i)
    for _, idx in groups.items():
        first = idx[0]
        sel = {s: grid_index(ds[s].values, arrays[j][first], s)
               for j, s in enumerate(quantity.select)}
        y = var.isel(sel)
        d = disc_var.isel(sel) if disc_var is not None else None
        if quantity.along is None:
            if y.ndim:
                raise ProblemError(f"{problem.id}:{quantity.name}: selectors leave dims "
                                   f"{y.dims}; the spec must select all of them")
            value[idx] = float(y)
            if d is not None:
                disc[idx] = float(d)
        else:
            x = ds[quantity.along]
            x = x.isel({k: v for k, v in sel.items() if k in x.dims})
            if x.ndim != 1 or y.ndim != 1:
                raise ProblemError(f"{problem.id}:{quantity.name}: curve is not 1-D after "
                                   f"selection ({y.dims})")
            xq = np.asarray(arrays[-1][idx], dtype=float)
            chosen = {s: ds[s].values[i] for s, i in sel.items()}
            try:
                value[idx], interp[idx] = _curve_at(
                    np.asarray(x.values, float), np.asarray(y.values, float), xq,
                    quantity.along, quantity.along_scale == "log",
                    quantity.interpolate_power, interpolation_weight(quantity, chosen))
            except ValueError as exc:
                raise ValueError(f"{describe_curve(chosen)}: {exc}") from None
    tol = quantity.accuracy.tolerance(value, quantity.accuracy.discretisation + disc)
    return Reference(value, tol + interp, interp)


def reference_json(problem: Problem) -> dict[str, Any]:
    """Spec plus, per quantity, the reference coordinates, values, units, accuracy and
    confirmation (the spec's records with what they measured:
    ``debench.reference.confirmations.records``)."""

    def clean(a):
        a = np.asarray(a)
        if a.dtype.kind == "f":
            return np.where(np.isfinite(a), a, None).tolist()
        return a.astype(str).tolist() if a.dtype.kind in "US" else a.tolist()


    out = {"spec": problem.spec(), "reference": {}}
    for q in problem.quantities:
        item: dict[str, Any] = {"units": q.units, "long_name": q.long_name,
                                "accuracy": q.accuracy.as_json(),
                                "confirmation": confirmations.records(problem.id, q)}
        if q.source == "function":
            x = np.linspace(q.grid["start"], q.grid["stop"], int(q.grid["num"]))
            item.update(dims=[q.along], coords={q.along: clean(x)},
                        values=clean(_function(q)(x)))
        else:
            ds = quantity_dataset(q)
            var = ds[q.variable]
            item.update(dims=list(var.dims),
                        coords={d: clean(ds[d].values) for d in var.dims},
                        values=clean(var.values))
            if q.along:
                a = ds[q.along]
                item["along"] = {"name": q.along, "units": q.along_units,
                                 "dims": list(a.dims), "values": clean(a.values)}
            if q.discretisation_from:
                item["discretisation_error"] = clean(
                    _discretisation_error(ds, var, q.discretisation_from).values)
        out["reference"][q.name] = item
    return out

