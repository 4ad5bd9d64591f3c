"""The axisymmetric path study of the clamped film (pull-in and wrinkling,
:mod:`debench.reference.builders.ch5_axisym_path`): its convergence estimate and decision
rule on synthetic sequences, and the curated dataset against its own definitions and the
3D model."""

from __future__ import annotations

import numpy as np
import pytest
from debench.reference.builders import ch5_axisym_path as path

FULL = path.PLANS[True]["discs"]


def test_converged_takes_the_top_discretisation_and_both_changes():
    """Exponential p-convergence 1e-3 * 10^-p plus a grading term: the value is the top
    (order 4, 6 layers) entry, the changes are exactly the two differences, and the safety
    factor is 1.25 (three orders at 6 layers)."""
    vals = {(2, 6): 1.0 + 1e-5, (3, 6): 1.0 + 1e-6, (4, 6): 1.0 + 1e-7, (4, 4): 1.0 + 3e-7}
    x = np.array([vals[d] for d in FULL])
    got = path.converged(x, FULL)
    assert got["value"] == x[FULL.index((4, 6))]
    # the differences of numbers near 1: exact to a few ulps of 1
    assert got["p_change"] == pytest.approx(9e-7, abs=1e-15)
    assert got["grading_change"] == pytest.approx(2e-7, abs=1e-15)
    assert path.safety_factor(FULL) == 1.25
    assert got["error"] == pytest.approx(1.25 * 9e-7, abs=1e-15)


def test_converged_with_two_orders_uses_the_larger_safety_factor():
    discs = ((2, 3), (3, 3), (3, 2))
    assert path.safety_factor(discs) == 3.0
    got = path.converged(np.array([2.0, 1.0, 1.5]), discs)
    assert got["value"] == 1.0 and got["error"] == 3.0 * 1.0


def test_converged_is_nan_where_a_discretisation_has_no_value():
    """A crossing found on some discretisations only has no error estimate."""
    x = np.array([[1.0, 1.1, 1.2, 1.3], [np.nan, 1.0, 1.0, 1.0]])
    got = path.converged(x, FULL)
    assert np.isfinite(got["error"][0])
    assert np.isfinite(got["error"][1])      # the NaN is at order 2, not used
    x[1, 1] = np.nan
    assert np.isnan(path.converged(x, FULL)["error"][1])


def test_converged_refuses_a_plan_without_a_lower_order():
    with pytest.raises(ValueError, match="no lower order"):
        path.converged(np.ones(2), ((3, 4), (3, 6)))


@pytest.mark.parametrize("w_cross, err, before, expected", [
    ([np.nan, 7.0, 7.5], [np.nan, 0.01, 0.01], True, (1, 1)),    # wrinkling, clear margin
    ([np.nan, 10.0, np.nan], [np.nan, 0.2, np.nan], True, (-1, 1)),  # margin below errors
    ([np.nan, np.nan, 11.0], [np.nan, np.nan, 0.01], False, (0, 2)),  # only past the max
    ([np.nan, np.nan, np.nan], [np.nan] * 3, True, (-1, 2)),   # a coarse one crosses
])
def test_decide(w_cross, err, before, expected):
    """Wrinkling when the first crossing before the maximum (w_max = 10.1 +- 0.05) clears
    the summed error estimates; pull-in when none crosses before it on any discretisation
    and the eigenvalues at the maximum are positive beyond their errors (the smallest,
    index 2, is the one the decision rests on); undecided otherwise."""
    lam_max, lam_err = np.array([0.3, 0.2, 0.1]), np.array([1e-3] * 3)
    got = path.decide(10.1, 0.05, np.array(w_cross), np.array(err), lam_max, lam_err, before)
    assert (got["first"], got["n_index"]) == expected


def test_decide_pull_in_is_undecided_when_an_eigenvalue_at_the_maximum_is_within_error():
    got = path.decide(5.0, 0.01, np.full(3, np.nan), np.full(3, np.nan),
                      np.array([1e-4, 0.2, 0.3]), np.array([2e-4, 1e-3, 1e-3]), False)
    assert got["first"] == -1 and got["n_index"] == 0
