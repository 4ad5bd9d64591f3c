"""scikit-fem adapter of mms_electroelastic: the manufactured solution of compressible
nonlinear electro-elasticity, the observed order of convergence of the requested quantity
for Lagrange degrees 1, 2, 3.

    python peers/run.py scikit-fem mms_electroelastic --label nh-u-L2 [-- --quantity u_L2_order]
    python peers/scikit-fem/adapter.py mms_electroelastic --out DIR       # by hand

The physics (scikit-fem Basis / BilinearForm / LinearForm on Lagrange triangles, the
first Piola stress and the Lagrangian displacement written out from the page, the tangent
by central differences, Newton from the linearised problem, Dirichlet data and the
manufactured loads from the page's formula strings, errors with a quadrature exact to
degree 2p + 4) is the repository's clean room ``verification/cleanroom/mms.py`` (written
from the problem page with numpy and scikit-fem only; loaded here by its path, so the peer
venv needs nothing from debench). This adapter runs it on h = 1/8 .. 1/64 and fits the
order over the finest three levels (least squares of log error against log h, the page's
definition).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import _common
import numpy as np
import skfem

PROBLEM = "mms_electroelastic"
CLEAN_ROOM = Path(__file__).resolve().parents[2] / "verification" / "cleanroom" / "mms.py"
LEVELS = (8, 16, 32, 64)
DEGREES = (1, 2, 3)
FINEST = 3
QUANTITIES = {"u_L2_order": "u_L2", "u_H1_order": "u_H1", "phi_L2_order": "phi_L2",
              "phi_H1_order": "phi_H1"}




def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    extra = argparse.ArgumentParser(add_help=False)
    extra.add_argument("--quantity", default="u_L2_order", choices=sorted(QUANTITIES))
    extra.add_argument("--material", default="neo_hookean", choices=("neo_hookean", "gent"))
    own, rest = extra.parse_known_args(argv)
    a = _common.arguments(PROBLEM, rest)
    _common.problem_json(a.problem_json)
    cr = _common.load_clean_room(CLEAN_ROOM, "cleanroom_mms")
    column = QUANTITIES[own.quantity]
    t0 = time.perf_counter()
    orders, notes = [], []
    for p in DEGREES:
        rows = [cr.solve_mms(own.material, p, n) for n in LEVELS]
        fit = rows[-FINEST:]
        orders.append(float(np.polyfit(np.log([r["h"] for r in fit]),
                                       np.log([r[column] for r in fit]), 1)[0]))
        notes.append(f"P{p}: " + ", ".join(f"h 1/{n} {r[column]:.6e}"
                                           for n, r in zip(LEVELS, rows, strict=True)))
        print(f"{notes[-1]}; {own.quantity} {orders[-1]:.4f} "
              f"({time.perf_counter() - t0:.1f} s)", flush=True)
    _common.write_results(a.out, f"degree [1],{own.quantity} [1]",
                          [(p, o) for p, o in zip(DEGREES, orders, strict=True)])
    _common.write_adapter_json(a.out, quantity=own.quantity, method={
        "description": "plane-strain displacement-potential finite-element model of the "
                       f"manufactured problem ({own.material}, kappa = 10"
                       + (", Jm = 50" if own.material == "gent" else "")
                       + "): first Piola stress and Lagrangian displacement written out from "
                       "the page, the manufactured body force, charge and Dirichlet data "
                       "from the formula strings of reference/mms_electroelastic_formulas.json",
        "discretisation": "Lagrange P1, P2, P3 triangles (skfem ElementTriP1..P3) for u and "
                          "phi on MeshTri.init_tensor (n x n squares cut in two); "
                          "quadrature exact to degree 2p + 4 for residual and errors",
        "mesh_or_resolution": f"h = 1/n, n = {', '.join(map(str, LEVELS))}; order fitted "
                              f"over the finest {FINEST}; errors {column}: "
                              + "; ".join(notes),
        "solver": "Newton (tangent by central differences of the stress at the quadrature "
                  "points) from the problem linearised at the undeformed state, scipy "
                  "sparse direct solves",
        "tolerances": "Newton: free residual <= 1e-11 x its first value",
        "physics_differences": "none"},
        check=None, code_version=skfem.__version__)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
