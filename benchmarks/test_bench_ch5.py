"""Benchmarks of the Chapter 5 NGSolve buckling membrane on the named problems of the suite.

Thread count fixed: OMP_NUM_THREADS=1 and ngsolve.SetNumThreads(1) (named in the groups).
Run: ``python -m pytest benchmarks/test_bench_ch5.py --benchmark-only -s`` (the reports
print their tables; ``CH5_BENCH_SIZES="3,1.4,0.7,0.31"`` sets the mesh sizes h/t0 of the
solver comparison, default 3, 2, 1.4 (one layer: h = 0.31 t0 is ~150,000 DOFs);
``CH5_ENGINE_H`` the mesh of the engine comparison, default 1.4).

* ``test_solver_comparison_report``: every sparse direct solver of the build that factors
  the project's own Jacobian (the flat film tangent at v = 0.15 and the tangent past the
  critical voltage, which has negative eigenvalues): factorisation time, refactorisation
  with reused symbolic analysis (``Update()``), solve time and ``||Ax - b|| / ||b||`` at
  every size, and the scaling exponent of factorisation time in the DOFs;
* ``test_engine_speedup_report``: critical voltages and coarse ramps with the default
  engine (sparsecholesky, one factorisation object updated, chord steps, LOBPCG) and the
  former one (umfpack, a new ``Inverse`` per Newton step, subspace iteration) on the same mesh:
  CPU time, speed-up, Newton-step time / factorisation time, factorisation counts;
* pytest-benchmark timings of assembly (interpreted vs C++-compiled energy), one
  factorisation per solver, and a full ramp to pull-in.
"""

from __future__ import annotations

import os
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")

import ngsolve  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from debench.models.buckling.fem import MembraneModel  # noqa: E402
from debench.models.buckling.parameters import (  # noqa: E402
    Discretisation,
    NeoHookean,
    Ogden,
    Plate,
)
from debench.models.buckling.solver import critical_voltage, voltage_ramp  # noqa: E402

ngsolve.SetNumThreads(1)

SIZES = tuple(float(x) for x in os.environ.get("CH5_BENCH_SIZES", "3,2,1.4").split(","))
ENGINE_H = float(os.environ.get("CH5_ENGINE_H", "1.4"))
OLD = {"inverse": "umfpack", "reuse": False, "eigensolver": "subspace", "chord": False}


def _working_solvers():
    """Solvers listed by the build that factorise a small saddle-point tangent of the
    project (pardiso is listed but needs MKL at run time)."""
    m = MembraneModel(Plate(), NeoHookean(), Discretisation(h_rel=5.0, layers=1),
                      with_imperfection=False)
    m.set_voltage(0.1)
    m.assemble()
    out = []
    for s in ("sparsecholesky", "umfpack", "pardiso", "superlu"):
        if s not in ngsolve.la.GetAvailableSolvers():
            continue
        try:
            m.a.mat.Inverse(m.X.FreeDofs(), inverse=s)
        except Exception:  # noqa: BLE001 - not usable in this build
            continue
        out.append(s)
    return out


SOLVERS = _working_solvers()


def _flat_model(h, v=0.15, inverse="sparsecholesky", mat=None, compile="auto"):
    m = MembraneModel(Plate(), mat or NeoHookean(), Discretisation(h_rel=h, layers=1),
                      with_imperfection=False, inverse=inverse, compile=compile)
    m.set_voltage(v)
    m.newton()
    return m


def _measure(m, solver):
    """(factor s, refactor s, solve s, relative residual) of the assembled tangent."""
    free = np.array(m.X.FreeDofs(), dtype=bool)
    t = time.perf_counter()
    inv = m.a.mat.Inverse(m.X.FreeDofs(), inverse=solver)
    tf = time.perf_counter() - t
    t = time.perf_counter()
    inv.Update()
    tu = time.perf_counter() - t
    b = m.gf.vec.CreateVector()
    b.FV().NumPy()[:] = np.random.default_rng(0).standard_normal(m.ndof) * free
    t = time.perf_counter()
    x = (inv * b).Evaluate()
    ts = time.perf_counter() - t
    r = (m.a.mat * x - b).Evaluate()
    rel = np.linalg.norm(r.FV().NumPy()[free]) / np.linalg.norm(b.FV().NumPy()[free])
    return tf, tu, ts, float(rel)


