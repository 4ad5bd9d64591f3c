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

import os
from pathlib import Path

import numpy as np
import xarray as xr
from debench.models.errors import ConvergenceError
from debench.models.materials.constants import OGDEN_DELTA
from debench.reference.datasets import write_dataset
from scipy.optimize import brentq

CASES = {  # name: (material, thickness [m])
    "nh_t1": ("nh", 1e-3),
    "ogden_t1": ("ogden", 1e-3),
    "ogden_t0p5": ("ogden", 0.5e-3),
}
SCALE_COPIES = {"ogden_t0p5": "ogden_t1"}
"""Cases identical in normalised variables by scale invariance (radius/thickness fixed: no
intrinsic length; ``verification/test_ch5_fem.py::test_normalised_results_are_scale_invariant``
checks it on the coarse mesh): computed once, from the case they copy."""
LEVELS = {False: (3.0, 2.0, 1.4), True: (2.0, 1.4, 1.0, 0.7, 0.5)}
RAMP_H = {False: 3.0, True: 1.0}
LAYERS = 1          # through-thickness: 1 layer of quadratic prisms (2 layers change the
                    # critical voltage by < 0.4 %, see verification/test_ch5_fem.py)
ORDER = 2
EIG_EVERY = 4
RAMP_DV_MAX = 0.02  # largest voltage step of the ramps (normalised): >= 3 points in the
                    # Southwell window 0.4-0.9 v_cr of the Ogden case (v_cr ~ 0.17)
GUARD_DV_MAX = 0.04  # coarse_values(): only the pull-in is needed (step-independent to
                     # the parabola's accuracy)
COARSE_H = 3.0      # the coarsest level: what coarse_values() and `debench verify` recompute


def _material(name):
    from debench.models.buckling.parameters import NeoHookean, Ogden
    return NeoHookean() if name == "nh" else Ogden()


def richardson(h, v):
    """Fit v = v_inf + C h^p through the last three levels; returns (v_inf, p)."""
    h1, h2, h3 = h[-3:]
    v1, v2, v3 = v[-3:]
    ratio = (v1 - v2) / (v2 - v3)

    def f(p):
        return (h1**p - h2**p) / (h2**p - h3**p) - ratio

    p = brentq(f, 0.05, 8.0)
    c = (v2 - v3) / (h2**p - h3**p)
    return v3 - c * h3**p, p


#: On synthetic sequences v_inf + C h^1.7 + D h^3 with the h^3 term 1-4 % of the leading
#: one at the coarsest level (5 levels, h = 3 ... 0.7), the true error of the fitted limit
#: was up to 2x the larger of (drop-a-level change, fit residual); 3x covers it.
FIT_SAFETY = 3.0


def convergence_fit(h, v) -> dict[str, float]:
    """Mesh limit of ``v(h) = v_inf + C h^p`` with an error estimate.

    Three levels: the exact three-point fit (:func:`richardson`); its error estimate is
    the distance of the limit from the finest level (no redundancy to do better). Four or
    more levels (more levels than unknowns): least squares over all levels (log-spaced
    start from the three-point fit); the error estimate is :data:`FIT_SAFETY` times the
    larger of the change of the limit when the coarsest level is dropped and the largest
    fit residual. Returns
    ``v_inf``, ``p``, ``error``, ``residual`` (largest |fit - v|, 0 for three levels).
    """
    from scipy.optimize import least_squares

    h, v = np.asarray(h, float), np.asarray(v, float)
    if h.size < 3:
        raise ValueError(f"convergence_fit needs >= 3 levels, got {h.size}")
    v3, p3 = richardson(h, v)
    if h.size == 3:
        return {"v_inf": float(v3), "p": float(p3), "error": float(abs(v3 - v[-1])),
                "residual": 0.0}
    scale = abs(v[-1] - v[-2]) or 1.0

    def fit(hh, vv, start):
        c0 = (vv[-1] - start[0]) / hh[-1] ** start[1]
        res = least_squares(lambda x: (x[0] + x[1] * hh**x[2] - vv) / scale,
                            [start[0], c0, start[1]], bounds=([-np.inf, -np.inf, 0.05],
                                                              [np.inf, np.inf, 8.0]))
        if not res.success:
            raise ConvergenceError(f"convergence_fit: least squares failed ({res.message})")
        return res.x, float(np.max(np.abs(res.fun))) * scale

    (vi, _, p), resid = fit(h, v, (v3, p3))
    dropped = fit(h[1:], v[1:], (v3, p3))[0][0] if h.size >= 4 else vi
    return {"v_inf": float(vi), "p": float(p), "residual": float(resid),
            "error": FIT_SAFETY * float(max(abs(vi - dropped), resid))}


