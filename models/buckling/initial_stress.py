"""Linearised buckling of the flat clamped film: initial stress, frozen potential, coupled.

Three generalised eigenproblems on the meshes of the coupled model
(:class:`~debench.models.buckling.fem.MembraneModel`), all of the form

    K_0 x = lambda (-dK(v_t)) x,        v_cr^2 = lambda v_t^2,

with ``K_0`` the mechanical tangent of the unloaded film (small-strain elasticity of
(5.15) or (5.26) + k/2 (J-1)^2, clamped lateral face) and ``dK(v_t)`` the change of the
tangent the flat pre-buckled state at the trial voltage ``v_t`` brings:

* ``"initial_stress"`` -- purely mechanical: the stress-stiffness (geometric) matrix
  ``K_sigma(S) = int S_IJ du_k,I dw_k,J dV`` of the total second Piola-Kirchhoff stress
  ``S = F^-1 dOmega/dF`` of the finite-element flat state (mechanical + Maxwell, the
  enthalpy of :func:`~debench.models.buckling.energy.enthalpy_cf`) with the material
  stiffness of the unloaded film: the classical linear buckling analysis of a plate under
  a given in-plane pre-stress, in 3D.  The field does not follow the buckling mode;
* ``"frozen_potential"`` -- ``dK = K_uu(v_t) - K_0``: the full tangent of the flat state
  at fixed electric potential (geometric stiffness + the field's contribution to the
  material tangent + the material nonlinearity of the pre-buckled state), the potential
  not redistributed by the mode;
* ``"coupled"`` -- ``dK = S(v_t) - K_0`` with the condensed tangent at fixed electrode
  voltage ``S = K_uu - K_up K_pp^-1 K_pu``: the electromechanical eigen-analysis of
  :func:`~debench.models.buckling.solver.critical_voltage`, solved here by another
  algorithm (fixed point on the load factor instead of a secant on the lowest eigenvalue).

The stress of the flat state is proportional to ``v^2`` up to the small thinning of the
film, so the load factor is iterated to a fixed point ``v_t <- v_t sqrt(lambda)``: at the
fixed point ``K_0 + dK(v_t)`` is singular, the definition of the bifurcation of each
model.  ``S(0) = K_uu(0) = K_0`` (the mixed derivatives of the enthalpy vanish at zero
field), so the three problems differ only in what ``dK`` keeps.  At fixed potential the
enthalpy is a maximum in the potential (``K_pp`` negative definite), so condensing the
potential adds a positive semi-definite term: the coupled critical voltage is never below
the frozen-potential one.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp
from debench.models import validation as val
from debench.models.buckling.analytic import critical_voltage_plate
from debench.models.buckling.energy import enthalpy_cf
from debench.models.buckling.fem import MembraneModel
from debench.models.buckling.parameters import Discretisation, Plate
from debench.models.errors import ConvergenceError
from debench.models.materials.protocol import IdealDielectricElastomer
from scipy.sparse.linalg import LinearOperator, eigsh, splu

#: the three linearised buckling eigenproblems (``method=``), described in the module docstring
METHODS = ("initial_stress", "frozen_potential", "coupled")
FIXED_POINT_VTOL = 1e-9
"""The fixed point stops when the load-factor update changes v by less than this
(normalised voltage, v_cr ~ 0.2: 5e-9 relative; the update contracts by the small
non-proportionality of the stress in v^2, measured factor ~1e-2 per step)."""
ARPACK_TOL = 1e-12
"""ARPACK's relative accuracy of the Ritz values (its round-off floor ~1e-15 times the
conditioning of K_0 solves, ~1e3 for these meshes)."""
EIG_BACKWARD_MAX = 1e-8
"""Largest accepted backward error ||(K_0 + lambda dK) x|| / (||K_0 x|| + |lambda| ||dK x||)
of the returned pair: 1e4 above the ARPACK tolerance's effect, far below the 1e-6 relative
error in v it would allow."""
NEV = 3


@dataclass(frozen=True)
class LinearisedBucklingResult:
    """Critical voltage of one linearised buckling model on one mesh.

    ``v``: the fixed point of the load factor (normalised voltage); ``method``: one of
    :data:`METHODS`; ``load_factors``: the lowest ``NEV`` critical load factors
    ``lambda = (v_i/v_t)^2`` at the last trial voltage (the first is 1 to
    ``FIXED_POINT_VTOL``); ``eig_residual``: backward error of the first pair;
    ``history``: (v_t, v_t sqrt(lambda)) per step; ``ndof`` (of the coupled space),
    ``ndof_u`` (free displacement dofs), ``h_rel``, ``layers``, ``order``; ``seconds``.
    """

    v: float
    method: str
    load_factors: tuple
    eig_residual: float
    iterations: int
    history: tuple = field(default=())
    ndof: int = 0
    ndof_u: int = 0
    h_rel: float = float("nan")
    layers: int = 0
    order: int = 0
    seconds: float = float("nan")


def _sym(A):
    return (0.5 * (A + A.T)).tocsr()


def _stress_stiffness(model: MembraneModel) -> sp.csr_matrix:
    """Geometric stiffness of the current state's total 2nd Piola-Kirchhoff stress
    (normalised by mu_ref) on the free displacement dofs."""
    u, p = model.gf.components
    F = ngs.Id(3) + ngs.Grad(u)
    omega = enthalpy_cf(F, -ngs.Grad(p), model.material, ogden_delta=model.disc.ogden_delta)
    S = ngs.Inv(F) * omega.Diff(F)
    V = model.X.components[0]
    du, dw = V.TnT()
    kg = ngs.BilinearForm(V, symmetric=False)
    kg += ngs.InnerProduct(ngs.Grad(du) * S, ngs.Grad(dw)) * ngs.dx
    kg.Assemble()
    r, c, vals = kg.mat.COO()
    K = sp.csr_matrix((np.asarray(vals), (np.asarray(r), np.asarray(c))),
                      shape=(V.ndof, V.ndof))
    free = np.flatnonzero(np.asarray(V.FreeDofs(), dtype=bool))
    return _sym(K[free][:, free])


def _flat_state(model: MembraneModel, v: float) -> None:
    model.set_state(np.zeros(model.ndof))
    model.set_voltage(v)
    model.newton()
    model.assemble()


def _tangent_change(model: MembraneModel, method: str, K0):
    """``x -> dK(v_t) x`` of ``method`` at the model's flat state (see the module
    docstring), ``K0`` the mechanical tangent of the unloaded film."""
    if method == "initial_stress":
        return _stress_stiffness(model).__matmul__
    iu, ip = model._ufree, model._pfree
    Kuu = _sym(model._scipy(model.a.mat, iu, iu))
    dKuu = (Kuu - K0).tocsr()
    if method == "frozen_potential":
        return dKuu.__matmul__
    Kup = model._scipy(model.a.mat, iu, ip)
    Kpu = model._scipy(model.a.mat, ip, iu)
    Kpp = splu(model._scipy(model.a.mat, ip, ip).tocsc())

    def apply_dK(x, dKuu=dKuu, Kup=Kup, Kpu=Kpu, Kpp=Kpp):
        return dKuu @ x - Kup @ Kpp.solve(np.asarray(Kpu @ x))
    return apply_dK


def _load_factors(apply_dK, K0, K0inv, n: int, method: str, v_t: float):
    """``(mu, lambda_1, backward error)``: the :data:`NEV` largest eigenvalues ``mu`` of
    ``-dK x = mu K_0 x`` (descending, ARPACK), the load factor ``lambda_1 = 1/mu_1`` and
    the backward error of its eigenpair; ConvergenceError when ARPACK fails, no load
    factor is positive or the backward error exceeds :data:`EIG_BACKWARD_MAX`."""
    A = LinearOperator((n, n), matvec=lambda x, f=apply_dK: -f(x), dtype=float)
    try:
        mu, X = eigsh(A, k=NEV, M=K0, Minv=K0inv, which="LA", tol=ARPACK_TOL,
                      v0=np.ones(n))
    except Exception as exc:  # ArpackNoConvergence
        raise ConvergenceError(f"linearised_critical_voltage ({method}): ARPACK failed "
                               f"at v_t = {v_t:.6g}: {exc}") from exc
    order = np.argsort(mu)[::-1]
    mu, X = mu[order], X[:, order]
    if not mu[0] > 0:
        raise ConvergenceError(f"linearised_critical_voltage ({method}): no compressive "
                               f"load factor at v_t = {v_t:.6g} (mu = {mu})")
    lam = 1.0 / mu[0]
    x = X[:, 0]
    k0x, dkx = K0 @ x, apply_dK(x)
    eig_res = float(np.linalg.norm(k0x + lam * dkx)
                    / (np.linalg.norm(k0x) + abs(lam) * np.linalg.norm(dkx)))
    if not eig_res <= EIG_BACKWARD_MAX:
        raise ConvergenceError(f"linearised_critical_voltage ({method}): eigen backward "
                               f"error {eig_res:.3g} > {EIG_BACKWARD_MAX}")
    return mu, lam, eig_res


def linearised_critical_voltage(plate: Plate, mat: IdealDielectricElastomer, disc: Discretisation,
                                *, method: str = "initial_stress", v_start: float | None = None,
                                vtol: float = FIXED_POINT_VTOL, maxit: int = 20
                                ) -> LinearisedBucklingResult:
    """Critical normalised voltage of the flat film by a linearised buckling model.

    ``method``: ``"initial_stress"`` (purely mechanical: K_0 and the stress stiffness of
    the flat state's total stress), ``"frozen_potential"`` or ``"coupled"`` (see the
    module docstring).  ``v_start``: first trial voltage (default: the Mindlin plate
    estimate of :func:`~debench.models.buckling.analytic.critical_voltage_plate`).

    Accuracy contract: ``v`` is the fixed point of ``v_t -> v_t sqrt(lambda_1(v_t))`` to
    ``|dv| < vtol`` on this mesh, each ``lambda_1`` the largest eigenvalue of
    ``-dK x = mu K_0 x`` (ARPACK, shift-free with a sparse LU of K_0) with backward error
    below :data:`EIG_BACKWARD_MAX`; the flat state is the Newton equilibrium of
    :meth:`MembraneModel.newton`.  The discretisation error is not included (mesh
    sequence).  Raises ConvergenceError (no fixed point, no positive load factor, large
    eigen-residual), ValueError on bad input.
    """
    val.choice("method", method, METHODS)
    vtol = val.tolerance("vtol", vtol)
    maxit = val.integer_at_least("maxit", maxit, 1)
    t_start = time.perf_counter()
    model = MembraneModel(plate, mat, disc, with_imperfection=False)
    iu = model._ufree
    _flat_state(model, 0.0)
    K0 = _sym(model._scipy(model.a.mat, iu, iu))
    K0_lu = splu(K0.tocsc())
    n = K0.shape[0]
    K0inv = LinearOperator((n, n), matvec=K0_lu.solve, dtype=float)
    v_t = critical_voltage_plate(mat, plate.aspect) if v_start is None else \
        val.positive("v_start", v_start)
    hist = []
    for it in range(1, maxit + 1):
        _flat_state(model, v_t)
        apply_dK = _tangent_change(model, method, K0)
        mu, lam, eig_res = _load_factors(apply_dK, K0, K0inv, n, method, v_t)
        v_new = v_t * math.sqrt(lam)
        hist.append((v_t, v_new))
        if abs(v_new - v_t) < vtol:
            factors = tuple(float(1.0 / m) if m > 0 else float("inf") for m in mu)
            return LinearisedBucklingResult(
                v=v_new, method=method, load_factors=factors, eig_residual=eig_res,
                iterations=it, history=tuple(hist), ndof=model.ndof, ndof_u=n,
                h_rel=disc.h_rel, layers=disc.layers, order=disc.order,
                seconds=time.perf_counter() - t_start)
        v_t = v_new
    raise ConvergenceError(f"linearised_critical_voltage ({method}): no fixed point in "
                           f"{maxit} steps: {hist}")
