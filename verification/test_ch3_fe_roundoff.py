"""The thin solid's results do not depend on round-off (:mod:`debench.models.circular.fe_solid`).

The solid's bordered tangent is a saddle-point matrix whose pressure block is the mass
matrix over the penalty: unscaled, its condition is ~1e18, and the pressure part of an LU
solve is then round-off whose value depends on the pivot order (explicit zeros in the
sparse structure, the order of the unknowns). The solve is equilibrated (condition ~1e6)
and Newton takes only contracting steps, so that a solve, a state and an event value are
the same under such perturbations, and a continuation that meets a fold of the branch
fails loudly instead of jumping across it.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
import pytest
import scipy.sparse as sp
from debench.models.circular import fe_continuation as FC
from debench.models.circular.fe_solid import CircularSolidFE, SolidMesh
from debench.models.errors import ConvergenceError
from debench.reference.producers import ch3_fe as producers
from debench.reference.studies import ch3_fe as P

SMALL_MESH = SolidMesh(n_a=2, n_b=5, nz=1)
#: relative perturbation of the matrix values (a few hundred ulps: what another BLAS,
#: another summation order in the assembly or a DOF renumbering can change)
PERTURBATION = 1e-13
#: forward error of the equilibrated solve: condition ~1e6 (measured: 9.5e5 at H = 0.2,
#: lam = 3.2; <= 6.3e6 along the H = 0.05 branch) times the perturbation above is 1e-7;
#: SOLVE_RTOL is 10x that. Unscaled, the same perturbations move the solution by O(1)
SOLVE_RTOL = 1e-6


def _with_explicit_zeros(model, M):
    """``M`` on the solid's full scatter structure, its zero entries kept explicitly."""
    plan = model._plan
    indptr, indices = plan["indptr"], plan["indices"]
    cols = np.repeat(np.arange(len(indptr) - 1), np.diff(indptr))
    data = np.asarray(sp.csr_matrix(M)[indices, cols]).ravel()
    out = sp.csc_matrix((data, indices.copy(), indptr.copy()), shape=M.shape)
    assert out.nnz > sp.csc_matrix(M).nnz        # zeros really kept
    return out


def _variants(model, M, b, rng):
    """Solutions of ``M z = b`` under round-off perturbations of the same system."""
    out = {"explicit zeros": FC.solve_bordered(_with_explicit_zeros(model, M), b, 3.2)}
    pr, pc = rng.permutation(M.shape[0]), rng.permutation(M.shape[1])
    y = FC.solve_bordered(sp.csc_matrix(M)[pr][:, pc], b[pr], 3.2)
    z = np.empty_like(y)
    z[pc] = y
    out["permuted unknowns"] = z
    Mp = sp.csc_matrix(M, copy=True)
    Mp.data = Mp.data * (1 + PERTURBATION * rng.standard_normal(Mp.nnz))
    out["perturbed values"] = FC.solve_bordered(Mp, b, 3.2)
    return out


def test_solid_bordered_solve_does_not_depend_on_round_off():
    """The Newton update and the continuation tangent of a state under voltage (lamP = 3,
    H = 0.2, edge stretch 3.2) are the same, to SOLVE_RTOL, with explicit zeros kept in the
    sparse structure, with the unknowns and equations renumbered, and with the matrix
    values perturbed by PERTURBATION."""
    model = CircularSolidFE(3.0, 0.2, mesh=SMALL_MESH)
    s = model.solve(3.2)
    M, col = model.bordered(s.x, s.phibar2)
    rng = np.random.default_rng(7)
    # a residual like a Newton start's: the predictor's error over a step 0.05
    x = s.x.copy()
    x[model._F] += 0.05 * s.tangent[:-1]
    res = model._system(x, s.phibar2 + 0.05 * s.tangent[-1])[0][model._E]
    for b in (-col, -res):
        z0 = FC.solve_bordered(M, b, 3.2)
        for name, z in _variants(model, M, b, rng).items():
            err = np.max(np.abs(z - z0)) / np.max(np.abs(z0))
            assert err <= SOLVE_RTOL, (name, err)


