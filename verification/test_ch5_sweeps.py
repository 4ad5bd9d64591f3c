"""Chapter 5 sweeps on Dask ``distributed`` and the coarse recomputation for ``verify``.

Claims:

* the independent finite-element cases of ``reference/studies/ch5.py`` give the same
  results as tasks on a 2-worker ``LocalCluster`` (one thread per worker, reached by its
  scheduler address as an existing cluster would be) as in the serial run: each task is
  deterministic and single-threaded, so the values are bit-identical;
* the default LocalCluster's workers keep glibc's adaptive malloc thresholds (Dask's
  default ``MALLOC_TRIM_THRESHOLD_`` is unset for them);
* :func:`coarse_values` returns its documented keys with the values of the tasks it runs;
* the task cache (``DEBENCH_FE_CACHE``) returns a finished task's result without running it
  again and never serves a result computed by other model code;
* the plan of the converged run meets the reference contract: more mesh levels than the
  fit has unknowns, a finest mesh of >= 150,000 DOFs with >= 2 layers, >= 3 ramp meshes.
"""

from __future__ import annotations

import os

import dask
import pytest
from debench.models.errors import ConvergenceError
from debench.reference import tasks as runner
from debench.reference.studies import ch5

CALLS: list = []


def _square(x):
    """A cheap picklable task that records its calls."""
    CALLS.append(x)
    return {"x2": x * x}


def test_two_worker_dask_sweep_equals_serial_run():
    """Two coarse cases (critical voltage, neo-Hookean 1 mm at h = 3 and 2.5 t0) computed
    as tasks on a 2-worker LocalCluster equal the serial run exactly."""
    from distributed import LocalCluster

    tasks = [(ch5.critical_task, "nh_t1", 3.0), (ch5.critical_task, "nh_t1", 2.5)]
    serial = runner.run_tasks(tasks, scheduler=None, progress=False)
    with dask.config.set(runner.WORKER_CONFIG), \
            LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                         dashboard_address=":0") as cluster:
        parallel = runner.run_tasks(tasks, scheduler=cluster.scheduler_address)
    def values(results):  # everything but the wall time
        return [{k: v for k, v in r.items() if k != "seconds"} for r in results]

    assert values(parallel) == values(serial)
    assert serial[0]["ndof"] < serial[1]["ndof"]


@pytest.mark.skipif("MALLOC_TRIM_THRESHOLD_" in os.environ,
                    reason="the test process itself sets MALLOC_TRIM_THRESHOLD_")
def test_local_cluster_workers_keep_the_adaptive_malloc_threshold(monkeypatch):
    """The workers of the default LocalCluster do not get Dask's MALLOC_TRIM_THRESHOLD_
    (which fixes glibc's mmap threshold and made an FE case 3-7x slower in a worker)."""
    monkeypatch.setenv("DEBENCH_WORKERS", "2")
    tasks = [(os.getenv, "MALLOC_TRIM_THRESHOLD_", "unset")] * 2
    assert runner.run_tasks(tasks, scheduler="local", progress=False) == ["unset", "unset"]


def test_scale_copies_are_the_cases_scale_invariance_makes_identical():
    """Only the 0.5 mm Ogden case is copied, from the 1 mm Ogden case (same material,
    same aspect ratio; the invariance itself is tested in test_ch5_fem.py)."""
    for copy, source in ch5.SCALE_COPIES.items():
        assert ch5.CASES[copy][0] == ch5.CASES[source][0]
        assert ch5.CASES[copy][1] != ch5.CASES[source][1]


@pytest.mark.slow
def test_coarse_values_keys_and_values():
    """--full (about a minute): every case has its coarse critical voltage, the computed
    (non-copy) cases their coarse pull-in voltage and deflection; the values are those of
    the tasks."""
    vals = ch5.coarse_values()
    want = {f"{c}.v_cr" for c in ch5.CASES}
    want |= {f"{c}.{q}" for c in ch5.CASES if c not in ch5.SCALE_COPIES
             for q in ("v_pullin", "w_pullin")}
    assert set(vals) == want
    assert vals["nh_t1.v_cr"] == ch5.critical_task("nh_t1", ch5.COARSE_H)["v"]
    assert vals["ogden_t0p5.v_cr"] == pytest.approx(vals["ogden_t1.v_cr"], rel=1e-5)
    assert vals["ogden_t1.v_pullin"] < vals["nh_t1.v_pullin"]


