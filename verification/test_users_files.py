"""``debench check`` on the files users write: semicolon- and tab-separated CSV, an Excel
byte-order mark, a misspelt column, a directory given as FILE, no-event cells, curves of a
single stored point, stored coordinates a round-off away, and range messages that show
the excess. Each right file is accepted (exit 0) and a wrong one still fails (exit 1) or
is refused with a message naming what is wrong (exit 2)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from debench.reference import cli, problems, problems_reference

#: the closed-form free-membrane reference over its whole range, as densely as its grid
FREE_LAM = np.linspace(1.0, 5.0, 401)
#: a relative perturbation far above every stated accuracy of the problems used here (the
#: free membrane's atol 1e-12, ch3's and ch4's rtol 1e-7)
PERTURBATION = 1e-4


def _free_phibar(lam):
    return np.sqrt(lam**-2 - lam**-8)


def _write(path, header, rows, sep=",", encoding="utf-8"):
    """A CSV of ``header`` (cells) and ``rows`` (cells, written as given) joined by ``sep``."""
    lines = [sep.join(header), *(sep.join(r) for r in rows)]
    path.write_text("\n".join(lines) + "\n", encoding=encoding)
    return str(path)


def _free_rows(scale=1.0):
    return [[repr(float(a)), repr(float(b) * scale)]
            for a, b in zip(FREE_LAM, _free_phibar(FREE_LAM), strict=True)]


FREE_HEADER = ["lam [1]", "phibar [1]"]


# ------------------------------------------------------------------ dialects and encodings

@pytest.mark.parametrize("sep", [";", "\t", "; ", ", ", " , ", "\t "],
                         ids=["semicolon", "tab", "semicolon-space", "comma-space",
                              "spaced-comma", "tab-space"])
def test_check_reads_semicolon_tab_and_spaced_csv(tmp_path, capsys, sep):
    """The same right file in each ordinary dialect matches (exit 0); scaled by 1 + 1e-4
    it fails (exit 1): the columns are read, not skipped."""
    ok = _write(tmp_path / "ok.csv", FREE_HEADER, _free_rows(), sep)
    assert cli.main(["check", "ch3_free_membrane_nh", ok]) == 0
    assert "MATCHES: 401/401" in capsys.readouterr().out
    bad = _write(tmp_path / "bad.csv", FREE_HEADER, _free_rows(1 + PERTURBATION), sep)
    assert cli.main(["check", "ch3_free_membrane_nh", bad]) == 1


@pytest.mark.parametrize("header, rows, message", [
    ("lam [1] phibar [1]", ["1.5 0.4"], "separate the columns with ',', ';' or a tab"),
    ("lam [1]|phibar [1]", ["1.5|0.4"], "separate the columns with ',', ';' or a tab"),
    ("lam [1],phibar [1]", ["1.5,0.4", "# a comment", "1.6"],
     "line 4: 1 cell(s), the header has 2"),
    ("lam [1];phibar [1]", ["1,5;0,4"],
     "line 2: column lam holds '1,5', which is not a number (a decimal comma"),
    ("lam [1],phibar [1]", ["1.5,0.4", ",0.5"], "line 3: column lam is empty"),
])
def test_check_refuses_a_file_whose_columns_it_cannot_read(tmp_path, capsys, header, rows,
                                                            message):
    """Space- or bar-separated columns, a short row, a decimal comma, an empty coordinate
    cell: usage errors (exit 2) saying what to change and where."""
    path = tmp_path / "x.csv"
    path.write_text("\n".join([header, *rows]) + "\n")
    assert cli.main(["check", "ch3_free_membrane_nh", str(path), "--partial"]) == 2
    assert message in capsys.readouterr().err


@pytest.mark.parametrize("encoding, sep", [("utf-8-sig", ","), ("utf-16", "\t")],
                         ids=["excel-csv-utf8", "excel-unicode-text"])
def test_check_reads_a_byte_order_mark(tmp_path, capsys, encoding, sep):
    """Excel's "CSV UTF-8" (a UTF-8 byte-order mark) and "Unicode text" (UTF-16, tab
    separated) are read: the mark is not part of the first column's name."""
    path = _write(tmp_path / "bom.csv", FREE_HEADER, _free_rows(), sep, encoding)
    assert cli.main(["check", "ch3_free_membrane_nh", path]) == 0
    assert "MATCHES" in capsys.readouterr().out


