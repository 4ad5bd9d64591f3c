"""The curated axisymmetric critical voltages (``ch5_axisym.nc``, builder
:mod:`debench.reference.builders.ch5_axisym`): the converged values and their error
estimates follow from the stored p- and grading-sequences by the stated rule, the coarsest
solve of the plan reproduces, the catalogue's values lie within the computed error, and the
3D model's error bar is compared with them by the check functions the producers call."""

from __future__ import annotations

import math

import numpy as np
import pytest
from debench.reference import catalogue
from debench.reference.builders import ch5_axisym as builder
from debench.reference.datasets import read_dataset
from debench.reference.producers import ch5 as prod

#: converged() recomputed from the stored sequence is the same arithmetic on the same
#: numbers: exact up to the netCDF round trip (none for float64)
EXACT = 0.0
AXISYM_ENTRIES = ("ch5.derived.axisym_critical_voltage_nh",
                  "ch5.derived.axisym_critical_voltage_n1_nh",
                  "ch5.derived.axisym_critical_voltage_n1_ogden",
                  "ch5.derived.axisym_critical_voltage_ogden")
CROSSCHECK_ENTRIES = ("ch5.crosscheck.axisym_vs_3d_critical_voltage_nh",
                      "ch5.crosscheck.axisym_vs_3d_critical_voltage_ogden")


@pytest.fixture(scope="module")
def ds():
    return read_dataset("ch5_axisym")


def test_converged_value_and_error_follow_the_gci_rule_on_synthetic_sequences():
    """Converged value = top order at the finest grading; error = 1.25 (>= 3 orders) or 3
    (fewer) times the larger of the last p-step change and the finest grading change."""
    v = np.array([[1.0, 0.9], [0.8, 0.75]])            # 2 orders: factor 3
    got = builder.converged(v)
    assert got.value == 0.75
    assert got.p_change == pytest.approx(0.15)
    assert got.grading_change == pytest.approx(0.05)
    assert got.error == pytest.approx(3 * 0.15)
    v3 = np.array([[1.0, 0.9], [0.8, 0.75], [0.7, 0.74]])   # 3 orders: factor 1.25
    got = builder.converged(v3)
    assert got.safety_factor == 1.25
    assert got.error == pytest.approx(1.25 * max(0.01, 0.04))
    with pytest.raises(ValueError, match="need >= 2 orders"):
        builder.converged(np.array([[1.0, 0.9]]))
    # the floor: a sequence that does not change has the floor as its error estimate
    flat = builder.converged(np.full((3, 2), 0.5), floor=2e-7)
    assert flat.error == 2e-7 and flat.p_change == 0.0


def test_curated_converged_values_follow_from_the_stored_sequences(ds):
    """v_cr_converged, v_cr_error, the two changes and the safety factor are the rule of
    :func:`converged` applied to the stored v_cr(order, layers) of every (case, n), with the
    error floor the dataset states (the builder's REGEN_ATOL)."""
    import json

    floor = json.loads(ds.attrs["parameters"])["error_floor"]
    assert floor == builder.REGEN_ATOL
    for case in ds.case.values:
        for n in ds.n.values:
            c = ds.sel(case=case, n=n)
            got = builder.converged(c.v_cr.values, floor)
            for var, key in (("v_cr_converged", "value"), ("v_cr_error", "error"),
                             ("p_step_change", "p_change"),
                             ("grading_change", "grading_change")):
                assert abs(float(c[var]) - getattr(got, key)) <= EXACT, (case, n, var)
    assert float(ds.safety_factor) == builder.safety_factor(ds.sizes["order"])


def test_axisymmetric_mode_is_critical_and_the_sequences_decrease(ds):
    """n = 1 bifurcates above n = 0 at every discretisation (the flat film buckles
    axisymmetrically first), and raising the order lowers every critical voltage at the
    finest grading (the FE model is stiffer than the limit; with the regularised Ogden
    evaluation the Ogden p = 5 -> 6 step of n = 0 rose by 4.9e-8)."""
    v = ds.v_cr
    assert bool((v.sel(n=1) > v.sel(n=0)).all())
    finest = v.isel(layers=-1)
    assert np.all(np.diff(finest.values, axis=-1) < 0)