def test_solver_comparison_report(record_property):
    """Time and residual of every working direct solver on the project's Jacobians."""
    rows = []
    for h in SIZES:
        for v in (0.15, 0.40):          # flat film before and past the critical voltage
            m = _flat_model(h, v=v)
            m.assemble()
            for s in SOLVERS:
                tf, tu, ts, rel = _measure(m, s)
                rows.append((h, m.ndof, v, s, tf, tu, ts, rel))
    print("\nh/t0   ndof    v     solver          factor_s  update_s  solve_s   ||Ax-b||/||b||")
    for h, n, v, s, tf, tu, ts, rel in rows:
        print(f"{h:4.1f} {n:7d} {v:5.2f}  {s:14s} {tf:9.3f} {tu:9.3f} {ts:8.4f}   {rel:.1e}")
    for s in SOLVERS:
        sel = [(n, tf) for h, n, v, ss, tf, *_ in rows if ss == s and v == 0.15]
        if len(sel) >= 2:
            p = np.polyfit(np.log([a for a, _ in sel]), np.log([b for _, b in sel]), 1)[0]
            print(f"scaling exponent of factorisation time, {s}: {p:.2f}")
            record_property(f"factor_exponent_{s}", p)
    assert all(rel < 1e-6 for *_, rel in rows)


def _run(fn, *args, **kw):
    """Result and CPU seconds of this (single-threaded) process: robust to other load on a
    shared machine, unlike the wall time."""
    t = time.process_time()
    r = fn(*args, **kw)
    return r, time.process_time() - t


def test_engine_speedup_report(record_property):
    """Default engine vs the former one on the same mesh and result (coarse, 1 thread)."""
    disc = Discretisation(h_rel=ENGINE_H, layers=1)
    lines = []
    for name, fn, args, kw in (
            ("critical voltage NH", critical_voltage, (Plate(), NeoHookean(), disc), {}),
            ("critical voltage Ogden", critical_voltage, (Plate(), Ogden(), disc), {}),
            ("ramp NH h=3", voltage_ramp,
             (Plate(), NeoHookean(), Discretisation(h_rel=3.0, layers=1)),
             {"dv_max": 0.04, "eig_every": 6}),
            ("ramp Ogden h=3", voltage_ramp,
             (Plate(), Ogden(), Discretisation(h_rel=3.0, layers=1)),
             {"dv_max": 0.04, "eig_every": 6})):
        new, t_new = _run(fn, *args, **kw)
        old, t_old = _run(fn, *args, **kw, **OLD)
        st = new.stats
        step = (st["assemble_s"] + st["factor_s"] + st["solve_s"]) / max(st["factorisations"], 1)
        ratio = step / (st["factor_s"] / max(st["factorisations"], 1))
        lines.append(f"{name:24s} ndof {new.ndof:6d}  new {t_new:7.2f} s  old {t_old:7.2f} s CPU  "
                     f"speed-up {t_old / t_new:4.2f}  Newton-step/factorisation {ratio:4.2f}  "
                     f"factorisations {st['factorisations']} (old {old.stats['factorisations']})")
        record_property(f"speedup {name}", t_old / t_new)
        v_new = new.v if hasattr(new, "lam") else new.v_pullin
        v_old = old.v if hasattr(old, "lam") else old.v_pullin
        assert v_new == pytest.approx(v_old, rel=1e-5)
    print("\n" + "\n".join(lines))


@pytest.mark.parametrize("compile", [False, True], ids=["tree", "realcompile"])
@pytest.mark.parametrize("mat", [NeoHookean(), Ogden()], ids=["nh", "ogden"])
@pytest.mark.benchmark(group="ch5-assembly-1thread")
def test_bench_assembly(benchmark, mat, compile):
    m = _flat_model(2.0, mat=mat, compile=compile)
    benchmark.extra_info["ndof"] = m.ndof
    benchmark.extra_info["energy"] = m.stats["energy"]
    benchmark(m.a.AssembleLinearization, m.gf.vec)
    assert m.a.mat.height == m.ndof


@pytest.mark.parametrize("solver", SOLVERS)
@pytest.mark.parametrize("h", SIZES)
@pytest.mark.benchmark(group="ch5-factorisation-1thread")
def test_bench_factorisation(benchmark, h, solver):
    m = _flat_model(h, inverse=solver)
    m.assemble()
    benchmark.extra_info["ndof"] = m.ndof
    inv = benchmark(m.a.mat.Inverse, m.X.FreeDofs(), inverse=solver)
    m.a.Apply(m.gf.vec, m.res)
    du = (inv * m.res).Evaluate()
    assert np.all(np.isfinite(du.FV().NumPy()))


@pytest.mark.benchmark(group="ch5-full-ramp-1thread")
def test_bench_full_ramp_to_pullin(benchmark):
    args = (Plate(), NeoHookean(), Discretisation(h_rel=3.0, layers=1))
    r = benchmark.pedantic(voltage_ramp, args=args,
                           kwargs={"dv_max": 0.04}, rounds=1, iterations=1)
    benchmark.extra_info["ndof"] = r.ndof
    benchmark.extra_info["newton_steps"] = r.stats["newton_steps"]
    assert r.v_pullin is not None
