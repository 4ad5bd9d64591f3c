# ruff: noqa: E501  -- CF attribute dicts and dataset descriptions read best on one line
"""Builder of the Chapter 3 datasets and figures (Figs 3.2-3.9 of Zeng 2020).

Datasets (``ch3_*``, written with :func:`debench.reference.datasets.write_dataset`):

* ``ch3_annulus_profiles``: lambda_1, lambda_2, lambda_3 along R/R_A in annulus B and the
  circle-A stretch, lamP = 3, R_B/R_A = 15, Phibar = 0.2, c = 0 and -0.053 (Figs 3.2-3.3).
* ``ch3_voltage_stretch``: Phibar(lambda), sigma1^(A)(lambda), the breakdown line, for the
  pre-stretches and c values of Figs 3.4-3.8 (equilibrium as printed, Eq. 3.33).
* ``ch3_voltage_stretch_membrane``: the same curves with the consistent thin-membrane
  balance d(R T1)/dR = T2 in annulus B (erratum ch3.erratum.eq_3_33).
* ``ch3_failure_points``: pull-in, loss of tension, breakdown and the first failure per
  (equilibrium variant, lamP, c) (Fig. 3.7 symbols; the printed/membrane comparison).
* ``ch3_c_sweep``: lam_max and Phibar at failure over c in [-0.1, 0] for lamP = 1.25, 2,
  3 (Fig. 3.9), with the failure mode.
* ``ch3_eps_r_sensitivity``: lam_max and failure mode per eps_r (assumption
  ch3.assumption.eps_r) for the Fig. 3.7 pre-stretches, c = 0 and -0.053.
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import xarray as xr
from debench.models.circular import circle_a, params
from debench.models.circular.actuator import Event
from debench.models.circular.chapter_pass import Chapter
from debench.models.circular.events import EVENT_KINDS
from debench.reference import figures as figure_io
from debench.reference.datasets import write_dataset
from debench.reference.figures import LABELS as L
from debench.reference.figures import (
    mark_thesis,
    mark_thesis_x,
    percent_note,
    printed_value,
    pyplot,
    written,
)
from debench.reference.studies.ch3 import (
    C_CURVES,
    EPS_R,
    LAMP_CURVES,
    LAMP_SWEEP,
    PROFILE_STATE,
    RADIUS_RATIO,
    c_grid,
    chapter_pass,
    settings,
)

#: CPU seconds of the default build (one thread, measured in one `debench reproduce` with
#: two pool processes on the quiet 2-core machine): the pool starts the longest first.
BUILD_CPU_S = 8.0
#: ``debench verify`` rebuilds this chapter's default plan and compares it with data/.
REGENERATED_BY_VERIFY = True
#: Model guards ``debench verify`` runs for this chapter (none).
GUARDS = {}

#: failure kinds, flag values 1..6; "permittivity": the factor K = 1 + c(5 lam/2 - 2) of
#: (3.30) reaches 0 (at the pre-stretch itself: no admissible curve at all)
MODES = ("pullin", "loss_of_tension", "breakdown", "locking", "end", "permittivity")


def _mode_code(failure) -> int:
    return 0 if failure is None else MODES.index(failure.kind) + 1


def _mode_attrs() -> dict:
    return {"long_name": "failure mode (first event along increasing stretch)", "units": "1",
            "flag_values": np.arange(len(MODES) + 1, dtype=np.int8),
            "flag_meanings": ("none pull_in loss_of_tension dielectric_breakdown "
                              "gent_locking end_of_admissible_branch "
                              "nonpositive_permittivity_factor")}


def _curve(ch: Chapter, lamP: float, c: float, eps_r=None, equilibrium="printed"):
    """The chapter's curve, or the :func:`_inadmissible_curve` record where the
    permittivity factor K of (3.30) is non-positive at the pre-stretch."""
    e = float(ch.spec.eps_r if eps_r is None else eps_r)
    key = (float(lamP), float(c), e, equilibrium)
    if key in ch.curves:
        return ch.curves[key]
    br = ch.branches[(float(lamP), equilibrium)]
    return _inadmissible_curve(br, float(c), circle_a._breakdown(br.lam, e, ch.spec.mu))


def _inadmissible_curve(br, c: float, phibar_breakdown: np.ndarray) -> SimpleNamespace:
    """The record of a (lamP, c) whose permittivity factor K = 1 + c(5 lam/2 - 2) of (3.30)
    is non-positive already at the pre-stretch: no voltage-stretch curve exists; the
    failure is computed (kind "permittivity", at lamP) and the curve holds no values."""
    lamP = float(br.annulus.lamP)
    nan = np.full(br.lam.size, np.nan)
    fail = Event("permittivity", lamP, 0.0, float("nan"))
    return SimpleNamespace(lam=br.lam, phibar=nan, sigma1A=nan,
                           phibar_breakdown=phibar_breakdown,
                           events={k: None for k in EVENT_KINDS}, failure=fail,
                           lam_max=lamP, phibar_max=0.0, c=c)


def _common_params(full: bool) -> dict:
    s = settings(full)
    return {"mu": params.MU_VHB, "Jm": params.JM_VHB, "radius_ratio": RADIUS_RATIO,
            "eps_r": params.EPS_R_ASSUMED, "eps0": params.EPS0,
            "breakdown_field": "51e6 * lam**1.13 V/m", "rk4_steps": s["steps"],
            "equilibrium": "printed (Eq. 3.33)"}


# ------------------------------------------------------------------ datasets
def annulus_profiles(full: bool = False, ch: Chapter | None = None) -> xr.Dataset:
    """Figs 3.2-3.3: the states at :data:`PROFILE_STATE` for c = 0 and c (equilibrium as
    printed) and their annulus profiles, from the chapter pass."""
    ch = ch if ch is not None else chapter_pass(full)
    lamP, phibar, c1 = PROFILE_STATE
    cs = (0.0, c1)
    rows = [(float(lamP), float(phibar), float(c), "printed") for c in cs]
    sts = [ch.states[r] for r in rows]
    l1 = np.array([ch.profiles[r][0] for r in rows])
    l2 = np.array([ch.profiles[r][1] for r in rows])
    rho = ch.profiles[rows[0]][2]
    one = {"units": "1"}
    return xr.Dataset(
        {
            "lambda1": (("c", "r_over_ra"), l1, {**one, "long_name": "radial stretch lambda_1 in annulus B"}),
            "lambda2": (("c", "r_over_ra"), l2, {**one, "long_name": "hoop stretch lambda_2 in annulus B"}),
            "lambda3": (("c", "r_over_ra"), 1 / (l1 * l2), {**one, "long_name": "thickness stretch lambda_3 in annulus B"}),
            "lambda_a": ("c", [st["lam"] for st in sts], {**one, "long_name": "equibiaxial stretch of circle A"}),
            "lambda3_a": ("c", [st["lam3A"] for st in sts], {**one, "long_name": "thickness stretch of circle A"}),
        },
        coords={
            "c": ("c", np.array(cs), {**one, "long_name": "Zhao-Suo electrostrictive factor c (Eq. 3.27)"}),
            "r_over_ra": ("r_over_ra", rho, {**one, "long_name": "normalised reference radius R/R_A"}),
        },
        attrs={"lamP": lamP, "phibar": phibar})


def voltage_stretch(family) -> xr.Dataset:
    lamPs = list(family)
    n = family[lamPs[0]][0].lam.size
    lam = np.array([family[p][0].lam for p in lamPs])
    T1 = np.array([family[p][0].T1 for p in lamPs])
    phi = np.array([[cv.phibar for cv in family[p][1]] for p in lamPs])
    sig = np.array([[cv.sigma1A for cv in family[p][1]] for p in lamPs])
    pb = np.array([family[p][1][0].phibar_breakdown for p in lamPs])
    one = {"units": "1"}
    return xr.Dataset(
        {
            "lambda_a": (("lamP", "point"), lam, {**one, "long_name": "equibiaxial stretch of circle A"}),
            "t1_interface": (("lamP", "point"), T1, {**one, "long_name": "nominal radial stress of annulus B at R_A over mu"}),
            "phibar": (("lamP", "c", "point"), phi, {**one, "long_name": "normalised voltage sqrt(eps_bar/mu) Phi/H"}),
            "sigma1_a": (("lamP", "c", "point"), sig, {**one, "long_name": "true radial stress of circle A over mu (Eq. 3.30)"}),
            "phibar_breakdown": (("lamP", "point"), pb, {**one, "long_name": "normalised voltage at dielectric breakdown"}),
        },
        coords={
            "lamP": ("lamP", np.array(lamPs), {**one, "long_name": "equibiaxial pre-stretch"}),
            "c": ("c", np.array(C_CURVES), {**one, "long_name": "Zhao-Suo electrostrictive factor c"}),
            "point": ("point", np.arange(n), {**one, "long_name": "index along the continuation in the circle-A stretch"}),
        })


#: the ``equilibrium`` parameter of a dataset built with the thin-membrane balance
MEMBRANE_EQUILIBRIUM = "membrane: d(R T1)/dR = T2 (consistent thin-membrane balance)"


def _with_equilibrium(ds: xr.Dataset, equilibrium: str) -> xr.Dataset:
    """``ds`` with the ``equilibrium`` parameter (a dataset attribute, which the writer
    merges over the common parameters)."""
    ds = ds.copy()
    ds.attrs["equilibrium"] = equilibrium
    return ds


def _family(ch: Chapter, equilibrium: str = "printed") -> dict:
    """{lamP: (branch, curves over C_CURVES)} of one variant, from the chapter pass."""
    return {p: (ch.branches[(float(p), equilibrium)],
                [_curve(ch, p, c, equilibrium=equilibrium) for c in C_CURVES])
            for p in LAMP_CURVES}


def failure_points(full: bool = False, ch: Chapter | None = None) -> xr.Dataset:
    """Events and failure modes of the C_CURVES curves, both equilibrium variants."""
    ch = ch if ch is not None else chapter_pass(full)
    variants = ("printed", "membrane")
    data = {k: np.full((2, len(LAMP_CURVES), len(C_CURVES)), np.nan) for k in
            [f"{e}_{q}" for e in EVENT_KINDS for q in ("lambda", "phibar")]}
    mode = np.zeros((2, len(LAMP_CURVES), len(C_CURVES)), np.int8)
    for v, eq in enumerate(variants):
        fam = _family(ch, eq)
        for i, lamP in enumerate(LAMP_CURVES):
            for j, cv in enumerate(fam[lamP][1]):
                for k, ev in cv.events.items():
                    if ev is not None:
                        data[f"{k}_lambda"][v, i, j] = ev.lam
                        data[f"{k}_phibar"][v, i, j] = ev.phibar
                mode[v, i, j] = _mode_code(cv.failure)
    one = {"units": "1"}
    dims = ("equilibrium", "lamP", "c")
    names = {"pullin": "pull-in (local maximum of Phibar)", "minimum": "local minimum of Phibar",
             "loss_of_tension": "loss of tension (sigma1 of circle A = 0)",
             "breakdown": "dielectric breakdown"}
    dv = {}
    for k in EVENT_KINDS:
        dv[f"{k}_lambda"] = (dims, data[f"{k}_lambda"], {**one, "long_name": f"stretch at {names[k]}"})
        dv[f"{k}_phibar"] = (dims, data[f"{k}_phibar"], {**one, "long_name": f"Phibar at {names[k]}"})
    dv["failure_mode"] = (dims, mode, _mode_attrs())
    return xr.Dataset(dv, coords={
        "equilibrium": ("equilibrium", np.array(variants, dtype=object),
                        {"long_name": "annulus equilibrium: printed Eq. (3.33) or thin-membrane balance d(R T1)/dR = T2"}),
        "lamP": ("lamP", np.array(LAMP_CURVES), {**one, "long_name": "equibiaxial pre-stretch"}),
        "c": ("c", np.array(C_CURVES), {**one, "long_name": "Zhao-Suo electrostrictive factor c"}),
    })


def c_sweep(full: bool = False, lamPs=LAMP_SWEEP, ch: Chapter | None = None) -> xr.Dataset:
    """Fig. 3.9: the first failure over the c grid at ``lamPs`` (among LAMP_SWEEP)."""
    ch = ch if ch is not None else chapter_pass(full)
    cs = c_grid(full)
    lam = np.full((len(lamPs), cs.size), np.nan)
    phi = np.full_like(lam, np.nan)
    mode = np.zeros(lam.shape, np.int8)
    for i, lamP in enumerate(lamPs):
        for j, c in enumerate(cs):
            cv = _curve(ch, lamP, c)
            lam[i, j], phi[i, j] = cv.lam_max, cv.phibar_max
            mode[i, j] = _mode_code(cv.failure)
    one = {"units": "1"}
    return xr.Dataset(
        {"lambda_max": (("lamP", "c"), lam, {**one, "long_name": "maximum stretch of circle A (first failure)"}),
         "phibar_at_lambda_max": (("lamP", "c"), phi, {**one, "long_name": "Phibar at the maximum stretch"}),
         "failure_mode": (("lamP", "c"), mode, _mode_attrs())},
        coords={"lamP": ("lamP", np.array(lamPs), {**one, "long_name": "equibiaxial pre-stretch"}),
                "c": ("c", cs, {**one, "long_name": "Zhao-Suo electrostrictive factor c"})})


def eps_r_sensitivity(full: bool = False, ch: Chapter | None = None) -> xr.Dataset:
    """lam_max and the failure mode per eps_r (assumption), c = 0 and -0.053."""
    ch = ch if ch is not None else chapter_pass(full)
    cs2 = (0.0, params.C_WISSLER_MAZZA)
    lam = np.full((len(EPS_R), len(LAMP_CURVES), 2), np.nan)
    mode = np.zeros(lam.shape, np.int8)
    for i, lamP in enumerate(LAMP_CURVES):
        for k, e in enumerate(EPS_R):
            for j, c in enumerate(cs2):
                cv = _curve(ch, lamP, c, e)
                lam[k, i, j] = cv.lam_max
                mode[k, i, j] = _mode_code(cv.failure)
    one = {"units": "1"}
    return xr.Dataset(
        {"lambda_max": (("eps_r", "lamP", "c"), lam, {**one, "long_name": "maximum stretch of circle A (first failure)"}),
         "failure_mode": (("eps_r", "lamP", "c"), mode, _mode_attrs())},
        coords={"eps_r": ("eps_r", np.array(EPS_R), {**one, "long_name": "relative permittivity (assumption)"}),
                "lamP": ("lamP", np.array(LAMP_CURVES), {**one, "long_name": "equibiaxial pre-stretch"}),
                "c": ("c", np.array(cs2), {**one, "long_name": "Zhao-Suo electrostrictive factor c"})})


def compute(full: bool = False) -> dict[str, xr.Dataset]:
    """All Chapter 3 datasets (no I/O), from the one memoised chapter pass
    (:func:`debench.reference.studies.ch3.chapter_spec`: the branches of both equilibrium variants in one scan and one
    grid integration, every event of every curve located together)."""
    ch = chapter_pass(full)
    return {
        "ch3_annulus_profiles": annulus_profiles(full, ch),
        "ch3_voltage_stretch": voltage_stretch(_family(ch)),
        "ch3_voltage_stretch_membrane": _with_equilibrium(
            voltage_stretch(_family(ch, "membrane")), MEMBRANE_EQUILIBRIUM),
        "ch3_failure_points": failure_points(full, ch),
        "ch3_c_sweep": c_sweep(full, ch=ch),
        "ch3_eps_r_sensitivity": eps_r_sensitivity(full, ch),
    }


_TEXT = {
    "ch3_annulus_profiles": ("Chapter 3 annulus stretch profiles (Figs 3.2-3.3)",
                             "Stretches along the radius of annulus B of the pre-stretched circular actuator, lamP = 3, RB/RA = 15, Phibar = 0.2, constant (c = 0) and Zhao-Suo (c = -0.053) permittivity."),
    "ch3_voltage_stretch": ("Chapter 3 voltage-stretch curves (Figs 3.4-3.8)",
                            "Normalised voltage and circle-A stress versus circle-A stretch for pre-stretches 1.1-5 and c from 0 to -0.1, RB/RA = 15, Gent Jm = 120; the dielectric breakdown line."),
    "ch3_voltage_stretch_membrane": ("Chapter 3 voltage-stretch curves, consistent thin-membrane balance",
                                     "Normalised voltage and circle-A stress versus circle-A stretch for pre-stretches 1.1-5 and c from 0 to -0.1, RB/RA = 15, Gent Jm = 120, with the thin-membrane balance d(R T1)/dR = T2 in annulus B instead of the printed Eq. (3.33); the dielectric breakdown line."),
    "ch3_failure_points": ("Chapter 3 failure points (Fig. 3.7) for both annulus equilibrium variants",
                           "Pull-in, local minimum, loss of tension and breakdown points and the governing failure mode for each pre-stretch and c, with Eq. (3.33) as printed and with the thin-membrane balance."),
    "ch3_c_sweep": ("Chapter 3 maximum stretch versus c (Fig. 3.9)",
                    "Maximum achievable stretch of circle A and the corresponding normalised voltage over c in [-0.1, 0] for lamP = 1.25, 2, 3."),
    "ch3_eps_r_sensitivity": ("Chapter 3 sensitivity to the assumed relative permittivity",
                              "Maximum stretch and failure mode for eps_r = 3.5 .. 5.5 (the thesis does not state eps_r), c = 0 and -0.053."),
}


# ------------------------------------------------------------------ figures
_PCT_LABEL = r"thesis: printed % change, applied to our $c$ = 0 value"
_ENDS_NOTE = ("diamond pull-in (dotted beyond), square breakdown;\n"
              "curves end at loss of tension or breakdown")


def figures(ds: dict[str, xr.Dataset], fig_dir: Path) -> list[Path]:
    """Figs 3.2-3.9 from the datasets of :func:`compute`, each with the thesis' printed
    values marked (:func:`debench.reference.figures.mark_thesis`)."""
    plt = pyplot()
    a, s = ds["ch3_annulus_profiles"], ds["ch3_c_sweep"]
    v, f = ds["ch3_voltage_stretch"], ds["ch3_failure_points"].sel(equilibrium="printed")
    drawn = (("fig3_2_annulus_stretches", _fig3_2, (a,)),
             ("fig3_3_thickness_stretch", _fig3_3, (a,)),
             ("fig3_4_voltage_stretch_c0", _fig3_4, (v, f)),
             ("fig3_5_voltage_stretch_lamP_1p25", _fig3_5, (v, f)),
             ("fig3_6_sigma1_lamP_3", _fig3_6, (v, f)),
             ("fig3_7_failure_modes", _fig3_7, (v, f)),
             ("fig3_8_voltage_stretch_c", _fig3_8, (v, f)),
             ("fig3_9_c_sweep", _fig3_9, (s,)))
    out = []
    for name, draw, data in drawn:
        out += figure_io.save(draw(plt, *data), fig_dir / name)  # module attribute: tests replace it
    return out


def _implied(entry_id: str, base: float, sign: int) -> float:
    """The c = -0.053 value the thesis' printed percentage implies from our c = 0 one."""
    return base * (1 + sign * printed_value(entry_id) / 100)


