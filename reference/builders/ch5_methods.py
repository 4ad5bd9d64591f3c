"""Chapter 5: three methods for the critical voltage, the incompressible limit, and the
Figs 5.4 / 5.6 counterparts with the thesis' printed values overlaid.

``build(out_dir, full=False)`` writes

* ``ch5_methods.nc`` --

  - the critical normalised voltage of the perfect neo-Hookean film (Table 5.1, R/t0 = 10)
    by the three linearised buckling models of
    :mod:`debench.models.buckling.initial_stress` (``initial_stress``: purely mechanical,
    stress stiffness of the flat state's total stress; ``frozen_potential``; ``coupled``:
    the electromechanical eigen-analysis) on one mesh sequence, their mesh limits, and the
    Kirchhoff and Mindlin clamped-plate estimates
    (:func:`debench.models.buckling.analytic.critical_voltage_plate`): the decomposition of
    the difference between the coupled value and the plate estimates into
    electromechanical coupling (coupled vs initial stress, same mesh), transverse shear /
    3D mechanics (initial stress vs Mindlin vs Kirchhoff) and mesh (the sequence);
  - the coupled critical voltage for a sequence of bulk moduli k/mu -> infinity (the
    thesis' "J = 1" vs Table 5.1's k) with quadratic and cubic elements (the locking
    check: quadratic prisms lock as k/mu grows, the cubic ones much less), and the
    extrapolation to k/mu = infinity;

* figures (PNG and SVG): ``fig5_4_overlay`` and ``fig5_6_overlay`` (the ramps of
  ``ch5_ramps.nc`` with the thesis' printed pull-in / critical / wrinkling values as
  printed and converted under the "mu in MPa" hypothesis, factor sqrt(0.156) = 0.395),
  ``ch5_methods_convergence``.

``full=False``: meshes h = 3, 2 t0 (about a minute on one core); ``full=True``: h = 3, 2,
1.4, 1 t0 for the methods and h = 3, 2 for the bulk-modulus study (minutes).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import xarray as xr
from debench.models.buckling.analytic import critical_voltage_plate
from debench.models.buckling.initial_stress import linearised_critical_voltage
from debench.models.buckling.parameters import Discretisation, NeoHookean, Plate
from debench.models.numerics import convergence_fit, propagated_accuracy
from debench.reference import catalogue
from debench.reference import figures as style
from debench.reference.datasets import read_dataset, variable_attrs, write_dataset

#: CPU seconds of the default build (one thread, measured in one `debench reproduce` with
#: two pool processes on the quiet 2-core machine): the pool starts the longest first.
BUILD_CPU_S = 26.0
#: ``debench verify`` does not rebuild this chapter (minutes of CPU, or the catalogue itself):
#: its model guards and the value check stand for it.
REGENERATED_BY_VERIFY = False
#: Model guards ``debench verify`` runs for this chapter (none).
GUARDS = {}

NAME = "ch5_methods"
METHODS = ("initial_stress", "frozen_potential", "coupled")
LEVELS = {False: (3.0, 2.0), True: (3.0, 2.0, 1.4, 1.0)}
K_RATIOS = (None, 200.0, 1000.0, 1e4)
"""Bulk modulus / shear modulus of the incompressibility study; None: Table 5.1's k."""
K_LEVELS = {False: (3.0,), True: (3.0, 2.0)}
K_ORDERS = (2, 3)
LAYERS = 1
ORDER = 2
ASPECT = 10.0
K_VTOL = 1e-7
"""Fixed-point stop of the bulk-modulus study: at k/mu = 1e4 the eigenvalues of the
condensed tangent carry ~1e-7 of round-off (the conditioning grows like k/mu; measured
secant noise of the engine at k/mu = 1e4, order 3), so 1e-9 would chase noise; 1e-7 is
5e-7 relative, far below the effects reported (percent)."""
MU_IN_MPA_FACTOR = math.sqrt(0.156)
"""The "mu in MPa" hypothesis: thesis voltage = ours x sqrt(0.156 MPa / 1 MPa)."""


def _nh(k_ratio=None):
    if k_ratio is None:
        return NeoHookean()
    base = NeoHookean()
    return NeoHookean(mu=base.mu, k=k_ratio * base.mu)


