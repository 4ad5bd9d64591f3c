"""Chapter 5 datasets and figures: the clamped dielectric buckling membrane (NGSolve).

``build(out_dir, full=False)`` writes

* ``ch5_critical_voltage.nc`` -- critical normalised voltage of the perfect film by the
  linearised eigen-analysis on a sequence of meshes (case x level), the fitted
  convergence rate and Richardson limit, plate-theory estimates (Kirchhoff, Mindlin) and
  the Southwell estimate from the ramp of the imperfect film;
* ``ch5_ramps.nc`` -- centre deflection, thickness and true field versus normalised
  voltage of the imperfect film (case x step), pull-in (bracketed limit point), the
  eigenvalues of the condensed tangent along the path and their modes' axisymmetric
  fraction (wrinkling detection);
* figures mirroring Figs 5.4 and 5.6 and the mesh-convergence of the critical voltage.

``full=False``: coarse meshes (in-plane size 3, 2, 1.4 t0; ramps at 3 t0), about a minute
on one core.  ``full=True``: refined meshes (down to 0.5 t0; ramps at 1 t0), hours, run as
independent tasks on Dask ``distributed`` (:func:`run_tasks`).  The 0.5 mm Ogden case is
the 1 mm case by scale invariance (:data:`SCALE_COPIES`).  :func:`coarse_values` recomputes
the coarsest level of every case (``debench verify``).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import xarray as xr
from debench.models.buckling import analytic
from debench.models.buckling.parameters import MU_REF, Plate
from debench.models.buckling.ramp_result import RampResult, southwell
from debench.models.errors import ConvergenceError
from debench.models.materials.constants import OGDEN_DELTA
from debench.models.numerics import convergence_fit, level_fit, reference_fit
from debench.models.numerics.convergence import FIT_SAFETY, NO_FIT
from debench.reference import figures as figure_io
from debench.reference.datasets import DatasetError, read_dataset, variable_attrs, write_dataset
from debench.reference.figures import LABELS, pyplot
from debench.reference.studies.ch5 import (
    CASES,
    EIG_EVERY,
    LAYER_STUDY,
    LAYERS,
    LEVELS,
    ORDER,
    RAMP_DV_MAX,
    RAMP_LAYERS,
    RAMP_LEVELS,
    SCALE_COPIES,
    critical_task,
    expected_order,
    first_instability,
    lowest_nonaxisymmetric,
    material,
    plan,
    ramp_task,
    task_cost,
)
from debench.reference.tasks import resolve_scheduler, run_tasks

#: CPU seconds of the default build (one thread, measured in one `debench reproduce` with
#: two pool processes on the quiet 2-core machine): the pool starts the longest first.
BUILD_CPU_S = 83.0
#: ``debench verify`` does not rebuild this chapter (minutes of CPU, or the catalogue itself):
#: its model guards and the value check stand for it.
REGENERATED_BY_VERIFY = False
#: The model guards ``debench verify`` runs for this chapter instead of rebuilding it
#: (``module:function`` returning guarded values -> measured CPU seconds, one thread).
GUARDS = {"debench.reference.producers.ch5:coarse_guards": 5.7}


def _source(case: str) -> str:
    """The case whose FE results ``case`` reads: itself, or the case it is a scale copy of
    (:data:`SCALE_COPIES`)."""
    return SCALE_COPIES.get(case, case)


def _at_pullin(r, arr) -> float:
    """A path quantity interpolated (in the centre deflection) at the pull-in deflection."""
    k = int(np.argmax(r.v))
    return float(np.interp(r.w_pullin, r.w[: k + 2], arr[: k + 2]))


def _run_plan(full: bool, scheduler, progress: bool) -> dict:
    """Every task of :func:`plan` once (a task that appears twice, a layer-study mesh that
    is also a level of the sequence, runs once): ``{task: result}``."""
    roles = plan(full)
    unique = list(dict.fromkeys(t for ts in roles.values() for t in ts))
    return dict(zip(unique, run_tasks(unique, scheduler=scheduler, progress=progress,
                                      cost=task_cost),
                    strict=True))


def _ramp_results(done: dict, full: bool) -> dict:
    """The ramps of the plan as :class:`~debench.models.buckling.ramp_result.RampResult`,
    ``{(case, h): ramp}`` (scale copies read the case they copy)."""
    return {(c, h): RampResult(**dict(done[(ramp_task, _source(c), h, EIG_EVERY, RAMP_DV_MAX,
                                            RAMP_LAYERS)]))
            for c in CASES for h in RAMP_LEVELS[full]}


def compute(full: bool = False, progress: bool = True, scheduler=None):
    """Run the FE computations; returns (critical dataset, ramps dataset, parameters).

    Every task of :func:`plan` is independent (run serially, or on Dask with
    ``scheduler``); a task that appears twice (a layer-study mesh that is also a level of
    the sequence) runs once; scale copies (:data:`SCALE_COPIES`) are filled from the case
    they copy.
    """
    done = _run_plan(full, scheduler, progress)
    ramps = _ramp_results(done, full)
    return critical_dataset(done, ramps, full), ramps_dataset(ramps, full), _parameters(full)


# ------------------------------------------------------------------ ch5_critical_voltage
_THIS_MESH = ("of this mesh: secant on the lowest eigenvalue to |dv| < 1e-6; the "
              "discretisation error is what the sequence measures")


def _mesh_sequence(done: dict, full: bool) -> dict[str, np.ndarray]:
    """The critical-voltage results per (case, level) of the in-plane sequence and per
    (case, layer count) of the through-thickness study."""
    levels, lay = LEVELS[full], LAYERS[full]
    h_ls, layer_counts = LAYER_STUDY[full]
    crit = [[done[(critical_task, _source(c), h, lay)] for h in levels] for c in CASES]
    layer = [[done[(critical_task, _source(c), h_ls, n)] for n in layer_counts] for c in CASES]

    def table(rows, key, dtype=None):
        return np.array([[r[key] for r in row] for row in rows], dtype=dtype)

    return {"v_cr": table(crit, "v"), "ndof": table(crit, "ndof", np.int64),
            "nelements": table(crit, "nelements", np.int64),
            "wall_seconds": table(crit, "seconds"), "eig_residual": table(crit, "eig_residual"),
            "v_cr_layers": table(layer, "v"), "ndof_layers": table(layer, "ndof", np.int64)}


def _case_estimates(seq: dict, done: dict, ramps: dict, full: bool) -> dict[str, np.ndarray]:
    """Per case: the in-plane mesh limit (:func:`reference_fit` at the expected order, and
    a free-rate fit), the through-thickness limit (a fit in 1/layers), their sum (the
    reference), the plate-theory estimates and the Southwell estimate from the finest ramp."""
    levels, lay = np.array(LEVELS[full]), LAYERS[full]
    layer_counts = LAYER_STUDY[full][1]
    finest_ramp = RAMP_LEVELS[full][-1]
    out: dict[str, list] = {k: [] for k in (
        "v_cr_extrapolated", "convergence_rate", "v_cr_error", "v_cr_fit_residual",
        "fit_kind", "expected_order", "v_cr_free_fit", "free_fit_rate", "v_cr_layer_limit",
        "layer_error", "layer_correction", "v_cr_kirchhoff", "v_cr_mindlin",
        "v_cr_southwell", "v_cr_ramp_mesh")}
    for i, case in enumerate(CASES):
        out["expected_order"].append(expected_order(_source(case)))
        fitted = reference_fit(levels, seq["v_cr"][i], out["expected_order"][-1])
        out["fit_kind"].append(fitted.kind)
        out["v_cr_extrapolated"].append(fitted.v_inf)
        out["convergence_rate"].append(fitted.p)
        out["v_cr_error"].append(fitted.error)
        out["v_cr_fit_residual"].append(fitted.residual)
        try:
            free_fit = convergence_fit(levels, seq["v_cr"][i])
        except ConvergenceError:   # a free rate at its bound: no free-rate limit
            free_fit = NO_FIT
        out["v_cr_free_fit"].append(free_fit.v_inf)
        out["free_fit_rate"].append(free_fit.p)
        # through-thickness: v(n layers) ~ v_n_inf + C n^-q, i.e. a fit in 1/n
        v_layers = seq["v_cr_layers"][i]
        lf = level_fit(1.0 / np.array(layer_counts, float), v_layers)
        out["v_cr_layer_limit"].append(lf.v_inf)
        out["layer_error"].append(lf.error)
        out["layer_correction"].append(lf.v_inf - v_layers[list(layer_counts).index(lay)])
        mat = material(CASES[case][0])
        out["v_cr_kirchhoff"].append(analytic.critical_voltage_plate(mat, 10.0, mindlin=False))
        out["v_cr_mindlin"].append(analytic.critical_voltage_plate(mat, 10.0, mindlin=True))
        r = ramps[(case, finest_ramp)]
        v_rm = done[(critical_task, _source(case), finest_ramp, RAMP_LAYERS)]["v"]
        out["v_cr_ramp_mesh"].append(v_rm)
        out["v_cr_southwell"].append(southwell(r.v, r.w_mid, v_guess=v_rm))
    est = {k: np.array(v, dtype=str if k == "fit_kind" else None) for k, v in out.items()}
    est["v_cr_reference"] = est["v_cr_extrapolated"] + est["layer_correction"]
    est["v_cr_reference_error"] = est["v_cr_error"] + np.abs(est["layer_error"])
    return est


def critical_dataset(done: dict, ramps: dict, full: bool) -> xr.Dataset:
    """``ch5_critical_voltage``: the mesh sequence (case x level), the through-thickness
    study (case x layer_count) and the per-case estimates of :func:`_case_estimates`."""
    seq = _mesh_sequence(done, full)
    est = _case_estimates(seq, done, ramps, full)
    a, cl, c = variable_attrs, ("case", "level"), ("case",)
    return xr.Dataset(
        {
            "v_cr": (cl, seq["v_cr"], a(
                "normalised critical voltage Phi/t0 sqrt(eps/mu_ref) of the perfect film "
                "(linearised eigen-analysis)", accuracy=_THIS_MESH)),
            "ndof": (cl, seq["ndof"], a("degrees of freedom")),
            "nelements": (cl, seq["nelements"], a("prism elements")),
            "eig_residual": (cl, seq["eig_residual"], a(
                "relative eigen-residual ||S x - lambda M x||/||M x|| at v_cr")),
            "wall_seconds": (cl, seq["wall_seconds"], a(
                "wall time of the critical-voltage computation (one thread)", "s")),
            "v_cr_extrapolated": (c, est["v_cr_extrapolated"], a(
                "in-plane mesh limit of v_cr at the sequence's layer count (fit_kind: "
                "v_inf + C h^q at the expected order q over the three finest levels when "
                "they show it, else a free-rate fit over all levels)",
                accuracy="+- v_cr_error")),
            "v_cr_error": (c, est["v_cr_error"], a(
                "error estimate of the in-plane mesh limit (expected order: 3 x the largest "
                "of the fit residual, the distance from the three-point limit with a free "
                "rate and the change when the next coarser level is added; free rate: 3 x "
                "the largest of the drop-a-level change, the residual and the distance "
                "from the limit at the expected order)")),
            "fit_kind": (c, est["fit_kind"], a("which fit gives v_cr_extrapolated")),
            "expected_order": (c, est["expected_order"], a(
                "asymptotic convergence order q of v_cr: 2 s(nu), s the Williams exponent "
                "of the clamped-free edge for the material's small-strain Poisson ratio")),
            "v_cr_fit_residual": (c, est["v_cr_fit_residual"], a(
                "largest |fit - v_cr| over the three finest levels")),
            "convergence_rate": (c, est["convergence_rate"], a(
                "observed convergence order of v_cr on the three finest levels")),
            "v_cr_free_fit": (c, est["v_cr_free_fit"], a(
                "mesh limit of a least-squares fit v_inf + C h^p with a free rate over all "
                "levels (a diagnostic: the coarse levels are pre-asymptotic)")),
            "free_fit_rate": (c, est["free_fit_rate"], a(
                "rate p of the free-rate fit over all levels")),
            "v_cr_layers": (("case", "layer_count"), seq["v_cr_layers"], a(
                "v_cr at the layer-study in-plane size versus layers through the thickness",
                accuracy=_THIS_MESH)),
            "ndof_layers": (("case", "layer_count"), seq["ndof_layers"],
                            a("degrees of freedom of the layer study")),
            "v_cr_layer_limit": (c, est["v_cr_layer_limit"], a(
                "through-thickness limit of v_cr at the layer-study in-plane size (fit in "
                "1/layers; with two counts: the finer)", accuracy="+- v_cr_layer_error")),
            "v_cr_layer_error": (c, np.abs(est["layer_error"]), a(
                "error estimate of the through-thickness limit")),
            "layer_correction": (c, est["layer_correction"], a(
                "v_cr_layer_limit minus v_cr with the sequence's layer count, same mesh")),
            "v_cr_reference": (c, est["v_cr_reference"], a(
                "reference critical voltage: in-plane limit plus through-thickness "
                "correction (errors assumed additive)", accuracy="+- v_cr_reference_error")),
            "v_cr_reference_error": (c, est["v_cr_reference_error"], a(
                "error estimate of v_cr_reference: v_cr_error + v_cr_layer_error")),
            "v_cr_kirchhoff": (c, est["v_cr_kirchhoff"], a(
                "Kirchhoff clamped-plate estimate (14.68 D/a^2, compressible flat film)")),
            "v_cr_mindlin": (c, est["v_cr_mindlin"], a(
                "Mindlin (thick-plate) corrected clamped-plate estimate")),
            "v_cr_southwell": (c, est["v_cr_southwell"], a(
                "Southwell estimate from the ramp of the imperfect film (finest ramp mesh)")),
            "v_cr_ramp_mesh": (c, est["v_cr_ramp_mesh"], a(
                "eigen-analysis critical voltage on the finest ramp mesh")),
            "thickness_m": (c, _thicknesses(), a("initial thickness t0", "m")),
        },
        coords={"case": _case_coord(),
                "level": ("level", np.arange(len(LEVELS[full])), a("mesh level")),
                "h_rel": ("level", np.array(LEVELS[full]), a("in-plane mesh size / t0")),
                "layer_count": ("layer_count", np.array(LAYER_STUDY[full][1], dtype=np.int64),
                                a("layers of quadratic prisms through the thickness"))},
    )


def _case_coord() -> tuple:
    return ("case", list(CASES), {"long_name": "material and thickness case"})


def _thicknesses() -> np.ndarray:
    return np.array([CASES[c][1] for c in CASES])


# ------------------------------------------------------------------ ch5_ramps
_PULLIN_ACCURACY = "parabola through the voltage maximum of this mesh (< 1e-3 relative)"
_PATH_QUANTITIES = (
    ("v", "normalised voltage Phi/t0 sqrt(eps/mu_ref)"),
    ("w", "vertical displacement of the top-surface centre / t0"),
    ("w_mid", "mean vertical displacement of top and bottom centre / t0"),
    ("thickness", "current centre thickness / t0"),
    ("e_centre", "normalised true field at the centre E sqrt(eps/mu_ref)"),
    ("e_max", "largest sampled normalised true field (mid-plane radius)"))
"""The path quantities stored per converged load step: (name, long_name), all
dimensionless."""
_EIG_RECORDS = (
    ("eig_lambda", "eig_lam",
     "lowest eigenvalues of the condensed tangent S u = lambda M u (M: L2 mass / t0^2)"),
    ("eig_axisymmetry", "eig_axisym", "fraction of the mode in the angular harmonic n = 0"),
    ("eig_wavenumber", "eig_wavenumber",
     "dominant angular harmonic of the mode (0: axisymmetric)"))
"""The per-mode eigen-records along the path: (variable, RampResult field, long_name)."""


def _pad(a, n, extra=()):
    """``a`` NaN-padded to length ``n`` along its first axis."""
    out = np.full((n,) + extra, np.nan)
    out[: len(a)] = a
    return out


def _wrinkling(r) -> dict:
    """The first instability of a ramp (:func:`first_instability`) when it is
    non-axisymmetric; its voltage and deflection NaN otherwise."""
    f = first_instability(r.eig_w, r.eig_v, r.eig_lam, r.eig_axisym, r.eig_wavenumber)
    return f if f["kind"] == "non-axisymmetric" else {**f, "v": np.nan, "w": np.nan}


def _path_variables(rl: list) -> dict:
    """The finest ramp of each case step by step (case x step) and its eigen-records
    (case x eig_record [x mode]), NaN-padded to the longest."""
    a = variable_attrs
    nstep = max(len(r.v) for r in rl)
    neig = max(len(r.eig_v) for r in rl)
    data = {key: (("case", "step"), np.array([_pad(getattr(r, key), nstep) for r in rl]),
                  a(ln, "1")) for key, ln in _PATH_QUANTITIES}
    data["eig_v"] = (("case", "eig_record"), np.array([_pad(r.eig_v, neig) for r in rl]),
                     a("normalised voltage of the eigen-analysis record"))
    data["eig_w"] = (("case", "eig_record"), np.array([_pad(r.eig_w, neig) for r in rl]),
                     a("centre deflection / t0 of the eigen-analysis record"))
    for name, field, ln in _EIG_RECORDS:
        data[name] = (("case", "eig_record", "mode"),
                      np.array([_pad(getattr(r, field), neig, (3,)) for r in rl]), a(ln))
    return data


def _pullin_variables(rl: list) -> dict:
    """Pull-in and the first instability on the finest ramp of each case."""
    a = variable_attrs
    first = [_wrinkling(r) for r in rl]
    return {
        "v_pullin": (("case",), np.array([r.v_pullin for r in rl]), a(
            "pull-in on the finest ramp mesh: voltage limit point (vertex of the parabola "
            "v(w) through the maximum)", accuracy=_PULLIN_ACCURACY)),
        "v_max_computed": (("case",), np.array([np.max(r.v) for r in rl]), a(
            "largest normalised voltage among the computed path points")),
        "w_pullin": (("case",), np.array([r.w_pullin for r in rl]), a(
            "centre deflection / t0 at pull-in (finest ramp mesh)", accuracy=_PULLIN_ACCURACY)),
        "thickness_pullin": (("case",), np.array([_at_pullin(r, r.thickness) for r in rl]),
                             a("centre thickness / t0 at pull-in")),
        "e_centre_pullin": (("case",), np.array([_at_pullin(r, r.e_centre) for r in rl]),
                            a("normalised true centre field at pull-in")),
        "e_max_pullin": (("case",), np.array([_at_pullin(r, r.e_max) for r in rl]),
                         a("largest sampled normalised true field at pull-in")),
        "first_kind": (("case",), np.array([f["kind"] for f in first], dtype=str), {
            "long_name": "kind of the first instability along the finest ramp (first "
            "eigen-record with an eigenvalue <= 0): axisymmetric (pull-in), non-axisymmetric "
            "(wrinkling) or none"}),
        "v_wrinkling": (("case",), np.array([f["v"] for f in first]), a(
            "normalised voltage at the onset of a non-axisymmetric mode when it is the first "
            "instability (NaN: pull-in or nothing comes first)")),
        "w_wrinkling": (("case",), np.array([f["w"] for f in first]), a(
            "centre deflection / t0 at the onset of a non-axisymmetric mode when it is the "
            "first instability (NaN: none)")),
        "ndof": (("case",), np.array([r.ndof for r in rl]), a("degrees of freedom")),
    }


def _ramp_level_variables(ramps: dict, full: bool) -> dict:
    """Pull-in and wrinkling on every ramp level (case x ramp_level) and the mesh limit of
    the pull-in voltage and deflection (:func:`level_fit`)."""
    a, ramp_levels, cr = variable_attrs, RAMP_LEVELS[full], ("case", "ramp_level")
    by_level = {key: np.array([[getattr(ramps[(c, h)], key) for h in ramp_levels]
                               for c in CASES], float) for key in ("v_pullin", "w_pullin")}
    data = {
        "v_pullin_levels": (cr, by_level["v_pullin"], a(
            "pull-in voltage per ramp mesh", accuracy=_PULLIN_ACCURACY)),
        "w_pullin_levels": (cr, by_level["w_pullin"], a(
            "centre deflection / t0 at pull-in per ramp mesh", accuracy=_PULLIN_ACCURACY)),
        "v_wrinkling_levels": (cr, np.array(
            [[_wrinkling(ramps[(c, h)])["v"] for h in ramp_levels] for c in CASES]), a(
            "onset voltage of a non-axisymmetric mode as the first instability per ramp "
            "mesh (NaN: none)")),
        "ndof_ramp_levels": (cr, np.array(
            [[ramps[(c, h)].ndof for h in ramp_levels] for c in CASES], dtype=np.int64),
            a("degrees of freedom of the ramp meshes")),
    }
    for key, ln in (("v_pullin", "pull-in voltage"), ("w_pullin", "pull-in deflection / t0")):
        fits = [level_fit(ramp_levels, by_level[key][i]) for i in range(len(CASES))]
        data[f"{key}_extrapolated"] = (("case",), np.array([f.v_inf for f in fits]), a(
            f"mesh limit of the {ln} (fit v_inf + C h^p with three or more ramp levels; "
            "else the finest level)", accuracy=f"+- {key}_error"))
        data[f"{key}_error"] = (("case",), np.array([f.error for f in fits]), a(
            f"error estimate of the mesh limit of the {ln} (NaN: one ramp level)"))
        data[f"{key}_rate"] = (("case",), np.array([f.p for f in fits]), a(
            f"fitted convergence rate of the {ln} (NaN: fewer than three levels)"))
    return data


def ramps_dataset(ramps: dict, full: bool) -> xr.Dataset:
    """``ch5_ramps``: the finest ramp of each case step by step with its eigen-records,
    pull-in and the first instability, and the pull-in on every ramp level."""
    a = variable_attrs
    rl = [ramps[(c, RAMP_LEVELS[full][-1])] for c in CASES]
    data = {**_path_variables(rl), **_pullin_variables(rl), **_ramp_level_variables(ramps, full)}
    data["thickness_m"] = (("case",), _thicknesses(), a("initial thickness t0", "m"))
    data["min_nonaxisymmetric_lambda"] = (("case",), np.array([_min_nonaxisym(r) for r in rl]),
                                          a("smallest eigenvalue of a non-axisymmetric "
                                            "mode recorded before pull-in"))
    coords = {
        "case": _case_coord(),
        "step": ("step", np.arange(data["v"][1].shape[1]), a("converged load step")),
        "eig_record": ("eig_record", np.arange(data["eig_v"][1].shape[1]),
                       a("eigen-analysis record")),
        "mode": ("mode", np.arange(3), a("mode index (ascending eigenvalue)")),
        "ramp_level": ("ramp_level", np.array(RAMP_LEVELS[full]), a(
            "in-plane mesh size / t0 of the ramp"))}
    return xr.Dataset(data, coords=coords)


def _parameters(full: bool) -> dict:
    """The model and plan parameters both Chapter 5 datasets record."""
    nh, og = material("nh"), material("ogden")
    h_ls, layer_counts = LAYER_STUDY[full]
    return {"mu_ref_Pa": MU_REF, "nh_mu_Pa": nh.mu, "k_Pa": nh.k,
            "ogden_alphas": list(og.alphas), "ogden_mus_Pa": list(og.mus),
            "ogden_delta": OGDEN_DELTA, "aspect": 10.0, "imperfection_rel": 1e-3,
            "imperfection_shape": "t0*1e-3*(1-r^2/a^2)^2", "eps_r": 4.7, "layers": LAYERS[full],
            "order": ORDER, "levels_h_rel": list(LEVELS[full]),
            "ramp_h_rel": list(RAMP_LEVELS[full]), "ramp_layers": RAMP_LAYERS,
            "layer_study_h_rel": h_ls, "layer_counts": list(layer_counts),
            "full": full, "ramp_dc_over_t0": 0.2, "ramp_dv_max": RAMP_DV_MAX,
            "eig_every": EIG_EVERY, "fit_safety": FIT_SAFETY,
            "scale_copies": ", ".join(f"{a} = {b}" for a, b in SCALE_COPIES.items())}


def _min_nonaxisym(r) -> float:
    """Smallest eigenvalue of a non-axisymmetric mode (:func:`axisymmetric`) among the
    records up to the pull-in deflection (NaN: none recorded)."""
    if len(r.eig_v) == 0:
        return float("nan")
    upto = np.asarray(r.eig_w) <= (r.w_pullin if r.w_pullin is not None else np.inf)
    lam = lowest_nonaxisymmetric(r.eig_lam, r.eig_wavenumber)[upto]
    return float(np.min(lam)) if np.any(np.isfinite(lam)) else float("nan")


def figures(crit, ramps, fig_dir: Path) -> list[Path]:
    """Figs 5.4 and 5.6 (deflection versus voltage, pull-in marked), the Fig 5.5
    counterpart (the lowest non-axisymmetric eigenvalue along the path: wrinkling where it
    crosses zero before pull-in), and the mesh convergence of the critical voltage, the
    pull-in and the through-thickness study.  The thesis' printed values are overlaid in
    the overlays of :mod:`debench.reference.builders.ch5_methods`."""
    plt = pyplot()
    fig_dir.mkdir(parents=True, exist_ok=True)
    out = []
    for name, draw in (("fig5_4_deflection_voltage_thickness", _fig5_4),
                       ("fig5_6_deflection_voltage_material", _fig5_6),
                       ("fig5_5_nonaxisymmetric_modes", _fig5_5)):
        out += figure_io.save(draw(plt, ramps), fig_dir / name)
    out += figure_io.save(_fig_convergence(plt, crit, ramps),
                          fig_dir / "fig5_x_critical_voltage_convergence")
    return out


def _fig5_4(plt, ramps):
    """Fig 5.4: thickness study (Ogden), deflection in mm versus voltage (normalised and in
    kV at eps_r 4.7)."""
    fig, axs = plt.subplots(1, 2, figsize=(10, 4))
    for case, style in (("ogden_t1", "-"), ("ogden_t0p5", "--")):
        r = ramps.sel(case=case)
        t0 = float(r.thickness_m)
        ok = np.isfinite(r.v.values)
        pl = Plate(thickness=t0)
        lab = rf"$t_0$ = {t0 * 1e3:g} mm"
        axs[0].plot(r.v.values[ok], r.w.values[ok] * t0 * 1e3, style, label=lab)
        axs[1].plot([pl.volts(x) / 1e3 for x in r.v.values[ok]], r.w.values[ok] * t0 * 1e3,
                    style, label=lab)
        axs[0].plot(float(r.v_pullin), float(r.w_pullin) * t0 * 1e3, "ko")
    axs[0].set_xlabel(LABELS["phibar_ch5"] + r", $\mu$ = 156 kPa")
    axs[1].set_xlabel(r"voltage $\Phi$ [kV], $\varepsilon_r$ = 4.7")
    for ax in axs:
        ax.set_ylabel(LABELS["deflection_mm"])
        ax.legend()
    fig.suptitle("Fig 5.4 (debench): Ogden films, radius/thickness 10; dot = pull-in")
    return fig


def _fig5_6(plt, ramps):
    """Fig 5.6: material study at 1 mm, centre deflection / t0 versus voltage."""
    fig, ax = plt.subplots(figsize=(5.8, 4.2))
    for case, style, lab in (("nh_t1", "-", "neo-Hookean"), ("ogden_t1", "--", "Ogden")):
        r = ramps.sel(case=case)
        ok = np.isfinite(r.v.values)
        ax.plot(r.v.values[ok], r.w.values[ok], style, label=lab)
        ax.plot(float(r.v_pullin), float(r.w_pullin), "ko")
    ax.set_xlabel(LABELS["phibar_ch5"] + r", $\mu$ = 156 kPa")
    ax.set_ylabel(r"centre deflection $w/t_0$")
    ax.legend()
    ax.set_title(r"Fig 5.6 (debench): $t_0$ = 1 mm; dot = pull-in")
    return fig


def _fig5_5(plt, ramps):
    """Fig 5.5 counterpart: the lowest non-axisymmetric eigenvalue along the path."""
    fig, ax = plt.subplots(figsize=(5.8, 4.2))
    for case, style in (("nh_t1", "-o"), ("ogden_t1", "--s")):
        r = ramps.sel(case=case)
        lam_min = lowest_nonaxisymmetric(r.eig_lambda.values, r.eig_wavenumber.values)
        ok = np.isfinite(r.eig_w.values) & np.isfinite(lam_min)
        ax.plot(r.eig_w.values[ok], lam_min[ok], style, ms=3,
                label=f"{case}, radius/thickness 10")
        ax.axvline(float(r.w_pullin), color="0.5", lw=0.8, ls=":")
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_xlabel(r"centre deflection $w/t_0$ (dotted: pull-in)")
    ax.set_ylabel(r"lowest non-axisymmetric eigenvalue $\lambda$")
    ax.set_title("Fig 5.5 counterpart: wrinkling where a non-axisymmetric mode crosses 0")
    ax.legend()
    return fig


def _fig_convergence(plt, crit, ramps):
    """Convergence: critical voltage (in-plane sequence), pull-in (ramps), through-thickness."""
    fig, axs = plt.subplots(1, 3, figsize=(14, 4.2))
    for case in crit.case.values:
        c = crit.sel(case=case)
        err = np.abs(c.v_cr.values - float(c.v_cr_extrapolated))
        axs[0].loglog(crit.h_rel.values, err, "o-",
                      label=f"{case} (p = {float(c.convergence_rate):.2f})")
        axs[2].plot(c.layer_count.values, c.v_cr_layers.values, "o-", label=str(case))
    axs[0].set_xlabel(LABELS["h_over_t0"])
    axs[0].set_ylabel(r"$|v_{cr}(h) - v_{cr}(h \to 0)|$")
    axs[0].set_title("critical voltage, in-plane sequence")
    for case in ("nh_t1", "ogden_t1"):
        r = ramps.sel(case=case)
        axs[1].plot(r.ramp_level.values, r.v_pullin_levels.values, "o-", label=case)
    axs[1].set_xlabel(LABELS["h_over_t0"])
    axs[1].set_ylabel(r"pull-in voltage $v_{pi}(h)$")
    axs[1].set_title("pull-in per ramp mesh")
    axs[2].set_xlabel("layers through the thickness")
    axs[2].set_ylabel(r"$v_{cr}$ at the layer-study mesh")
    axs[2].set_title("through-thickness convergence")
    for ax in axs:
        ax.legend()
    return fig


def curated_note(name: str) -> str:
    """What a figure drawn from the curated dataset ``name`` says about its data."""
    return (f"Drawn from the curated dataset {name}.nc (converged-only study, computed by "
            f"`debench reproduce {name} --full`); not recomputed by the default run.")


def not_recomputed_line(name: str, cost: str) -> str:
    """The line ``debench reproduce`` reports for the dataset of a converged-only study in
    its default run: why it is not recomputed and what its figure is drawn from."""
    return (f"{name}.nc: not recomputed by the default run (converged-only: {cost}); its "
            f"figure is drawn from the curated {name}.nc, checksum verified; recompute it "
            f"with `debench reproduce {name} --full`")


def draw_from_curated(name: str, cost: str, draw, out_dir: Path) -> list[Path]:
    """The default build of a converged-only study (no mesh of its plan is cheap enough
    for the default run: ``cost`` says what one costs): its figure drawn by ``draw(ds,
    fig_dir, note)`` from the curated dataset ``name`` (sha256 verified on reading) into
    ``out_dir/figures``, stated on stderr and on the figure (:func:`curated_note`); the
    dataset itself is not written. Nothing is drawn where figures are not written
    (:func:`debench.reference.figures.written`) or without the curated dataset (then
    stderr says so)."""
    print(not_recomputed_line(name, cost), file=sys.stderr)
    if not figure_io.written():
        return []
    try:
        ds = read_dataset(name)
    except (DatasetError, FileNotFoundError) as exc:
        print(f"{name}: figure not drawn: no curated dataset to draw it from ({exc})",
              file=sys.stderr)
        return []
    return draw(ds, Path(out_dir) / "figures", curated_note(name))


def build(out_dir: Path, *, full: bool = False, scheduler: str | None = None) -> list[Path]:
    """Compute and write the Chapter 5 datasets and figures into ``out_dir``.

    ``scheduler``: ``"serial"`` runs the FE tasks one after the other in this process;
    ``"local"`` on a Dask LocalCluster sized to the machine (``DEBENCH_WORKERS`` overrides
    the number of worker processes; one thread each); an address on an existing Dask
    scheduler.  None: ``"local"`` on a machine with more than one core, else serial.
    """
    out_dir = Path(out_dir)
    crit, ramps, params = compute(full=full, scheduler=resolve_scheduler(scheduler))
    size = "converged (full)" if full else "coarse"
    paths = [
        write_dataset(crit, "ch5_critical_voltage", out_dir=out_dir, overwrite=True,
                      title="Ch. 5 buckling membrane: critical voltage of the clamped DE film",
                      summary=("Normalised critical voltage of the perfect clamped dielectric "
                               f"film (radius/thickness 10) by FE eigen-analysis on {size} "
                               "meshes, Richardson limit, plate-theory and Southwell estimates "
                               "(thesis Tables 5.2, 5.4)."),
                      parameters=params),
        write_dataset(ramps, "ch5_ramps", out_dir=out_dir, overwrite=True,
                      title="Ch. 5 buckling membrane: voltage ramps to pull-in",
                      summary=("Centre deflection, thickness and true field versus normalised "
                               f"voltage of the imperfect clamped film ({size} mesh), pull-in, "
                               "eigenvalues along the path (thesis Figs 5.4, 5.6, Tables 5.3, "
                               "5.5)."),
                      parameters=params),
    ]
    return paths + figures(crit, ramps, out_dir / "figures")
