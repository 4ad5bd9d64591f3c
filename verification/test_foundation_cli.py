"""The `debench` command line and the citation metadata."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import numpy as np
import pytest
import yaml
from debench.reference.cli import main

ROOT = Path(__file__).resolve().parents[1]
STABLE_KEYS = {"kind", "id", "thesis_value", "value", "unit", "status", "diagnosis"}


def test_verify_json_lists_every_entry_with_stable_keys(capsys):
    from debench.reference import catalogue

    code = main(["verify", "--json", "--no-data"])
    rows = json.loads(capsys.readouterr().out)
    assert {r["id"] for r in rows} == {e.id for e in catalogue.load()}
    for row in rows:
        assert STABLE_KEYS <= set(row), row["id"]
        assert row["kind"] in catalogue.KINDS
        assert row["status"] in catalogue.STATUSES
        if row["status"] == "pending":
            assert row["value"] is None
    assert code == 0


def test_list_claims_prints_ids(capsys):
    assert main(["list", "claims"]) == 0
    assert "lit.membrane.pullin_voltage_nh" in capsys.readouterr().out


def test_errors_are_one_line_without_debug(capsys, tmp_path):
    code = main(["reproduce", "nonexistent_chapter", "--out", str(tmp_path)])
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert err.startswith("debench: error:") and "unknown chapter" in err
    assert len(err.splitlines()) == 1


@pytest.mark.slow
def test_reproduce_catalogue_writes_dataset_and_report(tmp_path, capsys):
    """The whole command: every catalogue entry evaluated and every model guard run (~50 s
    CPU). The default run has the same command path, catalogue builder and report with a
    three-entry evaluation and one cheap guard:
    test_reproduce_catalogue_writes_dataset_and_report_from_its_evaluation."""
    assert main(["reproduce", "catalogue", "--out", str(tmp_path)]) == 0
    assert (tmp_path / "thesis_values.nc").exists()
    assert (tmp_path / "REPORT.md").read_text().startswith("# debench report")


def test_reproduce_catalogue_writes_dataset_and_report_from_its_evaluation(
        tmp_path, capsys, monkeypatch):
    """``debench reproduce catalogue`` with the evaluation cut to three real entries and
    the model guards to one (the full evaluation and guards are checked by
    test_verify_json_lists_every_entry_with_stable_keys and verification/test_value_guard.py;
    the whole command runs under --full): the real catalogue builder writes
    ``thesis_values.nc``, equal to the curated one (it holds the catalogue, not the
    evaluation), and ``our_values.nc`` with the evaluation's and the guard's values, and the
    report opens with its title and the evaluation's summary."""
    from debench.reference import builds, catalogue, report_tables, values
    from debench.reference.datasets import read_dataset

    results = [catalogue.evaluate(e) for e in catalogue.load() if e.kind == "assumption"][:3]
    monkeypatch.setattr(catalogue, "evaluate_all", lambda entries=None, progress=None:
                        list(results))

    def probe_guard():
        return [values.Guarded("probe.value", 1.5, 0.0, "test")]

    monkeypatch.setattr(values, "probe_guard", probe_guard, raising=False)
    monkeypatch.setattr(builds, "model_guards",
                        lambda chapters: {"debench.reference.values:probe_guard": 1.0})
    assert main(["reproduce", "catalogue", "--out", str(tmp_path)]) == 0
    out, err = capsys.readouterr()
    assert "thesis_values.nc: matches curated" in err
    assert report_tables.summary_line(results) in out
    ours = read_dataset(values.STORE_NAME, data_dir=tmp_path)
    stored = dict(zip(ours.key.values, ours.value.values, strict=True))
    assert stored["probe.value"] == 1.5
    from_results = {g.key for g in values.guarded_from_results(results)}
    assert len(from_results) == 3 and from_results < set(stored)
    assert (tmp_path / "REPORT.md").read_text().startswith("# debench report")


def test_citation_cff_is_valid():
    schema = json.loads((ROOT / "verification/schemas/citation-cff-1.2.0.schema.json").read_text())
    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    cff["date-released"] = str(cff["date-released"])  # YAML parses dates; CFF wants strings
    jsonschema.validate(cff, schema)
    assert cff["cff-version"] == "1.2.0"
    assert any(r["type"] == "thesis" for r in cff["references"])


def _junit(tmp_path, tests: int, skipped: int) -> str:
    path = tmp_path / "junit.xml"
    path.write_text(f'<testsuites><testsuite name="pytest" tests="{tests}" skipped="{skipped}" '
                    'failures="0" errors="0"/></testsuites>')
    return str(path)


def test_ci_fails_when_no_test_ran(tmp_path):
    """.ci/run must fail when every test was skipped or none was collected."""
    from verification._loaders import load_script

    mod = load_script(".ci/count_tests.py")
    assert mod.main(["x", _junit(tmp_path, 0, 0)]) == 1
    assert mod.main(["x", _junit(tmp_path, 5, 5)]) == 1
    assert mod.main(["x", _junit(tmp_path, 5, 4)]) == 0


def test_ci_runs_the_readme_test_command_verbatim():
    readme = (ROOT / "README.md").read_text()
    block = readme.split("<!-- test-command -->", 1)[1].split("```bash\n", 1)[1].split("```")[0]
    assert "pip install" in block and "pytest" in block
    assert "<!-- test-command -->" in (ROOT / ".ci/run").read_text()


def _regenerated(chapters, jobs, tmp_path) -> list[str]:
    from debench.reference.regeneration import Recomputations

    with Recomputations(chapters, (), jobs=jobs, out=tmp_path) as work:
        return work.lines()


@pytest.mark.parametrize("jobs", [1, 2])
def test_verify_regeneration_finds_a_changed_model_output(jobs, tmp_path, monkeypatch):
    """``debench verify``'s regeneration (in this process, or in a pool of two processes,
    which inherit the patched builder): the cheap chapters rebuilt from the models equal
    the curated files, and a rebuilt value moved by 1e-6 relative (far above its stored
    accuracy) is reported as DIFFERS, in that file only."""
    from debench.reference.builders import ch2_appendix

    chapters = ("ch2_appendix", "ch3_fe")
    lines = _regenerated(chapters, jobs, tmp_path / "a")
    assert lines and not any("DIFFERS" in x or "cannot compare" in x for x in lines), lines
    original = ch2_appendix.compute

    def moved(*args, **kw):
        ds = original(*args, **kw)
        name = next(n for n, v in ds.data_vars.items() if v.dtype == np.float64)
        return ds.assign({name: ds[name].copy(data=ds[name].values * (1 + 1e-6))})

    monkeypatch.setattr(ch2_appendix, "compute", moved)
    found = [x for x in _regenerated(chapters, jobs, tmp_path / "b") if "DIFFERS" in x]
    assert len(found) == 1 and "ch2_kernel_reference_states" in found[0], found


def test_verify_recomputations_raise_a_failing_job(tmp_path, monkeypatch):
    """A recomputation that raises in a pool process raises in the command."""
    from debench.reference import values

    def broken():
        raise RuntimeError("a broken guard")

    monkeypatch.setattr(values, "broken_guard", broken, raising=False)
    from debench.reference.regeneration import Recomputations

    with pytest.raises(RuntimeError, match="a broken guard"), Recomputations(
            ("ch2_appendix",), ("debench.reference.values:broken_guard",), jobs=2,
            out=tmp_path) as work:
        work.guarded()