def limit_in_inverse_k(k_ratios, v) -> tuple[float, float]:
    """Limit k/mu -> infinity of ``v(k) = v_inf + c mu/k`` fitted through the two stiffest
    bulk moduli; error estimate: the change of the limit when the fit uses the second and
    third stiffest instead (the O((mu/k)^2) term)."""
    x = 1.0 / np.asarray(k_ratios, float)
    v = np.asarray(v, float)
    order = np.argsort(x)
    x, v = x[order], v[order]

    def lin(i, j):
        return v[i] - x[i] * (v[j] - v[i]) / (x[j] - x[i])

    lim = lin(0, 1)
    err = abs(lim - lin(1, 2)) if len(x) >= 3 else abs(v[1] - v[0])
    return float(lim), float(err)


def _methods_study(levels, plate, mat) -> dict:
    """The critical voltage of every linearised buckling method on every mesh level, with
    each method's mesh limit (convergence fit; NaN with fewer than three levels)."""
    v = np.zeros((len(METHODS), len(levels)))
    res = np.zeros_like(v)
    ndof = np.zeros_like(v, dtype=np.int64)
    for i, m in enumerate(METHODS):
        for j, h in enumerate(levels):
            r = linearised_critical_voltage(plate, mat, Discretisation(h_rel=h, layers=LAYERS,
                                                                      order=ORDER), method=m)
            v[i, j], res[i, j], ndof[i, j] = r.v, r.eig_residual, r.ndof_u
    lim = np.full(len(METHODS), np.nan)
    err = np.full(len(METHODS), np.nan)
    if len(levels) >= 3:
        for i in range(len(METHODS)):
            fit = convergence_fit(np.array(levels), v[i])
            lim[i], err[i] = fit.v_inf, fit.error
    return {"v": v, "res": res, "ndof": ndof, "lim": lim, "err": err}


def _k_study(k_levels, plate, mat) -> dict:
    """The coupled critical voltage for every bulk modulus of K_RATIOS, order and mesh level,
    its limit k/mu -> infinity with its error estimate and their regeneration accuracy
    (``kacc``), and the Kirchhoff plate estimate per bulk modulus."""
    kr = np.array([mat.k / mat.mu if k is None else k for k in K_RATIOS])
    vk = np.zeros((len(K_RATIOS), len(K_ORDERS), len(k_levels)))
    for a, k in enumerate(K_RATIOS):
        for b, order in enumerate(K_ORDERS):
            for c, h in enumerate(k_levels):
                vk[a, b, c] = linearised_critical_voltage(
                    plate, _nh(k), Discretisation(h_rel=h, layers=LAYERS, order=order),
                    method="coupled", vtol=K_VTOL).v
    klim = np.zeros((len(K_ORDERS), len(k_levels)))
    kerr = np.zeros_like(klim)
    for b in range(len(K_ORDERS)):
        for c in range(len(k_levels)):
            klim[b, c], kerr[b, c] = limit_in_inverse_k(kr, vk[:, b, c])
    plate_k = np.array([critical_voltage_plate(_nh(k), ASPECT, mindlin=False)
                        for k in K_RATIOS])
    # regenerations of a k-study voltage differ by up to twice the fixed point's tolerance
    # K_VTOL; the limit and its error estimate by what that moves them (the error estimate
    # is a difference of nearly equal extrapolations: its relative accuracy is poor)
    kacc = {name: float(np.max([propagated_accuracy(lambda x, i=i: limit_in_inverse_k(kr, x)[i],
                                                    vk[:, b, c], 2 * K_VTOL)
                                for b in range(len(K_ORDERS))
                                for c in range(len(k_levels))]))
            for i, name in enumerate(("v_cr_k_limit", "v_cr_k_limit_error"))}
    return {"kr": kr, "vk": vk, "klim": klim, "kerr": kerr, "plate_k": plate_k, "kacc": kacc}


