"""The distribution installs one namespace, ``debench``, with its data inside.

* Every package folder of the repository is listed in ``pyproject.toml`` under the
  ``debench`` namespace, and nothing else is installed at top level.
* With ``--install`` (run by ``.ci/run`` after the README test command): the wheel is
  built, installed into a fresh virtual environment outside the clone, and used from
  there as a user would - import, ``debench --version``, ``debench verify --no-regenerate``.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
NAMESPACE_DIRS = {"debench": "debench", "debench.data": "data",
                  "debench.models": "models", "debench.reference": "reference"}


def _pyproject() -> dict:
    return tomllib.loads((ROOT / "pyproject.toml").read_text())


def _expected_packages() -> set[str]:
    out = set()
    for pkg, folder in NAMESPACE_DIRS.items():
        for init in (ROOT / folder).rglob("__init__.py"):
            rel = init.parent.relative_to(ROOT / folder)
            out.add(".".join([pkg, *rel.parts]))
    return out


def test_pyproject_lists_every_package_folder_under_debench():
    """Each folder with an ``__init__.py`` installs as ``debench.<...>``, and only those."""
    tool = _pyproject()["tool"]["setuptools"]
    assert set(tool["packages"]) == _expected_packages()
    assert all(p == "debench" or p.startswith("debench.") for p in tool["packages"])
    assert tool["package-dir"] == NAMESPACE_DIRS


def test_console_script_and_module_entry_point():
    assert _pyproject()["project"]["scripts"] == {"debench": "debench.reference.cli:main"}
    out = subprocess.run([sys.executable, "-m", "debench", "--version"], capture_output=True,
                         text=True, check=True, timeout=120).stdout
    assert out.startswith("debench ") and "manifest sha256" in out


def test_data_dir_is_the_packaged_data_unless_overridden(monkeypatch, tmp_path):
    from debench.reference import datasets

    monkeypatch.delenv(datasets.DATA_DIR_ENV, raising=False)
    assert (datasets.data_dir() / datasets.MANIFEST_NAME).is_file()
    monkeypatch.setenv(datasets.DATA_DIR_ENV, str(tmp_path))
    assert datasets.data_dir() == tmp_path
    with pytest.raises(datasets.DatasetError, match=str(tmp_path).replace("\\", "\\\\")):
        datasets.read_dataset("ch3_voltage_stretch")


def _run(cmd: list[str], cwd: Path, env: dict[str, str]) -> str:
    proc = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True, timeout=3000)
    tail = f"{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}"
    assert proc.returncode == 0, f"{' '.join(cmd)} failed:\n{tail}"
    return proc.stdout


@pytest.mark.install
def test_wheel_installs_outside_the_clone_and_verifies(tmp_path):
    """Build the wheel, install it in a fresh venv in a temporary directory, use it there."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "VIRTUAL_ENV", "DEBENCH_DATA_DIR")}
    wheels = tmp_path / "wheels"
    _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(wheels), str(ROOT)],
         tmp_path, env)
    (wheel,) = wheels.glob("debench-*.whl")
    with zipfile.ZipFile(wheel) as zf:
        names = zf.namelist()
    top = {n.split("/")[0] for n in names if not n.split("/")[0].endswith((".dist-info", ".data"))}
    assert top == {"debench"}, f"top-level names in the wheel: {sorted(top)}"
    assert "debench/data/MANIFEST.json" in names
    assert "debench/reference/catalogue/ch3.toml" in names
    assert sum(n.startswith("debench/data/") and n.endswith(".nc") for n in names) >= 10

    venv = tmp_path / "venv"
    _run([sys.executable, "-m", "venv", str(venv)], tmp_path, env)
    bindir = venv / ("Scripts" if os.name == "nt" else "bin")
    py = str(bindir / "python")
    _run([py, "-m", "pip", "install", "-q", str(wheel)], tmp_path, env)
    work = tmp_path / "elsewhere"
    work.mkdir()
    _run([py, "-c", "import debench.models, debench.reference"], work, env)
    site = _run([py, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                work, env).strip()
    assert not (Path(site) / "models").exists() and not (Path(site) / "reference").exists()
    version = _run([str(bindir / "debench"), "--version"], work, env)
    assert str(site) in version, version
    _run([str(bindir / "debench"), "verify", "--no-regenerate"], work, env)
