"""Users' results files (CSV with a units header, or netCDF) read for the quantities of a
reference problem they hold: the reader behind ``debench check`` and submissions, and the
usage error it raises on bad input (the command line's exit code 2)."""

from __future__ import annotations

import codecs
import csv
import difflib
from pathlib import Path

import numpy as np

#: exit codes of ``debench``: 0 ok; 1 a check or verification failed; 2 usage error; 3
#: runtime error (a computation failed)
EXIT_OK, EXIT_FAILED, EXIT_USAGE, EXIT_RUNTIME = 0, 1, 2, 3

#: the metadata file that makes a folder a submission (:mod:`debench.reference.submissions`);
#: named here, below the submissions, so that a folder given as a results file is told apart
METADATA_NAME = "submission.toml"


class UsageError(ValueError):
    """Bad command-line input (exit code :data:`EXIT_USAGE`)."""


#: spellings of the dimensionless unit that engineers write and cf-units does not read as
#: 1 ('-' is its "no unit", 'dimensionless' it does not parse)
DIMENSIONLESS = {"-": "1", "dimensionless": "1"}


def _unit(spelled: str | None, expected: str, column: str, where: str):
    """A converter of a column in units ``spelled`` to ``expected`` (compared by
    meaning with cf-units, the UDUNITS-2 library of the CF conventions: ``J/m3`` ==
    ``J m-3``, ``kPa`` converts to ``Pa``; :data:`DIMENSIONLESS` spellings are 1).
    ``expected == ""``: a text coordinate, no units. UsageError for missing, unknown or
    incompatible units."""
    import cf_units

    if expected == "":
        if spelled:
            raise UsageError(f"{where}: {column} is a text coordinate and takes no units, "
                             f"got [{spelled}]")
        return None
    if spelled is None or not spelled.strip():
        raise UsageError(f"{where}: {column} has no units; write them as '{column} "
                         f"[{expected}]' ('1' for a dimensionless quantity)")
    spelled = spelled.strip()
    try:
        got = cf_units.Unit(DIMENSIONLESS.get(spelled.lower(), spelled))
        want = cf_units.Unit(expected)
    except ValueError:
        raise UsageError(f"{where}: {column} has units [{spelled}], which cf-units "
                         "(UDUNITS-2) does not parse") from None
    if got.is_unknown() or got.is_no_unit() or not got.is_convertible(want):
        raise UsageError(f"{where}: {column} has units [{spelled}], not convertible to "
                         f"the expected [{expected}]")
    return lambda x: got.convert(np.asarray(x, dtype=float), want)


def read_results(path: Path, quantity: str | None, prob) -> tuple[tuple[str, ...], dict]:
    """Columns of a user's results file for the quantities of ``prob`` it holds.

    Parameters
    ----------
    path
        A CSV file with the header ``name [units]`` (columns separated by a comma, a
        semicolon or a tab, spaces around them allowed; UTF-8 with or without a
        byte-order mark, or UTF-16 with one; lines starting with '#' skipped), or a
        netCDF file (``.nc``, ``.nc4``, ``.cdf``: variables named like the coordinates and
        the quantities, with a ``units`` attribute, broadcast against the first quantity).
    quantity
        The one quantity to check (None: every quantity of ``prob`` the file holds).
    prob
        The :class:`~debench.reference.problems.Problem`.

    Returns
    -------
    tuple
        The names of the quantities found (in the file's order; ``quantity``: that one
        alone) and ``{column: values}``. An empty cell, ``nan`` or ``NaN`` in a
        quantity's column is NaN (no value there, e.g. no event).

    Raises
    ------
    UsageError
        Several quantities that do not share their coordinates (each row is one point of
        every quantity); a numeric column without units or with units not convertible to
        the problem's (units are compared by meaning and converted); a column that is
        neither one of the quantities nor one of their coordinates (with ``quantity``
        given, another quantity's column too: the message suggests the column name it
        resembles and shows the expected header), or a repeated column; a directory, a
        file that is not UTF-8 or UTF-16 text, a header whose columns cannot be told
        apart, a row with another number of cells than the header, a cell that is not a
        number (a decimal comma is named), an empty coordinate cell.
    """
    path = Path(path)
    _check_is_file(path)
    names = [q.name for q in prob.quantities]
    if path.suffix in (".nc", ".nc4", ".cdf"):
        import xarray as xr

        with xr.open_dataset(path) as ds:
            found = _quantities_in(path, [n for n in ds.data_vars], names, quantity,
                                   "variable", prob)
            qs = [_quantity_of(prob, n) for n in found]
            coords = _shared_coordinates(path, qs)
            unknown = sorted(set(ds.data_vars) - {*found, *coords})
            if unknown:
                raise UsageError(f"{path}: variables {unknown} are not "
                                 f"{_what(found, coords, quantity)}"
                                 + _hint(unknown, qs if quantity else _sharing(prob, coords),
                                         prob, "variable"))
            _check_coordinates(path, list(ds.variables), qs, coords, "variable", prob)
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
    rows, lines = _csv_rows(path)
    header, spelled = [], {}
    for cell in rows[0]:
        name, bracket, rest = cell.strip().partition("[")
        name = name.strip()
        if name in spelled:
            raise UsageError(f"{path}: column {name} appears twice in the header")
        header.append(name)
        spelled[name] = rest.rstrip().removesuffix("]").strip() if bracket else None
    found = _quantities_in(path, header, names, quantity, "column", prob)
    qs = [_quantity_of(prob, n) for n in found]
    coords = _shared_coordinates(path, qs)
    unknown = [n for n in header if n not in (*found, *coords)]
    if unknown:
        raise UsageError(f"{path}: columns {unknown} are not "
                         f"{_what(found, coords, quantity)}"
                         + _hint(unknown, qs if quantity else _sharing(prob, coords), prob))
    _check_coordinates(path, header, qs, coords, "column", prob)
    cols = {}
    for j, name in enumerate(header):
        conv = _unit(spelled[name], _units(qs, name), name, str(path))
        raw = [r[j].strip() for r in rows[1:]]
        if conv is None:
            cols[name] = np.array(raw)
            continue
        cols[name] = conv(_numbers(path, name, raw, lines[1:], empty_is_nan=name in found))
    return tuple(found), cols