def compute(full: bool = False) -> tuple[xr.Dataset, dict]:
    levels = LEVELS[full]
    plate = Plate(aspect=ASPECT)
    mat = _nh()
    m = _methods_study(levels, plate, mat)
    v, res, ndof, lim, err = (m[k] for k in ("v", "res", "ndof", "lim", "err"))
    k_levels = K_LEVELS[full]
    ks = _k_study(k_levels, plate, mat)
    kr, vk, klim, kerr, plate_k, kacc = (ks[k] for k in ("kr", "vk", "klim", "kerr",
                                                         "plate_k", "kacc"))

    a = variable_attrs

    ds = xr.Dataset(
        {
            "v_cr": (("method", "level"), v, a(
                "normalised critical voltage Phi/t0 sqrt(eps/mu_ref) of the perfect "
                "neo-Hookean film, R/t0 = 10, by the linearised buckling model")),
            "eig_residual": (("method", "level"), res, a(
                "backward error of the critical eigenpair")),
            "ndof_u": (("method", "level"), ndof, a("free displacement degrees of freedom")),
            "v_cr_extrapolated": (("method",), lim, a(
                "mesh limit of v_cr (convergence fit; NaN with fewer than three levels)")),
            "v_cr_error": (("method",), err, a("error estimate of the mesh limit")),
            "v_cr_kirchhoff": ((), critical_voltage_plate(mat, ASPECT, mindlin=False), a(
                "Kirchhoff clamped-plate estimate (14.68 D/a^2, flat-film pre-stress)")),
            "v_cr_mindlin": ((), critical_voltage_plate(mat, ASPECT, mindlin=True), a(
                "Mindlin (transverse shear, kappa = 5/6) clamped-plate estimate")),
            "v_cr_k": (("k_ratio", "order", "k_level"), vk, a(
                "coupled critical voltage of the neo-Hookean film for bulk modulus k/mu",
                atol=2 * K_VTOL)),
            "v_cr_k_limit": (("order", "k_level"), klim, a(
                "limit k/mu -> infinity of the coupled critical voltage (linear in mu/k "
                "through the two stiffest bulk moduli)", atol=kacc["v_cr_k_limit"])),
            "v_cr_k_limit_error": (("order", "k_level"), kerr, a(
                "error estimate of the limit k/mu -> infinity",
                atol=kacc["v_cr_k_limit_error"])),
            "v_cr_k_kirchhoff": (("k_ratio",), plate_k, a(
                "Kirchhoff clamped-plate estimate for bulk modulus k/mu")),
        },
        coords={
            "method": ("method", list(METHODS), {"long_name": "linearised buckling model"}),
            "level": ("level", np.arange(len(levels)), a("mesh level")),
            "h_rel": ("level", np.array(levels), a("in-plane mesh size / t0")),
            "k_ratio": ("k_ratio", kr, a("bulk modulus / shear modulus k/mu")),
            "order": ("order", np.array(K_ORDERS), a("polynomial order of the elements")),
            "k_level": ("k_level", np.arange(len(k_levels)), a("mesh level of the k study")),
            "k_h_rel": ("k_level", np.array(k_levels), a("in-plane mesh size / t0 (k study)")),
        },
    )
    params = {"full": full, "levels_h_rel": list(levels), "k_levels_h_rel": list(k_levels),
              "layers": LAYERS, "order": ORDER, "k_orders": list(K_ORDERS), "aspect": ASPECT,
              "mu_Pa": mat.mu, "k_table_Pa": mat.k, "material": "neo-Hookean (5.15), Table 5.1",
              "k_vtol": K_VTOL}
    return ds, params


def _printed(ids):
    entries = catalogue.by_id()
    return {i: float(entries[i].value) for i in ids}


