"""Producers of the ``ch4.fe.*`` entries: the agreement of the strip FE with the
determinant (charge and voltage control) and the Biot and Euler limits, from the curated
FE roots and the live determinant roots of the study
(:mod:`debench.reference.studies.ch4_fe`)."""

from __future__ import annotations

from debench.reference.catalogue import Entry, Outcome
from debench.reference.studies.ch4_fe import (
    ACCURACY,
    BIOT,
    CASES_FAST,
    KH_BIOT,
    KH_EULER,
    TOL_COARSE,
    VOLTAGE_CASES,
    curated_comparisons,
    curated_limit,
    euler_slopes_of,
    tolerance,
)

__all__ = ["ACCURACY", "agreement_charge", "agreement_voltage", "biot_limit", "euler_limit"]


EV = "verification/test_ch4_fe.py"


def _agreement(cases, control, label, entry: Entry) -> Outcome:
    rows = curated_comparisons(cases, control)
    err = max(abs(c.diff) for c in rows)
    ok = all(abs(c.diff) <= tolerance(c.kH) for c in rows)
    levels = sorted({c.level for c in rows})
    return Outcome(ok, evidence=f"{EV}::test_strip_fe_agrees_with_determinant_{label}",
                   diagnosis=f"max |lam_FE - lam_det| = {err:.2e} over {len(rows)} roots "
                             f"(FE roots of the curated ch4_fe_agreement.nc, mesh level "
                             f"{levels}; bounds by kH {TOL_COARSE})",
                   details={"max_abs_diff": err,
                            "roots": [(c.xi, c.load, c.kH, c.parity, c.lam_det, c.lam_fe)
                                      for c in rows]})


def agreement_charge(entry: Entry) -> Outcome:
    """Figs 4.2/4.5 (representative subset): strip FE and determinant agree (charge control)."""
    return _agreement(CASES_FAST, "charge", "charge_control", entry)


def agreement_voltage(entry: Entry) -> Outcome:
    """Voltage control: strip FE and determinant agree."""
    return _agreement(VOLTAGE_CASES, "voltage", "voltage_control", entry)


def biot_limit(entry: Entry) -> Outcome:
    """Thick-plate limit: FE lam_cr at kH = KH_BIOT (curated ``ch4_fe_limits.nc``) against
    Biot's 0.66614."""
    v = curated_limit("biot").lam_fe
    return Outcome(v, evidence=f"{EV}::test_strip_fe_thick_limit_is_biot",
                   details={"kH": KH_BIOT, "biot": BIOT})


def euler_limit(entry: Entry) -> Outcome:
    """Thin-plate limit: FE (1 - lam_cr)/kH^2 at kH = KH_EULER (FE root of the curated
    ``ch4_fe_limits.nc``, determinant live) against plate theory 1/18."""
    fe, det = euler_slopes_of(curated_limit("euler"))
    return Outcome(fe, evidence=f"{EV}::test_strip_fe_thin_limit_is_euler",
                   details={"kH": KH_EULER, "determinant": det, "plate_theory": 1 / 18})
