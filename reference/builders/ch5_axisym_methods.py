"""Chapter 5: the critical voltage by three stability operators on the axisymmetric model.

The perfect clamped film's critical voltage in the axisymmetric wavenumber n = 0 (the
lowest mode) by the three linearised buckling operators of
:meth:`~debench.models.buckling.axisym.AxisymModel.spectrum`
(:data:`~debench.reference.studies.ch5_axisym_methods.TANGENTS`): the condensed tangent at
fixed voltage (``coupled``: the definition of the critical voltage), the tangent at frozen
potential and the classical initial-stress operator (purely mechanical: the unloaded
film's stiffness plus the stress stiffness of the flat state's total stress), each
converged by polynomial order and geometric grading on the same discretisations, so that
their ratios are free of the discretisation to the error estimates. With the Mindlin and
Kirchhoff plate estimates (:func:`~debench.models.buckling.analytic.critical_voltage_plate`)
they split the gap between the coupled critical voltage and the Mindlin plate into the 3D
mechanics (initial stress / Mindlin) and the electromechanical coupling of the mode
(coupled / initial stress)
(:func:`debench.reference.producers.ch5_methods.axisym_gap_decomposition`).

``build(out_dir, full=False)`` writes ``ch5_axisym_methods.nc``: ``v_cr(case, tangent,
disc)`` with its secant tolerance, CPU seconds and degrees of freedom; per (case, tangent)
the converged value (top discretisation) and its error estimate (Roache's safety factor
times the larger of the change from the order below and from the coarser grading:
:func:`debench.models.numerics.p_grading_estimate`); the plate estimates.

Plans: ``full`` the neo-Hookean film (the one the catalogue's coupling diagnosis is about)
on (p, L) = (3, 6), (4, 6), (5, 6), (5, 4) (three orders: safety factor 1.25); default the
same film on (2, 3), (3, 3), (3, 2) (a coarse check of the same code path; CPU in
``cpu_seconds``). The Ogden film is not in the plan: its initial-stress operator carries
the symbolic derivative of the Ogden enthalpy (the state's stress) inside the Hessian form,
and one critical voltage at p = 2 with 3 layers did not finish in 4 CPU minutes (its coupled
and frozen-potential ones take 5-60 s on the full plan's discretisations).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr
from debench.models.buckling.analytic import critical_voltage_plate
from debench.models.numerics import p_grading_estimate, p_grading_safety, propagated_accuracy
from debench.reference.builders.ch5_axisym import REPEAT_ATOL, critical_solve_variables
from debench.reference.datasets import variable_attrs, write_dataset
from debench.reference.studies import ch5_axisym as study
from debench.reference.studies.ch5 import case_material
from debench.reference.studies.ch5_axisym_methods import TANGENTS, critical_task
from debench.reference.tasks import resolve_scheduler, run_tasks

#: CPU seconds of the default build (one thread, measured in one `debench reproduce` with
#: two pool processes on the quiet 2-core machine): the pool starts the longest first.
BUILD_CPU_S = 20.0
#: ``debench verify`` does not rebuild this chapter (minutes of CPU, or the catalogue itself):
#: its model guards and the value check stand for it.
REGENERATED_BY_VERIFY = False
#: The model guards ``debench verify`` runs for this chapter instead of rebuilding it
#: (``module:function`` returning guarded values -> measured CPU seconds, one thread).
GUARDS = {"debench.reference.producers.ch5_methods:axisym_methods_guards": 8.2}

NAME = "ch5_axisym_methods"
def plan(full: bool = False) -> list[tuple]:
    """The FE tasks ``(critical_task, case, tangent, order, layers)`` of a build."""
    p = study.METHODS[full]
    return [(critical_task, c, t, order, layers) for c in p["cases"] for t in TANGENTS
            for order, layers in p["discs"]]


def compute(full: bool = False, scheduler=None, progress: bool = True):
    p = study.METHODS[full]
    cases, discs = p["cases"], p["discs"]
    tasks = plan(full)
    res = {(r["case"], r["tangent"], r["order"], r["layers"]): r for r in run_tasks(
        tasks, scheduler=scheduler, progress=progress, label="ch5 axisym methods")}
    shape = (len(cases), len(TANGENTS), len(discs))
    keys = ("v", "vtol", "thickness", "e", "eig_residual", "newton_residual_rel", "cpu_s")
    f = {k: np.zeros(shape) for k in keys}
    ndof = np.zeros(shape, dtype=np.int64)
    for c, t, k in np.ndindex(shape):
        r = res[(cases[c], TANGENTS[t], *discs[k])]
        for key in keys:
            f[key][c, t, k] = r[key]
        ndof[c, t, k] = r["ndof"]
    conv = p_grading_estimate(f["v"], discs)
    acc = {key: float(np.max([propagated_accuracy(
        lambda x, key=key: getattr(p_grading_estimate(x, discs), key), row, REPEAT_ATOL)
        for row in f["v"].reshape(-1, len(discs))])) + REPEAT_ATOL
        for key in ("value", "error", "p_change", "grading_change")}
    plates = np.array([[critical_voltage_plate(case_material(c), study.ASPECT, mindlin=m)
                        for m in (True, False)] for c in cases])

    a = variable_attrs
    d3, d2 = ("case", "tangent", "disc"), ("case", "tangent")
    variables = {
        **critical_solve_variables(d3, f, ndof, "in wavenumber 0 under the stability "
                                   "operator (this discretisation)", REPEAT_ATOL),
        "v_cr_converged": (d2, conv.value, a(
            "converged critical voltage: v_cr on the top discretisation of the plan",
            atol=acc["value"], accuracy="+- v_cr_error")),
        "v_cr_error": (d2, conv.error, a(
            "error estimate of v_cr_converged: safety_factor x max(p_change, "
            "grading_change)", atol=acc["error"])),
        "v_cr_p_change": (d2, conv.p_change, a(
            "change of v_cr from the order below (finest grading)", atol=acc["p_change"])),
        "v_cr_grading_change": (d2, conv.grading_change, a(
            "change of v_cr from the coarser grading (top order)",
            atol=acc["grading_change"])),
        "safety_factor": ((), p_grading_safety(discs), a(
            "Roache's GCI safety factor of the plan (1.25 with >= 3 orders, else 3)")),
        "v_cr_mindlin": (("case",), plates[:, 0], a(
            "clamped Mindlin plate estimate of the critical voltage (shear-corrected)",
            atol=1e-12)),
        "v_cr_kirchhoff": (("case",), plates[:, 1], a(
            "clamped Kirchhoff plate estimate of the critical voltage", atol=1e-12)),
    }
    ds = xr.Dataset(variables, coords={
        "case": ("case", list(cases), {"long_name": "material and thickness (nh: "
                                       "neo-Hookean (5.15)-(5.17), ogden: Ogden (5.26); t1: "
                                       "1 mm, R/t0 = 10)"}),
        "tangent": ("tangent", list(TANGENTS), {"long_name": "stability operator: coupled "
                                                "(condensed at fixed voltage), frozen "
                                                "potential, initial stress"}),
        "disc": ("disc", np.arange(len(discs)), a("discretisation index")),
        "order": ("disc", np.array([o for o, _ in discs]), a("polynomial order of every "
                                                             "field")),
        "layers": ("disc", np.array([L for _, L in discs]), a(
            "geometric layers towards the rim and towards each face")),
    })
    params = {"full": full, "cases": list(cases), "tangents": list(TANGENTS),
              "discs": [list(d) for d in discs], "thickness_m": study.THICKNESS,
              "aspect": study.ASPECT, "wavenumber": 0,
              "materials": "Table 5.1 neo-Hookean (5.15)-(5.17); Ogden (5.26), k of Table 5.1"}
    return ds, params


def build(out_dir: Path, *, full: bool = False, scheduler: str | None = None) -> list[Path]:
    """Write ``ch5_axisym_methods.nc`` (see the module docstring). ``scheduler`` as for
    :func:`debench.reference.builders.ch5.build`."""
    ds, params = compute(full, scheduler=resolve_scheduler(scheduler))
    return [write_dataset(
        ds, NAME, out_dir=out_dir, overwrite=True,
        title="Chapter 5: critical voltage by three stability operators, axisymmetric FE",
        summary=("Critical voltage of the perfect clamped film (Table 5.1 neo-Hookean and "
                 "Ogden, R/t0 = 10) in the axisymmetric wavenumber by the coupled tangent at "
                 "fixed voltage, the frozen-potential tangent and the initial-stress "
                 "operator, converged by order and grading, with the Mindlin and Kirchhoff "
                 "plate estimates: the coupling's share of the gap to the plate."),
        parameters=params)]
