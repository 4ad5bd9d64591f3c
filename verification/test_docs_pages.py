"""The docs' generated pages, fast (the site itself is built by ``test_docs.py``, opt-in
with ``--docs``):

* the peers page: the submission guide and the consensus table are shown where the
  repository has them, said absent where it does not, and any other failure fails the
  build;
* the docs extra alone builds the site: the page generation and every module it documents
  or evaluates import without the test extra (pytest above all; autodoc mocks only what
  ``docs/conf.py`` names in ``autodoc_mock_imports``).
"""

from __future__ import annotations

import ast
import os
import re
import subprocess
import sys
import textwrap
import tomllib
import types

import pytest

from verification._loaders import ROOT, load_script

#: import names of the test extra's distributions that the base install lacks: the README's
#: documentation command installs only the docs extra, so none of these may be needed
TEST_ONLY_IMPORTS = {
    "pytest": ("pytest", "_pytest"), "pytest-benchmark": ("pytest_benchmark",),
    "pytest-xdist": ("xdist",), "hypothesis": ("hypothesis",), "pyyaml": ("yaml",),
    "compliance-checker": ("compliance_checker",), "scikit-fem": ("skfem",),
}


@pytest.fixture
def pages(tmp_path, monkeypatch):
    mod = load_script("docs/_ext/debench_pages.py")
    monkeypatch.setattr(mod, "OUT", tmp_path / "generated")
    monkeypatch.setattr(mod, "ROOT", tmp_path)
    return mod


def _page(pages) -> str:
    pages.peers_page()
    return (pages.OUT / "peers.md").read_text()


def test_absent_guide_and_consensus_are_said_absent(pages, monkeypatch):
    monkeypatch.setitem(sys.modules, "debench.reference.consensus", None)  # import fails
    text = _page(pages)
    assert "has no `peers/README.md`" in text and "has no consensus table" in text


def test_present_guide_and_consensus_are_shown(pages, monkeypatch):
    (pages.ROOT / "peers").mkdir()
    (pages.ROOT / "peers" / "README.md").write_text("# Submitting\n")
    fake = types.ModuleType("debench.reference.consensus")
    fake.consensus_markdown = lambda: "| code | value |\n|---|---|\n| peer | 0.22 |"
    monkeypatch.setitem(sys.modules, "debench.reference.consensus", fake)
    text = _page(pages)
    assert "{include} ../../peers/README.md" in text and "| peer | 0.22 |" in text


def test_consensus_without_a_known_function_fails(pages, monkeypatch):
    monkeypatch.setitem(sys.modules, "debench.reference.consensus",
                        types.ModuleType("debench.reference.consensus"))
    with pytest.raises(RuntimeError, match="consensus"):
        _page(pages)


def test_a_failing_consensus_table_fails(pages, monkeypatch):
    fake = types.ModuleType("debench.reference.consensus")

    def broken():
        raise ValueError("a submission does not match its checksum")

    fake.consensus_markdown = broken
    monkeypatch.setitem(sys.modules, "debench.reference.consensus", fake)
    with pytest.raises(ValueError, match="checksum"):
        _page(pages)


def _names(requirements: list[str]) -> set[str]:
    return {re.split(r"[<>=!~\[; ]", r, maxsplit=1)[0].lower() for r in requirements}


