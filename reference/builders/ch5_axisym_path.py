"""Chapter 5: pull-in and wrinkling of the clamped film by the axisymmetric FE model.

The imperfect film (the clamped-plate imperfection of 1e-3 t0 of the 3D model, as the
exact lift map of :class:`~debench.models.buckling.axisym.AxisymModel`) is followed along
its axisymmetric equilibrium path, by voltage control and then by centre-deflection
control through the voltage maximum; at every recorded state the lowest eigenvalue at
fixed voltage of each angular wavenumber n is computed (wavenumber n = 0: the axisymmetric
one, whose zero is the voltage maximum, i.e. pull-in; n >= 1: wrinkling modes). Per film
(:data:`~debench.reference.studies.ch5_axisym.PATH_FILMS`: neo-Hookean and Ogden at
R/t0 = 10, t0 = 1 mm; Ogden at R/t0 = 20, t0 = 0.5 mm with R = 10 mm kept) and per
discretisation (order p, geometric layers L towards the rim and its corners):

* the path (deflection w / t0, voltage v, centre thickness / t0, centre field, the
  eigenvalues of the recorded wavenumbers);
* the voltage maximum (pull-in: v_max, w_max, thickness there) and each wavenumber's
  lowest eigenvalue there;
* the first zero of each wavenumber's eigenvalue along the path (w_cross, v_cross; NaN
  where it stays positive).

Converged values and their error estimates: the value on the top discretisation of the
plan (highest order at the finest grading); the error estimate is Roache's safety factor
(1.25 with >= 3 orders at the finest grading, else 3) times the larger of the change from
the order below (at the finest grading) and the change from the coarser grading (at the
top order) (:func:`~debench.models.numerics.p_grading_estimate`). The decision per film
(:func:`decide`): the first instability is wrinkling when the smallest converged w_cross
lies below the converged w_max by more than the sum of their error estimates; pull-in when
no wavenumber's eigenvalue crosses zero before the maximum on any discretisation and the
smallest converged eigenvalue at the maximum exceeds its error estimate; otherwise
undecided.

Plans (:data:`~debench.reference.studies.ch5_axisym.PATH`): ``full`` the neo-Hookean and
Ogden films at R/t0 = 10 and the Ogden film at R/t0 = 20 on (p, L) = (2, 6), (3, 6), (4, 6),
(4, 4) (the Ogden paths cost more than ten times the neo-Hookean ones, through the Ogden
Hessian's assembly at every eigen-analysis: measured CPU per path in the dataset's
``cpu_seconds``, about 1,100 s at (4, 4)). The default build the neo-Hookean film at R/t0 =
10 on (2, 3), (3, 3), (3, 2) with wavenumbers 1..4 (a coarse check of the same code path;
measured CPU in the dataset's ``cpu_seconds``).

The 3D-like resolution study (:func:`three_d_like`, variables ``*_3d_like``): the voltage
maximum of the R/t0 = 10 films on the 3D ramps' discretisation (quadratic elements, one
through the thickness, uniform radial elements of the 3D ramps' sizes, no grading), which
says what those choices cost the 3D pull-in.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr
from debench.models.buckling.analytic import critical_voltage_plate
from debench.models.buckling.parameters import Plate
from debench.models.numerics import p_grading_estimate, p_grading_safety, propagated_accuracy
from debench.reference.datasets import variable_attrs, write_dataset
from debench.reference.studies import ch5_axisym as study
from debench.reference.studies.ch5 import material
from debench.reference.studies.ch5_axisym import V_SWITCH, W_END, path_task
from debench.reference.tasks import resolve_scheduler, run_tasks

#: CPU seconds of the default build (one thread, measured in one `debench reproduce` with
#: two pool processes on the quiet 2-core machine): the pool starts the longest first.
BUILD_CPU_S = 82.0
#: ``debench verify`` does not rebuild this chapter (minutes of CPU, or the catalogue itself):
#: its model guards and the value check stand for it.
REGENERATED_BY_VERIFY = False
#: The model guards ``debench verify`` runs for this chapter instead of rebuilding it
#: (``module:function`` returning guarded values -> measured CPU seconds, one thread).
GUARDS = {"debench.reference.producers.ch5_path:axisym_path_guards": 5.4}

NAME = "ch5_axisym_path"
COARSE_3D_H = {False: (2.5, 2.0), True: (10.0 / 3.0, 2.5, 2.0, 1.0, 0.5)}
"""Radial element sizes / t0 of the 3D-like resolution study (:func:`three_d_like`): the 3D
ramps' in-plane mesh sizes 3, 2.5, 2 t0 (10/3 here, so that the elements tile the radius)
and two finer ones."""
REGEN_ATOL = {"v": 1e-8, "w": 1e-6, "lam": 1e-8, "thickness": 1e-7}
"""Regenerations agree to about 1e-9 in the voltage and 1e-8 in the deflection of a
crossing (the secant on the eigenvalue stops at a deflection step of 1e-9 t0, or where it
stagnates at the eigenvalue's round-off floor, within 1e-6 t0:
:data:`~debench.models.buckling.axisym.path.ZERO_STALL_W`; the Newton
states carry round-off of 1e-10 of the load next to the singular tangent, which moves the
eigenvalues near zero by ~1e-10 and the crossing deflection by that over the eigenvalue's
slope, ~1e-3 per t0: 1e-7); 10x that, in the quantity's units."""
TIMING_RTOL = 1.0
"""CPU seconds depend on the machine and its load: within a factor two of the curated."""


