"""The whole Chapter 3 computation, current code against its previous version, in CPU
seconds measured in the same run.

"The whole chapter" is what a command computes for Chapter 3: the builder's
:func:`debench.reference.builders.ch3.compute` (every dataset of Figs 3.2-3.9, both
equilibrium variants, the eps_r study) and every Chapter 3 catalogue producer (the
producers of ``reference/catalogue/ch3.toml`` and the Chapter 3 literature entries), each
from cold caches. The current code computes both in one memoised pass
(:func:`debench.models.circular.chapter_pass.chapter`), so its builder time holds the
catalogue's plan too and its producers mostly read; the sum is what compares. The
previous version is read from git history (:data:`PREVIOUS_COMMIT`, by
:mod:`benchmarks.baseline`; skipped without a git checkout); its values are asserted equal
to the current ones within the producers' stored tolerance. CPU seconds
(``time.process_time``), one thread (conftest), best of :data:`ROUNDS` alternating rounds
(the pytest-benchmark time is that of all rounds, old and new).
Run: ``python -m pytest benchmarks/test_bench_ch3_chapter.py --benchmark-only
-s`` (about 25 s of CPU).
"""

from __future__ import annotations

import time

import numpy as np
import pytest
from debench.reference import catalogue
from debench.reference.builders import ch3 as builder
from debench.reference.producers import ch3 as producers

#: the Chapter 3 analytic code before the one memoised chapter pass shared by the builder
#: and the producers (each computed its own branches, curves and roots)
PREVIOUS_COMMIT = "bench/ch3-before-shared-chapter-pass"
PREVIOUS_FILES = {
    "actuator": "models/circular/actuator.py",
    "analysis": "models/circular/analysis.py",
    "shooting": "models/circular/shooting.py",
    "ch3_builder": "reference/builders/ch3.py",
    "ch3_producers": "reference/producers/ch3.py",
}
ROUNDS = 3


def _entries():
    return [e for e in catalogue.load()
            if (e.producer or "").startswith("debench.reference.producers.ch3:")]


def _clear(mod):
    """Cold caches: the producers' own and the chapter pass's memo."""
    mod.clear_caches()


def _chapter(build, prod, entries):
    """CPU seconds of (builder compute, all ch3 producers) from cold caches, and the
    producers' outcomes."""
    _clear(prod)
    t0 = time.process_time()
    build.compute()
    t1 = time.process_time()
    out = [getattr(prod, e.producer.split(":")[1])(e) for e in entries]
    return t1 - t0, time.process_time() - t1, out


def _alternating(old, new, entries):
    """Best of :data:`ROUNDS` rounds for each of ``old`` and ``new`` (builder, producers
    modules), the rounds alternating so that a change of the machine's load between
    them biases neither: ((builder s, producers s, outcomes) of old, of new)."""
    runs = {0: [], 1: []}
    for _ in range(ROUNDS):
        for k, (build, prod) in enumerate((old, new)):
            runs[k].append(_chapter(build, prod, entries))
    return tuple((min(r[0] for r in runs[k]), min(r[1] for r in runs[k]), runs[k][-1][2])
                 for k in (0, 1))


def _same(a, b):
    """Outcome values equal within the producers' stored tolerance (numbers), else equal."""
    if isinstance(a, float | int) and not isinstance(a, bool):
        return bool(np.isclose(b, a, rtol=producers.ACCURACY.rtol,
                               atol=producers.ACCURACY.atol))
    return a == b


@pytest.mark.benchmark(group="ch3-whole-chapter-cpu-1thread")
def test_bench_whole_chapter_cpu_previous_vs_current(benchmark):
    from benchmarks import baseline

    try:
        old = baseline.load(PREVIOUS_COMMIT, PREVIOUS_FILES)
    except baseline.BaselineUnavailable as exc:
        pytest.skip(f"previous Chapter 3 code not available from git: {exc}")
    entries = _entries()
    # import costs (catalogue, builder modules) paid before timing
    _chapter(builder, producers, entries[:1])
    (ob, op, o_out), (nb, np_, n_out) = benchmark.pedantic(
        _alternating, args=((old["ch3_builder"], old["ch3_producers"]),
                            (builder, producers), entries), rounds=1, iterations=1)
    bad = [e.id for e, a, b in zip(entries, o_out, n_out, strict=True)
           if not _same(a.value, b.value)]
    assert not bad, bad
    benchmark.extra_info.update({
        "previous_builder_cpu_s": ob, "previous_producers_cpu_s": op,
        "current_builder_cpu_s": nb, "current_producers_cpu_s": np_,
        "ratio_previous_over_current": (ob + op) / (nb + np_)})
    print(f"\nChapter 3 CPU s (best of {ROUNDS}): previous {ob:.3f} + {op:.3f} = "
          f"{ob + op:.3f}; current {nb:.3f} + {np_:.3f} = {nb + np_:.3f}; "
          f"ratio {(ob + op) / (nb + np_):.2f}")
