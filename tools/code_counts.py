"""Size and hygiene counts of the source tree (run from anywhere: ``python tools/code_counts.py``).

Counts, over the package folders (``models/``, ``reference/``, ``debench/``; generated
``_generated*.py`` files excluded) unless said otherwise:

* functions of 50 lines or more (``def`` to its last line, decorators excluded);
* modules over 600 lines;
* imports inside function bodies (function-level imports);
* commit hashes written as string literals in ``benchmarks/``;
* ``>>>`` examples in package modules that no test runs (all of them unless a
  ``verification/test_doctests.py`` collects the package's doctests);
* test files in ``verification/`` that import or reach a private name of ``debench``
  (``from debench.x import _y``, a private module ``debench.x._y``, or ``module._y`` on an
  imported ``debench`` module);
* package functions referenced nowhere (the name occurs in no other place of the tree:
  package, tests, benchmarks, tools, examples, ``pyproject.toml``
  and the catalogue's TOML and JSON files).

``--list`` prints the items behind each count.
"""

from __future__ import annotations

import argparse
import ast
import io
import os
import re
import sys
import tokenize
from collections import Counter
from pathlib import Path

#: the source tree counted (``CODE_COUNTS_ROOT`` overrides: count another checkout)
ROOT = Path(os.environ.get("CODE_COUNTS_ROOT") or Path(__file__).resolve().parents[1])
PACKAGE_DIRS = ("models", "reference", "debench")
OTHER_DIRS = ("verification", "benchmarks", "tools", "examples")
LONG_FUNCTION = 50
LONG_MODULE = 600
COMMIT = re.compile(r"^[0-9a-f]{7,40}$")


def _files(dirs) -> list[Path]:
    out = []
    for d in dirs:
        out += sorted(p for p in (ROOT / d).rglob("*.py")
                      if ".venv" not in p.parts and "__pycache__" not in p.parts)
    return out


def _package_files() -> list[Path]:
    return [p for p in _files(PACKAGE_DIRS) if not p.name.startswith("_generated")]


def _rel(p: Path) -> str:
    return str(p.relative_to(ROOT))


def long_functions(files):
    out = []
    for p in files:
        for node in ast.walk(ast.parse(p.read_text())):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                n = node.end_lineno - node.lineno + 1
                if n >= LONG_FUNCTION:
                    out.append((n, f"{_rel(p)}:{node.lineno} {node.name}"))
    return sorted(out, reverse=True)


def long_modules(files):
    out = []
    for p in files:
        n = len(p.read_text().splitlines())
        if n > LONG_MODULE:
            out.append((n, _rel(p)))
    return sorted(out, reverse=True)


def function_level_imports(files):
    out = []
    for p in files:
        tree = ast.parse(p.read_text())
        for fn in ast.walk(tree):
            if isinstance(fn, ast.FunctionDef | ast.AsyncFunctionDef):
                for node in ast.walk(fn):
                    if isinstance(node, ast.Import | ast.ImportFrom):
                        out.append(f"{_rel(p)}:{node.lineno} in {fn.name}")
    # a nested function's import is found from every enclosing function: count it once
    return sorted(set(out))


def hard_coded_commits():
    out = []
    for p in _files(("benchmarks",)):
        for node in ast.walk(ast.parse(p.read_text())):
            if (isinstance(node, ast.Constant) and isinstance(node.value, str)
                    and COMMIT.match(node.value) and re.search(r"\d", node.value)
                    and re.search(r"[a-f]", node.value)):
                out.append(f"{_rel(p)}:{node.lineno} {node.value}")
    return out


def unrun_doctests(files):
    runner = ROOT / "verification" / "test_doctests.py"
    if runner.exists():
        return []
    out = []
    for p in files:
        for i, line in enumerate(p.read_text().splitlines(), 1):
            if line.lstrip().startswith(">>>"):
                out.append(f"{_rel(p)}:{i}")
    return out


def _is_private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")


def private_name_tests():
    out = []
    tests = _files(("verification",))
    tests = [p for p in tests if p.name.startswith("test_")]
    for p in tests:
        tree = ast.parse(p.read_text())
        modules: set[str] = set()
        hits = []
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("debench"):
                if any(_is_private(part) for part in node.module.split(".")):
                    hits.append(node.module)
                for a in node.names:
                    if _is_private(a.name):
                        hits.append(f"{node.module}.{a.name}")
                    else:
                        modules.add(a.asname or a.name)
            elif isinstance(node, ast.Import):
                for a in node.names:
                    if a.name.startswith("debench"):
                        if any(_is_private(part) for part in a.name.split(".")):
                            hits.append(a.name)
                        modules.add(a.asname or a.name.split(".")[0])
        for node in ast.walk(tree):
            if (isinstance(node, ast.Attribute) and _is_private(node.attr)
                    and isinstance(node.value, ast.Name) and node.value.id in modules):
                hits.append(f"{node.value.id}.{node.attr}")
        if hits:
            out.append(f"{_rel(p)}: {', '.join(sorted(set(hits)))}")
    return out, len(tests)


def _names(p: Path) -> Counter:
    c = Counter()
    try:
        for tok in tokenize.generate_tokens(io.StringIO(p.read_text()).readline):
            if tok.type == tokenize.NAME:
                c[tok.string] += 1
            elif tok.type == tokenize.STRING:
                # names used in strings (entry points, getattr, __all__, registries)
                for w in re.findall(r"[A-Za-z_][A-Za-z0-9_]*", tok.string):
                    c[w] += 1
    except (tokenize.TokenError, SyntaxError):
        pass
    return c


def unused_functions(files):
    every = Counter()
    for p in _files(PACKAGE_DIRS + OTHER_DIRS):
        every += _names(p)
    # names used from configuration and the catalogue (entry points, check functions)
    extras = [ROOT / "pyproject.toml", *sorted((ROOT / "reference").rglob("*.toml")),
              *sorted((ROOT / "reference").rglob("*.json"))]
    for extra in extras:
        every += Counter(re.findall(r"[A-Za-z_][A-Za-z0-9_]*", extra.read_text()))
    out = []
    for p in files:
        tree = ast.parse(p.read_text())
        for node in tree.body:
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                if node.name.startswith("__") or node.decorator_list:
                    continue
                if every[node.name] <= 1:
                    out.append(f"{_rel(p)}:{node.lineno} {node.name}")
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--list", action="store_true", help="print the items behind each count")
    args = ap.parse_args(argv)
    pkg = _package_files()
    priv, n_tests = private_name_tests()
    rows = [
        (f"functions >= {LONG_FUNCTION} lines", long_functions(pkg)),
        (f"modules > {LONG_MODULE} lines", long_modules(pkg)),
        ("function-level imports", function_level_imports(pkg)),
        ("hard-coded commits in benchmarks", hard_coded_commits()),
        (">>> examples no test runs", unrun_doctests(pkg)),
        (f"test files reaching private names (of {n_tests})", priv),
        ("package functions referenced nowhere", unused_functions(pkg)),
    ]
    for label, items in rows:
        print(f"{len(items):5d}  {label}")
        if args.list:
            for it in items:
                print("        ", *(it if isinstance(it, tuple) else (it,)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