def test_guard_solve_reproduces_the_curated_value(ds):
    """The n = 0 critical voltage of both films on the guard discretisation (seconds),
    recomputed by the model guard that ``debench verify`` runs, equals the stored one
    within the dataset's regeneration accuracy, and the reported value the guard
    recomputes from it is the curated converged value."""
    guards = {g.key: g for g in prod.axisym_coarse_guards()}
    for case in ("nh_t1", "ogden_t1"):
        key = f"ch5.guard.axisym.{case}"
        diff = guards[f"{key}.v_cr_coarse_minus_curated"]
        assert abs(diff.value) <= diff.tolerance, (case, diff.value, diff.tolerance)
        assert guards[f"{key}.ndof_coarse"].value == int(ds.ndof_guard.sel(case=case))
        rep = guards[f"{key}.v_cr_reported"]
        assert abs(rep.value - float(ds.v_cr_converged.sel(case=case, n=0))) <= rep.tolerance


def test_a_one_percent_ogden_modulus_change_moves_the_reported_critical_voltage(
        ds, monkeypatch):
    """The reported (converged) Ogden critical voltage that verify recomputes moves with the
    model: Ogden moduli 1 % higher raise it by about 0.5 % (v_cr ~ sqrt(mu) at fixed eps),
    far outside the guard's tolerance, while the neo-Hookean one stays."""
    import dataclasses

    from debench.reference.producers import ch5 as tasks

    original = tasks.case_material

    def stiffer(case):
        m = original(case)
        return dataclasses.replace(m, mus=tuple(1.01 * x for x in m.mus)) if "ogden" in case \
            else m

    monkeypatch.setattr(tasks, "case_material", stiffer)
    guards = {g.key: g for g in prod.axisym_coarse_guards()}
    og = guards["ch5.guard.axisym.ogden_t1.v_cr_reported"]
    v0 = float(ds.v_cr_converged.sel(case="ogden_t1", n=0))
    # sqrt(1.01) - 1 = 0.00499 at fixed k; the bulk term shifts it by less than 1e-4
    assert og.value / v0 - 1 == pytest.approx(0.005, abs=2e-4)
    assert abs(og.value - v0) > 100 * og.tolerance
    nh = guards["ch5.guard.axisym.nh_t1.v_cr_reported"]
    assert abs(nh.value - float(ds.v_cr_converged.sel(case="nh_t1", n=0))) <= nh.tolerance


def test_axisym_catalogue_values_lie_within_the_computed_error(ds):
    """Each catalogued axisymmetric critical voltage lies within the dataset's error
    estimate of the converged value (the check the producer calls), and the catalogue's
    stated tolerance is not tighter than that estimate."""
    entries = catalogue.by_id()
    for eid in AXISYM_ENTRIES:
        e = entries[eid]
        case = f"{e.parameters['material']}_t1"
        got = prod.axisym_value_check(ds, case, int(e.parameters["n"]), e.value)
        assert got["within"], (eid, got["v"], e.value, got["error"])
        assert e.tolerance >= got["error"], (eid, e.tolerance, got["error"])
        assert catalogue.evaluate(e).status == e.expected_status == "reproduced"


def test_3d_error_bar_contains_the_axisymmetric_critical_voltage(ds):
    """The 3D model's reference critical voltage (in-plane mesh limit plus through-thickness
    correction) contains the axisymmetric converged value within its error bar for both
    materials (the check the cross-check entries' producer calls), and the dataset's stored
    comparison says the same."""
    crit = read_dataset("ch5_critical_voltage")
    for eid in CROSSCHECK_ENTRIES:
        e = catalogue.by_id()[eid]
        case = f"{e.parameters['material']}_t1"
        got = prod.axisym_vs_3d(ds, crit, case)
        assert got["contains"], (case, got["bias"], got["v_3d_error"])
        assert int(ds.reference_bar_contains_axisym.sel(case=case)) == int(got["contains"])
        assert float(ds.bias_3d_reference.sel(case=case)) == pytest.approx(got["bias"],
                                                                           abs=1e-15)
        assert catalogue.evaluate(e).status == e.expected_status


def test_problem_page_quotes_the_3d_values_of_the_curated_dataset():
    """The reference problem ch5_critical_voltage quotes the 3D model's n = 0 values and
    error bars in its summary: they are those of ch5_critical_voltage.nc, to the printed
    digits."""
    from debench.reference import problems

    summary = problems.get("ch5_critical_voltage").summary
    crit = read_dataset("ch5_critical_voltage")
    for case in ("nh_t1", "ogden_t1"):
        c = crit.sel(case=case)
        quoted = f"{float(c.v_cr_reference):.5f} +- {float(c.v_cr_reference_error):.5f}"
        assert quoted in summary, (case, quoted)


