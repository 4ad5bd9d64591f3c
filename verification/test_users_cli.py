"""What users see: ``debench problems``, ``check``, ``cite``; exit codes (0 ok, 1 check
failed, 2 usage, 3 runtime error); ``--debug`` after the subcommand; chapter aliases;
progress bars only on a terminal; CITATION.cff fields."""

from __future__ import annotations

import io
import json
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
import yaml
from debench.reference import builds, cite, cli, cli_cite, provenance

ROOT = Path(__file__).resolve().parents[1]


def _csv(path, lam, phibar, header="lam [1],phibar [1]"):
    np.savetxt(path, np.column_stack([lam, phibar]), delimiter=",", header=header,
               comments="", fmt="%.17g")
    return path


def test_problems_lists_and_prints_json(capsys):
    assert cli.main(["problems"]) == 0
    assert "ch3_free_membrane_nh" in capsys.readouterr().out
    assert cli.main(["problems", "ch4_plate_critical_stretch", "--json"]) == 0
    blob = json.loads(capsys.readouterr().out)
    ref = blob["reference"]["lam_cr"]
    assert blob["spec"]["provenance"]["datasets"]["ch4_fig4_2_curves"]["sha256"]
    assert ref["dims"] == ["variant", "xi", "Dhat", "kH", "root"]
    assert len(ref["coords"]["kH"]) == np.shape(ref["values"])[3]
    assert ref["accuracy"]["rtol"] > 0


def test_check_csv_exit_codes(tmp_path, capsys):
    lam = np.linspace(1.05, 2.5, 20)
    good = np.sqrt(lam**-2 - lam**-8)
    assert cli.main(["check", "ch3_free_membrane_nh", str(_csv(tmp_path / "a.csv", lam,
                                                                   good)), "--partial"]) == 0
    assert "MATCHES" in capsys.readouterr().out
    assert cli.main(["check", "ch3_free_membrane_nh",
                     str(_csv(tmp_path / "b.csv", lam, good * 1.001)), "--partial"]) == 1
    out = capsys.readouterr().out
    assert "DOES NOT MATCH" in out and "|err|/tol" in out
    # the user's tolerance is applied
    assert cli.main(["check", "ch3_free_membrane_nh", str(tmp_path / "b.csv"),
                     "--rtol", "0.01", "--partial"]) == 0
    # wrong units in the header, unknown problem, missing file: usage errors
    bad_units = _csv(tmp_path / "c.csv", lam, good, header="lam [m],phibar [1]")
    assert cli.main(["check", "ch3_free_membrane_nh", str(bad_units)]) == 2
    assert cli.main(["check", "no_such_problem", str(tmp_path / "a.csv")]) == 2
    assert cli.main(["check", "ch3_free_membrane_nh", str(tmp_path / "none.csv")]) == 2
    assert "does not exist" in capsys.readouterr().err


def test_check_netcdf_with_selectors(tmp_path):
    """netCDF input: the quantity over (c, lambda_a) with lamP as a scalar coordinate."""
    import xarray as xr
    from debench.reference.datasets import read_dataset

    ds = read_dataset("ch3_voltage_stretch_membrane").sel(lamP=2.0)
    lam = ds.lambda_a.values[1:60]
    phibar = ds.phibar.sel(c=[0.0, -0.053]).values[:, 1:60]
    user = xr.Dataset({"phibar": (("c", "n"), phibar, {"units": "1"}),
                       "lambda_a": ("n", lam, {"units": "1"})},
                      coords={"c": ("c", [0.0, -0.053], {"units": "1"}),
                              "lamP": ((), 2.0, {"units": "1"})})
    user.to_netcdf(tmp_path / "ok.nc")
    assert cli.main(["check", "ch3_voltage_stretch", str(tmp_path / "ok.nc"),
                     "--partial"]) == 0
    user["phibar"] = user.phibar * (1 + 1e-4)
    user.to_netcdf(tmp_path / "bad.nc")
    assert cli.main(["check", "ch3_voltage_stretch", str(tmp_path / "bad.nc"),
                     "--partial"]) == 1
    del user["lamP"].attrs["units"]
    user.to_netcdf(tmp_path / "nounits.nc")
    assert cli.main(["check", "ch3_voltage_stretch", str(tmp_path / "nounits.nc"),
                     "--partial"]) == 2


