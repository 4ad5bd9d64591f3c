"""The Chapter 5 axisymmetric studies in one table: the films, the discretisations each
study runs (its plan: the default build and ``full``) and the cheap settings that
``debench verify`` recomputes. The builders (:mod:`~debench.reference.builders.ch5_axisym`,
:mod:`~debench.reference.builders.ch5_axisym_path`,
:mod:`~debench.reference.builders.ch5_axisym_methods`), their tasks and the producers read
them from here, so that a plan changes in this file only.

A discretisation (:class:`~debench.models.buckling.axisym.AxisymDiscretisation`) is the
polynomial order p of every field and L geometric layers (ratio 0.25) towards the clamped
rim (a rim zone of one thickness) and towards each face, on ``n_r`` equal radial elements
of [0, a - t0] and two elements through the thickness; the plans below name (p, L) and
``n_r``, the rest is the class's default.
"""

from __future__ import annotations

import math
import time

import numpy as np
from debench.models.buckling.analytic import critical_voltage_plate
from debench.models.buckling.parameters import Plate
from debench.models.errors import ConvergenceError
from debench.reference.studies.ch5 import material
from debench.reference.tasks import limit_threads

THICKNESS = 1e-3
"""Thickness t0 [m] of the perfect films of the critical-voltage studies (Table 5.1's 1 mm
film; the normalised voltages are scale-free)."""
ASPECT = 10.0
"""Radius / thickness of the perfect films (the stated geometry of Section 5.3)."""
CRITICAL_N_R = 10
"""Equal radial elements on [0, a - t0] of the critical-voltage studies (elements of
1.9 t0 at R/t0 = 10)."""

CRITICAL = {
    False: {"cases": ("nh_t1", "ogden_t1"), "wavenumbers": (0, 1),
            "orders": (3, 4), "layers": (3, 4)},
    True: {"cases": ("nh_t1", "ogden_t1"), "wavenumbers": (0, 1),
           "orders": (4, 5, 6), "layers": (6, 8)},
}
"""The critical voltages of the perfect film (builder ``ch5_axisym``): every order with
every layer count, per case and wavenumber."""
CRITICAL_GUARD = (2, 3)
"""(order, layers) of the guard solve: the n = 0 critical voltage of each film on this
cheap discretisation (about 1 and 2 s of CPU, measured), stored as ``v_cr_guard`` so that
``debench verify`` can recompute it and, with the stored correction to the converged
value, the reported critical voltage (:func:`~debench.reference.producers.ch5.
axisym_coarse_guards`)."""

METHODS = {
    False: {"cases": ("nh_t1",), "discs": ((2, 3), (3, 3), (3, 2))},
    True: {"cases": ("nh_t1",), "discs": ((3, 6), (4, 6), (5, 6), (5, 4))},
}
"""The stability-operator study (builder ``ch5_axisym_methods``): (order, layers) per case."""

PATH_FILMS = {
    # name: (material, thickness t0 [m], radius/thickness, wavenumbers recorded,
    #        deflection / t0 from which they are recorded, record spacing / t0)
    "nh_r10": ("nh", 1e-3, 10.0, tuple(range(1, 9)), 1.0, 0.5),
    "ogden_r10": ("ogden", 1e-3, 10.0, tuple(range(1, 9)), 1.0, 0.5),
    "ogden_r20": ("ogden", 0.5e-3, 20.0, tuple(range(1, 15)), 5.0, 0.5),
}
"""The imperfect films of the path study: Table 5.1 neo-Hookean and Ogden at R/t0 = 10 (the
stated geometry, t0 = 1 mm) and the Ogden film at R/t0 = 20 (t0 = 0.5 mm with the radius
R = 10 mm kept). Wavenumbers 1..8 at R/t0 = 10 (their lowest eigenvalues at the voltage
maximum grow with n from n = 1 on: the minimum over n is inside the range) and 1..14 at
R/t0 = 20 (the unstable band at the voltage maximum is n = 6..12, n = 5 and 13 stable: the
range contains the band and a stable wavenumber on either side)."""
PATH_N_R_PER_ASPECT = 0.8
"""Equal radial elements on [0, a - t0] of the path study: 0.8 per unit of R/t0 (elements
of ~1.1-1.2 t0)."""
PATH = {
    False: {"cases": ("nh_r10",), "discs": ((2, 3), (3, 3), (3, 2)), "n_max": 4},
    True: {"cases": ("nh_r10", "ogden_r10", "ogden_r20"),
           "discs": ((2, 6), (3, 6), (4, 6), (4, 4)), "n_max": None},
}
"""The path study (builder ``ch5_axisym_path``): its films, (order, layers) and the largest
wavenumber recorded (None: every wavenumber of the film)."""
PATH_GUARD = ("nh_r10", 2, 1, 0)
"""The path guard (case, order, layers, largest wavenumber): the path task on its cheapest
setting, the neo-Hookean film at R/t0 = 10 at order 2 with one geometric layer and the
axisymmetric eigenvalue only (~9 s CPU: 318 tangent assemblies of 567 DOFs along the path
and the secant to the maximum)."""


V_SWITCH = 0.8
"""Voltage control up to this multiple of the plate estimate of the critical voltage
(:func:`~debench.models.buckling.analytic.critical_voltage_plate`), in 8 steps, then
centre-deflection control through the voltage maximum."""
W_END = 30.0
"""Deflection / t0 at which a path would end if no voltage maximum came before (none does:
the paths end one record past their maximum)."""


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
