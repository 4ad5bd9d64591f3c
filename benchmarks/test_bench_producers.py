"""Benchmarks of the catalogue producers that ``debench verify`` runs, against their
previous code loaded from git history (:mod:`benchmarks.baseline`; skipped without a git
checkout), in the same process and run.

Thread count fixed (``DEBENCH_THREADS``, default 1, see ``conftest.py``; named in the
groups). CPU seconds of this process (``time.process_time``) are reported beside the
pytest-benchmark wall times: on a shared machine they are the better guide. Run the
reports (CPU seconds, ~1 min) with ``python -m pytest benchmarks/test_bench_producers.py
-k report -s`` and the timings with ``--benchmark-only``.

Named problems (every catalogue entry of the producer, memoised results cleared before
each run, so that a run costs what one command costs):

* "ch4_inplane": the ``ch4.beyond.inplane.*`` entries (determinant and FE roots of the
  in-plane fibre). Previous: ellipticity and characteristic roots one grid point at a
  time, the roots of five cases traced twice (memo keyed on how the arguments were
  passed). Current: stacked calls per scan grid, one memo entry per parameter set, each
  FE stretch's eigenvalues once per scan.
* "ch3_c_threshold": the two ``ch3.pullin.c_threshold_*`` entries. Previous: a new
  800-point branch per variant and definition. Current: one per variant, from the
  producers' branch cache.
* "ch4": the ``ch4.*`` entries of the plate producers. Previous: the max-area critical
  Dhat recomputed its 16 regions per xi. Current: from the memoised areas, which the
  Fig. 4.2 producers share at seven Dhat for xi = 0 and 5.

Every value and detail of the current producers equals the previous one exactly (the
changes reorganise the same floating-point operations): asserted.
"""

from __future__ import annotations

import time

import pytest
from debench.reference import catalogue

from benchmarks import baseline
from benchmarks.conftest import THREADS

#: the producers before this rework
PRODUCERS_BEFORE = "bench/producers-before-rework"
FILES_BEFORE = {
    "inplane": "models/plate/inplane.py",
    "ch4_inplane": "reference/producers/ch4_inplane.py",
    "analysis": "models/circular/analysis.py",
    "ch3": "reference/producers/ch3.py",
    "plate_analysis": "models/plate/analysis.py",
    "ch4": "reference/producers/ch4.py",
}


@pytest.fixture(scope="module")
def previous():
    try:
        return baseline.load(PRODUCERS_BEFORE, FILES_BEFORE)
    except baseline.BaselineUnavailable as exc:
        pytest.skip(str(exc))


def _entries(module: str, prefix: str = ""):
    return [e for e in catalogue.load()
            if e.producer and e.producer.split(":")[0].rsplit(".", 1)[-1] == module
            and e.id.startswith(prefix)]


def _clear(mod) -> None:
    """Forget every memoised result of a producer module (its lru caches and, where it
    has one, its ``clear_caches``)."""
    for name in dir(mod):
        obj = getattr(mod, name)
        if callable(getattr(obj, "cache_clear", None)):
            obj.cache_clear()
    if callable(getattr(mod, "clear_caches", None)):
        mod.clear_caches()


def _run_all(mod, entries):
    """(outcomes, CPU seconds): every entry's producer function of ``mod``, caches cold."""
    _clear(mod)
    t = time.process_time()
    out = [getattr(mod, e.producer.split(":")[1])(e) for e in entries]
    return out, time.process_time() - t


def _same(a, b) -> bool:
    """Equal outcomes: value, status and details to the last digit (repr: NaN equals NaN,
    arrays compare element by element)."""
    return (repr(a.value), a.status, repr(a.details)) == (repr(b.value), b.status,
                                                          repr(b.details))


CASES = {"ch4_inplane": ("ch4_inplane", ""),
         "ch3_c_threshold": ("ch3", "ch3.pullin.c_threshold"),
         "ch4": ("ch4", "")}


@pytest.mark.parametrize("name", list(CASES))
def test_producers_speedup_report(name, previous, record_property):
    """Previous and current producers on the same entries: CPU seconds and equality."""
    from importlib import import_module

    module, prefix = CASES[name]
    current = import_module(f"debench.reference.producers.{module}")
    entries = _entries(module, prefix)
    assert entries
    old, t_old = _run_all(previous[module], entries)
    new, t_new = _run_all(current, entries)
    print(f"\n{name} ({len(entries)} entries, {THREADS} thread): previous {t_old:6.2f} s, "
          f"current {t_new:6.2f} s CPU, speed-up {t_old / t_new:4.2f}")
    record_property(f"cpu_previous_{name}", t_old)
    record_property(f"cpu_current_{name}", t_new)
    assert all(_same(a, b) for a, b in zip(old, new, strict=True))


@pytest.mark.benchmark(group=f"producers-ch4_inplane-methods_agree-{THREADS}thread")
@pytest.mark.parametrize("which", ["previous", "current"])
def test_bench_ch4_inplane_methods_agree(benchmark, previous, which):
    """One producer: both methods at the five fibre angles (cold caches)."""
    from debench.reference.producers import ch4_inplane

    mod = ch4_inplane if which == "current" else previous["ch4_inplane"]
    entry = next(e for e in _entries("ch4_inplane")
                 if e.producer.endswith(":methods_agree"))
    out = benchmark.pedantic(lambda: (_clear(mod), mod.methods_agree(entry))[1],
                             rounds=1, iterations=1)
    assert out.value is True
