"""Opt-in (``--peers``): rebuild the peer codes' environments and rerun their adapters.

For every curated submission produced by an adapter of ``peers/`` the exact command it
records is run again (``peers/run.py``: the venv is built from the pinned requirements
when absent, which needs the library's Python, e.g. 3.12 for DOLFINx; a missing
interpreter or a failed install fails the test), into a temporary folder, and the new
values must agree with the curated ones point by point within the submission's own stated
accuracy (its ``[check]`` atol + rtol |value|): a rerun on another machine moves them by
round-off, far less than that resolution error.
"""

from __future__ import annotations

import csv
import shlex
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from debench.reference import submissions

REPO = Path(__file__).resolve().parent.parent
RERUNNABLE = [f for f in submissions.discover(REPO / "submissions")
              if submissions.load(f).meta["run"].get("adapter", "").startswith("peers/")]

pytestmark = pytest.mark.peers


def _rows(path: Path) -> dict[tuple, float]:
    with path.open(newline="") as fh:
        rows = [r for r in csv.reader(fh) if r and not r[0].startswith("#")]
    header = [h.split("[")[0].strip() for h in rows[0]]
    out = {}
    for r in rows[1:]:
        key = tuple(r[:-1])
        out[key] = float(r[-1])
    assert header[-1], "the quantity is the last column"
    return out


def _rerun_command(command: str, out: Path) -> list[str]:
    argv = shlex.split(command)
    if argv[:2] != ["python", "peers/run.py"]:
        pytest.fail(f"not a peers/run.py command: {command}")
    argv[0] = sys.executable
    extra = []
    if "--" in argv:
        i = argv.index("--")
        argv, extra = argv[:i], argv[i:]
    return [*argv, "--out", str(out), *extra]


def test_there_is_a_rerunnable_submission():
    assert RERUNNABLE, "no curated submission records a peers/ adapter"


@pytest.mark.parametrize("folder", RERUNNABLE, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_rerun_of_adapter_agrees_with_curated_submission(folder, tmp_path):
    sub = submissions.load(folder)
    claims = sub.claims
    if "atol" not in claims and "rtol" not in claims:
        pytest.fail(f"{folder}: states no accuracy of its own to compare a rerun with")
    out = tmp_path / folder.name
    cmd = _rerun_command(sub.meta["run"]["command"], out)
    proc = subprocess.run(cmd, cwd=REPO, capture_output=True, text=True)
    assert proc.returncode == 0, (f"{shlex.join(cmd)} failed:\n{proc.stdout[-3000:]}\n"
                                  f"{proc.stderr[-3000:]}")
    new = submissions.load(out)
    old_rows, new_rows = _rows(sub.results), _rows(new.results)
    assert set(new_rows) == set(old_rows), "the rerun covers the same points"
    keys = sorted(old_rows)
    old = np.array([old_rows[k] for k in keys])
    got = np.array([new_rows[k] for k in keys])
    tol = claims.get("atol", 0.0) + claims.get("rtol", 0.0) * np.abs(old)
    worst = int(np.argmax(np.abs(got - old) / tol))
    assert np.all(np.abs(got - old) <= tol), (
        f"rerun differs at {keys[worst]}: {got[worst]!r} vs curated {old[worst]!r} "
        f"(stated accuracy {tol[worst]:.3g})")
    assert new.claims.get("claimed") == claims.get("claimed")
