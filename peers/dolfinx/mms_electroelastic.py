"""DOLFINx adapter: mms_electroelastic, the manufactured solution of compressible nonlinear
electro-elasticity (observed orders of convergence of u and phi, degrees 1, 2, 3).

Written as a DOLFINx user writes it, from the problem page alone
(``debench problems mms_electroelastic --markdown``) and the formula strings the page points
to (``reference/mms_electroelastic_formulas.json``, Python syntax pasted into UFL), with no
debench code:

* plane strain on the unit square, triangles of ``dolfinx.mesh.create_unit_square``
  (n x n squares, each cut in two), h = 1/n for n = 8, 16, 32, 64;
* mixed unknowns w = (u, phi) in one Lagrange space of degree p (vector displacement,
  scalar potential);
* the electric enthalpy in UFL, F = I + grad u embedded in 3D with F_33 = 1,
  Omega = W(F) - 1/2 J C^-1 : (E x E), E = -grad phi (normalised: mu = eps = 1), W the
  compressible neo-Hookean 1/2 (J^(-2/3) I1 - 3) + kappa/2 (J - 1)^2 or the Gent
  -Jm/2 ln(1 - (J^(-2/3) I1 - 3)/Jm) + kappa/2 (J - 1)^2 (kappa = 10, Jm = 50);
  Pi = int (Omega - b.u + q phi) dx with the manufactured body force b and charge q of the
  formula file; residual and tangent by ufl.derivative;
* Dirichlet data u = u_exact, phi = phi_exact on the whole boundary (interpolated into the
  Lagrange space: basix's default nodes, GLL-warped from degree 3 on, where scikit-fem's
  are equispaced; the P3 errors therefore differ from scikit-fem's by ~0.1 % and the P3
  order by 7.5e-4, while with ``lagrange_variant=equispaced`` they agree to every printed
  digit, 1.169339e-06 and 6.772908e-08 at n = 8 and 16, measured; P1 and P2 nodes
  coincide);
* PETSc SNES (Newton with backtracking line search, MUMPS LU) from zero in the interior;
* errors ||u_h - u||_L2, ||grad(u_h - u)||_L2, and the same for phi, with quadrature of
  degree 2p + 4 against the exact fields and gradients of the formula file; the observed
  order is the least-squares slope of log(error) against log(h) over the finest three
  levels (the page's definition).

``results.csv``: the degree and the observed order of the requested quantity; the whole
error table is in the submission's method notes.
"""

from __future__ import annotations  # noqa: I001 - dolfinx_solver must precede dolfinx

import argparse
import json
import math
import time
from pathlib import Path

import dolfinx_solver  # the wheel's package first: it loads MPI ahead of dolfinx and PETSc
import dolfinx
import dolfinx.fem.petsc
import numpy as np
import ufl
from mpi4py import MPI

FORMULAS = Path(__file__).resolve().parents[2] / "reference" / "mms_electroelastic_formulas.json"
LEVELS = (8, 16, 32, 64)
DEGREES = (1, 2, 3)
FINEST = 3
PARAMETERS = {"kappa": 10.0, "Jm": 50.0}
QUANTITIES = {"u_L2_order": ("u", "L2"), "u_H1_order": ("u", "H1"),
              "phi_L2_order": ("phi", "L2"), "phi_H1_order": ("phi", "H1")}
SNES_RTOL, SNES_ATOL = 1e-12, 1e-14
ERRORS = ("u_L2", "u_H1", "phi_L2", "phi_H1")


def exact_fields(case: dict, x):
    """u, grad u, phi, grad phi, b, q of a formula-file case as UFL expressions of the
    spatial coordinate ``x`` (the assignments evaluated in order, then the outputs)."""
    ns = {"X": x[0], "Y": x[1], "sin": ufl.sin, "cos": ufl.cos, "pi": math.pi,
          **{k: PARAMETERS[k] for k in case["parameters"]}}
    py = case["python"]
    for name, expr in py["assignments"]:
        ns[name] = eval(expr, {}, ns)  # noqa: S307 - the problem's own formula strings

    def ev(e):
        return eval(e, {}, ns)  # noqa: S307

    return {"u": ufl.as_vector([ev(e) for e in py["u"]]),
            "grad_u": ufl.as_matrix([[ev(e) for e in row] for row in py["grad_u"]]),
            "phi": ev(py["phi"]),
            "grad_phi": ufl.as_vector([ev(e) for e in py["grad_phi"]]),
            "b": ufl.as_vector([ev(e) for e in py["b"]]), "q": ev(py["q"])}


