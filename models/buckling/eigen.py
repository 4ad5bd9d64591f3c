"""Eigen-analysis numerics of the Chapter 5 finite-element model
(:class:`~debench.models.buckling.fem.MembraneModel`), free of the model's state.

* Inertia counts: the number of negative eigenvalues of a sparse symmetric matrix by the
  negative pivots of an LDL^T factorisation (Sylvester's law of inertia,
  :func:`negative_pivots`); with Haynsworth's inertia additivity they count the
  eigenvalues of the condensed pencil below a shift, which certifies an eigen-solve
  (:func:`certified`) or finds a shift below the whole spectrum
  (:func:`shift_below_spectrum`).
* LOBPCG (Knyazev 2001) for the *algebraically* smallest eigenpairs of ``S x = lambda M x``
  (:func:`lobpcg`), also on the pencil shifted below its spectrum
  (:func:`shifted_lobpcg`).
* The former engine: block inverse subspace iteration for the smallest |lambda|
  (:func:`subspace_iteration`, kept for the benchmarks; not certified).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.sparse as sp
from debench.models.errors import ConvergenceError, require
from scipy.sparse.linalg import splu

EIG_RTOL = 1e-10
"""LOBPCG backward error ||S x - lambda M x|| / (||S|| ||x|| + |lambda| ||M x||): its
round-off floor is ~1e-15 (eps times the growth of the saddle-point solves); 1e-10 makes the
eigenvalue error far below the 1e-7 change of lambda over the secant's last step."""
EIG_MAXIT = 200
EIG_COUNT_MARGIN = 1e-8
"""Margin below the lowest computed eigenvalue at which the inertia count certifies it (no
eigenvalue of the pencil below ``lambda_1 - margin``; and, when no computed eigenvalue is
within the margin of zero, as many eigenvalues below zero as were computed), relative to
the pencil's scale (the largest Rayleigh quotient of the random start block, ~ its upper
spectrum).  Far above the eigenvalue error (EIG_RTOL on that scale) and the pivots'
round-off next to a singular tangent (at the critical voltage lambda_1 is zero to 1e-11:
a shift 1e-17 below it gave a wrong count), and far below the gaps between the modes the
records resolve."""


def negative_pivots(A) -> int:
    """Number of negative eigenvalues of the sparse symmetric matrix ``A`` (Sylvester's law of
    inertia): the negative pivots of ``P A P^T = L D L^T``, computed by SuperLU in symmetric
    mode with diagonal pivots only (threshold 0; the row and column orderings must agree,
    checked).  Raises ConvergenceError on a zero or non-finite pivot (``A`` singular to
    working precision) or when SuperLU had to pivot off the diagonal; ValueError when ``A``
    is not square or has non-finite entries."""
    A = sp.csc_matrix(A, dtype=float)
    require(A.ndim == 2 and A.shape[0] == A.shape[1] and A.shape[0] > 0,
            f"A must be a non-empty square matrix, got shape {A.shape}")
    require(bool(np.all(np.isfinite(A.data))), "A must have finite entries")
    try:
        lu = splu(A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                  options={"SymmetricMode": True})
    except RuntimeError as exc:          # SuperLU: "Factor is exactly singular"
        raise ConvergenceError(f"negative_pivots: {exc} (matrix singular)") from exc
    return negative_pivots_of(lu)


def negative_pivots_of(lu) -> int:
    """:func:`negative_pivots` of a matrix already factorised by SuperLU in symmetric mode
    with diagonal pivots (``lu``, as :func:`negative_pivots` factorises it), with the same
    checks."""
    if not np.array_equal(lu.perm_r, lu.perm_c):
        raise ConvergenceError("negative_pivots: SuperLU pivoted off the diagonal")
    d = lu.U.diagonal()
    if not np.all(np.isfinite(d)) or np.any(d == 0.0):
        raise ConvergenceError("negative_pivots: zero pivot (matrix singular)")
    return int(np.count_nonzero(d < 0.0))


