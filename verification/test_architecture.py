"""The import graph of the package holds its layers (DESIGN.md, "Where a computation
lives"): the physics (``models``) never imports the verdict (``reference``); the chapters'
models never import each other, nor do different chapters' studies, builders and
producers; builders (datasets, figures) and producers (catalogue outcomes) never import
each other, both read the chapter's study; and the modules of ``reference`` import each
other without a cycle.

Imports are read with :mod:`ast` from the source folders (at any depth of a file: a
function-level import is an edge too) and resolved through the folder-to-namespace
mapping of ``pyproject.toml`` (``models/`` -> ``debench.models`` ...)."""

from __future__ import annotations

import ast
import functools
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: source folder -> installed package (pyproject.toml [tool.setuptools.package-dir])
FOLDERS = {"debench": "debench", "models": "debench.models", "reference": "debench.reference"}
#: the chapter of each model package
MODEL_CHAPTERS = {"circular": "3", "plate": "4", "buckling": "5"}


def _modules() -> dict[str, Path]:
    out = {}
    for folder, package in FOLDERS.items():
        for path in sorted((ROOT / folder).rglob("*.py")):
            rel = path.relative_to(ROOT / folder).with_suffix("")
            parts = [p for p in rel.parts if p != "__init__"]
            out[".".join([package, *parts])] = path
    return out


MODULES = _modules()


@functools.cache
def _tree(path: Path) -> ast.Module:
    """The parsed source of ``path`` (parsed once per process; the tests only read it)."""
    return ast.parse(path.read_text())


def _resolve(name: str) -> str | None:
    """The module ``name`` names, or the nearest enclosing module of ours (an attribute)."""
    while name:
        if name in MODULES:
            return name
        name = name.rpartition(".")[0]
    return None


def _imports(module: str, path: Path) -> set[str]:
    is_package = path.name == "__init__.py"
    package = module if is_package else module.rpartition(".")[0]
    out = set()
    for node in ast.walk(_tree(path)):
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")
                anchor = anchor[: len(anchor) - (node.level - 1)]
                base = ".".join([*anchor, base] if base else anchor)
            names = [f"{base}.{a.name}" for a in node.names] + [base]
        else:
            continue
        for name in names:
            target = _resolve(name)
            if target is not None and target != module:
                out.add(target)
    return out


@functools.cache
def _graph() -> dict[str, set[str]]:
    """Module -> the modules of ours it imports (built when a test first asks, not at
    collection)."""
    return {m: _imports(m, p) for m, p in MODULES.items()}


def _edges(src, dst):
    return sorted(f"{a} -> {b}" for a, targets in _graph().items() if src(a)
                  for b in targets if dst(b))


def _under(prefix: str):
    return lambda m: m == prefix or m.startswith(prefix + ".")


def _chapter(module: str) -> str | None:
    parts = module.split(".")
    if parts[:2] == ["debench", "models"] and len(parts) > 2:
        return MODEL_CHAPTERS.get(parts[2])
    if parts[:2] == ["debench", "reference"] and len(parts) > 3 and parts[2] in (
            "builders", "producers", "studies"):
        match = re.match(r"_?ch(\d)", parts[3])
        return match.group(1) if match else None
    return None


def test_the_graph_sees_every_layer():
    """The parse finds the package's modules and their imports (a guard against a graph
    that is empty and therefore passes everything)."""
    assert len(MODULES) > 80
    assert "debench.reference.catalogue" in _graph()["debench.reference.producers.ch3"]
    assert "debench.models.circular.actuator" in _graph()["debench.reference.producers.ch3"]


def test_models_never_import_reference():
    assert _edges(_under("debench.models"), _under("debench.reference")) == []


def test_chapters_never_import_each_other():
    """Models of one chapter import no model of another; the studies, builders and
    producers of one chapter import none of another chapter's."""
    bad = [f"{a} -> {b}" for a, targets in _graph().items() for b in targets
           if _chapter(a) and _chapter(b) and _chapter(a) != _chapter(b)]
    assert bad == []


def test_builders_and_producers_never_import_each_other():
    builders, producers = (_under("debench.reference.builders"),
                           _under("debench.reference.producers"))
    assert _edges(builders, producers) == []
    assert _edges(producers, builders) == []


def test_studies_import_neither_builders_nor_producers():
    studies = _under("debench.reference.studies")
    assert _edges(studies, _under("debench.reference.builders")) == []
    assert _edges(studies, _under("debench.reference.producers")) == []


