"""Chapter 5 sweeps on Dask ``distributed`` and the coarse recomputation for ``verify``.

Claims:

* the independent finite-element cases of ``reference/builders/ch5.py`` give the same
  results as tasks on a 2-worker ``LocalCluster`` (one thread per worker, reached by its
  scheduler address as an existing cluster would be) as in the serial run: each task is
  deterministic and single-threaded, so the values are bit-identical;
* :func:`coarse_values` returns its documented keys with the values of the tasks it runs.
"""

from __future__ import annotations

import pytest
from debench.reference.builders import ch5


def test_two_worker_dask_sweep_equals_serial_run():
    """Two coarse cases (critical voltage, neo-Hookean 1 mm at h = 3 and 2.5 t0) computed
    as tasks on a 2-worker LocalCluster equal the serial run exactly."""
    from distributed import LocalCluster

    tasks = [(ch5.critical_task, "nh_t1", 3.0), (ch5.critical_task, "nh_t1", 2.5)]
    serial = ch5.run_tasks(tasks, scheduler=None, progress=False)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster:
        parallel = ch5.run_tasks(tasks, scheduler=cluster.scheduler_address)
    assert parallel == serial
    assert serial[0]["ndof"] < serial[1]["ndof"]


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