def _curve_upto(v: xr.Dataset, lp, c, stop, phi_stop=np.nan):
    """The computed curve below ``stop``, closed by the event point (stop, phi_stop)."""
    lam = v.lambda_a.sel(lamP=lp).values
    phi = v.phibar.sel(lamP=lp, c=c).values
    m = (lam < stop) & np.isfinite(phi)
    lam, phi = lam[m], phi[m]
    if np.isfinite(stop) and np.isfinite(phi_stop):
        lam, phi = np.append(lam, stop), np.append(phi, phi_stop)
    return lam, phi


def _end_of(f: xr.Dataset, lp, c):
    """Where a curve ends: loss of tension (the membrane model ends) or dielectric
    breakdown (the material fails), whichever comes first: (lambda, Phibar, kind)."""
    fp = f.sel(lamP=lp, c=c)
    ends = [(float(fp.loss_of_tension_lambda), float(fp.loss_of_tension_phibar), "lot"),
            (float(fp.breakdown_lambda), float(fp.breakdown_phibar), "breakdown")]
    ends = [e for e in ends if np.isfinite(e[0])]
    return min(ends) if ends else (np.inf, np.nan, None)


def _draw(ax, v: xr.Dataset, f: xr.Dataset, lp, c, label: str) -> None:
    """One voltage-stretch curve up to its end, dotted past pull-in (the unstable
    branch), with the pull-in diamond and the breakdown square."""
    stop, phi_stop, kind = _end_of(f, lp, c)
    lam, phi = _curve_upto(v, lp, c, stop, phi_stop)
    fp = f.sel(lamP=lp, c=c)
    pl, pp = float(fp.pullin_lambda), float(fp.pullin_phibar)
    if np.isfinite(pl) and pl < stop:
        st = lam < pl
        (ln,) = ax.plot(np.append(lam[st], pl), np.append(phi[st], pp), label=label)
        ax.plot(np.insert(lam[~st], 0, pl), np.insert(phi[~st], 0, pp), ":",
                color=ln.get_color(), lw=1.1)
        ax.plot(pl, pp, "kd", ms=5)
    else:
        ax.plot(lam, phi, label=label)
    if kind == "breakdown":
        ax.plot(stop, phi_stop, "ks", ms=5, mfc="none")


