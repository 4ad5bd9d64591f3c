"""Bad input never yields a number: each example of the validation issue raises a project
error naming the argument and the bound (DESIGN.md, "Numerical honesty").

Chapter 5 (``debench.models.buckling``) examples are tested with that model.
"""

from __future__ import annotations

import numpy as np
import pytest
from debench.models import validation as v
from debench.models.circular import analysis, circle_a, collocation, shooting
from debench.models.circular.actuator import branch, curves
from debench.models.circular.params import Annulus, CircularActuator, locking_stretch_equibiaxial
from debench.models.errors import ConvergenceError
from debench.models.invariants import invariants
from debench.models.materials import NeoHookeanIdealDielectric
from debench.models.plate import PlateParams
from debench.models.plate.ansatz import critical_stretches, curves_vectorised, determinant

KAPPA = 1 / 120


# ------------------------------------------------------ non-finite solver tolerances
@pytest.mark.parametrize("bad", [np.inf, np.nan, 0.0, -1.0, 1e300])
def test_non_finite_or_meaningless_tolerances_are_rejected(bad):
    """A tolerance must be finite in (0, 1): otherwise a solver stops after one step."""
    an = Annulus(2.0)
    with pytest.raises(ValueError, match="xtol must be"):
        curves_vectorised([1.0], PlateParams(), xtol=bad)
    with pytest.raises(ValueError, match="rtol must be"):
        shooting.q_for_stretch(an, np.array([2.5]), 1.9, rtol=bad)
    with pytest.raises(ValueError, match="tol must be"):
        collocation.solve(an, 2.5, tol=bad)
    with pytest.raises(ValueError, match="xtol must be"):
        analysis.pullin_suppression_prestretch(xtol=bad)


# ------------------------------------------------------------- degenerate settings
@pytest.mark.parametrize("n_scan", [0, 1, 2])
def test_degenerate_scan_size_is_an_error_not_an_empty_root_list(n_scan):
    with pytest.raises(ValueError, match="n_scan must be an integer >= 10"):
        critical_stretches(1.0, PlateParams(), n_scan=n_scan)


@pytest.mark.parametrize("maxiter", [0, -1])
def test_zero_iteration_count_is_an_error_not_an_unbound_local(maxiter):
    with pytest.raises(ValueError, match="maxiter must be an integer >= 1"):
        shooting.q_for_stretch(Annulus(2.0), np.array([2.5]), 1.9, maxiter=maxiter)


# ----------------------------------------------------------------- state checks
def test_inverted_element_has_no_invariants():
    with pytest.raises(ValueError, match="det F must be > 0"):
        invariants(np.diag([1.0, 1.0, -1.0]), np.zeros(3))


def test_overflowing_deformation_is_rejected():
    """1e300 I: det F overflows; the energy would be NaN."""
    with pytest.raises(ValueError, match="det F must be > 0 and finite"):
        NeoHookeanIdealDielectric().energy(1e300 * np.eye(3), np.zeros(3))


def test_phibar_past_the_locking_stretch_names_the_bound():
    lock = locking_stretch_equibiaxial(120.0)
    with pytest.raises(ValueError, match=rf"lam = 12 is past the Gent locking stretch "
                                         rf"{lock:.6g} \(Jm = 120\)"):
        circle_a.phibar_squared(12.0, 0.0, 0.0, KAPPA)


def test_annulus_past_the_locking_stretch_names_the_bound():
    with pytest.raises(ValueError, match=r"lamP = 12 is past the Gent locking stretch 7.84"):
        Annulus(12.0)


@pytest.mark.parametrize("Jm", [-1.0, 0.0, np.nan])
def test_locking_stretch_needs_a_positive_Jm(Jm):
    with pytest.raises(ValueError, match="Jm"):
        locking_stretch_equibiaxial(Jm)


def test_actuator_rejects_non_positive_electrostriction_factor():
    """K = 1 + c(5 lam/2 - 2) of (3.30) must be > 0 at lamP (the permittivity (3.27)
    alone, 1 + c(2 lamP - 2), is still positive here)."""
    lamP, c = 3.0, -0.2
    assert 1 + c * (2 * lamP - 2) > 0
    with pytest.raises(ValueError, match="K = 1 \\+ c\\(5 lam/2 - 2\\)"):
        CircularActuator(Annulus(lamP), c=c)


def test_curve_ends_where_the_electrostriction_factor_vanishes():
    """On a curve the stretch where K reaches 0 bounds the failure: the failure (first
    event, or ``permittivity``) is never beyond it and Phibar is finite up to it."""
    br = branch(Annulus(1.5), n=60)
    c = -0.2
    lam_K = (2 - 1 / c) / 2.5
    assert lam_K < br.lam_end
    cv = curves(br, [c])[0]
    assert cv.failure.lam <= lam_K
    assert np.all(np.isfinite(cv.phibar[cv.lam <= cv.failure.lam]))


def test_public_determinant_raises_where_not_strongly_elliptic():
    p = PlateParams(xi=5.0)
    lam_E = (2 * 5.0 / (2 * 5.0 - 1)) ** 0.25
    with pytest.raises(ValueError, match="strongly elliptic"):
        determinant(1.1 * lam_E, 1.0, p, "E")


def test_dphibar2_dlam_refuses_a_branch_beyond_K_zero():
    br = branch(Annulus(2.0), n=40)
    with pytest.raises(ValueError, match="non-positive"):
        analysis.dphibar2_dlam(br, -0.3)


# ----------------------------------------------------- valid input, clear outcome
def test_loss_of_tension_of_an_unstretched_membrane_is_at_lamP():
    """lamP = 1: T1 = 0 at lamP (rounding leaves ~1e-56) and compressive beyond; the
    Illinois iteration used to stall on that bracket."""
    assert analysis.loss_of_tension_stretch(branch(Annulus(1.0), n=40)) == 1.0


def test_inadmissible_shooting_parameter_is_a_value_error():
    with pytest.raises(ValueError, match="leaves the admissible set"):
        shooting.interface_state(Annulus(2.0), np.array([1e-3]), steps=20)


def test_convergence_error_message_is_built_without_error():
    """A solver that fails reports the measure reached (no IndexError while building)."""
    with pytest.raises(ConvergenceError, match="max \\|dq\\|"):
        shooting.q_for_stretch(Annulus(2.0), np.array([2.5]), 1.99, maxiter=1)


# ------------------------------------------------------------------- the helpers
@pytest.mark.parametrize("bad, exc", [("x", TypeError), (None, TypeError), (True, TypeError),
                                      (np.nan, ValueError), (np.inf, ValueError)])
def test_helpers_reject_wrong_types_and_non_finite_values(bad, exc):
    with pytest.raises(exc, match="mu"):
        v.positive("mu", bad)


def test_integer_helper_rejects_non_integers_and_small_counts():
    with pytest.raises(ValueError, match="n must be an integer >= 2, got 2.5"):
        v.integer_at_least("n", 2.5, 2)
    with pytest.raises(ValueError, match="n must be an integer >= 2, got 1"):
        v.integer_at_least("n", 1, 2)
    assert v.integer_at_least("n", np.int64(3), 2) == 3


def test_deformation_gradient_helper_checks_shape_and_determinant():
    with pytest.raises(ValueError, match=r"F must have shape \(3, 3\)"):
        v.deformation_gradient("F", np.eye(2))
    with pytest.raises(ValueError, match="det F must be > 0"):
        v.deformation_gradient("F", np.zeros((3, 3)))
    F = np.diag([2.0, 0.5, 1.0])
    np.testing.assert_array_equal(v.deformation_gradient("F", F), F)