def test_check_refuses_text_that_is_not_utf8(tmp_path, capsys):
    path = tmp_path / "latin1.csv"
    path.write_bytes("lam [1],phibar [1]\n1.5,0.4 \xb5\n".encode("latin-1"))
    assert cli.main(["check", "ch3_free_membrane_nh", str(path), "--partial"]) == 2
    assert "not UTF-8" in capsys.readouterr().err


def test_check_reads_rows_ending_in_a_separator(tmp_path, capsys):
    """Some writers end every line with the separator: the empty last column is no
    column."""
    rows = [[*r, ""] for r in _free_rows()]
    path = _write(tmp_path / "trail.csv", [*FREE_HEADER, ""], rows, ";")
    assert cli.main(["check", "ch3_free_membrane_nh", path]) == 0
    assert "MATCHES: 401/401" in capsys.readouterr().out


@pytest.mark.parametrize("suffix", [".xlsx", ".ods"])
def test_check_refuses_a_spreadsheet_workbook_saying_to_export_csv(tmp_path, capsys,
                                                                   suffix):
    path = tmp_path / f"results{suffix}"
    path.write_bytes(b"PK\x03\x04" + bytes(60))
    assert cli.main(["check", "ch3_free_membrane_nh", str(path)]) == 2
    assert "a spreadsheet workbook: save it as CSV" in capsys.readouterr().err


@pytest.mark.parametrize("units", ["-", "dimensionless", "%"])
def test_check_reads_dimensionless_spelled_as_engineers_do(tmp_path, capsys, units):
    """'[-]' and '[dimensionless]' are the dimensionless unit 1 (cf-units reads '-' as
    "no unit" and does not parse 'dimensionless'); '%' converts by 1/100; '[-]' on a
    dimensional quantity is still refused."""
    scale = 100.0 if units == "%" else 1.0
    rows = [[repr(float(a)), repr(float(b) * scale)]
            for a, b in zip(FREE_LAM, _free_phibar(FREE_LAM), strict=True)]
    path = _write(tmp_path / "u.csv", ["lam [-]", f"phibar [{units}]"], rows)
    assert cli.main(["check", "ch3_free_membrane_nh", path]) == 0
    assert "MATCHES: 401/401" in capsys.readouterr().out
    bad = tmp_path / "w.csv"
    bad.write_text("material,state,W [-]\nnh,uniaxial,1.0\n")
    assert cli.main(["check", "ch2_kernel_states", str(bad), "--partial"]) == 2
    assert "W has units [-], not convertible to the expected [J m-3]" in capsys.readouterr().err


# ------------------------------------------------------------------ column names

@pytest.mark.parametrize("header, hint", [
    (["Lam [1]", "phibar [1]"], "'Lam' is not a column of this problem; did you mean 'lam'?"),
    (["lam [1]", "Phibar [1]"], "'Phibar' is not a column of this problem; did you mean "
                                "'phibar'?"),
    (["lam [1]", "phi [1]"], "expected header: lam [1],phibar [1]"),
])
def test_check_names_the_expected_column(tmp_path, capsys, header, hint):
    """A column name in the wrong case or misspelt is refused (exit 2) with the name it
    resembles and the expected header line."""
    path = _write(tmp_path / "x.csv", header, _free_rows())
    assert cli.main(["check", "ch3_free_membrane_nh", path]) == 2
    err = capsys.readouterr().err
    assert hint in err and "expected header: lam [1],phibar [1]" in err


def test_check_names_the_expected_netcdf_variable(tmp_path, capsys):
    """netCDF: a variable in the wrong case gets the same hint, naming the variables."""
    import xarray as xr

    ds = xr.Dataset({"Phibar": ("n", _free_phibar(FREE_LAM), {"units": "1"}),
                     "lam": ("n", FREE_LAM, {"units": "1"})})
    ds.to_netcdf(tmp_path / "x.nc")
    assert cli.main(["check", "ch3_free_membrane_nh", str(tmp_path / "x.nc")]) == 2
    err = capsys.readouterr().err
    assert "did you mean 'phibar'?" in err and "expected variables: lam, phibar" in err


@pytest.mark.parametrize("problem, text, missing, header", [
    ("ch3_free_membrane_nh", "phibar [1]\n0.4\n", "['lam']", "lam [1],phibar [1]"),
    ("ch4_plate_voltage_control", "xi [1],kH [1],lam_cr [1]\n0,0.01,1.02\n", "['Vhat']",
     "variant,xi [1],Vhat [1],root [1],kH [1],lam_cr [1]"),
])
def test_check_names_a_missing_coordinate_column(tmp_path, capsys, problem, text,
                                                  missing, header):
    """A coordinate column left out (one without a default) is refused naming it, with
    the expected header."""
    path = tmp_path / "x.csv"
    path.write_text(text)
    assert cli.main(["check", problem, str(path), "--partial"]) == 2
    err = capsys.readouterr().err
    assert f"no column for the coordinates {missing}" in err
    assert f"expected header: {header}" in err