def _failure(f: xr.Dataset, lp, c):
    """(lambda_max, Phibar there, failure code) of one curve (Fig. 3.7 symbols)."""
    fp = f.sel(lamP=lp, c=c)
    code = int(fp.failure_mode)
    ev = {1: "pullin", 2: "loss_of_tension", 3: "breakdown"}.get(code)
    if ev is None:
        return np.inf, np.nan, code
    return float(fp[f"{ev}_lambda"]), float(fp[f"{ev}_phibar"]), code


def _fig3_2(plt, a: xr.Dataset):
    """Fig. 3.2: radial and hoop stretch in annulus B, c = 0 and c = -0.053."""
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    for k, (c, ls) in enumerate(zip(a.c.values, ("-", "--"), strict=True)):
        ax.plot(a.r_over_ra, a.lambda1[k], "b" + ls, label=rf"$\lambda_1$, $c$ = {c:g}")
        ax.plot(a.r_over_ra, a.lambda2[k], "r" + ls, label=rf"$\lambda_2$, $c$ = {c:g}")
    at_ra = a.sel(c=0.0).isel(r_over_ra=0)
    for eid, var, sign, off in (("ch3.annulus.lam1_interface_increase", "lambda1", 1, (7, -12)),
                                ("ch3.annulus.lam2_interface_decrease", "lambda2", -1, (7, -12))):
        mark_thesis(ax, 1.0, _implied(eid, float(at_ra[var]), sign),
                    _PCT_LABEL if sign > 0 else None, entries=[eid],
                    note=percent_note(eid, "+" if sign > 0 else "\u2212"), note_offset=off)
    ax.set(xlabel=L["r_over_ra"], ylabel=L["lambda_12"],
           title=r"Fig. 3.2: annulus B, $\lambda_P$ = 3, $\bar\Phi$ = 0.2")
    ax.legend(fontsize=8)
    return fig