def plan(full: bool = False, cases=None) -> list[tuple]:
    """The FE tasks ``(path_task, case, order, layers, n_max)`` of a build (``cases``: the
    plan's films, or the given ones on the plan's discretisations)."""
    p = study.PATH[full]
    return [(path_task, c, order, layers, p["n_max"]) for c in (cases or p["cases"])
            for order, layers in p["discs"]]


def three_d_like(case: str, h: float) -> tuple[float, float]:
    """Voltage maximum (v, w / t0) of the axisymmetric path of ``case`` at the resolution of
    the 3D ramps: quadratic elements, one through the thickness, radial elements of size
    ``h`` t0 up to the rim (no grading). The 3D model's own discretisation choices, in the
    independent model, isolate what they cost."""
    from debench.models.buckling import axisym as ax

    mat_name, t0, aspect, *_ = study.PATH_FILMS[case]
    mat = material(mat_name)
    n_r = round((aspect - h) / h)
    disc = ax.AxisymDiscretisation(order=2, n_z=1, face_layers=0, edge_layers=0, n_r=n_r,
                                   edge_zone=h)
    model = ax.AxisymModel(Plate(thickness=t0, aspect=aspect), mat, disc)
    v_switch = V_SWITCH * critical_voltage_plate(mat, aspect)
    points = ax.follow_path(model, W_END, v_switch=v_switch, dv=v_switch / 8,
                            record_every=0.5, wavenumbers=(0,))
    peak = ax.zero_crossing(model, points, 0)
    return float(peak.v), float(peak.w)


def decide(w_max, w_max_err, w_cross, w_cross_err, lam_max, lam_max_err,
           any_cross_before) -> dict:
    """The first instability of one film (see the module docstring), from the converged
    values and error estimates per wavenumber and ``any_cross_before`` (whether any
    wavenumber crosses zero before the voltage maximum on any discretisation): ``first`` = 1
    (wrinkling first), 0 (pull-in first), -1 (undecided); ``n_first`` the wavenumber of the
    first crossing (0 for pull-in, -1 undecided); ``margin`` (w_max - w_cross of the first
    crossing, or the smallest eigenvalue at the maximum) and ``margin_error`` (its bound)."""
    w_cross = np.asarray(w_cross, float)
    if np.any(np.isfinite(w_cross) & (w_cross < w_max)):
        j = int(np.nanargmin(w_cross))
        margin, bound = w_max - w_cross[j], w_max_err + w_cross_err[j]
        first = 1 if np.isfinite(bound) and margin > bound else -1
        return {"first": first, "n_index": j, "margin": margin, "margin_error": bound}
    j = int(np.nanargmin(lam_max))   # NaN: a wavenumber this film does not record
    margin, bound = float(lam_max[j]), float(lam_max_err[j])
    first = 0 if (not any_cross_before and margin > bound) else -1
    return {"first": first, "n_index": j, "margin": margin, "margin_error": bound}


