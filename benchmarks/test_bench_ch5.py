"""Benchmarks of the Chapter 5 NGSolve buckling membrane on the named problems of the suite.

Thread count fixed: OMP_NUM_THREADS=1 and ngsolve.SetNumThreads(1) (named in the groups).
Run: ``python -m pytest benchmarks/test_bench_ch5.py --benchmark-only``.

* one Newton step (tangent assembly, factorisation, solve) at the flat film v = 0.15 on
  meshes h = 3, 2, 1.4 t0 (one layer of quadratic prisms), assembly and factorisation
  timed separately, for every sparse direct solver of the build that factorises the
  (non-symmetric storage) saddle-point tangent: umfpack, superlu, and pardiso when MKL is
  present (probed; this build lists pardiso but lacks MKL; sparsecholesky needs symmetric
  storage and is not applicable to the indefinite saddle point);
* the scaling exponent of assembly and factorisation time in the number of DOFs
  (``test_scaling_exponent``: a timing report, recorded in ``extra_info``, no assertion on
  speed);
* a full voltage ramp to and past pull-in (neo-Hookean, coarse mesh h = 3 t0).
"""

from __future__ import annotations

import os
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

ngsolve = pytest.importorskip("ngsolve")
ngsolve.SetNumThreads(1)

from debench.models.buckling.fem import MembraneModel  # noqa: E402
from debench.models.buckling.parameters import Discretisation, NeoHookean, Ogden, Plate  # noqa: E402
from debench.models.buckling.solver import voltage_ramp  # noqa: E402

SIZES = (3.0, 2.0, 1.4)


def _working_solvers():
    """Solvers listed by the build that actually factorise (pardiso is listed but needs MKL
    at run time; sparsecholesky needs symmetric storage and an SPD matrix)."""
    from netgen.geom2d import unit_square
    mesh = ngsolve.Mesh(unit_square.GenerateMesh(maxh=0.5))
    fes = ngsolve.H1(mesh, order=1, dirichlet=".*")
    u, v = fes.TnT()
    a = ngsolve.BilinearForm(ngsolve.grad(u) * ngsolve.grad(v) * ngsolve.dx).Assemble()
    out = []
    for s in ("umfpack", "pardiso", "superlu"):
        if s not in ngsolve.la.GetAvailableSolvers():
            continue
        try:
            a.mat.Inverse(fes.FreeDofs(), inverse=s)
        except Exception:  # noqa: BLE001 - not usable in this build
            continue
        out.append(s)
    return out


SOLVERS = _working_solvers()


def _flat_model(h, inverse="umfpack", mat=None):
    m = MembraneModel(Plate(), mat or NeoHookean(), Discretisation(h_rel=h, layers=1),
                      with_imperfection=False, inverse=inverse)
    m.set_voltage(0.15)
    m.newton()
    return m


@pytest.mark.parametrize("h", SIZES)
@pytest.mark.benchmark(group="ch5-assembly-1thread")
def test_bench_assembly(benchmark, h):
    m = _flat_model(h)
    benchmark.extra_info["ndof"] = m.ndof
    benchmark(m.a.AssembleLinearization, m.gf.vec)
    assert m.a.mat.height == m.ndof


@pytest.mark.parametrize("h", SIZES)
@pytest.mark.benchmark(group="ch5-assembly-ogden-1thread")
def test_bench_assembly_ogden(benchmark, h):
    m = _flat_model(h, mat=Ogden())
    benchmark.extra_info["ndof"] = m.ndof
    benchmark(m.a.AssembleLinearization, m.gf.vec)
    assert m.a.mat.height == m.ndof


@pytest.mark.parametrize("solver", SOLVERS)
@pytest.mark.parametrize("h", SIZES)
@pytest.mark.benchmark(group="ch5-factorisation-1thread")
def test_bench_factorisation(benchmark, h, solver):
    m = _flat_model(h, inverse=solver)
    m.a.AssembleLinearization(m.gf.vec)
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


def test_scaling_exponent(record_property):
    """Fit t ~ ndof^p for assembly and factorisation (umfpack); report, do not assert speed."""
    rows = []
    for h in SIZES + (1.0,):
        m = _flat_model(h)
        t = time.perf_counter()
        m.a.AssembleLinearization(m.gf.vec)
        ta = time.perf_counter() - t
        t = time.perf_counter()
        m.a.mat.Inverse(m.X.FreeDofs(), inverse="umfpack")
        tf = time.perf_counter() - t
        rows.append((m.ndof, ta, tf))
    rows = np.array(rows)
    pa = np.polyfit(np.log(rows[:, 0]), np.log(rows[:, 1]), 1)[0]
    pf = np.polyfit(np.log(rows[:, 0]), np.log(rows[:, 2]), 1)[0]
    record_property("assembly_exponent", pa)
    record_property("factorisation_exponent", pf)
    print(f"\nndof, assembly s, factorisation s:\n{rows}\nexponents: assembly {pa:.2f}, "
          f"factorisation {pf:.2f}")
    assert np.all(rows[:, 1:] > 0)