def _fig3_3(plt, a: xr.Dataset):
    """Fig. 3.3: thickness stretch in annulus B and circle A."""
    at_ra = a.sel(c=0.0).isel(r_over_ra=0)
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    for k, (c, ls) in enumerate(zip(a.c.values, ("-", "--"), strict=True)):
        ax.plot(a.r_over_ra, a.lambda3[k], "k" + ls, label=f"annulus B, $c$ = {c:g}")
        ax.plot([0, 1], [a.lambda3_a[k]] * 2, "g" + ls, label=f"circle A, $c$ = {c:g}")
    eid = "ch3.annulus.thickness_A_increase"
    mark_thesis(ax, 0.5, _implied(eid, float(a.lambda3_a.sel(c=0.0)), 1), _PCT_LABEL,
                entries=[eid], note=percent_note(eid))
    eid = "ch3.annulus.lam3_interface_decrease"
    mark_thesis(ax, 1.0, _implied(eid, float(at_ra.lambda3), -1), None, entries=[eid],
                note=percent_note(eid, "\u2212"), note_offset=(7, 4))
    ax.set(xlabel=L["r_over_ra"], ylabel=L["lambda_3"],
           title=r"Fig. 3.3: thickness stretch, $\lambda_P$ = 3, $\bar\Phi$ = 0.2")
    ax.legend(fontsize=8, loc="center right")
    return fig


