"""Chapter 4: the incremental equations re-derived from the energy (4.22) and compared with
the printed (4.38), (4.54)-(4.66), (4.75)-(4.82). Evidence tests of the ch4 errata.

Three independent routes to the incremental energy matrix S (debench.models.plate.coefficients):
the sympy derivation (tools/derive_ch4.py -> generated.py), central finite differences
of a numpy transcription of (4.22) written here, and the constitutive kernel
debench.models.materials (TransverselyIsotropicNeoHookean + push_forward).
"""

from __future__ import annotations

import numpy as np
import pytest
from debench.models.plate import PlateParams, base_state, coefficients, energy_matrix
from debench.models.plate.ansatz import critical_stretches
from debench.models.plate.coefficients import reduced_quartic
from debench.reference.producers import ch4_errata
from hypothesis import given
from hypothesis import strategies as st

#: finite differences of second order with step 1e-4 on O(1) quantities: error
#: ~ h^2 * |W''''| ~ 1e-8, rounding ~ eps/h^2 ~ 1e-8
FD_TOL = 1e-6
#: exact algebra in floating point (a few operations on O(10) numbers)
ALG_TOL = 1e-12
#: the roots are refined by brentq to xtol 1e-13; 1e-10 leaves room for conditioning
ROOT_TOL = 1e-10

LAMS = (0.7, 1.0, 1.3, 2.1)
XIS = (0.0, 3.0, 5.0, 10.0)


# --------------------------------------------------------------------------- helpers
def _W(F, DL, xi, alpha, beta):
    """(4.22) with mu = eps = 1, A = e2, I4 = A.CA, I5 = D_L.C D_L, I6 = D_L.D_L."""
    C = F.T @ F
    return (0.5 * (np.trace(C) - 3) + 0.5 * xi * (C[1, 1] - 1) ** 2
            + 0.5 * (alpha * DL @ DL + beta * DL @ C @ DL))


def _fd_energy_matrix(lam, xi, alpha, beta, D, h=1e-4):
    """S by central differences of W((I + L) F0, D_L0 + F0^-1 Dd) - p det(I + L)."""
    F0 = np.diag([lam, lam**-2, lam])
    DL0 = np.array([0.0, lam**2 * D, 0.0])
    # base pressure from tau22 = 0: p = (F dW/dF^T)_22 by central difference
    e = np.zeros((3, 3))
    e[1, 1] = h
    dW = (_W(F0 + e, DL0, xi, alpha, beta) - _W(F0 - e, DL0, xi, alpha, beta)) / (2 * h)
    p = F0[1, 1] * dW
    comps = [(0, 0), (0, 1), (1, 0), (1, 1)]

    def energy(z):
        L = np.zeros((3, 3))
        for k, (i, j) in enumerate(comps):
            L[i, j] = z[k]
        Dd = np.array([z[4], z[5], 0.0])
        F = (np.eye(3) + L) @ F0
        return _W(F, DL0 + np.linalg.solve(F0, Dd), xi, alpha, beta) - p * np.linalg.det(
            np.eye(3) + L)

    S = np.zeros((6, 6))
    for a in range(6):
        for b in range(6):
            ea, eb = np.eye(6)[a] * h, np.eye(6)[b] * h
            S[a, b] = (energy(ea + eb) - energy(ea - eb) - energy(-ea + eb)
                       + energy(-ea - eb)) / (4 * h * h)
    return S


def _restrict_divfree(S):
    """Only div-free L (L22 = -L11) enter; compare S on that subspace."""
    T = np.zeros((6, 5))
    T[0, 0], T[3, 0] = 1.0, -1.0
    T[1, 1] = T[2, 2] = T[4, 3] = T[5, 4] = 1.0
    return T.T @ S @ T


# --------------------------------------------------------------------------- S
@pytest.mark.parametrize("lam", LAMS)
@pytest.mark.parametrize("xi", XIS)
def test_energy_matrix_equals_finite_difference_of_energy_4_22(lam, xi):
    """S (sympy-generated coefficients) = second differences of (4.22) with the
    Dorfmann-Ogden push-forward and the base pressure (Eqs 4.29-4.31, tau22 = 0)."""
    p = PlateParams(xi=xi, Dhat=1.7, beta=0.5, alpha=0.3, variant="derived")
    S = energy_matrix(np.array(lam), p)
    S_fd = _fd_energy_matrix(lam, xi, 0.3, 0.5, 1.7)
    np.testing.assert_allclose(_restrict_divfree(S), _restrict_divfree(S_fd),
                               atol=FD_TOL * max(1.0, np.abs(S).max()))