def test_check_says_a_directory_is_a_directory(tmp_path, capsys):
    """A folder as FILE: said to be a folder; one holding submission metadata: the
    ``--submission`` form is suggested."""
    folder = tmp_path / "adir"
    folder.mkdir()
    assert cli.main(["check", "ch3_free_membrane_nh", str(folder)]) == 2
    err = capsys.readouterr().err
    assert "is a directory, not a results file" in err and "does not exist" not in err
    assert "--submission" not in err
    (folder / "submission.toml").write_text("")
    assert cli.main(["check", "ch3_free_membrane_nh", str(folder)]) == 2
    assert f"debench check --submission {folder}" in capsys.readouterr().err


# ------------------------------------------------------------------ no-event cells

def _failure_points_rows(no_event):
    """Every stored (lamP, c) of ch3_failure_points with a value of at least one quantity,
    all six quantities at their reference values; ``no_event`` is written where the
    reference has no event (NaN)."""
    ref = problems_reference.reference_json(problems.get("ch3_failure_points"))["reference"]
    names = list(ref)
    lamP, c = (ref[names[0]]["coords"][k] for k in ("lamP", "c"))
    rows = []
    for i, a in enumerate(lamP):
        for j, b in enumerate(c):
            vals = [ref[n]["values"][i][j] for n in names]
            if any(v is not None for v in vals):
                rows.append([repr(a), repr(b),
                             *(no_event if v is None else repr(v) for v in vals)])
    return ["lamP [1]", "c [1]", *(f"{n} [1]" for n in names)], rows


@pytest.mark.parametrize("no_event", ["", "nan", "NaN"])
def test_failure_points_in_one_file_match_with_no_event_cells(tmp_path, capsys, no_event):
    """The one file the spec asks for (six quantities, every (lamP, c)) matches when the
    cases without an event are empty, nan or NaN."""
    header, rows = _failure_points_rows(no_event)
    assert any(no_event in r[2:] for r in rows)
    path = _write(tmp_path / "fp.csv", header, rows)
    assert cli.main(["check", "ch3_failure_points", path]) == 0
    out = capsys.readouterr().out
    assert "ch3_failure_points MATCHES: all 6 quantities" in out
    assert "of them no value (NaN) where the reference has none" in out


def test_failure_points_number_for_no_event_or_no_event_for_a_number_fails(tmp_path,
                                                                           capsys):
    """A value where the reference has no event, and no event where it has a value, are
    mismatches (exit 1) naming the quantity."""
    header, rows = _failure_points_rows("")
    k = next(i for i, r in enumerate(rows) if r[2] == "")
    rows[k][2] = "1.5"
    path = _write(tmp_path / "a.csv", header, rows)
    assert cli.main(["check", "ch3_failure_points", path]) == 1
    assert "1 of 6 quantities failed (pullin_lambda)" in capsys.readouterr().out
    header, rows = _failure_points_rows("")
    k = next(i for i, r in enumerate(rows) if r[6] != "")
    rows[k][6] = "NaN"
    path = _write(tmp_path / "b.csv", header, rows)
    assert cli.main(["check", "ch3_failure_points", path]) == 1
    assert "1 of 6 quantities failed (breakdown_lambda)" in capsys.readouterr().out


def test_compare_counts_no_event_as_a_match_only_where_the_reference_has_none():
    """The API: NaN against a NaN reference matches (ratio 0), a number there fails, NaN
    against a value fails; the spec's domain says so."""
    from debench.testing import compare

    p = problems.get("ch3_failure_points")
    q = p.quantity("pullin_lambda")
    ref = problems_reference.reference_json(p)["reference"][q.name]
    i, j = next((i, j) for i, row in enumerate(ref["values"]) for j, v in enumerate(row)
                if v is None and i < len(ref["coords"]["lamP"]) - 1)
    coords = {"lamP": ref["coords"]["lamP"][i], "c": ref["coords"]["c"][j]}
    assert compare(p.id, q.name, np.nan, coords, coverage="partial").ratio[0] == 0.0
    assert not compare(p.id, q.name, 1.5, coords, coverage="partial").passed
    i, j = next((i, j) for i, row in enumerate(ref["values"]) for j, v in enumerate(row)
                if v is not None)
    coords = {"lamP": ref["coords"]["lamP"][i], "c": ref["coords"]["c"][j]}
    assert not compare(p.id, q.name, np.nan, coords, coverage="partial").passed
    for q in p.quantities:
        assert "an empty cell, nan or NaN" in q.domain["window"], q.name


