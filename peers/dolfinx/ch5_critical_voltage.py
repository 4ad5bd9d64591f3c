"""DOLFINx adapter: ch5_critical_voltage, the clamped film's n = 0 critical voltage.

Written as a DOLFINx user writes it, from the problem page alone
(``debench problems ch5_critical_voltage --markdown``), with no debench code:

* axisymmetric (R, Z) body of revolution, lengths in units of t0 (0 <= R <= a/t0,
  0 <= Z <= 1), mixed unknowns w = (u_R, u_Z, phi) in one blocked Lagrange space;
  F = [[1 + u_R,R, u_R,Z, 0], [u_Z,R, 1 + u_Z,Z, 0], [0, 0, 1 + u_R/R]],
  E_L = -(phi_R, phi_Z, 0);
* the electric enthalpy per mu_ref (stresses / mu_ref, potential normalised as
  v = Phi/t0 sqrt(eps/mu_ref)): Omega = W_mech(F)/mu_ref - (1/2) J C^-1 : (E_L x E_L),
  W_mech the compressible neo-Hookean (5.15)-(5.17) or the three-term Ogden (5.26) with
  k/2 (J - 1)^2, written in UFL; Pi = int Omega R dR dZ, residual and tangent by
  ufl.derivative (the tangent is the second variation: the exact fixed-voltage stability
  operator of the spec, coupled, mechanical + mixed + electric);
* boundary conditions of the spec: rim R = a clamped (u = 0), axis u_R = 0, phi = 0 on
  Z = 0 and phi = v on Z = 1 (whole faces), the rest natural;
* the flat state at voltage v by PETSc SNES (Newton, MUMPS LU), continuation in v from 0;
* stability at fixed voltage, n = 0: the tangent K of the (u_R, u_Z, phi) problem with the
  Dirichlet rows eliminated is factorised by MUMPS LDL^T (Cholesky interface, symmetric
  indefinite, with pivoting) and its inertia read (MatGetInertia). K_pp is negative
  definite, so by Haynsworth's inertia additivity the number of negative eigenvalues of
  the condensed S = K_uu - K_up K_pp^-1 K_pu is neg(K) - (free potential dofs); the flat
  state is stable while it is zero. v_cr is bracketed by a scan in v and bisected on that
  count (the first crossing from v = 0: every scanned state below it is certified
  stable).

Ogden: the principal stretches squared of the (R, Z) block of C are
(tr +- sqrt(d^2 + delta^2))/2 with d^2 = (C_RR - C_ZZ)^2 + 4 C_RZ^2 (delta regularises
the repeated stretches of the undeformed film, where the square root is not
differentiable; the energy is even in that root, so the error is O(delta^2)); the hoop
stretch squared is C_TT.

Resolution: P3 displacement and P3 potential (``--degree``) on a quadrilateral mesh graded
towards the rim and towards both faces (the clamped corners); v_cr on two meshes (the
second twice as fine in each direction); the finer is written and twice the change is
stated as its accuracy. Measured (neo-Hookean): P2 on 20 x 2, 40 x 4 cells: 0.2206167,
0.2203691; P3 on 40 x 4, 80 x 8: 0.2202962, 0.2202765.
"""

from __future__ import annotations  # noqa: I001 - dolfinx_solver must precede dolfinx

import argparse
import json
import time
from pathlib import Path

import dolfinx_solver  # the wheel's package first: it loads MPI ahead of dolfinx and PETSc
import dolfinx
import dolfinx.fem.petsc
import numpy as np
import ufl
from mpi4py import MPI
from petsc4py import PETSc

#: Newton: relative update 1e-10 (quadratic convergence: the state is then exact to
#: round-off) or residual 1e-11 relative / 1e-12 absolute (residuals per mu_ref ~ 1)
SNES_RTOL, SNES_ATOL, SNES_STOL = 1e-11, 1e-12, 1e-10
#: bisection on the stability count stops at this relative bracket width (far below the
#: discretisation error of ~1e-5 relative)
BISECT_RTOL = 1e-7
#: regularisation of repeated principal stretches in the Ogden energy (O(delta^2) error)
OGDEN_DELTA = 1e-4


def graded_mesh(aspect: float, nr: int, nz: int, beta_r: float, beta_z: float):
    """Quadrilaterals on [0, aspect] x [0, 1], tanh-graded: in R the cells shrink towards
    the rim (R = aspect tanh(beta_r s)/tanh(beta_r): the rim cell is sech^2(beta_r) of
    the axis cell), in Z towards both faces (the clamped corners are where both meet)."""
    mesh = dolfinx.mesh.create_rectangle(MPI.COMM_SELF, [[0.0, 0.0], [1.0, 1.0]],
                                         [nr, nz], dolfinx.mesh.CellType.quadrilateral)
    x = mesh.geometry.x
    s, t = x[:, 0].copy(), x[:, 1].copy()
    x[:, 0] = aspect * np.tanh(beta_r * s) / np.tanh(beta_r)
    x[:, 1] = 0.5 * (1.0 + np.tanh(beta_z * (2.0 * t - 1.0)) / np.tanh(beta_z))
    return mesh


