"""Users' results files (CSV with a units header, or netCDF) read for a reference problem's
quantity: the reader behind ``debench check`` and submissions, and the usage error it raises
on bad input (the command line's exit code 2)."""

from __future__ import annotations

from pathlib import Path

import numpy as np


class UsageError(ValueError):
    """Bad command-line input (exit code 2)."""


def _unit(spelled: str | None, expected: str, column: str, where: str):
    """A converter of a column in units ``spelled`` to ``expected`` (compared by
    meaning with cf-units, the UDUNITS-2 library of the CF conventions: ``J/m3`` ==
    ``J m-3``, ``kPa`` converts to ``Pa``). ``expected == ""``: a text coordinate, no
    units. UsageError for missing, unknown or incompatible units."""
    import cf_units

    if expected == "":
        if spelled:
            raise UsageError(f"{where}: {column} is a text coordinate and takes no units, "
                             f"got [{spelled}]")
        return None
    if spelled is None or not spelled.strip():
        raise UsageError(f"{where}: {column} has no units; write them as '{column} "
                         f"[{expected}]' ('1' for a dimensionless quantity)")
    try:
        got, want = cf_units.Unit(spelled.strip()), cf_units.Unit(expected)
    except ValueError:
        raise UsageError(f"{where}: {column} has units [{spelled}], which cf-units "
                         "(UDUNITS-2) does not parse") from None
    if got.is_unknown() or got.is_no_unit() or not got.is_convertible(want):
        raise UsageError(f"{where}: {column} has units [{spelled}], not convertible to "
                         f"the expected [{expected}]")
    return lambda x: got.convert(np.asarray(x, dtype=float), want)


def read_results(path: Path, quantity: str | None, prob) -> tuple[str, dict]:
    """Columns of a user's results file for one quantity of ``prob``: CSV with header
    ``name [units]``, or netCDF (variables named like the coordinates and the quantity,
    with a ``units`` attribute, broadcast against it). Every numeric column needs units,
    compared by meaning and converted to the problem's; a column that is neither the
    quantity nor one of its coordinates, or a repeated column, is refused."""
    path = Path(path)
    if not path.is_file():
        raise UsageError(f"FILE {path} does not exist")
    names = [q.name for q in prob.quantities]
    if path.suffix in (".nc", ".nc4", ".cdf"):
        import xarray as xr

        with xr.open_dataset(path) as ds:
            qname = quantity or next((n for n in names if n in ds.data_vars), None)
            if qname is None or qname not in ds:
                raise UsageError(f"{path} has no variable for quantity "
                                 f"{quantity or names}")
            q = _quantity_of(prob, qname)
            unknown = sorted(set(ds.data_vars) - {qname, *q.coordinates})
            if unknown:
                raise UsageError(f"{path}: variables {unknown} are not the quantity "
                                 f"{qname} or its coordinates {list(q.coordinates)}")
            cols = {}
            for n in (*q.coordinates, qname):
                if n not in ds.variables:
                    continue
                conv = _unit(ds[n].attrs.get("units"), q.units_of(n), n, str(path))
                a, _ = xr.broadcast(ds[n], ds[qname])
                v = a.transpose(*ds[qname].dims).values.ravel()
                cols[n] = conv(v) if conv else v
        return qname, cols
    import csv

    with path.open(newline="", encoding="utf-8") as fh:
        rows = [r for r in csv.reader(fh) if r and not r[0].startswith("#")]
    if len(rows) < 2:
        raise UsageError(f"{path}: expected a header and at least one row")
    header, spelled = [], {}
    for cell in rows[0]:
        name, bracket, rest = cell.strip().partition("[")
        name = name.strip()
        if name in spelled:
            raise UsageError(f"{path}: column {name} appears twice in the header")
        header.append(name)
        spelled[name] = rest.rstrip().removesuffix("]").strip() if bracket else None
    qname = quantity or next((n for n in header if n in names), None)
    if qname is None or qname not in header:
        raise UsageError(f"{path}: no column for quantity {quantity or names}; "
                         f"header {header}")
    q = _quantity_of(prob, qname)
    unknown = [n for n in header if n not in (qname, *q.coordinates)]
    if unknown:
        raise UsageError(f"{path}: columns {unknown} are not the quantity {qname} or its "
                         f"coordinates {list(q.coordinates)}")
    cols = {}
    for j, name in enumerate(header):
        conv = _unit(spelled[name], q.units_of(name), name, str(path))
        raw = [r[j].strip() if j < len(r) else "" for r in rows[1:]]
        if conv is None:
            cols[name] = np.array(raw)
            continue
        try:
            cols[name] = conv(np.array([float(x) for x in raw]))
        except ValueError:
            raise UsageError(f"{path}: column {name} holds a value that is not a "
                             "number") from None
    return qname, cols


def _quantity_of(prob, name: str):
    from debench.reference import problems

    try:
        return prob.quantity(name)
    except problems.ProblemError as exc:
        raise UsageError(str(exc)) from None