def _fig3_4(plt, v: xr.Dataset, f: xr.Dataset):
    """Fig. 3.4: voltage-stretch curves at c = 0 for every pre-stretch."""
    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    for lp in v.lamP.values:
        _draw(ax, v, f, lp, 0.0, rf"$\lambda_P$ = {lp:g}")
    eid = "ch3.pullin.suppression_prestretch"
    mark_thesis(ax, printed_value(eid), 0.0,
                rf"thesis: no pull-in for $\lambda_P \geq$ {printed_value(eid):g}",
                entries=[eid])
    ax.set(xlabel=L["lambda_A"], ylabel=L["phibar"], ylim=(-0.02, 0.8),
           title="Fig. 3.4: $c$ = 0; " + _ENDS_NOTE)
    ax.legend(fontsize=8, ncol=2)
    return fig


def _fig3_5(plt, v: xr.Dataset, f: xr.Dataset):
    """Fig. 3.5: voltage-stretch curves at lamP = 1.25 for every c."""
    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    for c in v.c.values:
        _draw(ax, v, f, 1.25, c, f"$c$ = {c:g}")
    eid = "ch3.pullin.voltage_lamP_1p25"
    mark_thesis(ax, float(f.pullin_lambda.sel(lamP=1.25, c=0.0)), printed_value(eid),
                r"thesis: pull-in $\bar\Phi$, $c$ = 0", entries=[eid])
    ax.set(xlabel=L["lambda_A"], ylabel=L["phibar"],
           title="Fig. 3.5: $\\lambda_P$ = 1.25; " + _ENDS_NOTE)
    ax.legend(fontsize=8, loc="lower right")
    return fig