# ------------------------------------------------------------------ stored coordinates

def _plate_rows(problem, kH=lambda k, i: repr(k)):
    """Every finite stored point of the 'derived' variant of a ch4 problem (every root),
    with kH written by ``kH(value, index)``; the header and the rows."""
    ref = problems_reference.reference_json(problems.get(problem))["reference"]["lam_cr"]
    dims, co = ref["dims"], ref["coords"]
    vals = np.array(ref["values"], dtype=float)
    sel = [d for d in dims if d not in ("variant", "kH")]
    rows = []
    for idx in np.ndindex(*vals.shape):
        at = dict(zip(dims, idx, strict=True))
        if co["variant"][at["variant"]] != "derived" or not np.isfinite(vals[idx]):
            continue
        rows.append([str(co[d][at[d]]) for d in sel]
                    + [kH(co["kH"][at["kH"]], at["kH"]), repr(float(vals[idx]))])
    return [*(f"{d} [1]" for d in sel), "kH [1]", "lam_cr [1]"], rows


@pytest.mark.parametrize("problem", ["ch4_plate_voltage_control",
                                     "ch4_plate_critical_stretch"])
def test_plate_complete_file_with_single_point_curves_matches(tmp_path, capsys, problem):
    """The complete file of every root (some root numbers exist at one stored kH only)
    matches; that point off by 1e-4 fails; left out, coverage refuses the file."""
    header, rows = _plate_rows(problem)
    path = _write(tmp_path / "all.csv", header, rows)
    assert cli.main(["check", problem, path]) == 0
    assert "MATCHES" in capsys.readouterr().out
    curves: dict[tuple, list[int]] = {}
    for k, r in enumerate(rows):
        curves.setdefault(tuple(r[:3]), []).append(k)
    single = next(idx[0] for idx in curves.values() if len(idx) == 1)
    off = [list(r) for r in rows]
    off[single][-1] = repr(float(off[single][-1]) * (1 + PERTURBATION))
    assert cli.main(["check", problem, _write(tmp_path / "off.csv", header, off)]) == 1
    capsys.readouterr()
    left = [r for k, r in enumerate(rows) if k != single]
    assert cli.main(["check", problem, _write(tmp_path / "left.csv", header, left)]) == 2
    assert "not covered" in capsys.readouterr().err


def _kH_percent(header, rows):
    """``header`` and ``rows`` of :func:`_plate_rows` with kH in %."""
    return ([h if h != "kH [1]" else "kH [%]" for h in header],
            [[*r[:-2], repr(float(r[-2]) * 100), r[-1]] for r in rows])


#: ch4_plate_voltage_control's kH grid: 81 points, geometric from 0.01 to 20
VC_KH = (0.01, 2000.0, 80)


@pytest.mark.parametrize("how", ["percent", "12-digits", "ulp-up", "ulp-down", "power"])
def test_plate_kH_a_round_off_from_a_stored_value_is_that_value(tmp_path, capsys, how):
    """kH given in % (converted), to 12 significant digits, one ulp off, or computed as
    0.01 * 2000**(i/80) instead of numpy.geomspace: the complete file still matches."""
    start, ratio, n = VC_KH
    write = {"12-digits": lambda k, i: f"{k:.12g}",
             "ulp-up": lambda k, i: repr(math.nextafter(k, math.inf)),
             "ulp-down": lambda k, i: repr(math.nextafter(k, -math.inf)),
             "power": lambda k, i: repr(start * ratio ** (i / n))}.get(how)
    header, rows = _plate_rows("ch4_plate_voltage_control", *([write] if write else []))
    if how == "percent":
        header, rows = _kH_percent(header, rows)
    else:
        stored = [r[-2] for r in _plate_rows("ch4_plate_voltage_control")[1]]
        assert any(float(r[-2]) != float(k) for r, k in zip(rows, stored, strict=True))
    path = _write(tmp_path / "kH.csv", header, rows)
    assert cli.main(["check", "ch4_plate_voltage_control", path]) == 0
    assert "MATCHES" in capsys.readouterr().out