def solve(case: dict, material: str, degree: int, n: int) -> dict:
    """One level: the errors of u and phi in L2 and the H1 seminorm, the dofs, the Newton
    iterations."""
    import basix.ufl

    mesh = dolfinx.mesh.create_unit_square(MPI.COMM_SELF, n, n,
                                           dolfinx.mesh.CellType.triangle)
    cell = mesh.basix_cell()
    me = basix.ufl.mixed_element([basix.ufl.element("Lagrange", cell, degree, shape=(2,)),
                                  basix.ufl.element("Lagrange", cell, degree)])
    W = dolfinx.fem.functionspace(mesh, me)
    w = dolfinx.fem.Function(W)
    u, phi = ufl.split(w)
    ex = exact_fields(case, ufl.SpatialCoordinate(mesh))
    dx = ufl.Measure("dx", domain=mesh, metadata={"quadrature_degree": 2 * degree + 4})
    g = ufl.grad(u)
    F = ufl.as_matrix([[1 + g[0, 0], g[0, 1], 0], [g[1, 0], 1 + g[1, 1], 0], [0, 0, 1]])
    C = F.T * F
    J = ufl.det(F)
    I1bar = J ** (-2.0 / 3.0) * ufl.tr(C)
    kappa = PARAMETERS["kappa"]
    if material == "neo_hookean":
        Wmech = 0.5 * (I1bar - 3) + 0.5 * kappa * (J - 1) ** 2
    else:
        Jm = PARAMETERS["Jm"]
        Wmech = -0.5 * Jm * ufl.ln(1 - (I1bar - 3) / Jm) + 0.5 * kappa * (J - 1) ** 2
    E = ufl.as_vector([-phi.dx(0), -phi.dx(1), 0])
    Omega = Wmech - 0.5 * J * ufl.inner(ufl.inv(C) * E, E)
    Pi = (Omega - ufl.dot(ex["b"], u) + ex["q"] * phi) * dx
    R = ufl.derivative(Pi, w, ufl.TestFunction(W))
    K = ufl.derivative(R, w, ufl.TrialFunction(W))

    fdim = mesh.topology.dim - 1
    mesh.topology.create_connectivity(fdim, mesh.topology.dim)
    facets = dolfinx.mesh.exterior_facet_indices(mesh.topology)
    bcs = []
    for sub, field in ((W.sub(0), "u"), (W.sub(1), "phi")):
        V, _ = sub.collapse()
        data = dolfinx.fem.Function(V)
        data.interpolate(dolfinx.fem.Expression(ex[field], V.element.interpolation_points))
        dofs = dolfinx.fem.locate_dofs_topological((sub, V), fdim, facets)
        bcs.append(dolfinx.fem.dirichletbc(data, dofs, sub))
    problem = dolfinx.fem.petsc.NonlinearProblem(
        R, w, bcs=bcs, J=K, petsc_options_prefix=f"mms_{degree}_{n}_",
        petsc_options={"snes_type": "newtonls", "snes_linesearch_type": "bt",
                       "snes_rtol": SNES_RTOL, "snes_atol": SNES_ATOL, "snes_stol": 0.0,
                       "snes_max_it": 50, "ksp_type": "preonly", "pc_type": "lu",
                       "pc_factor_mat_solver_type": "mumps"})
    problem.solve()
    reason = problem.solver.getConvergedReason()
    if reason <= 0 or not np.all(np.isfinite(w.x.array)):
        raise RuntimeError(f"SNES did not converge (degree {degree}, n {n}, reason {reason})")

    def norm(expr):
        return math.sqrt(dolfinx.fem.assemble_scalar(dolfinx.fem.form(ufl.inner(expr, expr)
                                                                       * dx)))

    return {"h": 1.0 / n, "ndof": W.dofmap.index_map.size_local * W.dofmap.index_map_bs,
            "newton": problem.solver.getIterationNumber(),
            "u_L2": norm(u - ex["u"]), "u_H1": norm(ufl.grad(u) - ex["grad_u"]),
            "phi_L2": norm(phi - ex["phi"]), "phi_H1": norm(ufl.grad(phi) - ex["grad_phi"])}