def _fig3_6(plt, v: xr.Dataset, f: xr.Dataset):
    """Fig. 3.6: circle-A stress at lamP = 3, c = 0, up to the loss of tension."""
    fig, ax = plt.subplots(figsize=(5, 4))
    lam = v.lambda_a.sel(lamP=3.0).values
    lot = float(f.loss_of_tension_lambda.sel(lamP=3.0, c=0.0))
    m = lam <= lot
    ax.plot(lam[m], v.sigma1_a.sel(lamP=3.0, c=0.0).values[m], label="computed (Eq. 3.33)")
    ax.axhline(0, color="k", lw=0.5)
    ax.axvline(lot, color="r", ls=":", label=f"loss of tension {lot:.3f}")
    eid = "ch3.loss_of_tension.stretch_lamP_3"
    mark_thesis(ax, printed_value(eid), 0.0, "thesis: loss of tension", entries=[eid])
    ax.set(xlabel=L["lambda_A"], ylabel=L["sigma1_mu"],
           title=r"Fig. 3.6: $\lambda_P$ = 3, $c$ = 0")
    ax.legend()
    return fig


def _fig3_7(plt, v: xr.Dataset, f: xr.Dataset):
    """Fig. 3.7: every curve to its first failure (c = 0 and -0.053), the breakdown line,
    and the printed percentage changes applied to our c = 0 values."""
    fig, ax = plt.subplots(figsize=(6.5, 4.8))
    sym = {1: "d", 2: "o", 3: "s", 4: "x", 5: "x"}
    for lp in v.lamP.values:
        for c, ls in ((0.0, "-"), (-0.053, ":")):
            stop, phi_stop, code = _failure(f, lp, c)
            lam, phi = _curve_upto(v, lp, c, stop, phi_stop)
            ax.plot(lam, phi, "k" + ls, lw=0.9)
            if code in sym:
                ax.plot(stop, phi_stop, "k" + sym[code], ms=5, mfc="none" if c else "k")
    lam = np.linspace(1, 7.8, 200)
    ax.plot(lam, circle_a.breakdown_phibar(lam, params.EPS_R_ASSUMED, params.MU_VHB), "r--",
            lw=1, label=r"breakdown ($\varepsilon_r$ = 4.7)")
    first = True
    for lp, stretch, eid, off in (
            (3.0, 4.5, "ch3.voltage_increase.lamP_3_stretch_4p5", (95, 118)),
            (4.0, 5.0, "ch3.voltage_increase.lamP_4_stretch_5", (100, -50))):
        lam0, phi0 = _curve_upto(v, lp, 0.0, np.inf)
        mark_thesis(ax, stretch, _implied(eid, float(np.interp(stretch, lam0, phi0)), 1),
                    _PCT_LABEL if first else None, entries=[eid],
                    note=percent_note(eid) + rf" $\bar\Phi$ ($\lambda_P$ = {lp:g})",
                    note_offset=off, arrow=True)
        first = False
    eid = "ch3.max_stretch_gain.lamP_2"     # loss of tension of c = -0.053 at this stretch
    mark_thesis(ax, _implied(eid, _failure(f, 2.0, 0.0)[0], 1), _failure(f, 2.0, -0.053)[1],
                None, entries=[eid],
                note=percent_note(eid) + r" $\lambda_{\max}$ ($\lambda_P$ = 2)",
                note_offset=(120, 120), arrow=True)
    eid = "ch3.max_stretch_reduction.lamP_4"  # breakdown of c = -0.053 at this stretch
    x = _implied(eid, _failure(f, 4.0, 0.0)[0], -1)
    mark_thesis(ax, x, float(circle_a.breakdown_phibar(x, params.EPS_R_ASSUMED, params.MU_VHB)),
                None, entries=[eid],
                note=percent_note(eid, "\u2212") + r" $\lambda_{\max}$ ($\lambda_P$ = 4)",
                note_offset=(55, 63), arrow=True)
    ax.set(xlabel=L["lambda_A"], ylabel=L["phibar"], ylim=(0, 0.8),
           title="Fig. 3.7: $c$ = 0 (solid), $c$ = -0.053 (dotted), ends at the first failure:\n"
                 "diamond pull-in, circle loss of tension, square breakdown")
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2)
    return fig