# ------------------------------------------------------------------ tasks (plain data out)
def _limit_threads():
    """One thread for BLAS and NGSolve's TaskManager in this process (a Dask worker runs
    one task per process; nothing oversubscribes): :func:`debench.threads.limit_threads`."""
    import ngsolve  # noqa: F401 - loaded first so that its TaskManager is limited too

    from debench.threads import limit_threads

    limit_threads(1)


def critical_task(case: str, h_rel: float) -> dict:
    """One critical-voltage computation as plain data (a Dask task)."""
    from debench.models.buckling.parameters import Discretisation, Plate
    from debench.models.buckling.solver import critical_voltage
    _limit_threads()
    mat_name, t0 = CASES[case]
    r = critical_voltage(Plate(thickness=t0), _material(mat_name),
                         Discretisation(h_rel=h_rel, layers=LAYERS, order=ORDER))
    return {"v": r.v, "ndof": r.ndof, "nelements": r.nelements, "eig_residual": r.eig_residual,
            "newton_residual": r.newton_residual}


def ramp_task(case: str, h_rel: float, eig_every: int = EIG_EVERY,
              dv_max: float = RAMP_DV_MAX) -> dict:
    """One voltage ramp as plain data (a Dask task): the RampResult fields."""
    import dataclasses

    from debench.models.buckling.parameters import Discretisation, Plate
    from debench.models.buckling.solver import voltage_ramp
    _limit_threads()
    mat_name, t0 = CASES[case]
    r = voltage_ramp(Plate(thickness=t0), _material(mat_name),
                     Discretisation(h_rel=h_rel, layers=LAYERS, order=ORDER),
                     dv_max=dv_max, eig_every=eig_every)
    return {f.name: getattr(r, f.name) for f in dataclasses.fields(r)}


def run_tasks(tasks: list[tuple], scheduler=None, progress: bool = True) -> list:
    """Run ``(function, *args)`` tasks serially (``scheduler=None``) or on Dask
    ``distributed``: ``"local"`` starts a LocalCluster sized to the machine (one process per
    core, one thread each), any other string is the address of an existing scheduler
    (e.g. one started by dask-jobqueue on SLURM/PBS or by dask-kubernetes).  Results come
    back in task order."""
    if scheduler is None:
        out = []
        try:
            from tqdm import tqdm
        except ImportError:  # pragma: no cover
            tqdm = None
        it = tqdm(tasks, desc="ch5 FE", disable=not progress) if tqdm else tasks
        for fn, *args in it:
            out.append(fn(*args))
        return out
    from distributed import Client, LocalCluster
    if scheduler == "local":
        n = os.cpu_count() or 1
        with LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                          dashboard_address=None) as cluster, Client(cluster) as client:
            return client.gather([client.submit(fn, *args, pure=False)
                                  for fn, *args in tasks])
    with Client(scheduler) as client:
        return client.gather([client.submit(fn, *args, pure=False) for fn, *args in tasks])


def coarse_values(*, cases=tuple(CASES)) -> dict[str, float]:
    """The coarsest level of every case, recomputed now (what ``debench verify`` guards).

    Keys (stable): ``"<case>.v_cr"`` -- critical voltage on the coarsest mesh (h = 3 t0,
    one layer of quadratic prisms), for every case; ``"<case>.v_pullin"`` and
    ``"<case>.w_pullin"`` -- pull-in voltage and centre deflection / t0 of the ramp on the
    same mesh (no eigen-analysis along the path), for the cases that are not scale copies
    (``nh_t1``, ``ogden_t1``).  Accuracy: v_cr to the secant's |dv| < 1e-6; pull-in to the
    parabola through the maximum (< 1e-3 relative, see ``voltage_ramp``).
    """
    out = {}
    for case in cases:
        out[f"{case}.v_cr"] = float(critical_task(case, COARSE_H)["v"])
    for case in cases:
        if case in SCALE_COPIES:
            continue
        r = ramp_task(case, COARSE_H, eig_every=0, dv_max=GUARD_DV_MAX)
        out[f"{case}.v_pullin"] = float(r["v_pullin"])
        out[f"{case}.w_pullin"] = float(r["w_pullin"])
    return out