def axi_F(u, R):
    g = ufl.grad(u)
    return ufl.as_matrix([[1 + g[0, 0], g[0, 1], 0], [g[1, 0], 1 + g[1, 1], 0],
                          [0, 0, 1 + u[0] / R]])


def energy_nh(F, mu, k):
    C = F.T * F
    J = ufl.det(F)
    return mu / 2 * (J ** (-2.0 / 3.0) * ufl.tr(C) - 3) + k / 2 * (J - 1) ** 2


def energy_ogden(F, mu_p, alpha, k, delta):
    C = F.T * F
    J = ufl.det(F)
    tr2 = C[0, 0] + C[1, 1]
    disc = ufl.sqrt((C[0, 0] - C[1, 1]) ** 2 + 4 * C[0, 1] ** 2 + delta**2)
    lam2 = [(tr2 + disc) / 2, (tr2 - disc) / 2, C[2, 2]]  # principal stretches squared
    W = k / 2 * (J - 1) ** 2
    for m, a in zip(mu_p, alpha, strict=True):
        W += 2 * m / a**2 * (sum((J ** (-2.0 / 3.0) * l2) ** (a / 2) for l2 in lam2) - 3)
    return W


class Film:
    """The axisymmetric clamped film on one mesh."""

    def __init__(self, case: dict, aspect: float, nr: int, nz: int, degree: int,
                 beta: tuple[float, float], quad: int):
        import basix.ufl

        self.mesh = mesh = graded_mesh(aspect, nr, nz, *beta)

        cell = mesh.basix_cell()
        me = basix.ufl.mixed_element([basix.ufl.element("Lagrange", cell, degree, shape=(2,)),
                                      basix.ufl.element("Lagrange", cell, degree)])
        self.W = W = dolfinx.fem.functionspace(mesh, me)
        self.w = w = dolfinx.fem.Function(W)
        u, phi = ufl.split(w)
        R = ufl.SpatialCoordinate(mesh)[0]
        F = axi_F(u, R)
        J = ufl.det(F)
        C = F.T * F
        E = ufl.as_vector([-phi.dx(0), -phi.dx(1), 0])
        if case["material"] == "nh":
            Wm = energy_nh(F, case["mu"], case["k"])
        else:
            Wm = energy_ogden(F, case["mu_p"], case["alpha"], case["k"], OGDEN_DELTA)
        Omega = Wm - 0.5 * J * ufl.inner(ufl.inv(C) * E, E)
        dx = ufl.dx(metadata={"quadrature_degree": quad})
        Pi = Omega * R * dx
        self.Fres = ufl.derivative(Pi, w, ufl.TestFunction(W))
        self.Jac = ufl.derivative(self.Fres, w, ufl.TrialFunction(W))
        fdim = 1
        rim = dolfinx.mesh.locate_entities_boundary(mesh, fdim,
                                                    lambda x: np.isclose(x[0], aspect))
        axis = dolfinx.mesh.locate_entities_boundary(mesh, fdim, lambda x: np.isclose(x[0], 0))
        bot = dolfinx.mesh.locate_entities_boundary(mesh, fdim, lambda x: np.isclose(x[1], 0))
        top = dolfinx.mesh.locate_entities_boundary(mesh, fdim, lambda x: np.isclose(x[1], 1))
        Wu, _ = W.sub(0).collapse()
        zero_u = dolfinx.fem.Function(Wu)
        self.v = dolfinx.fem.Constant(mesh, 0.0)
        dofs_rim = dolfinx.fem.locate_dofs_topological((W.sub(0), Wu), fdim, rim)
        dofs_axis = dolfinx.fem.locate_dofs_topological(W.sub(0).sub(0), fdim, axis)
        dofs_bot = dolfinx.fem.locate_dofs_topological(W.sub(1), fdim, bot)
        dofs_top = dolfinx.fem.locate_dofs_topological(W.sub(1), fdim, top)
        self.bcs = [dolfinx.fem.dirichletbc(zero_u, dofs_rim, W.sub(0)),
                    dolfinx.fem.dirichletbc(0.0, dofs_axis, W.sub(0).sub(0)),
                    dolfinx.fem.dirichletbc(0.0, dofs_bot, W.sub(1)),
                    dolfinx.fem.dirichletbc(self.v, dofs_top, W.sub(1))]
        phi_dofs = np.unique(W.sub(1).dofmap.list)
        constrained_phi = np.union1d(dofs_bot, dofs_top)
        self.free_phi = phi_dofs.size - constrained_phi.size
        self.ndofs = W.dofmap.index_map.size_local * W.dofmap.index_map_bs
        self.problem = dolfinx.fem.petsc.NonlinearProblem(
            self.Fres, w, bcs=self.bcs, J=self.Jac, petsc_options_prefix="film_",
            petsc_options={"snes_type": "newtonls", "snes_linesearch_type": "basic",
                           "snes_rtol": SNES_RTOL, "snes_atol": SNES_ATOL,
                           "snes_stol": SNES_STOL, "snes_max_it": 30,
                           "ksp_type": "preonly", "pc_type": "lu",
                           "pc_factor_mat_solver_type": "mumps"})
        self.jac_form = dolfinx.fem.form(self.Jac)
        self.newton = 0

    def solve(self, v: float, start: np.ndarray) -> bool:
        self.w.x.array[:] = start
        self.v.value = v
        self.problem.solve()
        self.newton += self.problem.solver.getIterationNumber()
        return (self.problem.solver.getConvergedReason() > 0
                and bool(np.all(np.isfinite(self.w.x.array))))

    def unstable_count(self) -> int:
        """Negative eigenvalues of the condensed fixed-voltage tangent S at the current
        state: inertia of the LDL^T factorisation of K minus the free potential dofs."""
        A = dolfinx.fem.petsc.assemble_matrix(self.jac_form, bcs=self.bcs, diag=1.0)
        A.assemble()
        A.setOption(PETSc.Mat.Option.SYMMETRIC, True)
        ksp = PETSc.KSP().create(MPI.COMM_SELF)
        ksp.setOperators(A)
        ksp.setType("preonly")
        pc = ksp.getPC()
        pc.setType("cholesky")
        pc.setFactorSolverType("mumps")
        pc.setFactorSetUpSolverType()
        Fm = pc.getFactorMatrix()
        Fm.setMumpsIcntl(13, 1)  # inertia on the root front too (sequential)
        Fm.setMumpsIcntl(24, 1)  # null-pivot detection (required by MatGetInertia)
        ksp.setUp()
        neg, zero, _ = Fm.getInertia()
        ksp.destroy()
        A.destroy()
        if zero:
            raise RuntimeError(f"singular tangent at v = {float(self.v.value)} ({zero} "
                               "null pivots): move the scan off the critical point")
        return neg - self.free_phi


