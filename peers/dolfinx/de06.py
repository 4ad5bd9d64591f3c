"""Run the published DE06 notebook (pre-stretched axisymmetric VHB membrane with a central
electrode) on this DOLFINx, as published and with one physical or numerical choice changed
at a time, and write its voltage-stretch history.

    python peers/run.py dolfinx --script de06.py -- --variant published --out DIR

Source: Stewart, Chester & Anand, "Example codes for coupled theories in solid mechanics",
https://github.com/SolidMechanicsCoupledTheories/FEniCSx_codes (doi 10.5281/zenodo.14680876),
``07_dielectric_elastomers/DE06_AXI_preStretch_membrane.ipynb`` at commit
:data:`COMMIT`. The repository states no licence, so no copy of it is kept here: its code
cells are read at run time from a git mirror of that repository (``--mirror``, default
:data:`MIRROR`, or ``$DE06_MIRROR``), and the edits below are applied to them as text:

* the port from DOLFINx 0.8 to 0.11 (:data:`PORT`): the Newton-solver problem class was
  renamed ``NewtonSolverNonlinearProblem`` (``NonlinearProblem`` is now the SNES one),
  ``LinearProblem`` takes its ``bcs`` by keyword and a ``petsc_options_prefix``,
  ``element.interpolation_points`` is a property, and the output goes to ``--out``; the
  plotting cells (pyvista, matplotlib) are not run;
* the variant (:data:`VARIANTS`), each a textual change of one published choice.

The notebook's own probes are recorded at every increment: the electrode-edge radius on
the top face (its "electrode A/A0"), the thickness at the axis, and, added here, the radial
stretch of the mid-plane at half the electrode radius (inside the homogeneous electroded
disc, where the membrane model's lambda_a is defined).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import subprocess
import time
from pathlib import Path

COMMIT = "5d7d642e2282f2b5930300f10c37c1fa00c8ecc7"
NOTEBOOK = "07_dielectric_elastomers/DE06_AXI_preStretch_membrane.ipynb"
URL = "https://github.com/SolidMechanicsCoupledTheories/FEniCSx_codes"
MIRROR = "/work/.mirror/SolidMechanicsCoupledTheories+FEniCSx_codes/repo"

#: cells not run: plotting and interactive display (they need pyvista/matplotlib and
#: produce only pictures); identified by a line they contain
SKIP_MARKERS = ("import pyvista", "plotter.show()", "plt.rc('font'")

#: the port to DOLFINx 0.11 (old text -> new text; each must occur)
PORT = [
    ("from dolfinx.fem.petsc import NonlinearProblem",
     "from dolfinx.fem.petsc import NewtonSolverNonlinearProblem as NonlinearProblem"),
    ("projection_problem = dolfinx.fem.petsc.LinearProblem(a, L, [], \\",
     "projection_problem = dolfinx.fem.petsc.LinearProblem(a, L, bcs=[], "
     "petsc_options_prefix='proj_', \\"),
    ("import matplotlib.pyplot as plt\nplt.close('all')", "pass"),
    ('"results/" + results_name + ".bp"', 'OUT_DIR + "/" + results_name + ".bp"'),
    (".element.interpolation_points()", ".element.interpolation_points"),
]

#: one published choice changed per variant (old text -> new text)
VARIANTS = {
    "published": [],
    # stiffer in bulk: K = 1e4 G instead of 1e3 G
    "bulk1e4": [("Kbulk   = Constant(domain, PETSc.ScalarType(1e3*Geq_0))",
                 "Kbulk   = Constant(domain, PETSc.ScalarType(1e4*Geq_0))")],
    # nearly incompressible: K = 1e5 G instead of 1e3 G (J - 1 ~ 1e-5 instead of ~1e-3)
    "bulk1e5": [("Kbulk   = Constant(domain, PETSc.ScalarType(1e3*Geq_0))",
                 "Kbulk   = Constant(domain, PETSc.ScalarType(1e5*Geq_0))")],
    # full integration: quadrature degree 4 for the P2 quadrilaterals instead of 2
    "quad4": [("dx = ufl.Measure('dx', domain=domain, metadata={'quadrature_degree': 2})",
               "dx = ufl.Measure('dx', domain=domain, metadata={'quadrature_degree': 4})")],
    # a ten times thinner film (0.02 mm instead of 0.2 mm), same mesh
    "thin": [("thickness  = 0.2 # undeformed thickness, mm",
              "thickness  = 0.02 # undeformed thickness, mm")],
    # all three together: the membrane limit with matched physics
    "matched": [("Kbulk   = Constant(domain, PETSc.ScalarType(1e3*Geq_0))",
                 "Kbulk   = Constant(domain, PETSc.ScalarType(1e5*Geq_0))"),
                ("dx = ufl.Measure('dx', domain=domain, metadata={'quadrature_degree': 2})",
                 "dx = ufl.Measure('dx', domain=domain, metadata={'quadrature_degree': 4})"),
                ("thickness  = 0.2 # undeformed thickness, mm",
                 "thickness  = 0.02 # undeformed thickness, mm")],
}
# the matched physics with four times finer voltage increments (1200 instead of 300):
# whether the notebook's fixed-increment Newton failure is a matter of step size
VARIANTS["matched_fine"] = VARIANTS["matched"] + [
    ("num_steps2  = 300", "num_steps2  = 1200")]

#: the extra probe, recorded beside the notebook's own time histories (inserted after
#: each "timeHist4[ii] = ..." line of the two load steps)
PROBE = ("timeHist4[ii] = w.sub(0).sub(1).eval([0,thickness,0],colliding_cellsB[0])[0]"
         " # time history of actuator thinning")
PROBE_ADD = (PROBE + "\n    PROBE_HIST.append((ii, t, "
             "w.sub(0).sub(0).eval([electrode/2, thickness/2, 0], "
             "colliding_cellsD[0])[0]))")
SETUP_PROBE = (
    "\npointForEvalD = np.array([electrode/2, thickness/2, 0])\n"
    "cell_candidates = dolfinx.geometry.compute_collisions_points(bb_tree, pointForEvalD)\n"
    "colliding_cellsD = dolfinx.geometry.compute_colliding_cells(domain, cell_candidates, "
    "pointForEvalD).array\n")


def notebook_cells(mirror: str) -> list[str]:
    text = subprocess.run(["git", "--git-dir", mirror, "show", f"{COMMIT}:{NOTEBOOK}"],
                          check=True, capture_output=True, text=True).stdout
    nb = json.loads(text)
    return ["".join(c["source"]) for c in nb["cells"] if c["cell_type"] == "code"]


def edited_source(cells: list[str], variant: str) -> str:
    src = "\n\n".join(c for c in cells if not any(m in c for m in SKIP_MARKERS))
    for old, new in PORT + VARIANTS[variant]:
        if old not in src:
            raise RuntimeError(f"DE06 edit not applicable (text not found): {old!r}")
        src = src.replace(old, new)
    if src.count(PROBE) != 2:
        raise RuntimeError("DE06: the two time-history blocks were not found")
    src = src.replace(PROBE, PROBE_ADD)
    anchor = "colliding_cellsC = dolfinx.geometry.compute_colliding_cells(domain, " \
             "cell_candidates, pointForEvalC).array"
    if anchor not in src:
        raise RuntimeError("DE06: probe set-up anchor not found")
    return src.replace(anchor, anchor + SETUP_PROBE)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--variant", choices=sorted(VARIANTS), default="published")
    ap.add_argument("--out", required=True)
    ap.add_argument("--mirror", default=os.environ.get("DE06_MIRROR", MIRROR))
    a = ap.parse_args()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    src = edited_source(notebook_cells(a.mirror), a.variant)
    (out / f"de06_{a.variant}.py.txt").write_text(src)  # what ran (not kept in the repo)
    import dolfinx_solver  # noqa: F401 - must precede dolfinx (orders MPI ahead of PETSc)

    ns = {"__name__": "de06", "OUT_DIR": str(out), "PROBE_HIST": []}
    t0 = time.perf_counter()
    c0 = time.process_time()
    with (out / f"de06_{a.variant}.log").open("w") as log, contextlib.redirect_stdout(log):
        exec(compile(src, f"DE06[{a.variant}]", "exec"), ns)  # noqa: S102
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    import numpy as np

    thickness, length, electrode = ns["thickness"], ns["length"], ns["electrode"]
    G, eps = float(ns["Geq_0"]), float(ns["vareps"])
    probe = {i: ur for i, _, ur in ns["PROBE_HIST"]}
    rows = []
    for i in sorted(probe):  # the converged increments (the notebook stops at a failure)
        t = ns["timeHist2"][i]
        rows.append({
            "step": i, "time": t, "actuation": bool(t > ns["step1_time"] + 1e-12),
            "phibar": ns["timeHist1"][i] / (thickness * np.sqrt(G / eps)),
            "edge_radius": electrode + ns["timeHist3"][i],
            "axis_thickness_ratio": ns["timeHist4"][i] / thickness + 1.0,
            "mid_radial_stretch": 1.0 + probe[i] / (electrode / 2),
        })
    converged_all = len(probe) == ns["num_steps1"] + ns["num_steps2"]
    summary = {"variant": a.variant, "edits": VARIANTS[a.variant], "commit": COMMIT,
               "url": URL, "notebook": NOTEBOOK, "wall_seconds": round(wall, 2),
               "cpu_seconds": round(cpu, 2), "increments": len(probe),
               "completed": bool(converged_all),
               "parameters": {"preStretch": ns["preStretch"], "length": length,
                              "electrode": electrode, "thickness": thickness, "G": G,
                              "K": float(ns["Kbulk"]), "I_m": float(ns["I_m"]),
                              "quadrature_degree": 4 if "quad" in a.variant
                              or a.variant == "matched" else 2},
               "rows": rows}
    (out / f"de06_{a.variant}.json").write_text(json.dumps(summary, indent=1))
    print(f"DE06 {a.variant}: {len(probe)} converged increments of "
          f"{ns['num_steps1'] + ns['num_steps2']}, wall {wall:.1f} s, cpu {cpu:.1f} s")


if __name__ == "__main__":
    main()