def _fig3_8(plt, v: xr.Dataset, f: xr.Dataset):
    """Fig. 3.8: voltage-stretch curves for every c at lamP = 2 and 3."""
    fig, axs = plt.subplots(1, 2, figsize=(10, 4.3))
    for ax, lp in zip(axs, (2.0, 3.0), strict=True):
        for c in v.c.values:
            _draw(ax, v, f, lp, c, f"$c$ = {c:g}")
        ax.set(xlabel=L["lambda_A"], ylabel=L["phibar"],
               title=rf"Fig. 3.8: $\lambda_P$ = {lp:g}")
        ax.legend(fontsize=8)
    fig.suptitle(_ENDS_NOTE.replace(";\n", "; "), fontsize=10)
    return fig


def _fig3_9(plt, s: xr.Dataset):
    """Fig. 3.9: maximum stretch and its voltage over c, coloured by the failure mode."""
    names = {1: "pull-in", 2: "loss of tension", 3: "breakdown"}
    fig, axs = plt.subplots(2, 3, figsize=(11, 6.5), sharex=True, layout="constrained")
    for k, lp in enumerate(s.lamP.values):
        sel = s.sel(lamP=lp)
        for code, col in ((1, "b"), (2, "g"), (3, "r")):
            m = sel.failure_mode.values == code
            axs[0, k].plot(s.c.values[m], sel.lambda_max.values[m], col + ".", ms=4,
                           label=f"fails by {names[code]}")
            axs[1, k].plot(s.c.values[m], sel.phibar_at_lambda_max.values[m], col + ".", ms=4)
        axs[0, k].set_title(rf"({'abc'[k]}) $\lambda_P$ = {lp:g}")
        axs[1, k].set_xlabel(L["c"])
    axs[0, 0].set_ylabel(L["lambda_max"])
    axs[1, 0].set_ylabel(L["phibar_at_max"])
    eid = "ch3.pullin.voltage_lamP_1p25"    # Phibar at lam_max = pull-in voltage for c = 0
    mark_thesis(axs[1, 0], 0.0, printed_value(eid), "thesis (printed value)", entries=[eid],
                note=rf"{printed_value(eid):g} (pull-in, $c$ = 0)", note_offset=(-40, 125),
                arrow=True)
    eids = ["ch3.pullin.c_threshold_lamP_1p25"]
    mark_thesis_x(axs[0, 0], printed_value(eids[0]), None, entries=eids, note_y=0.3,
                  note=f"no pull-in below\n$c$ = {printed_value(eids[0]):g}")
    eid = "ch3.max_stretch_gain.lamP_2"
    lam0 = float(s.lambda_max.sel(lamP=2.0, c=0.0))
    mark_thesis(axs[0, 1], -0.053, _implied(eid, lam0, 1), None, entries=[eid],
                note=percent_note(eid) + r" at $c$ = -0.053", note_offset=(6, -3))
    handles = {}
    for ax in axs.flat:
        for h, lab in zip(*ax.get_legend_handles_labels(), strict=True):
            handles.setdefault(lab, h)
    fig.legend(handles.values(), handles.keys(), loc="outside lower center", ncol=4)
    fig.suptitle(r"Fig. 3.9: maximum stretch $\lambda_{\max}$ and its voltage over $c$")
    return fig


def build(out_dir: Path, *, full: bool = False) -> list[Path]:
    """Write the Chapter 3 datasets and figures into ``out_dir`` (and ``out_dir/figures``)."""
    out_dir = Path(out_dir)
    ds = compute(full)
    paths = []
    for name, d in ds.items():
        title, summary = _TEXT[name]
        prm = {**_common_params(full), "full": full, **{k: v for k, v in d.attrs.items()}}
        d = d.copy()
        d.attrs = {}
        paths.append(write_dataset(d, name, title=title, summary=summary, parameters=prm,
                                   out_dir=out_dir, overwrite=True))
    if written():
        paths += figures(ds, out_dir / "figures")
    return paths
