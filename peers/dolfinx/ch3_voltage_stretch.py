"""DOLFINx adapter: ch3_voltage_stretch, the pre-stretched circular actuator (membrane).

Written as a DOLFINx user writes it, from the problem page alone
(``debench problems ch3_voltage_stretch --markdown``), with no debench code:

* the passive annulus R_A <= R <= R_B (lengths in units of R_A) is an axisymmetric
  membrane: the unknown is the radial displacement u(R), r = R + u, l1 = dr/dR,
  l2 = r/R, and the total energy per 2 pi H mu is Pi = int W(l1, l2) R dR with the
  incompressible plane-stress Gent energy W = -(Jm/2) ln(1 - (l1^2 + l2^2 + l1^-2 l2^-2 - 3)/Jm);
  the weak form is its Gateaux derivative (ufl.derivative), the Jacobian its second,
  solved by PETSc SNES (Newton, MUMPS LU) through
  ``dolfinx.fem.petsc.NonlinearProblem``. Stationarity of Pi is the membrane balance
  d(R T1)/dR = T2 of the spec;
* stretch control: r(R_A) = lambda_a R_A and r(R_B) = lamP R_B are Dirichlet conditions,
  lambda_a is stepped from lamP along the stored grid (secant predictor, step halving on
  a failed solve);
* the interface stress T1_B(R_A) is the reaction of the FE solution: with w_A the P2 basis
  function of the node R = R_A, R_A T1_B(R_A) = -F(u; w_A) (F the residual form), the
  variationally consistent reaction;
* circle A is homogeneous and equibiaxial (spec, model.equations): its radial balance
  gives Phibar^2 = (s(lambda_a) - lambda_a T1_B(R_A)) / (lambda_a^4 K(lambda_a)) with
  s and K of the spec; points where K <= 0 are outside the domain and not written.

Resolution: P2 Lagrange on a mesh geometrically graded towards R_A; the whole curve set is
solved on the mesh and on its uniform refinement (twice the cells); the finer values are
written and the largest change between the two is stated as the accuracy (x 2).
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

#: Newton (full steps) stops when its update is below 1e-10 of the solution norm
#: (quadratic convergence: the state is then exact to round-off, ~1e-15 relative), or the
#: residual below 1e-12 relative / 1e-10 absolute. The residual's round-off floor grows
#: with the stretch (measured: 1e-13 at lambda_a = 1.1, 1e-11 at 5 with lamP = 1.1), so a
#: residual test alone cannot be met everywhere; the update test can.
SNES_RTOL, SNES_ATOL, SNES_STOL = 1e-12, 1e-10, 1e-10


def graded_interval(n: int, r0: float, r1: float, ratio: float):
    """An interval mesh of n cells on [r0, r1], cell sizes growing geometrically by
    ``ratio`` overall from r0 (fine at the interface) to r1."""
    mesh = dolfinx.mesh.create_interval(MPI.COMM_SELF, n, [0.0, 1.0])
    s = mesh.geometry.x[:, 0].copy()
    q = ratio ** (1.0 / max(n - 1, 1))
    # cumulative geometric spacing mapped from s in [0, 1]
    mapped = (q ** (s * n) - 1.0) / (q ** n - 1.0) if abs(q - 1.0) > 1e-14 else s
    mesh.geometry.x[:, 0] = r0 + (r1 - r0) * mapped
    return mesh


class Annulus:
    """The annulus boundary-value problem on one mesh, for one pre-stretch."""

    def __init__(self, cells: int, radius_ratio: float, Jm: float, grading: float):
        self.rb = radius_ratio
        self.mesh = graded_interval(cells, 1.0, radius_ratio, grading)
        self.V = dolfinx.fem.functionspace(self.mesh, ("Lagrange", 2))
        self.u = dolfinx.fem.Function(self.V)
        self.u_prev = dolfinx.fem.Function(self.V)
        R = ufl.SpatialCoordinate(self.mesh)[0]
        l1 = 1.0 + self.u.dx(0)
        l2 = 1.0 + self.u / R
        I1 = l1**2 + l2**2 + 1.0 / (l1**2 * l2**2)
        W = -(Jm / 2.0) * ufl.ln(1.0 - (I1 - 3.0) / Jm)
        Pi = W * R * ufl.dx(metadata={"quadrature_degree": 8})
        v = ufl.TestFunction(self.V)
        self.F = ufl.derivative(Pi, self.u, v)
        J = ufl.derivative(self.F, self.u, ufl.TrialFunction(self.V))
        fdim = 0
        left = dolfinx.mesh.locate_entities_boundary(self.mesh, fdim,
                                                     lambda x: np.isclose(x[0], 1.0))
        right = dolfinx.mesh.locate_entities_boundary(self.mesh, fdim,
                                                      lambda x: np.isclose(x[0], radius_ratio))
        self.dofs_a = dolfinx.fem.locate_dofs_topological(self.V, fdim, left)
        self.dofs_b = dolfinx.fem.locate_dofs_topological(self.V, fdim, right)
        self.ua = dolfinx.fem.Constant(self.mesh, 0.0)
        self.ub = dolfinx.fem.Constant(self.mesh, 0.0)
        bcs = [dolfinx.fem.dirichletbc(self.ua, self.dofs_a, self.V),
               dolfinx.fem.dirichletbc(self.ub, self.dofs_b, self.V)]
        self.problem = dolfinx.fem.petsc.NonlinearProblem(
            self.F, self.u, bcs=bcs, J=J, petsc_options_prefix="annulus_",
            petsc_options={"snes_type": "newtonls", "snes_linesearch_type": "basic",
                           "snes_rtol": SNES_RTOL, "snes_atol": SNES_ATOL,
                           "snes_stol": SNES_STOL, "snes_max_it": 40,
                           "ksp_type": "preonly", "pc_type": "lu",
                           "pc_factor_mat_solver_type": "mumps"})
        # the reaction at R_A: the residual tested with the basis function of that node
        self.w_a = dolfinx.fem.Function(self.V)
        self.w_a.x.array[self.dofs_a] = 1.0
        self.reaction = dolfinx.fem.form(ufl.replace(self.F, {v: self.w_a}))
        self.iterations = 0

    def set_homogeneous(self, lamP: float):
        """The pre-stretched state u = (lamP - 1) R (exact for lambda_a = lamP)."""
        self.u.interpolate(lambda x: (lamP - 1.0) * x[0])

    def solve(self, lam_a: float, lamP: float) -> bool:
        self.ua.value = lam_a - 1.0
        self.ub.value = (lamP - 1.0) * self.rb
        self.problem.solve()
        reason = self.problem.solver.getConvergedReason()
        self.iterations += self.problem.solver.getIterationNumber()
        ok = reason > 0 and np.all(np.isfinite(self.u.x.array))
        return bool(ok)

    def interface_T1(self) -> float:
        """T1_B(R_A) (per mu) from the reaction: R_A T1 = -F(u; w_a), R_A = 1."""
        return -dolfinx.fem.assemble_scalar(self.reaction)


def trace(ann: Annulus, lamP: float, lam_grid: np.ndarray) -> np.ndarray:
    """T1_B(R_A) at every stretch of lam_grid (increasing from lamP), by continuation."""
    ann.set_homogeneous(lamP)
    out = np.empty(lam_grid.size)
    hist = []  # (lam, u array) of the last two converged states
    lam_now = lamP
    ok = ann.solve(lam_now, lamP)
    if not ok:
        raise RuntimeError(f"annulus did not converge at lamP = {lamP}")
    hist.append((lam_now, ann.u.x.array.copy()))
    for i, target in enumerate(lam_grid):
        while lam_now < target:
            step = target - lam_now
            for _ in range(30):
                lam_try = lam_now + step
                if len(hist) == 2:  # secant predictor in the stretch
                    (l0, u0), (l1, u1) = hist
                    ann.u.x.array[:] = u1 + (u1 - u0) * (lam_try - l1) / (l1 - l0)
                else:
                    ann.u.x.array[:] = hist[-1][1]
                if ann.solve(lam_try, lamP):
                    break
                step /= 2.0
            else:
                raise RuntimeError(f"annulus continuation stalled at lambda_a = {lam_now} "
                                   f"(lamP = {lamP})")
            lam_now = lam_try
            hist = (hist + [(lam_now, ann.u.x.array.copy())])[-2:]
        out[i] = ann.interface_T1()
    return out


def phibar(lam: np.ndarray, T1: np.ndarray, c: float, Jm: float) -> np.ndarray:
    """Eq. (3.30) with the interface balance (3.32), as the spec states them."""
    s = (lam**2 - lam**-4) / (1.0 - (2.0 * lam**2 + lam**-4 - 3.0) / Jm)
    K = 1.0 + c * (2.5 * lam - 2.0)
    return np.sqrt((s - lam * T1) / (lam**4 * K))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--problem-json", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--label", default="default")
    ap.add_argument("--cells", type=int, default=96, help="cells of the coarser mesh")
    ap.add_argument("--grading", type=float, default=30.0,
                    help="ratio of the largest to the smallest cell")
    a = ap.parse_args()
    doc = json.loads(Path(a.problem_json).read_text())
    spec, ref = doc["spec"], doc["reference"]["phibar"]
    par = spec["parameters"]
    Jm, ratio = float(par["Jm"]["value"]), float(par["radius_ratio"]["value"])
    lamPs = [float(x) for x in ref["coords"]["lamP"]]
    cs = [float(x) for x in ref["coords"]["c"]]
    grid = np.asarray(ref["along"]["values"], dtype=float)  # (lamP, point)

    t0 = time.perf_counter()
    T1 = {}
    iters = {}
    for cells in (a.cells, 2 * a.cells):
        ann = Annulus(cells, ratio, Jm, a.grading)
        for i, lamP in enumerate(lamPs):
            lam = grid[i][np.isfinite(grid[i])]
            T1[cells, lamP] = trace(ann, lamP, lam)
        iters[cells] = ann.iterations
        print(f"P2, {cells} cells: {ann.iterations} Newton iterations, "
              f"{time.perf_counter() - t0:.1f} s", flush=True)
    rows, worst = [], 0.0
    for i, lamP in enumerate(lamPs):
        lam = grid[i][np.isfinite(grid[i])]
        for c in cs:
            K = 1.0 + c * (2.5 * lam - 2.0)
            keep = K > 0
            if not keep.any():
                continue
            fine = phibar(lam[keep], T1[2 * a.cells, lamP][keep], c, Jm)
            coarse = phibar(lam[keep], T1[a.cells, lamP][keep], c, Jm)
            if not np.all(np.isfinite(fine)):
                raise RuntimeError(f"Phibar^2 < 0 at lamP = {lamP}, c = {c}")
            worst = max(worst, float(np.max(np.abs(fine - coarse))))
            rows += [(lamP, c, x, y) for x, y in zip(lam[keep], fine, strict=True)]
    out = Path(a.out)
    with (out / "results.csv").open("w") as fh:
        fh.write("lamP [1],c [1],lambda_a [1],phibar [1]\n")
        for r in rows:
            fh.write(",".join(repr(float(x)) for x in r) + "\n")
    n1, n2 = a.cells, 2 * a.cells
    atol = 2.0 * worst
    meta = {
        "quantity": "phibar",
        "code": {"name": "DOLFINx", "version": dolfinx.__version__,
                 "commit_or_release": f"dolfinx-solver-real {dolfinx_solver.__version__} "
                                      f"(packages the DOLFINx {dolfinx_solver.RELEASE} release)",
                 "url": "https://github.com/FEniCS/dolfinx", "license": "LGPL-3.0-or-later"},
        "method": {
            "description": "axisymmetric membrane annulus in u(R) (UFL energy, "
                           "ufl.derivative residual and Jacobian), stretch control "
                           "r(R_A) = lambda_a R_A by a Dirichlet condition, T1_B(R_A) from "
                           "the variationally consistent reaction at R_A, circle A "
                           "homogeneous: Phibar^2 = (s - lambda_a T1_B)/(lambda_a^4 K) "
                           "(spec model.equations)",
            "discretisation": "Lagrange P2 on the annulus R_A <= R <= R_B; quadrature "
                              "degree 8",
            "mesh_or_resolution": f"interval mesh of {n2} cells geometrically graded "
                                  f"(largest/smallest cell {a.grading:g}) towards R_A; "
                                  f"checked against {n1} cells",
            "solver": "PETSc SNES newtonls (full Newton steps), MUMPS LU; "
                      "continuation in lambda_a along the stored grid with a secant "
                      "predictor and step halving",
            "tolerances": f"snes_rtol {SNES_RTOL:g}, snes_atol {SNES_ATOL:g}, snes_stol "
                          f"{SNES_STOL:g} (relative Newton update)",
            "physics_differences": "none (the consistent membrane balance of the spec; "
                                   "points with K <= 0 are outside the domain and not "
                                   "written)",
        },
        "check": {"atol": atol,
                  "reason": f"twice the largest change of Phibar between {n1} and {n2} "
                            f"P2 cells over every written point ({worst:.3g})"},
    }
    (out / "adapter.json").write_text(json.dumps(meta, indent=1))
    print(f"{len(rows)} points; largest change between {n1} and {n2} cells: {worst:.3g}; "
          f"{time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main()