def test_usage_and_runtime_errors_have_distinct_codes(capsys, monkeypatch):
    with pytest.raises(SystemExit) as exc:
        cli.main(["check"])  # argparse: missing arguments
    assert exc.value.code == 2
    assert cli.main(["cite", "no.such.id"]) == 2

    def boom(args):
        raise RuntimeError("solver failed")

    monkeypatch.setattr(cli_cite, "cmd_cite", boom)
    assert cli.main(["cite", "x"]) == 3
    assert "RuntimeError: solver failed" in capsys.readouterr().err
    with pytest.raises(RuntimeError, match="solver failed"):
        cli.main(["cite", "x", "--debug"])  # --debug after the subcommand


def test_every_subcommand_has_the_function_that_runs_it():
    """The command table names each subcommand of the parser once, and each entry names a
    function of an importable module."""
    parser = cli.build_parser()
    [sub] = [a for a in parser._actions if a.dest == "command"]
    assert set(cli.COMMANDS) == set(sub.choices)
    assert all(callable(cli.command(name)) for name in cli.COMMANDS)


def test_chapter_aliases():
    assert cli.resolve_chapter("ch2") == "ch2_appendix"
    assert cli.resolve_chapter("2") == "ch2_appendix"
    assert cli.resolve_chapter("ch3") == "ch3"
    with pytest.raises(cli.UsageError, match="unknown chapter 'ch9'"):
        cli.resolve_chapter("ch9")
    assert cli.main(["reproduce", "ch9", "--out", "unused"]) == 2


def test_progress_bars_only_on_a_terminal(monkeypatch):
    class Tty(io.StringIO):
        def isatty(self):
            return True

    monkeypatch.setattr("sys.stderr", io.StringIO())
    list(cli.progress_bar(range(3), "x"))
    assert cli.sys.stderr.getvalue() == ""
    monkeypatch.setattr("sys.stderr", Tty())
    list(cli.progress_bar(range(3), "x"))
    assert "x:" in cli.sys.stderr.getvalue()


@pytest.mark.parametrize("item, expect", [
    ("ch3_voltage_stretch", ["ch3_voltage_stretch_membrane.nc sha256",
                             "10.1016/j.mechrescom.2019.103420", "equation 3.17-3.32"]),
    ("ch3_voltage_stretch_as_printed", ["ch3_voltage_stretch.nc sha256", "equation 3.17-3.35"]),
    ("ch3.pullin.voltage_lamP_1p25", ["thesis_values.nc sha256", "page 42",
                                      "10.1016/j.mechrescom.2019.103420"]),
    ("ch4_fig4_2_curves", ["ch4_fig4_2_curves.nc sha256", "zeng_2020"]),
])
def test_cite_names_version_commit_checksum_and_references(item, expect):
    from debench.reference.datasets import data_dir, read_manifest
    from debench.reference.provenance import git_commit

    from debench import __version__

    text = cite.render(item)
    items = json.loads(text[text.index("\n["):])
    assert items[0]["version"] == __version__ and git_commit() in items[0]["note"]
    for e in expect:
        assert e in text, e
    manifest = read_manifest(data_dir())
    for name, meta in manifest.items():
        if f"{name} sha256" in text:
            assert meta["sha256"] in text
    assert text.startswith("@misc{debench_")
    if "ch4" in item:
        assert "mechrescom" not in text  # the Chapter 3 paper only for Chapter 3


def _cite_ids() -> list[str]:
    from debench.reference import catalogue, problems
    from debench.reference.datasets import data_dir, read_manifest

    ids = [p.id for p in problems.load_all()]
    for name in read_manifest(data_dir()):
        ids += [name, name.removesuffix(".nc")]
    return list(dict.fromkeys(ids + [e.id for e in catalogue.load()]))


#: every problem id, dataset name (with and without ``.nc``) and catalogue entry id
CITE_IDS = _cite_ids()


@pytest.mark.parametrize("item", CITE_IDS)
def test_cite_works_for_every_problem_dataset_and_catalogue_entry(item, capsys):
    """``debench cite ID`` exits 0 for every problem, dataset (``NAME`` and ``NAME.nc``)
    and catalogue entry, prints CSL-JSON whose first item names what was cited (a problem
    before a dataset of the same name), cites every reference of a problem's spec (as an
    item, or as text in the note), and, when a name is both a problem and a dataset, says
    on stderr how to cite the dataset."""
    from debench.reference import problems
    from debench.reference.datasets import data_dir, read_manifest

    assert cli.main(["cite", item, "--format", "csl"]) == 0
    out, err = capsys.readouterr()
    items = json.loads(out)
    is_problem = item in {p.id for p in problems.load_all()}
    is_dataset = f"{item.removesuffix('.nc')}.nc" in read_manifest(data_dir())
    first = ("reference problem" if is_problem else "dataset" if is_dataset
             else "catalogue entry")
    head = items[0]["note"].split("; ")[0]  # "dataset ch5_ramps.nc", "catalogue entry (claim) ID"
    assert head.startswith(first) and head.endswith(f" {item}"), head
    if is_problem and is_dataset:
        assert f"`debench cite {item}.nc`" in err
    else:
        assert err == ""
    if is_problem:
        titles = [it["title"].casefold() for it in items[1:]]
        for ref in problems.get(item).references:
            text = " ".join(ref.split())
            assert (ref in {it["id"] for it in items}
                    or any(title in text.casefold() for title in titles)
                    or f"also cites: {text}" in items[0]["note"]), ref