def critical_voltage(film: Film, dv: float, v_max: float) -> tuple[float, dict]:
    """The first v at which the flat state loses stability: scan with step dv, then bisect."""
    state = np.zeros_like(film.w.x.array)
    prev = None
    v_lo, s_lo = 0.0, state.copy()
    v = 0.0
    scanned = 0
    while True:
        v_new = v + dv
        if v_new > v_max:
            raise RuntimeError(f"no loss of stability up to v = {v_max}")
        guess = s_lo if prev is None else s_lo + (s_lo - prev) * (v_new - v_lo) / dv
        if not film.solve(v_new, guess):
            raise RuntimeError(f"flat state did not converge at v = {v_new}")
        scanned += 1
        if film.unstable_count() > 0:
            if scanned == 1:
                raise RuntimeError(f"unstable already at the first scan step v = {v_new}:"
                                   " reduce --dv")
            v_hi = v_new
            break
        prev, s_lo, v_lo, v = s_lo, film.w.x.array.copy(), v_new, v_new
    bis = 0
    while v_hi - v_lo > BISECT_RTOL * v_hi:
        vm = 0.5 * (v_lo + v_hi)
        if not film.solve(vm, s_lo):
            raise RuntimeError(f"flat state did not converge at v = {vm}")
        bis += 1
        if film.unstable_count() > 0:
            v_hi = vm
        else:
            v_lo, s_lo = vm, film.w.x.array.copy()
    return 0.5 * (v_lo + v_hi), {"scan_steps": scanned, "bisections": bis,
                                 "bracket": [v_lo, v_hi]}


