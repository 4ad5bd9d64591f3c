"""The three registries that describe the builders stay consistent with the builders that
exist: the expected build cost of ``debench reproduce --jobs`` (longest first,
``builds.BUILD_CPU_S``), the chapters ``debench verify`` does not rebuild
(``cli.NOT_REGENERATED_BY_VERIFY``) and the model guards that verify runs instead
(``values.EXTRA_GUARDS``). A builder added, renamed or removed without its entries fails
here, not silently in the scheduling or in what verify checks."""

from __future__ import annotations

import importlib
import math

from debench.reference import builds, cli, values


def test_every_builder_has_a_build_cost_and_every_cost_a_builder():
    """Each builder has its measured cost (a builder without one is scheduled as if it cost
    ``UNLISTED_BUILD_CPU_S``, out of order), and no cost names a builder that is gone."""
    assert set(builds.BUILD_CPU_S) == set(cli.CHAPTERS) - {"catalogue"}
    assert all(math.isfinite(c) and c >= 0 for c in builds.BUILD_CPU_S.values())


def test_chapters_verify_does_not_rebuild_exist_and_the_rest_is_rebuilt():
    """NOT_REGENERATED_BY_VERIFY names builders only; REGENERATED_BY_VERIFY is the rest."""
    assert set(cli.NOT_REGENERATED_BY_VERIFY) <= set(cli.CHAPTERS)
    assert set(cli.REGENERATED_BY_VERIFY) == set(cli.CHAPTERS) - set(
        cli.NOT_REGENERATED_BY_VERIFY)


def test_every_extra_guard_resolves_to_a_function_of_a_producer():
    """Each ``module:function`` of EXTRA_GUARDS imports and is callable (verify calls it),
    and lives among the producers of the catalogue."""
    for name in values.EXTRA_GUARDS:
        module, _, func = name.partition(":")
        assert module.startswith("debench.reference.producers."), name
        assert callable(getattr(importlib.import_module(module), func)), name
