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
    LIMITS,
    TOL_COARSE,
    VOLTAGE_CASES,
    compare,
    curated_comparisons,
    curated_limit,
    euler_slopes_of,
    limit_comparison,
    tolerance,
)
from debench.reference.values import Guarded

__all__ = ["ACCURACY", "GUARD_CASES", "agreement_charge", "agreement_voltage", "biot_limit",
           "euler_limit", "strip_fe_guards"]


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


#: The strip-FE cases :func:`strip_fe_guards` recomputes, as (control, (xi, load, kH)): the
#: thin isotropic and the anisotropic (xi = 5) charge-controlled cases of ``CASES_FAST``
#: and the anisotropic voltage-controlled one, which with the two limits run the isotropic
#: and the transversely isotropic material, both parities, both controls and the thin and
#: thick meshes (~5 s of CPU against the 34 s of the whole ``ch4_fe`` build)
GUARD_CASES = (("charge", (0.0, 2.0, 0.3)), ("charge", (5.0, 0.0, 2.0)),
               ("voltage", (5.0, 0.5, 10.0)))


def strip_fe_guards(cases=None) -> list:
    """The strip-FE model guard of ``debench verify``, which does not rebuild ``ch4_fe``
    (``debench reproduce`` rebuilds and compares its three datasets): the FE roots of
    :data:`GUARD_CASES` and of both limits recomputed now on the mesh level of the curated
    ``ch4_fe_agreement.nc`` and ``ch4_fe_limits.nc``, each guarded as
    ``ch4.guard.fe.<control>.<case>.root<k>`` (or ``ch4.guard.fe.limit.<name>``) and as its
    difference from the curated root (``..._minus_curated``, stored ~0). A change of the strip
    model (material, mesh, eigen-solver, root search) moves them, although the producers
    read the curated roots. ``cases``: a subset of :data:`GUARD_CASES` without the limits
    (for mutation tests)."""
    out = []

    def guard(key, fresh, stored):
        tol = ACCURACY.tolerance(fresh)
        out.extend([Guarded(key, float(fresh), tol, ACCURACY.reason),
                    Guarded(f"{key}_minus_curated", float(fresh) - float(stored), tol,
                            ACCURACY.reason)])

    for control, case in (GUARD_CASES if cases is None else cases):
        stored = curated_comparisons([case], control)
        fresh = compare(*case, level=stored[0].level, control=control)
        name = "xi={:g}.load={:g}.kH={:g}".format(*case)
        for k, (s, f) in enumerate(zip(stored, fresh, strict=True)):
            guard(f"ch4.guard.fe.{control}.{name}.root{k}.{s.parity}", f.lam_fe, s.lam_fe)
    if cases is None:
        for limit in LIMITS:
            guard(f"ch4.guard.fe.limit.{limit}", limit_comparison(limit).lam_fe,
                  curated_limit(limit).lam_fe)
    return out
