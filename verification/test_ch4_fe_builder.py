"""The Chapter 4 strip-FE builder runs its comparisons as independent tasks
(:func:`debench.reference.builders.ch4_fe.plan`, on Dask or serially) and assembles its
three datasets from their results: every comparison the datasets hold is one task, listed
once, and a dataset is built from the task results it is given (no comparison computed
again)."""

from __future__ import annotations

import numpy as np
import pytest
from debench.reference.builders import ch4_fe as builder
from debench.reference.studies import ch4_fe as prod_study


@pytest.mark.parametrize("full", [False, True])
def test_plan_lists_every_comparison_of_the_datasets_once(full):
    p = builder.plan(full)
    cases = prod_study.CASES_FULL if full else prod_study.CASES_FAST
    assert len(p["agreement"]) == len(cases) + len(prod_study.VOLTAGE_CASES)
    assert len(p["convergence"]) == len(builder.CONVERGENCE_CASES) * len(
        builder.CONVERGENCE_LEVELS)
    assert [t[1] for t in p["limits"]] == list(prod_study.LIMITS)
    tasks = [t for ts in p.values() for t in ts]
    assert len(set(tasks)) == len(tasks)
    assert {t[4] for t in p["agreement"]} == {2 if full else 0}


def test_datasets_are_built_from_the_task_results(monkeypatch):
    """With every task's result given, no comparison is computed and each row is the
    given result (distinct stand-in values per task)."""
    def refuse(*a, **k):
        raise AssertionError("a comparison was computed again")

    monkeypatch.setattr(prod_study, "compare", refuse)
    monkeypatch.setattr(prod_study, "limit_comparison", refuse)
    p = builder.plan(False)
    done, k = {}, 0
    for t in (t for ts in p.values() for t in ts):
        k += 1
        xi, load, kH = (0.0, 0.0, 20.0) if t[0] is builder.limit_task else t[1:4]
        done[t] = (prod_study.Comparison(xi, load, kH, "E", "charge", 1.0, 1.0 + k * 1e-3, 10 * k,
                                   0),)
        if t[0] is builder.limit_task:
            done[t] = done[t][0]
    agr = builder.agreement_dataset(False, done)
    want = [done[t][0].lam_fe for t in p["agreement"]]
    np.testing.assert_array_equal(agr.lam_fe.values, want)
    conv, _ = builder.convergence_dataset(done)
    np.testing.assert_array_equal(conv.error.values.ravel(),
                                  [done[t][0].diff for t in p["convergence"]])
    lim = builder.limits_dataset(done)
    np.testing.assert_array_equal(lim.ndof.values, [done[t].ndof for t in p["limits"]])