def _mortho(Z, MZ, drop=1e-10):
    """Coefficients T with (Z T)^T M (Z T) = I over the well-conditioned part of span(Z)."""
    B = Z.T @ MZ
    B = 0.5 * (B + B.T)
    bw, bv = np.linalg.eigh(B)
    keep = bw > drop * bw.max()
    return bv[:, keep] / np.sqrt(bw[keep])


def lobpcg(S, M, T, X, nev, rtol, iters):
    """Locally optimal block preconditioned conjugate gradient (Knyazev 2001) for the
    algebraically smallest eigenpairs of ``S x = lambda M x``.

    ``S``, ``T`` act on blocks (T: the exact inverse S^-1, applied by the factorised
    saddle-point tangent), ``M`` sparse SPD.  Rayleigh-Ritz on span[X, T M X, P] (equal
    to LOBPCG's span[X, T R, P] for this T); the new directions are M-orthogonalised
    against X before the Gram matrix (near-dependent directions dropped).  Converged when
    the backward error
    ``||S x - lambda M x|| / (||S|| ||x|| + |lambda| ||M x||)`` of the first ``nev`` pairs
    is below ``rtol`` (||S|| estimated on the start block).
    Returns (lambda[:nev], X[:, :nev], residuals, iterations); raises ConvergenceError.
    """
    nb = X.shape[1]
    SX = S(X)
    # scale of S: ||S x|| / ||x|| over the (random or previous) start block
    s_norm = float(np.max(np.linalg.norm(SX, axis=0) / np.linalg.norm(X, axis=0)))
    lam = np.zeros(nb)
    P = None
    res = np.full(nev, np.inf)
    for it in range(1, iters + 1):
        blocks, sblocks = [X], [SX]
        if it > 1:
            MX = M @ X
            R = SX - MX * lam
            scale = (s_norm * np.linalg.norm(X[:, :nev], axis=0)
                     + np.abs(lam[:nev]) * np.linalg.norm(MX[:, :nev], axis=0))
            res = np.linalg.norm(R[:, :nev], axis=0) / scale
            if np.all(res <= rtol):
                return lam[:nev], X[:, :nev], res, it - 1
            # span[X, T R] = span[X, T M X] for T = S^-1; T M X is the numerically stable
            # form when S is (nearly) singular (T R would cancel), as in inverse iteration
            # new directions M-orthogonalised against the (M-orthonormal) Ritz block,
            # twice: a Gram matrix of nearly parallel columns would lose the correction
            # below sqrt(eps)
            W = T(MX)
            if P is not None:
                W = np.hstack([W, P])
            for _ in range(2):
                W = W - X @ (MX.T @ W)
                W = W / np.sqrt(np.einsum("ij,ij->j", W, M @ W))
            blocks.append(W)
            sblocks.append(S(W))
        Z, SZ = np.hstack(blocks), np.hstack(sblocks)
        C = _mortho(Z, M @ Z)
        A = C.T @ (Z.T @ SZ) @ C
        theta, Q = np.linalg.eigh(0.5 * (A + A.T))
        if len(theta) < nb:
            raise ConvergenceError("LOBPCG: the search space collapsed")
        Y = C @ Q[:, :nb]
        lam = theta[:nb]
        if it > 1:
            P = Z[:, nb:] @ Y[nb:]
        X, SX = Z @ Y, SZ @ Y
    raise ConvergenceError(f"LOBPCG: eigen-residuals {res} above {rtol} after {iters} "
                           f"iterations ({lam[:nev]})")


def shifted_lobpcg(S, M, K_shifted, u_rows, shift, X, nev, rtol, iters):
    """:func:`lobpcg` for the pencil shifted by ``shift``, ``(S - shift M) x = mu M x``,
    preconditioned by the exact inverse of the shifted saddle-point matrix ``K_shifted``
    (sparse, on the free DOFs, its Schur complement ``S - shift M``; ``u_rows``: its
    displacement rows), factorised here by SuperLU.  Returns (lambda = mu + shift, X,
    residuals, iterations) as :func:`lobpcg`."""
    lu = splu(K_shifted)
    nfree = K_shifted.shape[0]
    n = len(u_rows)

    def S_shift(X):
        return S(X) - shift * (M @ X.reshape(n, -1))

    def T_shift(R):
        R = R.reshape(n, -1)
        rhs = np.zeros((nfree, R.shape[1]))
        rhs[u_rows] = R
        return lu.solve(rhs)[u_rows]

    w, V, res, its = lobpcg(S_shift, M, T_shift, X, nev, rtol, iters)
    return w + shift, V, res, its


