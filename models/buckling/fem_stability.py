"""Stability of the 3D model's states: the certified lowest eigenvalues (Ch. 5).

The eigen-analysis of :class:`~debench.models.buckling.fem.MembraneModel`, cut from its
module because it is a coherent whole of its own: the condensed tangent at fixed voltage
``S = K_uu - K_up K_pp^-1 K_pu`` with the L2 mass ``M`` (the formulation:
:mod:`debench.models.buckling.fem`), its algebraically lowest eigenvalues by LOBPCG
preconditioned with the factorised saddle-point tangent, and their certification by the
inertia count of Haynsworth and Sylvester (the eigen-solvers themselves:
:mod:`debench.models.buckling.eigen`).

:class:`MembraneStability` is the part of the model class that analyses stability: it
reads the discrete problem the model holds (the forms ``a`` and ``m``, the state ``gf``,
the masks ``_free``, ``_ufree``, ``_pfree``, the factorisation ``_inv`` and whether it is
``_fresh``, the ``eigensolver`` choice), assembles and factorises through the model's
:meth:`~debench.models.buckling.fem.MembraneModel.tangent` and
:meth:`~debench.models.buckling.fem.MembraneModel.assemble`, and records in ``stats`` and
``last_eig``.
"""

from __future__ import annotations

import time

import numpy as np
import scipy.sparse as sp
from debench.models import validation as val
from debench.models.buckling.eigen import (
    EIG_COUNT_MARGIN,
    EIG_MAXIT,
    EIG_RTOL,
    certified,
    lobpcg,
    negative_pivots,
    shift_below_spectrum,
    shifted_lobpcg,
    subspace_iteration,
)
from debench.models.errors import ConvergenceError
from scipy.sparse.linalg import splu


