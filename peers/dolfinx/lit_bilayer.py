"""DOLFINx adapter: lit_bilayer, the plane-strain dielectric-elastomer bilayer strip bending
under voltage (tip deflection or tip rotation at the problem's voltages).

Written as a DOLFINx user writes it, from the problem page alone
(``debench problems lit_bilayer --markdown``), with no debench code:

* lengths in units of the total thickness H: the strip 0 <= x <= L/H = 10, 0 <= y <= 1, the
  passive layer below y = h_p = 1/2, the active layer above; mixed unknowns
  w = (u_x, u_y, phi) in one Lagrange space (vector displacement, scalar potential);
* stresses in units of mu, potentials in units of H sqrt(mu/eps): the top electrode's
  potential is v h_a with v the normalised voltage and h_a = 1/2;
* the energy written in UFL: plane strain F = I + grad u embedded in 3D with F_33 = 1,
  W = 1/2 (J^(-2/3) I1 - 3) + kappa/2 (J - 1)^2 (kappa = k/mu = 7748003.92/156000) in both
  layers, minus 1/2 J C^-1 : (E x E), E = -grad phi, in the active layer only (a cell tag
  restricts the measure); Pi = int W dx, residual and tangent by ufl.derivative;
* boundary conditions of the page: u_x = 0 on x = 0 (sliding clamp), u_y = 0 at the point
  (0, h_p); phi = 0 on the interface and at every potential dof of the passive layer (no
  field there), phi = v h_a on y = 1; the rest natural (traction free, insulated);
* continuation in v from 0 in steps of 0.025, each state by PETSc SNES (Newton with a
  backtracking line search, MUMPS LU) from the previous one;
* outputs from the vertex dofs at the free end's corners: w = u_y(L, 0) and
  theta = atan2(-(u_x(L, 1) - u_x(L, 0)), 1 + u_y(L, 1) - u_y(L, 0)).

Resolution: Lagrange Q_p on quadrilaterals, 20 columns x 2 rows per layer, graded
geometrically (ratio 0.2, ``levels`` layers) towards the free end of the interface; the
sequence (p, levels) = (3, 2), (4, 1), (4, 2) by default (``--sequence``; the curated
submissions ran 5:2, 6:1, 6:2), the last written, 3 x its largest change from the others
stated as its accuracy.
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

LENGTH, HP, KAPPA = 10.0, 0.5, 7748003.92 / 156000.0
NX, NY, RATIO = 20, 2, 0.2
STEP = 0.025
SAFETY = 3.0
UNITS = {"tip_deflection": "1", "tip_rotation": "rad"}


def graded(lo, hi, n, levels, at_lo, at_hi):
    x = np.linspace(lo, hi, n + 1)
    h = (hi - lo) / n
    inner = h * RATIO ** np.arange(levels, 0, -1)
    parts = [x] + ([lo + inner] if at_lo else []) + ([hi - inner] if at_hi else [])
    return np.unique(np.concatenate(parts))


def strip_mesh(levels):
    xs = graded(0.0, LENGTH, NX, levels, False, True)
    ys = np.concatenate([graded(0.0, HP, NY, levels, False, True),
                         graded(HP, 1.0, NY, levels, True, False)[1:]])
    mesh = dolfinx.mesh.create_rectangle(MPI.COMM_SELF, [[0.0, 0.0], [1.0, 1.0]],
                                         [xs.size - 1, ys.size - 1],
                                         dolfinx.mesh.CellType.quadrilateral)
    g = mesh.geometry.x
    # the unit square's vertices sit at i/nx, j/ny: map them onto the graded lines
    g[:, 0] = np.interp(g[:, 0], np.linspace(0, 1, xs.size), xs)
    g[:, 1] = np.interp(g[:, 1], np.linspace(0, 1, ys.size), ys)
    return mesh


def solve(voltages, degree, levels):
    import basix.ufl
    from petsc4py import PETSc

    mesh = strip_mesh(levels)
    cell = mesh.basix_cell()
    me = basix.ufl.mixed_element([basix.ufl.element("Lagrange", cell, degree, shape=(2,)),
                                  basix.ufl.element("Lagrange", cell, degree)])
    W = dolfinx.fem.functionspace(mesh, me)
    w = dolfinx.fem.Function(W)
    u, phi = ufl.split(w)
    tdim = mesh.topology.dim
    # cell tags: 1 the active layer
    ncells = mesh.topology.index_map(tdim).size_local
    mid = dolfinx.mesh.compute_midpoints(mesh, tdim, np.arange(ncells, dtype=np.int32))
    active = np.flatnonzero(mid[:, 1] > HP).astype(np.int32)
    tags = dolfinx.mesh.meshtags(mesh, tdim, active, np.ones_like(active))
    dx = ufl.Measure("dx", domain=mesh, subdomain_data=tags,
                     metadata={"quadrature_degree": 2 * degree + 2})
    g = ufl.grad(u)
    F = ufl.as_matrix([[1 + g[0, 0], g[0, 1], 0], [g[1, 0], 1 + g[1, 1], 0], [0, 0, 1]])
    C = F.T * F
    J = ufl.det(F)
    E = ufl.as_vector([-phi.dx(0), -phi.dx(1), 0])
    Wmech = 0.5 * (J ** (-2.0 / 3.0) * ufl.tr(C) - 3) + 0.5 * KAPPA * (J - 1) ** 2
    Welec = -0.5 * J * ufl.inner(ufl.inv(C) * E, E)
    Pi = Wmech * dx + Welec * dx(1)
    R = ufl.derivative(Pi, w, ufl.TestFunction(W))
    K = ufl.derivative(R, w, ufl.TrialFunction(W))

    fdim = tdim - 1
    V0, _ = W.sub(0).sub(0).collapse()
    V1, _ = W.sub(0).sub(1).collapse()
    Q, _ = W.sub(1).collapse()
    clamp = dolfinx.mesh.locate_entities_boundary(mesh, fdim, lambda x: np.isclose(x[0], 0))
    top = dolfinx.mesh.locate_entities_boundary(mesh, fdim, lambda x: np.isclose(x[1], 1))
    d_clamp = dolfinx.fem.locate_dofs_topological(W.sub(0).sub(0), fdim, clamp)
    d_pin = dolfinx.fem.locate_dofs_geometrical(
        (W.sub(0).sub(1), V1), lambda x: np.isclose(x[0], 0) & np.isclose(x[1], HP))
    d_ground = dolfinx.fem.locate_dofs_geometrical(
        (W.sub(1), Q), lambda x: x[1] <= HP + 1e-12)
    d_top = dolfinx.fem.locate_dofs_topological(W.sub(1), fdim, top)
    if len(d_pin[0]) != 1:
        raise RuntimeError(f"pin dof not found uniquely ({d_pin})")
    zero_y, zero_q = dolfinx.fem.Function(V1), dolfinx.fem.Function(Q)
    phi_top = dolfinx.fem.Constant(mesh, 0.0)
    bcs = [dolfinx.fem.dirichletbc(0.0, d_clamp, W.sub(0).sub(0)),
           dolfinx.fem.dirichletbc(zero_y, d_pin, W.sub(0).sub(1)),
           dolfinx.fem.dirichletbc(zero_q, d_ground, W.sub(1)),
           dolfinx.fem.dirichletbc(phi_top, d_top, W.sub(1))]
    problem = dolfinx.fem.petsc.NonlinearProblem(
        R, w, bcs=bcs, J=K, petsc_options_prefix="bilayer_",
        petsc_options={"snes_type": "newtonls", "snes_linesearch_type": "bt",
                       "snes_rtol": 1e-10, "snes_atol": 1e-12, "snes_stol": 0.0,
                       "snes_max_it": 50, "ksp_type": "preonly", "pc_type": "lu",
                       "pc_factor_mat_solver_type": "mumps"})

    def corner(sub, space, x, y):
        d = dolfinx.fem.locate_dofs_geometrical(
            (sub, space), lambda p: np.isclose(p[0], x) & np.isclose(p[1], y))
        return int(d[0][0])

    ux_b, ux_t = (corner(W.sub(0).sub(0), V0, LENGTH, y) for y in (0.0, 1.0))
    uy_b, uy_t = (corner(W.sub(0).sub(1), V1, LENGTH, y) for y in (0.0, 1.0))
    out, newton, v0 = [], 0, 0.0
    for v in voltages:
        n = max(1, math.ceil((v - v0) / STEP - 1e-12))
        for vi in np.linspace(v0, v, n + 1)[1:]:
            phi_top.value = vi * (1.0 - HP)
            problem.solve()
            reason = problem.solver.getConvergedReason()
            newton += problem.solver.getIterationNumber()
            if reason <= 0 or not np.all(np.isfinite(w.x.array)):
                raise RuntimeError(f"SNES did not converge at v = {vi} (reason {reason})")
        v0 = v
        a = w.x.array
        dxx, dyy = a[ux_t] - a[ux_b], 1.0 + a[uy_t] - a[uy_b]
        out.append((float(a[uy_b]), math.atan2(-dxx, dyy)))
    ndofs = W.dofmap.index_map.size_local * W.dofmap.index_map_bs
    del PETSc
    return np.array(out), ndofs, newton


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--problem-json", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--label", default="default")
    ap.add_argument("--quantity", default="tip_deflection", choices=sorted(UNITS))
    ap.add_argument("--sequence", default="3:2,4:1,4:2",
                    help="degree:levels pairs; the last is written")
    a = ap.parse_args()
    doc = json.loads(Path(a.problem_json).read_text())
    voltages = [float(x) for x in doc["spec"]["parameters"]["v"]["value"]]
    seq = [tuple(int(t) for t in s.split(":")) for s in a.sequence.split(",")]
    col = 0 if a.quantity == "tip_deflection" else 1
    t0 = time.perf_counter()
    vals, notes = [], []
    for degree, levels in seq:
        res, ndofs, newton = solve(voltages, degree, levels)
        vals.append(res[:, col])
        notes.append(f"Q{degree} L{levels}: " + ", ".join(f"{x:.9f}" for x in res[:, col]))
        print(f"Q{degree} levels {levels}: {ndofs} dofs, {newton} Newton iterations, "
              f"{time.perf_counter() - t0:.1f} s: w = {res[:, 0].tolist()}, "
              f"theta = {res[:, 1].tolist()}", flush=True)
    vals = np.array(vals)
    err = SAFETY * float(np.max(np.abs(vals[-1] - vals[:-1])))
    out = Path(a.out)
    with (out / "results.csv").open("w") as fh:
        fh.write(f"v [1],{a.quantity} [{UNITS[a.quantity]}]\n")
        for v, x in zip(voltages, vals[-1], strict=True):
            fh.write(f"{v!r},{float(x)!r}\n")
    degree, levels = seq[-1]
    meta = {
        "quantity": a.quantity,
        "code": {"name": "DOLFINx", "version": dolfinx.__version__,
                 "commit_or_release": f"dolfinx-solver-real {dolfinx_solver.__version__} "
                                      f"(packages the DOLFINx {dolfinx_solver.RELEASE} release)",
                 "url": "https://github.com/FEniCS/dolfinx", "license": "LGPL-3.0-or-later"},
        "method": {
            "description": "plane-strain mixed displacement-potential model of the bilayer "
                           "strip (UFL electric enthalpy, the electric part on the active "
                           "layer's cell tag; ufl.derivative residual and tangent); sliding "
                           "clamp u_x = 0 at x = 0 with u_y(0, h_p) = 0; continuation in v "
                           "in steps of 0.025",
            "discretisation": f"Lagrange Q{degree} (vector displacement) and Q{degree} "
                              f"(potential) on quadrilaterals; quadrature degree "
                              f"{2 * degree + 2}",
            "mesh_or_resolution": f"{NX} columns x {NY} rows per layer, {levels} geometric "
                                  f"layers (ratio {RATIO:g}) towards the free end of the "
                                  f"interface; sequence " + "; ".join(notes),
            "solver": "PETSc SNES newtonls with backtracking line search (bt), MUMPS LU",
            "tolerances": "snes_rtol 1e-10, snes_atol 1e-12",
            "physics_differences": "none",
        },
        "check": {"atol": err,
                  "reason": f"{SAFETY:g} x the largest change of the written values from the "
                            "other discretisations of the sequence (" + "; ".join(notes)
                            + ")"},
    }
    (out / "adapter.json").write_text(json.dumps(meta, indent=1))
    print(f"done in {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main()
