"""The report: a verdict per chapter generated from the results, errata never truncated, no
raw dicts or doubled units, every figure shown (PNG linked, SVG beside it), and the
cross-check matrix measured from the datasets within the tolerances its tests assert."""

from __future__ import annotations

import re

import pytest
from debench.reference import catalogue, crosschecks, report
from debench.reference.catalogue import Entry, Result


@pytest.fixture(scope="module")
def results():
    """Every catalogue entry with its stated value as 'ours' (no producer is run)."""
    out = []
    for e in catalogue.load():
        status = e.expected_status or "reproduced"
        out.append(Result(e, {"a": 1.0, "b": 2.0} if e.kind == "diagnosis" else e.value,
                          status, e.diagnosis or ""))
    return out


def test_report_has_a_verdict_per_chapter_and_shows_every_figure(results, tmp_path):
    figs = tmp_path / "figures"
    figs.mkdir()
    names = ["fig3_4_voltage_stretch_c0", "table5_1_uniaxial", "ch4_beyond_voltage_control",
             "unrelated_plot"]
    for n in names:
        (figs / f"{n}.png").write_bytes(b"png")
        (figs / f"{n}.svg").write_text("<svg/>")
    text = report.write_report(tmp_path, results, figures_dir=figs).read_text()
    verdicts = text.split("## Verdict per chapter")[1].split("## ")[0]
    for prefix in {r.entry.id.split(".")[0] for r in results}:
        title = report.CHAPTER_TITLES.get(prefix, prefix)
        assert f"**{title}.**" in verdicts
    for n in names:
        assert f"](figures/{n}.png)" in text and f"](figures/{n}.svg)" in text
    links = re.findall(r"\]\(([^)]+\.(?:png|svg))\)", text)
    assert links and all((tmp_path / link).exists() for link in links)
    assert "{'" not in text, "a raw Python dict was printed"
    assert not re.search(r"(\S+) \1 \|", text), "a doubled unit"


def test_errata_are_never_truncated(results):
    table = report.errata_table(results)
    for r in results:
        if r.entry.kind == "erratum":
            for text in (r.entry.as_printed, r.entry.corrected):
                assert " ".join(str(text).split()).replace("|", "\\|") in table


def test_fmt_renders_dicts_as_pairs_and_never_doubles_the_unit():
    assert report.format_value({"x": 1.5, "y": "a"}) == "x = 1.5; y = a"
    assert report.format_value("3.64 mm", "mm") == "3.64 mm"
    assert report.format_value(3.64, "mm") == "3.64 mm"


def test_every_crosscheck_names_an_existing_test_and_agrees_within_its_tolerance():
    rows = crosschecks.matrix()
    assert rows
    for row in rows:
        assert crosschecks.test_exists(row.check.test), row.check.test
        if row.tolerance is not None:
            assert row.measured <= row.tolerance, (row.check.quantity, row.measured)
        else:
            assert row.measured > 0  # a diagnosis pair: the two really differ


def test_figures_save_writes_png_and_svg(tmp_path):
    from debench.reference.figures import pyplot, save

    fig, ax = pyplot().subplots()
    ax.plot([0, 1], [0, 1])
    paths = save(fig, tmp_path / "fig9_1_example.png")
    assert [p.name for p in paths] == ["fig9_1_example.png", "fig9_1_example.svg"]
    assert all(p.stat().st_size > 0 for p in paths)


def test_row_check_flags_a_deflection_compared_with_a_voltage():
    """:func:`report.row_problems` can fail: a hypothesis predicting a deflection (w/t0)
    against a normalised voltage, a share against a voltage, and a boolean beside a
    number are each reported; the same hypothesis predicting a voltage is not."""
    from dataclasses import replace

    target = Entry(id="ch5.t.voltage", kind="claim", quantity="normalised critical voltage",
                   value=0.078, printed="0.078", source={"section": "5.3", "page": 1})
    deflection = Entry(id="ch5.hypothesis.t.read_off", kind="diagnosis",
                       quantity="centre deflection at the printed voltage",
                       parameters={"target": target.id, "quantity": "displacement"})
    share = replace(deflection, id="ch5.hypothesis.t.share",
                    parameters={"target": target.id, "quantity": "share"})
    good = replace(deflection, id="ch5.hypothesis.t.voltage",
                   parameters={"target": target.id, "quantity": "voltage"})
    rows = [Result(target, True, "not_reproduced", ""),
            Result(deflection, 0.0026, "unexplained", ""),
            Result(share, 0.31, "unexplained", ""), Result(good, 0.08, "unexplained", "")]
    problems = report.row_problems(rows)
    assert [p.split(":")[0] for p in problems] == [
        "ch5.t.voltage", "ch5.hypothesis.t.read_off", "ch5.hypothesis.t.share"]
    assert report.quantity_kind(target) == "voltage"


def test_errata_are_grouped_by_root_cause(results):
    """The errata table lists each root error first and the errata it causes after it;
    the root-cause table names the other entries that follow from a root."""
    table = report.errata_table(results).splitlines()[2:]
    ids = [row.split("|")[2].strip(" `") for row in table]
    causes = [row.split("|")[1].strip(" `") for row in table]
    by_id = {r.entry.id: r.entry for r in results}
    for i, (eid, cause) in enumerate(zip(ids, causes, strict=True)):
        root = by_id[eid].root_cause
        assert cause == ("root" if root == eid else root)
        if root != eid:       # a consequence comes after its root, within its group
            j = ids.index(root)
            assert j < i and all(by_id[x].root_cause == root for x in ids[j:i + 1])
    roots = report.root_cause_table(results)
    assert "`ch4.erratum.eq4_55_b`" in roots and "`ch4.ellipticity.ti_curves_well_posed`" in roots