def test_citation_cff_has_repository_data_reference_and_keywords():
    jsonschema = pytest.importorskip("jsonschema")
    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    cff["date-released"] = str(cff["date-released"])
    schema = json.loads((ROOT / "verification/schemas/citation-cff-1.2.0.schema.json")
                        .read_text())
    jsonschema.validate(cff, schema)
    # the URLs are those of [project.urls]: the repository's only once the project has a
    # public address
    assert cff.get("repository-code") == provenance.repository_url()
    thesis = next(r for r in cff["references"] if r["type"] == "thesis")
    assert thesis["url"] == provenance.project_urls()["Thesis"]
    assert any(r["type"] == "data" for r in cff["references"])
    assert any(r.get("doi") == "10.1016/j.mechrescom.2019.103420" for r in cff["references"])
    assert len(cff["keywords"]) >= 8


def test_citation_urls_come_from_the_project_urls(monkeypatch):
    """The BibTeX and CSL-JSON carry the URLs of ``[project.urls]`` (pyproject.toml) and
    no other: the thesis' now, the repository's (and the datasets' ACDD links) once the
    project states one; with none stated, the debench item has no URL."""
    from debench.reference import standards

    urls = provenance.project_urls()
    items = cite.citation("ch3_free_membrane_nh")
    assert "URL" not in items[0] and provenance.repository_url() is None
    assert next(i for i in items if i["id"] == "zeng_2020")["URL"] == urls["Thesis"]
    stated = {**urls, "Source Code": "https://example.org/debench"}
    monkeypatch.setattr(provenance, "project_urls", lambda: stated)
    items = cite.citation("ch5_critical_voltage.nc")
    assert items[0]["URL"] == "https://example.org/debench"
    assert "url = {https://example.org/debench}" in cite.bibtex(items)
    assert standards.acdd_attributes("x", "2026")["metadata_link"] == stated["Source Code"]
    monkeypatch.setattr(provenance, "project_urls", lambda: {})
    assert all("URL" not in i for i in cite.citation("ch3_free_membrane_nh"))


