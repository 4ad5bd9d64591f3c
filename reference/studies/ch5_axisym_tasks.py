"""The finite-element task of the Chapter 5 axisymmetric path study
(:mod:`debench.reference.builders.ch5_axisym_path`), the path settings it depends on, and
the material of each axisymmetric case. The films and the plan:
:mod:`debench.reference.studies.ch5_axisym`.

The task cache of :func:`debench.reference.tasks.run_tasks` keys on the source of
the module that defines a task and of the study modules it imports: the films and the path
settings are the inputs of the FE results, while the convergence analysis lives in the
builder.
"""

from __future__ import annotations

import math
import time

import numpy as np
from debench.models.buckling.analytic import critical_voltage_plate
from debench.models.buckling.parameters import Plate
from debench.models.errors import ConvergenceError
from debench.models.materials import material as library_material
from debench.reference.studies.ch5_axisym import PATH_FILMS, PATH_N_R_PER_ASPECT
from debench.reference.tasks import limit_threads

V_SWITCH = 0.8
"""Voltage control up to this multiple of the plate estimate of the critical voltage
(:func:`~debench.models.buckling.analytic.critical_voltage_plate`), in 8 steps, then
centre-deflection control through the voltage maximum."""
W_END = 30.0
"""Deflection / t0 at which a path would end if no voltage maximum came before (none does:
the paths end one record past their maximum)."""


def material(case: str):
    """The Table 5.1 material of a case or material name (``nh``, ``nh_t1``, ``nh_r10``:
    neo-Hookean; ``ogden...``: Ogden; the part before the first ``_`` is looked up in the
    library registry, which raises ``ValueError`` naming the valid names)."""
    return library_material(case.split("_")[0] if isinstance(case, str) else case)


def path_task(case: str, order: int, layers: int, n_max: int | None = None) -> dict:
    """One axisymmetric path of the imperfect film as plain data (a Dask task).

    The path (:func:`~debench.models.buckling.axisym.follow_path`) to one record past its
    voltage maximum, with the lowest eigenvalue at fixed voltage of every recorded
    wavenumber; the voltage maximum (the zero of the wavenumber-0 eigenvalue,
    :func:`~debench.models.buckling.axisym.zero_crossing`) and the lowest eigenvalue of each
    wavenumber there; then the first zero of each wavenumber n >= 1 along the path (NaN
    where its eigenvalue stays positive). ``n_max``: only the case's wavenumbers up to it."""
    from debench.models.buckling import axisym as ax

    limit_threads()
    mat_name, t0, aspect, ns, w_from, spacing = PATH_FILMS[case]
    ns = tuple(n for n in ns if n_max is None or n <= n_max)
    mat = material(mat_name)
    cpu = time.process_time()
    disc = ax.AxisymDiscretisation(order=order, edge_layers=layers, face_layers=layers,
                                   n_r=max(1, round(PATH_N_R_PER_ASPECT * aspect)))
    model = ax.AxisymModel(Plate(thickness=t0, aspect=aspect), mat, disc,
                           with_imperfection=True)
    v_switch = V_SWITCH * critical_voltage_plate(mat, aspect)
    points = ax.follow_path(model, W_END, v_switch=v_switch, dv=v_switch / 8,
                            record_every=spacing, wavenumbers=(0,), stop_past_maximum=True,
                            all_from=w_from, all_wavenumbers=ns)
    cpu_path = time.process_time() - cpu
    peak = ax.zero_crossing(model, points, 0)
    if peak is None:
        raise ConvergenceError(f"path_task({case}, {order}, {layers}): the path ends at "
                               f"w = {points[-1].w:.3f} t0 before a voltage maximum")
    lam_at_max = [float(model.spectrum(n, nev=1).lam[0]) for n in ns]
    crossings = {}
    for n in ns:
        c = ax.zero_crossing(model, points, n)
        crossings[n] = ((math.nan,) * 3 if c is None else (c.w, float(c.v), c.thickness))
    lam = np.full((len(points), len(ns)), np.nan)
    for i, p in enumerate(points):
        for j, n in enumerate(ns):
            lam[i, j] = p.lam.get(n, np.nan)
    return {
        "case": case, "order": order, "layers": layers, "ndof": model.ndof,
        "wavenumbers": list(ns),
        "w": [p.w for p in points], "v": [float(p.v) for p in points],
        "thickness": [p.thickness for p in points], "e": [float(p.e) for p in points],
        "lam0": [p.lam[0] for p in points], "lam": lam.tolist(),
        "newton_residual_rel": max(p.newton_residual_rel for p in points),
        "w_max": peak.w, "v_max": float(peak.v), "thickness_max": peak.thickness,
        "wtol_max": peak.wtol, "lam_at_max": lam_at_max,
        "w_cross": [crossings[n][0] for n in ns], "v_cross": [crossings[n][1] for n in ns],
        "thickness_cross": [crossings[n][2] for n in ns],
        "cpu_path_s": cpu_path, "cpu_s": time.process_time() - cpu,
    }
