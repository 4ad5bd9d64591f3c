"""Observed orders of convergence of a manufactured-solution study (problem ``mms_electroelastic``).

A user solves the manufactured problem (:mod:`debench.models.mms`, formulas in
``reference/mms_electroelastic_formulas.json``) with Lagrange elements of degree ``p`` on
a sequence of uniformly refined meshes and tabulates the mesh size ``h`` (or the number
of degrees of freedom) and the errors of ``u`` and ``phi`` in the L2 norm and the H1
seminorm. The observed order is the least-squares slope of ``log(error)`` against
``log(h)`` over the finest levels (the scikit-fem ``test_convergence`` pattern: a fit over
more levels than unknowns, so that it has a residual), and is judged against the
a-priori order of smooth solutions, ``p + 1`` in L2 and ``p`` in H1, within
:data:`ORDER_ATOL`.

Examples
--------
>>> import numpy as np
>>> from debench.reference import mms_check
>>> h = np.array([1/4, 1/8, 1/16, 1/32])
>>> fit = mms_check.fit_order(h, 0.3 * h**3 * (1 + 0.2 * h))
>>> round(fit.order, 3), fit.levels
(3.013, 3)
>>> mms_check.check_order(h, 0.3 * h**3, expected=3).passed
True
"""

from __future__ import annotations

import csv
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from debench.models import validation as val
from debench.reference.results_files import UsageError

ORDER_ATOL = 0.1
"""|observed - expected| allowed for the fitted order. Why 0.1: over the finest three of
h = 1/8 .. 1/64, debench's NGSolve solver (plane strain, p = 1, 2, 3, neo-Hookean and
Gent) and the clean-room scikit-fem solver (p = 1, 2, 3) observe the a-priori orders to
within 0.07, except the displacement L2 order of p = 1, 1.909 (NGSolve) and 1.960 (clean
room): pre-asymptotic, its local orders are 1.86, 1.96, 1.99 up to h = 1/128. A wrong body
force, charge, sign or boundary datum is an O(1) consistency error that stalls the order
(towards 0) or costs a whole order; 0.1 is the margin of scikit-fem's test_convergence."""
FINEST_LEVELS = 3
"""Levels fitted by default: the finest three (the coarsest meshes are pre-asymptotic)."""
FIELDS = ("u", "phi")
NORMS = ("L2", "H1")


@dataclass(frozen=True)
class OrderFit:
    """The fitted order and how well a straight line fits ``log e`` vs ``log h``.

    ``order`` the slope; ``levels`` the number of (finest) levels fitted; ``local`` the
    orders between consecutive fitted levels; ``misfit`` the largest deviation of
    ``log(error)`` from the fitted line (natural log; 0 for exact powers); ``expected``,
    ``atol``, ``passed`` set by :func:`check_order`.
    """

    order: float
    levels: int
    local: tuple[float, ...]
    misfit: float
    expected: float | None = None
    atol: float | None = None

    @property
    def passed(self) -> bool | None:
        if self.expected is None:
            return None
        return bool(abs(self.order - self.expected) <= self.atol)


def _sizes(h, ndof, dim):
    if (h is None) == (ndof is None):
        raise ValueError("give exactly one of h (mesh sizes) and ndof (degrees of freedom)")
    if h is not None:
        hs = np.asarray(val.finite("h", val.array("h", h)), dtype=float).ravel()
        if np.any(hs <= 0):
            raise ValueError(f"h must be > 0, got min {hs.min():.6g}")
        return hs
    dim = val.integer_at_least("dim", dim, 1)
    if dim > 3:
        raise ValueError(f"dim must be <= 3, got {dim}")
    nd = np.asarray(val.finite("ndof", val.array("ndof", ndof)), dtype=float).ravel()
    if np.any(nd < 1):
        raise ValueError(f"ndof must be >= 1, got min {nd.min():.6g}")
    return nd ** (-1.0 / dim)      # h ~ ndof^(-1/dim) on uniform refinements


