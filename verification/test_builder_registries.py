"""Every builder declares its own properties: the CPU seconds of its default build
(``BUILD_CPU_S``: ``debench reproduce --jobs`` starts the longest first), whether ``debench
verify`` rebuilds it (``REGENERATED_BY_VERIFY``) and the model guards verify runs for it
(``GUARDS``). A builder added without them is refused by
:func:`~debench.reference.builds.properties`, not scheduled or verified by guess; a guard
that does not resolve to a producer's function fails here."""

from __future__ import annotations

import importlib
import math
from types import SimpleNamespace

import pytest
from debench.reference import builds, cli, values


@pytest.mark.parametrize("chapter", cli.CHAPTERS)
def test_every_builder_declares_its_properties(chapter):
    """Each builder module declares the three properties, of the right kinds."""
    props = builds.properties(chapter)
    assert math.isfinite(props.cpu_s) and props.cpu_s >= 0
    assert isinstance(props.regenerated_by_verify, bool)
    assert all(math.isfinite(c) and c >= 0 for c in props.guards.values())


def test_a_chapter_verify_does_not_rebuild_has_a_reason_to_be_trusted():
    """A finite-element chapter verify does not rebuild is guarded by its model guards; the
    cheap chapters are rebuilt."""
    rebuilt = set(builds.regenerated_by_verify(cli.CHAPTERS))
    assert {"ch2_appendix", "ch3", "ch4"} <= rebuilt
    assert "catalogue" not in rebuilt
    for chapter in ("ch5", "ch5_axisym", "ch5_axisym_path", "ch5_axisym_methods",
                    "ch3_fe_thickness", "ch4_fe"):
        assert chapter not in rebuilt and builds.properties(chapter).guards, chapter


def test_every_model_guard_resolves_to_a_function_of_a_producer():
    """Each ``module:function`` a builder declares imports and is callable (verify calls
    it), lives among the producers of the catalogue, and is declared by one builder only."""
    names = values.model_guard_names()
    assert len(names) == len(set(names)) and names
    declared = [g for c in cli.CHAPTERS for g in builds.properties(c).guards]
    assert len(declared) == len(set(declared))
    for name in names:
        module, _, func = name.partition(":")
        assert module.startswith("debench.reference.producers."), name
        assert callable(getattr(importlib.import_module(module), func)), name


@pytest.mark.parametrize("attrs, named", [
    ({"REGENERATED_BY_VERIFY": False, "GUARDS": {}}, "BUILD_CPU_S"),
    ({"BUILD_CPU_S": -1.0, "REGENERATED_BY_VERIFY": False, "GUARDS": {}}, "BUILD_CPU_S"),
    ({"BUILD_CPU_S": math.inf, "REGENERATED_BY_VERIFY": False, "GUARDS": {}}, "BUILD_CPU_S"),
    ({"BUILD_CPU_S": 1.0, "REGENERATED_BY_VERIFY": "yes", "GUARDS": {}},
     "REGENERATED_BY_VERIFY"),
    ({"BUILD_CPU_S": 1.0, "REGENERATED_BY_VERIFY": True}, "GUARDS"),
    ({"BUILD_CPU_S": 1.0, "REGENERATED_BY_VERIFY": True, "GUARDS": {"nocolon": 1.0}}, "GUARDS"),
])
def test_a_builder_without_its_properties_is_refused_naming_the_attribute(
        monkeypatch, attrs, named):
    monkeypatch.setattr(builds, "builder", lambda chapter: SimpleNamespace(build=None, **attrs))
    with pytest.raises(ValueError, match=f"builder 'stub': {named}"):
        builds.properties("stub")


def test_a_stale_cpu_declaration_is_reported(monkeypatch):
    """``debench reproduce`` names a default build whose measured CPU lies outside
    ``STALE_RATIO`` of its declaration, either way, and only builds that matter for the
    pool's order (at least ``STALE_MIN_S`` declared or measured)."""
    declared = {"slow": 10.0, "fast": 10.0, "ok": 10.0, "tiny": 1.0}
    monkeypatch.setattr(builds, "properties", lambda c: builds.BuildProperties(
        declared[c], False, {}))
    r = builds.STALE_RATIO
    lines = builds.stale_declarations({"slow": 10.0 * r * 1.01, "fast": 10.0 / r / 1.01,
                                       "ok": 10.0 * r * 0.99, "tiny": 4.0})
    assert [line.split(":")[0] for line in lines] == ["slow", "fast"]
    assert "BUILD_CPU_S declares 10 s" in lines[0]