def cases_from_spec(spec: dict) -> dict:
    par = spec["parameters"]
    mu_ref = float(par["mu_ref"]["value"])
    mats = {m["name"]: m for m in spec["model"]["material"]}
    out = {}
    for case in [str(c) for c in par["case"]["value"]]:
        mat = case.split("_")[0]
        mp = mats[mat]["parameters"]
        if mat == "nh":
            out[case] = {"material": "nh", "mu": float(mp["mu"]["value"]) / mu_ref,
                         "k": float(mp["k"]["value"]) / mu_ref}
        else:
            out[case] = {"material": "ogden",
                         "mu_p": [float(x) / mu_ref for x in mp["mu_p"]["value"]],
                         "alpha": [float(x) for x in mp["alpha"]["value"]],
                         "k": float(mp["k"]["value"]) / mu_ref}
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--problem-json", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--label", default="default")
    ap.add_argument("--nr", type=int, default=40, help="cells along R (coarser mesh)")
    ap.add_argument("--nz", type=int, default=4, help="cells through the thickness")
    ap.add_argument("--degree", type=int, default=3)
    ap.add_argument("--beta-r", type=float, default=3.0, help="grading towards the rim")
    ap.add_argument("--beta-z", type=float, default=2.0, help="grading towards the faces")
    ap.add_argument("--dv", type=float, default=0.02, help="scan step in v")
    ap.add_argument("--cases", nargs="*", help="subset of the cases (default: all)")
    a = ap.parse_args()
    doc = json.loads(Path(a.problem_json).read_text())
    spec = doc["spec"]
    aspect = float(spec["parameters"]["aspect"]["value"])
    cases = cases_from_spec(spec)
    if a.cases:
        cases = {k: cases[k] for k in a.cases}
    quad = 3 * a.degree
    t0 = time.perf_counter()
    rows, notes, worst = [], [], 0.0
    meshes = [(a.nr, a.nz), (2 * a.nr, 2 * a.nz)]
    for name, case in cases.items():
        vals = []
        for nr, nz in meshes:
            film = Film(case, aspect, nr, nz, a.degree, (a.beta_r, a.beta_z), quad)
            vcr, info = critical_voltage(film, a.dv, 2.0)
            vals.append(vcr)
            print(f"{name}: {nr}x{nz} cells, {film.ndofs} dofs: v_cr = {vcr:.9f} "
                  f"({info['scan_steps']} scan steps, {info['bisections']} bisections, "
                  f"{film.newton} Newton iterations), {time.perf_counter() - t0:.1f} s",
                  flush=True)
        change = abs(vals[1] - vals[0])
        worst = max(worst, change)
        notes.append(f"{name} {vals[0]:.7f} -> {vals[1]:.7f}")
        rows.append((name, vals[-1]))
    out = Path(a.out)
    with (out / "results.csv").open("w") as fh:
        fh.write("case,v_cr [1]\n")
        for name, val in rows:
            fh.write(f"{name},{val!r}\n")
    (n1, z1), (n2, z2) = meshes
    meta = {
        "quantity": "v_cr",
        "code": {"name": "DOLFINx", "version": dolfinx.__version__,
                 "commit_or_release": f"dolfinx-solver-real {dolfinx_solver.__version__} "
                                      f"(packages the DOLFINx {dolfinx_solver.RELEASE} release)",
                 "url": "https://github.com/FEniCS/dolfinx", "license": "LGPL-3.0-or-later"},
        "method": {
            "description": "axisymmetric (R, Z) mixed displacement-potential model of the "
                           "clamped film (UFL electric enthalpy, ufl.derivative residual "
                           "and exact fixed-voltage tangent); flat state by continuation in "
                           "v; n = 0 stability by the inertia of the MUMPS LDL^T "
                           "factorisation of the coupled tangent (negative count minus the "
                           "free potential dofs = negative eigenvalues of the condensed "
                           "S), scan then bisection",
            "discretisation": f"Lagrange P{a.degree} displacement and P{a.degree} "
                              f"potential on quadrilaterals; quadrature degree {quad}",
            "mesh_or_resolution": f"{n2} x {z2} cells (R x Z), tanh-graded towards the "
                                  f"rim (beta {a.beta_r:g}) and both faces (beta "
                                  f"{a.beta_z:g}); checked against {n1} x {z1}",
            "solver": "PETSc SNES newtonls (full Newton steps), MUMPS LU; stability: "
                      "MUMPS Cholesky/LDL^T (symmetric indefinite) with MatGetInertia",
            "tolerances": f"snes_rtol {SNES_RTOL:g}, snes_atol {SNES_ATOL:g}, snes_stol "
                          f"{SNES_STOL:g}; bisection to {BISECT_RTOL:g} relative; Ogden "
                          f"delta {OGDEN_DELTA:g}",
            "physics_differences": "the torsional (u_Theta) family of n = 0 is not "
                                   "included (it decouples from (u_R, u_Z, phi) at n = 0); "
                                   "otherwise none",
        },
        "check": {"atol": 2.0 * worst,
                  "reason": "twice the largest change of v_cr between the two meshes ("
                            + "; ".join(notes) + ")"},
    }
    (out / "adapter.json").write_text(json.dumps(meta, indent=1))
    print(f"done in {time.perf_counter() - t0:.1f} s: " + "; ".join(notes))


if __name__ == "__main__":
    main()