def test_energy_matrix_agrees_with_models_materials_kernel():
    """The push-forward moduli of debench.models.materials (written independently) give
    the same plane-strain incremental energy as debench.models.plate (Eqs 2.72-2.73, 4.29-4.31)."""
    import debench.models.materials.library as materials
    import debench.models.materials.response as response
    lam, xi, alpha, beta, D = 1.23, 5.0, 0.4, 0.5, 1.9
    mat = materials.TransverselyIsotropicNeoHookean(mu=1.0, xi=xi, alpha=alpha, beta=beta,
                                                    eps=1.0)
    F = np.diag([lam, lam**-2, lam])
    DL = np.array([0.0, lam**2 * D, 0.0])
    AA, AAA, A = response.moduli(mat, F, DL)
    AA0, AAA0, A0 = response.push_forward(F, AA, AAA, A)
    p = response.pressure_from_traction_free_face(mat, F, DL, np.array([0.0, 1.0, 0.0]))
    comps = [(0, 0), (0, 1), (1, 0), (1, 1)]
    S = np.zeros((6, 6))
    for a, (i, pp) in enumerate(comps):
        for b, (j, q) in enumerate(comps):
            S[a, b] = AA0[i, pp, j, q] + p * (i == q) * (pp == j)
        for r in range(2):
            S[a, 4 + r] = S[4 + r, a] = AAA0[i, pp, r]
    S[4:, 4:] = A0[:2, :2]
    ours = energy_matrix(np.array(lam), PlateParams(xi, D, beta, alpha, "derived"))
    np.testing.assert_allclose(_restrict_divfree(ours), _restrict_divfree(S), atol=1e-10)


def test_generated_code_matches_fresh_sympy_derivation():
    """Re-derive with tools/derive_ch4.py and compare with generated.py numerically."""

    import sympy as sp

    from verification._loaders import load_script

    mod = load_script("tools/derive_ch4.py")
    S, p, tau11 = mod.derive()
    _, _, _, coeff = mod.symbol(S)
    rng = np.random.default_rng(4)
    for _ in range(5):
        lam, xi, al, be, D = rng.uniform([0.5, 0, 0, 0.1, 0], [3, 10, 1, 2, 5])
        subs = {mod.lam: lam, mod.xi: xi, mod.al: al, mod.be: be, mod.Dh: D}
        ours = coefficients(np.array(lam), PlateParams(xi, D, be, al, "derived"))
        fresh = [float(sp.N(coeff[k].subs(subs))) for k in ("a", "b2", "c", "d", "e", "f", "g")]
        np.testing.assert_allclose(np.array(ours, float), fresh, rtol=ALG_TOL * 100)
        pb, t11 = base_state(np.array(lam), PlateParams(xi, D, be, al, "derived"))
        assert float(pb) == pytest.approx(float(sp.N(p.subs(subs))), rel=1e-12)
        assert float(t11) == pytest.approx(float(sp.N(tau11.subs(subs))), rel=1e-12, abs=1e-12)


@given(lam=st.floats(0.5, 3.0), xi=st.floats(0.0, 10.0), D=st.floats(0.0, 5.0))
def test_energy_matrix_is_symmetric_and_electric_block_positive(lam, xi, D):
    """S is symmetric and K0 = diag(alpha lam^-2 + beta, alpha lam^4 + beta) > 0 (4.59-4.60)."""
    S = energy_matrix(np.array(lam), PlateParams(xi, D))
    np.testing.assert_array_equal(S, S.T)
    assert np.all(np.linalg.eigvalsh(S[4:, 4:]) > 0)


# --------------------------------------------------------------------------- errata
# Each erratum's evidence: the check function its producer calls (reference.producers.
# ch4_errata), asserted here on the grid, plus the exact size of the missing term.
@pytest.mark.parametrize("lam", LAMS)
@pytest.mark.parametrize("xi", XIS)
def test_printed_b_and_c_miss_the_I4_minus_1_term(lam, xi):
    """Errata ch4.erratum.eq4_55_b, eq4_56_c: derived - printed = -2 xi lam^-4 in 2b and c;
    a, d, e, f, g (4.54, 4.57-4.60) are right."""
    diff = ch4_errata.b_c_terms(lam, xi)
    expected = np.array([0, -2 * xi * lam**-4, -2 * xi * lam**-4, 0, 0, 0, 0])
    np.testing.assert_allclose(diff, expected, atol=ALG_TOL * 100)
    assert ch4_errata.eq4_55_b().confirmed


