"""The curated submissions (``submissions/``) and the consensus table built from them.

Every curated submission must validate (schema, checksum), pass the ordinary check's
preconditions (columns, units, coverage) and obtain the outcome it claims; the consensus
table lists every one of them, and the problem pages show it. Rerunning the peer codes
themselves is opt-in (``--peers``, verification/test_peers.py).
"""

from __future__ import annotations

import importlib.util
import tomllib
from pathlib import Path

import pytest
from debench.reference import consensus, problems, problems_reference, submissions

REPO = Path(__file__).resolve().parent.parent
CURATED = submissions.discover(REPO / "submissions")


def _run_module():
    spec = importlib.util.spec_from_file_location("peers_run", REPO / "peers" / "run.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_there_are_curated_submissions():
    assert len(CURATED) >= 2, f"expected curated submissions under {REPO / 'submissions'}"
    assert submissions.curated_root().resolve() == (REPO / "submissions").resolve(), (
        "debench reads the curated submissions of this checkout (an editable install)")


@pytest.mark.parametrize("folder", CURATED, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_curated_submission_validates_and_obtains_its_claimed_outcome(folder):
    sub = submissions.load(folder)
    assert folder.parent.name == sub.problem, "a submission lives under its problem's folder"
    assert "claimed" in sub.claims, "a curated submission states the outcome it obtained"
    outcome = submissions.check(sub)
    assert outcome.claim_holds, (f"{folder}: claims {sub.claims['claimed']}, the check "
                                 f"says {outcome.verdict.summary()}")
    adapter = sub.meta["run"].get("adapter")
    if adapter:
        assert (REPO / adapter).is_file(), f"the adapter {adapter} is in the repository"


def test_consensus_table_lists_every_curated_submission():
    listed = {r.folder for t in consensus.tables() for r in t.rows}
    assert listed == {str(f) for f in CURATED}
    assert not [m for t in consensus.tables() for m in t.refused]


def test_problem_page_and_report_show_the_consensus():
    for prob in {submissions.load(f).problem for f in CURATED}:
        page = consensus.problem_page(problems.get(prob))
        assert "## Other codes (curated submissions)" in page
    text = "\n".join(consensus.report_section())
    assert "Consensus of codes" in text and "DOLFINx" in text


def test_a_broken_submission_is_shown_as_refused(tmp_path):
    """A tampered curated submission is refused in the table, never dropped silently."""
    import shutil

    src = CURATED[0]
    dst = tmp_path / src.parent.name / src.name
    shutil.copytree(src, dst)
    res = dst / submissions.load(src).meta["results"]
    res.write_text(res.read_text() + "\n")
    [table] = consensus.tables(tmp_path)
    assert not table.rows and "does not match" in table.refused[0]
    assert "Refused:" in consensus.markdown(table)


def test_spread_of_values_across_codes(tmp_path):
    """Two copies of a scalar submission, one with its values shifted by d: the spread
    (codes and reference) is max - min of the two values and the reference, per
    selection."""
    import hashlib
    import shutil

    scalar = [f for f in CURATED if f.parent.name == "ch5_critical_voltage"]
    if not scalar:
        pytest.fail("no curated ch5_critical_voltage submission to build the fixture from")
    src = scalar[0]
    a, b = tmp_path / "ch5_critical_voltage" / "a", tmp_path / "ch5_critical_voltage" / "b"
    shutil.copytree(src, a)
    shutil.copytree(src, b)
    meta = tomllib.loads((b / "submission.toml").read_text())
    lines = (b / meta["results"]).read_text().splitlines()
    d = 1e-3
    shifted = [lines[0]] + [f"{ln.split(',')[0]},{float(ln.split(',')[1]) + d!r}"
                            for ln in lines[1:] if ln]
    (b / meta["results"]).write_text("\n".join(shifted) + "\n")
    digest = hashlib.sha256((b / meta["results"]).read_bytes()).hexdigest()
    text = (b / "submission.toml").read_text().replace(meta["results_sha256"], digest)
    (b / "submission.toml").write_text(text.replace('claimed = "match"',
                                                    'claimed = "mismatch"'))
    [table] = consensus.tables(tmp_path)
    assert len(table.rows) == 2 * (len(lines) - 1)
    for sel, spread in table.spread().items():
        rows = [r for r in table.rows if r.selection == sel]
        vals = sorted(r.value for r in rows)
        assert vals[1] - vals[0] == pytest.approx(d, rel=1e-9)
        ref = rows[0].reference
        assert spread == pytest.approx(max(vals[1], ref) - min(vals[0], ref), rel=1e-12)
        assert spread >= d


# --------------------------------------------------------------------------- peers/run.py
def test_run_writes_metadata_that_tomllib_reads_back():
    run = _run_module()
    meta = {"a": 1, "b": "x \"quoted\" \\ back", "c": 1.5e-7, "t": {"l": ["p==1", "q==2"],
                                                                   "flag": True}}
    assert tomllib.loads(run.to_toml(meta)) == meta


def test_run_refuses_unpinned_requirements(tmp_path, monkeypatch):
    run = _run_module()
    lib = tmp_path / "lib"
    lib.mkdir()
    (lib / "python-version").write_text("3.12\n")
    (lib / "requirements.txt").write_text("numpy>=2\n")
    monkeypatch.setattr(run, "PEERS", tmp_path)
    with pytest.raises(run.PeerError, match="pin every requirement"):
        run.requirements("lib")


def test_run_names_a_missing_python():
    run = _run_module()
    with pytest.raises(run.PeerError, match="no working Python 2.9"):
        run.find_python("2.9")


def test_every_peer_library_pins_its_requirements():
    run = _run_module()
    libs = [p.name for p in (REPO / "peers").iterdir() if (p / "requirements.txt").is_file()]
    assert "dolfinx" in libs
    for lib in libs:
        assert run.requirements(lib)
        assert (REPO / "peers" / lib / "python-version").read_text().strip()


def test_template_adapter_yields_a_valid_submission(tmp_path):
    """The adapter template (peers/template/adapter.py) run by hand on its worked example,
    then completed by peers/run.py's writer: the folder validates and matches."""
    import json
    import platform
    import subprocess
    import sys

    run = _run_module()
    pj = tmp_path / "problem.json"
    pj.write_text(json.dumps(problems_reference.reference_json(problems.get("ch3_free_membrane_nh"))))
    work = tmp_path / "work"
    work.mkdir()
    subprocess.run([sys.executable, str(REPO / "peers" / "template" / "adapter.py"),
                    "--problem-json", str(pj), "--out", str(work)], check=True)
    out = run.write_submission(
        work, "ch3_free_membrane_nh",
        info={"python": platform.python_version(), "freeze": ["numpy==2.0.0"]},
        command="python peers/template/adapter.py", wall=0.1, cpu=0.1,
        adapter="peers/template/adapter.py", out=tmp_path / "submission")
    sub = submissions.load(out)
    assert sub.claims["claimed"] == "match" and submissions.check(sub).passed


def test_template_refuses_a_problem_it_does_not_know(tmp_path):
    import json
    import subprocess
    import sys

    pj = tmp_path / "problem.json"
    pj.write_text(json.dumps(problems_reference.reference_json(problems.get("ch5_critical_voltage"))))
    proc = subprocess.run([sys.executable, str(REPO / "peers" / "template" / "adapter.py"),
                           "--problem-json", str(pj), "--out", str(tmp_path)],
                          capture_output=True, text=True)
    assert proc.returncode != 0 and "write the solver of ch5_critical_voltage" in proc.stderr
    assert not (tmp_path / "results.csv").exists()
