"""What the scikit-fem adapters share: the adapter protocol of ``peers/run.py`` (arguments,
the problem's JSON, results.csv and adapter.json)."""

from __future__ import annotations

import argparse
import importlib.util
import json
import platform
import sys
from pathlib import Path

import numpy as np
import scipy
import skfem

URL = "https://github.com/kinnala/scikit-fem"


def arguments(problem: str, argv=None):
    ap = argparse.ArgumentParser(prog=f"peers/scikit-fem/{problem}.py",
                                 description=f"scikit-fem adapter of {problem}")
    ap.add_argument("--problem-json", help="`debench problems ID --json` (peers/run.py "
                    "passes it; without it the page's parameters and grid are used)")
    ap.add_argument("--out", required=True, help="folder for results.csv and adapter.json")
    ap.add_argument("--label", default="default")
    return ap.parse_args(argv)


def load_clean_room(path, name: str):
    """The repository's clean-room module at ``path`` loaded by its file path as ``name``
    (the peer venv has nothing of debench installed)."""
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod
    spec.loader.exec_module(mod)
    return mod


def problem_json(path):
    if path is None:
        return None
    doc = json.loads(Path(path).read_text())
    return doc


def spec_parameters(doc) -> list[dict]:
    """The spec's parameters as a list of {name, value, units}."""
    return [{"name": k, **v} for k, v in doc["spec"]["parameters"].items()]


def write_results(out, header: str, rows) -> Path:
    """results.csv (written whole, then renamed into place)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    tmp = out / ".results.csv.tmp"
    with tmp.open("w") as fh:
        fh.write(header + "\n")
        for r in rows:
            fh.write(",".join(repr(float(x)) if isinstance(x, float | np.floating) else str(x)
                              for x in r) + "\n")
    tmp.replace(out / "results.csv")
    return out / "results.csv"


def write_adapter_json(out, *, quantity: str, method: dict, check: dict | None,
                       code_version: str) -> Path:
    meta = {"quantity": quantity,
            "code": {"name": "scikit-fem", "version": code_version,
                     "commit_or_release": f"scikit-fem {code_version} (PyPI release), with "
                                          f"numpy {np.__version__}, scipy {scipy.__version__}"
                                          f" on Python {platform.python_version()}",
                     "url": URL, "license": "BSD-3-Clause"},
            "method": method}
    if check:
        meta["check"] = check
    path = Path(out) / "adapter.json"
    path.write_text(json.dumps(meta, indent=1))
    return path


__all__ = ["arguments", "load_clean_room", "problem_json", "spec_parameters", "write_results",
           "write_adapter_json", "skfem"]