@pytest.mark.parametrize("how", ["percent", "12-digits"])
def test_plate_kH_a_round_off_from_a_stored_value_matches_charge_control(tmp_path, how):
    """The same for ch4_plate_critical_stretch (401 kH), whose curves have pieces of two
    and three stored points between jumps, too short to spline: a kH a round-off from one
    of their points is that point."""
    if how == "percent":
        header, rows = _kH_percent(*_plate_rows("ch4_plate_critical_stretch"))
    else:
        header, rows = _plate_rows("ch4_plate_critical_stretch", lambda k, i: f"{k:.12g}")
    assert cli.main(["check", "ch4_plate_critical_stretch",
                     _write(tmp_path / "kH.csv", header, rows)]) == 0


def test_a_coordinate_between_stored_values_is_not_snapped():
    """Off the grid by far more than round-off (1e-6 relative) inside a jump of the root
    numbering: still refused, naming the jump."""
    ref = problems_reference.reference_json(
        problems.get("ch4_plate_voltage_control"))["reference"]["lam_cr"]
    p = problems.get("ch4_plate_voltage_control")
    q = p.quantity()
    kH = np.array(ref["coords"]["kH"])
    y = np.array(ref["values"], float)[0, 0, 0, :, 0]      # derived, xi = 0, Vhat = 0.25
    pieces = problems_reference.curve_pieces(np.log(kH), y)
    end = pieces[0][1]
    assert end < kH.size - 1 and np.isfinite(y[end + 1])   # a jump, not a gap
    coords = {"xi": 0.0, "Vhat": 0.25, "kH": kH[end] * (1 + 1e-6)}
    with pytest.raises(ValueError, match="on a jump"):
        problems_reference.reference_at(p, q, coords)
    near = problems_reference.reference_at(p, q, {**coords, "kH": kH[end] * (1 + 1e-13)})
    assert near.value[0] == y[end]
    # the change of the curve over that distance is added to the tolerance: tiny
    stated = near.tolerance[0] - near.interpolation[0]
    assert 0 < near.interpolation[0] < 1e-3 * stated


# ------------------------------------------------------------------ messages

def test_range_message_shows_the_excess():
    """Just beyond the end of a stored curve (ch3_voltage_stretch, lamP = 1.1, c = 0) and
    of a closed form's range: the limit and the value are printed with the digits that
    show the difference, as plain numbers."""
    p = problems.get("ch3_voltage_stretch")
    ref = problems_reference.reference_json(p)["reference"]["phibar"]
    assert ref["dims"] == ["lamP", "c", "point"] and ref["along"]["dims"] == ["lamP", "point"]
    i, j = ref["coords"]["lamP"].index(1.1), ref["coords"]["c"].index(0.0)
    lam = np.array(ref["along"]["values"][i], dtype=float)
    y = np.array(ref["values"][i][j], dtype=float)
    hi = float(np.max(lam[np.isfinite(y)]))
    beyond = hi * (1 + 1e-7)
    with pytest.raises(ValueError) as exc:
        problems_reference.reference_at(p, p.quantity(), {"lamP": 1.1, "c": 0.0,
                                                          "lambda_a": beyond})
    msg = str(exc.value)
    assert f"{hi!r}]; got [{beyond!r}]" in msg and "np.float64" not in msg
    free = problems.get("ch3_free_membrane_nh")
    with pytest.raises(ValueError, match=r"\[1\.0, 5\.0\] \(problem ch3_free_membrane_nh\); "
                                         r"got \[5\.000001\]"):
        problems_reference.reference_at(free, free.quantity(), {"lam": 5.000001})


@pytest.mark.parametrize("problem", problems.load_all(), ids=lambda p: p.id)
def test_the_header_a_problem_page_shows_is_the_one_check_reads(tmp_path, problem):
    """Each quantity's header on the page, with a row of reference coordinates, is read
    back as that quantity."""
    from debench.reference.problems_markdown import render_markdown
    from debench.reference.results_files import expected_header, read_results

    page = render_markdown(problem)
    ref = problems_reference.reference_json(problem)["reference"]
    for q in problem.quantities:
        header = expected_header([q])
        assert f"with the header `{header}`" in page
        first = {c: ref[q.name]["coords"][c][0] for c in q.select
                 if c in ref[q.name]["coords"]}
        if q.along:
            x = ref[q.name].get("along", {}).get("values") or ref[q.name]["coords"][q.along]
            while isinstance(x, list):
                x = x[0]
            first[q.along] = x
        # --json writes a non-finite coordinate (lit_balloon's Jm = inf) as null; a file
        # spells it inf, as the page says
        row = [str(v) if v is not None else "inf"
               for v in (first.get(c, q.defaults.get(c, 1.0)) for c in q.coordinates)]
        path = _write(tmp_path / f"{q.name}.csv", header.split(","), [[*row, "1.0"]])
        assert read_results(path, None, problem)[0] == (q.name,)