def _cycles(nodes: set[str]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(_graph()[v] & nodes):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(nodes):
        if v not in index:
            visit(v)
    return out


@pytest.mark.parametrize("layer", ["debench.reference", "debench.models"])
def test_no_import_cycles(layer):
    """No cycle among the modules of a layer (package ``__init__`` re-exports excluded: an
    ``__init__`` that imports its own submodules is how a package presents them)."""
    nodes = {m for m in _graph() if _under(layer)(m)
             and MODULES[m].name != "__init__.py"}
    assert _cycles(nodes) == []


def _bound_names(node) -> set[tuple]:
    """(module, name, alias) of every name an import statement binds."""
    if isinstance(node, ast.Import):
        return {(a.name, None, a.asname) for a in node.names}
    return {(node.module, a.name, a.asname) for a in node.names}


def test_no_function_imports_what_its_module_already_imports():
    """An import inside a function is for a heavy or optional package, or to keep a
    command's start-up light; one that repeats a module-level import of the same file
    binds nothing new and only hides where the name comes from."""
    found = []
    for path in MODULES.values():
        tree = _tree(path)
        top = set().union(*(_bound_names(n) for n in tree.body
                            if isinstance(n, (ast.Import, ast.ImportFrom))))
        for fn in ast.walk(tree):
            if not isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            for node in ast.walk(fn):
                if isinstance(node, (ast.Import, ast.ImportFrom)):
                    found += [f"{path.relative_to(ROOT)}:{node.lineno} {m}.{n or ''}"
                              for m, n, a in _bound_names(node) & top]
    assert not found, found


#: the longest a hand-written module may be (a longer one holds more than one concept);
#: generated code (sympy output, named ``generated*``) is exempt
MAX_MODULE_LINES = 600


def test_no_hand_written_module_is_longer_than_the_limit():
    long = {name: n for name, path in MODULES.items()
            if "generated" not in path.stem
            and (n := len(path.read_text().splitlines())) > MAX_MODULE_LINES}
    assert not long, f"modules over {MAX_MODULE_LINES} lines: {long}"


#: third-party packages whose import costs start-up time or which are optional: a
#: function may import them (or a module of ours that imports one at its top) lazily
HEAVY_PACKAGES = {"ngsolve", "netgen", "pyngcore", "matplotlib", "dask", "distributed",
                  "sympy", "mpmath", "skfem", "tqdm", "xarray", "netCDF4", "cf_units",
                  "scipy", "hypothesis", "pytest", "compliance_checker", "yaml"}
#: the modules every ``debench`` command imports before it parses its arguments: their
#: function-level imports keep the start-up light (measured: ``import
#: debench.reference.cli`` 0.3 s; 1.1 s with their imports at module level, which load
#: xarray and netCDF4 for every command)
START_UP = {"debench", "debench.__main__", "debench.reference.cli",
            "debench.reference.results_files", "debench.reference.builds",
            "debench.threads", "debench.pytest_plugin", "debench.testing"}


def _top_level_imports(module: str, path: Path) -> tuple[set[str], set[str]]:
    """(modules of ours, third-party top-level packages) that ``module`` imports at its top
    level (in ``try`` and ``if`` blocks too)."""
    ours, theirs = set(), set()
    tree = _tree(path)
    for stmt in tree.body:
        if isinstance(stmt, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            continue
        for node in ast.walk(stmt):
            if isinstance(node, ast.Import):
                theirs |= {a.name.split(".")[0] for a in node.names}
            elif isinstance(node, ast.ImportFrom) and not node.level:
                theirs.add((node.module or "").split(".")[0])
    ours = {t for t in _imports(module, path) if t in _top_level_targets(module, tree)}
    return ours, theirs - {"debench"}


def _top_level_targets(module: str, tree) -> set[str]:
    body = ast.Module(body=[s for s in tree.body if not isinstance(
        s, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef))], type_ignores=[])
    is_package = MODULES[module].name == "__init__.py"
    package = module if is_package else module.rpartition(".")[0]
    out = set()
    for node in ast.walk(body):
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                base = ".".join([*anchor, base] if base else anchor)
            names = [f"{base}.{a.name}" for a in node.names] + [base]
        else:
            continue
        out |= {t for n in names if (t := _resolve(n)) is not None}
    # importing a module imports its packages
    return out | {p for t in out for p in _parents(t)}


def _parents(module: str) -> set[str]:
    parts = module.split(".")
    return {".".join(parts[:i]) for i in range(1, len(parts)) if ".".join(parts[:i]) in MODULES}


@functools.cache
def _top() -> dict[str, tuple[set[str], set[str]]]:
    """Module -> its top-level imports (:func:`_top_level_imports`), built when first asked."""
    return {m: _top_level_imports(m, p) for m, p in MODULES.items()}


def _is_heavy(module: str, seen=None) -> bool:
    """Whether importing our ``module`` loads a heavy package (through its top-level
    imports, its packages' and theirs)."""
    seen = set() if seen is None else seen
    if module in seen:
        return False
    seen.add(module)
    ours, theirs = _top()[module]
    return bool(theirs & HEAVY_PACKAGES) or any(
        _is_heavy(t, seen) for t in ours | _parents(module))


def test_function_level_imports_are_for_heavy_packages_or_the_start_up():
    """Outside the command start-up path (:data:`START_UP`), a function imports only what
    is heavy or optional (:data:`HEAVY_PACKAGES`, or a module of ours that loads one);
    everything else is imported at the top of the module, where a reader sees it."""
    found = []
    for module, path in MODULES.items():
        if module in START_UP or "generated" in path.stem:
            continue
        tree = _tree(path)
        for fn in ast.walk(tree):
            if not isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            for node in ast.walk(fn):
                if isinstance(node, ast.Import):
                    names = [a.name for a in node.names]
                elif isinstance(node, ast.ImportFrom):
                    if node.level:
                        continue
                    base = node.module or ""
                    names = [f"{base}.{a.name}" for a in node.names]
                else:
                    continue
                for name in names:
                    ours = _resolve(name)
                    heavy = (_is_heavy(ours) if ours is not None
                             else name.split(".")[0] in HEAVY_PACKAGES)
                    if not heavy:
                        found.append(f"{path.relative_to(ROOT)}:{node.lineno} {name}")
    assert not found, found


def test_the_command_start_up_loads_no_heavy_package():
    """``import debench.reference.cli`` (what every ``debench`` command loads before it
    parses its arguments, ``debench --help`` included) loads none of
    :data:`HEAVY_PACKAGES`: a subcommand's module loads what it needs when it runs."""
    code = ("import sys, debench.reference.cli; "
            "print(' '.join(sorted({m.split('.')[0] for m in sys.modules})))")
    loaded = set(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                                check=True).stdout.split())
    assert loaded & HEAVY_PACKAGES == set()