def fit_order(h=None, errors=None, *, ndof=None, dim=None,
              finest: int = FINEST_LEVELS) -> OrderFit:
    """Least-squares order of ``errors`` against the mesh size over the finest levels.

    Parameters
    ----------
    h : array_like, optional
        Mesh sizes (> 0, all distinct), one per level, any order.
    errors : array_like
        Errors (> 0, finite), one per level.
    ndof, dim : optional
        Instead of ``h``: degrees of freedom (>= 1) and the space dimension (1-3), with
        ``h ~ ndof^(-1/dim)`` (uniform refinement).
    finest : int
        Number of finest levels fitted (>= 3, so that the fit has a residual; at most the
        number of levels given).
    """
    hs = _sizes(h, ndof, dim)
    if errors is None:
        raise ValueError("errors must be given (one per level)")
    es = np.asarray(val.finite("errors", val.array("errors", errors)), dtype=float).ravel()
    if es.size != hs.size:
        raise ValueError(f"errors has {es.size} levels, the mesh sizes {hs.size}")
    if np.any(es <= 0):
        raise ValueError(f"errors must be > 0 (log-log fit), got min {es.min():.6g}")
    finest = val.integer_at_least("finest", finest, 3)
    if hs.size < finest:
        raise ValueError(f"finest = {finest} needs at least {finest} levels, got {hs.size}")
    order = np.argsort(hs)
    hs, es = hs[order][:finest], es[order][:finest]
    if np.any(np.diff(hs) <= 0):
        raise ValueError(f"mesh sizes must be distinct, got {hs.tolist()}")
    x, y = np.log(hs), np.log(es)
    # numpy's line fit, not numerics.loglog_order: every command loads this module at its
    # start-up (the CLI's defaults), which must not load scipy (the numerics package does)
    slope, icept = np.polyfit(x, y, 1)
    local = tuple(float(v) for v in np.diff(y) / np.diff(x))
    misfit = float(np.max(np.abs(y - (slope * x + icept))))
    return OrderFit(order=float(slope), levels=int(finest), local=local[::-1], misfit=misfit)


def expected_order(degree, *, norm: str):
    """The a-priori order of Lagrange elements of ``degree`` p for smooth solutions:
    ``p + 1`` in L2, ``p`` in the H1 seminorm (array in, array out; degrees integers >= 1)."""
    val.choice("norm", norm, NORMS)
    p = np.asarray(val.finite("degree", degree), dtype=float)
    if np.any(p < 1) or np.any(p != np.round(p)):
        raise ValueError(f"degree must be an integer >= 1, got {np.ravel(p)[:4].tolist()}")
    return p + 1.0 if norm == "L2" else p


def check_order(h=None, errors=None, *, expected, ndof=None, dim=None,
                finest: int = FINEST_LEVELS, atol: float = ORDER_ATOL) -> OrderFit:
    """:func:`fit_order` judged against ``expected`` within ``atol`` (``.passed``)."""
    expected = val.finite("expected", expected)
    atol = val.positive("atol", atol)
    fit = fit_order(h, errors, ndof=ndof, dim=dim, finest=finest)
    return OrderFit(order=fit.order, levels=fit.levels, local=fit.local, misfit=fit.misfit,
                    expected=float(expected), atol=float(atol))


def check_table(table: Mapping[str, Sequence[float]], degree: int, *, dim: int | None = None,
                finest: int = FINEST_LEVELS, atol: float = ORDER_ATOL) -> dict[str, OrderFit]:
    """Every error column of a user's table judged against the order of ``degree``.

    ``table`` maps column names to one value per level: ``h`` (or ``ndof`` with ``dim``)
    and any of ``u_L2``, ``u_H1``, ``phi_L2``, ``phi_H1``; at least one error column. Keys
    of the result are the error columns given.
    """
    val.instance("table", table, Mapping)
    degree = val.integer_at_least("degree", degree, 1)
    known = {f"{f}_{n}" for f in FIELDS for n in NORMS}
    unknown = sorted(set(table) - known - {"h", "ndof"})
    if unknown:
        raise ValueError(f"table has unknown columns {unknown}; expected h or ndof and any "
                         f"of {sorted(known)}")
    cols = [c for c in sorted(known) if c in table]
    if not cols:
        raise ValueError(f"table has no error column; give any of {sorted(known)}")
    out = {}
    for c in cols:
        norm = c.rsplit("_", 1)[1]
        out[c] = check_order(table.get("h"), table[c], ndof=table.get("ndof"), dim=dim,
                             expected=float(expected_order(degree, norm=norm)),
                             finest=finest, atol=atol)
    return out


# ------------------------------------------------------------------ command line
def read_table(path) -> dict[str, np.ndarray]:
    """A CSV of levels: a header row (``name`` or ``name [units]``), one row per level;
    columns ``h`` or ``ndof``, optionally ``degree``, and error columns (:func:`check_table`)."""
    text = Path(path).read_text(encoding="utf-8")
    rows = [r for r in csv.reader(line for line in text.splitlines()
                                  if line.strip() and not line.lstrip().startswith("#"))]
    if len(rows) < 2:
        raise ValueError("needs a header row and at least one level")
    names = [c.split("[")[0].strip() for c in rows[0]]
    try:
        values = np.array([[float(x) for x in r] for r in rows[1:]], dtype=float)
    except ValueError as exc:
        raise ValueError(f"every entry below the header must be a number ({exc})") \
            from None
    if values.shape[1] != len(names):
        raise ValueError(f"rows have {values.shape[1]} entries, the header {len(names)}")
    return {n: values[:, k] for k, n in enumerate(names)}


