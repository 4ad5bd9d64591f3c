"""Curated data carry provenance one can check: made by `debench reproduce --write-data`
from a clean tree, and holding no curve that is all missing values without a cause."""

from __future__ import annotations

import numpy as np
import pytest
from debench.reference.datasets import data_dir, read_dataset, read_manifest

MANIFEST = read_manifest(data_dir())
NAMES = sorted(n.removesuffix(".nc") for n in MANIFEST)


def provenance_problems(attrs: dict) -> list[str]:
    """What is wrong with a dataset's provenance (empty when it is checkable)."""
    out = []
    commit = str(attrs.get("git_commit", ""))
    if commit.endswith("-dirty") or commit in ("", "unknown"):
        out.append(f"git_commit {commit!r} (not a clean commit)")
    command = str(attrs.get("command", ""))
    if not command.startswith("debench reproduce") or "--write-data" not in command:
        out.append(f"command {command!r} (not `debench reproduce ... --write-data`)")
    return out


def test_provenance_check_can_fail():
    assert provenance_problems({"git_commit": "abc-dirty", "command": "-c"})
    assert provenance_problems({"git_commit": "abc", "command": "debench reproduce ch3"})
    assert not provenance_problems({"git_commit": "abc", "command":
                                    "debench reproduce --write-data"})


@pytest.mark.parametrize("name", NAMES)
def test_curated_dataset_was_made_by_reproduce_write_data_from_a_clean_tree(name):
    ds = read_dataset(name)
    assert not provenance_problems(ds.attrs), provenance_problems(ds.attrs)
    assert not provenance_problems(MANIFEST[f"{name}.nc"]), name


def test_every_stored_voltage_stretch_curve_has_values_or_a_computed_cause():
    """A curve of ch3_voltage_stretch is computed (finite values up to its failure point),
    or its absence is a computed failure with its cause: the permittivity factor
    K = 1 + c(5 lam/2 - 2) of (3.30) is already non-positive at the pre-stretch."""
    from debench.models.circular.circle_a import electrostriction_factor
    from debench.reference.builders.ch3 import MODES

    ds = read_dataset("ch3_voltage_stretch")
    fp = read_dataset("ch3_failure_points").sel(equilibrium="printed")
    code = MODES.index("permittivity") + 1
    finite = np.isfinite(ds.phibar.values).sum(axis=-1)
    for i, j in zip(*np.nonzero(finite < 2), strict=True):
        lamP, c = float(ds.lamP[i]), float(ds.c[j])
        assert int(fp.failure_mode.sel(lamP=lamP, c=c)) == code, (lamP, c)
        assert float(electrostriction_factor(lamP, c)) <= 0, (lamP, c)


@pytest.mark.parametrize("argv0", ["/usr/bin/debench", "/x/reference/cli.py",
                                   "/x/venv/src/debench/__main__.py"])
def test_every_entry_point_is_recorded_as_debench(argv0, monkeypatch):
    """The console script, the CLI module and `python -m debench` record the same command,
    so that a dataset written by any of them passes the provenance check."""
    import sys

    from debench.reference.provenance import command_line
    monkeypatch.setattr(sys, "argv", [argv0, "reproduce", "ch3", "--write-data"])
    assert command_line() == "debench reproduce ch3 --write-data"
    assert not provenance_problems({"git_commit": "abc", "command": command_line()})
    monkeypatch.setattr(sys, "argv", ["/x/other/__main__.py", "reproduce"])
    assert command_line().startswith("/x/other/__main__.py")
