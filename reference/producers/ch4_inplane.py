"""Producers of the ``ch4.beyond.inplane.*`` entries (the fibre in the plane of the plate):
catalogue outcomes from the checks of the study (:mod:`debench.reference.studies.ch4_inplane`)
with the curated FE roots."""

from __future__ import annotations

import math

import numpy as np
from debench.models.plate import PlateParams, energy_matrix
from debench.models.plate import inplane as ip
from debench.reference.catalogue import Entry, Outcome
from debench.reference.studies.ch4_inplane import (
    ACCURACY,
    KH_THIN,
    N_SCAN,
    T_WINDOW,
    THETAS,
    TOL_AGREE,
    TOL_MATRIX,
    XI,
    compression_case,
    det_roots,
    det_roots_many,
    ellipticity_stretch,
    max_disagreement,
    membrane_limit_closed_form,
    tension_check,
    voltage_agreement,
)

__all__ = ["ACCURACY", "ellipticity_limit", "ellipticity_limit_closed_form",
           "lam_cr_decreases_with_theta", "methods_agree", "tension_membrane_limit",
           "tension_wrinkling", "theta90_is_isotropic", "voltage_methods_agree",
           "wrinkling_before_ellipticity_loss"]


EV = "verification/test_ch4_inplane.py"


def methods_agree(entry: Entry) -> Outcome:
    """Every determinant root has an FE root within TOL_AGREE, and the counts match (FE
    roots of the curated ``ch4_inplane_roots.nc``)."""
    err, same, rows = max_disagreement(fe_source="curated")
    ok = bool(same and err <= TOL_AGREE and rows)
    return Outcome(ok, evidence=f"{EV}::test_methods_agree_on_every_root",
                   details={"max_abs_diff": err, "same_count": same, "roots": rows})


def lam_cr_decreases_with_theta(entry: Entry) -> Outcome:
    """lam_cr (largest root in the window) decreases strictly from theta = 0 to 90."""
    det = det_roots_many([compression_case(th) for th in THETAS])
    lc = [max(r) if r else math.nan for r in det]
    ok = bool(np.all(np.isfinite(lc)) and np.all(np.diff(lc) < 0))
    return Outcome(ok, evidence=f"{EV}::test_lam_cr_decreases_with_theta",
                   details={"theta": list(THETAS), "lam_cr": lc})


def ellipticity_limit_closed_form(entry: Entry) -> float:
    """Our closed form lam_E = (1 - 1/(2 xi cos^2 theta))^(1/2) (vanishing L21 modulus)."""
    th = math.radians(entry.parameters["theta"])
    return math.sqrt(1 - 1 / (2 * entry.parameters["xi"] * math.cos(th) ** 2))


def ellipticity_limit(entry: Entry) -> Outcome:
    """lam_E scanned and bisected on the strong-ellipticity test, against the closed form."""
    pr = entry.parameters
    lam_e = ip.ellipticity_limit(pr["theta"], PlateParams(xi=pr["xi"], Dhat=0.0),
                                 window=(0.45, 0.999))
    return Outcome(lam_e, evidence=f"{EV}::test_ellipticity_limit_closed_form",
                   details={"closed_form": ellipticity_limit_closed_form(entry)})


def wrinkling_before_ellipticity_loss(entry: Entry) -> Outcome:
    """Dhat = 0: at every theta a root lies above lam_E (the plate wrinkles first)."""
    det_roots_many([compression_case(th) for th in THETAS])
    rows = [(th, max(det_roots(compression_case(th)), default=math.nan),
             ellipticity_stretch(float(th), XI, 0.0)) for th in THETAS]
    ok = all(r > e for _, r, e in rows)
    return Outcome(ok, evidence=f"{EV}::test_wrinkling_before_ellipticity_loss",
                   details={"rows": rows})


def theta90_is_isotropic(entry: Entry) -> Outcome:
    """At theta = 90 degrees the in-plane energy matrix is the isotropic thesis one."""
    worst = 0.0
    for lam in (0.6, 0.9, 1.3):
        for D in (0.0, 2.0):
            S = ip.energy_matrix(lam, 90.0, PlateParams(xi=XI, Dhat=D))
            iso = energy_matrix(np.asarray(lam), PlateParams(xi=0.0, Dhat=D))
            keep = [0, 1, 2, 3, 6, 7]
            worst = max(worst, float(np.max(np.abs(S[np.ix_(keep, keep)] - iso))),
                        float(np.max(np.abs(S[4:6, keep]))))
    return Outcome(worst <= TOL_MATRIX, evidence=f"{EV}::test_theta90_is_isotropic",
                   details={"max_abs_diff": worst})


def voltage_methods_agree(entry: Entry) -> Outcome:
    """Voltage control: every determinant root has an FE root within TOL_AGREE (FE roots
    of the curated ``ch4_inplane_roots.nc``)."""
    err, same, rows = voltage_agreement("curated")
    ok = bool(same and err <= TOL_AGREE and len(rows) >= len(THETAS))
    return Outcome(ok, evidence=f"{EV}::test_voltage_methods_agree_on_every_root",
                   details={"max_abs_diff": err, "same_count": same, "roots": rows})


def tension_wrinkling(entry: Entry) -> Outcome:
    """Tension: with Dhat = D_TENSION a root above 1 at every theta and kH of KH_TENSION
    (both methods, within TOL_AGREE; FE roots of the curated ``ch4_inplane_roots.nc``),
    lam_cr increasing with theta, none at Dhat = 0."""
    ok, rows, none_without_field = tension_check("curated")
    return Outcome(ok, evidence=f"{EV}::test_tension_wrinkling_with_field",
                   details={"rows": rows, "none_without_field": none_without_field})


def tension_membrane_limit(entry: Entry) -> Outcome:
    """lam_cr(kH) of the determinant at KH_THIN, fitted a + b (kH)^2: a against the
    closed-form zero of the total lateral stress (the catalogue value)."""
    pr = entry.parameters
    p = PlateParams(xi=pr["xi"], Dhat=pr["Dhat"])
    lam = []
    for kh in KH_THIN:
        r = ip.critical_stretches_det(kh, pr["theta"], p, window=T_WINDOW, n_scan=N_SCAN)
        lam.append(max(r, default=math.nan))
    A = np.vander(np.square(KH_THIN), 2, increasing=True)
    coef, res, *_ = np.linalg.lstsq(A, np.asarray(lam), rcond=None)
    return Outcome(float(coef[0]), evidence=f"{EV}::test_tension_membrane_limit",
                   details={"lam_cr": lam, "kH": list(KH_THIN), "slope": float(coef[1]),
                            "fit_residual": float(np.sqrt(res[0])) if res.size else 0.0,
                            "closed_form": membrane_limit_closed_form(
                                pr["theta"], pr["xi"], pr["Dhat"])})