#: the problem whose quantities are the fitted orders of an error table
PROBLEM = "mms_electroelastic"
PROBLEM_DIM = 2
"""Space dimension of that problem's reference (plane strain): ``h ~ ndof^(-1/2)``."""
ERROR_COLUMNS = tuple(f"{f}_{n}" for f in FIELDS for n in NORMS)


def _header(path) -> list[str]:
    """The column names (units dropped) of the first row of a CSV that is not a comment."""
    for line in Path(path).read_text(encoding="utf-8-sig").splitlines():
        if line.strip() and not line.lstrip().startswith("#"):
            return [c.split("[")[0].strip() for c in line.split(",")]
    return []


def is_error_table(path) -> bool:
    """Whether a CSV is a table of errors per mesh level (columns ``h`` or ``ndof`` and
    any of :data:`ERROR_COLUMNS`), the input of :func:`fit_error_table`, rather than a table
    of fitted orders (``*_order`` columns)."""
    names = set(_header(path))
    return bool(names & set(ERROR_COLUMNS)) and bool(names & {"h", "ndof"})


def fit_error_table(path, *, degree: int | None = None, dim: int | None = None,
                    finest: int = FINEST_LEVELS) -> dict[int, dict[str, OrderFit]]:
    """Every error column of the CSV ``path`` (:func:`read_table`) fitted and judged per
    degree (:func:`check_table`): ``{degree: {column: OrderFit}}``. The degree comes from
    a ``degree`` column or ``degree``; ValueError when neither or both disagree."""
    table = read_table(path)
    if "degree" in table:
        degrees = table.pop("degree")
        if degree is not None and not np.all(degrees == degree):
            raise ValueError("--degree contradicts the table's degree column")
    elif degree is None:
        raise ValueError("give --degree or a degree column")
    else:
        degrees = np.full(len(next(iter(table.values()))), float(degree))
    results = {}
    for p in sorted(set(degrees.tolist())):
        rows = degrees == p
        results[int(p)] = check_table({k: v[rows] for k, v in table.items()}, int(p),
                                      dim=dim, finest=finest)
    return results


def order_lines(results: dict[int, dict[str, OrderFit]]) -> list[str]:
    """One line per degree and column: observed and expected order, verdict, local orders."""
    return [f"p = {p} {col:7s} observed {fit.order:6.3f} expected {fit.expected:g} "
            f"(|diff| <= {fit.atol:g}): {'PASS' if fit.passed else 'FAIL'}; local "
            f"{', '.join(f'{x:.3f}' for x in fit.local)}; misfit {fit.misfit:.2g}"
            for p, res in results.items() for col, fit in res.items()]


def order_columns(results: dict[int, dict[str, OrderFit]]) -> dict[str, np.ndarray]:
    """The fitted orders as the columns of problem :data:`PROBLEM`: ``degree`` and
    ``<column>_order`` (NaN where a degree lacks the column)."""
    cols = sorted({c for res in results.values() for c in res})
    out = {"degree": np.array(list(results), dtype=float)}
    for c in cols:
        out[f"{c}_order"] = np.array([res[c].order if c in res else np.nan
                                      for res in results.values()], dtype=float)
    return out


def cmd_orders(args) -> int:
    """``debench orders TABLE.csv``: fit and judge the orders of a manufactured-solution
    study; ``--write`` saves them as a table ``debench check mms_electroelastic`` reads
    (which also reads the error table itself when it has a ``degree`` column and ``h``)."""
    try:
        results = fit_error_table(args.table, degree=args.degree, dim=args.dim,
                                  finest=args.finest)
    except (ValueError, TypeError) as exc:
        raise UsageError(f"{args.table}: {exc}") from None
    for line in order_lines(results):
        print(line)
    ok = all(bool(fit.passed) for res in results.values() for fit in res.values())
    if args.write:

        cols = order_columns(results)
        names = list(cols)
        lines = [",".join(f"{n} [1]" for n in names)]
        for k in range(len(cols["degree"])):
            lines.append(",".join([str(int(cols["degree"][k]))]
                                  + [f"{cols[n][k]:.6g}" for n in names[1:]]))
        Path(args.write).write_text("\n".join(lines) + "\n", encoding="utf-8")
        print(f"wrote {args.write}: debench check mms_electroelastic {args.write}")
    return 0 if ok else 1
