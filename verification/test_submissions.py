"""Submissions (metadata + results) and ``debench check --submission DIR``.

The format: ``reference/submission.schema.json`` (also at verification/schemas/). A
submission without the required metadata is refused with every missing field named; a
results file that does not match its checksum is refused; then the results are checked like
``debench check`` does.
"""

from __future__ import annotations

import copy
import json
import tomllib

import numpy as np
import pytest
from debench.reference import problems, problems_reference, submissions
from debench.reference.cli import EXIT_FAILED, EXIT_OK, EXIT_USAGE, main

PROBLEM = "ch5_critical_voltage"

#: the required fields of the format (submission_format: every field not marked optional)
REQUIRED = [
    ("schema_version",), ("problem",), ("quantity",), ("results",), ("results_sha256",),
    ("code", "name"), ("code", "version"), ("code", "commit_or_release"), ("code", "url"),
    ("submitter", "name"), ("submitter", "date"),
    ("method", "description"), ("method", "discretisation"), ("method", "mesh_or_resolution"),
    ("method", "solver"), ("method", "tolerances"), ("method", "physics_differences"),
    ("environment", "python"), ("environment", "platform"), ("environment", "hardware"),
    ("environment", "requirements"),
    ("run", "command"), ("run", "wall_seconds"),
]


def _toml(meta: dict) -> str:
    """A minimal TOML writer for the metadata tables used here (strings, numbers, bools,
    lists of strings, one level of tables)."""
    def val(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, int | float):
            return repr(v)
        if isinstance(v, list):
            return "[" + ", ".join(val(x) for x in v) + "]"
        return json.dumps(v)

    top = [f"{k} = {val(v)}" for k, v in meta.items() if not isinstance(v, dict)]
    tables = [f"\n[{k}]\n" + "\n".join(f"{kk} = {val(vv)}" for kk, vv in v.items())
              for k, v in meta.items() if isinstance(v, dict)]
    return "\n".join(top) + "\n" + "\n".join(tables) + "\n"


def _results_csv(values) -> str:
    rows = [f"{c},{v!r}" for c, v in zip(["nh_t1", "ogden_t1"], values, strict=True)]
    return "case,v_cr [1]\n" + "\n".join(rows) + "\n"


def _reference_values():
    ref = problems_reference.reference_json(problems.get(PROBLEM))["reference"]["v_cr"]
    assert ref["coords"]["case"] == ["nh_t1", "ogden_t1"]
    return [float(x) for x in ref["values"]]


def _meta(results_text: str) -> dict:
    import hashlib

    return {
        "schema_version": 1, "problem": PROBLEM, "quantity": "v_cr",
        "results": "results.csv",
        "results_sha256": hashlib.sha256(results_text.encode()).hexdigest(),
        "code": {"name": "testcode", "version": "1.0", "commit_or_release": "v1.0",
                 "url": "https://example.org/testcode"},
        "submitter": {"name": "A. Tester", "date": "2026-12-01"},
        "method": {"description": "fixture", "discretisation": "P2",
                   "mesh_or_resolution": "none", "solver": "none", "tolerances": "none",
                   "physics_differences": "none"},
        "environment": {"python": "3.12.1", "platform": "linux", "hardware": "1 core",
                        "requirements": ["numpy==2.0.0"]},
        "run": {"command": "python fixture.py", "wall_seconds": 1.0},
    }


def _write(folder, meta: dict, results_text: str):
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "results.csv").write_text(results_text, encoding="utf-8")
    (folder / "submission.toml").write_text(_toml(meta), encoding="utf-8")
    return folder


@pytest.fixture
def valid(tmp_path):
    text = _results_csv(_reference_values())
    return _write(tmp_path / "valid", _meta(text), text), text


def test_valid_submission_is_accepted_and_checked(valid, capsys):
    folder, _ = valid
    sub = submissions.load(folder)
    assert sub.problem == PROBLEM and sub.code == "testcode"
    assert submissions.check(sub).passed
    assert main(["check", "--submission", str(folder)]) == EXIT_OK
    out = capsys.readouterr().out
    assert "sha256 verified" in out and "MATCHES" in out


def test_toml_dates_are_accepted(valid):
    """A TOML date (unquoted, parsed by tomllib as datetime.date) is the ISO 8601 text."""
    folder, _ = valid
    path = folder / "submission.toml"
    path.write_text(path.read_text().replace('date = "2026-12-01"', "date = 2026-12-01"))
    assert isinstance(tomllib.loads(path.read_text())["submitter"]["date"], object)
    submissions.load(folder)


@pytest.mark.parametrize("field", REQUIRED, ids=".".join)
def test_submission_missing_a_required_field_is_refused_naming_it(tmp_path, capsys, field):
    text = _results_csv(_reference_values())
    meta = _meta(text)
    holder = meta
    for key in field[:-1]:
        holder = holder[key]
    del holder[field[-1]]
    folder = _write(tmp_path / "s", meta, text)
    with pytest.raises(submissions.SubmissionError, match="refused") as exc:
        submissions.load(folder)
    assert f"{'.'.join(field)}: missing (required)" in str(exc.value)
    assert main(["check", "--submission", str(folder)]) == EXIT_USAGE
    assert f"{'.'.join(field)}: missing (required)" in capsys.readouterr().err


