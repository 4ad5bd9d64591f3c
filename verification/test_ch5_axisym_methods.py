"""The critical voltage by three stability operators on the axisymmetric model
(``ch5_axisym_methods.nc``, builder :mod:`debench.reference.builders.ch5_axisym_methods`):
the converged values follow from the stored sequences by the stated rule, the operators
are ordered as their physics says, the coarsest solve reproduces through the model guard
that ``debench verify`` runs, and the gap between the coupled critical voltage and the
Mindlin plate is decomposed by the check function the catalogue entry calls."""

from __future__ import annotations

import numpy as np
import pytest
from debench.models.numerics import p_grading_estimate
from debench.reference import catalogue
from debench.reference.datasets import read_dataset
from debench.reference.producers import ch5_methods as prod
from debench.reference.studies import ch5_axisym as study

#: the estimate recomputed from the stored sequence is the same arithmetic on the same
#: float64 numbers
EXACT = 0.0
ENTRY = "ch5.hypothesis.coupling.critical_voltage_above_mindlin_nh"


@pytest.fixture(scope="module")
def ds():
    return read_dataset("ch5_axisym_methods")


def test_curated_data_are_the_full_plan(ds):
    """The curated dataset is the converged plan (three orders at the finest grading: the
    safety factor 1.25), for every operator."""
    plan = study.METHODS[True]
    assert [list(d) for d in plan["discs"]] == [[int(o), int(L)] for o, L in zip(
        ds.order.values, ds.layers.values, strict=True)]
    assert list(ds.case.values) == list(plan["cases"])
    assert float(ds.safety_factor) == 1.25


def test_curated_converged_values_follow_from_the_stored_sequences(ds):
    discs = list(zip(ds.order.values.tolist(), ds.layers.values.tolist(), strict=True))
    got = p_grading_estimate(ds.v_cr.values, discs)
    for var, key in (("v_cr_converged", "value"), ("v_cr_error", "error"),
                     ("v_cr_p_change", "p_change"),
                     ("v_cr_grading_change", "grading_change")):
        assert np.max(np.abs(ds[var].values - getattr(got, key))) <= EXACT, var


def test_operators_are_ordered_and_converged(ds):
    """On every discretisation the coupled operator is the stiffest (the field
    redistributing with the mode stabilises the film) and the frozen-potential one the
    softest; each converged value's error estimate is below 1e-4 relative, an order below
    the smallest effect the operators' ratios measure (initial stress / Mindlin - 1, about
    1.6e-3)."""
    v = ds.v_cr
    assert bool((v.sel(tangent="coupled") > v.sel(tangent="initial_stress")).all())
    assert bool((v.sel(tangent="initial_stress") > v.sel(tangent="frozen_potential")).all())
    assert float((ds.v_cr_error / ds.v_cr_converged).max()) < 1e-4


def test_coupled_operator_agrees_with_the_critical_voltage_study(ds):
    """The coupled operator's converged value is the critical voltage of the independent
    plan of ``ch5_axisym.nc`` (other orders and gradings) within the two error
    estimates."""
    cv = read_dataset("ch5_axisym")
    for case in ds.case.values:
        a = ds.sel(case=case, tangent="coupled")
        b = cv.sel(case=case, n=0)
        assert abs(float(a.v_cr_converged - b.v_cr_converged)) <= float(
            a.v_cr_error + b.v_cr_error), case


def test_the_converged_operators_explain_the_gap(ds):
    """The catalogue's verdict is the check function on the curated data: the 3D purely
    mechanical buckling (initial stress) lies within PLATE_3D_RTOL of Mindlin, and the
    coupling is more than three quarters of the gap; the decomposition closes
    (log(1 + gap) = log(1 + coupling) + log(1 + mechanics), to round-off)."""
    d = prod.axisym_gap_decomposition(ds, "nh_t1")
    closes = np.log1p(d["coupling"]) + np.log1p(d["mechanics_3d_vs_mindlin"])
    assert closes == pytest.approx(np.log1p(d["gap"]), rel=1e-12)   # round-off of 3 ratios
    ok = prod.axisym_coupling_explains_gap(d)
    entry = catalogue.by_id()[ENTRY]
    assert catalogue.evaluate(entry).status == ("explained" if ok else "unexplained")


def test_the_model_guard_recomputes_the_reported_values(ds):
    """The guard that ``debench verify`` runs recomputes the frozen-potential and
    initial-stress critical voltages on the coarsest discretisation of the plan; the
    recomputed coarse values equal the stored ones and the reported values the converged
    ones, within the dataset's regeneration accuracy."""
    guards = {g.key: g for g in prod.axisym_methods_guards()}
    for tangent in ("frozen_potential", "initial_stress"):
        c = ds.sel(case="nh_t1", tangent=tangent)
        key = f"ch5.guard.axisym_methods.nh_t1.{tangent}"
        coarse, rep = guards[f"{key}.v_cr_coarse"], guards[f"{key}.v_cr_reported"]
        assert abs(coarse.value - float(c.v_cr.isel(disc=0))) <= coarse.tolerance
        assert abs(rep.value - float(c.v_cr_converged)) <= rep.tolerance
