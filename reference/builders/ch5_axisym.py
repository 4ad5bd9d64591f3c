"""Chapter 5: the critical voltage of the clamped film by the axisymmetric FE model.

The second, independent finite-element model of the clamped buckling film
(:mod:`debench.models.buckling.axisym`: a body of revolution, the stability of the flat
state per angular wavenumber n), converged by polynomial order p and by the geometric
grading towards the rim and its clamped corners (``edge_layers = face_layers = L``).

``build(out_dir, full=False)`` writes ``ch5_axisym.nc``:

* ``v_cr(case, n, order, layers)``: the critical normalised voltage of the perfect film
  (lowest eigenvalue of the condensed tangent at fixed voltage of wavenumber n through
  zero) for the neo-Hookean and Ogden films of Table 5.1 (t0 = 1 mm, R/t0 = 10) and
  n = 0, 1, with the CPU seconds and degrees of freedom of each solve;
* per (case, n) the converged value ``v_cr_converged`` = ``v_cr`` at the finest (order,
  layers) of the plan, and its error estimate ``v_cr_error`` = a safety factor times the
  larger of the last p-step change (at the finest grading) and the change between the two
  finest gradings (at the top order); the factor is Roache's: 1.25 with three or more
  orders, else 3 (:func:`converged`);
* ``v_cr_guard(case)``: n = 0 on the cheap guard discretisation
  (:data:`~debench.reference.studies.ch5_axisym.CRITICAL_GUARD`), which
  ``debench verify`` recomputes;
* the comparison with the 3D model (``ch5_critical_voltage.nc``): its reference and its
  in-plane mesh limit with their error bars, the differences 3D - axisymmetric and
  whether each 3D error bar contains the axisymmetric value (n = 0, the lowest mode).

Plans (:data:`~debench.reference.studies.ch5_axisym.CRITICAL`): default orders 3, 4 and
layers 3, 4 (measured: 78 s of CPU in the solves at load 6 on the 2-core machine; error
estimates 1.2e-5 .. 2.0e-5 with the safety factor 3 of two orders, and the converged
values within 0.09 of the sum of both plans' estimates from the curated ones); ``full``
orders 4 .. 6 and layers 6, 8 (the curated plan; its error estimates are the p-step and
grading changes, far above the reproducibility floor :data:`REGEN_ATOL`; its CPU in
``cpu_seconds``; the coarser orders and gradings add nothing to the estimate at the top).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr
from debench.models.buckling.parameters import Plate
from debench.models.numerics import (
    PGradingEstimate,
    gci_safety,
    p_grading_estimate,
    propagated_accuracy,
)
from debench.reference.datasets import read_dataset, variable_attrs, write_dataset
from debench.reference.studies import ch5_axisym as study
from debench.reference.studies.ch5 import case_material

#: CPU seconds of the default build (one thread, measured in one `debench reproduce` with
#: two pool processes on the quiet 2-core machine): the pool starts the longest first.
BUILD_CPU_S = 97.0
#: ``debench verify`` does not rebuild this chapter (minutes of CPU, or the catalogue itself):
#: its model guards and the value check stand for it.
REGENERATED_BY_VERIFY = False
#: The model guards ``debench verify`` runs for this chapter instead of rebuilding it
#: (``module:function`` returning guarded values -> measured CPU seconds, one thread).
GUARDS = {"debench.reference.producers.ch5:axisym_coarse_guards": 4.7}

NAME = "ch5_axisym"
CASES = study.CRITICAL[False]["cases"]
"""The films (the same in both plans: :data:`~debench.reference.studies.ch5_axisym.CRITICAL`)."""
WAVENUMBERS = study.CRITICAL[False]["wavenumbers"]
N1_START = 1.3
"""The n = 1 secant starts at this multiple of the same discretisation's n = 0 critical
voltage (the measured ratio is 1.326; the secant needs a start within its basin)."""
SEED_STEP = 1e-3
"""Each level of the plan after a film's first starts its secants at its predecessor's
critical voltages (same film and wavenumber) and ``1 - SEED_STEP`` times them: consecutive
levels differ by < 1e-4 relative, so three flat-state solves reach the root instead of four
or five (measured, both films, orders 3-4, layers 4-6)."""
REPEAT_ATOL = 1e-10
"""Repeats of one critical-voltage solve from the same start agree to round-off: the root
is the secant's inverse-quadratic root (its own error vtol <= 1e-11, ``v_cr_tolerance``) of
an eigenvalue refined by its quadrature Rayleigh quotient (reproducible to ~1e-16 of the
bending scale, ~3e-15 in v) at flat states solved to 1e-11 of the load (< 1e-11 in v);
10x the secant's bound. The guard solve and every task of independent solves (default
starts) are judged with it."""
REGEN_ATOL = 1e-9
"""What a critical voltage of the plan is reproducible to: its secant starts from the
previous level (:data:`SEED_STEP`) instead of the default start; the root does not depend
on the start beyond the secant's own tolerance (measured between the seeded and the
default starts: see ``verification/test_ch5_axisym.py``, <= 1e-15 at order 2 with 6
layers, and on the plan's finest levels in the dataset's test); 10x :data:`REPEAT_ATOL`.
It is also the floor of every error estimate (:func:`converged`): a p-step or grading
change below it is not resolved."""
TIMING_RTOL = 1.0
"""CPU seconds depend on the machine and its load: a regeneration is only asked to lie
within a factor two of the curated timing."""


def safety_factor(n_orders: int) -> float:
    """Roache's GCI safety factor for a p-sequence of ``n_orders`` orders
    (:func:`~debench.models.numerics.gci_safety`: 1.25 with >= 3 orders, else 3)."""
    return gci_safety(n_orders)


def converged(v, floor: float = 0.0) -> PGradingEstimate:
    """Converged value and error estimate from ``v[order, layers]`` (orders and layers
    ascending, every pair computed): the value at the top order and finest grading; the
    error estimate is :func:`safety_factor` times the larger of the last p-step change at
    the finest grading and the change between the two finest gradings at the top order,
    and at least ``floor`` (what each value is reproducible to, :data:`REGEN_ATOL` in the
    dataset): :func:`~debench.models.numerics.p_grading_estimate` on the grid."""
    v = np.asarray(v, float)
    if v.ndim != 2 or v.shape[0] < 2 or v.shape[1] < 2:
        raise ValueError(f"converged: need >= 2 orders and >= 2 gradings, got shape {v.shape}")
    grid = [(p, L) for p in range(v.shape[0]) for L in range(v.shape[1])]
    return p_grading_estimate(v.reshape(-1), grid, floor=floor)


def solve_plan(full: bool = False, progress=None) -> dict:
    """Every critical voltage of the plan: ``{(case, n, order, layers): AxisymCritical}``."""
    from debench.models.buckling.axisym import AxisymDiscretisation, critical_voltage

    plate = Plate(thickness=study.THICKNESS, aspect=study.ASPECT)
    plan = study.CRITICAL[full]
    out, seed = {}, {}
    jobs = [(c, p, L) for c in CASES for p in plan["orders"] for L in plan["layers"]]
    for case, p, L in (progress(jobs) if progress else jobs):
        disc = AxisymDiscretisation(order=p, edge_layers=L, face_layers=L,
                                    n_r=study.CRITICAL_N_R)
        mat = case_material(case)
        # a film's first level starts from the plate estimate (n = 0) and N1_START times
        # its n = 0 value (n = 1), every later one from the level before
        v0, v1 = seed.get(case, (None, None))
        step = {"start_step": SEED_STEP} if case in seed else {}
        r0 = critical_voltage(plate, mat, disc, n=0, v_start=v0, **step)
        r1 = critical_voltage(plate, mat, disc, n=1,
                              v_start=N1_START * r0.v if v1 is None else v1, **step)
        out[(case, 0, p, L)], out[(case, 1, p, L)] = r0, r1
        seed[case] = (r0.v, r1.v)
    for case in CASES:
        order, layers = study.CRITICAL_GUARD
        disc = AxisymDiscretisation(order=order, edge_layers=layers, face_layers=layers,
                                    n_r=study.CRITICAL_N_R)
        out[(case, "guard")] = critical_voltage(plate, case_material(case), disc, n=0)
    return out


def _vs_3d(v_ax: np.ndarray) -> dict:
    """The 3D model's reference critical voltage and in-plane mesh limit
    (``ch5_critical_voltage.nc``) against the converged n = 0 values ``v_ax`` per case
    (its lowest mode is axisymmetric): values, errors, biases and whether each 3D
    error bar contains the axisymmetric value."""
    ds3 = read_dataset("ch5_critical_voltage").sel(case=list(CASES))
    v3_ref, e3_ref = ds3.v_cr_reference.values, ds3.v_cr_reference_error.values
    v3_ext, e3_ext = ds3.v_cr_extrapolated.values, ds3.v_cr_error.values
    bias_ref, bias_ext = v3_ref - v_ax, v3_ext - v_ax
    within_ref = (np.abs(bias_ref) <= e3_ref).astype(np.int8)
    within_ext = (np.abs(bias_ext) <= e3_ext).astype(np.int8)
    return {"v3_ref": v3_ref, "e3_ref": e3_ref, "v3_ext": v3_ext, "e3_ext": e3_ext,
            "bias_ref": bias_ref, "bias_ext": bias_ext, "within_ref": within_ref,
            "within_ext": within_ext}


def critical_solve_variables(dims: tuple[str, ...], fields: dict, ndof: np.ndarray,
                             v_cr_of: str, atol: float) -> dict:
    """The variables of one critical-voltage solve per entry of ``dims`` (v_cr, its
    root-finding tolerance, the flat state's centre thickness and field, the residuals, the
    CPU time, the DOFs), from ``fields`` (keys v, vtol, thickness, e, eig_residual,
    newton_residual_rel, cpu_s; :func:`~debench.models.buckling.axisym.critical_voltage`'s
    result fields) and ``ndof``; ``v_cr_of`` ends v_cr's long name (which film, which
    wavenumber, which operator); ``atol``: what regenerations of a solve agree to."""
    a = variable_attrs
    return {
        "v_cr": (dims, fields["v"], a(
            "normalised critical voltage Phi/t0 sqrt(eps/mu_ref) of the perfect clamped "
            f"film {v_cr_of}", atol=atol)),
        "v_cr_tolerance": (dims, fields["vtol"], a(
            "root-finding tolerance of v_cr (inverse quadratic vs secant root)",
            atol=atol)),
        "thickness_centre": (dims, fields["thickness"], a(
            "centre thickness / t0 of the flat state at v_cr", atol=atol)),
        "e_centre": (dims, fields["e"], a(
            "normalised true field at the centre of the flat state at v_cr",
            atol=atol)),
        "eig_residual": (dims, fields["eig_residual"], a(
            "backward error of the critical eigenpair", atol=1e-10)),
        "newton_residual_rel": (dims, fields["newton_residual_rel"], a(
            "last Newton residual of the flat state relative to its reference",
            atol=1e-8)),
        "cpu_seconds": (dims, fields["cpu_s"], a(
            "process CPU time of the critical-voltage solve (one thread)", "s",
            rtol=TIMING_RTOL)),
        "ndof": (dims, ndof, a("degrees of freedom of the state (r, z, potential)")),
    }


def _variables(fields, ndof, ndof_mode, res, conv, acc, fs, vs3d) -> dict:
    """The data variables of ``ch5_axisym.nc`` with their attributes."""
    v3_ref, e3_ref, v3_ext, e3_ext = (vs3d[k] for k in ("v3_ref", "e3_ref", "v3_ext",
                                                        "e3_ext"))
    bias_ref, bias_ext = vs3d["bias_ref"], vs3d["bias_ext"]
    within_ref, within_ext = vs3d["within_ref"], vs3d["within_ext"]
    a = variable_attrs
    dims4 = ("case", "n", "order", "layers")
    flag = {"flag_values": np.array([0, 1], dtype=np.int8), "flag_meanings": "outside inside"}
    return {
        **critical_solve_variables(dims4, fields, ndof, "in angular wavenumber n "
                                   "(axisymmetric FE model, this discretisation)",
                                   REGEN_ATOL),
        "ndof_mode": (dims4, ndof_mode, a("degrees of freedom of the wavenumber-n "
                                          "perturbation problem")),
        "v_cr_guard": (("case",), np.array([res[(c, "guard")].v for c in CASES]), a(
            "n = 0 critical voltage on the guard discretisation (parameters guard_order, "
            "guard_layers), recomputed by debench verify", atol=REPEAT_ATOL)),
        "ndof_guard": (("case",), np.array([res[(c, "guard")].ndof for c in CASES],
                                           dtype=np.int64),
                       a("degrees of freedom of the guard solve's state")),
        "v_cr_converged": (("case", "n"), conv["v"], a(
            "converged critical voltage: v_cr at the top order and finest grading of "
            "the plan", atol=acc["v"], accuracy="+- v_cr_error")),
        "v_cr_error": (("case", "n"), conv["error"], a(
            "error estimate of v_cr_converged: safety_factor x max(p_step_change, "
            "grading_change), at least error_floor (the reproducibility of each v_cr)",
            atol=acc["error"])),
        "p_step_change": (("case", "n"), conv["p_step_change"], a(
            "abs(v_cr(top order) - v_cr(top order - 1)) at the finest grading",
            atol=acc["p_step_change"])),
        "grading_change": (("case", "n"), conv["grading_change"], a(
            "abs(v_cr(finest grading) - v_cr(second finest)) at the top order",
            atol=acc["grading_change"])),
        "safety_factor": ((), fs, a(
            "GCI safety factor (Roache): 1.25 with >= 3 orders in the p-sequence, else 3")),
        "v_cr_3d_reference": (("case",), v3_ref, a(
            "3D model's reference critical voltage (ch5_critical_voltage.nc "
            "v_cr_reference)")),
        "v_cr_3d_reference_error": (("case",), e3_ref, a(
            "its error estimate (v_cr_reference_error)")),
        "v_cr_3d_extrapolated": (("case",), v3_ext, a(
            "3D model's in-plane mesh limit (v_cr_extrapolated)")),
        "v_cr_3d_extrapolated_error": (("case",), e3_ext, a(
            "its error estimate (v_cr_error)")),
        "bias_3d_reference": (("case",), bias_ref, a(
            "v_cr_3d_reference - v_cr_converged(n = 0)", atol=acc["v"])),
        "bias_3d_extrapolated": (("case",), bias_ext, a(
            "v_cr_3d_extrapolated - v_cr_converged(n = 0)", atol=acc["v"])),
        "reference_bar_contains_axisym": (("case",), within_ref, a(
            "abs(bias_3d_reference) <= v_cr_3d_reference_error", **flag)),
        "extrapolated_bar_contains_axisym": (("case",), within_ext, a(
            "abs(bias_3d_extrapolated) <= v_cr_3d_extrapolated_error", **flag)),
    }


def compute(full: bool = False, solved: dict | None = None) -> tuple[xr.Dataset, dict]:
    from debench.models.buckling.axisym import AxisymDiscretisation

    orders, layers = study.CRITICAL[full]["orders"], study.CRITICAL[full]["layers"]
    res = solved if solved is not None else solve_plan(full)
    shape = (len(CASES), len(WAVENUMBERS), len(orders), len(layers))
    fields = {k: np.zeros(shape) for k in ("v", "cpu_s", "eig_residual", "newton_residual_rel",
                                           "vtol", "thickness", "e")}
    ndof = np.zeros(shape, dtype=np.int64)
    ndof_mode = np.zeros(shape, dtype=np.int64)
    for idx in np.ndindex(shape):
        c, n, p, L = idx
        r = res[(CASES[c], WAVENUMBERS[n], orders[p], layers[L])]
        for k, arr in fields.items():
            arr[idx] = getattr(r, k)
        ndof[idx], ndof_mode[idx] = r.ndof, r.ndof_mode
    v = fields["v"]
    # the dataset's names of the estimate's fields
    fields_of = {"v": "value", "error": "error", "p_step_change": "p_change",
                 "grading_change": "grading_change"}
    conv = {k: np.zeros(shape[:2]) for k in fields_of}
    acc = {k: np.zeros(shape[:2]) for k in fields_of}
    fs = safety_factor(len(orders))
    for c, n in np.ndindex(shape[:2]):
        got = converged(v[c, n], REGEN_ATOL)
        for k, field in fields_of.items():
            conv[k][c, n] = getattr(got, field)
            # regenerations move each input by up to REGEN_ATOL: the derived values by
            # what that moves them
            acc[k][c, n] = float(propagated_accuracy(
                lambda x, field=field: getattr(converged(x, REGEN_ATOL), field), v[c, n],
                REGEN_ATOL))
    acc = {k: float(np.max(x)) for k, x in acc.items()}

    vs3d = _vs_3d(conv["v"][:, WAVENUMBERS.index(0)])
    a = variable_attrs
    ds = xr.Dataset(
        _variables(fields, ndof, ndof_mode, res, conv, acc, fs, vs3d),
        coords={
            "case": ("case", list(CASES), {"long_name": "material and thickness "
                                           "(nh: neo-Hookean, ogden: Ogden (5.26); t1: 1 mm)"}),
            "n": ("n", np.array(WAVENUMBERS), a("angular wavenumber of the perturbation")),
            "order": ("order", np.array(orders), a("polynomial order of every field")),
            "layers": ("layers", np.array(layers), a(
                "geometric layers towards the rim (edge_layers) and towards each face "
                "(face_layers)")),
        },
    )
    d = AxisymDiscretisation()
    params = {"full": full, "orders": list(orders), "layers": list(layers), "cases": list(CASES),
              "wavenumbers": list(WAVENUMBERS), "thickness_m": study.THICKNESS,
              "aspect": study.ASPECT, "n_r": study.CRITICAL_N_R,
              "n_z": d.n_z, "edge_zone": d.edge_zone, "grading": d.grading,
              "n1_start": N1_START, "gci_safety": fs,
              "error_floor": REGEN_ATOL, "seed_step": SEED_STEP,
              "guard_order": study.CRITICAL_GUARD[0], "guard_layers": study.CRITICAL_GUARD[1],
              "materials": "Table 5.1 neo-Hookean (5.15)-(5.17); Ogden (5.26), k of Table 5.1 "
                           "(exact principal-stretch evaluation, no regularisation)"}
    return ds, params


def build(out_dir: Path, *, full: bool = False) -> list[Path]:
    ds, params = compute(full)
    return [write_dataset(
        ds, NAME, out_dir=out_dir, overwrite=True,
        title="Chapter 5: critical voltage of the clamped film, axisymmetric FE model",
        summary=("Critical normalised voltage of the perfect clamped film (Table 5.1 "
                 "neo-Hookean and Ogden, t0 = 1 mm, R/t0 = 10) in angular wavenumbers n = 0 "
                 "and 1 by the axisymmetric body-of-revolution FE model on p- and "
                 "grading-sequences, the converged values with their error estimates, and "
                 "the comparison with the 3D model's critical voltage."),
        parameters=params)]
