"""Comparison of values with a reference problem, point by point: the judgement that
``debench check``, the peer submissions, the confirmations and :mod:`debench.testing`
(the users' entry point, which re-exports :func:`compare`) all apply.

:func:`compare` interpolates the verified reference of a problem to the given coordinates
where the quantity is a curve, and applies the accuracy the reference states (solver
tolerance + discretisation error + interpolation error estimate) or the caller's
tolerance, whichever is larger: a reference cannot be checked tighter than it is known.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from debench.reference import problems, problems_coverage, problems_reference

__all__ = ["Comparison", "Comparisons", "compare"]

#: rows of the worst points shown in a failure message
WORST_ROWS = 10


@dataclass(frozen=True)
class Comparison:
    """The outcome of comparing values with a reference problem, point by point."""

    problem: str
    quantity: str
    units: str
    coords: dict[str, np.ndarray]
    values: np.ndarray
    reference: np.ndarray
    tolerance: np.ndarray
    tolerance_source: str
    #: :class:`debench.reference.problems_coverage.Coverage` of the addressed reference
    #: (None: not assessed)
    coverage: Any = None

    @property
    def error(self) -> np.ndarray:
        return self.values - self.reference

    @property
    def ratio(self) -> np.ndarray:
        """|error| / tolerance per point (> 1 fails).

        Where the reference has no value (NaN: no event, e.g. no pull-in on that curve)
        only NaN matches (ratio 0); a number there, and NaN where the reference has a
        value, count as failures (ratio inf)."""
        with np.errstate(invalid="ignore", divide="ignore"):
            r = np.abs(self.error) / self.tolerance
        none = np.isnan(self.values) & np.isnan(self.reference)
        return np.where(none, 0.0, np.where(np.isfinite(r), r, np.inf))

    @property
    def failed(self) -> np.ndarray:
        return self.ratio > 1.0

    @property
    def passed(self) -> bool:
        return not bool(self.failed.any())

    def summary(self) -> str:
        """One line: how many points, how many failed, the worst ratio."""
        n, bad = self.values.size, int(self.failed.sum())
        worst = float(self.ratio.max()) if n else 0.0
        verdict = "MATCHES" if not bad else "DOES NOT MATCH"
        cov = f"; {self.coverage.describe()}" if self.coverage is not None else ""
        none = int((np.isnan(self.values) & np.isnan(self.reference)).sum())
        none = f", {none} of them no value (NaN) where the reference has none" if none else ""
        return (f"{self.problem}:{self.quantity} {verdict}: {n - bad}/{n} points within "
                f"tolerance ({self.tolerance_source}){none}; worst |error|/tolerance = "
                f"{worst:.3g}{cov}")

    def by_curve(self, along: str | None = None) -> str:
        """One row per curve (selector combination; ``along``: the abscissa, not a
        selector): points, failures and the worst |error|/tolerance, worst first."""
        names = [k for k in self.coords if k != along]
        if not names:
            return ""
        groups: dict[tuple, list[int]] = {}
        for i, key in enumerate(zip(*(self.coords[k] for k in names), strict=True)):
            groups.setdefault(tuple(_fmt(v) for v in key), []).append(i)
        body = sorted(([*key, str(len(idx)), str(int(self.failed[idx].sum())),
                        _fmt(float(self.ratio[idx].max()))]
                       for key, idx in groups.items()),
                      key=lambda r: -float(r[-1]))
        head = [*names, "points", "failed", "worst |err|/tol"]
        widths = [max(len(h), *(len(r[j]) for r in body)) for j, h in enumerate(head)]
        line = lambda cells: "  ".join(c.rjust(w) for c, w in zip(cells, widths, strict=True))  # noqa: E731
        return "\n".join([f"per curve ({len(body)}):" if along else
                          f"per selection ({len(body)}):", line(head),
                          *(line(r) for r in body)])

    def table(self, rows: int = WORST_ROWS) -> str:
        """The worst points: coordinates, value, reference, error, tolerance."""
        order = np.argsort(-self.ratio, kind="stable")[:rows]
        names = list(self.coords)
        head = names + ["value", "reference", "error", "tolerance", "|err|/tol"]
        body = []
        for i in order:
            body.append([_fmt(self.coords[k][i]) for k in names] + [
                _fmt(self.values[i]), _fmt(self.reference[i]), _fmt(self.error[i]),
                _fmt(self.tolerance[i]), _fmt(self.ratio[i])])
        widths = [max(len(h), *(len(r[j]) for r in body)) if body else len(h)
                  for j, h in enumerate(head)]
        line = lambda cells: "  ".join(c.rjust(w) for c, w in zip(cells, widths, strict=True))  # noqa: E731
        units = f" [{self.units}]" if self.units else ""
        return "\n".join([f"worst {len(order)} of {self.values.size} points ({self.quantity}"
                          f"{units}):", line(head), *(line(r) for r in body)])


@dataclass(frozen=True)
class Comparisons:
    """Several quantities of one problem compared at the same points, one
    :class:`Comparison` each (in the order given); passed when every one passed."""

    problem: str
    items: tuple[Comparison, ...]

    @property
    def quantities(self) -> tuple[str, ...]:
        return tuple(c.quantity for c in self.items)

    def __getitem__(self, quantity: str) -> Comparison:
        for c in self.items:
            if c.quantity == quantity:
                return c
        raise KeyError(f"{self.problem}: no comparison of {quantity!r}; compared "
                       f"{list(self.quantities)}")

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.items)

    @property
    def failing(self) -> tuple[str, ...]:
        """The quantities that did not match."""
        return tuple(c.quantity for c in self.items if not c.passed)

    def summary(self) -> str:
        """One line per quantity (:meth:`Comparison.summary`), then the verdict naming the
        quantities that failed."""
        n, bad = len(self.items), self.failing
        verdict = (f"{self.problem} MATCHES: all {n} quantities" if not bad else
                   f"{self.problem} DOES NOT MATCH: {len(bad)} of {n} quantities failed "
                   f"({', '.join(bad)})")
        return "\n".join([*(c.summary() for c in self.items), verdict])

    def worst(self) -> str:
        """One row per quantity, worst first: points, failures, its worst
        |error|/tolerance and the point where it occurs."""
        names = list(self.items[0].coords) if self.items else []
        body = []
        for c in self.items:
            i = int(np.argmax(c.ratio)) if c.values.size else None
            at = [_fmt(c.coords[k][i]) if i is not None else "" for k in names]
            body.append([c.quantity, c.units or "-", str(c.values.size),
                         str(int(c.failed.sum())),
                         _fmt(float(c.ratio[i])) if i is not None else "", *at])
        body.sort(key=lambda r: -float(r[4] or 0.0))
        head = ["quantity", "units", "points", "failed", "worst |err|/tol",
                *(f"at {k}" for k in names)]
        widths = [max(len(h), *(len(r[j]) for r in body)) if body else len(h)
                  for j, h in enumerate(head)]
        line = lambda cells: "  ".join(c.rjust(w) for c, w in zip(cells, widths, strict=True))  # noqa: E731
        return "\n".join([f"per quantity ({len(body)}):", line(head),
                          *(line(r) for r in body)])

    def table(self, rows: int = WORST_ROWS) -> str:
        """:meth:`worst`, then the worst points of each quantity (:meth:`Comparison.table`)."""
        return "\n".join([self.worst(), *(c.table(rows) for c in self.items)])


def _fmt(x: Any) -> str:
    if isinstance(x, float | np.floating):
        return f"{float(x):.6g}" if np.isfinite(x) else str(float(x))
    return str(x)


def compare(problem: str, quantity: str | None, values, coords: Mapping[str, Any], *,
            rtol: float | Mapping[str, float] | None = None,
            atol: float | Mapping[str, float] | None = None,
            coverage: str = "full") -> Comparison | Comparisons:
    """Compare ``values`` at ``coords`` with the reference of ``problem``.

    Parameters
    ----------
    problem, quantity
        A problem id (``debench problems``) and one of its quantities (``None``: the
        only one, or the keys of ``values`` when it is a mapping).
    values
        Your values, broadcastable with the coordinate arrays; or a mapping quantity name
        -> values, to check several quantities of the problem at the same ``coords``
        (they must share their coordinates), each against its own reference and stated
        accuracy; ``quantity`` must then be ``None``. NaN says there is no value (e.g.
        no event): it matches where the reference has none (NaN) and fails where it has
        one; a number where the reference has none fails.
    coords
        Coordinate name -> scalar or array: every ``select`` coordinate of the quantity
        (matched exactly to the reference grid; defaults from the spec apply) and, for a
        curve, its abscissa (``along``), at which the reference is interpolated.
    rtol, atol
        Your tolerance. ``None`` (default) applies the stated accuracy of the reference;
        otherwise the larger of yours and the stated one, plus the interpolation error
        estimate, applies.
    coverage
        ``"full"`` (default): your points must cover every reference curve or value they
        address (:func:`debench.reference.problems_coverage.coverage`: every grid value
        of a selector without a default, the values you give of one with a default; each
        curve at least as densely as the stored grid over its whole range), else
        :class:`~debench.reference.problems_coverage.CoverageError`; ``"partial"``: any
        subset, reported in :attr:`Comparison.coverage`. Repeated coordinates raise
        ValueError.

    Returns
    -------
    Comparison
        for one quantity; :class:`Comparisons` (one :class:`Comparison` per quantity)
        when ``values`` is a mapping. ``rtol`` and ``atol`` may then be mappings quantity
        name -> tolerance too (a quantity not named gets the stated accuracy alone).
    """
    if coverage not in ("full", "partial"):
        raise ValueError(f"coverage must be 'full' or 'partial', got {coverage!r}")
    if isinstance(values, Mapping):
        return _compare_several(problem, quantity, values, coords, rtol, atol, coverage)
    _check_tolerances(rtol, atol)
    prob, q, ref, cov = _covered_reference(problem, quantity, coords, coverage)
    given = {**q.defaults, **dict(coords)}
    arrays = np.broadcast_arrays(np.asarray(values, dtype=float),
                                 *[np.asarray(given[n]) for n in q.coordinates])
    vals = arrays[0].ravel()
    if vals.size != ref.value.size:
        raise ValueError(f"values ({vals.size}) and coords ({ref.value.size} points) differ "
                         "in size")
    tol, source = ref.tolerance, "stated accuracy of the reference"
    if rtol is not None or atol is not None:
        user = (atol or 0.0) + (rtol or 0.0) * np.abs(ref.value)
        tol = np.maximum(tol, user + ref.interpolation)
        source = f"rtol={rtol}, atol={atol} (floor: the stated accuracy)"
    return Comparison(problem=prob.id, quantity=q.name, units=q.units,
                      coords={n: a.ravel() for n, a in zip(q.coordinates, arrays[1:],
                                                           strict=True)},
                      values=vals, reference=ref.value, tolerance=tol,
                      tolerance_source=source, coverage=cov)


def _check_tolerances(rtol, atol) -> None:
    """The user's ``rtol`` and ``atol`` of :func:`compare` for one quantity: each None or a
    finite number >= 0 (a mapping per quantity only goes with a mapping of values);
    ValueError naming the argument otherwise."""
    for name, x in (("rtol", rtol), ("atol", atol)):
        if isinstance(x, Mapping):
            raise ValueError(f"{name} is a mapping per quantity, but values is not: pass "
                             "values as a mapping quantity name -> values")
        if x is not None and not (np.isfinite(x) and x >= 0):
            raise ValueError(f"{name} must be finite and >= 0, got {x}")


def _covered_reference(problem: str, quantity: str | None, coords: Mapping[str, Any],
                       coverage: str):
    """``(problem, quantity, reference, coverage)`` of :func:`compare` for one quantity:
    the reference at ``coords`` and the :class:`~debench.reference.problems_coverage.Coverage`
    of the points; ValueError on repeated coordinates, and
    :class:`~debench.reference.problems_coverage.CoverageError` when ``coverage`` is
    ``"full"`` and the points do not cover what they address."""
    prob = problems.get(problem)
    q = prob.quantity(quantity)
    ref = problems_reference.reference_at(prob, q, coords)
    dup = problems_coverage.duplicates(q, coords)
    if dup:
        raise ValueError(f"{prob.id}:{q.name}: repeated coordinates ({len(dup)}): "
                         + "; ".join(dup[:3]))
    cov = problems_coverage.coverage(prob, q, coords,
                                     declared="declared" if coverage == "partial"
                                     else "not declared")
    if coverage == "full" and not cov.complete:
        raise problems_coverage.CoverageError(
            f"{prob.id}:{q.name}: {cov.describe()}. Cover every reference point of what "
            "you address, or declare partial coverage (coverage='partial', "
            "debench check --partial)")
    return prob, q, ref, cov


def _compare_several(problem, quantity, values, coords, rtol, atol, coverage) -> Comparisons:
    """:func:`compare` for ``values`` = {quantity name: values}: one comparison each; an
    error about one quantity names it."""
    if quantity is not None:
        raise ValueError(f"quantity must be None when values is a mapping (its keys name "
                         f"the quantities), got {quantity!r}")
    if not values:
        raise ValueError("values is an empty mapping: name at least one quantity")
    prob = problems.get(problem)
    qs = [prob.quantity(n) for n in values]
    shared = set(qs[0].coordinates)
    for q in qs[1:]:
        if set(q.coordinates) != shared:
            raise ValueError(f"{prob.id}: quantities {qs[0].name} (coordinates "
                             f"{list(qs[0].coordinates)}) and {q.name} (coordinates "
                             f"{list(q.coordinates)}) do not share their coordinates; "
                             "compare them separately")

    for name, x in (("rtol", rtol), ("atol", atol)):
        extra = sorted(set(x) - set(values)) if isinstance(x, Mapping) else []
        if extra:
            raise ValueError(f"{name} names quantities {extra} that values does not hold "
                             f"({list(values)})")
    items = []
    for q in qs:
        kw = {k: (x.get(q.name) if isinstance(x, Mapping) else x)
              for k, x in (("rtol", rtol), ("atol", atol))}
        try:
            items.append(compare(prob.id, q.name, values[q.name], coords,
                                 coverage=coverage, **kw))
        except ValueError as exc:
            if str(exc).startswith(f"{prob.id}:{q.name}"):
                raise
            raise type(exc)(f"{prob.id}:{q.name}: {exc}") from None
    return Comparisons(problem=prob.id, items=tuple(items))
