"""Benchmarks of Chapter 4 (plate bifurcation) on the named problems of the verification
suite. Thread counts are fixed (OMP_NUM_THREADS=1) and named in the group; the 2-core
variant splits the Fig. 4.2 cases over two worker processes (pool started outside the
timed region). Run: ``python -m pytest benchmarks/test_bench_ch4.py --benchmark-only``.

Named problems:
* "fig4_2_all": all Fig. 4.2 cases (9 Dhat x 2 materials, printed coefficients) on 400
  kH points, method 1 (vectorised scan + bracketed Illinois refinement); target < 2 s.
* "region": both parity determinants on the area window, per parity on the expanded
  mesh (previous) vs one pass with the lam-only work once per lam.
* "critical_D_thin_extensional": the Fig. 4.6 onset, scalar Dhat loop (previous) vs the
  vectorised chunked scan (same bisection).
* "fe_lowest_8_eigenvalues": method 2, dense eigh (previous) vs the banded solver.
* "single_root": one critical stretch (xi = 5, Dhat = 2, kH = 2, printed), refined from
  the same bracket by method 1 (brentq on the determinant) and method 2 (brentq on the
  crossing FE eigenvalue, elements_for(kh) elements): their ratio is the cost per root.
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")

from concurrent.futures import ProcessPoolExecutor  # noqa: E402

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from debench.models.plate import PlateParams  # noqa: E402
from debench.models.plate.ansatz import critical_stretches, curves_vectorised, determinant  # noqa: E402
from debench.models.plate.fem import eigenvalues, elements_for  # noqa: E402
from scipy.optimize import brentq  # noqa: E402

FIG42 = [(xi, D) for D in (0.0, 1.0, 2.0, 2.2, 2.4, 2.6, 3.0, 4.0, 5.0) for xi in (0.0, 5.0)]
KH = np.geomspace(0.01, 20.0, 400)


def _case(args):
    xi, D = args
    lam, _ = curves_vectorised(KH, PlateParams(xi, D, variant="printed"))
    return int(np.isfinite(lam).sum())


def _all_cases_serial():
    return sum(_case(c) for c in FIG42)


@pytest.mark.benchmark(group="ch4-fig4_2_all-400kH-1thread")
def test_bench_fig4_2_all_cases_one_thread(benchmark):
    n = benchmark.pedantic(_all_cases_serial, rounds=3, iterations=1)
    assert n > 18 * 400  # at least one root per kH on average


@pytest.fixture(scope="module")
def pool():
    with ProcessPoolExecutor(max_workers=2) as ex:
        list(ex.map(_case, FIG42[:2]))  # warm up (imports) outside the timed region
        yield ex


@pytest.mark.benchmark(group="ch4-fig4_2_all-400kH-2procs-1thread-each")
def test_bench_fig4_2_all_cases_two_processes(benchmark, pool):
    n = benchmark.pedantic(lambda: sum(pool.map(_case, FIG42)), rounds=3, iterations=1)
    assert n == _all_cases_serial()


P = PlateParams(5.0, 2.0, variant="printed")
KH1 = 2.0
ROOT = float(critical_stretches(KH1, P).lam[-1])
BRACKET = (ROOT * (1 - 1e-3), ROOT * (1 + 1e-3))


@pytest.mark.benchmark(group="ch4-single_root-1thread")
def test_bench_single_root_method1_determinant(benchmark):
    r = benchmark(lambda: brentq(lambda x: float(determinant(x, KH1, P, "E")), *BRACKET,
                                 xtol=1e-13))
    assert r == pytest.approx(ROOT, abs=1e-12)


@pytest.mark.benchmark(group="ch4-single_root-1thread")
def test_bench_single_root_method2_fe(benchmark):
    n = elements_for(KH1 * ROOT**-2)
    j = int(np.sum(eigenvalues(BRACKET[0], KH1, P, n, 8) < 0)) - 1

    def solve():
        return brentq(lambda x: eigenvalues(x, KH1, P, n, j + 1)[j], *BRACKET, xtol=1e-13)

    r = benchmark(solve)
    assert r == pytest.approx(ROOT, abs=2e-5)


# --------------------------------------------------------------------------- vectorised
#: the voltage-control dataset's problem: lam_cr(kH) at fixed Vhat, 81 kH, 240 scan points
KH_V = np.geomspace(0.01, 20.0, 81)
PV = PlateParams(5.0, 0.0, variant="printed")


def _voltage_per_kh_brentq():
    """The scalar path: one scan and one brentq per bracket at every kH."""
    from debench.models.plate.ansatz import scan_grid
    from debench.models.plate.voltage import _determinant_at_voltage

    grid = scan_grid(n=240)
    n = 0
    for k in KH_V:
        for par in ("E", "O"):
            dv = _determinant_at_voltage(grid, float(k), 0.5, PV, par)
            ok = np.isfinite(dv[:-1]) & np.isfinite(dv[1:])
            for i in np.nonzero(ok & (dv[:-1] * dv[1:] < 0))[0]:
                brentq(lambda x, par=par, k=k: float(_determinant_at_voltage(
                    np.array(x), float(k), 0.5, PV, par)), grid[i], grid[i + 1], xtol=1e-13)
                n += 1
    return n


@pytest.mark.benchmark(group="ch4-voltage_control_81kH-1thread")
def test_bench_voltage_control_scalar_brentq(benchmark):
    n = benchmark.pedantic(_voltage_per_kh_brentq, rounds=3, iterations=1)
    assert n > KH_V.size


@pytest.mark.benchmark(group="ch4-voltage_control_81kH-1thread")
def test_bench_voltage_control_vectorised(benchmark):
    from debench.models.plate.voltage import curves_at_voltage

    lam, _ = benchmark.pedantic(curves_at_voltage, args=(KH_V, 0.5, PV),
                             kwargs={"n_scan": 240}, rounds=3, iterations=1)
    assert int(np.isfinite(lam).sum()) == _voltage_per_kh_brentq()


@pytest.mark.benchmark(group="ch4-roots_at_one_kH-1thread")
def test_bench_critical_stretches_vectorised_refinement(benchmark):
    r = benchmark(critical_stretches, KH1, P)
    assert r.lam[-1] == pytest.approx(ROOT, abs=1e-12)


# ------------------------------------------------------------- unstable regions (Fig. 4.3)
#: the area window of the catalogue producers (81 kH x 241 lam, both parities)
PA = PlateParams(5.0, 2.6, variant="printed")


def _region_per_parity_full_grid():
    """The previous path: each parity's determinant on the expanded (kH, lam) mesh (the
    coefficients, quartic roots and ellipticity evaluated at every mesh point)."""
    from debench.models.plate.ansatz import _determinant
    from debench.reference.producers.ch4 import _kH, _lam

    K, L = np.meshgrid(_kH(), _lam(), indexing="ij")
    return _determinant(L, K, PA, "E"), _determinant(L, K, PA, "O")


def _region_one_pass():
    from debench.models.plate.ansatz import _determinants
    from debench.reference.producers.ch4 import _kH, _lam

    return _determinants(_lam()[None, :], _kH()[:, None], PA, ("E", "O"))


@pytest.mark.benchmark(group="ch4-region_81x241-1thread")
def test_bench_region_per_parity_full_grid(benchmark):
    dE, dO = benchmark(_region_per_parity_full_grid)
    assert dE.shape == (81, 241)


@pytest.mark.benchmark(group="ch4-region_81x241-1thread")
def test_bench_region_both_parities_lam_once(benchmark):
    dE, dO = benchmark(_region_one_pass)
    ref = _region_per_parity_full_grid()
    np.testing.assert_array_equal(np.isfinite(dE), np.isfinite(ref[0]))
    np.testing.assert_allclose(dE, ref[0], rtol=1e-12, atol=0)
    np.testing.assert_allclose(dO, ref[1], rtol=1e-12, atol=0)


# ----------------------------------------------------- Fig. 4.6 thin-extensional onset
PT = PlateParams(xi=5.0, variant="printed")


def _thin_extensional_scalar_loop():
    """The previous path: the 111-point Dhat scan one Dhat at a time, then bisection."""
    from dataclasses import replace

    from debench.models.plate.ansatz import _determinant

    lam = np.geomspace(0.4, 8.0, 1500)

    def has_root(D):
        dv = _determinant(lam, 1e-3, replace(PT, Dhat=float(D)), "O")
        ok = np.isfinite(dv[:-1]) & np.isfinite(dv[1:])
        return bool(np.any(ok & (dv[:-1] * dv[1:] < 0)))

    Ds = np.linspace(0.5, 6.0, 111)
    i = int(np.argmax([has_root(D) for D in Ds]))
    lo, hi = Ds[i - 1], Ds[i]
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if has_root(mid) else (mid, hi)
    return 0.5 * (lo + hi)


@pytest.mark.benchmark(group="ch4-critical_D_thin_extensional-1thread")
def test_bench_thin_extensional_scalar_loop(benchmark):
    d = benchmark.pedantic(_thin_extensional_scalar_loop, rounds=3, iterations=1)
    assert 2.0 < d < 4.0


@pytest.mark.benchmark(group="ch4-critical_D_thin_extensional-1thread")
def test_bench_thin_extensional_vectorised_scan(benchmark):
    from debench.models.plate.analysis import critical_D_thin_extensional

    d = benchmark.pedantic(critical_D_thin_extensional, args=(PT,), rounds=3, iterations=1)
    assert d == _thin_extensional_scalar_loop()


# ------------------------------------------------------- method 2: lowest eigenvalues
#: a thick case of the agreement dataset: kH = 10 at lam = 0.8, 40 elements (163 dofs)
FE_CASE = (0.8, 10.0, PlateParams(5.0, 2.0, variant="printed"), 40)
#: both solvers are backward stable: their eigenvalues agree to the round-off of the
#: stiffness, ~eps ||K|| with ||K|| ~ 1e5 |omega_max| here (t^-3 bending terms; measured
#: differences <= 1e-9 of the largest of the 8), 1e-7 of it is 100x that
EIG_ATOL = 1e-7


def _eigenvalues_dense():
    """The previous path: LAPACK on the dense Hermitian stiffness (eigh subset)."""
    import scipy.linalg as sla
    from debench.models.plate.fem import stiffness

    K, _ = stiffness(*FE_CASE)
    return sla.eigh(K, eigvals_only=True, subset_by_index=(0, 7))


@pytest.mark.benchmark(group="ch4-fe_lowest_8_eigenvalues_163dofs-1thread")
def test_bench_fe_eigenvalues_dense(benchmark):
    w = benchmark(_eigenvalues_dense)
    assert w.size == 8


@pytest.mark.benchmark(group="ch4-fe_lowest_8_eigenvalues_163dofs-1thread")
def test_bench_fe_eigenvalues_banded(benchmark):
    w = benchmark(eigenvalues, *FE_CASE, 8)
    np.testing.assert_allclose(w, _eigenvalues_dense(), rtol=0, atol=EIG_ATOL * np.max(
        np.abs(w)))