def _collect(res: dict, cases, discs, ns) -> dict:
    """The tasks' results ``res[(case, order, layers)]`` as arrays over (case, disc, ...):
    the path records (``path``, ``path_lam``), the per-path scalars (``scal``, ``ndof``)
    and the per-wavenumber values (``per_n``), NaN where a path has fewer records or a
    wavenumber was not recorded."""
    nrec = max(len(r["w"]) for r in res.values())
    C, K, N = len(cases), len(discs), len(ns)

    def full_of(shape):
        return np.full(shape, np.nan)

    path = {k: full_of((C, K, nrec)) for k in ("w", "v", "thickness", "e", "lam0")}
    path_lam = full_of((C, K, nrec, N))
    scal = {k: full_of((C, K)) for k in ("w_max", "v_max", "thickness_max", "wtol_max",
                                         "cpu_s", "cpu_path_s", "newton_residual_rel")}
    ndof = np.zeros((C, K), dtype=np.int64)
    per_n = {k: full_of((C, K, N)) for k in ("lam_at_max", "w_cross", "v_cross",
                                             "thickness_cross")}
    for ci, c in enumerate(cases):
        for k, (order, layers) in enumerate(discs):
            r = res[(c, order, layers)]
            m = len(r["w"])
            for key in path:
                path[key][ci, k, :m] = r[key]
            cols = [ns.index(n) for n in r["wavenumbers"]]
            path_lam[ci, k, :m][:, cols] = np.asarray(r["lam"], float)
            for key in scal:
                scal[key][ci, k] = r[key]
            ndof[ci, k] = r["ndof"]
            for key in per_n:
                per_n[key][ci, k, cols] = r[key]
    return {"path": path, "path_lam": path_lam, "scal": scal, "ndof": ndof, "per_n": per_n,
            "nrec": nrec}


def _converge(scal: dict, per_n: dict, discs) -> tuple[dict, dict]:
    """Per converged quantity its estimate from the p- and grading-sequence
    (:func:`~debench.models.numerics.p_grading_estimate`, ``conv``) and the regeneration
    accuracy it carries (``acc``: what REGEN_ATOL of the inputs moves the error estimate by,
    plus REGEN_ATOL)."""
    K = len(discs)
    conv, acc = {}, {}
    for key, src in (("v_max", scal["v_max"]), ("w_max", scal["w_max"]),
                     ("thickness_max", scal["thickness_max"]),
                     ("lam_at_max", per_n["lam_at_max"]), ("w_cross", per_n["w_cross"]),
                     ("v_cross", per_n["v_cross"])):
        conv[key] = p_grading_estimate(np.moveaxis(src, 1, -1), discs)
        kind = key.split("_")[0] if key.split("_")[0] in REGEN_ATOL else "v"
        atol = REGEN_ATOL["lam" if key == "lam_at_max" else kind]
        flat = np.moveaxis(src, 1, -1).reshape(-1, K)
        acc[key] = float(np.nanmax([np.nan_to_num(propagated_accuracy(
            lambda x: p_grading_estimate(x, discs).error, row, atol), nan=0.0)
            for row in flat] + [0.0])) + atol
    return conv, acc


def _variables(got: dict, conv: dict, acc: dict, dec: list, discs, coarse) -> dict:
    """The data variables of ``ch5_axisym_path.nc`` with their attributes: the path
    records, the per-path and per-wavenumber values, their converged values and error
    estimates, the decision per film and the 3D-like coarse voltage maxima."""
    at, a = REGEN_ATOL, variable_attrs
    variables = _sequence_variables(got, discs)
    variables.update(_converged_variables(variables, conv, acc))
    variables.update(_decision_variables(dec, got["ns"], acc))
    variables["v_max_3d_like"] = (("case_r10", "h_3d_like"), coarse[..., 0], a(
        "voltage maximum at the 3D ramps' resolution (three_d_like)", atol=at["v"]))
    variables["w_max_3d_like"] = (("case_r10", "h_3d_like"), coarse[..., 1], a(
        "deflection / t0 at it", atol=at["w"]))
    return variables


