"""Clean-room solver of the plane-strain manufactured problem ``mms_electroelastic``,
written from its spec and the formula strings it ships
(``reference/mms_electroelastic_formulas.json``, read as JSON): numpy and scikit-fem,
nothing from debench.

Model (normalised, mu = eps = 1): Omega(F, E_L) = W(F) - 1/2 J C^-1 : (E_L x E_L),
E_L = -Grad phi, plane strain (F_33 = 1, E_3 = 0). Stresses derived by hand::

    neo-Hookean:  P_mech = J^(-2/3) (F - I1/3 F^-T) + kappa (J - 1) J F^-T
    Gent:         P_mech = g J^(-2/3) (F - I1/3 F^-T) + kappa (J - 1) J F^-T,
                  g = 1/(1 - (J^(-2/3) I1 - 3)/Jm)
    electric:     a = F^-T E_L,  P_ele = -1/2 J |a|^2 F^-T + J a x (F^-1 a),
                  D_L = -dOmega/dE_L = J F^-1 a = J C^-1 E_L

Weak form (the saddle point of int Omega - b.u + q phi): for all test (v, w) vanishing on
the boundary, int P : Grad v + D_L . Grad w - b.v + q w = 0. Newton with the tangent
d(P, D_L)/d(Grad u, Grad phi) by central differences at each quadrature point (the
tangent only steers Newton; the residual is exact, so the solution is not affected),
started from the problem linearised at the undeformed state. Dirichlet data: the exact
u, phi at the boundary nodes (nodal interpolation of the Lagrange element). Every integral
(residual, tangent, errors) uses the triangle rule of :func:`quadrature_order`, exact for
polynomials of degree 2p + 4 (the spec's criterion for the error norms).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from skfem import (
    Basis,
    BilinearForm,
    ElementTriP1,
    ElementTriP2,
    ElementTriP3,
    ElementVector,
    Functional,
    LinearForm,
    MeshTri,
    asm,
    condense,
    solve,
)

FORMULAS = Path(__file__).resolve().parents[2] / "reference" / "mms_electroelastic_formulas.json"
FD_STEP = 1e-6
"""Central-difference step of the tangent: truncation ~1e-12, round-off ~1e-10 relative."""
NEWTON_RTOL = 1e-11
ELEMENTS = {1: ElementTriP1, 2: ElementTriP2, 3: ElementTriP3}


def quadrature_order(degree: int) -> int:
    """Polynomial degree integrated exactly by the rule used with elements of ``degree``."""
    return 2 * degree + 4


def load_case(material: str) -> dict:
    return json.loads(FORMULAS.read_text())["cases"][f"plane_strain_{material}"]["python"]


def exact(case: dict, X, Y, params: dict) -> dict:
    """Evaluate the formula strings at coordinate arrays (assignments first)."""
    env = {"sin": np.sin, "cos": np.cos, "pi": np.pi, "X": X, "Y": Y, **params}
    g = {"__builtins__": {}}
    for name, expr in case["assignments"]:
        env[name] = eval(expr, g, env)  # noqa: S307 - our own shipped formulas

    def ev(e):
        if isinstance(e, list):
            return [ev(x) for x in e]
        return np.broadcast_to(np.asarray(eval(e, g, env), dtype=float), np.shape(X))

    return {k: ev(case[k]) for k in ("u", "phi", "grad_u", "grad_phi", "b", "q")}


def flux(G, material, kappa, Jm):
    """(P11, P12, P21, P22, D1, D2) from G = (u1,1 u1,2 u2,1 u2,2 phi,1 phi,2), shape (6, N)."""
    N = G.shape[1]
    F = np.zeros((N, 3, 3))
    F[:, 0, 0] = 1 + G[0]
    F[:, 0, 1] = G[1]
    F[:, 1, 0] = G[2]
    F[:, 1, 1] = 1 + G[3]
    F[:, 2, 2] = 1.0
    E = np.zeros((N, 3))
    E[:, 0], E[:, 1] = -G[4], -G[5]
    J = np.linalg.det(F)
    Fi = np.linalg.inv(F)
    FiT = np.transpose(Fi, (0, 2, 1))
    I1 = np.einsum("nij,nij->n", F, F)
    Jm23 = J ** (-2.0 / 3.0)
    dev = Jm23[:, None, None] * (F - (I1 / 3)[:, None, None] * FiT)
    if material == "gent":
        dev = dev / (1 - (Jm23 * I1 - 3) / Jm)[:, None, None]
    P = dev + (kappa * (J - 1) * J)[:, None, None] * FiT
    a = np.einsum("nij,nj->ni", FiT, E)
    Fia = np.einsum("nij,nj->ni", Fi, a)
    P += (-0.5 * J * np.einsum("ni,ni->n", a, a))[:, None, None] * FiT
    P += J[:, None, None] * np.einsum("ni,nj->nij", a, Fia)
    D = J[:, None] * Fia
    return np.array([P[:, 0, 0], P[:, 0, 1], P[:, 1, 0], P[:, 1, 1], D[:, 0], D[:, 1]])


def _six(grad):
    return np.array([grad[0, 0], grad[0, 1], grad[1, 0], grad[1, 1], grad[2, 0], grad[2, 1]])


def solve_mms(material: str, degree: int, n: int, *, kappa=10.0, Jm=50.0) -> dict:
    """Errors {u_L2, u_H1, phi_L2, phi_H1} (H1: seminorm) on the uniform n x n mesh."""
    case = load_case(material)
    params = {"kappa": kappa} | ({"Jm": Jm} if material == "gent" else {})
    t = np.linspace(0.0, 1.0, n + 1)
    mesh = MeshTri.init_tensor(t, t)
    basis = Basis(mesh, ElementVector(ELEMENTS[degree](), 3), intorder=quadrature_order(degree))
    xq = basis.mapping.F(basis.X)            # quadrature points (2, nel, nqp)
    ex = exact(case, xq[0], xq[1], params)
    b, q = np.array(ex["b"]), ex["q"]
    state = {}

    def update(x):
        G = _six(basis.interpolate(x).grad)
        shp = G.shape[1:]
        Gf = G.reshape(6, -1)
        S = flux(Gf, material, kappa, Jm)
        T = np.empty((6, 6, Gf.shape[1]))
        for k in range(6):
            Gp, Gm = Gf.copy(), Gf.copy()
            Gp[k] += FD_STEP
            Gm[k] -= FD_STEP
            T[:, k] = (flux(Gp, material, kappa, Jm) - flux(Gm, material, kappa, Jm)) / (
                2 * FD_STEP)
        state["S"] = S.reshape((6,) + shp)
        state["T"] = T.reshape((6, 6) + shp)

    @LinearForm
    def residual(v, w):
        S = state["S"]
        dv = _six(v.grad)
        return (np.einsum("a...,a...->...", S, dv)
                - b[0] * v[0] - b[1] * v[1] + q * v[2])

    @BilinearForm
    def tangent(u, v, w):
        return np.einsum("ab...,b...,a...->...", state["T"], _six(u.grad), _six(v.grad))

    # Dirichlet data: nodal values of the exact fields on every boundary DOF
    g = np.zeros(basis.N)
    locs = basis.doflocs
    for comp, idx in enumerate(basis.split_indices()):
        e = exact(case, locs[0, idx], locs[1, idx], params)
        g[idx] = e["u"][comp] if comp < 2 else e["phi"]
    D = basis.get_dofs().all()

    x = np.zeros(basis.N)
    update(x)
    x = solve(*condense(asm(tangent, basis), -asm(residual, basis), x=g, D=D))
    free = np.setdiff1d(np.arange(basis.N), D)
    hist = []
    for _ in range(20):
        update(x)
        r = asm(residual, basis)
        hist.append(float(np.linalg.norm(r[free])))
        if hist[-1] <= NEWTON_RTOL * hist[0]:
            break
        x = x + solve(*condense(asm(tangent, basis), -r, D=D))
    else:
        raise RuntimeError(f"clean-room MMS Newton did not converge: {hist}")

    @Functional
    def errors(w):
        s = w["sol"]
        X, Y = w.x
        e = exact(case, X, Y, params)
        du = s[:2] - np.array(e["u"])
        dgu = s.grad[:2] - np.array(e["grad_u"])
        dp = s[2] - e["phi"]
        dgp = s.grad[2] - np.array(e["grad_phi"])
        return np.array([np.sum(du**2, axis=0), np.sum(dgu**2, axis=(0, 1)), dp**2,
                         np.sum(dgp**2, axis=0)])

    sol = basis.interpolate(x)
    vals = [asm(Functional(lambda w, k=k: errors.form(w)[k]), basis, sol=sol)
            for k in range(4)]
    return {"h": 1.0 / n, "ndof": int(free.size), "newton": len(hist) - 1,
            **dict(zip(("u_L2", "u_H1", "phi_L2", "phi_H1"),
                       (float(np.sqrt(v)) for v in vals), strict=True))}
