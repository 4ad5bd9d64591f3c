"""Chapter 4 datasets and figures: bifurcation of the pre-stretched anisotropic plate.

``build(out_dir, full=False)`` writes

* ``ch4_fig4_2_curves.nc`` - lam_cr(kH) for Dhat = 0 ... 5, xi = 0 and 5, three variants
  of the equations (derived / printed / literal; see debench.models.plate.coefficients);
* ``ch4_fig4_5_curves.nc`` - lam_cr(kH) at Dhat = 2 for xi = 0, 3, 5, 10;
* ``ch4_limits.nc`` - kH -> 0 limits (Fig. 4.4), half-space (Biot) limit, ellipticity limit;
* ``ch4_areas.nc`` - unstable-region areas (Fig. 4.3) for two definitions and three windows;
* ``ch4_critical_dhat.nc`` - critical Dhat vs xi (Fig. 4.6), two candidate definitions;
* ``ch4_method_agreement.nc`` - method 1 vs method 2 on sample roots of every figure case;
* ``ch4_voltage_control.nc`` - beyond the thesis: lam_cr(kH) at fixed voltage;

and the figures ``fig4_2_*.png``, ``fig4_3_areas.png``, ``fig4_4_thin_limit.png``,
``fig4_5_anisotropy.png``, ``fig4_6_critical_D.png`` in ``out_dir/figures``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr
from debench.models.plate import PlateParams, ellipticity_limit_stretch, strongly_elliptic
from debench.models.plate.analysis import (
    biot_equibiaxial_closed_form,
    half_space_limit,
    region,
    thin_limit,
)
from debench.models.plate.ansatz import LAM_WINDOW, critical_stretches, curves_vectorised
from debench.models.plate.fem import eigenvalues, elements_for, refine_root
from debench.models.plate.voltage import curves_at_voltage
from debench.reference import figures as figure_io
from debench.reference.datasets import variable_attrs as _attrs
from debench.reference.datasets import write_dataset
from debench.reference.figures import LABELS, pyplot, save, written
from debench.reference.figures import LABELS as L
from debench.reference.studies import ch4 as study
from tqdm import tqdm

#: CPU seconds of the default build (one thread, measured in one `debench reproduce` with
#: two pool processes on the quiet 2-core machine): the pool starts the longest first.
BUILD_CPU_S = 23.0
#: ``debench verify`` rebuilds this chapter's default plan and compares it with data/.
REGENERATED_BY_VERIFY = True
#: Model guards ``debench verify`` runs for this chapter (none).
GUARDS = {}

VARIANTS = ("derived", "printed", "literal")
FIG42_D = study.FIG42_D
FIG45_XI = study.FIG45_XI
MAX_ROOTS = 8
COMMON = {"alpha": 0.0, "beta": 0.5, "mu": 1.0, "eps": 1.0,
          "lam_window": list(LAM_WINDOW), "units": "mu = eps = 1, Dhat = D2/sqrt(mu eps)"}


def kH_grid(full: bool) -> np.ndarray:
    return np.geomspace(0.01, 20.0, 801 if full else 401)


def curves_dataset(xis, Ds, kH, variants=VARIANTS, progress=True) -> xr.Dataset:
    lam = np.full((len(variants), len(xis), len(Ds), kH.size, MAX_ROOTS), np.nan)
    par = np.full(lam.shape, -1, dtype=np.int8)
    jobs = [(iv, ix, iD) for iv in range(len(variants)) for ix in range(len(xis))
            for iD in range(len(Ds))]
    for iv, ix, iD in tqdm(jobs, desc="ch4 curves", disable=(not progress) or None, leave=False):
        p = PlateParams(xi=float(xis[ix]), Dhat=float(Ds[iD]), variant=variants[iv])
        lam[iv, ix, iD], par[iv, ix, iD] = curves_vectorised(kH, p, max_roots=MAX_ROOTS)
    lamE = np.array([[ellipticity_limit_stretch(PlateParams(xi=float(x), variant=v))
                      for x in xis] for v in variants])
    return xr.Dataset(
        {"lam_cr": (("variant", "xi", "Dhat", "kH", "root"), lam,
                    _attrs("critical lateral stretch (bifurcation), roots sorted ascending; NaN "
                           "= no further root in the lam window")),
         "parity": (("variant", "xi", "Dhat", "kH", "root"), par,
                    _attrs("mode parity: 0 = psi even (flexural, u2 even), 1 = psi odd "
                           "(extensional), -1 = none", flag_values=[-1, 0, 1])),
         "lam_ellipticity": (("variant", "xi"), lamE,
                             _attrs("stretch above which the model is not strongly elliptic "
                                    "(inf: elliptic for all lam >= 1)"))},
        coords={"variant": ("variant", list(variants),
                            {"long_name": "form of the equations: derived from (4.22) / "
                             "printed coefficients (4.54)-(4.60) / literal (4.64)-(4.82)"}),
                "xi": ("xi", np.asarray(xis, float), _attrs("anisotropy parameter of (4.21)")),
                "Dhat": ("Dhat", np.asarray(Ds, float),
                         _attrs("dimensionless electric displacement D2/sqrt(mu eps)")),
                "kH": ("kH", kH, _attrs("wavenumber times reference thickness")),
                "root": ("root", np.arange(MAX_ROOTS), _attrs("root index"))})


def limits_dataset() -> xr.Dataset:
    xis = np.asarray(FIG45_XI)
    Ds = np.asarray(FIG42_D)
    thin = np.full((len(VARIANTS), xis.size, Ds.size), np.nan)
    for iv, v in enumerate(VARIANTS):
        for ix, x in enumerate(xis):
            for iD, D in enumerate(Ds):
                r = thin_limit(PlateParams(float(x), float(D), variant=v))
                thin[iv, ix, iD] = r.max() if r.size else np.nan
    biot = half_space_limit(PlateParams(0.0, 0.0))
    return xr.Dataset(
        {"lam_cr_thin": (("variant", "xi", "Dhat"), thin,
                         _attrs("lam_cr as kH -> 0 of the flexural mode (Fig. 4.4): root of "
                                "a - c (tau11 = 0); literal: method-1 root at kH = 1e-4")),
         "lam_cr_halfspace_D0_iso": ((), biot,
                                     _attrs("kH -> inf limit, Dhat = 0, xi = 0 (half-space)")),
         "lam_biot_closed_form": ((), biot_equibiaxial_closed_form(),
                                  _attrs("Biot r^3 + r^2 + 3r - 1 = 0, r = lam^3")),
         "lam_ellipticity_derived": (("xi",), [ellipticity_limit_stretch(
             PlateParams(float(x), variant="derived")) for x in xis],
             _attrs("loss of strong ellipticity of (4.22): (2 xi/(2 xi - 1))^(1/4)"))},
        coords={"variant": ("variant", list(VARIANTS), {"long_name": "form of the equations"}),
                "xi": ("xi", xis, _attrs("anisotropy parameter")),
                "Dhat": ("Dhat", Ds, _attrs("dimensionless electric displacement"))})


def _area(xi: float, D: float, variant: str, which: str, kH_max: float) -> float:
    """:func:`debench.reference.studies.ch4.area`, NaN where the unstable region is
    undefined: the top of the lam window is not strongly elliptic (no stable reference;
    the derived model for xi > 1/2), where :meth:`Region.area` raises."""
    p = PlateParams(xi, D, variant=variant)
    if variant != "literal" and not bool(strongly_elliptic(np.array(study.AREA_LAM[1]), p)):
        return np.nan
    return study.area(xi, D, variant, which, kH_max)


def areas_dataset(progress=True) -> xr.Dataset:
    variants = ("printed", "literal", "derived")
    defs = ("thesis", "physical")
    kmax = (5.0, 10.0, 20.0)
    A = np.full((len(variants), 2, len(FIG42_D), len(defs), len(kmax)), np.nan)
    jobs = [(iv, ix, iD) for iv in range(3) for ix in range(2) for iD in range(len(FIG42_D))]
    for iv, ix, iD in tqdm(jobs, desc="ch4 areas", disable=(not progress) or None, leave=False):
        for idf, d in enumerate(defs):
            for ik, k in enumerate(kmax):
                A[iv, ix, iD, idf, ik] = _area((0.0, 5.0)[ix], FIG42_D[iD], variants[iv], d,
                                               k)
    return xr.Dataset(
        {"area": (("variant", "xi", "Dhat", "definition", "kH_max"), A,
                  _attrs("area of the unstable region in the (kH, lam) plane, kH in "
                         "[0.01, kH_max] linear, lam in [0.4, 8]; NaN where no stable "
                         "reference exists (derived model, xi > 1/2: not elliptic)"))},
        coords={"variant": ("variant", list(variants), {"long_name": "form of the equations"}),
                "xi": ("xi", [0.0, 5.0], _attrs("anisotropy parameter")),
                "Dhat": ("Dhat", np.asarray(FIG42_D), _attrs("dimensionless displacement")),
                "definition": ("definition", list(defs),
                               {"long_name": "thesis: det_E det_O < 0; physical: some "
                                "eigenvalue of the incremental energy negative"}),
                "kH_max": ("kH_max", np.asarray(kmax), _attrs("upper end of the kH window"))})


def critical_D_dataset() -> xr.Dataset:
    variants = ("printed", "literal")
    cands = ("max_area", "thin_extensional")
    C = np.full((len(variants), len(cands), len(FIG45_XI)), np.nan)
    for iv, v in enumerate(variants):
        for ic, c in enumerate(cands):
            for ix, x in enumerate(FIG45_XI):
                try:
                    C[iv, ic, ix] = study.critical_D(float(x), c, v)
                except Exception:  # noqa: BLE001 - recorded as NaN (no onset in range)
                    C[iv, ic, ix] = np.nan
    return xr.Dataset(
        {"Dhat_critical": (("variant", "candidate", "xi"), C,
                           _attrs("critical Dhat at which the field turns from destabilising "
                                  "to stabilising (Fig. 4.6), per candidate definition"))},
        coords={"variant": ("variant", list(variants), {"long_name": "form of the equations"}),
                "candidate": ("candidate", list(cands),
                              {"long_name": "max_area: Dhat maximising the thesis-definition "
                               "area (window kH <= 10); thin_extensional: onset of a psi-odd "
                               "root as kH -> 0"}),
                "xi": ("xi", np.asarray(FIG45_XI), _attrs("anisotropy parameter"))})


def agreement_dataset(kHs=(0.3, 2.0, 10.0), progress=True) -> xr.Dataset:
    cases = [(x, D) for D in FIG42_D for x in (0.0, 5.0)] + [(3.0, 2.0), (10.0, 2.0)]
    rec = {k: [] for k in ("variant", "xi", "Dhat", "kH", "lam_det", "lam_fe", "n_el")}
    for v in ("derived", "printed"):
        for x, D in tqdm(cases, desc=f"ch4 agreement {v}", disable=(not progress) or None,
                         leave=False):
            p = PlateParams(x, D, variant=v)
            for kH in kHs:
                roots = critical_stretches(kH, p).lam
                for lam1 in roots:
                    t = kH * lam1**-2
                    if t < 0.1:
                        continue
                    n = elements_for(t)
                    gaps = [abs(o - lam1) for o in roots if o != lam1]
                    d = min([1e-3] + [0.3 * g / lam1 for g in gaps])
                    n_lo = int(np.sum(eigenvalues(lam1 * (1 - d), kH, p, n, 8) < 0))
                    n_hi = int(np.sum(eigenvalues(lam1 * (1 + d), kH, p, n, 8) < 0))
                    lam2 = (refine_root(lam1, kH, p, n, index=min(n_lo, n_hi), rel=d)
                            if abs(n_lo - n_hi) == 1 else np.nan)
                    for k, val in zip(rec, (v, x, D, kH, lam1, lam2, n), strict=True):
                        rec[k].append(val)
    idx = np.arange(len(rec["kH"]))
    return xr.Dataset(
        {"variant": ("case", np.array(rec["variant"]), {"long_name": "form of the equations"}),
         "xi": ("case", np.array(rec["xi"]), _attrs("anisotropy parameter")),
         "Dhat": ("case", np.array(rec["Dhat"]), _attrs("dimensionless displacement")),
         "kH": ("case", np.array(rec["kH"]), _attrs("wavenumber times thickness")),
         "lam_det": ("case", np.array(rec["lam_det"]),
                     _attrs("critical stretch, method 1 (ansatz determinant)")),
         "lam_fe": ("case", np.array(rec["lam_fe"]),
                    _attrs("critical stretch, method 2 (through-thickness FE)")),
         "n_elements": ("case", np.array(rec["n_el"]), _attrs("FE elements used"))},
        coords={"case": ("case", idx, _attrs("sample root index"))})


def voltage_dataset(progress=True) -> xr.Dataset:
    """Beyond the thesis: lam_cr(kH) at fixed voltage Vhat (debench.models.plate.voltage)."""
    variants, xis, Vs = ("derived", "printed"), (0.0, 5.0), (0.25, 0.5, 0.75, 1.0)
    kH = np.geomspace(0.01, 20.0, 81)
    lam = np.full((2, 2, len(Vs), kH.size, MAX_ROOTS), np.nan)
    jobs = [(a, b, c) for a in range(2) for b in range(2) for c in range(len(Vs))]
    for iv, ix, iV in tqdm(jobs, desc="ch4 voltage control", disable=(not progress) or None,
                           leave=False):
        p = PlateParams(xis[ix], 0.0, variant=variants[iv])
        # all kH in one pass (the roots of critical_stretches_at_voltage at each kH)
        r, _ = curves_at_voltage(kH, Vs[iV], p, n_scan=240, max_roots=4 * MAX_ROOTS)
        lam[iv, ix, iV] = r[:, :MAX_ROOTS]
    return xr.Dataset(
        {"lam_cr": (("variant", "xi", "Vhat", "kH", "root"), lam,
                    _attrs("critical stretch under voltage control (electroded plate; "
                           "Dhat = Vhat lam^2/beta along the curve)"))},
        coords={"variant": ("variant", list(variants), {"long_name": "form of the equations"}),
                "xi": ("xi", list(xis), _attrs("anisotropy parameter")),
                "Vhat": ("Vhat", list(Vs), _attrs("dimensionless voltage V sqrt(eps/mu)/H")),
                "kH": ("kH", kH, _attrs("wavenumber times reference thickness")),
                "root": ("root", np.arange(MAX_ROOTS), _attrs("root index"))})


# --------------------------------------------------------------------------- figures
def _roots_as_points(kH, lam_cr):
    """(kH, lam_cr) of every root of a (kH, root) array as two flat arrays: one marker-only
    line draws all of them (one artist instead of one per root column, the same points)."""
    lam_cr = np.asarray(lam_cr, float)
    return np.repeat(np.asarray(kH, float), lam_cr.shape[1]), lam_cr.ravel()


def _plot_curves(ax, ds, v, xi, D, style, label):
    sel = ds.lam_cr.sel(variant=v, xi=xi, Dhat=D).values
    par = ds.parity.sel(variant=v, xi=xi, Dhat=D).values
    first = True
    for pcode, colour in ((0, "tab:blue"), (1, "tab:red")):
        x, y = _roots_as_points(ds.kH.values, np.where(par == pcode, sel, np.nan))
        if np.isfinite(y).any():
            ax.semilogx(x, y, style, color=colour, ms=1.6 if style == "." else 2.2,
                        mew=0.6, linestyle="none", label=label if first else None)
            first = False


def _shade_unstable(ax, ds, v, xi, D, **style):
    """Shade the thesis' unstable region {det < 0} (Sec. 4.4) of one case, as Fig. 4.2 does;
    nothing where the region is undefined (no strongly elliptic stable reference)."""
    kH = np.geomspace(float(ds.kH.min()), float(ds.kH.max()), 121)
    lam = np.geomspace(study.AREA_LAM[0], study.AREA_LAM[1], 241)
    r = region(PlateParams(xi=xi, Dhat=D, variant=v), kH, lam)
    mask = np.asarray(r.thesis, float)
    if not np.isfinite(mask).all() or not mask.any():
        return
    if style.get("hatches"):
        ax.contourf(kH, lam, mask.T, levels=[0.5, 1.5], colors="none", **style)
    else:
        ax.contourf(kH, lam, mask.T, levels=[0.5, 1.5], **style)


def figures(out: Path, c42: xr.Dataset, c45: xr.Dataset, lim: xr.Dataset, ar: xr.Dataset,
            crit: xr.Dataset) -> list[Path]:
    """Figs 4.2-4.6 from the datasets :func:`build` writes (PNG and SVG each, in ``out``)."""
    plt = pyplot()
    paths = []   # figure_io.save, a module attribute: tests replace it
    for v in VARIANTS:
        paths += figure_io.save(_fig4_2(plt, c42, v), out / f"fig4_2_curves_{v}")
    for draw, ds, name in ((_fig4_3, ar, "fig4_3_areas"), (_fig4_4, lim, "fig4_4_thin_limit"),
                           (_fig4_5, c45, "fig4_5_anisotropy"),
                           (_fig4_6, crit, "fig4_6_critical_D")):
        paths += figure_io.save(draw(plt, ds), out / name)
    return paths


def _fig4_2(plt, c42: xr.Dataset, v: str):
    """Fig. 4.2 of the coefficient variant ``v``: lam_cr(kH) of the nine Dhat cases, TI
    (xi = 5) and isotropic, with the unstable regions {det < 0} shaded."""
    fig, axs = plt.subplots(3, 3, figsize=(11, 10), sharex=True)
    for ax, D, tag in zip(axs.flat, FIG42_D, "abcdefghi", strict=True):
        _shade_unstable(ax, c42, v, 5.0, D, colors=["0.8"], alpha=0.6)
        _shade_unstable(ax, c42, v, 0.0, D, hatches=["////"])
        _plot_curves(ax, c42, v, 5.0, D, ".", r"TI $\xi$ = 5")
        _plot_curves(ax, c42, v, 0.0, D, "x", "isotropic")
        lamE = float(c42.lam_ellipticity.sel(variant=v, xi=5.0))
        if np.isfinite(lamE):
            ax.axhline(lamE, color="k", lw=0.6, ls=":", label="loss of ellipticity (TI)")
        ax.set_title(rf"({tag}) $\hat D$ = {D:g}")
        ax.set_ylim(0.4, 4.0 if v != "literal" else 5.5)
    axs[0, 0].legend(fontsize=8)
    for ax in axs[-1]:
        ax.set_xlabel(LABELS["kH"])
    for ax in axs[:, 0]:
        ax.set_ylabel(LABELS["lam_cr"])
    fig.suptitle(rf"Fig. 4.2 ({v}): blue $\psi$-even (flexural), red $\psi$-odd; "
                 r"dots TI $\xi$ = 5, crosses isotropic;" "\n"
                 r"unstable region $\det < 0$ shaded grey (TI), hatched (isotropic)")
    return fig


def _fig4_3(plt, ar: xr.Dataset):
    """Fig. 4.3: the areas of the unstable regions per Dhat case (thesis definition)."""
    fig, ax = plt.subplots(figsize=(8, 4))
    x = np.arange(len(FIG42_D))
    for k, (v, xi, off, hatch) in enumerate((("printed", 0.0, -0.3, ""), ("printed", 5.0, -0.1, ""),
                                             ("literal", 0.0, 0.1, "//"),
                                             ("literal", 5.0, 0.3, "//"))):
        a = ar.area.sel(variant=v, xi=xi, definition="thesis", kH_max=10.0).values
        ax.bar(x + off, a, width=0.2, hatch=hatch, color=f"C{k}",
               label=f"{v}, {'TI' if xi else 'iso'}")
    ax.set_xticks(x, [f"({t}) {D:g}" for t, D in zip("abcdefghi", FIG42_D, strict=True)])
    ax.set_xlabel(r"case, $\hat D$")
    ax.set_ylabel(r"area of $\{\det < 0\}$ in the $(kH, \lambda)$ plane")
    ax.legend(fontsize=8)
    lam_lo, lam_hi = study.AREA_LAM[0], study.AREA_LAM[1]
    ax.set_title("Fig. 4.3: unstable-region areas, assumed window "
                 rf"$kH \in$ [0.01, 10], $\lambda \in$ [{lam_lo:g}, {lam_hi:g}]"
                 "\n(the thesis' areas are in its figure image only)")
    return fig


def _fig4_4(plt, lim: xr.Dataset):
    """Fig. 4.4: the thin-plate limit kH -> 0 of lam_cr (root of a - c)."""
    fig, ax = plt.subplots(figsize=(7, 4))
    for k, (v, xi) in enumerate((vv, xx) for vv in VARIANTS for xx in (0.0, 5.0)):
        y = lim.lam_cr_thin.sel(variant=v, xi=xi).values[:3]
        ax.bar(np.arange(3) + (k - 2.5) * 0.13, y, width=0.13,
               label=f"{v}, {'TI' if xi else 'iso'}")
    ax.set_xticks(range(3), [r"(a) $\hat D$ = 0", r"(b) $\hat D$ = 1", r"(c) $\hat D$ = 2"])
    ax.set_ylabel(r"$\lambda_{cr}$ ($kH \to 0$)")
    ax.set_ylim(0.9, None)
    ax.legend(fontsize=8, ncol=2)
    ax.set_title(r"Fig. 4.4: thin-plate limit $kH \to 0$ (root of $a - c$)" "\n"
                 "(the thesis' values are in its figure image only)")
    return fig


def _fig4_5(plt, c45: xr.Dataset):
    """Fig. 4.5: lam_cr(kH) at Dhat = 2 for each anisotropy xi, one panel per variant,
    with each xi's loss of ellipticity."""
    fig, axs = plt.subplots(1, 3, figsize=(13, 4), sharey=True)
    for ax, v in zip(axs, VARIANTS, strict=True):
        for k, xi in enumerate(FIG45_XI):
            x, y = _roots_as_points(c45.kH.values,
                                    c45.lam_cr.sel(variant=v, xi=xi, Dhat=2.0).values)
            ax.semilogx(x, y, ".", ms=1.5, color=f"C{k}", label=rf"$\xi$ = {xi:g}")
            lamE = float(c45.lam_ellipticity.sel(variant=v, xi=xi))
            if np.isfinite(lamE):
                ax.axhline(lamE, color=f"C{k}", lw=0.7, ls=":",
                           label=r"loss of ellipticity (per $\xi$)" if k == len(FIG45_XI) - 1
                           else None)
        ax.set_title(rf"Fig. 4.5 ({v}), $\hat D$ = 2")
        ax.set_xlabel(LABELS["kH"])
        ax.set_ylim(0.4, 3.0)
    axs[0].set_ylabel(LABELS["lam_cr"])
    axs[0].legend(fontsize=8, markerscale=5)
    return fig


