"""Benchmarks of the Chapter 3 finite-element producers and the thin solid, against the code
before the continuation kept its tangents and the producers shared their work (loaded from
git history by :mod:`benchmarks.baseline`, skipped without a git checkout), in the same run.

Named problems (one thread, ``ngsolve.SetNumThreads(1)`` by the models; CPU time: the
machine is shared, so the timer is ``time.process_time``):

* "fe_suppression": the producer of ``ch3.fe.suppression_prestretch`` (c = 0, coarse mesh):
  the FE root of the minimum slope (previous: brentq on the whole window (2, 3.2), a fresh
  tangent for every predictor; now: from the membrane value -+ the tolerance) beside both
  analytic variants.
* "fe_events": the three ``ch3.fe.*`` event producers (loss of tension at lamP = 3, pull-in
  stretch and voltage at lamP = 1.25; previous: one FE pull-in per entry, the analytic
  events one branch and one event location each; now: one FE state, one batched pass).
* "solid_film": the thickest film (H = 0.2) of the lamP = 3 Phibar sequence of
  ``ch3_fe_thickness`` (previous: a sparse tangent rebuilt through scipy's CSR algebra
  and slicing at every Newton step; now: scattered into a fixed structure).

Run: ``python -m pytest benchmarks/test_bench_ch3_fe.py --benchmark-only``.
"""

from __future__ import annotations

import time

import pytest
from debench.reference import catalogue
from debench.reference.producers import ch3_fe as producers
from debench.reference.studies import ch3_fe as P

from benchmarks import baseline

#: the code before this work
BEFORE = "bench/ch3-fe-before-rework"
FILES = {"fe": "models/circular/fe.py", "fe_solid": "models/circular/fe_solid.py",
         "ch3_fe": "reference/producers/ch3_fe.py"}
EVENT_IDS = ("ch3.fe.loss_of_tension_lamP_3", "ch3.fe.pullin_voltage_lamP_1p25",
             "ch3.fe.pullin_stretch_lamP_1p25")


def _previous():
    try:
        return baseline.load(BEFORE, FILES)["ch3_fe"]
    except baseline.BaselineUnavailable as exc:
        pytest.skip(str(exc))


def _fresh(module):
    """Forget what a producer module memoised, so that every round computes."""
    for name in ("_branch", "_fe_event_state", "_analytic_events_many"):
        f = getattr(module, name, None)
        if f is not None:
            f.cache_clear()


def _close(a: float, b: float) -> bool:
    return abs(a - b) <= producers.ACCURACY.tolerance(b)


def _suppression(module):
    _fresh(module)
    return module.suppression_support(0.0, P.MESH_COARSE, P.TOL_SUPPRESSION_COARSE)


@pytest.mark.benchmark(group="ch3-fe_suppression-coarse-1thread", timer=time.process_time)
def test_bench_fe_suppression_previous(benchmark):
    old = _previous()
    d = benchmark.pedantic(_suppression, args=(old,), rounds=2, iterations=1)
    assert _close(d["fe"], _suppression(P)["fe"])


@pytest.mark.benchmark(group="ch3-fe_suppression-coarse-1thread", timer=time.process_time)
def test_bench_fe_suppression(benchmark):
    d = benchmark.pedantic(_suppression, args=(P,), rounds=2, iterations=1)
    assert d["supports"] == "membrane", d


def _events(module):
    _fresh(module)
    ids = catalogue.by_id()
    return [module.fe_event(ids[i]).details["fe"] for i in EVENT_IDS]


@pytest.mark.benchmark(group="ch3-fe_events-coarse-1thread", timer=time.process_time)
def test_bench_fe_events_previous(benchmark):
    old = _previous()
    got = benchmark.pedantic(_events, args=(old,), rounds=2, iterations=1)
    assert all(_close(a, b) for a, b in zip(got, _events(P), strict=True))


@pytest.mark.benchmark(group="ch3-fe_events-coarse-1thread", timer=time.process_time)
def test_bench_fe_events(benchmark):
    got = benchmark.pedantic(_events, args=(P,), rounds=2, iterations=1)
    assert len(got) == len(EVENT_IDS)


def _film(module):
    g = producers.GUARD_SEQUENCE
    return module.solid_value(g.quantity, g.lamP, g.c, P.THICKNESS_H[0], g.lam_centre,
                              dict(P.SOLID_MESH_COARSE, nz=g.nz))


@pytest.mark.benchmark(group="ch3-solid_film-H0.2-1thread", timer=time.process_time)
def test_bench_solid_film_previous(benchmark):
    old = _previous()
    v = benchmark.pedantic(_film, args=(old,), rounds=2, iterations=1)
    assert _close(v, _film(P))


@pytest.mark.benchmark(group="ch3-solid_film-H0.2-1thread", timer=time.process_time)
def test_bench_solid_film(benchmark):
    v = benchmark.pedantic(_film, args=(P,), rounds=2, iterations=1)
    assert 0 < v < 1