def certified(count: Callable[[float], int], w: np.ndarray, margin: float) -> bool:
    """Whether ``w`` starts at the lowest eigenvalue by inertia counts (``count(sigma)``:
    the number of eigenvalues of the pencil below ``sigma``): none below
    ``min(w) - margin`` and, when every ``w`` is farther than ``margin`` from zero,
    exactly as many below zero as ``w`` has."""
    if count(float(np.min(w)) - margin) > 0:
        return False
    if np.min(np.abs(w)) > margin:
        return count(0.0) == int(np.count_nonzero(w < 0))
    return True


def shift_below_spectrum(count: Callable[[float], int], start: float, scale: float) -> float:
    """A shift below every eigenvalue of the pencil: from ``start`` down in steps that
    double from ``scale`` until the inertia count ``count(sigma)`` is zero."""
    step = max(scale, 1e-12)
    sigma = start
    for _ in range(80):
        sigma -= step
        if count(sigma) == 0:
            return sigma
        step *= 2.0
    raise ConvergenceError("lowest_eigenvalues: no shift below the spectrum down to "
                           f"{sigma:.3g}")


def subspace_iteration(apply_m: Callable[[np.ndarray], np.ndarray],
                       apply_inv: Callable[[np.ndarray], np.ndarray], mask: np.ndarray,
                       nev: int, iters: int, rtol: float, seed: int):
    """Block inverse subspace iteration for the eigenvalues of smallest |lambda| of
    ``K x = lambda M x`` on the DOFs ``mask`` (the former engine).

    ``apply_m`` and ``apply_inv`` map a full-length vector to ``M x`` and ``K^-1 x``.
    Converged when the first ``nev`` Ritz values change by at most ``rtol`` times the
    largest finite one (+ 1e-13) from one iteration to the next.  Returns (lambda
    ascending, X as full-length columns, the last change, iterations); raises
    ConvergenceError.
    """
    rng = np.random.default_rng(seed)
    nb = nev + 2
    Xb = rng.standard_normal((len(mask), nb)) * mask[:, None]
    old = None
    for it in range(iters):
        MX = np.column_stack([apply_m(Xb[:, j]) for j in range(nb)])
        Y = np.column_stack([apply_inv(MX[:, j]) for j in range(nb)]) * mask[:, None]
        scale = np.max(np.abs(Y), axis=0)
        if not np.all(np.isfinite(scale)) or np.any(scale == 0):
            raise ConvergenceError("subspace iteration: singular tangent (exact bifurcation)")
        Y, MX = Y / scale, MX / scale
        MY = np.column_stack([apply_m(Y[:, j]) for j in range(nb)])
        A, B = Y.T @ MX, Y.T @ MY
        A, B = 0.5 * (A + A.T), 0.5 * (B + B.T)
        bw, bv = np.linalg.eigh(B)
        keep = bw > 1e-13 * bw.max()
        T = bv[:, keep] / np.sqrt(bw[keep])
        w, Q = np.linalg.eigh(T.T @ A @ T)
        Q = T @ Q
        if len(w) < nb:
            Q = np.column_stack([Q, rng.standard_normal((nb, nb - len(w)))])
            w = np.concatenate([w, np.full(nb - len(w), np.inf)])
        order = np.argsort(np.abs(w))
        w, Q = w[order], Q[:, order]
        Xb = Y @ Q
        wscale = np.max(np.abs(w[np.isfinite(w)]))
        if old is not None and np.all(np.abs(w[:nev] - old) <= rtol * wscale + 1e-13):
            idx = np.argsort(w[:nev])
            return (w[:nev][idx], Xb[:, :nev][:, idx], float(np.max(np.abs(w[:nev] - old))),
                    it + 1)
        old = w[:nev]
    raise ConvergenceError(f"subspace iteration: no convergence in {iters} steps ({w[:nev]})")
