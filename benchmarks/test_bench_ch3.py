"""Benchmarks of the Chapter 3 circular actuator on the named problems of the suite.

Thread count fixed: OMP_NUM_THREADS=1 (named in the groups). Run:
``python -m pytest benchmarks/test_bench_ch3.py --benchmark-only``.

* one curve point: shooting (one trajectory with complex-step sensitivities) vs one warm
  collocation solve;
* one voltage-stretch curve (lamP = 2, c = 0 and -0.053, 300 points, events located)
  vs the naive baseline: ``solve_bvp`` from a cold start at every one of the 300 points
  (no events);
* the whole chapter: :func:`debench.reference.builders.ch3.compute` (all datasets of Figs 3.2-3.9,
  both equilibrium variants, the eps_r study) against the previous code path (read from
  git history by :mod:`benchmarks.baseline`; skipped without a git checkout) in the same
  run, results asserted equal;
* one RK4 integration of the chapter's 4,800 branch trajectories (complex step): the
  term-by-term right-hand side, one call per variant, vs the factored one, one mixed call;
* the Chapter 3 catalogue producers with the shared memoised computation vs each producer
  computing its own branches and curves (caches cleared before every entry).
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from debench.models.circular import collocation, integrator, shooting  # noqa: E402
from debench.models.circular.actuator import branch, branches, curves  # noqa: E402
from debench.models.circular.chapter_pass import clear_memo  # noqa: E402
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
    """The whole chapter from a cold memo: the chapter pass is forgotten before every round
    (``compute`` memoises it, and a memo hit would time a dictionary look-up)."""
    ds = benchmark.pedantic(builder.compute, setup=clear_memo, rounds=5, iterations=1)
    assert set(ds) >= {"ch3_voltage_stretch", "ch3_c_sweep"}


#: the previous path computes the same discrete solutions (same RK4 grids, events to
#: EVENT_XTOL = 1e-14 in q): datasets agree to rounding amplified by the event location
#: (measured <= 1.1e-11 relative); 1e-9 keeps a 100x margin
SAME_RESULTS_RTOL = 1e-9


@pytest.mark.benchmark(group="ch3-chapter-1thread")
def test_bench_whole_chapter_previous_path(benchmark):
    """The code path before the batched pass (tag
    :data:`benchmarks.baseline.CH3_BEFORE_BATCHED_PASS`, loaded from git history: one trace
    and one event location per equilibrium variant, the term-by-term RK4, loss of tension
    located per c): same datasets, timed in the same run as :func:`builder.compute`."""
    from benchmarks import baseline

    try:
        previous = baseline.load()["ch3_builder"]
    except baseline.BaselineUnavailable as exc:
        pytest.skip(f"previous Chapter 3 code not available from git: {exc}")
    old = benchmark.pedantic(previous.compute, rounds=5, iterations=1)
    new = builder.compute()
    for name, ds in old.items():
        for var in ds.data_vars:
            a, b = ds[var].values, new[name][var].values
            if np.issubdtype(a.dtype, np.number):
                np.testing.assert_allclose(b, a, rtol=SAME_RESULTS_RTOL, atol=1e-14)
            else:
                np.testing.assert_array_equal(b, a)


#: the branch grids of the whole chapter: 8 pre-stretches x 300 points x 2 variants
_BRS = branches([Annulus(lp, equilibrium=eq) for eq in ("printed", "membrane")
                 for lp in builder.LAMP_CURVES])
GRID_Q = np.concatenate([b.q for b in _BRS])
GRID_LAMP = np.concatenate([np.full(b.q.size, b.annulus.lamP) for b in _BRS])
GRID_MEM = np.concatenate([np.full(b.q.size, b.annulus.equilibrium == "membrane")
                           for b in _BRS])


@pytest.mark.benchmark(group="ch3-rk4-4800-trajectories-complex-1thread")
def test_bench_rk4_term_by_term_two_calls(benchmark):
    """The previous integrator: term-by-term right-hand side, one call per variant."""
    an = {m: Annulus(2.0, equilibrium="membrane" if m else "printed") for m in (0, 1)}

    def run():
        return [integrator.integrate_reference(an[m], GRID_Q[GRID_MEM == m] + 1e-30j,
                                               lamP=GRID_LAMP[GRID_MEM == m])
                for m in (0, 1)]

    out = benchmark.pedantic(run, rounds=3, iterations=1)
    assert all(np.isfinite(o[0].real).all() for o in out)


@pytest.mark.benchmark(group="ch3-rk4-4800-trajectories-complex-1thread")
def test_bench_rk4_factored_one_mixed_call(benchmark):
    """The current integrator: factored right-hand side, both variants in one call."""
    l1, l2 = benchmark.pedantic(integrator.integrate,
                                args=(Annulus(2.0), GRID_Q + 1e-30j),
                                kwargs={"lamP": GRID_LAMP, "membrane": GRID_MEM}, rounds=3,
                                iterations=1)
    assert np.isfinite(l1.real).all()


# --------------------------------------------------------------------------- producers
def _clear_producer_caches():
    from debench.reference.producers import ch3 as prod

    prod.clear_caches()


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
