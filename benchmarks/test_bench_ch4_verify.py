"""Benchmarks of the Chapter 4 kernels that ``debench verify`` spends its Chapter 4 time
in, against the code before they were rewritten (loaded from git history by
:mod:`benchmarks.baseline`, skipped without a git checkout), in the same run.

Named problems (one thread, CPU time: the machine is shared, so the timer is
``time.process_time``):

* "region": both parity determinants of the ansatz on the unstable-area grid of the
  producers (81 kH x 241 lam, Fig. 4.2(c) TI case, printed coefficients): the 3 x 3
  determinant expanded into lam-only minors times tanh(s t / 2) vs the stacked columns
  and triple product.
* "inplane_det": the in-plane fibre determinant roots of one producer window
  (compression, theta = 30 degrees, xi = 5, kH = 2): stacked evaluations, a bracket of the
  second weight vector that holds a root of the first not refined again, vs one scalar
  brentq per bracket.
* "inplane_det_windows": the determinant roots of all 20 producer windows
  (compression, voltage control, tension): solved together (one stacked evaluation per
  refinement step for every bracket of every window) vs one window after another.
* "fem_agreement_root": the through-thickness FE root of the agreement dataset's thin
  case (xi = 0, Dhat = 2.4, kH = 0.3, flexural) located to its round-off vs to 1e-14
  inside the round-off band.
* "inplane_fe": the in-plane FE roots of the same producer window: each crossing to its
  round-off vs to 1e-14.

Run: ``python -m pytest benchmarks/test_bench_ch4_verify.py --benchmark-only``.
"""

from __future__ import annotations

import time

import numpy as np
import pytest
from debench.models.plate import PlateParams, ansatz, fem
from debench.models.plate import inplane as ip
from debench.models.plate import inplane_fe as ipfe
from debench.reference.studies import ch4 as prod_study
from debench.reference.studies import ch4_inplane as ipprod_study

from benchmarks import baseline
from benchmarks.test_bench_ch4_roots import fem_crossing_root

#: the code before these rewrites
BEFORE = "bench/ch4-verify-before-rewrites"
FILES = {"ansatz": "models/plate/ansatz.py", "inplane": "models/plate/inplane.py",
         "fem": "models/plate/fem.py"}
#: the two determinant forms differ by round-off relative to the largest |det| of the
#: grid (measured <= 1e-9 of |det| at points where |det| >= 1e-12 max|det|)
DET_RTOL = 1e-7
#: determinant roots: both searches stop on brackets of ~1e-14 (brentq vs the Illinois
#: iteration); a root's round-off is ~1e-12
DET_ROOT_ATOL = 1e-11
#: FE roots: both are sign changes inside the root's round-off band (eps ||K||_1 over
#: the eigenvalue's slope: 1.5e-7 at the agreement case, measured); 1e-6 is the stated
#: accuracy of the in-plane FE roots (inplane_fe.FE_ROOT_ROUNDOFF)
FE_ROOT_ATOL = ipfe.FE_ROOT_ROUNDOFF


def _previous():
    try:
        return baseline.load(BEFORE, FILES)
    except baseline.BaselineUnavailable as exc:
        pytest.skip(str(exc))


# ------------------------------------------------------------------ region
def _region(module):
    p = PlateParams(xi=prod_study.XI_TI, Dhat=2.0, variant="printed")
    return module._determinants(prod_study.lam_grid()[None, :], prod_study.kH_grid()[:, None], p)


@pytest.mark.benchmark(group="ch4-region-81x241-1thread", timer=time.process_time)
def test_bench_region_determinants_previous(benchmark):
    old = _previous()["ansatz"]
    got = benchmark.pedantic(_region, args=(old,), rounds=5, iterations=1)
    for a, b in zip(got, _region(ansatz), strict=True):
        np.testing.assert_allclose(a, b, rtol=DET_RTOL, atol=DET_RTOL * np.nanmax(abs(a)))


@pytest.mark.benchmark(group="ch4-region-81x241-1thread", timer=time.process_time)
def test_bench_region_determinants_minors(benchmark):
    dE, dO = benchmark.pedantic(_region, args=(ansatz,), rounds=5, iterations=1)
    assert np.isfinite(dE).any() and np.isfinite(dO).any()


