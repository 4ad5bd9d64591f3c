"""The ``>>>`` examples of the package's docstrings run and print what they show (the
package's modules are walked, so a new example is collected without being listed)."""

from __future__ import annotations

import doctest
import importlib
import importlib.util
import pkgutil

import pytest

import debench

PACKAGES = ("debench", "debench.models", "debench.reference")


def _modules_with_examples() -> list[str]:
    out = set()
    for name in PACKAGES:
        pkg = importlib.import_module(name)
        for info in pkgutil.walk_packages(pkg.__path__, prefix=f"{name}."):
            spec = importlib.util.find_spec(info.name)
            if spec is None or spec.origin is None or not spec.origin.endswith(".py"):
                continue
            with open(spec.origin, encoding="utf-8") as fh:
                if ">>>" in fh.read():
                    out.add(info.name)
    return sorted(out)


MODULES = _modules_with_examples()


def test_examples_are_found():
    """The walk sees the examples (a guard against collecting nothing)."""
    assert debench.__name__ == "debench"
    assert len(MODULES) >= 4, MODULES


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples_run(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE,
                             verbose=False)
    assert result.attempted > 0, name
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples of {name} failed"