def compute(full: bool = False, progress: bool = True, scheduler=None):
    """Run the FE computations; returns (critical dataset, ramps dataset, parameters).

    Every (case, level) critical voltage and every ramp is an independent task (run
    serially, or on Dask with ``scheduler``); scale copies (:data:`SCALE_COPIES`) are
    filled from the case they copy.
    """
    from debench.models.buckling import analytic
    from debench.models.buckling.parameters import MU_REF
    from debench.models.buckling.solver import RampResult, southwell
    levels = LEVELS[full]
    computed = [c for c in CASES if c not in SCALE_COPIES]
    tasks = ([(critical_task, c, h) for c in computed for h in levels]
             + [(ramp_task, c, RAMP_H[full]) for c in computed])
    results = run_tasks(tasks, scheduler=scheduler, progress=progress)
    crit_res = {(c, h): results[k] for k, (c, h) in
                enumerate((c, h) for c in computed for h in levels)}
    ramps = {c: RampResult(**results[len(computed) * len(levels) + k])
             for k, c in enumerate(computed)}
    for copy, source in SCALE_COPIES.items():
        for h in levels:
            crit_res[(copy, h)] = crit_res[(source, h)]
        ramps[copy] = ramps[source]
    vcr = np.array([[crit_res[(c, h)]["v"] for h in levels] for c in CASES])
    ndof = np.array([[crit_res[(c, h)]["ndof"] for h in levels] for c in CASES], dtype=np.int64)
    nel = np.array([[crit_res[(c, h)]["nelements"] for h in levels] for c in CASES],
                   dtype=np.int64)

    names = list(CASES)
    v_inf, rate, err, v_k, v_m, v_sw, v_cr_ramp_mesh = [], [], [], [], [], [], []
    for i, case in enumerate(names):
        fitted = convergence_fit(np.array(levels), vcr[i])
        v_inf.append(fitted["v_inf"])
        rate.append(fitted["p"])
        err.append(fitted["error"])
        mat = _material(CASES[case][0])
        v_k.append(analytic.critical_voltage_plate(mat, 10.0, mindlin=False))
        v_m.append(analytic.critical_voltage_plate(mat, 10.0, mindlin=True))
        r = ramps[case]
        j_ramp = list(levels).index(RAMP_H[full]) if RAMP_H[full] in levels else -1
        v_cr_ramp_mesh.append(vcr[i, j_ramp])
        v_sw.append(southwell(r.v, r.w_mid, v_guess=vcr[i, j_ramp]))
    attrs1 = lambda ln, u="1": {"long_name": ln, "units": u}  # noqa: E731
    crit = xr.Dataset(
        {
            "v_cr": (("case", "level"), vcr, attrs1(
                "normalised critical voltage Phi/t0 sqrt(eps/mu_ref) of the perfect film "
                "(linearised eigen-analysis)")),
            "ndof": (("case", "level"), ndof, attrs1("degrees of freedom")),
            "nelements": (("case", "level"), nel, attrs1("prism elements")),
            "v_cr_extrapolated": (("case",), np.array(v_inf), attrs1(
                "mesh limit of v_cr (fit v_inf + C h^p over all levels; exact through "
                "three)")),
            "v_cr_error": (("case",), np.array(err), attrs1(
                "error estimate of the mesh limit (dropping the coarsest level, fit "
                "residual; with three levels: distance to the finest level)")),
            "convergence_rate": (("case",), np.array(rate), attrs1(
                "fitted convergence rate p of v_cr in the in-plane mesh size")),
            "v_cr_kirchhoff": (("case",), np.array(v_k), attrs1(
                "Kirchhoff clamped-plate estimate (14.68 D/a^2, compressible flat film)")),
            "v_cr_mindlin": (("case",), np.array(v_m), attrs1(
                "Mindlin (thick-plate) corrected clamped-plate estimate")),
            "v_cr_southwell": (("case",), np.array(v_sw), attrs1(
                "Southwell estimate from the ramp of the imperfect film (ramp mesh)")),
            "v_cr_ramp_mesh": (("case",), np.array(v_cr_ramp_mesh), attrs1(
                "eigen-analysis critical voltage on the ramp mesh")),
            "thickness_m": (("case",), np.array([CASES[c][1] for c in names]),
                            attrs1("initial thickness t0", "m")),
        },
        coords={"case": ("case", names, {"long_name": "material and thickness case"}),
                "level": ("level", np.arange(len(levels)), attrs1("mesh level")),
                "h_rel": ("level", np.array(levels), attrs1("in-plane mesh size / t0"))},
    )
    nstep = max(len(r.v) for r in ramps.values())
    neig = max(len(r.eig_v) for r in ramps.values())

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
                     np.array([pad(getattr(ramps[c], key), nstep) for c in names]),
                     attrs1(ln, unit))
    data["eig_v"] = (("case", "eig_record"), np.array([pad(ramps[c].eig_v, neig) for c in names]),
                     attrs1("normalised voltage of the eigen-analysis record"))
    data["eig_w"] = (("case", "eig_record"), np.array([pad(ramps[c].eig_w, neig) for c in names]),
                     attrs1("centre deflection / t0 of the eigen-analysis record"))
    data["eig_lambda"] = (("case", "eig_record", "mode"),
                          np.array([pad(ramps[c].eig_lam, neig, (3,)) for c in names]),
                          attrs1("smallest-|lambda| eigenvalues of the condensed tangent "
                                 "S u = lambda M u (M: L2 mass / t0^2)"))
    data["eig_axisymmetry"] = (("case", "eig_record", "mode"),
                               np.array([pad(ramps[c].eig_axisym, neig, (3,)) for c in names]),
                               attrs1("fraction of the mode in the angular harmonic n = 0"))
    def at_pullin(r, arr):
        w = r.w
        k = int(np.argmax(r.v))
        return float(np.interp(r.w_pullin, w[: k + 2], arr[: k + 2]))

    rl = [ramps[c] for c in names]
    data["v_pullin"] = (("case",), np.array([r.v_pullin for r in rl]), attrs1(
        "pull-in: voltage limit point (vertex of the parabola v(w) through the maximum)"))
    data["v_max_computed"] = (("case",), np.array([np.max(r.v) for r in rl]), attrs1(
        "largest normalised voltage among the computed path points"))
    data["w_pullin"] = (("case",), np.array([r.w_pullin for r in rl]), attrs1(
        "centre deflection / t0 at pull-in"))
    data["thickness_pullin"] = (("case",), np.array([at_pullin(r, r.thickness) for r in rl]),
                                attrs1("centre thickness / t0 at pull-in"))
    data["e_centre_pullin"] = (("case",), np.array([at_pullin(r, r.e_centre) for r in rl]),
                               attrs1("normalised true centre field at pull-in"))
    data["e_max_pullin"] = (("case",), np.array([at_pullin(r, r.e_max) for r in rl]),
                            attrs1("largest sampled normalised true field at pull-in"))
    won = [r.wrinkling_onset() for r in ramps.values()]
    data["v_wrinkling"] = (("case",), np.array([w[0] if w else np.nan for w in won]), attrs1(
        "normalised voltage at the onset of a non-axisymmetric mode (NaN: none before pull-in)"))
    data["w_wrinkling"] = (("case",), np.array([w[1] if w else np.nan for w in won]), attrs1(
        "centre deflection / t0 at the onset of a non-axisymmetric mode (NaN: none)"))
    data["ndof"] = (("case",), np.array([r.ndof for r in ramps.values()]),
                    attrs1("degrees of freedom"))
    data["thickness_m"] = (("case",), np.array([CASES[c][1] for c in names]),
                           attrs1("initial thickness t0", "m"))
    ramp_ds = xr.Dataset(data, coords={
        "case": ("case", names, {"long_name": "material and thickness case"}),
        "step": ("step", np.arange(nstep), attrs1("converged load step")),
        "eig_record": ("eig_record", np.arange(neig), attrs1("eigen-analysis record")),
        "mode": ("mode", np.arange(3), attrs1("mode index (ascending eigenvalue)"))})
    nh, og = _material("nh"), _material("ogden")
    params = {"mu_ref_Pa": MU_REF, "nh_mu_Pa": nh.mu, "k_Pa": nh.k,
              "ogden_alphas": list(og.alphas), "ogden_mus_Pa": list(og.mus),
              "ogden_delta": OGDEN_DELTA, "aspect": 10.0, "imperfection_rel": 1e-3,
              "imperfection_shape": "t0*1e-3*(1-r^2/a^2)^2", "eps_r": 4.7, "layers": LAYERS,
              "order": ORDER, "levels_h_rel": list(levels), "ramp_h_rel": RAMP_H[full],
              "full": full, "ramp_dc_over_t0": 0.2, "ramp_dv_max": RAMP_DV_MAX,
              "scale_copies": ", ".join(f"{a} = {b}" for a, b in SCALE_COPIES.items())}
    return crit, ramp_ds, params


