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

The thin-solid thickness study has its own builder (:mod:`.ch3_fe_thickness`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr
from debench.models.circular.fe import CircularFE, FEMesh
from debench.models.circular.shooting import integrate_inward, q_for_stretch
from debench.reference.datasets import write_dataset
from debench.reference.studies import ch3_fe as study

#: CPU seconds of the default build (one thread, measured in one `debench reproduce` with
#: two pool processes on the quiet 2-core machine): the pool starts the longest first.
BUILD_CPU_S = 7.0
#: ``debench verify`` rebuilds this chapter's default plan and compares it with data/.
REGENERATED_BY_VERIFY = True
#: Model guards ``debench verify`` runs for this chapter (none).
GUARDS = {}


def voltage_stretch(full: bool) -> xr.Dataset:
    s = study.build_settings(full)
    k = np.arange(8)
    shape = (len(study.CURVE_LAMP), len(study.CURVE_C), len(k))
    data = {n: np.empty(shape) for n in ("fe", "printed", "membrane")}
    lam = np.empty((len(study.CURVE_LAMP), len(k)))
    # every curve's analytic branches (both variants) traced in one batch
    study.analytic_branches([(lamP, v) for lamP in study.CURVE_LAMP for v in study.VARIANTS],
                            s["steps"])
    for i, lamP in enumerate(study.CURVE_LAMP):
        lam[i] = study.curve_grid(lamP)
        for j, c in enumerate(study.CURVE_C):
            d = study.voltage_stretch(lamP, c, s["curve_mesh"], lam[i], steps=s["steps"])
            for n in data:
                data[n][i, j] = d[n]
    dims = ("lamP", "c", "point")
    ds = xr.Dataset(
        {f"phibar_{n}": (dims, v, {"long_name": f"normalised voltage Phibar, {what}", "units": "1"})
         for n, v, what in [("fe", data["fe"], "finite elements"),
                            ("printed", data["printed"], "analytic, Eq. (3.33) as printed"),
                            ("membrane", data["membrane"], "analytic, thin-membrane balance")]},
        coords={"lamP": ("lamP", np.array(study.CURVE_LAMP), {"long_name": "equibiaxial pre-stretch", "units": "1"}),
                "c": ("c", np.array(study.CURVE_C), {"long_name": "Zhao-Suo electrostrictive factor (3.27)", "units": "1"}),
                "point": ("point", k, {"long_name": "index of the stretch on the curve", "units": "1"}),
                "lam": (("lamP", "point"), lam, {"long_name": "stretch of circle A r(R_A)/R_A", "units": "1"})})
    ds.attrs = {"mesh_n_b": s["curve_mesh"]["n_b"], "rk4_steps": s["steps"]}
    return ds


def convergence(full: bool) -> xr.Dataset:
    s = study.build_settings(full)
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
    ref = {v: {**study.analytic_events(3.0, 0.0, v, s["steps"]),
               **{k: x for k, x in study.analytic_events(1.25, 0.0, v, s["steps"]).items() if k.startswith("pullin")}}
           for v in study.VARIANTS}
    a = lambda what: {"long_name": what, "units": "1"}  # noqa: E731
    vars_ = {"lam_loss_of_tension_fe": ("n_b", np.array(lot), a("FE loss-of-tension stretch, lamP = 3")),
             "lam_pullin_fe": ("n_b", np.array(pil), a("FE stretch at pull-in, lamP = 1.25, c = 0")),
             "phibar_pullin_fe": ("n_b", np.array(pip), a("FE Phibar at pull-in, lamP = 1.25, c = 0")),
             "T1_jump_fe": ("n_b", np.array(jump), a("FE T1^(A) - T1^(B) at R_A per mu, lamP = 3, lam = 4"))}
    for v in study.VARIANTS:
        vars_[f"lam_loss_of_tension_{v}"] = ((), ref[v]["loss_of_tension"], a(f"analytic ({v}) loss-of-tension stretch, lamP = 3"))
        vars_[f"lam_pullin_{v}"] = ((), ref[v]["pullin_lam"], a(f"analytic ({v}) stretch at pull-in, lamP = 1.25"))
        vars_[f"phibar_pullin_{v}"] = ((), ref[v]["pullin_phibar"], a(f"analytic ({v}) Phibar at pull-in, lamP = 1.25"))
    ds = xr.Dataset(vars_, coords={"n_b": ("n_b", nb, a("elements in annulus B (uniform in ln R)"))})
    ds.attrs = {"rk4_steps": s["steps"]}
    return ds


def profiles(full: bool) -> xr.Dataset:
    s = study.build_settings(full)
    lamP, lam = 3.0, 4.0
    fe = CircularFE(lamP, 0.0, mesh=FEMesh(**s["profile_mesh"]))
    st = fe.solve(lam)
    out = {}
    for v in study.VARIANTS:
        br = study.analytic_branch(lamP, v, s["steps"])
        q = q_for_stretch(br.annulus, np.array([lam]), np.interp(lam, br.lam, br.q), steps=s["steps"])
        _, _, t, P1, P2 = integrate_inward(br.annulus, q, steps=s["steps"], profile=True)
        R = np.exp(t)[::-1][1:-1]
        out[v] = (P1[::-1, 0][1:-1], P2[::-1, 0][1:-1])
    p = fe.profile(st, R)
    a = lambda what: {"long_name": what, "units": "1"}  # noqa: E731
    vars_ = {f"lam{i}_fe": ("R", p[f"lam{i}"], a(f"lambda{i}, finite elements")) for i in (1, 2, 3)}
    for v in study.VARIANTS:
        l1, l2 = out[v]
        vars_[f"lam1_{v}"] = ("R", l1, a(f"lambda1, analytic ({v})"))
        vars_[f"lam2_{v}"] = ("R", l2, a(f"lambda2, analytic ({v})"))
        vars_[f"lam3_{v}"] = ("R", 1 / (l1 * l2), a(f"lambda3, analytic ({v})"))
    ds = xr.Dataset(vars_, coords={"R": ("R", R, a("reference radius R/R_A in annulus B"))})
    ds.attrs = {"lamP": lamP, "lam": lam, "mesh_n_b": s["profile_mesh"]["n_b"], "rk4_steps": s["steps"]}
    return ds


DATASETS = {
    "ch3_fe_voltage_stretch": (voltage_stretch, "Chapter 3 voltage-stretch curves: finite elements vs both equilibrium variants",
                               "Phibar(lam) of the circular actuator by the axisymmetric membrane FE and by the analytic model with the printed (3.33) and the thin-membrane equilibrium."),
    "ch3_fe_convergence": (convergence, "Chapter 3 finite-element convergence study",
                           "Loss of tension (lamP = 3), pull-in (lamP = 1.25) and the interface stress jump per mesh, beside the analytic values of both equilibrium variants."),
    "ch3_fe_profiles": (profiles, "Chapter 3 annulus stretch profiles: finite elements vs both equilibrium variants",
                        "lambda1, lambda2, lambda3 in annulus B at lamP = 3, lambda(R_A) = 4 by FE and by the analytic model (printed and membrane)."),
}


def build(out_dir: Path, *, full: bool = False) -> list[Path]:
    """Write the Chapter 3 FE datasets to ``out_dir``; ``full`` uses the converged meshes."""
    out_dir = Path(out_dir)
    paths = []
    for name, (make, title, summary) in DATASETS.items():
        ds = make(full)
        prm = study.dataset_parameters(full, **ds.attrs)
        ds.attrs = {}
        paths.append(write_dataset(ds, name, title=title, summary=summary, parameters=prm,
                                   out_dir=out_dir, overwrite=True))
    return paths