def order(rows, column) -> float:
    """The least-squares slope of log(error) against log(h) over the finest levels."""
    rows = sorted(rows, key=lambda r: -r["h"])[-FINEST:]
    return float(np.polyfit(np.log([r["h"] for r in rows]),
                            np.log([r[column] for r in rows]), 1)[0])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--problem-json", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--label", default="default")
    ap.add_argument("--quantity", default="u_L2_order", choices=sorted(QUANTITIES))
    ap.add_argument("--material", default="neo_hookean", choices=("neo_hookean", "gent"))
    a = ap.parse_args()
    json.loads(Path(a.problem_json).read_text())          # the page the adapter answers
    case = json.loads(FORMULAS.read_text())["cases"][f"plane_strain_{a.material}"]
    column = "_".join(QUANTITIES[a.quantity])
    t0 = time.perf_counter()
    table, orders = [], []
    for degree in DEGREES:
        rows = [solve(case, a.material, degree, n) for n in LEVELS]
        table += [{"degree": degree, **r} for r in rows]
        orders.append(order(rows, column))
        levels = "; ".join(f"h 1/{round(1 / r['h'])} {r['ndof']} dofs {r['newton']} Newton: "
                           + ", ".join(f"{k} {r[k]:.4e}" for k in ERRORS) for r in rows)
        print(f"P{degree}: {levels}; {a.quantity} {orders[-1]:.4f} "
              f"({time.perf_counter() - t0:.1f} s)", flush=True)
    out = Path(a.out)
    tmp = out / ".results.csv.tmp"
    with tmp.open("w") as fh:
        fh.write(f"degree [1],{a.quantity} [1]\n")
        for degree, o in zip(DEGREES, orders, strict=True):
            fh.write(f"{degree},{o!r}\n")
    tmp.replace(out / "results.csv")
    errors = "; ".join(f"P{r['degree']} h 1/{round(1 / r['h'])}: {column} {r[column]:.6e}"
                       for r in table)
    meta = {
        "quantity": a.quantity,
        "code": {"name": "DOLFINx", "version": dolfinx.__version__,
                 "commit_or_release": f"dolfinx-solver-real {dolfinx_solver.__version__} "
                                      f"(packages the DOLFINx {dolfinx_solver.RELEASE} release)",
                 "url": "https://github.com/FEniCS/dolfinx", "license": "LGPL-3.0-or-later"},
        "method": {
            "description": "plane-strain mixed displacement-potential model of the "
                           f"manufactured problem ({a.material}, kappa = 10"
                           + (", Jm = 50" if a.material == "gent" else "")
                           + "): UFL electric enthalpy minus b.u plus q phi, the formula "
                           "strings of reference/mms_electroelastic_formulas.json evaluated "
                           "as UFL expressions; ufl.derivative residual and tangent; "
                           "Dirichlet data u, phi exact on the whole boundary",
            "discretisation": "Lagrange P1, P2, P3 (vector displacement and potential) on "
                              "triangles of create_unit_square (n x n squares cut in two); "
                              "quadrature degree 2p + 4 for the residual and the errors",
            "mesh_or_resolution": f"h = 1/n, n = {', '.join(map(str, LEVELS))}; order fitted "
                                  f"over the finest {FINEST}; errors: {errors}",
            "solver": "PETSc SNES newtonls with backtracking line search (bt) from zero in "
                      "the interior, MUMPS LU",
            "tolerances": f"snes_rtol {SNES_RTOL:g}, snes_atol {SNES_ATOL:g}",
            "physics_differences": "none",
        },
    }
    (out / "adapter.json").write_text(json.dumps(meta, indent=1))
    print(f"done in {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main()
