"""Earlier code paths loaded from git history, so that a benchmark times them against the
current code in the same run (no frozen copies in the tree).

:func:`load` reads the files of a named ref with ``git show <ref>:<path>``, writes them
into a temporary package and imports them. Relative and absolute imports between the
loaded files are redirected to the temporary package; every other import resolves to the
installed ``debench``. Raises :class:`BaselineUnavailable` when git, the checkout or the
ref is missing (an installed wheel, a shallow clone, a clone without the tags);
benchmarks skip with its message.

Baselines are named by tag, never by a commit written here: each benchmark names the tag
``bench/<what changed>`` of the last commit before the change it times (``git tag -l
'bench/*'`` lists them; a maintainer creates one with ``git tag bench/<name> <commit>``
when the change lands).
"""

from __future__ import annotations

import ast
import atexit
import importlib
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

#: the Chapter 3 code before the batched pass (one trace and one event location per
#: equilibrium variant, the term-by-term RK4, loss of tension located per c)
CH3_BEFORE_BATCHED_PASS = "bench/ch3-before-batched-pass"
#: module name in the temporary package -> path in the repository at that commit
CH3_FILES = {
    "actuator": "models/circular/actuator.py",
    "analysis": "models/circular/analysis.py",
    "shooting": "models/circular/shooting.py",
    "ch3_builder": "reference/builders/ch3.py",
}
#: repository folder -> installed package name (the namespace of pyproject.toml)
_PACKAGES = {"models": "debench.models", "reference": "debench.reference"}


class BaselineUnavailable(RuntimeError):
    """The earlier code cannot be read from git (no git, no checkout, commit absent)."""


def _git(root: Path, *args: str) -> str:
    try:
        out = subprocess.run(["git", "-C", str(root), *args], capture_output=True,
                             text=True, check=False, timeout=60)
    except (OSError, subprocess.SubprocessError) as exc:
        raise BaselineUnavailable(f"git is not available ({exc})") from exc
    if out.returncode != 0:
        raise BaselineUnavailable(f"git {' '.join(args)} failed: {out.stderr.strip()}")
    return out.stdout


def _package_of(path: str) -> str:
    """Installed package of a repository file: models/circular/x.py -> debench.models.circular."""
    parts = Path(path).parent.parts
    return ".".join([_PACKAGES[parts[0]], *parts[1:]])


def _rewrite(source: str, path: str, files: dict[str, str], pkg: str) -> str:
    """``source`` with every ``from ... import`` that names a loaded file pointed at the
    temporary package ``pkg`` and every other relative import made absolute."""
    loaded = {f"{_package_of(p)}.{Path(p).stem}": name for name, p in files.items()}
    here = _package_of(path)
    lines = source.splitlines(keepends=True)
    edits = []
    for node in ast.walk(ast.parse(source)):
        if not isinstance(node, ast.ImportFrom) or node.module == "__future__":
            continue
        base = here.rsplit(".", node.level - 1)[0] if node.level > 1 else here
        target = (f"{base}.{node.module}" if node.module else base) if node.level else \
            node.module
        alias = [f"{a.name} as {a.asname}" if a.asname else a.name for a in node.names]
        if target in loaded:
            stmts = [f"from {pkg}.{loaded[target]} import {', '.join(alias)}"]
        else:
            rest = [x for a, x in zip(node.names, alias, strict=True)
                    if f"{target}.{a.name}" not in loaded]
            stmts = [f"from {target} import {', '.join(rest)}"] if rest else []
            stmts += [f"from {pkg} import {loaded[f'{target}.{a.name}']} as {a.asname or a.name}"
                      for a in node.names if f"{target}.{a.name}" in loaded]
        indent = " " * node.col_offset
        edits.append((node.lineno, node.end_lineno, [f"{indent}{x}\n" for x in stmts]))
    for start, end, new in sorted(edits, key=lambda e: e[0], reverse=True):
        lines[start - 1:end] = new
    return "".join(lines)


def load(commit: str = CH3_BEFORE_BATCHED_PASS, files: dict[str, str] | None = None,
         *, root: Path | None = None) -> dict[str, object]:
    """Import ``files`` (module name -> repository path) as they were at the ref ``commit``
    (a tag ``bench/...``, or any ref git resolves).

    Returns the modules by name. Raises :class:`BaselineUnavailable` (with the reason and,
    for a missing ref, how to create it) when they cannot be read from git.
    """
    files = dict(CH3_FILES if files is None else files)
    root = Path(__file__).resolve().parents[1] if root is None else Path(root)
    if not (root / ".git").exists():
        raise BaselineUnavailable(f"{root} is not a git checkout (installed package?)")
    try:
        full = _git(root, "rev-parse", "--verify", "--quiet", f"{commit}^{{commit}}").strip()
    except BaselineUnavailable as exc:
        raise BaselineUnavailable(
            f"the baseline ref {commit!r} is not in this clone ({exc}); fetch the tags "
            f"(git fetch --tags) or create it: git tag {commit} <last commit before the "
            "change the benchmark times>") from exc
    pkg = f"_debench_baseline_{full[:12]}"
    if pkg not in sys.modules:
        tmp = Path(tempfile.mkdtemp(prefix="debench-baseline-"))
        atexit.register(shutil.rmtree, tmp, ignore_errors=True)
        (tmp / pkg).mkdir()
        (tmp / pkg / "__init__.py").write_text(
            f'"""Files of commit {full} loaded by benchmarks/baseline.py."""\n')
        for name, path in files.items():
            text = _git(root, "show", f"{full}:{path}")
            (tmp / pkg / f"{name}.py").write_text(_rewrite(text, path, files, pkg))
        sys.path.insert(0, str(tmp))
        try:
            importlib.import_module(pkg)
            for name in files:
                importlib.import_module(f"{pkg}.{name}")
        finally:
            sys.path.remove(str(tmp))
    return {name: sys.modules[f"{pkg}.{name}"] for name in files}