def figures(crit, ramps, fig_dir: Path) -> list[Path]:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from debench.models.buckling.parameters import Plate
    fig_dir.mkdir(parents=True, exist_ok=True)
    out = []
    # Fig 5.4: thickness study (Ogden), deflection in mm vs voltage in kV (eps_r 4.7)
    fig, axs = plt.subplots(1, 2, figsize=(10, 4))
    for case, style in (("ogden_t1", "-"), ("ogden_t0p5", "--")):
        r = ramps.sel(case=case)
        t0 = float(r.thickness_m)
        ok = np.isfinite(r.v.values)
        pl = Plate(thickness=t0)
        axs[0].plot(r.v.values[ok], r.w.values[ok] * t0 * 1e3, style, label=f"t0 = {t0 * 1e3:g} mm")
        axs[1].plot([pl.volts(x) / 1e3 for x in r.v.values[ok]], r.w.values[ok] * t0 * 1e3, style,
                    label=f"t0 = {t0 * 1e3:g} mm")
        axs[0].plot(float(r.v_pullin), float(r.w_pullin) * t0 * 1e3, "ko")
    axs[0].set_xlabel("normalised voltage Phi/t0 sqrt(eps/mu), mu = 156 kPa")
    axs[1].set_xlabel("voltage (kV), eps_r = 4.7")
    for ax in axs:
        ax.set_ylabel("centre deflection (mm)")
        ax.legend()
    fig.suptitle("Fig 5.4 (debench): Ogden plates, radius/thickness 10; dot = pull-in")
    p = fig_dir / "fig5_4_deflection_voltage_thickness.png"
    fig.savefig(p, dpi=110, bbox_inches="tight")
    plt.close(fig)
    out.append(p)
    # Fig 5.6: material study at 1 mm
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for case, style, lab in (("nh_t1", "-", "neo-Hookean"), ("ogden_t1", "--", "Ogden")):
        r = ramps.sel(case=case)
        ok = np.isfinite(r.v.values)
        ax.plot(r.v.values[ok], r.w.values[ok], style, label=lab)
        ax.plot(float(r.v_pullin), float(r.w_pullin), "ko")
    ax.set_xlabel("normalised voltage Phi/t0 sqrt(eps/mu), mu = 156 kPa")
    ax.set_ylabel("centre deflection / t0")
    ax.legend()
    ax.set_title("Fig 5.6 (debench): t0 = 1 mm; dot = pull-in")
    p = fig_dir / "fig5_6_deflection_voltage_material.png"
    fig.savefig(p, dpi=110, bbox_inches="tight")
    plt.close(fig)
    out.append(p)
    # convergence of the critical voltage
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for case in crit.case.values:
        c = crit.sel(case=case)
        err = np.abs(c.v_cr.values - float(c.v_cr_extrapolated))
        ax.loglog(crit.h_rel.values, err, "o-",
                  label=f"{case} (p = {float(c.convergence_rate):.2f})")
    ax.set_xlabel("in-plane mesh size / t0")
    ax.set_ylabel("|v_cr - Richardson limit|")
    ax.legend()
    p = fig_dir / "fig5_x_critical_voltage_convergence.png"
    fig.savefig(p, dpi=110, bbox_inches="tight")
    plt.close(fig)
    out.append(p)
    return out


def build(out_dir: Path, *, full: bool = False, scheduler: str | None = None) -> list[Path]:
    """Compute and write the Chapter 5 datasets and figures into ``out_dir``.

    ``scheduler``: None runs the FE tasks serially; ``"local"`` on a Dask LocalCluster
    sized to the machine; an address on an existing Dask scheduler.  ``full=True`` without
    a scheduler uses ``"local"``.
    """
    out_dir = Path(out_dir)
    if full and scheduler is None:
        scheduler = "local"
    crit, ramps, params = compute(full=full, scheduler=scheduler)
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