#: the column separators of ordinary CSV files: comma, semicolon (spreadsheets in
#: locales with a decimal comma) and tab (spreadsheets' "text" export)
DELIMITERS = (",", ";", "\t")


def _check_is_file(path: Path) -> None:
    """UsageError unless ``path`` is a file: a directory is named as one (one holding
    submission metadata: the ``--submission`` form is suggested), else it does not
    exist."""
    if path.is_file():
        return
    if path.is_dir():
        hint = (f"; it holds {METADATA_NAME}: to check a submission folder, run "
                f"'debench check --submission {path}'" if (path / METADATA_NAME).is_file()
                else "; give the path of a CSV or netCDF file")
        raise UsageError(f"FILE {path} is a directory, not a results file{hint}")
    raise UsageError(f"FILE {path} does not exist")


#: file suffixes of spreadsheet workbooks, which are not read: exported as CSV they are
SPREADSHEETS = (".xlsx", ".xlsm", ".xls", ".ods", ".numbers")


def _decode(path: Path) -> str:
    """The text of a CSV file: UTF-8, with or without a byte-order mark (Excel's "CSV
    UTF-8"), or UTF-16 with its mark (Excel's "Unicode text"); UsageError otherwise (a
    spreadsheet workbook named as one)."""
    if path.suffix.lower() in SPREADSHEETS:
        raise UsageError(f"{path} is a spreadsheet workbook: save it as CSV (Excel: 'CSV "
                         "UTF-8 (comma delimited)') with the header in its first row")
    raw = path.read_bytes()
    if raw.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        return raw.decode("utf-16")
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise UsageError(f"{path}: not UTF-8 text (byte {exc.start}): save the file as "
                         "UTF-8 (Excel: 'CSV UTF-8')") from None


def _csv_rows(path: Path) -> tuple[list[list[str]], list[int]]:
    """The header and rows of a CSV file (lines starting with '#' and blank lines
    skipped), separated by one of :data:`DELIMITERS` (spaces around it allowed): the one
    the header holds, or, if it holds several, the one that splits every row into as many
    cells as the header; and the line number of each in the file. UsageError when the
    columns cannot be told apart or a row has another number of cells than the header."""
    numbered = [(i, ln) for i, ln in enumerate(_decode(path).splitlines(), start=1)
                if ln.strip() and not ln.lstrip().startswith("#")]
    lines = [ln for _, ln in numbered]
    linenos = [i for i, _ in numbered]
    if len(lines) < 2:
        raise UsageError(f"{path}: expected a header and at least one row")

    def split(sep):
        return [[c.strip() for c in r]
                for r in csv.reader(lines, delimiter=sep, skipinitialspace=True)]

    present = [d for d in DELIMITERS if d in lines[0]]
    if len(present) > 1:
        fits = [d for d in present if {len(r) for r in split(d)} == {len(split(d)[0])}]
        if len(fits) != 1:
            raise UsageError(f"{path}: cannot tell the column separator: the header holds "
                             f"{[*map(_show_sep, present)]}; separate the columns with one "
                             "of ',', ';' or a tab")
        present = fits
    rows = split(present[0] if present else ",")
    if len(rows[0]) > 1 and all(r and r[-1] == "" for r in rows):
        rows = [r[:-1] for r in rows]   # every line ends with the separator
    if len(rows[0]) == 1 and (rows[0][0].count("[") > 1 or "|" in rows[0][0]
                              or len(rows[0][0].partition("[")[0].split()) > 1):
        raise UsageError(f"{path}: the header {rows[0][0]!r} is one column: separate the "
                         "columns with ',', ';' or a tab (spaces around it are allowed)")
    for r, line in zip(rows[1:], linenos[1:], strict=False):
        if len(r) != len(rows[0]):
            sep = _show_sep(present[0] if present else ",")
            raise UsageError(f"{path}, line {line}: {len(r)} cell(s), the header has "
                             f"{len(rows[0])} (separator {sep})")
    return rows, linenos


