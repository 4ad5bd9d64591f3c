"""Whether results cover the reference they address (:func:`coverage`, :class:`Coverage`)
and which coordinate tuples they repeat (:func:`duplicates`): what ``debench check`` and
:func:`debench.reference.comparison.compare` require before judging a results file as complete.

A curve counts as covered piece by piece, with the pieces and matching of
:mod:`debench.reference.problems_reference`, so what is required is what
:func:`~debench.reference.problems_reference.reference_at` can interpolate.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from debench.reference.problems import Problem, Quantity, quantity_dataset
from debench.reference.problems_reference import (
    curve_pieces,
    describe_curve,
    grid_index,
    interpolation_weight,
    spline_values,
)


class CoverageError(ValueError):
    """Results that do not cover the reference points they address (and did not declare
    partial coverage)."""


@dataclass(frozen=True)
class Coverage:
    """How much of the addressed reference a set of results covers.

    ``required``: the reference curves (or values) the results address: every grid value
    of a selector without a default, the values given (or the default) of a selector with
    one; ``covered``: those fully covered (a curve: on each finite stretch of the stored
    curve, the points span it and no gap between them, nor to its ends, exceeds the widest
    stored spacing there, in log for a log abscissa; a value: present). ``missing``:
    descriptions of the others (the first few).
    """

    declared: str
    required: int
    covered: int
    missing: tuple[str, ...]

    @property
    def complete(self) -> bool:
        return self.covered == self.required

    def describe(self) -> str:
        what = f"{self.covered}/{self.required} addressed reference curves or values covered"
        if self.complete:
            return f"coverage complete ({what})"
        head = "; ".join(self.missing[:3]) + (" ..." if len(self.missing) > 3 else "")
        return f"PARTIAL coverage ({self.declared}): {what}; not covered: {head}"


#: slack on "no gap wider than the widest stored spacing": relative round-off of the
#: user's printed abscissae (17 digits) is far below it, a skipped grid point far above
COVERAGE_GAP_SLACK = 1e-9


def _curve_covered(x: np.ndarray, y: np.ndarray, xq: np.ndarray, log: bool) -> str | None:
    """None if the points ``xq`` cover every piece of the curve (x, y) (values splined
    as ``y``; :func:`curve_pieces`: between gaps and jumps), else why."""
    order = np.argsort(x)
    x, y = x[order], y[order]
    t = np.log(x) if log else x
    tq = np.sort(np.log(xq) if log else xq)
    for a, b in curve_pieces(t, y):
        if b - a < 1:
            continue   # an isolated stored value: nothing to interpolate, not required
        seg = t[a:b + 1]
        gap = float(np.max(np.diff(seg))) * (1 + COVERAGE_GAP_SLACK)
        inside = tq[(tq >= seg[0] - gap) & (tq <= seg[-1] + gap)]
        pts = np.concatenate([[seg[0]], np.clip(inside, seg[0], seg[-1]), [seg[-1]]])
        widest = float(np.max(np.diff(pts)))
        if widest > gap:
            lo, hi = (np.exp(seg[[0, -1]]) if log else seg[[0, -1]])
            return (f"range [{lo:.6g}, {hi:.6g}] has a gap of {widest:.3g}"
                    f"{' in log' if log else ''} between your points (the reference "
                    f"spacing there is <= {gap:.3g})")
    return None


def coverage(problem: Problem, quantity: Quantity, coords: Mapping[str, Any], *,
             declared: str = "none") -> Coverage:
    """The :class:`Coverage` of results at ``coords`` (names -> arrays, as
    :func:`~debench.reference.problems_reference.reference_at`) of the reference of
    ``quantity``."""
    given = {**quantity.defaults, **dict(coords)}
    names = quantity.coordinates
    arrays = [np.ravel(a) for a in np.broadcast_arrays(*[np.asarray(given[n])
                                                         for n in names])]
    sel_arrays = dict(zip(quantity.select, arrays[:len(quantity.select)], strict=True))
    if quantity.source == "function":
        x = np.linspace(quantity.grid["start"], quantity.grid["stop"],
                        int(quantity.grid["num"]))
        why = _curve_covered(x, np.ones_like(x), np.asarray(arrays[-1], float),
                             quantity.along_scale == "log")
        return Coverage(declared, 1, int(why is None),
                        () if why is None else (f"{quantity.along}: {why}",))
    ds = quantity_dataset(quantity)
    var = ds[quantity.variable]
    choices = []
    for s in quantity.select:
        grid = ds[s].values
        if s in quantity.defaults:
            wanted = list(dict.fromkeys(np.asarray(sel_arrays[s]).tolist()))
            choices.append([grid_index(grid, w, s) for w in wanted])
        else:
            choices.append(list(range(grid.size)))
    required = covered = 0
    missing: list[str] = []
    # the user's points by grid combination (selector values matched as reference_at does)
    by_combo: dict[tuple, list[int]] = {}
    groups: dict[tuple, list[int]] = {}
    for i, k in enumerate(zip(*[sel_arrays[s] for s in quantity.select], strict=True)
                          if quantity.select else [()] * arrays[0].size):
        groups.setdefault(tuple(str(v) for v in k), []).append(i)
    for idx in groups.values():
        combo = tuple(grid_index(ds[s].values, sel_arrays[s][idx[0]], s) for s in quantity.select)
        by_combo.setdefault(combo, []).extend(idx)
    for combo in itertools.product(*choices):
        sel = dict(zip(quantity.select, combo, strict=True))
        y = np.asarray(var.isel(sel).values, float)
        if not np.isfinite(y).any():
            continue   # no reference value at all (e.g. a root number that never occurs)
        required += 1
        chosen = {s: ds[s].values[i] for s, i in sel.items()}
        mine = by_combo.get(tuple(combo), [])
        if quantity.along is None:
            if mine:
                covered += 1
            else:
                missing.append(describe_curve(chosen))
            continue
        x = ds[quantity.along].isel({k: v for k, v in sel.items()
                                     if k in ds[quantity.along].dims})
        xv = np.asarray(x.values, float)
        why = ("no points" if not mine else
               _curve_covered(xv, spline_values(xv, y, quantity.interpolate_power,
                                               interpolation_weight(quantity, chosen)),
                              np.asarray(arrays[-1], float)[mine],
                              quantity.along_scale == "log"))
        if why is None:
            covered += 1
        else:
            missing.append(f"{describe_curve(chosen)}: {why}")
    return Coverage(declared, required, covered, tuple(missing))


def duplicates(quantity: Quantity, coords: Mapping[str, Any]) -> list[str]:
    """Coordinate tuples that occur more than once in ``coords`` (described)."""
    given = {**quantity.defaults, **dict(coords)}
    names = quantity.coordinates
    arrays = [np.ravel(a) for a in np.broadcast_arrays(*[np.asarray(given[n])
                                                         for n in names])]
    seen: dict[tuple, int] = {}
    for row in zip(*arrays, strict=True):
        k = tuple(str(v) for v in row)
        seen[k] = seen.get(k, 0) + 1
    return [", ".join(f"{n} = {v}" for n, v in zip(names, k, strict=True)) + f" ({c} times)"
            for k, c in seen.items() if c > 1]
