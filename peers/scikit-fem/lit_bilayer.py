"""scikit-fem adapter of lit_bilayer: the plane-strain bilayer strip bending under voltage,
its tip deflection or tip rotation at the problem's voltages.

    python peers/run.py scikit-fem lit_bilayer --label p4 [-- --quantity tip_rotation]
    python peers/scikit-fem/adapter.py lit_bilayer --out DIR       # by hand

The physics (scikit-fem Basis / BilinearForm / LinearForm on Lagrange triangles, the
electric enthalpy's gradient written out from the page, its Hessian by complex step,
Newton with a backtracking line search, continuation in the voltage) is the repository's
clean room ``verification/cleanroom/bilayer.py`` (written from the problem page with numpy,
scipy and scikit-fem only; loaded here by its path, so the peer venv needs nothing from
debench). This adapter runs it along a p- and grading sequence and reports the top
discretisation, its stated error from the sequence.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import _common
import numpy as np
import skfem

PROBLEM = "lit_bilayer"
CLEAN_ROOM = Path(__file__).resolve().parents[2] / "verification" / "cleanroom" / "bilayer.py"
#: the sequence (order, geometric layers): the last is reported; the others are its p-step
#: (same mesh, order below) and its grading step (one geometric layer less)
SEQUENCE = ((3, 2), (4, 1), (4, 2))
#: Roache's grid-convergence safety factor for a two-direction estimate with two orders
SAFETY = 3.0
UNITS = {"tip_deflection": "1", "tip_rotation": "rad"}




def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    extra = argparse.ArgumentParser(add_help=False)
    extra.add_argument("--quantity", default="tip_deflection", choices=sorted(UNITS))
    own, rest = extra.parse_known_args(argv)
    a = _common.arguments(PROBLEM, rest)
    doc = _common.problem_json(a.problem_json)
    voltages = ([float(x) for x in doc["spec"]["parameters"]["v"]["value"]] if doc
                else [0.05, 0.1, 0.15, 0.2, 0.25, 0.3])
    b = _common.load_clean_room(CLEAN_ROOM, "cleanroom_bilayer")
    runs = []
    for order, levels in SEQUENCE:
        t0 = time.perf_counter()
        r = b.solve(voltages, order=order, levels=levels)
        runs.append(r)
        print(f"P{order} levels {levels}: {r.ndofs} dofs, {r.newton_iterations} Newton "
              f"iterations, {time.perf_counter() - t0:.1f} s; w = {r.tip_deflection.tolist()}"
              f"; theta = {r.tip_rotation.tolist()}", flush=True)
    q = own.quantity
    vals = np.array([getattr(r, q) for r in runs])
    err = SAFETY * np.max(np.abs(vals[-1] - vals[:-1]), axis=0)
    _common.write_results(a.out, f"v [1],{q} [{UNITS[q]}]",
                          list(zip(voltages, vals[-1].tolist(), strict=True)))
    steps = "; ".join(f"P{o} L{lv}: " + ", ".join(f"{x:.9f}" for x in row)
                      for (o, lv), row in zip(SEQUENCE, vals, strict=True))
    p, lv = SEQUENCE[-1]
    _common.write_adapter_json(a.out, quantity=q, method={
        "description": "plane-strain displacement-potential finite-element model of the "
                       "bilayer strip (electric enthalpy: compressible neo-Hookean in both "
                       "layers, -1/2 J |F^-T Grad phi|^2 in the active layer; the passive "
                       "layer's potential held at 0); sliding clamp u_X = 0 at X = 0 with "
                       "u_Y(0, H/2) = 0; continuation in v (steps 0.025) with Newton",
        "discretisation": f"Lagrange P{p} triangles (skfem ElementTriP{p}) for u_X, u_Y, "
                          f"phi; quadrature order {2 * p}; gradient of the enthalpy written "
                          "out, its Hessian by complex step (exact to round-off)",
        "mesh_or_resolution": f"tensor mesh 20 columns x 2 rows per layer, each rectangle "
                              f"cut in two; {lv} geometric layers (ratio 0.2) at the free end "
                              f"X = L and beside the interface; sequence {steps}",
        "solver": "Newton with backtracking on the residual norm (scipy spsolve), "
                  "continuation from the linear extrapolation of the two last states",
        "tolerances": "Newton: free residual <= 1e-10 x its value at the step's start",
        "physics_differences": "none"},
        check={"atol": float(np.max(err)),
               "reason": f"{SAFETY:g} x the larger change of the reported values from "
                         f"their p-step and their grading step ({steps})"},
        code_version=skfem.__version__)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
