"""Users' results files (CSV with a units header, or netCDF) read for the quantities of a
reference problem they hold: the reader behind ``debench check`` and submissions, and the
usage error it raises on bad input (the command line's exit code 2)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

#: exit codes of ``debench``: 0 ok; 1 a check or verification failed; 2 usage error; 3
#: runtime error (a computation failed)
EXIT_OK, EXIT_FAILED, EXIT_USAGE, EXIT_RUNTIME = 0, 1, 2, 3


class UsageError(ValueError):
    """Bad command-line input (exit code :data:`EXIT_USAGE`)."""


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


def read_results(path: Path, quantity: str | None, prob) -> tuple[tuple[str, ...], dict]:
    """Columns of a user's results file for the quantities of ``prob`` it holds: CSV with
    header ``name [units]``, or netCDF (variables named like the coordinates and the
    quantities, with a ``units`` attribute, broadcast against the first quantity).

    Returns the names of the quantities found (in the file's order; ``quantity``: that
    one alone) and ``{column: values}``. Several quantities in one file must share their
    coordinates (each row is one point of every quantity). Every numeric column needs
    units, compared by meaning and converted to the problem's; a column that is neither
    one of the quantities nor one of their coordinates (with ``quantity`` given, another
    quantity's column too), or a repeated column, is refused."""
    path = Path(path)
    if not path.is_file():
        raise UsageError(f"FILE {path} does not exist")
    names = [q.name for q in prob.quantities]
    if path.suffix in (".nc", ".nc4", ".cdf"):
        import xarray as xr

        with xr.open_dataset(path) as ds:
            found = _quantities_in(path, [n for n in ds.data_vars], names, quantity,
                                   "variable")
            qs = [_quantity_of(prob, n) for n in found]
            coords = _shared_coordinates(path, qs)
            unknown = sorted(set(ds.data_vars) - {*found, *coords})
            if unknown:
                raise UsageError(f"{path}: variables {unknown} are not "
                                 f"{_what(found, coords, quantity)}")
            cols = {}
            first = ds[found[0]]
            for n in (*coords, *found):
                if n not in ds.variables:
                    continue
                conv = _unit(ds[n].attrs.get("units"), _units(qs, n), n, str(path))
                a, _ = xr.broadcast(ds[n], first)
                v = a.transpose(*first.dims).values.ravel()
                cols[n] = conv(v) if conv else v
        return tuple(found), cols
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
    found = _quantities_in(path, header, names, quantity, "column")
    qs = [_quantity_of(prob, n) for n in found]
    coords = _shared_coordinates(path, qs)
    unknown = [n for n in header if n not in (*found, *coords)]
    if unknown:
        raise UsageError(f"{path}: columns {unknown} are not "
                         f"{_what(found, coords, quantity)}")
    cols = {}
    for j, name in enumerate(header):
        conv = _unit(spelled[name], _units(qs, name), name, str(path))
        raw = [r[j].strip() if j < len(r) else "" for r in rows[1:]]
        if conv is None:
            cols[name] = np.array(raw)
            continue
        try:
            cols[name] = conv(np.array([float(x) for x in raw]))
        except ValueError:
            raise UsageError(f"{path}: column {name} holds a value that is not a "
                             "number") from None
    return tuple(found), cols


def _quantities_in(path, present, names, quantity, kind: str) -> list[str]:
    """The quantities to check: ``quantity`` (which must be present), else every
    quantity of the problem that ``present`` (the file's columns) names."""
    found = [quantity] if quantity else [n for n in present if n in names]
    if not found or found[0] not in present:
        raise UsageError(f"{path}: no {kind} for quantity {quantity or names}; "
                         f"{'header' if kind == 'column' else 'variables'} {list(present)}")
    return found


def _shared_coordinates(path, qs) -> tuple[str, ...]:
    """The coordinates of the quantities ``qs``, which must be the same for all (one row
    is one point of each)."""
    coords = qs[0].coordinates
    for q in qs[1:]:
        if set(q.coordinates) != set(coords):
            raise UsageError(f"{path}: quantities {qs[0].name} (coordinates {list(coords)}) "
                             f"and {q.name} (coordinates {list(q.coordinates)}) do not share "
                             "their coordinates; check them in separate files")
    return coords


def _units(qs, name: str) -> str:
    """Units of column ``name``: its quantity's, or those of a coordinate, which every
    quantity of the file must state alike."""
    for q in qs:
        if name == q.name:
            return q.units
    units = {q.units_of(name) for q in qs}
    if len(units) != 1:
        raise UsageError(f"coordinate {name} has units {sorted(units)} in the quantities "
                         f"{[q.name for q in qs]}; check them in separate files")
    return units.pop()


def _what(found, coords, quantity) -> str:
    """``the quantity X or its coordinates [...]`` for a refusal message."""
    if len(found) == 1:
        text = f"the quantity {found[0]} or its coordinates {list(coords)}"
    else:
        text = f"the quantities {found} or their coordinates {list(coords)}"
    if quantity:
        text += (" (a quantity was named, so only it is checked: drop --quantity to check "
                 "every quantity column of the file)")
    return text


def _quantity_of(prob, name: str):
    from debench.reference import problems

    try:
        return prob.quantity(name)
    except problems.ProblemError as exc:
        raise UsageError(str(exc)) from None
