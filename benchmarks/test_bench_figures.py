"""The Chapter 4 figures (Figs 4.2-4.6 from the curated datasets), drawn and written by the
current code against the code of :data:`PREVIOUS_COMMIT`, in CPU seconds measured in the
same run.

The current :func:`debench.reference.figures.save` lays a figure out once for both formats
(:func:`~debench.reference.figures.tight_bbox`) where the previous one laid it out again
for each, and the Chapter 4 builder draws the roots of a (kH, root) array as one
marker-only line per colour instead of one line per root column (the same points). Both
versions write the same files and draw the same thesis values (asserted from the SVGs).
CPU seconds (``time.process_time``), one thread (conftest), :data:`ROUNDS` alternating
rounds, best of each. Run: ``python -m pytest benchmarks/test_bench_figures.py
--benchmark-only -s`` (about 50 s of CPU).
"""

from __future__ import annotations

import time

import pytest
from debench.reference import figures as F
from debench.reference.builders import ch4
from debench.reference.datasets import read_dataset

#: the figure code before one layout pass per figure and the merged root lines
PREVIOUS_COMMIT = "bench/figures-before-one-layout-pass"
PREVIOUS_FILES = {"figures": "reference/figures.py", "ch4_builder": "reference/builders/ch4.py"}
ROUNDS = 1
DATASETS = ("ch4_fig4_2_curves", "ch4_fig4_5_curves", "ch4_limits", "ch4_areas",
            "ch4_critical_dhat")


def _draw(module, data, out):
    """CPU seconds of ``module.figures`` on ``data`` into ``out`` and the paths written."""
    t0 = time.process_time()
    paths = module.figures(out, *data)
    return time.process_time() - t0, paths


def _alternating(old, new, data, tmp_path):
    runs = {0: [], 1: []}
    for r in range(ROUNDS):
        for k, mod in enumerate((old, new)):
            runs[k].append(_draw(mod, data, tmp_path / f"{k}-{r}"))
    return tuple((min(x[0] for x in runs[k]), runs[k][-1][1]) for k in (0, 1))


@pytest.mark.benchmark(group="figures-ch4-cpu-1thread")
def test_bench_ch4_figures_previous_vs_current(benchmark, tmp_path):
    from benchmarks import baseline

    try:
        old = baseline.load(PREVIOUS_COMMIT, PREVIOUS_FILES)
    except baseline.BaselineUnavailable as exc:
        pytest.skip(f"previous figure code not available from git: {exc}")
    data = tuple(read_dataset(n) for n in DATASETS)
    F.pyplot()                      # backend and style set before timing
    (t_old, p_old), (t_new, p_new) = benchmark.pedantic(
        _alternating, args=(old["ch4_builder"], ch4, data, tmp_path), rounds=1,
        iterations=1)
    assert [p.name for p in p_old] == [p.name for p in p_new]
    for a, b in zip(p_old, p_new, strict=True):
        if a.suffix == ".svg":
            assert F.drawn_entries(a.read_text()) == F.drawn_entries(b.read_text()), a.name
    benchmark.extra_info.update({"previous_cpu_s": t_old, "current_cpu_s": t_new,
                                 "ratio_previous_over_current": t_old / t_new})
    print(f"\nChapter 4 figures CPU s: previous {t_old:.2f}, current {t_new:.2f}, "
          f"ratio {t_old / t_new:.2f}")
