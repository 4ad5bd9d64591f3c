"""Producers of the finite-element circular actuator entries (``ch3.fe.*`` and the
interface erratum ``ch3.erratum.eq_3_32`` in ``reference/catalogue/ch3.toml``) and the
thin-solid guard of ``debench verify``: catalogue outcomes from the checks of the study
(:mod:`debench.reference.studies.ch3_fe`) on its coarse mesh, and from the stored
``ch3_fe_thickness`` films."""

from __future__ import annotations

import math
from functools import lru_cache

from debench.reference.catalogue import Accuracy, Entry, Outcome
from debench.reference.datasets import read_dataset
from debench.reference.studies.ch3_fe import (
    INTERFACE_MESHES,
    JUMP_ORDER_MIN,
    MESH_COARSE,
    SOLID_MESH_COARSE,
    THICKNESS_SEQUENCES,
    TOL_COARSE,
    TOL_SUPPRESSION_COARSE,
    event_support,
    interface_balance,
    solid_value,
    stored_sequence,
    suppression_support,
    thickness_limit,
)
from debench.reference.values import Guarded

EV = "verification/test_ch3_fe.py"


#: Accuracy of a recomputed FE value on a fixed mesh: Newton stops at a relative update of
#: 1e-10 (quadratic: the state is then exact to round-off, ~1e-13 relative) and roots are
#: located to 1e-11 in lam, so a recomputation on any CPU/BLAS moves a value by < 1e-11;
#: rtol 1e-8 is a 1000x margin and still far below the coarse mesh's discretisation error.
ACCURACY = Accuracy(rtol=1e-8, atol=1e-9, reason="ch3 FE on a fixed mesh: Newton to 1e-10 "
                    "relative update (quadratic), roots to 1e-11 in lam; 1000x margin")


def erratum_eq_3_32(entry: Entry) -> Outcome:
    """(3.32) holds in the FE limit (refuted as an erratum) when the FE stress jump at R_A
    vanishes under refinement at the order of the P2 stress; confirmed otherwise."""
    lamP = float(entry.parameters.get("lamP", 3.0))
    lam = float(entry.parameters.get("lam", 4.0))
    d = interface_balance(lamP, lam, INTERFACE_MESHES)
    holds = d["order"] >= JUMP_ORDER_MIN
    details = {"order": d["order"], "jump_finest": d["jump"][-1], "T1B": d["T1B"][-1],
               "circle_a_inhomogeneity": d["circle_a_inhomogeneity"]}
    return Outcome(value=not holds, status="refuted" if holds else "confirmed",
                   evidence=entry.evidence, details=details)


def fe_event(entry: Entry) -> Outcome:
    """``ch3.fe.*`` event entries: true when the FE agrees with exactly the variant named
    in the entry's ``parameters.variant`` (the consistent membrane balance)."""
    p = entry.parameters
    q = p["quantity"]
    d = event_support(q, float(p["lamP"]), float(p["c"]), MESH_COARSE, TOL_COARSE[q])
    ok = d["supports"] == p["variant"]
    details = {k: d[k] for k in ("fe", "printed", "membrane", "diff_printed",
                                 "diff_membrane")}
    return Outcome(value=bool(ok), details=details, evidence=entry.evidence)


def fe_suppression_prestretch(entry: Entry) -> Outcome:
    """``ch3.fe.suppression_prestretch``: true when the FE suppression pre-stretch agrees
    with exactly the variant named in ``parameters.variant`` on :data:`MESH_COARSE`."""
    p = entry.parameters
    d = suppression_support(float(p["c"]), MESH_COARSE, TOL_SUPPRESSION_COARSE)
    details = {k: d[k] for k in ("fe", "lam_cusp_fe", "printed", "membrane",
                                 "diff_printed", "diff_membrane")}
    return Outcome(value=d["supports"] == p["variant"], details=details,
                   evidence=entry.evidence)


@lru_cache(maxsize=2)
def thickness_data():
    return read_dataset("ch3_fe_thickness")


#: the sequence whose thickest film :func:`thickness_guards` recomputes: the lamP = 3,
#: c = 0 Phibar sequence, the cheapest kind (~2 s CPU for the thickest film)
GUARD_SEQUENCE = THICKNESS_SEQUENCES[0]


def thickness_guards() -> list:
    """The thin-solid model guard of ``debench verify`` (the ``ch3_fe_thickness`` dataset is
    not rebuilt by it: minutes of CPU): the thickest film of :data:`GUARD_SEQUENCE`
    recomputed on SOLID_MESH_COARSE, guarded as ``ch3.guard.thickness.thickest`` and as its
    difference from the stored film (``..._minus_curated``, stored ~0), so that a change of
    the solid model (material, electrode, penalty, solver) fails verify although the
    producers only read stored films."""
    g = GUARD_SEQUENCE
    s = stored_sequence(thickness_data(), g.quantity, g.lamP, g.c, g.lam_centre, g.nz)
    got = solid_value(g.quantity, g.lamP, g.c, s["H"][0], g.lam_centre,
                      dict(SOLID_MESH_COARSE, nz=g.nz))
    tol = ACCURACY.tolerance(got)
    return [Guarded("ch3.guard.thickness.thickest", float(got), tol, ACCURACY.reason),
            Guarded("ch3.guard.thickness.thickest_minus_curated", float(got) - s["values"][0],
                    tol, ACCURACY.reason)]


def fe_thickness(entry: Entry) -> Outcome:
    """``ch3.fe.thickness_*``: true when the thin solid's ``parameters.quantity`` on the
    film sequence stored in the ``ch3_fe_thickness`` dataset (SOLID_MESH_COARSE, nz = 1,
    at ``parameters.c``), extrapolated to H -> 0, meets exactly the variant named in
    ``parameters.variant`` and the sequence converges in H (observed order >=
    THICKNESS_ORDER_MIN). Nothing is solved here: the films, the membrane FE and both
    analytic variants are the stored ones; the evidence tests recompute the films and the
    analytic values."""
    p = entry.parameters
    q, lamP, c = p["quantity"], float(p["lamP"]), float(p["c"])
    lc = float(p.get("lam_centre", math.nan))
    s = stored_sequence(thickness_data(), q, lamP, c, lc)
    d = thickness_limit(q, lamP, c, lc, s["H"], s["values"], s["membrane_fe"],
                        s["mesh_error"], variants=s["variants"])
    details = {k: d[k] for k in ("extrapolated", "extrapolation_error", "mesh_error",
                                 "order", "membrane_fe", "printed", "membrane",
                                 "diff_printed", "diff_membrane")}
    details["films"] = s["H"]
    details["thickest"] = d["values"][0]
    details["diff_thickest"] = d["diff_membrane_fe"][0]
    return Outcome(value=bool(d["supports"] == p["variant"] and d["convergent"]),
                   details=details, evidence=entry.evidence)


__all__ = ["ACCURACY", "GUARD_SEQUENCE", "erratum_eq_3_32", "fe_event",
           "fe_suppression_prestretch", "fe_thickness", "thickness_guards"]
