"""Chapter 5: the stress singularity at the clamped edge of the film and the mesh-convergence
order of the critical voltage it implies (§5.2.3, Table 5.1; the extrapolation
``v = v_inf + C h^p`` of the Chapter 5 mesh studies).

Claims checked: the closed-form clamped-free determinant (Williams 1952, derived by
``tools/derive_ch5_singularity.py``) and a Chebyshev collocation of the Navier equations
give the same Williams spectrum; the incompressible and 180 degree limits have the
closed-form solutions the determinant reduces to; Table 5.1 (nu = 0.49) gives
``s = 0.59990`` and the expected order ``p = 2 s = 1.1998`` for quadratic prisms.

Literature anchor: no printed clamped-free 90 degree exponent was found with the search
tool (queries: "clamped free wedge stress singularity exponent Williams 1952",
"Sinclair stress singularities clamped-free", "clamped-free 90 degree corner singularity
exponent plane strain table", "elastic quarter plane bonded to rigid base free edge",
and the digits 0.71117, 0.2888, 0.59461); the ones found (Sinclair 2004, Appl. Mech. Rev.
57, 385, Part II) showed abstracts only. No literature test is therefore included.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from debench.models.buckling import singularity as sg
from debench.models.buckling.parameters import K_TABLE, MU_REF

METHODS_ATOL = 1e-7
"""Closed form vs collocation. brentq/Newton locate zeros of D to ~1e-15; the collocation's
second-derivative matrix amplifies round-off by ~n^4 (n = 48 on the finer grid:
48^4 eps ~ 1e-9); 1e-7 is 100x that estimate (measured differences <= 1e-10 at 90
degrees). A transcription error in D or a wrong boundary row moves the exponents by O(0.1)."""
RESIDUAL_TOL = 1e-12
"""Residual of a hand-reduced equation at the computed zero: the zero is located to
~1e-15 and the reduced equations have slopes of order 1-3, so residuals are ~1e-14;
1e-12 leaves a factor 100."""
COMPLEX_ZERO_TOL = 1e-8
"""180 degrees: Newton's method stops at relative steps of 1e-14, except at the double
zero of nu = 0.5 (kappa = 1) where it converges linearly and stops ~1e-9 away; 1e-8 covers
that and still fails for any wrong exponent."""
TABLE_NU_RTOL = 1e-7
"""Table 5.1 gives k to 9 digits (7748003.92 Pa): nu = 0.49 to ~5e-9."""

NUS = [0.0, 0.3, 0.49, 0.5]


@pytest.mark.parametrize("nu", [*NUS, -0.5])
def test_closed_form_and_collocation_give_the_same_williams_spectrum(nu):
    """Every eigenvalue with 0 < Re s <= 2.5 at 90 degrees: zeros of the Williams
    determinant D(s) (brentq, Newton, argument-principle count) and the collocated
    Navier equations agree one to one (nu = -0.5 has a complex leading pair)."""
    a = sg.williams_eigenvalues(nu, s_max=2.5)
    b = sg.williams_eigenvalues_collocation(nu, s_max=2.5)
    assert a.size == b.size >= 1, (a, b)
    np.testing.assert_allclose(a, b, rtol=0, atol=METHODS_ATOL)


@pytest.mark.parametrize("nu", NUS)
def test_edge_exponent_is_the_same_by_both_methods(nu):
    """``edge_singularity_exponent`` from the closed form and from the collocation."""
    s1 = sg.edge_singularity_exponent(nu)
    s2 = sg.edge_singularity_exponent(nu, method="collocation")
    assert 0 < s1 <= 1
    assert s1 == pytest.approx(s2, abs=METHODS_ATOL)


def test_incompressible_exponent_solves_cos_half_pi_s_equals_s():
    """At nu = 0.5 (kappa = 1) and 90 degrees D = 4 (cos^2(pi s/2) - s^2): the exponent is
    the root of cos(pi s/2) = s in (0, 1) (0.5946), and the stress singularity is the
    strongest of the range nu in [0, 0.5]."""
    s = sg.edge_singularity_exponent(0.5)
    assert abs(math.cos(math.pi * s / 2) - s) < RESIDUAL_TOL
    assert 0.5 < s < 0.6
    others = [sg.edge_singularity_exponent(nu) for nu in (0.0, 0.1, 0.2, 0.3, 0.4, 0.49)]
    assert all(x > y for x, y in zip(others, [*others[1:], s], strict=True)), others


def test_zero_poisson_ratio_has_a_polynomial_root_at_one_that_is_skipped():
    """At nu = 0 (kappa = 3) D(1) = (kappa + 1)(kappa - 3) = 0: s = 1 is the linear field
    u = (0, y) (clamped face y = 0; on the free face x = 0, sigma_xx = lambda_L div u = 0
    when lambda_L = 0), smooth. The exponent in (0, 1] is 1 (no singularity) and the
    expected order comes from the next zero, 1.352, not from the polynomial one."""
    roots = sg.williams_eigenvalues(0.0, s_max=2.5)
    assert abs(roots[0] - 1.0) < sg.INTEGER_TOL
    assert sg.edge_singularity_exponent(0.0) == 1.0
    assert sg.expected_eigenvalue_order(0.0, order=2) == pytest.approx(2 * roots[1].real,
                                                                      abs=1e-15)
    assert 1.3 < roots[1].real < 1.4


@pytest.mark.parametrize("nu", [0.0, 0.3, 0.49, 0.5])
def test_half_plane_clamped_on_one_side_has_the_oscillating_half_exponent(nu):
    """180 degrees (a crack along a rigid bond): D = kappa^2 + 1 + 2 kappa cos(2 pi s), zero
    at s = 1/2 + i log(kappa)/(2 pi) (the rigid-substrate limit of the interface crack,
    England 1965, J. Appl. Mech. 32, 400): the complex exponent is found by both methods
    and its real part, 1/2, is what the exponent reports."""
    kappa = sg.kolosov_constant(nu)
    expected = complex(0.5, math.log(kappa) / (2 * math.pi))
    a = sg.williams_eigenvalues(nu, math.pi)
    b = sg.williams_eigenvalues_collocation(nu, math.pi)
    assert a.size == b.size == 1, (a, b)
    assert abs(a[0] - expected) < COMPLEX_ZERO_TOL
    assert abs(b[0] - expected) < COMPLEX_ZERO_TOL
    assert sg.edge_singularity_exponent(nu, math.pi) == pytest.approx(0.5,
                                                                       abs=COMPLEX_ZERO_TOL)


def test_auxetic_materials_have_a_complex_pair_above_one_and_no_stress_singularity():
    """nu = -0.5 at 90 degrees: the leading exponents are a complex pair with Re s > 1
    (bounded, oscillating stress); capped at 1 by default, reported with cap = 2."""
    roots = sg.williams_eigenvalues(-0.5, s_max=2.0)
    assert roots[0].imag > 0.1 and 1.0 < roots[0].real < 1.2
    assert sg.edge_singularity_exponent(-0.5) == 1.0
    assert sg.edge_singularity_exponent(-0.5, cap=2.0) == pytest.approx(roots[0].real)


def test_table_5_1_expected_order_is_twice_the_exponent():
    """Table 5.1 (mu = 156000 Pa, k = 7748003.92 Pa) is nu = 0.49; with quadratic prisms
    the critical voltage converges like h^(2 s) = h^1.1998, not h^4; cubic elements do not
    change that (the singularity caps the rate)."""
    nu = sg.poisson_ratio(MU_REF, K_TABLE)
    assert nu == pytest.approx(0.49, rel=TABLE_NU_RTOL)
    s = sg.edge_singularity_exponent(nu)
    p2 = sg.expected_eigenvalue_order(nu, order=2)
    assert p2 == pytest.approx(2 * s, abs=1e-15)
    assert 1.19 < p2 < 1.21
    assert sg.expected_eigenvalue_order(nu, order=3) == pytest.approx(p2, abs=1e-15)
    assert sg.expected_eigenvalue_order(0.49, order=1) == pytest.approx(p2, abs=1e-6)


def test_characteristic_function_vanishes_at_the_exponent_and_not_at_zero():
    """D(s) at the returned exponent is zero (to the root tolerance) and D(0) =
    (kappa + 1)^2 > 0: s = 0 (rigid translation) is not a root of the reduced determinant."""
    kappa = sg.kolosov_constant(0.3)
    s = sg.edge_singularity_exponent(0.3)
    assert abs(sg.characteristic_function(s, kappa)) < RESIDUAL_TOL
    assert sg.characteristic_function(0.0, kappa) == pytest.approx((kappa + 1) ** 2)


@pytest.mark.parametrize(("call", "match"), [
    (lambda: sg.edge_singularity_exponent(0.6), r"nu must lie in \(-1, 0.5\]"),
    (lambda: sg.edge_singularity_exponent(-1.0), r"nu must lie in \(-1, 0.5\]"),
    (lambda: sg.edge_singularity_exponent(float("nan")), "nu must be finite"),
    (lambda: sg.edge_singularity_exponent(0.3, 0.0), r"angle must lie in \(0, 6.28319\]"),
    (lambda: sg.edge_singularity_exponent(0.3, 7.0), r"angle must lie in \(0, 6.28319\]"),
    (lambda: sg.edge_singularity_exponent(0.3, cap=0.0), r"cap must lie in \(0, 8\]"),
    (lambda: sg.edge_singularity_exponent(0.3, method="fem"), "method must be one of"),
    (lambda: sg.expected_eigenvalue_order(0.3, order=0), "order must be an integer >= 1"),
    (lambda: sg.expected_eigenvalue_order(0.3, order=5), "order must be <= 4"),
    (lambda: sg.williams_eigenvalues(0.3, s_max=9.0), r"s_max must lie in \(0, 8\]"),
    (lambda: sg.williams_eigenvalues_collocation(0.3, n=4), "n must be an integer >= 8"),
    (lambda: sg.characteristic_function(0.5, 0.5), r"kappa must lie in \[1, 7\)"),
    (lambda: sg.poisson_ratio(-1.0, 1.0), "shear_modulus must be > 0"),
])
def test_bad_input_raises_value_error_naming_the_bound(call, match):
    """Arguments outside their ranges raise ValueError naming the argument and bound."""
    with pytest.raises(ValueError, match=match):
        call()
