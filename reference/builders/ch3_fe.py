# ruff: noqa: E501  -- CF attribute dicts and dataset descriptions read best on one line
"""Builder of the Chapter 3 finite-element datasets (the FE actuator beside both analytic
equilibrium variants).

* ``ch3_fe_voltage_stretch``: Phibar(lam) by FE, by the printed (3.33) and by the membrane
  balance, lamP = 1.25, 2, 3, 4 and c = 0, -0.053 (Figs 3.4, 3.5, 3.8).
* ``ch3_fe_convergence``: loss-of-tension stretch (lamP = 3), pull-in stretch and Phibar
  (lamP = 1.25) and the one-sided stress jump at R_A (lamP = 3, lam = 4) per mesh, with the
  analytic values of both variants (the convergence study behind the tolerances).
* ``ch3_fe_profiles``: lambda1, lambda2, lambda3 in annulus B at lamP = 3, lam = 4 by FE and
  both variants (Figs 3.2-3.3).
* ``ch3_fe_thickness``: Phibar of the thin solid (models/circular/fe_solid.py) at fixed
  centre stretches, lamP = 3, per film thickness H, and its limit H -> 0 beside the
  membrane FE and both variants.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr
from debench.models.circular.fe import CircularFE, FEMesh
from debench.models.circular.shooting import integrate_inward, q_for_stretch
from debench.reference.datasets import write_dataset
from debench.reference.producers import ch3_fe as P


def _settings(full: bool) -> dict:
    return {"curve_mesh": P.MESH_FINE if full else P.MESH_CURVE,
            "steps": P.ANALYTIC_STEPS_FINE if full else P.ANALYTIC_STEPS,
            "levels": (5, 10, 20, 40, 80) if full else (5, 10, 20),
            "profile_mesh": P.MESH_FINE if full else dict(n_a=2, n_b=40, order=2)}


def _params(full: bool, **extra) -> dict:
    return {"Jm": 120.0, "radius_ratio": 15.0, "element_order": 2, "full": full,
            "model": "axisymmetric membrane FE (models/circular/fe.py)", **extra}


def voltage_stretch(full: bool) -> xr.Dataset:
    s = _settings(full)
    k = np.arange(8)
    shape = (len(P.CURVE_LAMP), len(P.CURVE_C), len(k))
    data = {n: np.empty(shape) for n in ("fe", "printed", "membrane")}
    lam = np.empty((len(P.CURVE_LAMP), len(k)))
    for i, lamP in enumerate(P.CURVE_LAMP):
        lam[i] = P.curve_grid(lamP)
        for j, c in enumerate(P.CURVE_C):
            d = P.voltage_stretch(lamP, c, s["curve_mesh"], lam[i], steps=s["steps"])
            for n in data:
                data[n][i, j] = d[n]
    dims = ("lamP", "c", "point")
    ds = xr.Dataset(
        {f"phibar_{n}": (dims, v, {"long_name": f"normalised voltage Phibar, {what}", "units": "1"})
         for n, v, what in [("fe", data["fe"], "finite elements"),
                            ("printed", data["printed"], "analytic, Eq. (3.33) as printed"),
                            ("membrane", data["membrane"], "analytic, thin-membrane balance")]},
        coords={"lamP": ("lamP", np.array(P.CURVE_LAMP), {"long_name": "equibiaxial pre-stretch", "units": "1"}),
                "c": ("c", np.array(P.CURVE_C), {"long_name": "Zhao-Suo electrostrictive factor (3.27)", "units": "1"}),
                "point": ("point", k, {"long_name": "index of the stretch on the curve", "units": "1"}),
                "lam": (("lamP", "point"), lam, {"long_name": "stretch of circle A r(R_A)/R_A", "units": "1"})})
    ds.attrs = {"mesh_n_b": s["curve_mesh"]["n_b"], "rk4_steps": s["steps"]}
    return ds


def convergence(full: bool) -> xr.Dataset:
    s = _settings(full)
    nb = np.array(s["levels"])
    lot, pil, pip, jump = [], [], [], []
    for n in nb:
        m = dict(n_a=2, n_b=int(n), order=2)
        lot.append(CircularFE(3.0, 0.0, mesh=FEMesh(**m)).loss_of_tension(8.0).lam)
        st = CircularFE(1.25, 0.0, mesh=FEMesh(**m)).pullin(4.0)
        pil.append(st.lam)
        pip.append(st.phibar)
        sj = CircularFE(3.0, 0.0, mesh=FEMesh(**m)).solve(4.0)
        jump.append(sj.T1A - sj.T1B)
    ref = {v: {**P.analytic_events(3.0, 0.0, v, s["steps"]),
               **{k: x for k, x in P.analytic_events(1.25, 0.0, v, s["steps"]).items() if k.startswith("pullin")}}
           for v in P.VARIANTS}
    a = lambda what: {"long_name": what, "units": "1"}  # noqa: E731
    vars_ = {"lam_loss_of_tension_fe": ("n_b", np.array(lot), a("FE loss-of-tension stretch, lamP = 3")),
             "lam_pullin_fe": ("n_b", np.array(pil), a("FE stretch at pull-in, lamP = 1.25, c = 0")),
             "phibar_pullin_fe": ("n_b", np.array(pip), a("FE Phibar at pull-in, lamP = 1.25, c = 0")),
             "T1_jump_fe": ("n_b", np.array(jump), a("FE T1^(A) - T1^(B) at R_A per mu, lamP = 3, lam = 4"))}
    for v in P.VARIANTS:
        vars_[f"lam_loss_of_tension_{v}"] = ((), ref[v]["loss_of_tension"], a(f"analytic ({v}) loss-of-tension stretch, lamP = 3"))
        vars_[f"lam_pullin_{v}"] = ((), ref[v]["pullin_lam"], a(f"analytic ({v}) stretch at pull-in, lamP = 1.25"))
        vars_[f"phibar_pullin_{v}"] = ((), ref[v]["pullin_phibar"], a(f"analytic ({v}) Phibar at pull-in, lamP = 1.25"))
    ds = xr.Dataset(vars_, coords={"n_b": ("n_b", nb, a("elements in annulus B (uniform in ln R)"))})
    ds.attrs = {"rk4_steps": s["steps"]}
    return ds


def profiles(full: bool) -> xr.Dataset:
    s = _settings(full)
    lamP, lam = 3.0, 4.0
    fe = CircularFE(lamP, 0.0, mesh=FEMesh(**s["profile_mesh"]))
    st = fe.solve(lam)
    out = {}
    for v in P.VARIANTS:
        br = P._branch(lamP, v, s["steps"])
        q = q_for_stretch(br.annulus, np.array([lam]), np.interp(lam, br.lam, br.q), steps=s["steps"])
        _, _, t, P1, P2 = integrate_inward(br.annulus, q, steps=s["steps"], profile=True)
        R = np.exp(t)[::-1][1:-1]
        out[v] = (P1[::-1, 0][1:-1], P2[::-1, 0][1:-1])
    p = fe.profile(st, R)
    a = lambda what: {"long_name": what, "units": "1"}  # noqa: E731
    vars_ = {f"lam{i}_fe": ("R", p[f"lam{i}"], a(f"lambda{i}, finite elements")) for i in (1, 2, 3)}
    for v in P.VARIANTS:
        l1, l2 = out[v]
        vars_[f"lam1_{v}"] = ("R", l1, a(f"lambda1, analytic ({v})"))
        vars_[f"lam2_{v}"] = ("R", l2, a(f"lambda2, analytic ({v})"))
        vars_[f"lam3_{v}"] = ("R", 1 / (l1 * l2), a(f"lambda3, analytic ({v})"))
    ds = xr.Dataset(vars_, coords={"R": ("R", R, a("reference radius R/R_A in annulus B"))})
    ds.attrs = {"lamP": lamP, "lam": lam, "mesh_n_b": s["profile_mesh"]["n_b"], "rk4_steps": s["steps"]}
    return ds


#: centre stretches of the thickness dataset (lamP = 3)
THICKNESS_LAM_CENTRE = (4.0, 4.5)


def thickness(full: bool) -> xr.Dataset:
    """Phibar of the thin solid at fixed centre stretches (lamP = 3) per film thickness H
    and through-thickness resolution nz, the membrane FE, both analytic variants and the
    H -> 0 extrapolation per (nz, lam_centre)."""
    Hs = P.THICKNESS_H_FINE if full else P.THICKNESS_H
    nzs = (1, 2) if full else (1,)
    lc = np.array(THICKNESS_LAM_CENTRE)
    phib = np.full((len(nzs), len(Hs), len(lc)), np.nan)
    extrap = np.empty((len(nzs), len(lc)))
    err = np.empty((len(nzs), len(lc)))
    order = np.empty((len(nzs), len(lc)))
    for i, nz in enumerate(nzs):
        mesh = dict(P.SOLID_MESH_COARSE, nz=nz)
        hs = Hs if nz == 1 else P.THICKNESS_H
        for k, lam_c in enumerate(lc):
            d = P.thickness_study("phibar", P.SOLID_LAMP, hs, mesh, float(lam_c))
            phib[i, :len(hs), k] = d["values"]
            extrap[i, k], err[i, k], order[i, k] = (d["extrapolated"], d["extrapolation_error"],
                                                    d["order"])
    mem = np.array([P._fe(P.SOLID_LAMP, 0.0, P.MEMBRANE_REFERENCE_MESH).solve(float(x)).phibar for x in lc])
    a = lambda what: {"long_name": what, "units": "1"}  # noqa: E731
    vars_ = {"phibar_solid": (("nz", "H", "lam_centre"), phib, a("Phibar of the thin axisymmetric solid (NaN: not computed)")),
             "phibar_extrapolated": (("nz", "lam_centre"), extrap, a("solid Phibar extrapolated to H -> 0 (Richardson, order 1, two thinnest films)")),
             "extrapolation_error": (("nz", "lam_centre"), err, a("uncertainty of the extrapolation: |order-1 minus observed-order extrapolation| + the in-plane mesh error of the membrane limit")),
             "order_observed": (("nz", "lam_centre"), order, a("observed order in H of the solid Phibar (three thinnest films)")),
             "phibar_membrane_fe": ("lam_centre", mem, a("Phibar of the membrane FE"))}
    for v in P.VARIANTS:
        vars_[f"phibar_{v}"] = ("lam_centre", P.analytic_phibar(P.SOLID_LAMP, 0.0, v, lc), a(f"Phibar, analytic ({v})"))
    ds = xr.Dataset(vars_, coords={
        "nz": ("nz", np.array(nzs), a("element rows through the half thickness (edge elements H/(2 nz) square)")),
        "H": ("H", np.array(Hs), a("undeformed film thickness H/R_A")),
        "lam_centre": ("lam_centre", lc, a("centre stretch of circle A (lambda_theta at the axis)"))})
    ds.attrs = {"model": "thin axisymmetric solid FE (models/circular/fe_solid.py) beside the membrane FE (models/circular/fe.py)",
                "lamP": P.SOLID_LAMP, "solid_n_a": P.SOLID_MESH_COARSE["n_a"],
                "solid_n_b": P.SOLID_MESH_COARSE["n_b"], "membrane_n_b": P.MEMBRANE_REFERENCE_MESH["n_b"]}
    return ds


DATASETS = {
    "ch3_fe_voltage_stretch": (voltage_stretch, "Chapter 3 voltage-stretch curves: finite elements vs both equilibrium variants",
                               "Phibar(lam) of the circular actuator by the axisymmetric membrane FE and by the analytic model with the printed (3.33) and the thin-membrane equilibrium."),
    "ch3_fe_convergence": (convergence, "Chapter 3 finite-element convergence study",
                           "Loss of tension (lamP = 3), pull-in (lamP = 1.25) and the interface stress jump per mesh, beside the analytic values of both equilibrium variants."),
    "ch3_fe_profiles": (profiles, "Chapter 3 annulus stretch profiles: finite elements vs both equilibrium variants",
                        "lambda1, lambda2, lambda3 in annulus B at lamP = 3, lambda(R_A) = 4 by FE and by the analytic model (printed and membrane)."),
    "ch3_fe_thickness": (thickness, "Chapter 3 film thickness: the thin axisymmetric solid tends to the membrane balance",
                         "Phibar at fixed centre stretches (lamP = 3) of the thin solid FE per film thickness H and through-thickness resolution, its extrapolation to H -> 0, the membrane FE and both analytic variants."),
}


def build(out_dir: Path, *, full: bool = False) -> list[Path]:
    """Write the Chapter 3 FE datasets to ``out_dir``; ``full`` uses the converged meshes."""
    out_dir = Path(out_dir)
    paths = []
    for name, (make, title, summary) in DATASETS.items():
        ds = make(full)
        prm = _params(full, **ds.attrs)
        ds.attrs = {}
        paths.append(write_dataset(ds, name, title=title, summary=summary, parameters=prm,
                                   out_dir=out_dir, overwrite=True))
    return paths
