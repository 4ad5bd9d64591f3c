"""Diagnoses of the Chapter 5 values that do not reproduce (``reference/catalogue/ch5.toml``,
kind ``hypothesis``): a normalisation with mu in MPa, values read off the thesis' curves, a
nominal instead of a true field, a thickness dependence, and the radius/thickness 20
wrinkling search of the 3D ramps with its imperfection sensitivity. Each tests a stated
cause against our numbers, read from the curated datasets (never the FE model).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from debench.reference import catalogue
from debench.reference.catalogue import Entry, Outcome
from debench.reference.datasets import read_dataset
from debench.reference.producers import ch5
from debench.reference.producers.ch5 import (
    EPS0,
    EPS_R,
    EV_DATA,
    MU_REF,
    _case,
    _field_V_per_um,
    _ramps,
)
from debench.reference.studies.ch5 import first_instability, lowest_nonaxisymmetric
from debench.reference.studies.ch5_imperfection import drop_exponent, wrinkling_governs

#: the accuracy of every value these diagnoses read from the curated datasets (as for
#: every Chapter 5 dataset value: :data:`debench.reference.producers.ch5.ACCURACY`)
ACCURACY = ch5.ACCURACY

#: The modulus the thesis states for the normalisation (Table 5.1) and the one the
#: hypothesis "mu in MPa" says was used instead: 1 MPa for 0.156 MPa, a units slip.
MU_HYPOTHESIS = 1.0e6
#: how each quantity transforms under a change of the normalising modulus: normalised
#: voltages scale with sqrt(mu_ref/mu_used). Deflections and physical fields do not depend
#: on the normalisation: a "mu in MPa" hypothesis about them cannot move its target, so it
#: is not offered (:func:`hypothesis_mu_in_mpa` refuses it).
_SCALING = {"voltage": math.sqrt(MU_REF / MU_HYPOTHESIS), "displacement": 1.0, "field": 1.0}


def moves_its_target(quantity: str) -> bool:
    """Whether the "mu in MPa" normalisation changes a quantity of this kind at all."""
    return _SCALING[quantity] != 1.0


def _target(entry: Entry):
    target = catalogue.by_id()[entry.parameters["target"]]
    return target, catalogue.evaluate(target)


def hypothesis_mu_in_mpa(entry: Entry) -> Outcome:
    """Our value of the target claim converted as the thesis would print it had it
    normalised with mu = 1 MPa instead of 0.156 MPa; ``explained`` when that gives the
    printed number within half a unit of its last digit."""
    if not moves_its_target(entry.parameters["quantity"]):
        raise ValueError(f"{entry.id}: the normalisation does not change a "
                         f"{entry.parameters['quantity']}: the hypothesis cannot move its target")
    target, ours = _target(entry)
    if isinstance(ours.value, bool | str):
        raise ValueError(f"{entry.id}: target {target.id} is not a numeric claim")
    if ours.value is None:
        return Outcome(None, status="unexplained" if ours.value is None else None,
                       diagnosis=f"{target.id}: we compute no number to convert "
                                 f"({ours.diagnosis})")
    factor = _SCALING[entry.parameters["quantity"]]
    predicted = float(ours.value) * factor
    tol = target.implied_tolerance()
    explained = abs(predicted - float(target.value)) <= tol * (1 + 1e-12)
    return Outcome(predicted, status="explained" if explained else "unexplained",
                   details={"ours": float(ours.value), "factor": factor,
                            "thesis": float(target.value), "tolerance": tol,
                            "thesis_over_prediction": float(target.value) / predicted})


def _rising_branch(case: str) -> tuple[np.ndarray, np.ndarray]:
    """Voltages and centre deflections / t0 of the imperfect ramp up to its voltage
    maximum (the finite records)."""
    r = _ramps().sel(case=case)
    vv, ww = r.v.values, r.w_mid.values
    ok = np.isfinite(vv) & np.isfinite(ww)
    vv, ww = vv[ok], ww[ok]
    top = int(np.argmax(vv)) + 1
    return vv[:top], ww[:top]


def _w_at_voltage(case: str, v: float) -> float:
    """Centre deflection / t0 of the imperfect ramp at normalised voltage ``v`` (before the
    voltage maximum; linear interpolation between ramp steps)."""
    vv, ww = _rising_branch(case)
    if not vv[0] <= v <= vv[-1]:
        raise ValueError(f"v = {v} outside the ramp of {case} [{vv[0]}, {vv[-1]}]")
    return float(np.interp(v, vv, ww))


def _v_at_w(case: str, w: float) -> float:
    """Normalised voltage of the imperfect ramp at centre deflection ``w`` / t0 (before the
    voltage maximum; linear interpolation between ramp steps)."""
    vv, ww = _rising_branch(case)
    if not ww[0] <= w <= ww[-1]:
        raise ValueError(f"w = {w} outside the ramp of {case} [{ww[0]}, {ww[-1]}]")
    return float(np.interp(w, ww, vv))


def hypothesis_read_off(entry: Entry) -> Outcome:
    """Were the printed critical voltages read off the imperfect ramps at one deflection?

    Under the "mu in MPa" normalisation the anchor's printed critical voltage (with its
    printed precision) maps to an interval of voltages of our imperfect ramp, hence to an
    interval of centre deflections; read off the target's ramp at those deflections, it
    predicts the target's critical voltage (converted the same way). Value: the prediction
    at the middle of the anchor's deflection interval, a voltage like the target's;
    ``explained`` when the predicted interval meets the target's printed one (one
    deflection threshold then gives both printed numbers)."""
    ids = catalogue.by_id()
    k = _SCALING["voltage"]
    w_int = {}
    for key in ("anchor", "target"):
        e = ids[entry.parameters[key]]
        tol = e.implied_tolerance()
        w_int[key] = (_w_at_voltage(_case(e), (float(e.value) - tol) / k),
                      _w_at_voltage(_case(e), (float(e.value) + tol) / k))
    target = ids[entry.parameters["target"]]
    tcase = _case(target)
    a0, a1 = w_int["anchor"]
    predicted = _v_at_w(tcase, 0.5 * (a0 + a1)) * k
    interval = [_v_at_w(tcase, a0) * k, _v_at_w(tcase, a1) * k]
    tol = target.implied_tolerance()
    overlap = (interval[0] <= float(target.value) + tol
               and float(target.value) - tol <= interval[1])
    return Outcome(predicted, status="explained" if overlap else "unexplained",
                   details={f"w_interval_over_t0.{_case(ids[entry.parameters[key]])}":
                            list(w_int[key]) for key in ("anchor", "target")}
                   | {"predicted_interval": interval, "imperfection_over_t0": 1e-3})


def hypothesis_nominal_field(entry: Entry) -> Outcome:
    """Is the printed "true field at instability" the nominal field Phi/t0 at pull-in?

    Ours: the nominal field of our pull-in voltage (mesh limit), in V/um at the assumed
    eps_r; ``explained`` when it gives the target's printed number to its digits. Details:
    the eps_r that would give the printed number, the nominal field of the printed pull-in
    voltage under the "mu in MPa" normalisation (the interval of its printed digits), and
    the same definition for the ``other`` claim (its target and our value)."""
    ids = catalogue.by_id()
    target = ids[entry.parameters["target"]]

    def nominal(pullin_id: str, eps_r: float = EPS_R) -> float:
        v = float(_ramps().sel(case=_case(ids[pullin_id])).v_pullin_extrapolated)
        return _field_V_per_um(v, eps_r)

    value = nominal(entry.parameters["pullin"])
    tol = target.implied_tolerance()
    explained = abs(value - float(target.value)) <= tol * (1 + 1e-12)
    pullin = ids[entry.parameters["pullin"]]
    ptol = pullin.implied_tolerance()
    in_mpa = math.sqrt(MU_HYPOTHESIS / (EPS_R * EPS0)) * 1e-6
    other = ids[entry.parameters["other"]]
    return Outcome(value, status="explained" if explained else "unexplained",
                   details={"thesis": float(target.value), "tolerance": tol,
                            "eps_r_that_would_match": EPS_R * (value / float(target.value)) ** 2,
                            "printed_pullin_field_interval": [
                                (float(pullin.value) - ptol) * in_mpa,
                                (float(pullin.value) + ptol) * in_mpa],
                            "other_thesis": float(other.value),
                            "other_nominal": nominal(entry.parameters["other_pullin"])})


@lru_cache(maxsize=4)
def _thickness():
    return read_dataset("ch5_thickness")


def hypothesis_thickness(entry: Entry) -> Outcome:
    """Table 5.2's 0.5 mm critical voltage predicted from its own 1 mm value under a
    hypothesis about the 0.5 mm model: ``radius_kept`` (R = 10 mm, so R/t0 = 20: factor
    v_cr(20)/v_cr(10) from ``ch5_thickness.nc``) and/or ``t1_normalisation`` (voltage
    divided by the 1 mm thickness: factor 1/2). Anchoring on the printed 1 mm value makes
    the test independent of the unknown absolute normalisation. ``explained`` when the
    predicted interval (printed precision of the anchor and the mesh error of the ratio)
    meets the printed interval of the target."""
    ids = catalogue.by_id()
    target, anchor = ids[entry.parameters["target"]], ids[entry.parameters["anchor"]]
    p = entry.parameters
    ds = _thickness()
    ratio, err = ((float(ds.ratio_extrapolated), float(ds.ratio_error))
                  if p["radius_kept"] else (1.0, 0.0))
    scale = 0.5 if p["t1_normalisation"] else 1.0
    a, da = float(anchor.value), anchor.implied_tolerance()
    lo, hi = (a - da) * (ratio - err) * scale, (a + da) * (ratio + err) * scale
    t, dt = float(target.value), target.implied_tolerance()
    explained = lo <= t + dt and hi >= t - dt
    return Outcome(a * ratio * scale, status="explained" if explained else "unexplained",
                   details={"predicted_interval": [lo, hi], "ratio_R20_over_R10": ratio,
                            "ratio_error": err, "normalisation_factor": scale,
                            "thesis_interval": [t - dt, t + dt]})



@lru_cache(maxsize=4)
def wrinkling_records():
    return read_dataset("ch5_wrinkling")


def wrinkling_search(ds) -> dict:
    """What the radius/thickness 20 ramps (``ch5_wrinkling.nc``) found, per mesh level (lists,
    coarse to fine): the first instability along the path
    (:func:`debench.reference.studies.ch5.first_instability`: ``first_kind``, its
    deflection / t0 ``w_first_over_t0``, its voltage over the largest voltage of the path
    ``v_first_over_v_max``, wavenumber ``n_first``, the recorded eigenvalues there
    ``lam_ratio_first``, their n = 0 fractions ``axisym_first`` and dominant wavenumbers
    ``wavenumbers_first``); ``first`` -- it is a
    non-axisymmetric mode (wrinkling before pull-in); ``consistent`` -- the same kind on
    every resolution; the two finest levels' wrinkling deflections / t0 (``w_over_t0``,
    ``w_over_t0_second``; NaN where the first instability is not wrinkling); per level the
    deflection / t0 where the lowest non-axisymmetric eigenvalue is smallest before the
    first instability (``w_min_lambda_over_t0``), that eigenvalue and its largest value on
    the path (``min_nonaxisymmetric_lambda``, ``max_nonaxisymmetric_lambda``); the path's
    voltage maximum (``w_pullin_over_t0``: the dataset's ``w_pullin``) and why it ended."""
    firsts, w_min, lam_min, lam_max = [], [], [], []
    for lev in ds.level.values:
        r = ds.sel(level=lev)
        f = first_instability(r.eig_w.values, r.eig_v.values, r.eig_lam.values,
                              r.eig_axisym.values, r.eig_wavenumber.values)
        f["v_over_v_max"] = f["v"] / float(np.nanmax(r.v.values))
        firsts.append(f)
        lam = lowest_nonaxisymmetric(r.eig_lam.values, r.eig_wavenumber.values)
        upto = r.eig_w.values <= (f["w"] if np.isfinite(f["w"]) else np.inf)
        lam = np.where(upto & np.isfinite(lam), lam, np.inf)
        k = int(np.argmin(lam))
        w_min.append(float(r.eig_w.values[k]))
        lam_min.append(float(lam[k]))
        lam_max.append(float(np.max(np.where(np.isfinite(lam), lam, -np.inf))))
    first = [f["kind"] == "non-axisymmetric" for f in firsts]
    kinds = [f["kind"] for f in firsts]

    def wrinkle(f, key):
        return f[key] if f["kind"] == "non-axisymmetric" else math.nan

    return {"first": first, "consistent": len(set(kinds)) == 1, "first_kind": kinds,
            "w_first_over_t0": [f["w"] for f in firsts],
            "v_first_over_v_max": [f["v_over_v_max"] for f in firsts],
            "n_first": [f["n"] for f in firsts],
            "lam_ratio_first": [f["lam_ratio"] for f in firsts],
            "axisym_first": [f["axisym"] for f in firsts],
            "wavenumbers_first": [f["wavenumbers"] for f in firsts],
            "w_over_t0": wrinkle(firsts[-1], "w"),
            "w_over_t0_second": wrinkle(firsts[-2], "w"),
            "v": wrinkle(firsts[-1], "v"), "n": wrinkle(firsts[-1], "n"),
            "w_min_lambda_over_t0": w_min, "min_nonaxisymmetric_lambda": lam_min,
            "max_nonaxisymmetric_lambda": lam_max,
            "w_pullin_over_t0": [float(x) for x in ds.w_pullin.values],
            "path_end": [str(x) for x in ds.path_end.values],
            "h_rel": [float(x) for x in ds.h_rel.values]}


@lru_cache(maxsize=4)
def _imperfection():
    return read_dataset("ch5_imperfection")


def hypothesis_wrinkling_failure(entry: Entry) -> Outcome:
    """§5.3.1: the 0.5 mm film "was more susceptible to wrinkling instability and fails at a
    lower achievable deformation" than the 1 mm film's pull-in. Under the hypothesis that
    its model kept R = 10 mm (R/t0 = 20), judged by the imperfection-sensitivity study
    ``ch5_imperfection.nc`` (films with wavenumber-1 seeds on two meshes): ``explained``
    when the reading fixed before the data
    (:func:`debench.reference.studies.ch5_imperfection.wrinkling_governs`) is that the
    wrinkling bifurcation governs the failure (every seeded film reaches its voltage maximum
    near the bifurcation, falling as the seed grows); ``unexplained`` when the films pass
    the bifurcation or the meshes disagree. The value: the centre deflection (mm) at the
    voltage maximum of the smallest seed on the finest mesh."""
    ds = _imperfection()
    t0_mm = float(entry.parameters["thickness_mm"])
    verdict = wrinkling_governs(ds)
    w = ds.w_at_v_max.values
    value = float(w[-1, 0]) * t0_mm if np.isfinite(w[-1, 0]) else None
    first, ends = [], []        # per path: first instability at fixed voltage; last point
    for lev in range(ds.sizes["level"]):
        first.append([])
        ends.append([])
        for j in range(ds.sizes["amplitude"]):
            r = ds.isel(level=lev, amplitude=j)
            first[-1].append(first_instability(
                r.eig_w.values, r.eig_v.values, r.eig_lam.values, r.eig_axisym.values,
                r.eig_wavenumber.values))
            k = int(np.flatnonzero(np.isfinite(r.w.values))[-1])
            ends[-1].append([float(r.w.values[k]), float(r.v.values[k])])
    return Outcome(value, status="explained" if verdict == "governs" else "unexplained",
                   details={
                       "reading": verdict, "h_rel": [float(x) for x in ds.h_rel.values],
                       "amplitudes": [float(x) for x in ds.amplitude.values],
                       "v_max": ds.v_max.values.tolist(),
                       "w_at_v_max_over_t0": w.tolist(),
                       "w_at_v_max_mm": (w * t0_mm).tolist(),
                       "w_asym_at_v_max": ds.w_asym_at_v_max.values.tolist(),
                       "path_end": ds.path_end.values.tolist(),
                       "drop_exponent": [drop_exponent(v) for v in ds.v_max.values],
                       "first_kind": [[f["kind"] for f in row] for row in first],
                       "first_w_over_t0": [[f["w"] for f in row] for row in first],
                       "first_v": [[f["v"] for f in row] for row in first],
                       "first_n": [[f["n"] for f in row] for row in first],
                       "end_w_over_t0_v": ends, "thickness_mm": t0_mm},
                   evidence=f"{EV_DATA}::test_curated_r20_imperfection_sensitivity")