# ------------------------------------------------------------------ in-plane determinant
def _inplane_case():
    return ipprod_study.compression_case(30.0)._args()


def _inplane_det(module):
    args, kw = _inplane_case()
    return module.critical_stretches_det(*args, **kw)


@pytest.mark.benchmark(group="ch4-inplane_det-theta30-1thread", timer=time.process_time)
def test_bench_inplane_det_roots_previous(benchmark):
    old = _previous()["inplane"]
    got = benchmark.pedantic(_inplane_det, args=(old,), rounds=3, iterations=1)
    np.testing.assert_allclose(got, _inplane_det(ip), rtol=0, atol=DET_ROOT_ATOL)


@pytest.mark.benchmark(group="ch4-inplane_det-theta30-1thread", timer=time.process_time)
def test_bench_inplane_det_roots_stacked(benchmark):
    got = benchmark.pedantic(_inplane_det, args=(ip,), rounds=3, iterations=1)
    assert got.size >= 1


def _windows():
    return [(*args, kw) for args, kw in (c._args() for c in ipprod_study.producer_cases())]


def _windows_one_by_one(module):
    return [module.critical_stretches_det(kH, th, p, **kw) for kH, th, p, kw in _windows()]


@pytest.mark.benchmark(group="ch4-inplane_det_windows-20-1thread", timer=time.process_time)
def test_bench_inplane_det_windows_one_by_one_previous(benchmark):
    old = _previous()["inplane"]
    got = benchmark.pedantic(_windows_one_by_one, args=(old,), rounds=1, iterations=1)
    for a, b in zip(got, ip.critical_stretches_det_many(_windows()), strict=True):
        np.testing.assert_allclose(a, b, rtol=0, atol=DET_ROOT_ATOL)


@pytest.mark.benchmark(group="ch4-inplane_det_windows-20-1thread", timer=time.process_time)
def test_bench_inplane_det_windows_together(benchmark):
    got = benchmark.pedantic(ip.critical_stretches_det_many, args=(_windows(),), rounds=1,
                             iterations=1)
    assert sum(r.size for r in got) >= len(got) // 2


# ------------------------------------------------------------------ FE agreement root
@pytest.fixture(scope="module")
def agreement_case():
    p = PlateParams(0.0, 2.4, variant="derived")
    r = ansatz.critical_stretches(0.3, p)
    lam = float(max(x for x, q in zip(r.lam, r.parity, strict=True) if q == "E"))
    return p, lam


def _fem_root(module, case):
    p, lam = case
    return fem_crossing_root(module, lam, 0.3, p, 1e-3)


@pytest.mark.benchmark(group="ch4-fem_agreement_root-kH0.3-1thread", timer=time.process_time)
def test_bench_fem_agreement_root_to_1e14_previous(benchmark, agreement_case):
    old = _previous()["fem"]
    got = benchmark.pedantic(_fem_root, args=(old, agreement_case), rounds=3, iterations=1)
    assert abs(got - _fem_root(fem, agreement_case)) <= FE_ROOT_ATOL


@pytest.mark.benchmark(group="ch4-fem_agreement_root-kH0.3-1thread", timer=time.process_time)
def test_bench_fem_agreement_root_to_roundoff(benchmark, agreement_case):
    got = benchmark.pedantic(_fem_root, args=(fem, agreement_case), rounds=3, iterations=1)
    assert abs(got - agreement_case[1]) <= 1e-5  # the determinant root beside it


# ------------------------------------------------------------------ in-plane FE
def _inplane_fe(module):
    args, kw = _inplane_case()
    return module.critical_stretches_fe(*args, **kw)


@pytest.mark.benchmark(group="ch4-inplane_fe-theta30-1thread", timer=time.process_time)
def test_bench_inplane_fe_roots_to_1e14_previous(benchmark):
    old = _previous()["inplane"]
    got = benchmark.pedantic(_inplane_fe, args=(old,), rounds=2, iterations=1)
    np.testing.assert_allclose(got, _inplane_fe(ipfe), rtol=0, atol=FE_ROOT_ATOL)


@pytest.mark.benchmark(group="ch4-inplane_fe-theta30-1thread", timer=time.process_time)
def test_bench_inplane_fe_roots_to_roundoff(benchmark):
    got = benchmark.pedantic(_inplane_fe, args=(ipfe,), rounds=2, iterations=1)
    assert got.size >= 1
