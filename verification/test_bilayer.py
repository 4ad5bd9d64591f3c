"""lit_bilayer: the plane-strain dielectric-elastomer bilayer bending under voltage.

The reference (dataset lit_bilayer: debench's NGSolve model, debench.models.bilayer, by p
and geometric grading, orders 4 .. 6) has no closed form. These tests check

* that debench's model at a coarse plan (seconds) agrees with the curated reference within
  the coarse plan's own error estimate plus the reference's;
* that the scikit-fem clean room (verification/cleanroom/bilayer.py: triangles, the
  enthalpy's gradient written out and its Hessian by complex step, nothing from debench)
  agrees with the reference within its own p-step error estimate at a low voltage
  (seconds), and at its submission's resolution over every stored voltage (slow);
* the small-strain limit: at small voltages the tip rotation is quadratic in v (the
  Maxwell stress, the only load, is quadratic in the field);
* the problem page renders with both quantities, the boundary conditions and the consensus.
"""

from __future__ import annotations

import numpy as np
import pytest
from debench.reference import problems
from debench.reference.datasets import read_dataset

from verification.cleanroom import bilayer as cr

PROBLEM = "lit_bilayer"
QUANTITIES = ("tip_deflection", "tip_rotation")
#: Roache's factor for an estimate from two polynomial orders (the clean room's check)
SAFETY_TWO_ORDERS = 3.0


@pytest.fixture(scope="module")
def ds():
    return read_dataset(PROBLEM)


@pytest.mark.fe
def test_coarse_model_agrees_with_the_reference_within_the_coarse_error_estimate(ds):
    """debench.models.bilayer.converged on COARSE_PLAN at v = 0.05 and 0.1: |coarse - ref|
    <= coarse error estimate + the reference's stated error (dataset *_error)."""
    from debench.models import bilayer

    vs = [0.05, 0.1]
    c = bilayer.converged(vs, plan=bilayer.COARSE_PLAN)
    for name in QUANTITIES:
        ref = ds[name].sel(v=vs).values
        ref_err = ds[f"{name}_error"].sel(v=vs).values
        coarse, err = getattr(c, name), getattr(c, f"{name}_error")
        assert np.all(np.abs(coarse - ref) <= err + ref_err), (name, coarse, ref, err)
        # the estimate is not vacuous: the coarse plan is well above the reference's error
        assert np.all(err > 10 * ref_err), (name, err, ref_err)


def test_reference_error_estimates_are_small_and_the_levels_converge(ds):
    """The stored estimate is Roache's 1.25 x the larger of the last p-step and grading step
    of the stored levels (debench.models.numerics.p_grading_estimate), and the p-steps
    shrink with the order (regular p-convergence)."""
    from debench.models.numerics import p_grading_estimate

    plan = list(zip(ds["order"].values.tolist(), ds["grading_levels"].values.tolist(),
                    strict=True))
    for name in QUANTITIES:
        lv = ds[f"{name}_levels"].values
        est = p_grading_estimate(lv, plan, floor=1e-9)
        np.testing.assert_allclose(est.error, ds[f"{name}_error"].values, rtol=1e-12)
        np.testing.assert_array_equal(est.value, ds[name].values)
        orders = {p: i for i, (p, L) in enumerate(plan) if L == max(x for _, x in plan)}
        steps = [np.abs(lv[:, orders[p + 1]] - lv[:, orders[p]]) for p in sorted(orders)[:-1]]
        assert np.all(steps[-1] < steps[0]), (name, steps)
        assert np.all(ds[f"{name}_error"].values < 1e-5 * np.maximum(1, np.abs(ds[name])))


def test_clean_room_agrees_with_the_reference_within_its_p_step(ds):
    """The scikit-fem clean room, P2 and P3 with one geometric layer at v = 0.05: its P3
    value lies within 3 x |P3 - P2| (+ the reference's error) of the reference."""
    vs = [0.05]
    lo = cr.solve(vs, order=2, levels=1)
    hi = cr.solve(vs, order=3, levels=1)
    for name in QUANTITIES:
        ref = ds[name].sel(v=vs).values
        tol = SAFETY_TWO_ORDERS * np.abs(getattr(hi, name) - getattr(lo, name)) \
            + ds[f"{name}_error"].sel(v=vs).values
        assert np.all(np.abs(getattr(hi, name) - ref) <= tol), (name, getattr(hi, name), ref)


def test_small_voltage_response_is_quadratic_in_the_voltage(ds):
    """The Maxwell stress is quadratic in the field: theta(v) = a v^2 (1 + O(v^2)), so
    theta(0.1)/theta(0.05) is 4 up to the geometric nonlinearity (|theta| < 0.04 rad)."""
    th = ds["tip_rotation"].sel(v=[0.05, 0.1]).values
    assert abs(th[1] / th[0] - 4.0) < 0.05, th
    w = ds["tip_deflection"].sel(v=[0.05, 0.1]).values
    assert np.all(w < 0) and abs(w[1] / w[0] - 4.0) < 0.05, w


@pytest.mark.parametrize("kwargs,fragment", [
    ({"order": 0}, "order"), ({"levels": -1}, "levels"), ({"voltages": [0.2, 0.1]}, "increasing"),
    ({"voltages": [-0.1]}, "voltages"), ({"voltages": [float("nan")]}, "voltages"),
    ({"voltages": []}, "non-empty")])
def test_bad_inputs_to_the_model_raise_naming_them(kwargs, fragment):
    from debench.models import bilayer

    args = {"voltages": [0.05], "order": 2, "levels": 0, **kwargs}
    with pytest.raises(ValueError, match=fragment):
        bilayer.solve(args.pop("voltages"), **args)


@pytest.mark.parametrize("kwargs,fragment", [
    ({"length": 0.0}, "length"), ({"passive": 1.0}, "passive"), ({"passive": 0.0}, "passive"),
    ({"bulk_ratio": -1.0}, "bulk_ratio"), ({"nx": 0}, "nx"), ({"ny": 1}, "ny")])
def test_bad_parameters_raise_naming_them(kwargs, fragment):
    from debench.models import bilayer

    with pytest.raises(ValueError, match=fragment):
        bilayer.BilayerParameters(**kwargs)


def test_problem_page_renders_with_quantities_and_boundary_conditions():
    from debench.reference.consensus import problem_page

    page = problem_page(problems.get(PROBLEM))
    for text in ("tip_deflection", "tip_rotation", "sliding clamp", "u_Y(L, 0)",
                 "atan2(-d_X, H + d_Y)", "0.05, 0.1, 0.15, 0.2, 0.25, 0.3"):
        assert text in page, text


@pytest.mark.slow
def test_clean_room_at_its_submission_resolution_agrees_at_every_voltage(ds):
    """The scikit-fem clean room at P4 with two geometric layers (its submission's top
    discretisation) over every stored voltage: within 3 x its change from P3 plus the
    reference's error."""
    vs = ds["v"].values.tolist()
    lo = cr.solve(vs, order=3, levels=2)
    hi = cr.solve(vs, order=4, levels=2)
    for name in QUANTITIES:
        tol = SAFETY_TWO_ORDERS * np.abs(getattr(hi, name) - getattr(lo, name)) \
            + ds[f"{name}_error"].values
        assert np.all(np.abs(getattr(hi, name) - ds[name].values) <= tol), name