@lru_cache(maxsize=1)
def _reference_phibar() -> float:
    return CircularSolidFE(3.0, 0.2, mesh=SMALL_MESH).at_centre_stretch(4.0).phibar


def _perturbed_starts(monkeypatch, rng):
    """Every Newton start of the continuation perturbed by PERTURBATION (relative)."""
    inner = FC.BorderedContinuation._newton

    def newton(self, x, p, lam, *a, **k):
        return inner(self, x * (1 + PERTURBATION * rng.standard_normal(x.shape)),
                     p * (1 + PERTURBATION), lam, *a, **k)

    monkeypatch.setattr(FC.BorderedContinuation, "_newton", newton)


def _explicit_zeros(monkeypatch):
    inner = CircularSolidFE.bordered

    def bordered(self, x, p):
        M, col = inner(self, x, p)
        return _with_explicit_zeros(self, M), col

    monkeypatch.setattr(CircularSolidFE, "bordered", bordered)


@pytest.mark.parametrize("how", ["perturbed starts", "explicit zeros"])
def test_solid_event_value_does_not_depend_on_round_off(monkeypatch, how):
    """Phibar at centre stretch 4 (lamP = 3, H = 0.2: a bracketed root on the
    continuation, like every stored film) is the unperturbed value within the recompute
    accuracy :data:`~debench.reference.producers.ch3_fe.ACCURACY` when every Newton start
    is perturbed by PERTURBATION or the tangent keeps its explicit zeros."""
    ref = _reference_phibar()
    if how == "perturbed starts":
        _perturbed_starts(monkeypatch, np.random.default_rng(3))
    else:
        _explicit_zeros(monkeypatch)
    got = CircularSolidFE(3.0, 0.2, mesh=SMALL_MESH).at_centre_stretch(4.0).phibar
    assert abs(got - ref) <= producers.ACCURACY.tolerance(ref), (got, ref)


def test_unsolvable_film_raises_naming_it(monkeypatch):
    """A film whose continuation fails raises ConvergenceError naming the film (no NaN);
    stored-film values that are not finite are refused."""
    def stall(*a, **k):
        raise ConvergenceError("FE continuation stalled at lam = 4.97539")

    monkeypatch.setattr(P, "solid_value", stall)
    with pytest.raises(ConvergenceError, match=r"loss_of_tension .*H = 0\.05"):
        P.film_value("loss_of_tension", 3.0, 0.0, 0.05, math.nan, P.SOLID_MESH_COARSE)
    with pytest.raises(ValueError, match="finite"):
        P.thickness_study("phibar", 3.0, (0.2, 0.1, 0.05), P.SOLID_MESH_COARSE, 4.0,
                          values=[0.2, math.nan, 0.2])


@pytest.mark.slow
def test_solid_continuation_does_not_jump_a_fold():
    """lamP = 3, H = 0.05 on the coarse solid mesh: the branch folds in the edge stretch at
    lam* = 4.9754 (the smallest singular value of the equilibrated bordered tangent falls
    like sqrt(lam* - lam)), before loss of tension; the continuation raises
    ConvergenceError there, with or without perturbed round-off, instead of landing on
    another state after a wandering Newton (~20 s CPU each)."""
    model = P.solid_model(3.0, 0.05, P.SOLID_MESH_COARSE)

    def smallest(lam):
        s = model.solve(lam)
        M, _ = model.bordered(s.x, s.phibar2)
        r, c = FC.equilibrate(M)
        sv = np.linalg.svd((sp.diags(r) @ M @ sp.diags(c)).toarray(), compute_uv=False)
        return sv[-1] / sv[0]

    # sqrt(lam* - lam) from 4.9 to 4.975: a factor 13 (measured 6.8); 4 is a margin
    assert smallest(4.975) < smallest(4.9) / 4
    with pytest.raises(ConvergenceError):
        model.loss_of_tension(P.LOT_LAM_HI)
