"""Benchmarks of the constitutive kernel on the states of the verification suite.

Thread counts are fixed (OMP_NUM_THREADS=1, ngsolve.SetNumThreads(1)) and named in the
group. Run: ``python -m pytest benchmarks/test_bench_kernel.py --benchmark-only``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from debench.models.invariants import closed_form, generated  # noqa: E402
from debench.models.materials import MATERIALS  # noqa: E402

F = np.array([[1.2, 0.1, 0.05], [0.0, 0.9, 0.1], [0.02, 0.0, 1 / 1.08]])
D = np.array([0.1, 0.2, 0.3])
A = np.array([0.0, 1.0, 0.0])


@pytest.mark.benchmark(group="invariant-derivatives-1thread")
@pytest.mark.parametrize("path", ["closed_form", "sympy_generated"])
def test_bench_invariant_derivatives(benchmark, path):
    """All first and second derivatives of I1..I6 (ti numbering) at one state."""
    if path == "closed_form":
        out = benchmark(lambda: closed_form.derivatives(F, D, A, numbering="ti").dFF)
    else:
        out = benchmark(lambda: generated.ti(F, D, A)["dFF"])
    assert out.shape == (6, 3, 3, 3, 3)


@pytest.mark.benchmark(group="material-response-1thread")
@pytest.mark.parametrize("name", sorted(MATERIALS))
def test_bench_material_response_numpy(benchmark, name):
    """Energy, stress, field and moduli by the numpy chain rule / spectral formula."""
    mat = MATERIALS[name]
    Dm = D * np.sqrt(mat.eps * (mat.shear_modulus or 1e5))
    r = benchmark(mat.response, F, Dm)
    assert np.all(np.isfinite(r.AA))


@pytest.mark.benchmark(group="material-response-1thread")
@pytest.mark.parametrize("name", ["gent_ideal_dielectric", "neo_hookean_ideal_dielectric"])
def test_bench_material_response_ngsolve(benchmark, name):
    """The same by NGSolve CoefficientFunction.Diff (expression trees built once)."""
    import ngsolve
    from debench.models.materials import ngsolve_forms as ngf

    ngsolve.SetNumThreads(1)
    mat = MATERIALS[name]
    Dm = D * np.sqrt(mat.eps * (mat.shear_modulus or 1e5))
    ngf.evaluate(mat, F, Dm)  # build once
    out = benchmark(ngf.evaluate, mat, F, Dm)
    assert np.allclose(out["AA"], mat.response(F, Dm).AA, rtol=1e-10, atol=0)