class MembraneStability:
    """The eigen-analysis of the 3D model's current state (module docstring)."""

    def _scipy(self, mat, rows_mask, cols_mask):
        r, c, v = mat.COO()
        A = sp.csr_matrix((np.asarray(v), (np.asarray(r), np.asarray(c))),
                          shape=(self.ndof, self.ndof))
        return A[np.flatnonzero(rows_mask)][:, np.flatnonzero(cols_mask)]

    def lowest_eigenvalues(self, *, nev: int = 3, iters: int = EIG_MAXIT,
                           rtol: float = EIG_RTOL, seed: int = 0, x0=None,
                           certify: bool = True):
        """Algebraically smallest eigenvalues of the condensed tangent ``S u = lambda M u``.

        ``S = K_uu - K_up K_pp^-1 K_pu`` is the stiffness at fixed electrode voltage (the
        potential condensed out), ``M`` the L2 mass of u / t0^2.  A negative eigenvalue is
        an unstable direction at fixed voltage.  LOBPCG finds the smallest eigenvalues
        whatever their sign (no shift to guess), preconditioned by the factorised
        saddle-point tangent (a solve with right-hand side ``(r, 0)`` applies ``S^-1 r``).
        ``x0``: optional starting modes (full-length vectors, as returned). A warm start is
        for speed only where the wanted modes are known to be in it: LOBPCG stops when the
        lowest Ritz pairs of its block have converged, and starting modes that miss an
        eigenvector (a mode that became unstable since they were computed) converge at
        once, hiding it (measured: a negative eigenvalue missed past a voltage maximum).
        Stability records start from the random block.  Whatever the start, the result
        is certified by an inertia count (:meth:`eigenvalue_count`): when an eigenvalue lies
        below the lowest one found, the pencil is shifted below its spectrum and solved
        again (positive definite, with the shifted tangent's inverse as preconditioner);
        ``last_eig["shift"]`` is that shift (0 when the first solve was certified).
        The former engine (``eigensolver="subspace"``, smallest |lambda|, kept for
        comparison) is not certified.  ``certify=False`` skips the counts (one sparse
        LDL^T of the saddle-point tangent each, which costs more than the eigen-solve on the
        largest meshes): for iterations whose final state is certified by the caller.
        Returns (eigenvalues ascending, modes as full-length columns); the largest
        eigen-residual (backward error, see
        :func:`~debench.models.buckling.eigen.lobpcg`) is in ``last_eig``.  Raises
        ConvergenceError if the residuals do not reach ``rtol`` in ``iters`` iterations.
        """
        nev = val.integer_at_least("nev", nev, 1)
        iters = val.integer_at_least("iters", iters, 1)
        rtol = val.tolerance("rtol", rtol)
        t_start = time.perf_counter()
        if not self._fresh:
            self.tangent()
        self.stats["eigen_analyses"] += 1
        if self.eigensolver == "subspace":
            out = self._subspace(nev, iters, rtol, seed)
            self.stats["eig_s"] += time.perf_counter() - t_start
            return out
        S, T, M = self._condensed_operators()
        idx = np.flatnonzero(self._ufree)
        n = len(idx)
        nb = nev + 2
        rng = np.random.default_rng(seed)
        X = rng.standard_normal((n, nb))
        if x0 is not None:
            x0 = np.asarray(x0)[idx].reshape(n, -1)[:, :nb]
            X[:, :x0.shape[1]] = x0
        scale = float(np.max(np.abs(np.einsum("ij,ij->j", X, S(X)))
                             / np.einsum("ij,ij->j", X, M @ X)))
        margin = EIG_COUNT_MARGIN * scale
        w, V, res, its = lobpcg(S, M, T, X, nev, rtol, iters)
        shift = 0.0
        if certify and not certified(self._count, w, margin):
            # LOBPCG converged on eigenpairs that are not the lowest: with the exact inverse
            # of the indefinite S as preconditioner it favours eigenvalues near zero, and a
            # well separated negative one can stay out of its block (measured: -0.032
            # missed beside +1.3e-4 past a voltage maximum).  Shift the pencil below the
            # whole spectrum (found by inertia counts) and solve the positive definite
            # problem, whose smallest eigenvalues LOBPCG finds from any start.
            shift = shift_below_spectrum(self._count, float(np.min(w)) - margin,
                                         max(float(np.max(np.abs(w))), margin))
            w, V, res, its = shifted_lobpcg(S, M, self._shifted_tangent(shift).tocsc(),
                                            np.flatnonzero(self._ufree[self._free]), shift,
                                            rng.standard_normal((n, nb)), nev, rtol, iters)
            if not certified(self._count, w, margin):
                raise ConvergenceError(
                    "lowest_eigenvalues: an eigenvalue below the computed "
                    f"{float(np.min(w)):.6g} remains after the shifted solve")
        self.stats["eig_s"] += time.perf_counter() - t_start
        self.last_eig = {"residual": float(np.max(res)), "iterations": its, "shift": shift}
        order = np.argsort(w)
        modes = np.zeros((self.ndof, nev))
        modes[idx] = V[:, order]
        return w[order], modes

    def _condensed_operators(self):
        """The condensed tangent at fixed voltage ``S = K_uu - K_up K_pp^-1 K_pu``, the
        preconditioner ``T = S^-1`` (a solve with the factorised saddle-point tangent and
        right-hand side ``(r, 0)``), both acting on blocks of the free displacement DOFs,
        and the mass ``M`` there (see :meth:`lowest_eigenvalues`)."""
        iu, ip = self._ufree, self._pfree
        Kuu = self._scipy(self.a.mat, iu, iu)
        Kup = self._scipy(self.a.mat, iu, ip)
        Kpu = self._scipy(self.a.mat, ip, iu)
        Kpp = splu(self._scipy(self.a.mat, ip, ip).tocsc())
        M = self._scipy(self.m.mat, iu, iu)
        n = Kuu.shape[0]

        def S(X):
            X = X.reshape(n, -1)
            return Kuu @ X - Kup @ Kpp.solve(np.asarray(Kpu @ X))

        vin, vout = self.gf.vec.CreateVector(), self.gf.vec.CreateVector()
        idx = np.flatnonzero(iu)

        def T(R):
            R = R.reshape(n, -1)
            out = np.empty_like(R)
            for j in range(R.shape[1]):
                vin.FV().NumPy()[:] = 0.0
                vin.FV().NumPy()[idx] = R[:, j]
                vout.data = self._inv * vin
                out[:, j] = vout.FV().NumPy()[idx]
            return out

        return S, T, M

    def _shifted_tangent(self, sigma: float):
        """The saddle-point tangent on the free DOFs with ``sigma`` times the mass taken off
        its displacement block: its Schur complement is ``S - sigma M``."""
        free = self._free
        K = self._scipy(self.a.mat, free, free)
        if sigma == 0.0:
            return K
        u = self._ufree[free].astype(float)
        Mu = sp.diags(u) @ self._scipy(self.m.mat, free, free) @ sp.diags(u)
        return (K - sigma * Mu).tocsc()

    def eigenvalue_count(self, sigma: float = 0.0) -> int:
        """Number of eigenvalues of the condensed pencil ``S u = lambda M u`` (see
        :meth:`lowest_eigenvalues`) below ``sigma``: a count independent of any eigen-solver.

        By Haynsworth's inertia additivity the saddle-point matrix ``K - sigma M``
        (mass on the displacement block only) has as many negative eigenvalues as its
        potential block ``K_pp`` and its Schur complement ``S - sigma M`` together; by
        Sylvester's law of inertia each is the number of negative pivots of an LDL^T
        factorisation (:func:`~debench.models.buckling.eigen.negative_pivots`).  Raises
        ConvergenceError when ``sigma`` is an eigenvalue to working precision (a zero
        pivot).  Assembles the tangent at the current state unless the factorised one is
        current.
        """
        sigma = float(val.finite("sigma", sigma))
        if not self._fresh:
            self.assemble()
        return self._count(sigma)

    def _count(self, sigma: float) -> int:
        """:meth:`eigenvalue_count` of the tangent as assembled."""
        pp = self._scipy(self.a.mat, self._pfree, self._pfree)
        return negative_pivots(self._shifted_tangent(sigma)) - negative_pivots(pp)

    def _subspace(self, nev, iters, rtol, seed):
        """Block inverse subspace iteration (smallest |lambda|; the former engine:
        :func:`~debench.models.buckling.eigen.subspace_iteration`) with the mass and the
        factorised tangent."""
        vin, vout = self.gf.vec.CreateVector(), self.gf.vec.CreateVector()

        def apply(mat_or_inv, x):
            vin.FV().NumPy()[:] = x
            vout.data = mat_or_inv * vin
            return np.array(vout.FV(), copy=True)

        Mmat, inv = self.m.mat, self._inv
        w, X, change, its = subspace_iteration(lambda x: apply(Mmat, x),
                                               lambda x: apply(inv, x), self._ufree,
                                               nev, iters, rtol, seed)
        self.last_eig = {"residual": change, "iterations": its, "shift": 0.0}
        return w, X