def test_blocked_imports_cover_the_test_only_distributions():
    """:data:`TEST_ONLY_IMPORTS` names every distribution of the test extra that is not a
    dependency of debench itself (a new test dependency must be added there)."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    only = _names(project["optional-dependencies"]["test"]) - _names(project["dependencies"])
    assert only == set(TEST_ONLY_IMPORTS)


def _mocked_by_autodoc() -> list[str]:
    tree = ast.parse((ROOT / "docs" / "conf.py").read_text())
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(
                getattr(t, "id", None) == "autodoc_mock_imports" for t in node.targets):
            return list(ast.literal_eval(node.value))
    return []


def test_docs_pages_need_no_test_extra(tmp_path):
    """With every test-only import blocked (as in a venv with only ``.[docs]``), the API,
    CLI and citation pages generate, and every module an API page documents, or any other
    debench module (the catalogue's producers the verdict evaluates), imports, or fails
    only on a module that autodoc mocks."""
    blocked = sorted({n for names in TEST_ONLY_IMPORTS.values() for n in names})
    script = textwrap.dedent(f"""
        import importlib, importlib.abc, pkgutil, re, sys
        from pathlib import Path

        BLOCKED, MOCKED = {blocked!r}, {_mocked_by_autodoc()!r}

        class Blocked(importlib.abc.MetaPathFinder):
            def find_spec(self, name, path=None, target=None):
                if name.split(".")[0] in BLOCKED:
                    raise ModuleNotFoundError(f"No module named {{name!r}}", name=name)

        sys.meta_path.insert(0, Blocked())
        sys.path.insert(0, {str(ROOT / "docs" / "_ext")!r})
        import debench_pages

        debench_pages.OUT = Path({str(tmp_path)!r})
        debench_pages.api_pages()
        debench_pages.cli_page()
        debench_pages.cite_example()
        documented = [re.search(r"automodule:: (\\S+)", p.read_text())[1]
                      for p in sorted(debench_pages.OUT.glob("api/*.rst"))]
        modules = []
        for top in ("debench", "debench.models", "debench.reference"):
            pkg = importlib.import_module(top)
            modules += [m.name for m in pkgutil.walk_packages(pkg.__path__, top + ".")
                        if not m.name.endswith("__main__")]
        for mod in dict.fromkeys(documented + modules):
            try:
                importlib.import_module(mod)
            except ModuleNotFoundError as exc:
                if (exc.name or "").split(".")[0] not in MOCKED:
                    raise
        print(len(documented), "documented modules")
    """)
    env = {**os.environ, "DEBENCH_THREADS": "1", "MPLBACKEND": "Agg"}
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         timeout=600, env=env)
    assert run.returncode == 0, run.stderr[-3000:]
    assert int(run.stdout.split()[-3]) > 10  # the API pages were really written


def test_dataset_page_numbers_are_formatted_for_reading(pages):
    """Numbers of a dataset page (parameters, accuracies, numeric attributes and JSON
    lists or mappings of them) are shown to 12 significant digits at most; other stored
    text is shown as the file stores it."""
    assert pages._md_number(4.1595000000000006e-11) == "4.1595e-11"
    assert pages._md_number("[3.3333333333333335, 2.5]") == "3.33333333333, 2.5"
    assert pages._md_number('{"nh_r10": 10.0}') == "nh_r10 = 10"
    assert pages._md_number(2.0000000000575113e-07, 6) == "2e-07"
    assert pages._md_number("fitted {'a': 1} | b") == "fitted {'a': 1} \\| b"


@pytest.mark.parametrize("problem_id", ["ch3_free_membrane_nh", "ch5_critical_voltage",
                                        "ch3_failure_points"])
def test_problem_csv_download_is_checked_as_a_match(pages, problem_id, tmp_path):
    """The CSV downloads of a problem page (docs/_ext) are the reference values in the
    results-file format: ``debench check ID FILE`` accepts each as a match (exit 0), and
    the JSON download is what ``debench problems ID --json`` prints."""
    import json

    from debench.reference import problems
    from debench.reference.cli import main
    from debench.reference.problems_reference import reference_json

    p = problems.get(problem_id)
    lines = pages.problem_downloads(p)
    folder = pages.OUT / "problems" / "data"
    assert json.loads((folder / f"{p.id}.json").read_text()) == json.loads(
        json.dumps(reference_json(p), ensure_ascii=False))
    for q in p.quantities:
        name = f"{p.id}.{q.name}.csv"
        assert any(f"<data/{name}>" in line for line in lines)
        assert main(["check", p.id, str(folder / name)]) == 0, name