@pytest.mark.parametrize("material", ["nh", "ogden"])
def test_the_3d_bias_is_the_single_term_fit_assumption(material):
    """The two-term fits of the stored 3D levels bracket the converged axisymmetric value
    (second exponents 1.6 .. 3), their spread lies inside the 3D error bar, and the
    regular second term (q = 2) removes most of the single-term centre's bias."""
    entry = catalogue.by_id()[f"ch5.crosscheck.axisym_vs_3d_critical_voltage_{material}"]
    d = catalogue.evaluate(entry).details
    lo, hi = d["two_term_bias_range"]
    assert lo < 0 < hi, d
    assert max(-lo, hi) < d["v_3d_error"], d
    q2 = d["two_term_bias"][d["two_term_second_exponents"].index(2.0)]
    assert abs(q2) < abs(d["bias"]) / 5, d


def _crossing_3d(model, index: int, v_guess: float) -> float:
    """The voltage at which the ``index``-th lowest eigenvalue (0-based) of the 3D model's
    condensed tangent of the flat film crosses zero: a secant in v^2 from 0.97 and 1.03
    v_guess, after a voltage ramp to 0.9 v_guess (the flat state far above the n = 0
    critical voltage, reached continuously), stopped at a step below 1e-7."""

    def lam(v):
        model.set_voltage(v)
        model.newton()
        return float(np.sort(model.lowest_eigenvalues(nev=4, certify=False)[0])[index])

    for v in np.linspace(0.3, 0.9, 4) * v_guess:
        model.set_voltage(v)
        model.newton()
    xs = [(0.97 * v_guess) ** 2, (1.03 * v_guess) ** 2]
    ls = [lam(math.sqrt(x)) for x in xs]
    for _ in range(12):
        xs.append(xs[-1] - ls[-1] * (xs[-1] - xs[-2]) / (ls[-1] - ls[-2]))
        ls.append(lam(math.sqrt(xs[-1])))
        if abs(math.sqrt(xs[-1]) - math.sqrt(xs[-2])) < 1e-7:
            return math.sqrt(xs[-1])
    raise AssertionError(f"no crossing of eigenvalue {index}: {xs}, {ls}")


@pytest.mark.slow
def test_the_3d_model_gives_the_wavenumber_one_to_zero_ratio_of_the_axisymmetric_one(ds):
    """Two independent models of the neo-Hookean film: the ratio of its n = 1 and n = 0
    critical voltages by the 3D prism model (h = 1.4 t0, 2 layers of quadratic prisms: the
    second and third eigenvalues, the n = 1 pair, cross zero at the n = 1 voltage) agrees
    with the converged axisymmetric ratio. Measured 3D ratios 1.37985 / 1.33355 / 1.32793 at
    h = 3 / 2 / 1.4 t0 (approaching from above) against the axisymmetric 1.32566; the
    ratio cancels most of the 3D model's through-thickness error (its v_cr alone is 2.9 %
    high here). An n = 1 space without the sideways translation of the axis gave 1.3522."""
    from debench.models.buckling.fem import MembraneModel
    from debench.models.buckling.parameters import Discretisation, NeoHookean, Plate
    from debench.models.buckling.solver import critical_voltage

    plate, disc = Plate(thickness=1e-3, aspect=10.0), Discretisation(h_rel=1.4, layers=2, order=2)
    v0 = critical_voltage(plate, NeoHookean(), disc).v
    model = MembraneModel(plate, NeoHookean(), disc, with_imperfection=False)
    v1 = [_crossing_3d(model, k, 0.292) for k in (1, 2)]
    ratio_3d = float(np.mean(v1)) / v0
    conv = ds.v_cr_converged.sel(case="nh_t1")
    ratio_axisym = float(conv.sel(n=1) / conv.sel(n=0))
    # 0.005: twice the 3D mesh's measured 0.0022 at h = 1.4 t0 (its change from h = 2 t0 is
    # 0.0056), a fifth of the 0.027 to the translation-free space's ratio
    assert abs(ratio_3d - ratio_axisym) < 0.005, (ratio_3d, ratio_axisym)
    # the n = 1 pair: degenerate in the continuum, split by the unstructured mesh only
    assert abs(v1[1] - v1[0]) < 2e-3 * v1[0]
