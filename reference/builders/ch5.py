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
from debench.models.errors import ConvergenceError
from debench.models.materials.constants import OGDEN_DELTA
from debench.models.numerics import convergence_fit, level_fit, reference_fit
from debench.models.numerics.convergence import FIT_SAFETY, NO_FIT
from debench.reference.datasets import variable_attrs, write_dataset
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


def _at_pullin(r, arr) -> float:
    """A path quantity interpolated (in the centre deflection) at the pull-in deflection."""
    k = int(np.argmax(r.v))
    return float(np.interp(r.w_pullin, r.w[: k + 2], arr[: k + 2]))


def compute(full: bool = False, progress: bool = True, scheduler=None):
    """Run the FE computations; returns (critical dataset, ramps dataset, parameters).

    Every task of :func:`plan` is independent (run serially, or on Dask with
    ``scheduler``); a task that appears twice (a layer-study mesh that is also a level of
    the sequence) runs once; scale copies (:data:`SCALE_COPIES`) are filled from the case
    they copy.
    """
    from debench.models.buckling import analytic
    from debench.models.buckling.parameters import MU_REF
    from debench.models.buckling.solver import RampResult, southwell
    levels, ramp_levels = LEVELS[full], RAMP_LEVELS[full]
    h_ls, layer_counts = LAYER_STUDY[full]
    roles = plan(full)
    unique = list(dict.fromkeys(t for ts in roles.values() for t in ts))
    done = dict(zip(unique, run_tasks(unique, scheduler=scheduler, progress=progress,
                                       cost=task_cost),
                    strict=True))

    def ramp(task):
        fields = dict(done[task])
        return RampResult(**fields)

    names = list(CASES)

    def source(case):
        return SCALE_COPIES.get(case, case)

    lay = LAYERS[full]
    crit_res = {(c, h): done[(critical_task, source(c), h, lay)] for c in names for h in levels}
    layer_res = {(c, n): done[(critical_task, source(c), h_ls, n)]
                 for c in names for n in layer_counts}
    ramps = {(c, h): ramp((ramp_task, source(c), h, EIG_EVERY, RAMP_DV_MAX, RAMP_LAYERS))
             for c in names for h in ramp_levels}
    vcr = np.array([[crit_res[(c, h)]["v"] for h in levels] for c in names])
    ndof = np.array([[crit_res[(c, h)]["ndof"] for h in levels] for c in names], dtype=np.int64)
    nel = np.array([[crit_res[(c, h)]["nelements"] for h in levels] for c in names],
                   dtype=np.int64)
    secs = np.array([[crit_res[(c, h)]["seconds"] for h in levels] for c in names])
    eig_res = np.array([[crit_res[(c, h)]["eig_residual"] for h in levels] for c in names])
    v_layers = np.array([[layer_res[(c, n)]["v"] for n in layer_counts] for c in names])
    ndof_layers = np.array([[layer_res[(c, n)]["ndof"] for n in layer_counts] for c in names],
                           dtype=np.int64)

    v_inf, rate, err, resid, v_k, v_m, v_sw, v_cr_ramp_mesh = ([] for _ in range(8))
    v_free, p_free, p_exp, fit_kind = [], [], [], []
    lay_lim, lay_err, lay_corr = [], [], []
    finest_ramp = ramp_levels[-1]
    for i, case in enumerate(names):
        p_exp.append(expected_order(source(case)))
        fitted = reference_fit(np.array(levels), vcr[i], p_exp[-1])
        fit_kind.append(fitted.kind)
        v_inf.append(fitted.v_inf)
        rate.append(fitted.p)
        err.append(fitted.error)
        resid.append(fitted.residual)
        try:
            free_fit = convergence_fit(np.array(levels), vcr[i])
        except ConvergenceError:   # a free rate at its bound: no free-rate limit
            free_fit = NO_FIT
        v_free.append(free_fit.v_inf)
        p_free.append(free_fit.p)
        # through-thickness: v(n layers) ~ v_n_inf + C n^-q, i.e. a fit in 1/n
        lf = level_fit(1.0 / np.array(layer_counts, float), v_layers[i])
        lay_lim.append(lf.v_inf)
        lay_err.append(lf.error)
        lay_corr.append(lf.v_inf - v_layers[i][list(layer_counts).index(lay)])
        mat = material(CASES[case][0])
        v_k.append(analytic.critical_voltage_plate(mat, 10.0, mindlin=False))
        v_m.append(analytic.critical_voltage_plate(mat, 10.0, mindlin=True))
        r = ramps[(case, finest_ramp)]
        v_rm = done[(critical_task, source(case), finest_ramp, RAMP_LAYERS)]["v"]
        v_cr_ramp_mesh.append(v_rm)
        v_sw.append(southwell(r.v, r.w_mid, v_guess=v_rm))
    v_ref = np.array(v_inf) + np.array(lay_corr)
    v_ref_err = np.array(err) + np.abs(np.array(lay_err))

    attrs1 = variable_attrs

    this_mesh = ("of this mesh: secant on the lowest eigenvalue to |dv| < 1e-6; the "
                 "discretisation error is what the sequence measures")
    crit = xr.Dataset(
        {
            "v_cr": (("case", "level"), vcr, attrs1(
                "normalised critical voltage Phi/t0 sqrt(eps/mu_ref) of the perfect film "
                "(linearised eigen-analysis)", accuracy=this_mesh)),
            "ndof": (("case", "level"), ndof, attrs1("degrees of freedom")),
            "nelements": (("case", "level"), nel, attrs1("prism elements")),
            "eig_residual": (("case", "level"), eig_res, attrs1(
                "relative eigen-residual ||S x - lambda M x||/||M x|| at v_cr")),
            "wall_seconds": (("case", "level"), secs, attrs1(
                "wall time of the critical-voltage computation (one thread)", "s")),
            "v_cr_extrapolated": (("case",), np.array(v_inf), attrs1(
                "in-plane mesh limit of v_cr at the sequence's layer count (fit_kind: "
                "v_inf + C h^q at the expected order q over the three finest levels when "
                "they show it, else a free-rate fit over all levels)",
                accuracy="+- v_cr_error")),
            "v_cr_error": (("case",), np.array(err), attrs1(
                "error estimate of the in-plane mesh limit (expected order: 3 x the largest "
                "of the fit residual, the distance from the three-point limit with a free "
                "rate and the change when the next coarser level is added; free rate: 3 x "
                "the largest of the drop-a-level change, the residual and the distance "
                "from the limit at the expected order)")),
            "fit_kind": (("case",), np.array(fit_kind, dtype=str), attrs1(
                "which fit gives v_cr_extrapolated")),
            "expected_order": (("case",), np.array(p_exp), attrs1(
                "asymptotic convergence order q of v_cr: 2 s(nu), s the Williams exponent "
                "of the clamped-free edge for the material's small-strain Poisson ratio")),
            "v_cr_fit_residual": (("case",), np.array(resid), attrs1(
                "largest |fit - v_cr| over the three finest levels")),
            "convergence_rate": (("case",), np.array(rate), attrs1(
                "observed convergence order of v_cr on the three finest levels")),
            "v_cr_free_fit": (("case",), np.array(v_free), attrs1(
                "mesh limit of a least-squares fit v_inf + C h^p with a free rate over all "
                "levels (a diagnostic: the coarse levels are pre-asymptotic)")),
            "free_fit_rate": (("case",), np.array(p_free), attrs1(
                "rate p of the free-rate fit over all levels")),
            "v_cr_layers": (("case", "layer_count"), v_layers, attrs1(
                "v_cr at the layer-study in-plane size versus layers through the thickness",
                accuracy=this_mesh)),
            "ndof_layers": (("case", "layer_count"), ndof_layers,
                            attrs1("degrees of freedom of the layer study")),
            "v_cr_layer_limit": (("case",), np.array(lay_lim), attrs1(
                "through-thickness limit of v_cr at the layer-study in-plane size (fit in "
                "1/layers; with two counts: the finer)", accuracy="+- v_cr_layer_error")),
            "v_cr_layer_error": (("case",), np.abs(np.array(lay_err)), attrs1(
                "error estimate of the through-thickness limit")),
            "layer_correction": (("case",), np.array(lay_corr), attrs1(
                "v_cr_layer_limit minus v_cr with the sequence's layer count, same mesh")),
            "v_cr_reference": (("case",), v_ref, attrs1(
                "reference critical voltage: in-plane limit plus through-thickness "
                "correction (errors assumed additive)", accuracy="+- v_cr_reference_error")),
            "v_cr_reference_error": (("case",), v_ref_err, attrs1(
                "error estimate of v_cr_reference: v_cr_error + v_cr_layer_error")),
            "v_cr_kirchhoff": (("case",), np.array(v_k), attrs1(
                "Kirchhoff clamped-plate estimate (14.68 D/a^2, compressible flat film)")),
            "v_cr_mindlin": (("case",), np.array(v_m), attrs1(
                "Mindlin (thick-plate) corrected clamped-plate estimate")),
            "v_cr_southwell": (("case",), np.array(v_sw), attrs1(
                "Southwell estimate from the ramp of the imperfect film (finest ramp mesh)")),
            "v_cr_ramp_mesh": (("case",), np.array(v_cr_ramp_mesh), attrs1(
                "eigen-analysis critical voltage on the finest ramp mesh")),
            "thickness_m": (("case",), np.array([CASES[c][1] for c in names]),
                            attrs1("initial thickness t0", "m")),
        },
        coords={"case": ("case", names, {"long_name": "material and thickness case"}),
                "level": ("level", np.arange(len(levels)), attrs1("mesh level")),
                "h_rel": ("level", np.array(levels), attrs1("in-plane mesh size / t0")),
                "layer_count": ("layer_count", np.array(layer_counts, dtype=np.int64),
                                attrs1("layers of quadratic prisms through the thickness"))},
    )
    rfin = {c: ramps[(c, finest_ramp)] for c in names}
    nstep = max(len(r.v) for r in rfin.values())
    neig = max(len(r.eig_v) for r in rfin.values())

    def pad(a, n, extra=()):
        out = np.full((n,) + extra, np.nan)
        out[: len(a)] = a
        return out

    data = {}
    for key, ln, unit in (("v", "normalised voltage Phi/t0 sqrt(eps/mu_ref)", "1"),
                          ("w", "vertical displacement of the top-surface centre / t0", "1"),
                          ("w_mid", "mean vertical displacement of top and bottom centre / t0",
                           "1"),
                          ("thickness", "current centre thickness / t0", "1"),
                          ("e_centre", "normalised true field at the centre E sqrt(eps/mu_ref)",
                           "1"),
                          ("e_max", "largest sampled normalised true field (mid-plane radius)",
                           "1")):
        data[key] = (("case", "step"),
                     np.array([pad(getattr(rfin[c], key), nstep) for c in names]),
                     attrs1(ln, unit))
    data["eig_v"] = (("case", "eig_record"), np.array([pad(rfin[c].eig_v, neig) for c in names]),
                     attrs1("normalised voltage of the eigen-analysis record"))
    data["eig_w"] = (("case", "eig_record"), np.array([pad(rfin[c].eig_w, neig) for c in names]),
                     attrs1("centre deflection / t0 of the eigen-analysis record"))
    data["eig_lambda"] = (("case", "eig_record", "mode"),
                          np.array([pad(rfin[c].eig_lam, neig, (3,)) for c in names]),
                          attrs1("lowest eigenvalues of the condensed tangent "
                                 "S u = lambda M u (M: L2 mass / t0^2)"))
    data["eig_axisymmetry"] = (("case", "eig_record", "mode"),
                               np.array([pad(rfin[c].eig_axisym, neig, (3,)) for c in names]),
                               attrs1("fraction of the mode in the angular harmonic n = 0"))
    data["eig_wavenumber"] = (("case", "eig_record", "mode"),
                              np.array([pad(rfin[c].eig_wavenumber, neig, (3,)) for c in names]),
                              attrs1("dominant angular harmonic of the mode (0: axisymmetric)"))

    rl = [rfin[c] for c in names]
    pullin_acc = "parabola through the voltage maximum of this mesh (< 1e-3 relative)"
    data["v_pullin"] = (("case",), np.array([r.v_pullin for r in rl]), attrs1(
        "pull-in on the finest ramp mesh: voltage limit point (vertex of the parabola v(w) "
        "through the maximum)", accuracy=pullin_acc))
    data["v_max_computed"] = (("case",), np.array([np.max(r.v) for r in rl]), attrs1(
        "largest normalised voltage among the computed path points"))
    data["w_pullin"] = (("case",), np.array([r.w_pullin for r in rl]), attrs1(
        "centre deflection / t0 at pull-in (finest ramp mesh)", accuracy=pullin_acc))
    data["thickness_pullin"] = (("case",), np.array([_at_pullin(r, r.thickness) for r in rl]),
                                attrs1("centre thickness / t0 at pull-in"))
    data["e_centre_pullin"] = (("case",), np.array([_at_pullin(r, r.e_centre) for r in rl]),
                               attrs1("normalised true centre field at pull-in"))
    data["e_max_pullin"] = (("case",), np.array([_at_pullin(r, r.e_max) for r in rl]),
                            attrs1("largest sampled normalised true field at pull-in"))

    def wrinkling(r) -> dict:
        f = first_instability(r.eig_w, r.eig_v, r.eig_lam, r.eig_axisym, r.eig_wavenumber)
        return f if f["kind"] == "non-axisymmetric" else {**f, "v": np.nan, "w": np.nan}

    first = [wrinkling(r) for r in rl]
    data["first_kind"] = (("case",), np.array([f["kind"] for f in first], dtype=str), {
        "long_name": "kind of the first instability along the finest ramp (first eigen-record "
        "with an eigenvalue <= 0): axisymmetric (pull-in), non-axisymmetric (wrinkling) or "
        "none"})
    data["v_wrinkling"] = (("case",), np.array([f["v"] for f in first]), attrs1(
        "normalised voltage at the onset of a non-axisymmetric mode when it is the first "
        "instability (NaN: pull-in or nothing comes first)"))
    data["w_wrinkling"] = (("case",), np.array([f["w"] for f in first]), attrs1(
        "centre deflection / t0 at the onset of a non-axisymmetric mode when it is the first "
        "instability (NaN: none)"))
    data["ndof"] = (("case",), np.array([r.ndof for r in rl]), attrs1("degrees of freedom"))
    # pull-in on every ramp level and its mesh limit
    by_level = {key: np.array([[getattr(ramps[(c, h)], key) for h in ramp_levels]
                               for c in names], float) for key in ("v_pullin", "w_pullin")}
    data["v_pullin_levels"] = (("case", "ramp_level"), by_level["v_pullin"], attrs1(
        "pull-in voltage per ramp mesh", accuracy=pullin_acc))
    data["w_pullin_levels"] = (("case", "ramp_level"), by_level["w_pullin"], attrs1(
        "centre deflection / t0 at pull-in per ramp mesh", accuracy=pullin_acc))
    data["v_wrinkling_levels"] = (("case", "ramp_level"), np.array(
        [[wrinkling(ramps[(c, h)])["v"] for h in ramp_levels] for c in names]), attrs1(
        "onset voltage of a non-axisymmetric mode as the first instability per ramp mesh "
        "(NaN: none)"))
    data["ndof_ramp_levels"] = (("case", "ramp_level"), np.array(
        [[ramps[(c, h)].ndof for h in ramp_levels] for c in names], dtype=np.int64),
        attrs1("degrees of freedom of the ramp meshes"))
    for key, ln in (("v_pullin", "pull-in voltage"), ("w_pullin", "pull-in deflection / t0")):
        fits = [level_fit(ramp_levels, by_level[key][i]) for i in range(len(names))]
        data[f"{key}_extrapolated"] = (("case",), np.array([f.v_inf for f in fits]), attrs1(
            f"mesh limit of the {ln} (fit v_inf + C h^p with three or more ramp levels; "
            "else the finest level)", accuracy=f"+- {key}_error"))
        data[f"{key}_error"] = (("case",), np.array([f.error for f in fits]), attrs1(
            f"error estimate of the mesh limit of the {ln} (NaN: one ramp level)"))
        data[f"{key}_rate"] = (("case",), np.array([f.p for f in fits]), attrs1(
            f"fitted convergence rate of the {ln} (NaN: fewer than three levels)"))
    data["thickness_m"] = (("case",), np.array([CASES[c][1] for c in names]),
                           attrs1("initial thickness t0", "m"))
    coords = {
        "case": ("case", names, {"long_name": "material and thickness case"}),
        "step": ("step", np.arange(nstep), attrs1("converged load step")),
        "eig_record": ("eig_record", np.arange(neig), attrs1("eigen-analysis record")),
        "mode": ("mode", np.arange(3), attrs1("mode index (ascending eigenvalue)")),
        "ramp_level": ("ramp_level", np.array(ramp_levels), attrs1(
            "in-plane mesh size / t0 of the ramp"))}
    data["min_nonaxisymmetric_lambda"] = (("case",), np.array([_min_nonaxisym(r) for r in rl]),
                                          attrs1("smallest eigenvalue of a non-axisymmetric "
                                                 "mode recorded before pull-in"))
    ramp_ds = xr.Dataset(data, coords=coords)
    nh, og = material("nh"), material("ogden")
    params = {"mu_ref_Pa": MU_REF, "nh_mu_Pa": nh.mu, "k_Pa": nh.k,
              "ogden_alphas": list(og.alphas), "ogden_mus_Pa": list(og.mus),
              "ogden_delta": OGDEN_DELTA, "aspect": 10.0, "imperfection_rel": 1e-3,
              "imperfection_shape": "t0*1e-3*(1-r^2/a^2)^2", "eps_r": 4.7, "layers": lay,
              "order": ORDER, "levels_h_rel": list(levels), "ramp_h_rel": list(ramp_levels),
              "ramp_layers": RAMP_LAYERS,
              "layer_study_h_rel": h_ls, "layer_counts": list(layer_counts),
              "full": full, "ramp_dc_over_t0": 0.2, "ramp_dv_max": RAMP_DV_MAX,
              "eig_every": EIG_EVERY, "fit_safety": FIT_SAFETY,
              "scale_copies": ", ".join(f"{a} = {b}" for a, b in SCALE_COPIES.items())}
    return crit, ramp_ds, params


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
    from debench.models.buckling.parameters import Plate
    from debench.reference.figures import LABELS, pyplot, save
    plt = pyplot()
    fig_dir.mkdir(parents=True, exist_ok=True)
    out = []
    # Fig 5.4: thickness study (Ogden), deflection in mm vs voltage in kV (eps_r 4.7)
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
    out += save(fig, fig_dir / "fig5_4_deflection_voltage_thickness")
    # Fig 5.6: material study at 1 mm
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
    out += save(fig, fig_dir / "fig5_6_deflection_voltage_material")
    # Fig 5.5 counterpart: the lowest non-axisymmetric eigenvalue along the path
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
    out += save(fig, fig_dir / "fig5_5_nonaxisymmetric_modes")
    # convergence: critical voltage (in-plane), pull-in (ramps), through-thickness
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
    out += save(fig, fig_dir / "fig5_x_critical_voltage_convergence")
    return out


def converged_only(name: str, levels) -> bool:
    """Whether the build of a converged-only chapter has nothing to compute (no mesh
    ``levels`` in this mode, the default build): then it says so on stderr."""
    if len(levels):
        return False
    print(f"{name}: converged-only (run with --full); nothing written", file=sys.stderr)
    return True


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
