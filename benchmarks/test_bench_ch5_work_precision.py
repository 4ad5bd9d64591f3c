"""Work-precision of the two Chapter 5 finite-element models: the error of the neo-Hookean
film's critical voltage (R/t0 = 10, n = 0) against the CPU time that buys it, for the 3D
prism model (:mod:`debench.models.buckling.fem`, in-plane mesh size h) and the
axisymmetric model (:mod:`debench.models.buckling.axisym`, order p and grading layers L),
in one benchmark run.

The reference is computed in the same run by the axisymmetric model on its finest
discretisation here (p = 7, L = 8; the curated full plan's error estimate at p = 6, L = 8 is
2e-7, the reproducibility floor of one critical voltage, far below every error in the
table). Thread count fixed: one (``benchmarks/conftest.py``).
Run: ``python -m pytest benchmarks/test_bench_ch5_work_precision.py -s`` (the table;
``--benchmark-only`` runs the timed pair alone). ``CH5_WP_3D="3,2,1.4"`` sets the 3D mesh
sizes h/t0, ``CH5_WP_AXISYM="2:4,3:4,4:6,5:6"`` the axisymmetric (p, L). The report prints
each solve's DOFs, CPU seconds and error, and compares the two curves where both are
measured: the error of the best axisymmetric solve that costs no more CPU than the 3D
model's finest, against that one's error. The CPU ratio at equal error is not measurable
on these sizes (the cheapest axisymmetric solve is already far more accurate than the
finest 3D one); the report gives it as an extrapolation of the 3D curve's measured slope,
labelled as such.
"""

from __future__ import annotations

import math
import os
import time

import numpy as np
import pytest
from debench.models.buckling import axisym
from debench.models.buckling.parameters import Discretisation, NeoHookean, Plate
from debench.models.buckling.solver import critical_voltage

SIZES_3D = tuple(float(x) for x in os.environ.get("CH5_WP_3D", "3,2,1.4").split(","))
DISCS = tuple(tuple(int(y) for y in x.split(":"))
              for x in os.environ.get("CH5_WP_AXISYM", "2:4,3:4,4:6,5:6").split(","))
REFERENCE = (7, 8)
PLATE = Plate(thickness=1e-3, aspect=10.0)


def _axisym(p, L):
    t = time.process_time()
    r = axisym.critical_voltage(PLATE, NeoHookean(), axisym.AxisymDiscretisation(
        order=p, edge_layers=L, face_layers=L), n=0)
    return r.v, r.ndof, time.process_time() - t


def _fem(h):
    t = time.process_time()
    r = critical_voltage(PLATE, NeoHookean(), Discretisation(h_rel=h, layers=1, order=2))
    return r.v, r.ndof, time.process_time() - t


@pytest.fixture(scope="module")
def reference():
    v, _, _ = _axisym(*REFERENCE)
    return v


def test_work_precision_report(reference):
    """Every solve of both models once (CPU time, DOFs, error against the in-run
    reference); the axisymmetric model reaches the 3D model's best accuracy at a fraction of
    its CPU time (asserted: < 1/10, the measured ratio is printed)."""
    rows = [("3D", f"h = {h:g} t0", *_fem(h)) for h in SIZES_3D]
    rows += [("axisym", f"p = {p}, L = {L}", *_axisym(p, L)) for p, L in DISCS]
    print(f"\nreference v_cr = {reference:.10f} (axisymmetric p = {REFERENCE[0]}, "
          f"L = {REFERENCE[1]})")
    print(f"{'model':8s} {'discretisation':16s} {'DOFs':>8s} {'CPU s':>8s} {'error':>10s}")
    for model, disc, v, ndof, cpu in rows:
        print(f"{model:8s} {disc:16s} {ndof:8d} {cpu:8.2f} {abs(v - reference):10.2e}")
    fem = [r for r in rows if r[0] == "3D"]
    ax = [r for r in rows if r[0] == "axisym"]
    finest = max(fem, key=lambda r: r[3])
    err3d, cpu3d = abs(finest[2] - reference), finest[4]
    affordable = [r for r in ax if r[4] <= cpu3d]
    assert affordable, "no axisymmetric solve of the table costs less than the finest 3D one"
    err_ax = min(abs(r[2] - reference) for r in affordable)
    print(f"at <= {cpu3d:.2f} CPU s (the finest 3D solve): 3D error {err3d:.2e}, "
          f"axisymmetric error {err_ax:.2e}, ratio {err3d / err_ax:.0f}")
    # the 3D curve's slope d log(error) / d log(CPU) over its two finest meshes, extrapolated
    # to the cheapest axisymmetric solve's error: an extrapolation, not a measurement
    (_, _, v1, _, c1), (_, _, v2, _, c2) = sorted(fem, key=lambda r: r[3])[-2:]
    slope = math.log(abs(v2 - reference) / abs(v1 - reference)) / math.log(c2 / c1)
    cheapest = min(ax, key=lambda r: r[4])
    e_c = abs(cheapest[2] - reference)
    cpu_3d_at = cpu3d * (e_c / err3d) ** (1.0 / slope)
    print(f"3D slope {slope:.2f}; extrapolated, the 3D model would need ~{cpu_3d_at:.0f} CPU s "
          f"for the error {e_c:.1e} of the cheapest axisymmetric solve ({cheapest[4]:.2f} s): "
          f"a CPU ratio of ~{cpu_3d_at / cheapest[4]:.0f}")
    # at equal CPU the axisymmetric error is 790x smaller (measured, p = 3 against h = 1.4 t0):
    # 3D converges like CPU^-0.8 (h^1.2 with the clamped edge's singularity), the
    # axisymmetric model exponentially in p; 100x is far inside that and robust to the
    # load-dependent CPU times (+-30 %) that decide which solve is "affordable"
    assert err3d / err_ax > 100.0
    errs = [abs(r[2] - reference) for r in ax]
    assert np.all(np.diff(errs) < 0), "the axisymmetric p-sequence must converge"


def test_bench_axisym_critical_voltage(benchmark):
    """One axisymmetric critical voltage at p = 2, L = 4: the cheapest of the table, error
    1.0e-4 (measured), 70x below the 3D solve of the same group."""
    benchmark.group = "ch5 critical voltage, one thread"
    v = benchmark.pedantic(lambda: _axisym(2, 4)[0], rounds=3, iterations=1)
    assert 0.2 < v < 0.25


def test_bench_3d_critical_voltage(benchmark):
    """One 3D critical voltage at h = 1.4 t0, error 7.1e-3 (measured; the same group: the
    ratio is the 3D model's cost over the axisymmetric one's at 70x its accuracy)."""
    benchmark.group = "ch5 critical voltage, one thread"
    v = benchmark.pedantic(lambda: _fem(1.4)[0], rounds=3, iterations=1)
    assert 0.2 < v < 0.25
