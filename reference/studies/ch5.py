"""The Chapter 5 study: the clamped dielectric buckling membrane's cases, mesh sequences
and finite-element tasks (the plan, :func:`plan`), the coarse recomputation that
``debench verify`` guards (:func:`coarse_values`), and the readings of a path's eigen-records
(:func:`first_instability`, :func:`lowest_nonaxisymmetric` ...) that the builder's datasets
and the producers' catalogue values share.

The finite-element tasks (:func:`critical_task`, :func:`ramp_task`,
:func:`wrinkling_task`) are plain functions of their arguments and of the settings they
read (the task cache keys on exactly those, :func:`debench.reference.tasks.task_inputs`).
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np
from debench.models.buckling.parameters import Discretisation, Plate
from debench.models.buckling.singularity import expected_eigenvalue_order, poisson_ratio
from debench.models.materials import material as library_material
from debench.reference.tasks import default_cost, limit_threads

__all__ = ["CASES", "COARSE_H", "EIG_EVERY", "GUARD_DV_MAX", "LAYER_STUDY", "LAYERS", "LEVELS",
           "ORDER", "RAMP_DV_MAX", "RAMP_LAYERS", "RAMP_LEVELS", "SCALE_COPIES",
           "axisymmetric", "case_material", "coarse_values", "critical_task", "expected_order",
           "first_instability", "lowest_nonaxisymmetric", "material", "plan", "ramp_task",
           "stable_records_past_voltage_maximum", "task_cost"]


CASES = {  # name: (material, thickness [m])
    "nh_t1": ("nh", 1e-3),
    "ogden_t1": ("ogden", 1e-3),
    "ogden_t0p5": ("ogden", 0.5e-3),
}
ORDER = 2
"""Polynomial order of the displacement (quadratic prisms)."""
EIG_EVERY = 4
"""Eigen-analysis every 4th converged path point of a ramp."""
RAMP_DV_MAX = 0.02  # largest voltage step of the ramps (normalised): >= 3 points in the
                    # Southwell window 0.4-0.9 v_cr of the Ogden case (v_cr ~ 0.17)


def material(name):
    """The Table 5.1 material of a case's material name (``"nh"``, ``"ogden"`` or any name
    of the library registry); ``ValueError`` naming the valid names otherwise."""
    return library_material(name)


def case_material(case: str):
    """The material of a case of :data:`CASES` (``"nh_t1"``: neo-Hookean, ...)."""
    if case not in CASES:
        raise ValueError(f"case must be one of {sorted(CASES)}, got {case!r}")
    return material(CASES[case][0])


def critical_task(case: str, h_rel: float, layers: int = 1, aspect: float = 10.0) -> dict:
    """One critical-voltage computation as plain data (a Dask task)."""
    from debench.models.buckling.solver import critical_voltage
    limit_threads()
    mat_name, t0 = CASES[case]
    start = time.perf_counter()
    r = critical_voltage(Plate(thickness=t0, aspect=aspect), material(mat_name),
                         Discretisation(h_rel=h_rel, layers=layers, order=ORDER))
    return {"v": r.v, "ndof": r.ndof, "nelements": r.nelements, "eig_residual": r.eig_residual,
            "newton_residual": r.newton_residual, "seconds": time.perf_counter() - start}


def ramp_task(case: str, h_rel: float, eig_every: int = EIG_EVERY,
              dv_max: float = RAMP_DV_MAX, layers: int = 1, aspect: float = 10.0) -> dict:
    """One voltage ramp as plain data (a Dask task): the RampResult fields."""

    from debench.models.buckling.solver import voltage_ramp
    limit_threads()
    mat_name, t0 = CASES[case]
    r = voltage_ramp(Plate(thickness=t0, aspect=aspect), material(mat_name),
                     Discretisation(h_rel=h_rel, layers=layers, order=ORDER),
                     dv_max=dv_max, eig_every=eig_every)
    return {f.name: getattr(r, f.name) for f in dataclasses.fields(r)}


WRINKLING_CASE = "ogden_t0p5"
WRINKLING_ASPECT = 20.0
WRINKLING_LAYERS = 1
WRINKLING_EIG_EVERY = 1
"""Eigen-analysis at every path point of the radius/thickness 20 ramps: the path steps
0.4 t0 in deflection there, and the lowest non-axisymmetric eigenvalue dips close to zero
over ~1-2 t0, so sparser records could step over a short excursion below zero. An
eigen-analysis costs ~1/10 of the Newton steps of one path point."""
WRINKLING_DV_MAX = 0.02


def wrinkling_task(h_rel: float, eig_every: int) -> dict:
    """One radius/thickness 20 ramp of the 0.5 mm Ogden film (the wrinkling search of
    :mod:`debench.reference.builders.ch5_wrinkling`) as plain data (a Dask task): the
    RampResult fields, with the eigen-analysis every ``eig_every`` path points; a path
    that stalls before a voltage maximum is kept (``stop_on_stall``)."""

    from debench.models.buckling.solver import voltage_ramp
    limit_threads()
    mat_name, t0 = CASES[WRINKLING_CASE]
    r = voltage_ramp(Plate(thickness=t0, aspect=WRINKLING_ASPECT), material(mat_name),
                     Discretisation(h_rel=h_rel, layers=WRINKLING_LAYERS, order=ORDER),
                     dv_max=WRINKLING_DV_MAX, eig_every=eig_every, stop_on_stall=True)
    return {f.name: getattr(r, f.name) for f in dataclasses.fields(r)}


SCALE_COPIES = {"ogden_t0p5": "ogden_t1"}
"""Cases identical in normalised variables by scale invariance (radius/thickness fixed: no
intrinsic length; ``verification/test_ch5_fem.py::test_normalised_results_are_scale_invariant``
checks it on the coarse mesh): computed once, from the case they copy."""
LEVELS = {False: (3.0, 2.0, 1.4), True: (3.0, 2.0, 1.4, 1.0, 0.7, 0.45)}
"""In-plane mesh sizes / t0 of the critical-voltage sequence (the finest full level, 0.45 t0
with two layers, has about 150,000 DOFs)."""
LAYERS = {False: 1, True: 2}
"""Layers of quadratic prisms through the thickness of the mesh sequences."""
LAYER_STUDY = {False: (3.0, (1, 2)), True: (2.0, (1, 2, 3, 4))}
"""(in-plane size, layer counts) of the through-thickness convergence study."""
RAMP_LEVELS = {False: (3.0,), True: (3.0, 2.5, 2.0)}
"""In-plane mesh sizes of the ramps (pull-in); the finest is the ramp stored step by step."""
RAMP_LAYERS = 1
"""Layers of the ramps: one. With two layers the Ogden ramp at h = 2 t0 met a singular
tangent at v = 0.449, just below its pull-in (direct solve residual NaN in the
eigen-analysis along the path), and the converged run stopped; the layer effect on the
critical voltage is measured by the through-thickness study (``v_cr_layers``)."""
GUARD_DV_MAX = 0.04  # coarse_values(): only the pull-in is needed (step-independent to
                     # the parabola's accuracy)
COARSE_H = 3.0      # the coarsest level: what coarse_values() and `debench verify` recompute


def expected_order(case: str) -> float:
    """Asymptotic convergence order of the critical voltage of ``case`` on quadratic prisms:
    2 s(nu), s the Williams exponent of the clamped-free edge at the material's small-strain
    Poisson ratio (:mod:`debench.models.buckling.singularity`)."""
    mat = material(CASES[case][0])
    mu0 = getattr(mat, "mu", None) or float(sum(mat.mus))   # initial shear modulus
    return expected_eigenvalue_order(poisson_ratio(mu0, mat.k), order=ORDER)


# ------------------------------------------------------------------ tasks (plain data out)
def task_cost(task: tuple) -> float:
    """Rough relative cost of a task (DOFs ~ layers / h^2 x aspect^2; Ogden assembles ~3x
    slower; a ramp is ~8 critical voltages): the longest tasks are submitted first.  Tasks
    whose first argument is the in-plane mesh size (the radius/thickness 20 paths, all of
    one kind within a build) cost ~ 1 / h^2 (:func:`debench.reference.tasks.default_cost`)."""
    if task[0] not in (critical_task, ramp_task):
        return default_cost(task)
    fn, case, h, *rest = task
    layers = rest[2] if fn is ramp_task and len(rest) > 2 else (rest[0] if rest else 1)
    aspect = (rest[3] if fn is ramp_task and len(rest) > 3
              else rest[1] if fn is critical_task and len(rest) > 1 else 10.0)
    c = (2 * layers + 1) / h**2 * (aspect / 10.0) ** 2
    return c * (3.0 if CASES[case][0] == "ogden" else 1.0) * (8.0 if fn is ramp_task else 1.0)


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


def plan(full: bool = False) -> dict[str, list[tuple]]:
    """The independent FE tasks of a build, by role: ``critical`` (case x level),
    ``layers`` (case x layer count of the through-thickness study, at its in-plane size),
    ``ramp_mesh`` (the critical voltage on the finest ramp mesh, for Southwell), ``ramps``
    (case x ramp level).  Scale copies are not computed.  (The radius/thickness 20
    wrinkling ramps are :mod:`debench.reference.builders.ch5_wrinkling`.)"""
    computed = [c for c in CASES if c not in SCALE_COPIES]
    lay = LAYERS[full]
    h_ls, layer_counts = LAYER_STUDY[full]
    return {
        "critical": [(critical_task, c, h, lay) for c in computed for h in LEVELS[full]],
        "layers": [(critical_task, c, h_ls, n) for c in computed for n in layer_counts],
        "ramp_mesh": [(critical_task, c, RAMP_LEVELS[full][-1], RAMP_LAYERS) for c in computed],
        "ramps": [(ramp_task, c, h, EIG_EVERY, RAMP_DV_MAX, RAMP_LAYERS)
                  for c in computed for h in RAMP_LEVELS[full]],
    }


def axisymmetric(eig_n) -> np.ndarray:
    """Which recorded modes are axisymmetric: those whose dominant angular harmonic (the
    harmonic with the largest share of the mode, ``eig_wavenumber`` of the records; see
    :func:`debench.models.buckling.modes.mode_harmonics`) is n = 0. The dominant harmonic
    rather than a threshold on the n = 0 share: on the unstructured meshes the pull-in mode
    can carry half of its amplitude in n >= 1 harmonics spread over several wavenumbers
    (measured: 47 % in n = 0 at the first record past pull-in of one R/t0 = 10 mesh),
    while a wrinkling mode's share is concentrated in one n >= 1. NaN padding is not
    axisymmetric."""
    n = np.asarray(eig_n, float)
    return np.isfinite(n) & (n == 0)


def lowest_nonaxisymmetric(eig_lam, eig_n) -> np.ndarray:
    """Per eigen-record, the lowest eigenvalue of a non-axisymmetric mode (dominant
    harmonic n >= 1, :func:`axisymmetric`); inf where a record has none or is NaN padding
    (the Fig. 5.5 counterparts plot it against the deflection)."""
    lam = np.where(axisymmetric(eig_n), np.nan, np.asarray(eig_lam, float))
    return np.nanmin(np.where(np.isfinite(lam), lam, np.inf), axis=1)


def first_instability(eig_w, eig_v, eig_lam, eig_axisym, eig_n) -> dict:
    """The first instability recorded along a path: the first eigen-record where an
    eigenvalue of the condensed tangent at fixed voltage is <= 0, classified by the mode
    that is lowest there (:func:`axisymmetric`): ``axisymmetric`` is the pull-in limit
    point of the axisymmetric film, ``non-axisymmetric`` a wrinkling bifurcation. Its
    deflection / t0 (``w``) and voltage (``v``) are interpolated linearly
    to the zero of the lowest eigenvalue of that kind between the previous record and this
    one; ``n`` is the mode's dominant wavenumber; ``lam_ratio`` the three recorded
    eigenvalues there over the largest lowest eigenvalue of the path (how far the next
    modes are from zero); ``axisym`` their n = 0 fractions, ``wavenumbers`` their dominant
    wavenumbers. Kind ``"none"`` (NaN values)
    when nothing became unstable. The voltage maximum of the deflection-controlled path is
    not used: where the path turns at a bifurcation, its maximum is the bifurcation, not
    the axisymmetric limit point."""
    lam, ax = np.asarray(eig_lam, float), np.asarray(eig_axisym, float)
    w, v = np.asarray(eig_w, float), np.asarray(eig_v, float)
    ok = np.isfinite(w)
    lam, ax, w, v, n = lam[ok], ax[ok], w[ok], v[ok], np.asarray(eig_n)[ok]
    out = {"kind": "none", "w": math.nan, "v": math.nan, "n": math.nan,
           "lam_ratio": [math.nan] * 3, "axisym": [math.nan] * 3,
           "wavenumbers": [math.nan] * 3}
    bad = np.flatnonzero(np.min(lam, axis=1) <= 0.0)
    if not bad.size:
        return out
    i = int(bad[0])
    j = int(np.argmin(lam[i]))
    sym = axisymmetric(n)
    axisym = bool(sym[i, j])
    same = sym if axisym else ~sym
    lowest = np.min(np.where(same, lam, np.inf), axis=1)
    wi, vi = w[i], v[i]
    if i > 0 and np.isfinite(lowest[i - 1]) and lowest[i - 1] > 0:
        f = lowest[i - 1] / (lowest[i - 1] - lowest[i])
        wi, vi = w[i - 1] + f * (w[i] - w[i - 1]), v[i - 1] + f * (v[i] - v[i - 1])
    scale = float(np.max(np.min(lam, axis=1)))
    out.update(kind="axisymmetric" if axisym else "non-axisymmetric", w=float(wi),
               v=float(vi), n=float(n[i, j]), lam_ratio=[float(x) / scale for x in lam[i]],
               axisym=[float(x) for x in ax[i]], wavenumbers=[float(x) for x in n[i]])
    return out


def stable_records_past_voltage_maximum(w, v, eig_w, eig_v, eig_lam) -> np.ndarray:
    """The eigen-records of one deflection-controlled path that lie past its voltage
    maximum and show no negative eigenvalue; an empty array when there are none.

    Past a voltage maximum the path descends in voltage: at the maximum the derivative of
    the equilibrium voltage along the path changes sign, and with it the determinant of the
    tangent at fixed voltage (the path's tangent solves K du/dw = -dR/dv dv/dw), so an odd
    number of its eigenvalues has crossed zero and at least one is negative until the path
    turns again. A record there whose eigenvalues are all positive is therefore not the
    lowest part of the spectrum: an eigen-solver that missed the unstable mode. The maximum
    is the largest computed path point (``w``, ``v``, the path; NaN padding ignored); the
    records checked are those after it in deflection and below it in voltage (``eig_w``,
    ``eig_v``, ``eig_lam``: the records, rows of eigenvalues). A path whose largest voltage
    is its last point has none. Returns the indices (into the records) of the offending
    ones."""
    w, v = np.asarray(w, float), np.asarray(v, float)
    ew, ev = np.asarray(eig_w, float), np.asarray(eig_v, float)
    lam = np.asarray(eig_lam, float)
    if w.shape != v.shape or ew.shape != ev.shape or lam.shape[:1] != ew.shape:
        raise ValueError(f"path shapes w {w.shape}, v {v.shape} and record shapes eig_w "
                         f"{ew.shape}, eig_v {ev.shape}, eig_lam {lam.shape} do not match")
    ok = np.flatnonzero(np.isfinite(v) & np.isfinite(w))
    if not ok.size:
        return np.array([], int)
    k = ok[int(np.argmax(v[ok]))]
    if k == ok[-1]:
        return np.array([], int)
    with np.errstate(invalid="ignore"):
        past = np.isfinite(ew) & (ew > w[k]) & (ev < v[k])
        stable = np.all(lam > 0.0, axis=1)
    return np.flatnonzero(past & stable)