def test_task_cache_resumes_without_recomputing(tmp_path, monkeypatch):
    """A cached result is returned without calling the task; other model code misses."""
    cache = runner.TaskCache(tmp_path, "a" * 64)
    monkeypatch.setattr(runner.TaskCache, "from_env", classmethod(lambda cls: cache))
    CALLS.clear()
    first = runner.run_tasks([(_square, 3), (_square, 4)], progress=False)
    second = runner.run_tasks([(_square, 4), (_square, 5)], progress=False)
    assert first == [{"x2": 9}, {"x2": 16}] and second == [{"x2": 16}, {"x2": 25}]
    assert CALLS == [3, 4, 5]
    other = runner.TaskCache(tmp_path, "b" * 64)
    assert other.get((_square, 3)) is None and cache.get((_square, 3)) == {"x2": 9}


def _fails(x):
    raise ConvergenceError(f"task {x} did not converge")


def test_a_failed_task_does_not_lose_the_others(tmp_path, monkeypatch):
    """A sweep with a failing task still runs and caches every other task, then raises
    naming the failed one (so that a rerun computes only what failed)."""
    cache = runner.TaskCache(tmp_path, "c" * 64)
    monkeypatch.setattr(runner.TaskCache, "from_env", classmethod(lambda cls: cache))
    CALLS.clear()
    with pytest.raises(ConvergenceError, match=r"1 of 3 FE tasks failed \(_fails\(7,\)\)"):
        runner.run_tasks([(_fails, 7), (_square, 3), (_square, 4)], progress=False)
    assert CALLS == [3, 4]
    assert cache.get((_square, 3)) == {"x2": 9} and cache.get((_square, 4)) == {"x2": 16}


def test_task_cache_key_follows_the_model_source(tmp_path, monkeypatch):
    """The cache key includes the source of debench.models: a different digest misses;
    from_env reads DEBENCH_FE_CACHE and digests the installed models package."""
    monkeypatch.setenv("DEBENCH_FE_CACHE", str(tmp_path))
    cache = runner.TaskCache.from_env()
    assert cache.code_digest == runner.models_digest() and len(cache.code_digest) == 64
    cache.put((_square, 2), {"x2": 4})
    assert runner.TaskCache(tmp_path, "0" * 64).get((_square, 2)) is None
    assert cache.get((_square, 2)) == {"x2": 4}


def _fresh_package(tmp_path, monkeypatch, files: dict):
    """Write the package ``cachekeypkg`` (``files``: module name -> source) and import its
    ``tasks`` module afresh."""
    import importlib
    import sys
    pkg = tmp_path / "cachekeypkg"
    pkg.mkdir(exist_ok=True)
    (pkg / "__init__.py").write_text("")
    for name, src in files.items():
        (pkg / f"{name}.py").write_text(src)
    monkeypatch.syspath_prepend(str(tmp_path))
    for name in [m for m in sys.modules if m.startswith("cachekeypkg")]:
        sys.modules.pop(name)
    importlib.invalidate_caches()
    return importlib.import_module("cachekeypkg.tasks")


TASKS = """from cachekeypkg.settings import OFFSET, helper
PLAN = {"levels": (3, 2)}
SCALE = 2


def scaled(x):
    from cachekeypkg.settings import EXPONENT
    return helper(x) * SCALE + OFFSET ** EXPONENT
"""
SETTINGS = """OFFSET = 1
EXPONENT = 2
UNUSED = 0


def helper(x):
    return x + SHIFT


SHIFT = 0.5
"""


@pytest.mark.parametrize("module, old, new, hit", [
    ("tasks", "SCALE = 2", "SCALE = 3", False),            # a setting the task reads
    ("tasks", '"levels": (3, 2)', '"levels": (3,)', True),  # a plan beside it it never reads
    ("settings", "OFFSET = 1", "OFFSET = 4", False),        # a setting it imports
    ("settings", "EXPONENT = 2", "EXPONENT = 3", False),    # imported inside its body
    ("settings", "SHIFT = 0.5", "SHIFT = 1.5", False),      # read by a helper it calls
    ("settings", "x + SHIFT", "x - SHIFT", False),          # the helper's code
    ("settings", "UNUSED = 0", "UNUSED = 7", True),         # nothing it reads
])
def test_task_cache_key_follows_exactly_what_the_task_reads(tmp_path, monkeypatch, module,
                                                           old, new, hit):
    """The key holds the task's source and every helper, setting and import it reads,
    transitively, inside its package: an edit of any of them misses (never a stale hit);
    an edit of something it never reads (a plan table beside the task) keeps the result."""
    files = {"tasks": TASKS, "settings": SETTINGS}
    tasks = _fresh_package(tmp_path, monkeypatch, files)
    cache = runner.TaskCache(tmp_path / "cache", "e" * 64)
    cache.put((tasks.scaled, 3), tasks.scaled(3))
    assert cache.get((tasks.scaled, 3)) == 8.0
    assert old in files[module]
    files[module] = files[module].replace(old, new)
    tasks = _fresh_package(tmp_path, monkeypatch, files)
    assert (cache.get((tasks.scaled, 3)) is not None) is hit


