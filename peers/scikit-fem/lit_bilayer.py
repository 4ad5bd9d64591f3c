"""scikit-fem adapter of lit_bilayer: the plane-strain bilayer strip bending under voltage,
its tip deflection or tip rotation at the problem's voltages.

    python peers/run.py scikit-fem lit_bilayer --label p4 [-- --quantity tip_rotation]
    python peers/run.py scikit-fem lit_bilayer --label q8 -- --element q8 [--quantity ...]
    python peers/scikit-fem/adapter.py lit_bilayer --out DIR       # by hand

The physics (scikit-fem Basis / BilinearForm / LinearForm on Lagrange triangles, the
electric enthalpy's gradient written out from the page, its Hessian by complex step,
Newton with a backtracking line search, continuation in the voltage) is the repository's
clean room ``verification/cleanroom/bilayer.py`` (written from the problem page with numpy,
scipy and scikit-fem only; loaded here by its path, so the peer venv needs nothing from
debench). This adapter runs it along a p- and grading sequence and reports the top
discretisation, its stated error from the sequence. ``--element q8`` runs the clean room's
high-order quadrilaterals instead (``verification/cleanroom/bilayer_quad.py``: scikit-fem's
hierarchical ``ElementQuadP`` on a mesh graded towards the singular point (L, 1/2)),
along Q7 and Q8 on 12 x 2 elements per layer.
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
CLEAN_ROOMS = Path(__file__).resolve().parents[2] / "verification" / "cleanroom"
CLEAN_ROOM = CLEAN_ROOMS / "bilayer.py"
#: the sequence (order, geometric layers) per element family: the last is reported; the
#: others are its p-step (same mesh, order below) and its grading step (one geometric
#: layer less)
SEQUENCES = {"p4": ((3, 2), (4, 1), (4, 2)), "q8": ((7, 2), (8, 1), (8, 2))}
SEQUENCE = SEQUENCES["p4"]
#: Roache's grid-convergence safety factor for a two-direction estimate with two orders
SAFETY = 3.0
UNITS = {"tip_deflection": "1", "tip_rotation": "rad"}




def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    extra = argparse.ArgumentParser(add_help=False)
    extra.add_argument("--quantity", default="tip_deflection", choices=sorted(UNITS))
    extra.add_argument("--element", default="p4", choices=sorted(SEQUENCES))
    own, rest = extra.parse_known_args(argv)
    sequence = SEQUENCES[own.element]
    a = _common.arguments(PROBLEM, rest)
    doc = _common.problem_json(a.problem_json)
    voltages = ([float(x) for x in doc["spec"]["parameters"]["v"]["value"]] if doc
                else [0.05, 0.1, 0.15, 0.2, 0.25, 0.3])
    b = (_common.load_clean_room(CLEAN_ROOM, "cleanroom_bilayer") if own.element == "p4"
         else _load_quad())
    runs = []
    for order, levels in sequence:
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
                      for (o, lv), row in zip(sequence, vals, strict=True))
    p, lv = sequence[-1]
    if own.element == "p4":
        element = (f"Lagrange P{p} triangles (skfem ElementTriP{p}) for u_X, u_Y, phi; "
                   f"quadrature order {2 * p}")
        mesh = (f"tensor mesh 20 columns x 2 rows per layer, each rectangle cut in two; {lv} "
                "geometric layers (ratio 0.2) at the free end X = L and beside the interface")
    else:
        element = (f"hierarchical tensor-product quadrilaterals of order {p} (skfem "
                   f"ElementQuadP({p})) for u_X, u_Y, phi; Gauss quadrature of degree "
                   f"{2 * p + 4}")
        mesh = (f"tensor mesh of quadrilaterals, 12 columns x 2 rows per layer; the column at "
                f"X = L and the rows beside the interface cut {lv} times geometrically "
                "(ratio 0.15) towards the singular point (L, 1/2)")
    _common.write_adapter_json(a.out, quantity=q, method={
        "description": "plane-strain displacement-potential finite-element model of the "
                       "bilayer strip (electric enthalpy: compressible neo-Hookean in both "
                       "layers, -1/2 J |F^-T Grad phi|^2 in the active layer; the passive "
                       "layer's potential held at 0); sliding clamp u_X = 0 at X = 0 with "
                       "u_Y(0, H/2) = 0; continuation in v (steps 0.025) with Newton",
        "discretisation": f"{element}; gradient of the enthalpy written out, its Hessian by "
                          "complex step (exact to round-off)",
        "mesh_or_resolution": f"{mesh}; sequence {steps}",
        "solver": "Newton with backtracking on the residual norm (scipy spsolve), "
                  "continuation from the linear extrapolation of the two last states",
        "tolerances": "Newton: free residual <= 1e-10 x its value at the step's start",
        "physics_differences": "none"},
        check={"atol": float(np.max(err)),
               "reason": f"{SAFETY:g} x the larger change of the reported values from "
                         f"their p-step and their grading step ({steps})"},
        code_version=skfem.__version__)
    return 0


def _load_quad():
    """``verification/cleanroom/bilayer_quad.py``, which imports the enthalpy of its sibling
    ``bilayer.py``: loaded as a module of a package over the clean-room directory (its
    ``__init__`` is not run)."""
    import importlib
    import types

    pkg = types.ModuleType("cleanroom_pkg")
    pkg.__path__ = [str(CLEAN_ROOMS)]
    sys.modules["cleanroom_pkg"] = pkg
    quad = importlib.import_module("cleanroom_pkg.bilayer_quad")

    class Quad:
        @staticmethod
        def solve(voltages, order, levels):
            return quad.solve(voltages, order=order, nx=12, ny=2, levels=levels, ratio=0.15)

    return Quad


if __name__ == "__main__":
    raise SystemExit(main())
