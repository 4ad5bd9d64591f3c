"""Benchmarks of the Chapter 3 circular actuator on the named problems of the suite.

Thread count fixed: OMP_NUM_THREADS=1 (named in the groups). Run:
``python -m pytest benchmarks/test_bench_ch3.py --benchmark-only``.

* one curve point: shooting (one trajectory with complex-step sensitivities) vs one warm
  collocation solve;
* one voltage-stretch curve (lamP = 2, c = 0 and -0.053, 300 points, events located)
  vs the naive baseline: ``solve_bvp`` from a cold start at every one of the 300 points
  (no events);
* the whole chapter: :func:`debench.reference.builders.ch3.compute` (all datasets of Figs 3.2-3.9,
  both equilibrium variants, the eps_r study);
* the Chapter 3 catalogue producers with the shared memoised computation vs each producer
  computing its own branches and curves (caches cleared before every entry).
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from debench.models.circular import collocation, shooting  # noqa: E402
from debench.models.circular.actuator import branch, curves  # noqa: E402
from debench.models.circular.params import Annulus  # noqa: E402
from debench.reference.builders import ch3 as builder  # noqa: E402

AN = Annulus(2.0)
N_POINTS = 300


@pytest.mark.benchmark(group="ch3-one-point-1thread")
def test_bench_point_shooting(benchmark):
    st = benchmark(shooting.interface_state, AN, np.array([1.99]))
    assert np.isfinite(st.T1[0])


@pytest.mark.benchmark(group="ch3-one-point-1thread")
def test_bench_point_collocation_warm(benchmark):
    prev = collocation.solve(AN, 3.0, collocation.solve(AN, 2.5))
    sol = benchmark(collocation.solve, AN, 3.05, prev)
    assert sol.nodes > 0


@pytest.mark.benchmark(group="ch3-one-point-1thread")
def test_bench_point_collocation_cold(benchmark):
    sol = benchmark(collocation.solve, AN, 3.05)
    assert sol.nodes > 0


def _curve():
    br = branch(AN, n=N_POINTS)
    return curves(br, [0.0, -0.053])


@pytest.mark.benchmark(group="ch3-one-curve-1thread")
def test_bench_curve_ours(benchmark):
    cvs = benchmark(_curve)
    assert cvs[0].failure.kind == "pullin"


@pytest.mark.benchmark(group="ch3-one-curve-1thread")
def test_bench_curve_naive_cold_solve_bvp(benchmark):
    lam = branch(AN, n=N_POINTS).lam[1:]
    out = benchmark.pedantic(lambda: collocation.branch(AN, lam, warm=False), rounds=1,
                             iterations=1)
    assert out.T1.size == lam.size


@pytest.mark.benchmark(group="ch3-one-curve-1thread")
def test_bench_curve_warm_collocation(benchmark):
    lam = branch(AN, n=N_POINTS).lam[1:]
    out = benchmark.pedantic(lambda: collocation.branch(AN, lam), rounds=1, iterations=1)
    assert out.T1.size == lam.size


@pytest.mark.benchmark(group="ch3-chapter-1thread")
def test_bench_whole_chapter(benchmark):
    ds = benchmark.pedantic(builder.compute, rounds=3, iterations=1)
    assert set(ds) >= {"ch3_voltage_stretch", "ch3_c_sweep"}


# --------------------------------------------------------------------------- producers
def _clear_producer_caches():
    from debench.reference.producers import ch3 as prod

    prod._BRANCHES.clear()
    prod._CURVES.clear()
    prod._PLANNED.clear()
    prod._STATES.clear()
    prod._interface_changes_cached.cache_clear()


def _ch3_entries():
    from debench.reference import catalogue

    return [e for e in catalogue.load()
            if (e.producer or "").startswith("debench.reference.producers.ch3:")]


def _evaluate(entries, shared: bool):
    from debench.reference import catalogue

    _clear_producer_caches()
    out = []
    for e in entries:
        if not shared:          # every producer computes its own branches and curves
            _clear_producer_caches()
        out.append(catalogue.evaluate(e))
    return out


@pytest.mark.benchmark(group="ch3-catalogue-producers-1thread")
def test_bench_producers_unshared(benchmark):
    entries = _ch3_entries()
    res = benchmark.pedantic(_evaluate, args=(entries, False), rounds=1, iterations=1)
    assert not [r for r in res if r.status == "error"]


@pytest.mark.benchmark(group="ch3-catalogue-producers-1thread")
def test_bench_producers_shared(benchmark):
    entries = _ch3_entries()
    res = benchmark.pedantic(_evaluate, args=(entries, True), rounds=1, iterations=1)
    assert not [r for r in res if r.status == "error"]
