"""Beyond the thesis: critical stretch of the plate with the fibre in its plane.

Datasets (in ``out_dir``), all by the models of :mod:`debench.models.plate.inplane`:

* ``ch4_inplane_lam_cr.nc`` - lam_cr(kH, theta, xi, Dhat) in equibiaxial compression,
  charge control, by both methods (exponential-ansatz determinant and through-thickness
  FE), with the strong-ellipticity limit lam_E(theta, xi). lam_cr is the largest
  bifurcation stretch in [max(lam_E (1 + ip.LAM_E_MARGIN), LAM_LO), 0.999]; NaN where
  there is none;
* ``ch4_inplane_curves.nc`` - lam_cr(kH) on a kH grid (determinant), compression, for
  the figure;
* ``ch4_inplane_tension.nc`` - stretches above 1 (equibiaxial tension) with a field,
  charge control: lam_cr in [1 + 5e-4, 2] by both methods and the membrane limit
  (zero of the total lateral stress tau11, the kH -> 0 limit);
* ``ch4_inplane_voltage.nc`` - voltage control (Dhat = Vhat lam^2/beta along the
  path), window [max(lam_E (1 + ip.LAM_E_MARGIN), LAM_LO), V_HI] across lam = 1, both
  methods;
* ``ch4_inplane_roots.nc`` - every root (both methods) of the windows the catalogue
  producers compare (:func:`debench.reference.producers.ch4_inplane.producer_cases`:
  compression, voltage control, tension); the producers read its FE roots (the same with
  ``full``);

and the figure ``figures/ch4_beyond_inplane.png`` (lam_cr against kH, theta, xi; tension
and voltage control). ``full=True``: theta every 10 degrees, more kH, xi, Dhat and Vhat.

Every window is solved through the producers' memo (:class:`Case`,
:func:`~debench.reference.producers.ch4_inplane.det_roots`,
:func:`~debench.reference.producers.ch4_inplane.fe_roots`), so a window shared by a
dataset and the producers (the tension cases) is solved once per process.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr
from debench.models.plate import PlateParams
from debench.models.plate import inplane as ip
from debench.models.plate import inplane_fe as ipfe
from debench.reference.datasets import variable_attrs as _attrs
from debench.reference.datasets import write_dataset
from debench.reference.figures import save, written
from debench.reference.studies import ch4_inplane as study
from debench.reference.studies.ch4_inplane import Case

#: CPU seconds of the default build (one thread, measured in one `debench reproduce` with
#: two pool processes on the quiet 2-core machine): the pool starts the longest first.
BUILD_CPU_S = 16.0
#: ``debench verify`` rebuilds this chapter's default plan and compares it with data/.
REGENERATED_BY_VERIFY = True
#: Model guards ``debench verify`` runs for this chapter (none).
GUARDS = {}

THETA_FAST = (0.0, 30.0, 45.0, 60.0, 90.0)
THETA_FULL = tuple(float(t) for t in range(0, 91, 10)) + (45.0,)
KH_FAST = (0.5, 2.0, 5.0)
KH_FULL = (0.25, 0.5, 1.0, 2.0, 3.0, 5.0, 8.0)
XI_FAST = (5.0,)
XI_FULL = (1.0, 5.0, 10.0)
D_FAST = (0.0,)
D_FULL = (0.0, 1.0, 2.0)
#: the kH grid of the curves (determinant only)
KH_CURVE_FAST = tuple(np.geomspace(0.2, 8.0, 9))
KH_CURVE_FULL = tuple(np.geomspace(0.1, 10.0, 25))
#: tension: fields (charge control) and the window of stretches above 1
D_TENSION_FAST = (2.0,)
D_TENSION_FULL = (1.0, 2.0, 3.0)
TENSION_WINDOW = (1.0005, 2.0)
#: tension, full sweep: kH >= 1. Dhat = 3 puts roots at lam ~ 1.6-1.7, where at kH = 0.5
#: the current thickness kH lam^-2 < 0.2 and an FE root's round-off (eps ||K|| over the
#: eigenvalue slope) is 1.7e-4 (xi = 5, theta = 80): the FE guard refuses it, rightly
KH_TENSION_FULL = tuple(k for k in KH_FULL if k >= 1.0)
#: voltage control: dimensionless voltages Vhat = V sqrt(eps/mu)/H
V_FAST = (0.5,)
V_FULL = (0.1, 0.25, 0.5)
#: upper end of the voltage-control window: across lam = 1, since at fixed voltage thin
#: plates wrinkle already in tension
V_HI = 1.5
#: lower end of the scanned window, above the slender-plate Euler roots of interest
LAM_LO = 0.6
#: grid points of the scan (each method): the producers' grid, whose memo solves each
#: window (:class:`Case`)
N_SCAN = study.N_SCAN
COMMON = {"alpha": 0.0, "beta": 0.5, "mu": 1.0, "eps": 1.0,
          "fibre": "A = (cos theta, 0, sin theta), in the plane of the plate",
          "units": "mu = eps = 1, Dhat = D2/sqrt(mu eps), Vhat = V sqrt(eps/mu)/H",
          "n_elements": ipfe.N_ELEMENTS}


def _coord(name, values, long_name, units="1"):
    return (name, np.asarray(values, float), _attrs(long_name, units))


def _largest(roots):
    return max(roots, default=np.nan)


def window_start(theta, params, Vhat=None):
    """(lam_E, lo) of the compression and voltage-control windows of the datasets at the
    fibre angle ``theta`` (degrees): lam_E the ellipticity limit
    (:func:`debench.models.plate.inplane.ellipticity_limit` on (0.45, 0.999), along the
    voltage path when ``Vhat`` is given) and lo, the window's lower end,
    max(lam_E (1 + :data:`debench.models.plate.inplane.LAM_E_MARGIN`), :data:`LAM_LO`)."""
    lam_e = ip.ellipticity_limit(theta, params, window=(0.45, 0.999), Vhat=Vhat)
    return lam_e, max(LAM_LO, lam_e * (1 + ip.LAM_E_MARGIN))


def lam_cr_dataset(full: bool) -> xr.Dataset:
    thetas = sorted(set(THETA_FULL)) if full else THETA_FAST
    khs = KH_FULL if full else KH_FAST
    xis = XI_FULL if full else XI_FAST
    ds_ = D_FULL if full else D_FAST
    shape = (len(xis), len(ds_), len(thetas), len(khs))
    det, fe = np.full(shape, np.nan), np.full(shape, np.nan)
    lam_e = np.full(shape[:3], np.nan)
    cases = {}
    for a, xi in enumerate(xis):
        for b, D in enumerate(ds_):
            p = PlateParams(xi=xi, Dhat=D)
            for c, th in enumerate(thetas):
                lam_e[a, b, c], lo = window_start(th, p)
                for d, kh in enumerate(khs):
                    cases[a, b, c, d] = Case("charge", th, xi, D, 0.0, kh, lo, 0.999)
    study.det_roots_many(list(cases.values()))   # every window's determinant roots at once
    for idx, case in cases.items():
        det[idx] = _largest(study.det_roots(case))
        fe[idx] = _largest(study.fe_roots(case))
    dims = ("xi", "Dhat", "theta", "kH")
    return xr.Dataset(
        {"lam_cr_det": (dims, det, _attrs(
            "critical stretch, exponential-ansatz determinant (method 1)")),
         "lam_cr_fe": (dims, fe, _attrs(
             "critical stretch, through-thickness FE (method 2)")),
         "lam_E": (dims[:3], lam_e, _attrs(
             "largest compressive stretch without plane strong ellipticity"))},
        coords={"xi": _coord("xi", xis, "anisotropy parameter"),
                "Dhat": _coord("Dhat", ds_, "Eulerian D2/sqrt(mu eps)"),
                "theta": _coord("theta", thetas, "fibre angle to the wave vector", "degree"),
                "kH": _coord("kH", khs, "wavenumber times reference thickness")})


def curves_dataset(full: bool) -> xr.Dataset:
    thetas = sorted(set(THETA_FULL)) if full else THETA_FAST
    khs = KH_CURVE_FULL if full else KH_CURVE_FAST
    xis = XI_FULL if full else XI_FAST
    lam = np.full((len(xis), len(thetas), len(khs)), np.nan)
    cases = {}
    for a, xi in enumerate(xis):
        p = PlateParams(xi=xi)
        for c, th in enumerate(thetas):
            _, lo = window_start(th, p)
            for d, kh in enumerate(khs):
                cases[a, c, d] = Case("charge", th, xi, 0.0, 0.0, kh, lo, 0.999)
    for idx, r in zip(cases, study.det_roots_many(list(cases.values())), strict=True):
        lam[idx] = _largest(r)
    return xr.Dataset(
        {"lam_cr_det": (("xi", "theta", "kH"), lam, _attrs(
            "critical stretch (largest root above the ellipticity limit), determinant"))},
        coords={"xi": _coord("xi", xis, "anisotropy parameter"),
                "theta": _coord("theta", thetas, "fibre angle to the wave vector", "degree"),
                "kH": _coord("kH", khs, "wavenumber times reference thickness")})


def tension_dataset(full: bool) -> xr.Dataset:
    thetas = sorted(set(THETA_FULL)) if full else THETA_FAST
    khs = KH_TENSION_FULL if full else KH_FAST   # the FE resolves these thin plates
    ds_ = D_TENSION_FULL if full else D_TENSION_FAST
    xi = 5.0
    shape = (len(ds_), len(thetas), len(khs))
    det, fe = np.full(shape, np.nan), np.full(shape, np.nan)
    memb = np.full(shape[:2], np.nan)
    cases = {}
    for b, D in enumerate(ds_):
        p = PlateParams(xi=xi, Dhat=D)
        for c, th in enumerate(thetas):
            m = ip.membrane_limit(th, p, window=(1.0, 8.0))
            memb[b, c] = np.nan if m is None else m
            for d, kh in enumerate(khs):
                cases[b, c, d] = Case("charge", th, xi, D, 0.0, kh, *TENSION_WINDOW)
    study.det_roots_many(list(cases.values()))   # every window's determinant roots at once
    for idx, case in cases.items():
        det[idx] = _largest(study.det_roots(case))
        fe[idx] = _largest(study.fe_roots(case))
    dims = ("Dhat", "theta", "kH")
    return xr.Dataset(
        {"lam_cr_det": (dims, det, _attrs(
            "critical stretch above 1 (largest root in the tension window), determinant")),
         "lam_cr_fe": (dims, fe, _attrs(
             "critical stretch above 1 (largest root in the tension window), FE")),
         "lam_membrane": (dims[:2], memb, _attrs(
             "membrane limit kH -> 0: largest zero of the total lateral stress tau11"))},
        coords={"Dhat": _coord("Dhat", ds_, "Eulerian D2/sqrt(mu eps)"),
                "theta": _coord("theta", thetas, "fibre angle to the wave vector", "degree"),
                "kH": _coord("kH", khs, "wavenumber times reference thickness")},
        attrs={"xi": xi})


def voltage_dataset(full: bool) -> xr.Dataset:
    thetas = sorted(set(THETA_FULL)) if full else THETA_FAST
    khs = KH_FULL if full else KH_FAST
    vs = V_FULL if full else V_FAST
    xi = 5.0
    p = PlateParams(xi=xi)
    shape = (len(vs), len(thetas), len(khs))
    det, fe = np.full(shape, np.nan), np.full(shape, np.nan)
    cases = {}
    for b, V in enumerate(vs):
        for c, th in enumerate(thetas):
            _, lo = window_start(th, p, Vhat=V)
            for d, kh in enumerate(khs):
                cases[b, c, d] = Case("voltage", th, xi, 0.0, V, kh, lo, V_HI)
    study.det_roots_many(list(cases.values()))   # every window's determinant roots at once
    for idx, case in cases.items():
        det[idx] = _largest(study.det_roots(case))
        fe[idx] = _largest(study.fe_roots(case))
    dims = ("Vhat", "theta", "kH")
    return xr.Dataset(
        {"lam_cr_det": (dims, det, _attrs(
            "critical stretch at fixed voltage (largest root in the window), determinant")),
         "lam_cr_fe": (dims, fe, _attrs(
             "critical stretch at fixed voltage (largest root in the window), FE"))},
        coords={"Vhat": _coord("Vhat", vs, "dimensionless voltage V sqrt(eps/mu)/H"),
                "theta": _coord("theta", thetas, "fibre angle to the wave vector", "degree"),
                "kH": _coord("kH", khs, "wavenumber times reference thickness")},
        attrs={"xi": xi})


def roots_dataset() -> xr.Dataset:
    """Every root, both methods, of the producers' windows (NaN-padded along ``root``),
    with the accuracy of the FE roots and the agreement tolerance as attributes."""
    cases = study.producer_cases()
    det = study.det_roots_many(cases)
    fe = [study.fe_roots(c) for c in cases]
    width = max([1, *(len(r) for r in det + fe)])

    def padded(rows):
        out = np.full((len(rows), width), np.nan)
        for i, r in enumerate(rows):
            out[i, :len(r)] = r
        return out

    def col(name):
        return np.array([getattr(c, name) for c in cases], dtype=float)

    acc = study.ACCURACY
    tol = {"accuracy_rtol": acc.rtol, "accuracy_atol": acc.atol,
           "accuracy_reason": acc.reason, "fe_root_roundoff": ipfe.FE_ROOT_ROUNDOFF,
           "agreement_tolerance": study.TOL_AGREE}
    return xr.Dataset(
        {"lam_det": (("case", "root"), padded(det), _attrs(
            "critical stretches in the window, exponential-ansatz determinant (method 1), "
            "ascending; NaN-padded")),
         "lam_fe": (("case", "root"), padded(fe), {**_attrs(
             "critical stretches in the window, through-thickness FE (method 2), "
             "ascending; NaN-padded"), **tol}),
         "n_det": ("case", np.array([len(r) for r in det]), _attrs(
             "number of determinant roots in the window")),
         "n_fe": ("case", np.array([len(r) for r in fe]), _attrs(
             "number of FE roots in the window")),
         "control": ("case", np.array([c.control for c in cases]),
                     {"long_name": "charge or voltage control"}),
         "theta": ("case", col("theta"), _attrs("fibre angle to the wave vector", "degree")),
         "xi": ("case", col("xi"), _attrs("anisotropy parameter")),
         "Dhat": ("case", col("Dhat"), _attrs("Eulerian D2/sqrt(mu eps) (charge control)")),
         "Vhat": ("case", col("Vhat"), _attrs(
             "dimensionless voltage V sqrt(eps/mu)/H (voltage control; 0 under charge "
             "control)")),
         "kH": ("case", col("kH"), _attrs("wavenumber times reference thickness")),
         "lam_lo": ("case", col("lo"), _attrs("lower end of the scanned window")),
         "lam_hi": ("case", col("hi"), _attrs("upper end of the scanned window"))},
        coords={"case": ("case", np.arange(len(cases)), _attrs("case index")),
                "root": ("root", np.arange(width), _attrs("root index"))})


def figure(out: Path, lc: xr.Dataset, cu: xr.Dataset, te: xr.Dataset,
           vo: xr.Dataset) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    fig, axs = plt.subplots(2, 2, figsize=(10, 8))
    ax = axs[0, 0]
    for k, th in enumerate(cu.theta.values):
        for j, xi in enumerate(cu.xi.values):
            ax.semilogx(cu.kH, cu.lam_cr_det.sel(xi=xi, theta=th), ("-", "--", ":")[j % 3],
                        color=f"C{k}", label=rf"$\theta={th:g}^\circ$" if j == 0 else None)
        fe = lc.lam_cr_fe.sel(Dhat=0.0, theta=th, xi=5.0) if th in lc.theta else None
        if fe is not None:
            ax.semilogx(lc.kH, fe, "o", mfc="none", color=f"C{k}", ms=5)
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    ax.set_xlabel(r"$kH$")
    ax.set_ylabel(r"$\lambda_{cr}$")
    ax.set_title(r"(a) compression, $\hat D=0$: $\lambda_{cr}(kH)$ (lines: determinant, "
                 r"$\circ$: FE)", fontsize=9)
    ax.legend(fontsize=7, title=r"$\xi$ = " + ", ".join(f"{x:g}" for x in cu.xi.values)
              + " (-, --, :)", title_fontsize=7)
    ax = axs[0, 1]
    for j, kh in enumerate(lc.kH.values):
        for i, xi in enumerate(lc.xi.values):
            ax.plot(lc.theta, lc.lam_cr_det.sel(xi=xi, Dhat=0.0, kH=kh), ("-", "--", ":")[i % 3],
                    color=f"C{j}", label=rf"$kH={kh:g}$" if i == 0 else None)
            ax.plot(lc.theta, lc.lam_cr_fe.sel(xi=xi, Dhat=0.0, kH=kh), "o", mfc="none",
                    color=f"C{j}", ms=4)
    for i, xi in enumerate(lc.xi.values):
        ax.plot(lc.theta, lc.lam_E.sel(xi=xi, Dhat=0.0), ("-", "--", ":")[i % 3], color="k",
                lw=0.8, label=r"$\lambda_E$ (ellipticity)" if i == 0 else None)
    ax.set_xlabel(r"$\theta$ (degree)")
    ax.set_ylabel(r"$\lambda_{cr}$")
    ax.set_title(r"(b) compression, $\hat D=0$: dependence on $\theta$ and $\xi$ "
                 r"($\xi$ = " + ", ".join(f"{x:g}" for x in lc.xi.values) + ")", fontsize=9)
    ax.legend(fontsize=7)
    ax = axs[1, 0]
    for b, D in enumerate(te.Dhat.values):
        ls = ("-", "--", ":")[b % 3]
        ax.plot(te.theta, te.lam_membrane.sel(Dhat=D), ls, color="k", lw=0.9,
                label=r"membrane limit ($\tau_{11}=0$)" if b == 0 else None)
        for j, kh in enumerate(te.kH.values):
            ax.plot(te.theta, te.lam_cr_det.sel(Dhat=D, kH=kh), ls, color=f"C{j}",
                    label=rf"$kH={kh:g}$" if b == 0 else None)
            ax.plot(te.theta, te.lam_cr_fe.sel(Dhat=D, kH=kh), "o", mfc="none",
                    color=f"C{j}", ms=4)
    ax.axhline(1.0, color="0.6", lw=0.6)
    ax.set_xlabel(r"$\theta$ (degree)")
    ax.set_ylabel(r"$\lambda_{cr}$")
    ax.set_title(rf"(c) tension with a field, $\xi={te.attrs['xi']:g}$, $\hat D$ = "
                 + ", ".join(f"{d:g}" for d in te.Dhat.values), fontsize=9)
    ax.legend(fontsize=7)
    ax = axs[1, 1]
    for b, V in enumerate(vo.Vhat.values):
        ls = ("-", "--", ":")[b % 3]
        for j, kh in enumerate(vo.kH.values):
            ax.plot(vo.theta, vo.lam_cr_det.sel(Vhat=V, kH=kh), ls, color=f"C{j}",
                    label=rf"$kH={kh:g}$" if b == len(vo.Vhat) - 1 else None)
            ax.plot(vo.theta, vo.lam_cr_fe.sel(Vhat=V, kH=kh), "o", mfc="none",
                    color=f"C{j}", ms=4)
    ax.set_xlabel(r"$\theta$ (degree)")
    ax.set_ylabel(r"$\lambda_{cr}$")
    ax.set_title(rf"(d) voltage control, $\xi={vo.attrs['xi']:g}$, $\hat V$ = "
                 + ", ".join(f"{x:g}" for x in vo.Vhat.values), fontsize=9)
    ax.legend(fontsize=7)
    fig.suptitle("Fibre in the plane of the plate (beyond the thesis): lines determinant, "
                 "circles through-thickness FE", fontsize=10)
    fig.tight_layout()
    return save(fig, out / "figures" / "ch4_beyond_inplane")


def build(out_dir: Path, *, full: bool = False, progress: bool = True) -> list[Path]:
    out_dir = Path(out_dir)
    lc, cu = lam_cr_dataset(full), curves_dataset(full)
    te, vo = tension_dataset(full), voltage_dataset(full)
    common = {**COMMON, "full": full, "lam_lo": LAM_LO, "lam_e_margin": ip.LAM_E_MARGIN,
              "n_scan": N_SCAN}
    note = "Our results beyond the thesis, not thesis values."
    paths = [
        write_dataset(
            lc, "ch4_inplane_lam_cr", out_dir=out_dir, overwrite=True,
            title="Plate bifurcation with the fibre in the plane (beyond the thesis)",
            summary="Critical stretch lam_cr(kH) of the equibiaxially compressed transversely "
                    "isotropic dielectric plate (energy 4.22) with the fibre in its plane at "
                    "the angle theta to the wave vector, by the exponential-ansatz determinant "
                    "and by through-thickness finite elements, with the strong-ellipticity "
                    "limit. " + note,
            parameters={**common, "control": "charge"}),
        write_dataset(
            cu, "ch4_inplane_curves", out_dir=out_dir, overwrite=True,
            title="In-plane fibre: lam_cr(kH) curves in compression (beyond the thesis)",
            summary="Largest bifurcation stretch above the ellipticity limit on a kH grid, "
                    "exponential-ansatz determinant, Dhat = 0. " + note,
            parameters={**common, "control": "charge", "Dhat": 0.0}),
        write_dataset(
            te, "ch4_inplane_tension", out_dir=out_dir, overwrite=True,
            title="In-plane fibre: wrinkling in equibiaxial tension with a field "
                  "(beyond the thesis)",
            summary="Critical stretch above 1 of the plate with the fibre in its plane under "
                    "charge control, both methods, and the membrane limit where the total "
                    "lateral stress tau11 vanishes. " + note,
            parameters={**common, "control": "charge", "xi": te.attrs["xi"],
                        "window": list(TENSION_WINDOW)}),
        write_dataset(
            vo, "ch4_inplane_voltage", out_dir=out_dir, overwrite=True,
            title="In-plane fibre: critical stretch under voltage control (beyond the thesis)",
            summary="Critical stretch of the plate with the fibre in its plane at "
                    "fixed voltage (Dhat = Vhat lam^2/beta along the path), both methods. "
                    + note,
            parameters={**common, "control": "voltage", "xi": vo.attrs["xi"],
                        "window_hi": V_HI}),
        write_dataset(
            roots_dataset(), "ch4_inplane_roots", out_dir=out_dir, overwrite=True,
            title="In-plane fibre: every root of the windows the catalogue compares "
                  "(beyond the thesis)",
            summary="Every bifurcation stretch, by the exponential-ansatz determinant and by "
                    "through-thickness finite elements, in the windows of the "
                    "ch4.beyond.inplane.* entries: compression (charge control), voltage "
                    "control and tension with a field, xi = 5. " + note,
            parameters={**COMMON, "n_scan": N_SCAN, "lam_e_margin": ip.LAM_E_MARGIN}),
    ]
    return paths + (figure(out_dir, lc, cu, te, vo) if written() else [])