@pytest.mark.parametrize("lam", LAMS)
@pytest.mark.parametrize("xi", XIS)
def test_a_minus_c_equals_lateral_stress_of_eq_4_28(lam, xi):
    """Erratum ch4.erratum.eq4_56_c: A0_1212 - A0_2121 = tau11 - tau22 (a universal
    identity of incremental elasticity, here with the field at fixed D_L2) where
    tau11 = (lam/2) dW/dlam of (4.28) at fixed D_L2 and tau22 = 0. The derived c satisfies
    it; the printed c is off by 2 xi lam^-4."""
    derived, printed = ch4_errata.lateral_stress_identity(lam, xi)
    assert derived == pytest.approx(0.0, abs=FD_TOL)
    assert printed == pytest.approx(-2 * xi * lam**-4, abs=FD_TOL)
    assert ch4_errata.eq4_56_c().confirmed


@pytest.mark.parametrize("xi", XIS)
def test_characteristic_polynomial_derived_vs_printed(xi):
    """Erratum ch4.erratum.eq4_63_bicubic: the roots of the printed (4.63) annihilate the
    symbol of the printed coefficients but not that of the derived ones (unless xi = 0);
    the reduced quartic roots annihilate the derived symbol."""
    r = ch4_errata.bicubic_residuals(xi)
    assert r["printed_roots_on_printed_symbol"] < ROOT_TOL * 1e3
    assert r["derived_roots_on_derived_symbol"] < ROOT_TOL * 1e3
    assert r["s1_on_derived_symbol"] < ALG_TOL  # the factor s^2 - 1
    if xi == 0:
        assert r["printed_roots_on_derived_symbol"] < ROOT_TOL * 1e3
    else:
        assert r["printed_roots_on_derived_symbol"] > 1e-3
    assert ch4_errata.eq4_63_bicubic().confirmed


def test_literal_rows_are_beta_one_rows():
    """Erratum ch4.erratum.eq4_75_80_beta: for xi = 0 the literal rows (4.75)-(4.80) give
    exactly the consistent curves with beta = 1, i.e. beta = 0.5 at Dhat sqrt(2)."""
    for D in (1.0, 2.0, 3.0):
        r = ch4_errata.literal_rows_vs_beta(D)
        np.testing.assert_allclose(r["literal"], r["beta_one"], rtol=1e-9)
        np.testing.assert_allclose(r["literal"], r["beta_half_D_sqrt2"], rtol=1e-9)
        assert r["stated"].size != r["literal"].size or not np.allclose(
            r["stated"], r["literal"], rtol=1e-3)
    assert ch4_errata.eq4_75_80_beta().confirmed


@pytest.mark.parametrize("lam", LAMS)
def test_normal_traction_row_coefficient(lam):
    """Erratum ch4.erratum.eq4_76_xi_term: (4.70) needs 2b + c, which from the printed
    (4.55)-(4.56) contains 8 xi lam^-8, while (4.76) prints 6 xi lam^-8."""
    xi = 5.0
    assert ch4_errata.normal_traction_xi_term(lam, xi) == pytest.approx(
        2 * xi * lam**-8, abs=ALG_TOL * 100)
    assert ch4_errata.eq4_76_xi_term().confirmed


@pytest.mark.parametrize("variant", ["derived", "printed"])
@pytest.mark.parametrize("xi", XIS)
def test_s_equal_one_mode_is_electric_for_xi_positive(variant, xi):
    """Erratum ch4.erratum.eq4_81_amplitude: M(1) = diag(a - 2b + c, 0) with
    a - 2b + c = -4 xi lam^-8; (A, B) = (1, 0) solves M(1) v = 0 only for xi = 0."""
    r = ch4_errata.s_one_mode(xi, variant)
    assert r["a_2b_c_plus_4xi_lam^-8"] == pytest.approx(0.0, abs=ALG_TOL * 100)
    assert r["electric_residual"] < ALG_TOL
    if xi == 0:
        assert r["mechanical_residual"] < ALG_TOL
    else:
        assert r["mechanical_residual"] > 1e-3
    assert ch4_errata.eq4_81_amplitude().confirmed