def _sequence_variables(got: dict, discs) -> dict:
    """The path records and the per-path and per-wavenumber values of every task
    (:func:`_collect`) with their attributes."""
    path, path_lam, scal, ndof, per_n = (got[k] for k in ("path", "path_lam", "scal",
                                                          "ndof", "per_n"))
    a = variable_attrs
    d3, d4 = ("case", "disc", "record"), ("case", "disc", "record", "n")
    dk, dkn = ("case", "disc"), ("case", "disc", "n")
    at = REGEN_ATOL
    return {
        "path_w": (d3, path["w"], a("centre deflection of the top surface / t0", atol=at["w"])),
        "path_v": (d3, path["v"], a("normalised voltage Phi/t0 sqrt(eps/mu_ref)",
                                    atol=at["v"])),
        "path_thickness": (d3, path["thickness"], a("centre thickness / t0",
                                                    atol=at["thickness"])),
        "path_e": (d3, path["e"], a("normalised true electric field at the centre",
                                    atol=at["thickness"])),
        "path_lam0": (d3, path["lam0"], a(
            "lowest eigenvalue at fixed voltage of wavenumber 0 (mass: int (U^2 + V^2 + W^2) "
            "R dR dZ)", atol=at["lam"])),
        "path_lam": (d4, path_lam, a(
            "lowest eigenvalue at fixed voltage of wavenumber n (NaN: not recorded there)",
            atol=at["lam"])),
        "v_max": (dk, scal["v_max"], a("voltage maximum of the path (pull-in)", atol=at["v"])),
        "w_max": (dk, scal["w_max"], a("deflection / t0 at the voltage maximum",
                                       atol=at["w"])),
        "thickness_max": (dk, scal["thickness_max"], a(
            "centre thickness / t0 at the voltage maximum", atol=at["thickness"])),
        "lam_at_max": (dkn, per_n["lam_at_max"], a(
            "lowest eigenvalue of wavenumber n at the voltage maximum", atol=at["lam"])),
        "w_cross": (dkn, per_n["w_cross"], a(
            "deflection / t0 of the first zero of wavenumber n's eigenvalue along the path "
            "(NaN: none)", atol=at["w"])),
        "v_cross": (dkn, per_n["v_cross"], a("voltage there", atol=at["v"])),
        "thickness_cross": (dkn, per_n["thickness_cross"], a("centre thickness / t0 there",
                                                             atol=at["thickness"])),
        "ndof": (dk, ndof, a("degrees of freedom of the state (r, z, potential)")),
        "cpu_seconds": (dk, scal["cpu_s"], a(
            "process CPU time of the path, its voltage maximum and crossings (one thread)",
            "s", rtol=TIMING_RTOL)),
        "newton_residual_rel": (dk, scal["newton_residual_rel"], a(
            "largest Newton residual of the recorded states relative to its reference",
            atol=1e-8)),
        "safety_factor": ((), p_grading_safety(discs), a(
            "Roache's GCI safety factor of the plan (1.25 with >= 3 orders, else 3)")),
    }


def _converged_variables(sequence: dict, conv: dict, acc: dict) -> dict:
    """Per converged quantity (:func:`_converge`) its value on the top discretisation, its
    error estimate and the two changes it rests on; each long name from the quantity's
    variable in ``sequence``."""
    a = variable_attrs
    dn = ("case", "n")
    out = {}
    for key, dims in (("v_max", ("case",)), ("w_max", ("case",)),
                      ("thickness_max", ("case",)), ("lam_at_max", dn), ("w_cross", dn),
                      ("v_cross", dn)):
        unit_of = sequence[key][2]["long_name"]
        out[f"{key}_converged"] = (dims, conv[key].value, a(
            f"converged: {unit_of}, on the top discretisation", atol=acc[key],
            accuracy=f"+- {key}_error"))
        out[f"{key}_error"] = (dims, conv[key].error, a(
            f"error estimate of {key}_converged: safety_factor x max(p_change, "
            "grading_change)", atol=acc[key]))
        out[f"{key}_p_change"] = (dims, conv[key].p_change, a(
            f"change of {key} from the order below (finest grading)", atol=acc[key]))
        out[f"{key}_grading_change"] = (dims, conv[key].grading_change, a(
            f"change of {key} from the coarser grading (top order)", atol=acc[key]))
    return out


def _decision_variables(dec: list, ns, acc: dict) -> dict:
    """The first instability of each film (:func:`decide`) as data variables: which, its
    wavenumber, the wavenumber the decision rests on, and its margin against its bound."""
    a = variable_attrs
    first = np.array([d["first"] for d in dec], dtype=np.int8)
    n_first = np.array([ns[d["n_index"]] if d["first"] == 1 else (0 if d["first"] == 0 else -1)
                        for d in dec], dtype=np.int64)
    n_lowest = np.array([ns[d["n_index"]] for d in dec], dtype=np.int64)
    margin_atol = acc["w_max"] + acc["w_cross"] + acc["lam_at_max"]
    return {
        "first_instability": (("case",), first, a(
            "first instability along the path: 1 wrinkling (a wavenumber n >= 1 crosses "
            "zero before the voltage maximum by more than the error estimates), 0 pull-in "
            "(none crosses and every n's eigenvalue at the maximum exceeds its error "
            "estimate), -1 undecided",
            flag_values=np.array([-1, 0, 1], dtype=np.int8),
            flag_meanings="undecided pull_in wrinkling")),
        "n_first": (("case",), n_first, a(
            "wavenumber of the first instability (0: pull-in, -1: undecided)")),
        "n_lowest": (("case",), n_lowest, a(
            "the wavenumber the decision rests on: the first crossing's, or the one with "
            "the smallest eigenvalue at the maximum when none crosses")),
        "margin": (("case",), np.array([d["margin"] for d in dec]), a(
            "w_max - w_cross of the first crossing (wrinkling, / t0), or the smallest "
            "eigenvalue at the maximum (pull-in)", atol=margin_atol)),
        "margin_error": (("case",), np.array([d["margin_error"] for d in dec]), a(
            "the bound the margin is held against: the sum of the two error estimates, or "
            "the eigenvalue's error estimate", atol=margin_atol)),
    }


