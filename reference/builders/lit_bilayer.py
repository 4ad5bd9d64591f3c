"""The dielectric-elastomer bilayer bending under voltage (beyond the thesis): the reference
dataset of the problem ``lit_bilayer``.

``build(out_dir, full=False)`` writes ``lit_bilayer.nc``: the tip deflection w/H and the tip
rotation theta at each normalised voltage of :data:`VOLTAGES`
(:func:`debench.models.bilayer.converged`) with their error estimates, and every
discretisation's values (``*_levels``, along ``disc``). ``full``: the reference plan
:data:`debench.models.bilayer.PLAN` (orders 4 .. 6 with two geometric layers, minutes of
CPU: the curated dataset); otherwise the coarse plan
:data:`debench.models.bilayer.COARSE_PLAN` (seconds; what the default-run test checks).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr
from debench.models.numerics import newton
from debench.reference.datasets import write_dataset

#: CPU seconds of the default build (one thread, measured in one `debench reproduce` with
#: two pool processes on the quiet 2-core machine): the pool starts the longest first.
BUILD_CPU_S = 8.0
#: ``debench verify`` does not rebuild this chapter (minutes of CPU, or the catalogue itself):
#: its model guards and the value check stand for it.
REGENERATED_BY_VERIFY = False
#: Model guards ``debench verify`` runs for this chapter (none).
GUARDS = {}

NAME = "lit_bilayer"
#: normalised voltages (Phi/h_a) sqrt(eps/mu) of the stored states
VOLTAGES = (0.05, 0.1, 0.15, 0.2, 0.25, 0.3)

REFERENCES = ("Timoshenko S (1925) Analysis of bi-metal thermostats. J. Opt. Soc. Am. "
              "11:233-255, doi:10.1364/JOSA.11.000233; Land S et al. (2015) Verification of "
              "cardiac mechanics software: benchmark problems and solutions for testing "
              "active and passive material behaviour. Proc. R. Soc. A 471:20150641, "
              "doi:10.1098/rspa.2015.0641")


def compute(full: bool = False) -> tuple[xr.Dataset, dict]:
    """The bilayer dataset and its parameters (pure computation, no I/O)."""
    from debench.models import bilayer

    plan = bilayer.PLAN if full else bilayer.COARSE_PLAN
    c = bilayer.converged(VOLTAGES, plan=plan)
    p = bilayer.BilayerParameters()
    disc = np.arange(len(plan))
    levels = {name: np.stack([getattr(r, name) for r in c.results], axis=-1)
              for name in ("tip_deflection", "tip_rotation")}
    data_vars = {
        "tip_deflection": ("v", c.tip_deflection,
                           {"units": "1", "long_name": "normalised tip deflection u_Y(L, 0)/H "
                            "(top discretisation of the plan)"}),
        "tip_deflection_error": ("v", c.tip_deflection_error,
                                 {"units": "1", "long_name": "error estimate of "
                                  "tip_deflection (Roache safety factor x max(p-step, "
                                  "grading step), at least the floor)"}),
        "tip_rotation": ("v", c.tip_rotation,
                         {"units": "rad", "long_name": "tip rotation atan2(-d_X, H + d_Y) of "
                          "the end-face chord (top discretisation of the plan)"}),
        "tip_rotation_error": ("v", c.tip_rotation_error,
                               {"units": "rad", "long_name": "error estimate of tip_rotation"}),
        "tip_deflection_levels": (("v", "disc"), levels["tip_deflection"],
                                  {"units": "1", "long_name": "tip_deflection on each "
                                   "discretisation of the plan"}),
        "tip_rotation_levels": (("v", "disc"), levels["tip_rotation"],
                                {"units": "rad", "long_name": "tip_rotation on each "
                                 "discretisation of the plan"}),
        "order": ("disc", np.array([o for o, _ in plan]),
                  {"units": "1", "long_name": "polynomial order of the discretisation"}),
        "grading_levels": ("disc", np.array([lv for _, lv in plan]),
                           {"units": "1", "long_name": "geometric mesh layers towards the "
                            "free end of the interface"}),
        "ndof": ("disc", np.array([r.ndof for r in c.results]),
                 {"units": "1", "long_name": "free degrees of freedom"}),
    }
    coords = {
        "v": ("v", np.array(VOLTAGES), {"units": "1", "long_name": "normalised voltage "
                                        "(Phi/h_a) sqrt(eps/mu)"}),
        "disc": ("disc", disc, {"units": "1", "long_name": "index of the discretisation in "
                                "the plan"}),
    }
    params = {"full": full, "plan": [list(x) for x in plan], "voltages": list(VOLTAGES),
              "length": p.length, "passive": p.passive, "bulk_ratio": p.bulk_ratio,
              "nx": p.nx, "ny": p.ny, "hp_factor": bilayer.HP_FACTOR,
              "max_step": bilayer.MAX_STEP, "newton_rtol": newton.RTOL,
              "error_floor": bilayer.ERROR_FLOOR}
    return xr.Dataset(data_vars, coords=coords), params


def build(out_dir: Path, *, full: bool = False) -> list[Path]:
    """Write ``lit_bilayer.nc`` into ``out_dir``; returns its path."""
    ds, params = compute(full)
    nc = write_dataset(
        ds, NAME,
        title="debench: dielectric-elastomer bilayer bending under voltage (plane strain)",
        summary=("Two bonded layers of the Table 5.1 compressible neo-Hookean, the upper an "
                 "ideal dielectric between electrodes, L = 10 H, sliding clamp at X = 0: "
                 "tip deflection and rotation at six normalised voltages, debench's NGSolve "
                 "model (debench.models.bilayer) by p and geometric grading with an error "
                 "estimate per value; peer codes' submissions in submissions/lit_bilayer."),
        references=REFERENCES, parameters=params, out_dir=Path(out_dir), overwrite=True)
    return [nc]