def test_cffconvert_validates_citation_cff():
    """The real tool, when installed (it pins jsonschema<4, so it lives in its own venv:
    ``pipx install cffconvert``)."""
    exe = shutil.which("cffconvert")
    if exe is None:
        pytest.skip("cffconvert not on PATH (pipx install cffconvert)")
    run = subprocess.run([exe, "--validate", "-i", str(ROOT / "CITATION.cff")],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stdout + run.stderr


def test_reproduce_ends_with_a_summary(tmp_path, monkeypatch, capsys):
    """After reproduce: chapters, files written, where, the report, the time taken (the
    builders and the catalogue are stubbed: this checks the CLI, not the physics)."""
    from types import SimpleNamespace

    from debench.reference import catalogue, report

    def build(out, full=False):
        path = Path(out) / "stub.txt"
        path.write_text("x")
        return [path]

    monkeypatch.setattr(builds, "builder", lambda chapter: SimpleNamespace(
        build=build, BUILD_CPU_S=1.0, REGENERATED_BY_VERIFY=False, GUARDS={}))
    monkeypatch.setattr(catalogue, "evaluate_all", lambda progress=None: [])
    monkeypatch.setattr(report, "write_report", lambda out, results, **kw: Path(out) / "R.md")
    monkeypatch.setattr(report, "summary_line", lambda results: "stub")
    assert cli.main(["reproduce", "ch3", "--out", str(tmp_path)]) == 0
    last = capsys.readouterr().out.strip().splitlines()[-1]
    assert last.startswith("reproduce: ch3: wrote 1 file(s) (0 datasets) to ")
    assert str(tmp_path.resolve()) in last and last.endswith(" s")


def _pullin_reference():
    """ch5_pullin's reference values and stated tolerances of each quantity, both films
    (PULLIN_FILMS, in that order)."""
    from debench.reference import problems, problems_reference

    p = problems.get("ch5_pullin")
    return {q.name: problems_reference.reference_at(p, q, {"case": list(PULLIN_FILMS)})
            for q in p.quantities}


#: the cases of ch5_pullin: a file covering both is complete
PULLIN_FILMS = ("nh_r10", "ogden_r10")


def _pullin_csv(path, v, w, header="case,v_pullin [1],w_pullin [1]"):
    """A file of one row per film of PULLIN_FILMS (``v``, ``w``: a value per film)."""
    rows = "".join(f"{c},{float(a)!r},{float(b)!r}\n"
                   for c, a, b in zip(PULLIN_FILMS, v, w, strict=True))
    path.write_text(f"{header}\n{rows}")
    return str(path)


def test_check_two_quantities_in_one_file(tmp_path, capsys):
    """ch5_pullin with v_pullin and w_pullin as two columns: each checked against its own
    reference and tolerance (half of each off the reference passes), the per-quantity
    table lists both; w_pullin 2 tolerances off fails (exit 1), the verdict names it."""
    ref = _pullin_reference()
    v, w = (ref[n].value + 0.5 * ref[n].tolerance for n in ("v_pullin", "w_pullin"))
    assert cli.main(["check", "ch5_pullin", _pullin_csv(tmp_path / "ok.csv", v, w)]) == 0
    out = capsys.readouterr().out
    assert "ch5_pullin MATCHES: all 2 quantities" in out
    table = out.split("per quantity (2):", 1)[1].splitlines()[2:4]
    assert sorted(r.split()[0] for r in table) == ["v_pullin", "w_pullin"]
    assert out.count("coverage complete (2/2") == 2
    w_bad = w.copy()                     # the neo-Hookean film's w_pullin 2 tolerances off
    w_bad[0] = ref["w_pullin"].value[0] + 2.0 * ref["w_pullin"].tolerance[0]
    bad = _pullin_csv(tmp_path / "bad.csv", v, w_bad)
    assert cli.main(["check", "ch5_pullin", bad]) == 1
    out = capsys.readouterr().out
    assert "DOES NOT MATCH: 1 of 2 quantities failed (w_pullin)" in out
    assert "ch5_pullin:v_pullin MATCHES" in out and "ch5_pullin:w_pullin DOES NOT MATCH" in out
    # the worst quantity heads the per-quantity table
    assert out.split("per quantity (2):", 1)[1].splitlines()[2].split()[0] == "w_pullin"
    # a tolerance per quantity: w_pullin's loosened to 1e-3 relative passes it
    assert cli.main(["check", "ch5_pullin", bad, "--rtol", "w_pullin=1e-3"]) == 0
    assert cli.main(["check", "ch5_pullin", bad, "--rtol", "no_such=1e-3"]) == 2
    assert "not a quantity of the file" in capsys.readouterr().err


@pytest.mark.parametrize("header, args, message", [
    ("case,v_pullin [1],w_pullin", [], "w_pullin has no units"),
    ("case,v_pullin [1],w_pullin [m]", [], "not convertible"),
    ("case,v_pullin [1],w_pullin [1],note", [], "columns ['note'] are not the quantities"),
    ("case,v_pullin [1],w_pullin [1],w_pullin [1]", [], "w_pullin appears twice"),
    ("case,v_pullin [1],w_pullin [1]", ["--quantity", "v_pullin"],
     "columns ['w_pullin'] are not the quantity v_pullin"),
])
def test_check_two_quantity_file_keeps_every_refusal(tmp_path, capsys, header, args,
                                                     message):
    """A unit missing or wrong on the second quantity, an unknown or a repeated column,
    another quantity's column when one is named: usage errors (exit 2) naming it."""
    ref = _pullin_reference()
    v, w = (float(ref[n].value[0]) for n in ("v_pullin", "w_pullin"))
    path = tmp_path / "x.csv"
    cells = header.count(",") + 1
    path.write_text(header + "\n" + ",".join(["nh_r10", repr(v), repr(w), repr(w)][:cells])
                    + "\n")
    assert cli.main(["check", "ch5_pullin", str(path), *args]) == 2
    assert message in capsys.readouterr().err


def _wrinkling_rows(skip=()):
    """Every (case, n) with a ch5_wrinkling reference, both quantities, at the reference."""
    from debench.reference.datasets import read_dataset

    ds = read_dataset("ch5_axisym_path").sel(case="ogden_r20")
    w, v = ds.w_cross_converged, ds.v_cross_converged
    return [f"ogden_r20,{int(n)},{float(w.sel(n=n))!r},{float(v.sel(n=n))!r}"
            for n in ds.n.values if np.isfinite(w.sel(n=n)) and int(n) not in skip]


def test_check_two_quantity_file_needs_the_coverage_of_each(tmp_path, capsys):
    """ch5_wrinkling, w_cross and v_cross per wavenumber: every crossing wavenumber covers
    both; one row left out is refused (exit 2) naming the quantity and the missing point,
    and with --partial each quantity reports what it covers."""
    header = "case,n [1],w_cross [1],v_cross [1]"
    path = tmp_path / "w.csv"
    rows = _wrinkling_rows()
    assert len(rows) >= 2
    path.write_text("\n".join([header, *rows]) + "\n")
    assert cli.main(["check", "ch5_wrinkling", str(path)]) == 0
    out = capsys.readouterr().out
    assert out.count(f"coverage complete ({len(rows)}/{len(rows)}") == 2
    missing = int(rows[-1].split(",")[1])
    path.write_text("\n".join([header, *_wrinkling_rows(skip=(missing,))]) + "\n")
    assert cli.main(["check", "ch5_wrinkling", str(path)]) == 2
    err = capsys.readouterr().err
    assert "ch5_wrinkling:w_cross: PARTIAL coverage (not declared)" in err
    assert f"n = {missing}" in err
    assert cli.main(["check", "ch5_wrinkling", str(path), "--partial"]) == 0
    out = capsys.readouterr().out
    assert out.count(f"PARTIAL coverage (declared): {len(rows) - 1}/{len(rows)}") == 2


def test_check_refuses_quantities_that_do_not_share_coordinates(tmp_path, capsys):
    """ch2_kernel_states: W is per (material, state), sigma per (material, state, i,
    alpha); one row cannot be a point of both."""
    path = tmp_path / "k.csv"
    path.write_text("material,state,i [1],alpha [1],W [J m-3],sigma [Pa]\n"
                    "nh,uniaxial,0,0,1.0,1.0\n")
    assert cli.main(["check", "ch2_kernel_states", str(path)]) == 2
    assert "do not share their coordinates" in capsys.readouterr().err


def test_problems_beyond_the_thesis_are_shown_as_beyond_it(capsys):
    """A problem beyond the thesis (chapter = 0, lit_balloon) is listed as "beyond", never
    as "ch0"; its text says "beyond the thesis" and prints its references, and no empty
    "thesis:" line; a thesis problem keeps its chapter and thesis location."""
    assert cli.main(["problems"]) == 0
    out = capsys.readouterr().out
    line = next(x for x in out.splitlines() if x.split()[:1] == ["lit_balloon"])
    assert line.split()[1] == "beyond" and "ch0" not in out
    assert any(x.split()[:2] == ["ch3_voltage_stretch", "ch3"] for x in out.splitlines())
    assert cli.main(["problems", "lit_balloon"]) == 0
    out = capsys.readouterr().out
    assert out.splitlines()[0].endswith("(beyond the thesis)")
    assert "Chapter 0" not in out and not any(x.startswith("thesis:") for x in out.splitlines())
    assert "references: zhu_cai_suo_2010" in out
    assert cli.main(["problems", "lit_balloon", "--markdown"]) == 0
    page = capsys.readouterr().out
    assert "Beyond the thesis." in page and "Chapter 0" not in page and "Thesis:" not in page
    assert cli.main(["problems", "ch3_voltage_stretch"]) == 0
    out = capsys.readouterr().out
    assert "(Chapter 3)" in out.splitlines()[0]
    assert any(x.startswith("thesis: ") and len(x) > 10 for x in out.splitlines())


@pytest.mark.parametrize("item", ["lit_balloon", "lit_balloon.nc"])
def test_cite_of_a_problem_beyond_the_thesis_names_its_source_not_the_thesis(item):
    """``debench cite lit_balloon`` (the problem, and its dataset): the balloon's source
    (Zhu, Cai & Suo 2010, with its DOI) is cited as an item and the thesis is not (neither
    as a reference nor as a location in the note)."""
    text = cite.render(item)
    items = json.loads(text[text.index("\n["):])
    ids = [it["id"] for it in items]
    assert "zeng_2020" not in ids and "zhu_cai_suo_2010" in ids
    assert items[0]["references"] == "zhu_cai_suo_2010"
    assert "thesis" not in items[0]["note"] and "Zeng" not in text
    assert "@article{zhu_cai_suo_2010," in text and "doi = {10.1002/pi.2767}" in text
