"""The thesis catalogue: completeness, provenance, status mechanism, citable dataset."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import numpy as np
import pytest
from debench.reference import catalogue
from debench.reference.catalogue import Entry, Outcome, judge, printed_half_ulp

ROOT = Path(__file__).resolve().parents[1]

#: Ids that must always exist, so that results can be tracked across versions.
REQUIRED_IDS = {
    "ch3.annulus.thickness_A_increase": 25.3,
    "ch3.annulus.lam1_interface_increase": 15.6,
    "ch3.annulus.lam2_interface_decrease": 10.7,
    "ch3.annulus.lam3_interface_decrease": 3.2,
    "ch3.pullin.suppression_prestretch": 2.53,
    "ch3.pullin.voltage_lamP_1p25": 0.518,
    "ch3.pullin.c_threshold_lamP_1p25": -0.085,
    "ch3.loss_of_tension.stretch_lamP_3": 6.73,
    "ch3.voltage_increase.lamP_3_stretch_4p5": 40.1,
    "ch3.max_stretch_gain.lamP_2": 28.4,
    "ch3.max_stretch_reduction.lamP_4": 19.12,
    "ch3.voltage_increase.lamP_4_stretch_5": 50.16,
    "ch5.critical_voltage.t0p5_ogden": 0.012,
    "ch5.critical_voltage.t1_ogden": 0.050,
    "ch5.critical_voltage.t1_nh": 0.078,
    "ch5.pullin_voltage.t1_nh": 0.268,
    "ch5.pullin_voltage.t1_ogden": 0.179,
    "ch5.pullin_displacement.t1": 5.98,
    "ch5.wrinkling_displacement.t0p5": 3.64,
    "ch5.field_at_instability.t0p5": 29.3,
    "ch5.field_at_instability.t1_ogden": 47.6,
    "ch5.field_at_instability.t1_nh": 41.6,
}


@pytest.fixture(scope="module")
def entries() -> list[Entry]:
    return catalogue.load()


@pytest.fixture(scope="module")
def results(entries):
    return catalogue.evaluate_all(entries)


def test_catalogue_holds_every_required_thesis_value(entries):
    ids = catalogue.by_id(entries)
    missing = sorted(set(REQUIRED_IDS) - set(ids))
    assert not missing, f"catalogue lacks required ids: {missing}"
    for key, value in REQUIRED_IDS.items():
        assert ids[key].value == pytest.approx(value), key
        assert ids[key].kind == "claim"


def test_thesis_entries_carry_provenance(entries):
    for e in entries:
        if e.kind == "claim":
            assert e.source.get("section") or e.source.get("equation"), e.id
            if e.source.get("section") != "beyond the thesis":  # our results: no page
                assert "page" in e.source, f"{e.id}: page missing"
            if isinstance(e.value, int | float) and not isinstance(e.value, bool):
                assert e.printed, f"{e.id}: numeric claim needs the printed digits"
                assert e.unit, e.id


def test_computed_statuses_match_expected_statuses(results):
    """`debench verify` regression rule: every producer runs and yields its expected status."""
    bad = [(r.entry.id, r.status, r.entry.expected_status, r.diagnosis)
           for r in results if r.regressed]
    assert not bad, bad


def test_status_is_computed_not_declared(results):
    """Only assumptions and pending entries may lack a producer."""
    for r in results:
        if r.status not in ("pending", "assumed"):
            assert r.entry.producer, r.entry.id


#: statuses a producer may name unconditionally: ``input`` is checked by ``judge`` against
#: the stated value (a mismatch becomes not_reproduced); ``not_comparable`` too (our
#: setting equal to the thesis' becomes input, a different one stays not_comparable);
#: ``assumed`` labels an assumption whose producer computes the sensitivity.
_LABEL_STATUSES = {"input", "not_comparable", "assumed"}


def _declared_statuses(path: Path) -> list[str]:
    """``Outcome(..., status="<literal>")`` calls that are not under an if/else/match."""
    tree = ast.parse(path.read_text())
    out = []

    def visit(node, conditional):
        if isinstance(node, ast.Call) and getattr(node.func, "id", "") == "Outcome":
            for kw in node.keywords:
                if (kw.arg == "status" and isinstance(kw.value, ast.Constant)
                        and kw.value.value not in _LABEL_STATUSES and not conditional):
                    out.append(f"{path.name}:{node.lineno} status={kw.value.value!r}")
        cond = conditional or isinstance(node, ast.If | ast.IfExp | ast.Match | ast.Try)
        for child in ast.iter_child_nodes(node):
            visit(child, cond)

    visit(tree, False)
    return out


def test_no_producer_declares_a_status_unconditionally():
    """A status is computed: a producer names a status literal only on a branch that a
    computed condition selects (or lets ``judge`` compare its value with the thesis)."""
    declared = [d for p in sorted((ROOT / "reference" / "producers").glob("*.py"))
                for d in _declared_statuses(p)]
    assert not declared, declared


def test_declared_status_detector_can_fail(tmp_path):
    bad = tmp_path / "p.py"
    bad.write_text("def f(e):\n    return Outcome(1.0, status='confirmed')\n")
    assert _declared_statuses(bad) == ["p.py:2 status='confirmed'"]
    ok = tmp_path / "q.py"
    ok.write_text("def f(e, x):\n    if x:\n        return Outcome(1.0, status='refuted')\n"
                  "    return Outcome(1.0, status='input')\n")
    assert _declared_statuses(ok) == []


def _test_functions(path: Path) -> set[str]:
    tree = ast.parse(path.read_text())
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            names.add(node.name)
    return names


def test_errata_evidence_names_an_existing_test(entries):
    for e in entries:
        if e.kind != "erratum":
            continue
        for node in e.evidence.split():
            file, _, rest = node.partition("::")
            path = ROOT / file
            assert path.is_file(), f"{e.id}: evidence file {file} does not exist"
            func = rest.split("::")[-1].split("[")[0]
            assert func in _test_functions(path), f"{e.id}: {func} not in {file}"


@pytest.mark.parametrize(("printed", "half_ulp"), [
    ("0.518", 5e-4), ("25.3", 0.05), ("19.12", 5e-3), ("-0.085", 5e-4), ("6.73", 5e-3),
    ("14.68", 5e-3), ("50", 0.5), ("7748003.92", 5e-3), ("hello", None),
])
def test_tolerance_is_half_a_unit_in_the_last_printed_digit(printed, half_ulp):
    got = printed_half_ulp(printed)
    assert got == (None if half_ulp is None else pytest.approx(half_ulp))


def _entry(**kw) -> Entry:
    base = dict(id="ch3.test.value", kind="claim", quantity="q", value=0.518, printed="0.518",
                source={"section": "3.5.2", "page": 42})
    return Entry(**{**base, **kw})


def test_judge_reproduced_within_printed_precision():
    assert judge(_entry(), Outcome(0.5184)).status == "reproduced"
    assert judge(_entry(), Outcome(0.5176)).status == "reproduced"
    assert judge(_entry(), Outcome(0.5186)).status == "not_reproduced"


def test_judge_not_reproduced_states_both_values():
    r = judge(_entry(), Outcome(0.6, diagnosis="model issue"))
    assert r.status == "not_reproduced"
    assert "0.6" in r.diagnosis and "0.518" in r.diagnosis and "model issue" in r.diagnosis


def test_judge_qualitative_and_explicit_statuses():
    assert judge(_entry(value="trend"), Outcome(True)).status == "reproduced"
    assert judge(_entry(value="trend"), Outcome(False)).status == "not_reproduced"
    r = judge(_entry(), Outcome(None, status="not_reproducible", diagnosis="eps_r missing"))
    assert r.status == "not_reproducible" and r.diagnosis == "eps_r missing"


def test_input_parameters_are_checked_but_not_counted_as_reproduced():
    assert judge(_entry(), Outcome(0.518, status="input")).status == "input"
    r = judge(_entry(), Outcome(0.52, status="input"))
    assert r.status == "not_reproduced" and "0.52" in r.diagnosis


def test_producer_exception_is_an_error_not_a_value():
    e = _entry(producer="debench.reference.nonexistent_module:f")
    r = catalogue.evaluate(e)
    assert r.status == "error" and r.regressed


def test_malformed_entries_are_rejected(tmp_path):
    (tmp_path / "x.toml").write_text('[[entry]]\nid = "ch3.a"\nkind = "rumour"\nquantity = "q"\n')
    with pytest.raises(catalogue.CatalogueError, match="kind"):
        catalogue.load(tmp_path)
    (tmp_path / "x.toml").write_text(
        '[[entry]]\nid = "ch3.a"\nkind = "claim"\nquantity = "q"\nvalue = 1.0\n'
        'source = {section = "3"}\ntolerance = 0.5\n')
    with pytest.raises(catalogue.CatalogueError, match="tolerance_reason"):
        catalogue.load(tmp_path)


def test_thesis_values_dataset_regenerates_from_catalogue(entries):
    """data/thesis_values.nc is the catalogue as a citable dataset, and up to date."""
    from debench.reference.builders.catalogue import catalogue_dataset
    from debench.reference.datasets import read_dataset

    curated = read_dataset("thesis_values")
    fresh = catalogue_dataset(entries)
    assert list(curated["entry"].values) == list(fresh["entry"].values)
    for var in fresh.data_vars:
        if np.issubdtype(fresh[var].dtype, np.number):
            np.testing.assert_array_equal(curated[var].values, fresh[var].values, err_msg=var)
        else:
            assert list(curated[var].values) == list(fresh[var].values), var


def test_readme_results_table_is_current(results):
    from debench.reference.report import END, START, readme_block

    text = (ROOT / "README.md").read_text()
    block = START + text.split(START, 1)[1].split(END, 1)[0] + END
    assert block == readme_block(results), "run `debench report --readme`"


#: a Python repr reaching a reader: a numpy scalar, a dict, a float of 15+ digits
RAW_REPR = re.compile(r"np\.(?:float|int|bool_)\d*\(|\{'")
#: significant digits from which a printed float is a repr, not a number for reading
REPR_DIGITS = 15


def raw_python(text: str) -> list[str]:
    """The places of ``text`` where a Python repr shows (:data:`RAW_REPR`, or a float with
    :data:`REPR_DIGITS` significant digits or more), each with some context."""
    hits = [m.start() for m in RAW_REPR.finditer(text)]
    for m in re.finditer(r"(?<![\w.])\d+\.\d+(?:e[-+]?\d+)?", text):
        mantissa = re.sub(r"e.*", "", m.group()).replace(".", "").lstrip("0")
        if len(mantissa) >= REPR_DIGITS:
            hits.append(m.start())
    return [text[max(0, i - 60):i + 40] for i in sorted(hits)]


def test_raw_python_is_detected():
    """The scan below can fail: it finds each kind of repr and passes readable numbers."""
    assert len(raw_python("a np.float64(2.334815259489528) b {'derived': 1.0} c "
                          "4.1595000000000006e-11 d 0.9999999994444345")) == 5
    assert raw_python("2.3348, derived = 1, literal = 0.99999999944, 4.1595e-11, "
                      "sha256 e13f1e851917f897c4719ac7cfbdf0f62a7b6998") == []


def test_report_and_problem_pages_show_no_raw_python(results, tmp_path):
    """Every number of the report (``debench report``, the verdict page) and of every
    problem page (``debench problems ID --markdown`` with its consensus table, as the site
    shows it) is formatted for reading: no numpy scalar or dict repr, no float printed
    with all its 17 digits."""
    from debench.reference import consensus, problems, report

    text = report.write_report(tmp_path, results, figures_dir=tmp_path / "none").read_text()
    found = {"REPORT.md": raw_python(text)}
    for p in problems.load_all():
        found[p.id] = raw_python(consensus.problem_page(p))
    found = {k: v for k, v in found.items() if v}
    assert not found, found


def test_a_setting_of_ours_is_an_input_when_equal_and_not_comparable_otherwise():
    """``not_comparable`` is judged: our setting equal to the thesis' is an input, a
    different one is neither reproduced nor not reproduced."""
    e = _entry()
    assert judge(e, Outcome(0.518, status="not_comparable")).status == "input"
    assert judge(e, Outcome(0.6, status="not_comparable")).status == "not_comparable"


def test_every_erratum_names_its_root_cause(entries):
    """Errata carry ``root_cause``: their own id for a root error, else a root erratum's
    id; entries that follow from an erratum (of any kind) name a root too."""
    ids = catalogue.by_id(entries)
    for e in entries:
        if e.kind == "erratum" and e.expected_status != "pending":
            assert e.root_cause, e.id
        if e.root_cause:
            root = ids[e.root_cause]
            assert root.kind == "erratum" and root.root_cause == root.id, e.id


def test_a_root_cause_that_is_no_root_is_rejected(tmp_path):
    """The loader rejects a root cause that is not an erratum or not its own root."""
    text = (CATALOGUE_TEXT_ERRATUM.format(id="ch3.erratum.a", root="ch3.erratum.a")
            + CATALOGUE_TEXT_ERRATUM.format(id="ch3.erratum.b", root="ch3.erratum.a"))
    (tmp_path / "x.toml").write_text(text)
    assert len(catalogue.load(tmp_path)) == 2
    (tmp_path / "x.toml").write_text(
        text + CATALOGUE_TEXT_ERRATUM.format(id="ch3.erratum.c", root="ch3.erratum.b"))
    with pytest.raises(catalogue.CatalogueError, match="not a root"):
        catalogue.load(tmp_path)
    (tmp_path / "x.toml").write_text(
        CATALOGUE_TEXT_ERRATUM.format(id="ch3.erratum.d", root="ch3.missing"))
    with pytest.raises(catalogue.CatalogueError, match="not an erratum"):
        catalogue.load(tmp_path)


CATALOGUE_TEXT_ERRATUM = """
[[entry]]
id = "{id}"
kind = "erratum"
root_cause = "{root}"
quantity = "q"
source = {{ chapter = 3, equation = "3.1", page = 1 }}
as_printed = "a"
corrected = "b"
evidence = "verification/test_x.py::test_y"
expected_status = "confirmed"
"""


def test_every_report_row_compares_like_with_like(results):
    """The report's tables put beside each other only values of the same kind: a claim's
    printed value and ours are both numbers, both booleans or both text, and a diagnosis
    predicts a quantity of the same unit and kind (voltage, field, displacement, share,
    Dhat) as the value it is compared with."""
    from debench.reference import report_tables

    assert report_tables.row_problems(results) == []


def test_readme_report_and_site_share_the_verdict(results, tmp_path):
    """The verdict in brief (reference/verdict.md filled from the computed records) is the
    same text in the README (between its verdict markers), the report (right after its
    title, before the counts) and the site's verdict page (which opens with it, before the
    counts and the catalogue ids); no record it quotes is missing."""
    from debench.reference import report

    from verification._loaders import load_script

    verdict = report.verdict_markdown(results)
    assert "not computed" not in verdict
    readme = (ROOT / "README.md").read_text()
    block = (report.VERDICT_START + readme.split(report.VERDICT_START, 1)[1]
             .split(report.VERDICT_END, 1)[0] + report.VERDICT_END)
    assert block == report.verdict_block(results), "run `debench report --readme`"
    text = report.write_report(tmp_path / "report", results).read_text()
    assert text.split("## The verdict in brief\n\n", 1)[1].startswith(verdict + "\n")
    assert text.index(verdict) < text.index("Summary:")
    pages = load_script("docs/_ext/debench_pages.py")
    pages.OUT = tmp_path / "generated"
    pages.verdict_page(results)
    page = (pages.OUT / "verdict.md").read_text()
    body = page.split("\n", 1)[1].lstrip()
    assert body.startswith("## The verdict in brief\n\n" + verdict + "\n")
    assert page.index(verdict) < min(page.index("Summary:"), page.index("`ch"))
