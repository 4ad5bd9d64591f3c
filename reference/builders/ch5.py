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

``full=False``: coarse meshes (in-plane size 3, 2, 1.4, 1 t0; ramps at 2 t0), minutes on
one core.  ``full=True``: refined meshes (down to 0.5 t0; ramps at 1 t0), hours.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import xarray as xr
from debench.reference.datasets import write_dataset
from scipy.optimize import brentq

CASES = {  # name: (material, thickness [m])
    "nh_t1": ("nh", 1e-3),
    "ogden_t1": ("ogden", 1e-3),
    "ogden_t0p5": ("ogden", 0.5e-3),
}
LEVELS = {False: (3.0, 2.0, 1.4, 1.0), True: (2.0, 1.4, 1.0, 0.7, 0.5)}
RAMP_H = {False: 2.0, True: 1.0}
LAYERS = 1          # through-thickness: 1 layer of quadratic prisms (2 layers change the
                    # critical voltage by < 0.4 %, see verification/test_ch5_fem.py)
ORDER = 2
EIG_EVERY = 4


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


def compute(full: bool = False, progress: bool = True):
    """Run the FE computations; returns (critical dataset, ramps dataset, parameters)."""
    import ngsolve
    from debench.models.buckling import analytic
    from debench.models.buckling.parameters import MU_REF, Discretisation, Plate
    from debench.models.buckling.solver import critical_voltage, southwell, voltage_ramp
    ngsolve.SetNumThreads(int(os.environ.get("OMP_NUM_THREADS", "1")))
    try:
        from tqdm import tqdm
    except ImportError:  # pragma: no cover
        tqdm = None
    levels = LEVELS[full]
    work = [(c, h) for c in CASES for h in levels]
    bar = tqdm(total=len(work) + len(CASES), desc="ch5 FE", disable=not progress) if tqdm else None
    vcr = np.full((len(CASES), len(levels)), np.nan)
    ndof = np.zeros((len(CASES), len(levels)), dtype=np.int64)
    nel = np.zeros_like(ndof)
    for i, case in enumerate(CASES):
        mat_name, t0 = CASES[case]
        for j, h in enumerate(levels):
            r = critical_voltage(Plate(thickness=t0), _material(mat_name),
                                 Discretisation(h_rel=h, layers=LAYERS, order=ORDER))
            vcr[i, j], ndof[i, j], nel[i, j] = r.v, r.ndof, r.nelements
            if bar:
                bar.set_postfix(case=case, h=h, v_cr=f"{r.v:.5f}")
                bar.update()
    ramps = {}
    for case in CASES:
        mat_name, t0 = CASES[case]
        ramps[case] = voltage_ramp(Plate(thickness=t0), _material(mat_name),
                                   Discretisation(h_rel=RAMP_H[full], layers=LAYERS, order=ORDER),
                                   eig_every=EIG_EVERY)
        if bar:
            bar.set_postfix(case=case, v_pullin=f"{ramps[case].v_pullin}")
            bar.update()
    if bar:
        bar.close()

    names = list(CASES)
    v_inf, rate, v_k, v_m, v_sw, v_cr_ramp_mesh = [], [], [], [], [], []
    for i, case in enumerate(names):
        vi, p = richardson(np.array(levels), vcr[i])
        v_inf.append(vi)
        rate.append(p)
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
                "Richardson limit of v_cr (fit v_inf + C h^p, last three levels)")),
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
    params = {"mu_ref_Pa": MU_REF, "nh_mu_Pa": 156000.0, "k_Pa": 7748003.92,
              "ogden_alphas": [1.293, 2.3252, 2.561], "ogden_mus_Pa": [8580.0, 84300.0, -23300.0],
              "ogden_delta": 1e-3, "aspect": 10.0, "imperfection_rel": 1e-3,
              "imperfection_shape": "t0*1e-3*(1-r^2/a^2)^2", "eps_r": 4.7, "layers": LAYERS,
              "order": ORDER, "levels_h_rel": list(levels), "ramp_h_rel": RAMP_H[full],
              "full": full, "ramp_dc_over_t0": 0.2}
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


def build(out_dir: Path, *, full: bool = False) -> list[Path]:
    """Compute and write the Chapter 5 datasets and figures into ``out_dir``."""
    out_dir = Path(out_dir)
    crit, ramps, params = compute(full=full)
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