def test_every_missing_field_is_named_at_once(tmp_path):
    text = _results_csv(_reference_values())
    meta = _meta(text)
    del meta["code"]["version"], meta["run"]["command"], meta["method"]
    with pytest.raises(submissions.SubmissionError) as exc:
        submissions.load(_write(tmp_path / "s", meta, text))
    msg = str(exc.value)
    assert "code.version: missing" in msg and "run.command: missing" in msg
    assert "method: missing" in msg and "3 field(s)" in msg


@pytest.mark.parametrize("path,value,fragment", [
    (("results_sha256",), "abc", "results_sha256"),
    (("code", "url"), "not a url", "code.url"),
    (("submitter", "date"), "yesterday", "submitter.date"),
    (("environment", "requirements"), ["numpy"], "environment.requirements.0"),
    (("run", "wall_seconds"), -1.0, "run.wall_seconds"),
    (("schema_version",), 2, "schema_version"),
    (("code", "name"), "  ", "code.name"),
])
def test_invalid_field_is_refused_naming_it(tmp_path, path, value, fragment):
    text = _results_csv(_reference_values())
    meta = _meta(text)
    holder = meta
    for key in path[:-1]:
        holder = holder[key]
    holder[path[-1]] = value
    with pytest.raises(submissions.SubmissionError, match=fragment.replace(".", r"\.")):
        submissions.load(_write(tmp_path / "s", meta, text))


def test_unknown_field_is_refused(tmp_path):
    text = _results_csv(_reference_values())
    meta = _meta(text)
    meta["code"]["verison"] = "1.0"
    with pytest.raises(submissions.SubmissionError, match="code.verison: not a field"):
        submissions.load(_write(tmp_path / "s", meta, text))


def test_bad_checksum_is_refused(valid, capsys):
    folder, text = valid
    (folder / "results.csv").write_text(text.replace("nh_t1,0.2", "nh_t1,0.3"))
    with pytest.raises(submissions.SubmissionError, match="does not match"):
        submissions.load(folder)
    assert main(["check", "--submission", str(folder)]) == EXIT_USAGE
    assert "results changed after the metadata" in capsys.readouterr().err


def test_missing_results_file_is_refused(valid):
    folder, _ = valid
    (folder / "results.csv").unlink()
    with pytest.raises(submissions.SubmissionError, match="is not in"):
        submissions.load(folder)


def test_unknown_problem_is_refused(tmp_path):
    text = _results_csv(_reference_values())
    meta = _meta(text)
    meta["problem"] = "ch9_no_such_problem"
    with pytest.raises(submissions.SubmissionError, match="ch9_no_such_problem"):
        submissions.load(_write(tmp_path / "s", meta, text))


def test_results_of_another_problem_are_refused(tmp_path, capsys):
    """Metadata naming ch3_voltage_stretch over Chapter 5 results: the check refuses the
    file (its columns are not that problem's), exit 2, never a verdict."""
    text = _results_csv(_reference_values())
    meta = _meta(text)
    meta["problem"], meta["quantity"] = "ch3_voltage_stretch", "phibar"
    folder = _write(tmp_path / "s", meta, text)
    sub = submissions.load(folder)
    with pytest.raises(submissions.SubmissionError, match="no column for quantity"):
        submissions.check(sub)
    assert main(["check", "--submission", str(folder)]) == EXIT_USAGE


def test_wrong_values_fail_and_declared_tolerance_applies(tmp_path):
    """Values 1e-4 relative off fail at the reference's stated accuracy (~6e-5 relative
    here) and pass at a declared rtol of 1e-3; the exit code follows the declared one."""
    vals = [v * (1 + 1e-4) for v in _reference_values()]
    text = _results_csv(vals)
    meta = _meta(text)
    folder = _write(tmp_path / "off", meta, text)
    out = submissions.check(submissions.load(folder))
    assert not out.passed and out.declared is None
    assert main(["check", "--submission", str(folder)]) == EXIT_FAILED
    meta = copy.deepcopy(meta)
    meta["check"] = {"rtol": 1e-3, "reason": "fixture", "claimed": "match"}
    folder = _write(tmp_path / "declared", meta, text)
    out = submissions.check(submissions.load(folder))
    assert out.passed and not out.stated.passed and out.claim_holds is True
    assert main(["check", "--submission", str(folder)]) == EXIT_OK


def test_a_tolerance_without_its_reason_is_refused(tmp_path):
    text = _results_csv(_reference_values())
    meta = _meta(text)
    meta["check"] = {"rtol": 1e-3}
    with pytest.raises(submissions.SubmissionError, match="reason"):
        submissions.load(_write(tmp_path / "s", meta, text))


def test_false_claim_is_detected(valid):
    folder, text = valid
    meta = _meta(text)
    meta["check"] = {"claimed": "mismatch"}
    _write(folder, meta, text)
    assert submissions.check(submissions.load(folder)).claim_holds is False


def test_submission_excludes_problem_and_file_arguments(valid):
    folder, _ = valid
    assert main(["check", PROBLEM, "x.csv", "--submission", str(folder)]) == EXIT_USAGE
    assert main(["check", "--submission", str(folder), "--rtol", "1e-3"]) == EXIT_USAGE
    with pytest.raises(SystemExit) as exc:  # argparse: PROBLEM without FILE
        main(["check", PROBLEM])
    assert exc.value.code == EXIT_USAGE


def test_schema_file_is_shared_with_the_verification_schemas():
    """One schema: verification/schemas/submission.schema.json is the packaged file."""
    from pathlib import Path

    here = Path(__file__).parent / "schemas" / "submission.schema.json"
    assert json.loads(here.read_text()) == submissions.schema()
    assert np.isfinite(len(submissions.schema()["required"]))
