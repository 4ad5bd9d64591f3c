"""Provenance of computed artefacts: git commit, package versions, command line.

Every dataset and report records where it came from (DESIGN.md, "Data carries
provenance"). These helpers never raise: a missing git checkout is recorded as
``"unknown"`` rather than failing a reproduction on a machine without git.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from functools import cache
from importlib.metadata import PackageNotFoundError, metadata, version
from pathlib import Path

#: Packages whose versions are recorded in every dataset.
TRACKED_PACKAGES = (
    "debench", "numpy", "scipy", "sympy", "xarray", "netCDF4", "ngsolve", "matplotlib",
)

def _source_root() -> Path | None:
    """The source checkout this package runs from (editable install), else ``None``."""
    root = Path(__file__).resolve().parents[1]
    return root if (root / "pyproject.toml").is_file() and (root / ".git").exists() else None


#: Labels of ``[project.urls]`` that name the source repository: the well-known label
#: ``source`` and its aliases (PyPA, "Well-known Project URLs in Metadata"), normalised
#: (lower case, punctuation and whitespace removed).
REPOSITORY_LABELS = ("source", "repository", "sourcecode", "github")


def project_urls() -> dict[str, str]:
    """The URLs of ``[project.urls]`` in ``pyproject.toml``: the one place the project's
    addresses are stated, read from the installed metadata (``Project-URL``).

    Returns
    -------
    dict of str to str
        Label to URL; empty when debench is not installed.
    """
    try:
        entries = metadata("debench").get_all("Project-URL") or []
    except PackageNotFoundError:
        return {}
    pairs = (e.partition(",") for e in entries)
    return {label.strip(): url.strip() for label, _, url in pairs}


def repository_url() -> str | None:
    """The public repository URL: the ``[project.urls]`` entry under a label of
    :data:`REPOSITORY_LABELS` (also ``repository-code`` in CITATION.cff).

    Returns
    -------
    str or None
        ``None`` while the project has no public address: a citation or dataset never
        carries a made-up one.
    """
    for label, url in project_urls().items():
        if re.sub(r"[^a-z]", "", label.lower()) in REPOSITORY_LABELS:
            return url
    return None


#: The git checkout of an editable install; ``None`` for an installed wheel.
REPO_ROOT = _source_root()


#: Outputs, not sources: changes below these paths do not make the tree dirty (a
#: ``debench reproduce --write-data`` rewrites ``data/`` while it runs).
OUTPUT_PATHS = ("data",)


def git_commit(root: Path | None = REPO_ROOT) -> str:
    """The commit of the source tree, with ``-dirty`` when its code has uncommitted changes.

    Changes to the curated outputs (:data:`OUTPUT_PATHS`) do not count: the data a
    reproduction writes must not mark the reproduction itself as made from a dirty tree.
    ``"unknown"`` outside a git checkout (an installed wheel).
    """
    if root is None:
        return "unknown"
    try:
        sha = subprocess.run(
            ["git", "rev-parse", "HEAD"], cwd=root, capture_output=True, text=True,
            check=True, timeout=10,
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=no", "--", ".",
             *(f":(exclude){p}" for p in OUTPUT_PATHS)], cwd=root,
            capture_output=True, text=True, check=True, timeout=10,
        ).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    return sha + ("-dirty" if dirty else "")


@cache
def package_versions() -> dict[str, str]:
    """Installed versions of :data:`TRACKED_PACKAGES` (``"not installed"`` if absent)."""
    out = {"python": sys.version.split()[0]}
    for name in TRACKED_PACKAGES:
        try:
            out[name] = version(name)
        except PackageNotFoundError:
            out[name] = "not installed"
    return out


def package_versions_json() -> str:
    return json.dumps(package_versions(), sort_keys=True)


def command_line() -> str:
    """The command that is running, as a user would type it."""
    argv = list(sys.argv)
    # the console script, the CLI module and `python -m debench` are one entry point
    if argv and (argv[0].endswith(("debench", "cli.py"))
                 or Path(argv[0]).parts[-2:] == ("debench", "__main__.py")):
        argv[0] = "debench"
    return " ".join(argv) if argv else "python"