def figures(ramps: xr.Dataset, methods: xr.Dataset, fig_dir: Path) -> list[Path]:
    """Figs 5.4 and 5.6 with the thesis' printed values, as printed (open markers) and
    converted to our normalisation under the "mu in MPa" hypothesis (filled markers:
    printed / 0.395); the convergence of the three methods."""
    plt = style.pyplot()
    fig_dir.mkdir(parents=True, exist_ok=True)
    f = MU_IN_MPA_FACTOR
    pr = _printed(["ch5.pullin_voltage.t1_nh", "ch5.pullin_voltage.t1_ogden",
                   "ch5.pullin_displacement.t1", "ch5.critical_voltage.t1_nh",
                   "ch5.critical_voltage.t1_ogden", "ch5.critical_voltage.t0p5_ogden",
                   "ch5.wrinkling_displacement.t0p5"])
    out = []

    def save(fig, name):
        out.extend(style.save(fig, fig_dir / name))

    def curve(ax, case, style, label, mm):
        r = ramps.sel(case=case)
        ok = np.isfinite(r.v.values)
        scale = float(r.thickness_m) * 1e3 if mm else 1.0
        ax.plot(r.v.values[ok], r.w.values[ok] * scale, style, color="0.3", label=label)
        ax.plot(float(r.v_pullin), float(r.w_pullin) * scale, "k.", ms=8)

    def thesis(ax, v, w, color, label):
        ax.plot(v, w, "o", mfc="none", color=color, label=f"{label}, as printed")
        ax.plot(v / f, w, "o", color=color, label=rf"{label} / {f:.3f} ($\mu$ in MPa)")
        ax.annotate("", xy=(v / f, w), xytext=(v, w),
                    arrowprops={"arrowstyle": "->", "color": color, "lw": 0.8})

    # Fig 5.4: Ogden, t0 = 1 mm and 0.5 mm, deflection in mm
    fig, ax = plt.subplots(figsize=(7, 4.5))
    curve(ax, "ogden_t1", "-", r"ours, $t_0$ = 1 mm", True)
    curve(ax, "ogden_t0p5", "--", r"ours, $t_0$ = 0.5 mm", True)
    thesis(ax, pr["ch5.pullin_voltage.t1_ogden"], pr["ch5.pullin_displacement.t1"], "C3",
           "thesis pull-in 1 mm")
    for key, c, lab in (("ch5.critical_voltage.t1_ogden", "C0", "thesis critical 1 mm"),
                        ("ch5.critical_voltage.t0p5_ogden", "C2", "thesis critical 0.5 mm")):
        ax.axvline(pr[key], color=c, ls=":", lw=1, label=f"{lab}, as printed")
        ax.axvline(pr[key] / f, color=c, ls="-.", lw=1, label=f"{lab} / {f:.3f}")
    ax.axhline(pr["ch5.wrinkling_displacement.t0p5"], color="C2", lw=0.6,
               label="thesis wrinkling deflection 0.5 mm")
    ax.set_xlabel(style.LABELS["phibar_ch5"] + r", $\mu$ = 156 kPa")
    ax.set_ylabel(style.LABELS["deflection_mm"])
    ax.set_title(r"Fig 5.4 with the thesis' values: Ogden, $R/t_0$ = 10")
    ax.legend(fontsize=7.5, loc="center left", bbox_to_anchor=(1.01, 0.5))
    save(fig, "fig5_4_overlay")
    # Fig 5.6: materials at 1 mm, deflection in mm
    fig, ax = plt.subplots(figsize=(7, 4.5))
    curve(ax, "nh_t1", "-", "ours, neo-Hookean", True)
    curve(ax, "ogden_t1", "--", "ours, Ogden", True)
    w = pr["ch5.pullin_displacement.t1"]
    thesis(ax, pr["ch5.pullin_voltage.t1_nh"], w, "C3", "thesis pull-in NH")
    thesis(ax, pr["ch5.pullin_voltage.t1_ogden"], w, "C0", "thesis pull-in Ogden")
    ax.set_xlabel(style.LABELS["phibar_ch5"] + r", $\mu$ = 156 kPa")
    ax.set_ylabel(style.LABELS["deflection_mm"])
    ax.set_title(r"Fig 5.6 with the thesis' values: $t_0$ = 1 mm")
    ax.legend(fontsize=8, loc="center left", bbox_to_anchor=(1.01, 0.5))
    save(fig, "fig5_6_overlay")
    # methods on the mesh sequence
    fig, ax = plt.subplots(figsize=(5.5, 4))
    h = methods.h_rel.values
    for i, m in enumerate(methods.method.values):
        ax.plot(h, methods.v_cr.isel(method=i).values, "o-", label=str(m))
    ax.axhline(float(methods.v_cr_kirchhoff), color="k", ls="--", label="Kirchhoff")
    ax.axhline(float(methods.v_cr_mindlin), color="k", ls=":", label="Mindlin")
    ax.set_xlabel(style.LABELS["h_over_t0"])
    ax.set_ylabel(style.LABELS["phibar_cr"])
    ax.set_title(r"neo-Hookean, $R/t_0$ = 10: three methods")
    ax.legend(fontsize=8)
    save(fig, "ch5_methods_convergence")
    return out


def build(out_dir: Path, *, full: bool = False) -> list[Path]:
    ds, params = compute(full)
    path = write_dataset(
        ds, NAME, out_dir=out_dir, overwrite=True,
        title="Chapter 5: critical voltage by three methods and the incompressible limit",
        summary=("Critical normalised voltage of the perfect clamped neo-Hookean film "
                 "(Table 5.1, R/t0 = 10) by linearised initial-stress buckling, by the "
                 "frozen-potential tangent and by the coupled electromechanical "
                 "eigen-analysis on one mesh sequence, with the Kirchhoff and Mindlin "
                 "plate estimates; the coupled critical voltage for k/mu -> infinity with "
                 "quadratic and cubic elements."),
        parameters=params)
    figs = figures(read_dataset("ch5_ramps"), ds, Path(out_dir) / "figures")
    return [path, *figs]
