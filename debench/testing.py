"""Check your own results against a debench reference problem.

:func:`assert_matches` loads the verified reference of a problem (see
:mod:`debench.reference.problems`; ``debench problems`` lists them), interpolates it to
your coordinates where the quantity is a curve, and applies the accuracy the reference
states (solver tolerance + discretisation error + interpolation error estimate) or your
tolerance, whichever is larger: a reference cannot be checked tighter than it is known.

Examples
--------
>>> import numpy as np
>>> from debench.testing import assert_matches
>>> lam = np.linspace(1.0, 5.0, 401)             # the reference range, as densely
>>> phibar = np.sqrt(lam**-2 - lam**-8)        # your free-membrane solver here
>>> assert_matches("ch3_free_membrane_nh", "phibar", phibar, {"lam": lam}).passed
True
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["Comparison", "assert_matches", "compare"]

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
    #: :class:`debench.reference.problems.Coverage` of the addressed reference (None: not
    #: assessed)
    coverage: Any = None

    @property
    def error(self) -> np.ndarray:
        return self.values - self.reference

    @property
    def ratio(self) -> np.ndarray:
        """|error| / tolerance per point (> 1 fails; NaN values count as failures)."""
        r = np.abs(self.error) / self.tolerance
        return np.where(np.isfinite(r), r, np.inf)

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
        return (f"{self.problem}:{self.quantity} {verdict}: {n - bad}/{n} points within "
                f"tolerance ({self.tolerance_source}); worst |error|/tolerance = "
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


def _fmt(x: Any) -> str:
    if isinstance(x, float | np.floating):
        return f"{float(x):.6g}" if np.isfinite(x) else str(float(x))
    return str(x)


def compare(problem: str, quantity: str | None, values, coords: Mapping[str, Any], *,
            rtol: float | None = None, atol: float | None = None,
            coverage: str = "full") -> Comparison:
    """Compare ``values`` at ``coords`` with the reference of ``problem``.

    Parameters
    ----------
    problem, quantity
        A problem id (``debench problems``) and one of its quantities (``None``: the
        only one).
    values
        Your values, broadcastable with the coordinate arrays.
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
        address (:func:`debench.reference.problems.coverage`: every grid value of a
        selector without a default, the values you give of one with a default; each curve
        at least as densely as the stored grid over its whole range), else
        :class:`~debench.reference.problems.CoverageError`; ``"partial"``: any subset,
        reported in :attr:`Comparison.coverage`. Repeated coordinates raise ValueError.

    Returns
    -------
    Comparison
    """
    from debench.reference import problems

    for name, x in (("rtol", rtol), ("atol", atol)):
        if x is not None and not (np.isfinite(x) and x >= 0):
            raise ValueError(f"{name} must be finite and >= 0, got {x}")
    if coverage not in ("full", "partial"):
        raise ValueError(f"coverage must be 'full' or 'partial', got {coverage!r}")
    prob = problems.get(problem)
    q = prob.quantity(quantity)
    ref = problems.reference_at(prob, q, coords)
    dup = problems.duplicates(q, coords)
    if dup:
        raise ValueError(f"{prob.id}:{q.name}: repeated coordinates ({len(dup)}): "
                         + "; ".join(dup[:3]))
    cov = problems.coverage(prob, q, coords, declared="declared" if coverage == "partial"
                            else "not declared")
    if coverage == "full" and not cov.complete:
        raise problems.CoverageError(
            f"{prob.id}:{q.name}: {cov.describe()}. Cover every reference point of what "
            "you address, or declare partial coverage (coverage='partial', "
            "debench check --partial)")
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


def assert_matches(problem: str, quantity: str | None, values, coords: Mapping[str, Any],
                   rtol: float | None = None, *, atol: float | None = None,
                   coverage: str = "full") -> Comparison:
    """Raise ``AssertionError`` (with a table of the worst points) unless ``values`` match
    the reference of ``problem``; see :func:`compare` for the arguments.

    Returns the :class:`Comparison` when they match.
    """
    result = compare(problem, quantity, values, coords, rtol=rtol, atol=atol,
                     coverage=coverage)
    if not result.passed:
        raise AssertionError(f"{result.summary()}\n{result.table()}")
    return result