def compute(full: bool = False, scheduler=None, progress: bool = True):
    p = study.PATH[full]
    cases, discs = p["cases"], p["discs"]
    tasks = plan(full)
    res = dict(zip([(t[1], t[2], t[3]) for t in tasks],
                   run_tasks(tasks, scheduler=scheduler, progress=progress), strict=True))
    ns = sorted({n for c in cases for n in study.PATH_FILMS[c][3]
                 if p["n_max"] is None or n <= p["n_max"]})
    got = _collect(res, cases, discs, ns) | {"ns": ns}
    scal, per_n = got["scal"], got["per_n"]
    conv, acc = _converge(scal, per_n, discs)
    dec = [decide(conv["w_max"].value[ci], conv["w_max"].error[ci],
                  conv["w_cross"].value[ci], conv["w_cross"].error[ci],
                  conv["lam_at_max"].value[ci], conv["lam_at_max"].error[ci],
                  bool(np.any(per_n["w_cross"][ci] < scal["w_max"][ci][:, None])))
           for ci in range(len(cases))]
    h3 = COARSE_3D_H[full]
    like = [c for c in cases if study.PATH_FILMS[c][2] == 10.0]
    coarse = np.array([[three_d_like(c, h) for h in h3] for c in like]).reshape(
        len(like), len(h3), 2)

    variables = _variables(got, conv, acc, dec, discs, coarse)
    a = variable_attrs
    ds = xr.Dataset(variables, coords={
        "case_r10": ("case_r10", like, {"long_name": "the R/t0 = 10 films"}),
        "h_3d_like": ("h_3d_like", np.array(h3), a(
            "radial element size / t0 (quadratic, one element through the thickness)")),
        "case": ("case", list(cases), {"long_name": "film: material and radius/thickness "
                                       "(nh: neo-Hookean, ogden: Ogden (5.26); r10: R/t0 = "
                                       "10 at t0 = 1 mm; r20: R/t0 = 20 at t0 = 0.5 mm)"}),
        "disc": ("disc", np.arange(len(discs)), a("discretisation index")),
        "order": ("disc", np.array([o for o, _ in discs]), a("polynomial order of every "
                                                             "field")),
        "layers": ("disc", np.array([L for _, L in discs]), a(
            "geometric layers towards the rim and towards each face")),
        "record": ("record", np.arange(got["nrec"]), a("recorded state along the path")),
        "n": ("n", np.array(ns), a("angular wavenumber of the perturbation")),
    })
    params = {"full": full, "cases": list(cases), "discs": [list(d) for d in discs],
              "wavenumbers": list(ns), "n_max": p["n_max"],
              "record_from_w": {c: study.PATH_FILMS[c][4] for c in cases},
              "record_spacing_w": {c: study.PATH_FILMS[c][5] for c in cases},
              "aspect": {c: study.PATH_FILMS[c][2] for c in cases},
              "thickness_m": {c: study.PATH_FILMS[c][1] for c in cases},
              "n_r_per_aspect": study.PATH_N_R_PER_ASPECT, "h_3d_like": list(h3),
              "v_switch": V_SWITCH, "w_end": W_END,
              "imperfection": "clamped-plate polynomial, amplitude 1e-3 t0 (the 3D model's)",
              "materials": "Table 5.1 neo-Hookean (5.15)-(5.17); Ogden (5.26), k of Table 5.1"}
    return ds, params


def build(out_dir: Path, *, full: bool = False, scheduler: str | None = None) -> list[Path]:
    """Write ``ch5_axisym_path.nc`` (see the module docstring). ``scheduler`` as for
    :func:`debench.reference.builders.ch5.build`."""
    ds, params = compute(full, scheduler=resolve_scheduler(scheduler))
    return [write_dataset(
        ds, NAME, out_dir=out_dir, overwrite=True,
        title="Chapter 5: pull-in and wrinkling of the clamped film, axisymmetric FE model",
        summary=("Axisymmetric equilibrium path of the imperfect clamped film (Table 5.1 "
                 "neo-Hookean and Ogden at R/t0 = 10, Ogden at R/t0 = 20) through its "
                 "voltage maximum, with the lowest eigenvalue at fixed voltage of each "
                 "angular wavenumber along it, on p- and grading-sequences: pull-in voltage "
                 "and deflection, the first zero of every wavenumber, converged values with "
                 "error estimates, and which instability comes first."),
        parameters=params)]