def test_task_inputs_do_not_follow_the_models_or_other_packages():
    """The models are keyed by their digest and the runner and libraries not at all: the
    path task's inputs are its source, the film table and path settings it reads and the
    material lookup of its study, nothing of debench.models or debench.reference.tasks."""
    from debench.reference.studies import ch5_axisym

    text = runner.task_inputs(ch5_axisym.path_task)
    assert "PATH_FILMS = " in text and "V_SWITCH = 0.8" in text and "def material(" in text
    assert "CRITICAL = " not in text            # the critical-voltage plan beside it
    assert "def limit_threads" not in text and "def follow_path" not in text


def test_full_plan_meets_the_reference_contract():
    """The converged plan (no FE run: mesh sizes only): >= 5 critical-voltage levels
    (the least-squares fit has 3 unknowns, and one more level is dropped for the error
    estimate), the finest with >= 2 layers and an in-plane size whose 2-layer mesh has
    >= 150,000 DOFs (0.45 t0: 154,340, counted by the curated data test), >= 3 ramp meshes
    for the pull-in fit, >= 3 layer counts."""
    plan = ch5.plan(full=True)
    levels = [t[2] for t in plan["critical"] if t[1] == "nh_t1"]
    assert len(levels) >= 5 and min(levels) <= 0.45
    assert {t[3] for t in plan["critical"]} == {ch5.LAYERS[True]} and ch5.LAYERS[True] >= 2
    assert len([t for t in plan["ramps"] if t[1] == "nh_t1"]) >= 3
    assert len(ch5.LAYER_STUDY[True][1]) >= 3
    assert not any(t[1] in ch5.SCALE_COPIES for ts in plan.values() for t in ts)


def test_task_cache_key_follows_the_task_module_settings(tmp_path, monkeypatch):
    """A module-level setting that a task reads (e.g. a builder's EIG_EVERY) is part of the
    key: the same function and arguments under another module source miss."""
    import importlib
    import inspect
    import linecache
    monkeypatch.syspath_prepend(str(tmp_path))
    mod = tmp_path / "cache_probe_task.py"
    mod.write_text("SETTING = 1\n\ndef task(x):\n    return {'y': x * SETTING}\n")
    probe = importlib.import_module("cache_probe_task")
    cache = runner.TaskCache(tmp_path / "cache", "d" * 64)
    cache.put((probe.task, 2), probe.task(2))
    assert cache.get((probe.task, 2)) == {"y": 2}
    mod.write_text("SETTING = 3\n\ndef task(x):\n    return {'y': x * SETTING}\n")
    linecache.clearcache()
    probe = importlib.reload(probe)
    assert "SETTING = 3" in inspect.getsource(probe)
    assert cache.get((probe.task, 2)) is None


def test_longest_tasks_rank_first():
    """The submission order puts the largest meshes first, so that the last task to start is
    a short one: finer critical-voltage meshes and Ogden cases before coarser and
    neo-Hookean ones, ramps before critical voltages on the same mesh, and the radius /
    thickness 20 paths (first argument the mesh size) finest first."""
    from debench.reference.builders import ch5_wrinkling
    from debench.reference.studies import ch5_imperfection as imperfect

    assert ch5.task_cost((ch5.critical_task, "ogden_t1", 2.0)) > ch5.task_cost(
        (ch5.critical_task, "ogden_t1", 3.0)) > ch5.task_cost((ch5.critical_task, "nh_t1", 3.0))
    assert (ch5.task_cost((ch5.ramp_task, "nh_t1", 3.0))
            > ch5.task_cost((ch5.critical_task, "nh_t1", 3.0)))
    paths = [(ch5_wrinkling.wrinkling_task, h, 1) for h in ch5_wrinkling.LEVELS[True]]
    assert max(paths, key=ch5.task_cost)[1] == min(ch5_wrinkling.LEVELS[True])
    assert ch5.task_cost((imperfect.imperfect_path_task, 2.0, 0.002)) > ch5.task_cost(
        (imperfect.imperfect_path_task, 2.5, 0.032))
