"""Sparse linear algebra of the axisymmetric model (:mod:`debench.models.buckling.axisym`).

The symmetric-indefinite factorisation with iterative refinement every Newton step and
every shift-invert eigen-solve uses (:class:`Factor`), the finiteness check before it, and
the conversions of NGSolve matrices to SciPy's.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from debench.models.errors import ConvergenceError
from scipy.sparse.linalg import splu

DIRECT_RTOL = 1e-3
"""A Newton solve whose relative residual exceeds this after iterative refinement raises
(breakdown: a zero pivot gives O(1) or non-finite residuals). The sparse LU gives 1e-15 ..
1e-12 on these matrices, but loses digits next to the critical voltage, where the tangent is
singular by definition (measured 4e-8): an inexact Newton correction that still converges,
which the nonlinear residual decides."""
REFINEMENTS = 4
"""Most iterative-refinement steps of one solve."""
REFINE_RTOL = 1e-13
"""Iterative refinement stops below this relative residual (two orders above round-off)."""
REFINE_STAGNATION = 0.5
"""Iterative refinement also stops when a step lowers the relative residual by less than
this factor: the residual has reached the floor the matrix's conditioning sets. Next to a
critical voltage the shifted tangent is nearly singular and that floor is far above
REFINE_RTOL (measured, order 4, 6 layers, v = 0.2202: 4.4e-9, 2.4e-9, 2.4e-9, 2.1e-9 over
four steps, with a normwise backward error ||r||_inf / (||A||_inf ||x||_inf + ||b||_inf) of
1e-19 already after the first solve), so further steps only repeat solves."""


class Factor:
    """Sparse symmetric-indefinite factorisation with iterative refinement.

    SuperLU in symmetric mode (minimum degree on A + A^T, diagonal pivots): 5-10x faster
    than its default column ordering on these saddle-point matrices (measured 0.46 s
    against 3.4 s at 24k DOFs), at the price of a first solve of relative residual ~1e-8
    that iterative refinement (at most :data:`REFINEMENTS` steps, stopped at
    :data:`REFINE_RTOL` or on stagnation, :data:`REFINE_STAGNATION`) brings to the floor the
    conditioning sets. A solve whose
    residual stays above :data:`DIRECT_RTOL` raises ConvergenceError (breakdown)."""

    def __init__(self, A: sp.spmatrix, what: str):
        self.A = sp.csc_matrix(A)
        self.what = what
        try:
            self.lu = splu(self.A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                           options={"SymmetricMode": True})
        except RuntimeError as exc:
            raise ConvergenceError(f"{what}: factorisation failed ({exc})") from exc

    def solve(self, b: np.ndarray, *, check: bool = True) -> np.ndarray:
        """``A^-1 b`` refined to REFINE_RTOL or until refinement stagnates; ``check=False``
        skips the breakdown test (for a caller that refines a larger system itself)."""
        b = np.asarray(b, dtype=float)
        x = self.lu.solve(b)
        nb = max(float(np.linalg.norm(b)), 1e-300)
        r = b - self.A @ x
        res = float(np.linalg.norm(r)) / nb
        for _ in range(REFINEMENTS):
            if not (np.isfinite(res) and res > REFINE_RTOL):
                break
            x_next = x + self.lu.solve(r)
            r_next = b - self.A @ x_next
            res_next = float(np.linalg.norm(r_next)) / nb
            if not res_next < res:
                break
            gain = res_next / res
            x, r, res = x_next, r_next, res_next
            if gain > REFINE_STAGNATION:
                break
        if not np.all(np.isfinite(x)) or (check and not res < DIRECT_RTOL):
            raise ConvergenceError(f"{self.what}: direct solve broke down (relative residual "
                                   f"{res:.2e}): singular matrix")
        return x


def require_finite_step(r: np.ndarray, K: sp.spmatrix, what: str) -> None:
    """Raise ConvergenceError when the residual ``r`` or the tangent ``K`` of a Newton step
    is not finite: the iterate left the material's domain (e.g. an inverted element, where
    the energy is NaN), and no step from it can converge. Checked
    before any factorisation: SuperLU's pivot search does not see NaN entries, builds
    inconsistent supernodes and calls BLAS with negative sizes (OpenBLAS prints "On entry to
    DGEMV parameter number 2 had an illegal value" and skips the call) before it fails."""
    if not (np.all(np.isfinite(r)) and np.all(np.isfinite(K.data))):
        raise ConvergenceError(f"{what}: non-finite residual or tangent (the state left the "
                               f"material's domain)")


def csr_of(mat, n: int) -> sp.csr_matrix:
    """The assembled NGSolve matrix ``mat`` (``n`` x ``n``) as a SciPy CSR matrix."""
    r, c, v = mat.COO()
    return sp.csr_matrix((np.asarray(v), (np.asarray(r), np.asarray(c))), shape=(n, n))


def embed_block(Mu: sp.spmatrix, iu: np.ndarray) -> sp.csc_matrix:
    """``Mu`` (displacement DOFs) placed in the free-DOF matrix (zero potential block)."""
    P = sp.csr_matrix((np.ones(int(iu.sum())), (np.flatnonzero(iu), np.arange(int(iu.sum())))),
                      shape=(len(iu), int(iu.sum())))
    return (P @ Mu @ P.T).tocsc()