def test_dI4_dF_printed_is_zero_corrected_matches_fd():
    """Erratum ch4.erratum.eq4_38_dI4: as extracted, a_a (F_ik a_k - F_im a_m) is zero;
    dI4/dF_ia = 2 F_ik a_k a_a matches a finite difference of I4 = A.F^T F A."""
    r = ch4_errata.dI4_dF()
    np.testing.assert_allclose(r["corrected"], r["fd"], atol=FD_TOL)
    assert np.abs(r["printed"]).max() == 0.0
    assert np.abs(r["fd"]).max() > 0.1
    assert ch4_errata.eq4_38_dI4().confirmed


def test_errata_checks_fail_when_the_printed_form_is_right():
    """The checks can fail: fed the derived coefficients as if they were printed, the
    b/c check reports nothing wrong (status would be refuted)."""
    from unittest import mock

    with mock.patch.object(ch4_errata, "printed_coefficients",
                           lambda lam, xi, alpha, beta, D: coefficients(
                               lam, PlateParams(xi, D, beta, alpha, "derived"))):
        assert not ch4_errata.eq4_55_b().printed_wrong
        assert not ch4_errata.eq4_56_c().printed_wrong


def test_bicubic_has_no_Dhat_dependence():
    """ch4.eq4_63.independent_of_D: with alpha = 0 the symbol's determinant factorises as
    beta (s^2 - 1)(qc s^4 - qb s^2 + qa) with qa, qb, qc free of Dhat and beta."""
    lam = 1.4
    base = reduced_quartic(np.array(lam), PlateParams(5.0, 0.0, 0.5))
    for D, beta in ((1.0, 0.5), (3.0, 0.5), (2.0, 1.7)):
        q = reduced_quartic(np.array(lam), PlateParams(5.0, D, beta))
        np.testing.assert_allclose(np.array(q, float), np.array(base, float), rtol=1e-13)
        cf = coefficients(np.array(lam), PlateParams(5.0, D, beta))
        for s in (0.3, 0.9, 1.7):
            ref = beta * (s**2 - 1) * (float(q[2]) * s**4 - float(q[1]) * s**2 + float(q[0]))
            assert ch4_errata.symbol_det(s, cf) == pytest.approx(ref, rel=1e-12)


def test_bad_parameters_raise_value_error_naming_the_bound():
    with pytest.raises(ValueError, match="xi must be >= 0"):
        PlateParams(xi=-1.0)
    with pytest.raises(ValueError, match="Dhat must be >= 0"):
        PlateParams(Dhat=-0.1)
    with pytest.raises(ValueError, match="beta must be > 0"):
        PlateParams(beta=0.0)
    with pytest.raises(ValueError, match="variant"):
        PlateParams(variant="nope")
    with pytest.raises(ValueError, match="lam must be finite and > 0"):
        coefficients(np.array([1.0, 0.0]), PlateParams())
    with pytest.raises(ValueError, match="kH must be finite and > 0"):
        critical_stretches(0.0, PlateParams())
    with pytest.raises(ValueError, match="alpha == 0"):
        critical_stretches(1.0, PlateParams(alpha=0.5))
    with pytest.raises(ValueError, match="no energy matrix"):
        energy_matrix(np.array(1.0), PlateParams(variant="literal"))


def test_every_consequence_follows_from_the_root_error_it_names():
    """Errata and claims that name (4.55) as their root cause follow from it: (4.56) misses
    the same term, (4.63) is exact for the printed (4.54)-(4.60), and the TI curves sit
    where (4.22) is not strongly elliptic because of that term; (4.38) is the formula of
    (A.4). Every Chapter 4 entry with another entry as root cause has such a check."""
    from debench.reference import catalogue
    from debench.reference.producers.ch4_errata import ROOT_CAUSE_CHECKS

    named = {e.id for e in catalogue.load() if e.file == "ch4.toml"
             and e.root_cause and e.root_cause != e.id}
    assert named == set(ROOT_CAUSE_CHECKS)
    for key, check in ROOT_CAUSE_CHECKS.items():
        assert check(), key