def _fig4_6(plt, crit: xr.Dataset):
    """Fig. 4.6: the critical Dhat against xi, for both candidate definitions."""
    names = {"max_area": r"$\hat D$ of the largest unstable area",
             "thin_extensional": r"first extensional mode as $kH \to 0$"}
    fig, ax = plt.subplots(figsize=(6, 4))
    for v, m in (("printed", "o-"), ("literal", "s--")):
        for c in crit.candidate.values:
            ax.plot(crit.xi, crit.Dhat_critical.sel(variant=v, candidate=c), m,
                    label=f"{v}: {names.get(str(c), c)}")
    ax.set_xlabel(LABELS["xi"])
    ax.set_ylabel(r"critical $\hat D$")
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.15), ncol=1)
    ax.set_title(r"Fig. 4.6: critical $\hat D$ vs $\xi$ (two candidate definitions;" "\n"
                 "the thesis' values are in its figure image only)")
    return fig


def build(out_dir: Path, *, full: bool = False, progress: bool = True) -> list[Path]:
    out_dir = Path(out_dir)
    kH = kH_grid(full)
    params = {**COMMON, "kH_min": float(kH[0]), "kH_max": float(kH[-1]), "n_kH": int(kH.size),
              "full": bool(full)}
    paths = []
    c42 = curves_dataset((0.0, 5.0), FIG42_D, kH, progress=progress)
    paths.append(write_dataset(
        c42, "ch4_fig4_2_curves", title="Chapter 4, Fig. 4.2: lam_cr(kH) of the plate",
        summary="Critical lateral stretch vs kH for Dhat = 0..5, isotropic and TI (xi = 5), "
        "charge control, method 1 (ansatz determinant, even/odd split, bracketed roots), "
        "for the equations derived from (4.22), the printed coefficients, and the literal "
        "printed rows.", parameters=params, out_dir=out_dir, overwrite=True))
    c45 = curves_dataset(FIG45_XI, (2.0,), kH, progress=progress)
    paths.append(write_dataset(
        c45, "ch4_fig4_5_curves", title="Chapter 4, Fig. 4.5: lam_cr(kH) for xi = 0, 3, 5, 10",
        summary="Critical stretch vs kH at Dhat = 2 for four anisotropy levels, three "
        "variants of the equations.", parameters=params, out_dir=out_dir, overwrite=True))
    lim = limits_dataset()
    paths.append(write_dataset(
        lim, "ch4_limits", title="Chapter 4, Fig. 4.4 and literature limits",
        summary="Thin-plate (kH -> 0) critical stretches, the thick-plate (Biot) limit and "
        "the loss of strong ellipticity of (4.22).", parameters=COMMON, out_dir=out_dir,
        overwrite=True))
    ar = areas_dataset(progress=progress)
    paths.append(write_dataset(
        ar, "ch4_areas", title="Chapter 4, Fig. 4.3: unstable-region areas",
        summary="Areas of the unstable region in the (kH, lam) plane, thesis definition "
        "(det < 0) and physical definition, three kH windows.",
        parameters={**COMMON, "lam_min": 0.4, "lam_max": 8.0, "n_kH": study.AREA_KH_N,
                    "n_lam": study.AREA_LAM[2]}, out_dir=out_dir, overwrite=True))
    crit = critical_D_dataset()
    paths.append(write_dataset(
        crit, "ch4_critical_dhat", title="Chapter 4, Fig. 4.6: critical Dhat vs xi",
        summary="Two candidate definitions of the Dhat at which the field turns from "
        "destabilising to stabilising.", parameters=COMMON, out_dir=out_dir, overwrite=True))
    agr = agreement_dataset(progress=progress)
    paths.append(write_dataset(
        agr, "ch4_method_agreement", title="Chapter 4: method 1 vs method 2",
        summary="Critical stretches of every figure case at kH = 0.3, 2, 10 (k h >= 0.1) "
        "from the ansatz determinant and from the through-thickness FE.",
        parameters=COMMON, out_dir=out_dir, overwrite=True))
    vc = voltage_dataset(progress=progress)
    paths.append(write_dataset(
        vc, "ch4_voltage_control", title="Chapter 4, beyond the thesis: voltage control",
        summary="Critical stretch vs kH at fixed voltage for the electroded plate; the "
        "incremental problem equals the charge-controlled one with Dhat = Vhat lam^2/beta.",
        parameters=COMMON, out_dir=out_dir, overwrite=True))
    if written():
        paths += figures(out_dir / "figures", c42, c45, lim, ar, crit)
        paths += _voltage_figure(out_dir / "figures", vc)
    return paths


def _voltage_figure(out: Path, vc: xr.Dataset) -> list[Path]:
    plt = pyplot()
    fig, axs = plt.subplots(1, 2, figsize=(11, 4), sharey=True)
    for ax, xi in zip(axs, (0.0, 5.0), strict=True):
        for k, V in enumerate(vc.Vhat.values):
            x, y = _roots_as_points(vc.kH.values,
                                    vc.lam_cr.sel(variant="printed", xi=xi, Vhat=V).values)
            ax.semilogx(x, y, ".", ms=2, color=f"C{k}", label=rf"$\hat V$ = {V:g}")
        ax.set_title(rf"voltage control (beyond the thesis), $\xi$ = {xi:g}, printed coeffs")
        ax.set_xlabel(L["kH"])
        ax.set_ylim(0.4, 3.0)
    axs[0].set_ylabel(L["lam_cr"])
    axs[0].legend(fontsize=8, markerscale=4, loc="upper right", bbox_to_anchor=(1.0, 0.9))
    return save(fig, out / "ch4_beyond_voltage_control")
