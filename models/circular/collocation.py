"""Annulus B by collocation (``scipy.integrate.solve_bvp``, as the thesis' bvp4c).

Independent of :mod:`debench.models.circular.shooting`: the right-hand sides and their Jacobians
come from the sympy-generated module :mod:`debench.models.circular.generated`
(``tools/derive_ch3.py``), the interface stress from a complex-step derivative of the Gent
energy (3.23), and the problem is posed as a two-point BVP in ``t = ln(R/R_A)``:

    y = (lambda_1, lambda_2),  y' = f(y)  (3.34)-(3.35) or the membrane balance,
    lambda_2(0) = lam  (3.31),   lambda_2(T) = lamP  (3.38),   T = ln(R_B/R_A),

solved for a sequence of circle-A stretches ``lam`` by natural-parameter continuation (the
previous solution is the next initial guess), as in the thesis (Sec. 3.4.2).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from debench.models import validation as v
from debench.models.errors import ConvergenceError
from scipy.integrate import solve_bvp

from . import generated as gen
from .params import Annulus, locking_stretch_equibiaxial

#: solve_bvp tolerance on the relative collocation residual; gives <= ~1e-7 relative
#: agreement with the shooting solver (test_ch3_solvers)
BVP_TOL = 1e-8
MAX_NODES = 20000


def _gent_energy(l1, l2, kappa):
    I1 = l1**2 + l2**2 + 1.0 / (l1**2 * l2**2)
    if kappa == 0.0:
        return (I1 - 3.0) / 2.0
    return -np.log(1.0 - kappa * (I1 - 3.0)) / (2.0 * kappa)


@v.finite_result
def nominal_radial_stress(l1, l2, kappa):
    """T1 = dWs/dl1 per unit mu (3.17, 3.36), by complex step of the energy (3.23).

    ``l1``, ``l2`` finite and > 0, ``kappa = 1/Jm >= 0``, the state below the Gent lock.
    """
    l1 = v.positive("l1", l1)
    l2 = v.positive("l2", l2)
    kappa = v.nonnegative("kappa", kappa)
    I1 = l1**2 + l2**2 + 1.0 / (l1**2 * l2**2)
    with np.errstate(over="ignore"):
        if not np.all(np.isfinite(I1) & (1.0 - kappa * (I1 - 3.0) > 0)):
            raise ValueError(f"l1 = {v._show(l1)}, l2 = {v._show(l2)}: I1 - 3 is past the "
                             f"Gent lock (must be < Jm = 1/kappa) or overflows")
    h = 1e-30
    return _gent_energy(np.asarray(l1) + 1j * h, l2, kappa).imag / h


def _funcs(annulus: Annulus):
    kappa = annulus.kappa
    rhs = gen.rhs_printed if annulus.equilibrium == "printed" else gen.rhs_membrane
    jac = gen.jac_printed if annulus.equilibrium == "printed" else gen.jac_membrane

    def fun(t, y):
        f1, f2 = rhs(y[0], y[1], kappa)
        return np.vstack([f1, np.broadcast_to(f2, y[0].shape)])

    def fun_jac(t, y):
        (a, b), (c, d) = jac(y[0], y[1], kappa)
        n = y.shape[1]
        J = np.empty((2, 2, n))
        J[0, 0], J[0, 1] = a, b
        J[1, 0], J[1, 1] = c, d
        return J

    return fun, fun_jac


@dataclass(frozen=True)
class CollocationSolution:
    """solve_bvp solution at one circle-A stretch ``lam``."""

    lam: float
    lam1: float          # lambda_1^(B)(R_A)
    T1: float            # T1^(B)(R_A) / mu
    sol: object          # scipy's BVP result (``sol.sol(t)`` is the interpolant)
    nodes: int


def solve(annulus: Annulus, lam: float, guess=None, *, tol: float = BVP_TOL):
    """One annulus BVP at circle-A stretch ``lam``; raises ConvergenceError on failure.

    ``guess``: a previous :class:`CollocationSolution` (continuation) or None (the uniform
    pre-stretched state lambda_1 = lambda_2 = lamP, a naive cold start). ``lam`` lies in
    [lamP, circle-A Gent locking stretch); ``tol`` a finite tolerance in (0, 1).
    Converged means ``solve_bvp`` reports success (relative collocation residuals below
    ``tol``) with finite, positive stretches; otherwise ConvergenceError.
    """
    v.instance("annulus", annulus, Annulus)
    lock = locking_stretch_equibiaxial(annulus.Jm)
    lam = v.in_range("lam", lam, annulus.lamP, lock, hi_open=True,
                     bound=f"past the Gent locking stretch {lock:.6g} (Jm = {annulus.Jm:.6g})")
    v.tolerance("tol", tol)
    if guess is not None:
        v.instance("guess", guess, CollocationSolution)
    T = float(np.log(annulus.radius_ratio))
    fun, fun_jac = _funcs(annulus)

    def bc(ya, yb):
        return np.array([ya[1] - lam, yb[1] - annulus.lamP])

    def bc_jac(ya, yb):
        return np.array([[0.0, 1.0], [0.0, 0.0]]), np.array([[0.0, 0.0], [0.0, 1.0]])

    if guess is None:
        t = np.linspace(0.0, T, 41)
        y = np.full((2, t.size), float(annulus.lamP))
    else:
        t = guess.sol.x
        y = guess.sol.y.copy()
        # shift the hoop stretch so the guess satisfies the new interface condition
        y[1] += (lam - y[1, 0]) * (1 - t / T)
    with np.errstate(all="ignore"):
        res = solve_bvp(fun, bc, t, y, fun_jac=fun_jac, bc_jac=bc_jac, tol=tol,
                        max_nodes=MAX_NODES)
    if not res.success or not np.all(np.isfinite(res.y)) or np.any(res.y[0] <= 0):
        resid = np.max(res.rms_residuals) if res.rms_residuals is not None else "n/a"
        raise ConvergenceError(f"solve_bvp failed for {annulus} at lam = {lam}: "
                               f"{res.message} (max residual {resid})")
    l1 = float(res.y[0, 0])
    return CollocationSolution(lam=float(lam), lam1=l1,
                               T1=float(nominal_radial_stress(l1, float(lam), annulus.kappa)),
                               sol=res, nodes=res.x.size)


@dataclass(frozen=True)
class CollocationBranch:
    annulus: Annulus
    lam: np.ndarray
    lam1: np.ndarray
    T1: np.ndarray
    solutions: tuple


def branch(annulus: Annulus, lam, *, tol: float = BVP_TOL, substeps: int = 1,
           warm: bool = True) -> CollocationBranch:
    """Natural-parameter continuation over increasing ``lam`` (``warm=False``: naive cold
    start at every point, the benchmark baseline). ``substeps`` intermediate solves per
    interval make the continuation steps smaller where needed. ``lam`` a non-empty 1-D
    array in [lamP, locking stretch), ``substeps >= 1``."""
    v.instance("annulus", annulus, Annulus)
    lam = np.asarray(v.array("lam", lam), dtype=float)
    if lam.ndim != 1 or lam.size == 0:
        raise ValueError(f"lam must be a non-empty 1-D array, got shape {lam.shape}")
    v.at_least("lam", lam, annulus.lamP)
    v.tolerance("tol", tol)
    v.integer_at_least("substeps", substeps, 1)
    if np.any(np.diff(lam) <= 0):
        raise ValueError("lam must be strictly increasing for continuation")
    sols = []
    prev = None
    start = annulus.lamP
    for target in lam:
        if warm:
            for s in np.linspace(start, target, substeps + 1)[1:]:
                prev = solve(annulus, float(s), prev, tol=tol) if s > annulus.lamP else prev
            start = target
            if prev is None:  # target == lamP
                prev = solve(annulus, float(target), None, tol=tol)
            sols.append(prev)
        else:
            sols.append(solve(annulus, float(target), None, tol=tol))
    return CollocationBranch(annulus=annulus, lam=lam,
                             lam1=np.array([s.lam1 for s in sols]),
                             T1=np.array([s.T1 for s in sols]), solutions=tuple(sols))