def _show_sep(sep: str) -> str:
    return "tab" if sep == "\t" else repr(sep)


def _numbers(path, name: str, raw: list[str], lines: list[int],
             empty_is_nan: bool) -> np.ndarray:
    """The cells ``raw`` of column ``name`` (on the file's ``lines``) as floats ('nan'
    and 'NaN' are NaN; an empty cell is NaN in a quantity's column (``empty_is_nan``: no
    value, e.g. no event) and refused in a coordinate's). UsageError naming the column
    and the line of the first bad cell."""
    out = np.empty(len(raw))
    for k, x in enumerate(raw):
        if not x and empty_is_nan:
            out[k] = np.nan
            continue
        try:
            out[k] = float(x)
        except ValueError:
            what = "is empty" if not x else f"holds {x!r}, which is not a number"
            if x.count(",") == 1 and x.replace(",", "", 1).lstrip("+-").isdigit():
                what += " (a decimal comma: write decimal points)"
            line = lines[k] if k < len(lines) else "?"
            raise UsageError(f"{path}, line {line}: column {name} {what}") from None
    return out


def _quantities_in(path, present, names, quantity, kind: str, prob) -> list[str]:
    """The quantities to check: ``quantity`` (which must be present), else every
    quantity of the problem that ``present`` (the file's columns) names."""
    found = [quantity] if quantity else [n for n in present if n in names]
    if not found or found[0] not in present:
        qs = [_quantity_of(prob, quantity)] if quantity else list(prob.quantities)
        known = {n for q in prob.quantities for n in (q.name, *q.coordinates)}
        raise UsageError(f"{path}: no {kind} for quantity {quantity or names}; "
                         f"{'header' if kind == 'column' else 'variables'} {list(present)}"
                         + _hint([n for n in present if n not in known], qs, prob, kind))
    return found


def expected_header(qs) -> str:
    """The CSV header line of a file of the quantities ``qs`` (which share their
    coordinates): each coordinate, then each quantity, as ``name [units]`` (a text
    coordinate without units)."""
    def cell(q, name):
        units = q.units_of(name)
        return f"{name} [{units}]" if units else name

    q0 = qs[0]
    return ",".join([*(cell(q0, c) for c in q0.coordinates), *(cell(q, q.name) for q in qs)])


def _hint(unknown, qs, prob, kind: str = "column") -> str:
    """``; 'Lam' is not a column of this problem; did you mean 'lam'? expected header:
    ...`` for a refusal naming the columns ``unknown`` (the file's quantities ``qs``, or
    every quantity of ``prob`` when none was found: one header per group of quantities
    that share their coordinates)."""
    known = list(dict.fromkeys(n for q in prob.quantities for n in (*q.coordinates, q.name)))
    lower = {k.lower(): k for k in known}
    out = []
    for name in unknown:
        key = name.lower()
        if key not in lower:
            key = next(iter(difflib.get_close_matches(key, list(lower), n=1)), None)
        if key is not None and lower[key] != name:
            out.append(f"'{name}' is not a {kind} of this problem; did you mean "
                       f"'{lower[key]}'?")
    groups: dict[tuple, list] = {}
    for q in qs:
        groups.setdefault(tuple(sorted(q.coordinates)), []).append(q)
    if kind == "column":
        headers = [expected_header(g) for g in groups.values()]
        what = "header"
    else:
        headers = [", ".join([*g[0].coordinates, *(q.name for q in g)]) + " (each with a "
                   "units attribute)" for g in groups.values()]
        what = "variables"
    out.append((f"expected {what}: " if len(headers) == 1 else
                f"expected {what} (one set per file): ") + "; ".join(headers))
    dflt = sorted({c for q in qs for c in q.defaults})
    if dflt:
        out[-1] += f" (columns with a default may be left out: {', '.join(dflt)})"
    return "; " + " ".join(out)


def _sharing(prob, coords) -> list:
    """The quantities of ``prob`` whose coordinates are ``coords``."""
    return [q for q in prob.quantities if set(q.coordinates) == set(coords)]


def _check_coordinates(path, present, qs, coords, kind: str, prob) -> None:
    """UsageError naming the coordinates of ``qs`` without a default that ``present`` (the
    file's columns or variables) lacks, with the expected header."""
    missing = [c for c in coords if c not in present and not all(c in q.defaults for q in qs)]
    if missing:
        raise UsageError(f"{path}: no {kind} for the coordinates {missing} of "
                         f"{', '.join(q.name for q in qs)}" + _hint([], qs, prob, kind))


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
