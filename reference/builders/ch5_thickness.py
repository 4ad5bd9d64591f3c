"""Chapter 5 thickness puzzle: did the 0.5 mm model keep R = 10 mm?

Table 5.2 prints critical voltages 0.012 (t0 = 0.5 mm) and 0.050 (t0 = 1 mm) for the
Ogden film. At a fixed radius/thickness R/t0 = 10 both are the same normalised number
(scale invariance, ``ch5.erratum.table5_2_thickness_dependence``). The hypotheses tested
by ``ch5.hypothesis.radius_kept.*``: the 0.5 mm model kept the radius R = 10 mm
(R/t0 = 20), and/or its voltage was normalised with the 1 mm thickness.

``build(out_dir, full=False)`` writes ``ch5_thickness.nc``: the critical voltage of the
perfect Ogden film (eigen-analysis, :func:`debench.models.buckling.solver.critical_voltage`)
at R/t0 = 10 and 20 on a sequence of meshes (in-plane size h = 3, 2 t0; with ``full``
also 1.4 t0; one layer of quadratic prisms), their ratio per level, and the
extrapolated ratio with an error estimate (:func:`ratio_limit`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr
from debench.models.buckling.parameters import Discretisation, Ogden, Plate
from debench.models.numerics import level_fit, propagated_accuracy
from debench.reference.datasets import variable_attrs, write_dataset

#: CPU seconds of the default build (one thread, measured in one `debench reproduce` with
#: two pool processes on the quiet 2-core machine): the pool starts the longest first.
BUILD_CPU_S = 30.0
#: ``debench verify`` does not rebuild this chapter (minutes of CPU, or the catalogue itself):
#: its model guards and the value check stand for it.
REGENERATED_BY_VERIFY = False
#: Model guards ``debench verify`` runs for this chapter (none).
GUARDS = {}

NAME = "ch5_thickness"
ASPECTS = (10.0, 20.0)
LEVELS = {False: (3.0, 2.0), True: (3.0, 2.0, 1.4)}
LAYERS = 1
ORDER = 2
THICKNESS = 0.5e-3


def ratio_limit(h, ratio) -> tuple[float, float]:
    """Mesh limit of the ratio and its error estimate: the convergence fit
    (:func:`debench.models.numerics.convergence_fit`) for three or more levels, which
    must converge monotonically; with two, the finest ratio and its change between the
    two levels (:func:`debench.models.numerics.level_fit`)."""
    fit = level_fit(h, ratio, spread_if_not_monotone=False)
    return fit.v_inf, fit.error


def compute(full: bool = False) -> xr.Dataset:
    from debench.models.buckling.solver import CRITICAL_VTOL, critical_voltage

    levels = LEVELS[full]
    v = np.zeros((len(ASPECTS), len(levels)))
    ndof = np.zeros_like(v, dtype=np.int64)
    for i, aspect in enumerate(ASPECTS):
        for j, h in enumerate(levels):
            r = critical_voltage(Plate(thickness=THICKNESS, aspect=aspect), Ogden(),
                                 Discretisation(h_rel=h, layers=LAYERS, order=ORDER))
            v[i, j], ndof[i, j] = r.v, r.ndof
    ratio = v[1] / v[0]
    lim, err = ratio_limit(levels, ratio)
    # regenerations differ by up to twice the secant's tolerance in each critical voltage
    # (each within it of the root); the derived values by what that moves them
    dv = 2 * CRITICAL_VTOL
    acc = {name: float(np.max(propagated_accuracy(f, v, dv))) for name, f in (
        ("ratio", lambda x: x[1] / x[0]),
        ("ratio_extrapolated", lambda x: ratio_limit(levels, x[1] / x[0])[0]),
        ("ratio_error", lambda x: ratio_limit(levels, x[1] / x[0])[1]))}

    a = variable_attrs

    return xr.Dataset(
        {
            "v_cr": (("aspect", "level"), v, a(
                "normalised critical voltage Phi/t0 sqrt(eps/mu_ref) of the perfect Ogden "
                "film, t0 = 0.5 mm (eigen-analysis)", atol=dv)),
            "ndof": (("aspect", "level"), ndof, a("degrees of freedom")),
            "ratio": (("level",), ratio, a("v_cr(R/t0 = 20) / v_cr(R/t0 = 10) per mesh level",
                                          atol=acc["ratio"])),
            "ratio_extrapolated": ((), lim, a("mesh limit of the ratio",
                                                   atol=acc["ratio_extrapolated"])),
            "ratio_error": ((), err, a("error estimate of the mesh limit of the ratio",
                                            atol=acc["ratio_error"])),
        },
        coords={"aspect": ("aspect", np.array(ASPECTS), a("radius / thickness R/t0")),
                "level": ("level", np.arange(len(levels)), a("mesh level")),
                "h_rel": ("level", np.array(levels), a("in-plane mesh size / t0"))},
    )


def build(out_dir: Path, *, full: bool = False) -> list[Path]:
    ds = compute(full)
    return [write_dataset(
        ds, NAME, out_dir=out_dir, overwrite=True,
        title="Chapter 5 thickness puzzle: critical voltage at R/t0 = 10 and 20",
        summary=("Critical normalised voltage of the perfect clamped Ogden film "
                 "(Table 5.1, t0 = 0.5 mm) at radius/thickness 10 and 20 on a mesh sequence, "
                 "their ratio and its mesh limit: the data behind the hypothesis that the "
                 "thesis' 0.5 mm model kept R = 10 mm (Table 5.2)."),
        parameters={"full": full, "levels_h_rel": list(LEVELS[full]), "layers": LAYERS,
                    "order": ORDER, "thickness_m": THICKNESS, "aspects": list(ASPECTS)},
    )]
