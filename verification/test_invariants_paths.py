"""Three (four) evaluations of the invariant derivatives agree; printed formulas are statused.

Paths: closed form (:mod:`debench.models.invariants.closed_form`, used by the materials),
sympy-generated (:mod:`debench.models.invariants.generated`, from ``tools/derive_invariants.py``),
numerical (complex step + central differences, :mod:`debench.models.invariants.numerical`), and
the thesis formulas as printed (:mod:`debench.models.invariants.printed`), eqs (2.75)-(2.92),
(4.35)-(4.51), (A.1)-(A.35).
"""

from __future__ import annotations

import numpy as np
import pytest
from debench.models.invariants import closed_form, generated, numerical
from debench.models.invariants.printed import PRINTED_DERIVATIVES, SAME_FORMULA
from hypothesis import given, settings
from hypothesis import strategies as st

from verification.strategies import (
    deformation_gradients,
    lagrangian_displacements,
    unit_vectors,
)

KINDS = ("I", "dF", "dD", "dFF", "dFD", "dDD")
EXACT_RTOL = 1e-11
"""Closed form vs sympy: both exact; differences are rounding of O(10) operations on
numbers up to ~|F|^6 (I3 terms), relative to the largest entry."""
NUMERICAL_RTOL = 1e-6
"""Central differences (h = 1e-4) of complex-step gradients: truncation h^2/6 * f''' with
f''' = O(10 |F|^3) for the drawn stretches <= 2, plus rounding eps/h ~ 1e-12."""

PRINTED_ERRATA = {"4.38": "app.erratum.eqA_4_dI4_dF", "A.4": "app.erratum.eqA_4_dI4_dF"}
"""Printed formulas that differ from the derivative (catalogue ids)."""

STATES = dict(F=deformation_gradients(min_stretch=0.6, max_stretch=2.0),
              D=lagrangian_displacements(max_norm=2.0), A=unit_vectors())


def _close(a, b, rtol):
    scale = max(1.0, float(np.max(np.abs(b))))
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b)))) <= rtol * scale


def _as_dict(d):
    return {k: getattr(d, k) for k in KINDS}


@pytest.mark.parametrize("numbering", ["iso", "ti"])
@given(**STATES)
def test_closed_form_equals_sympy_generated(numbering, F, D, A):
    """Closed forms (2.75)-(2.92), (4.35)-(4.51) corrected = sympy derivation, all orders."""
    cf = _as_dict(closed_form.derivatives(F, D, A, numbering=numbering))
    gen = getattr(generated, numbering)(F, D, A)
    for k in KINDS:
        assert _close(cf[k], gen[k], EXACT_RTOL), k


@pytest.mark.parametrize("numbering", ["iso", "ti"])
@settings(max_examples=15)
@given(**STATES)
def test_numerical_derivatives_equal_sympy_generated(numbering, F, D, A):
    """Complex-step / central-difference derivatives = sympy derivation."""
    num = numerical.derivatives(F, D, A, numbering=numbering)
    gen = getattr(generated, numbering)(F, D, A)
    assert _close(num["dF"], gen["dF"], EXACT_RTOL)
    assert _close(num["dD"], gen["dD"], EXACT_RTOL)
    for k in ("dFF", "dFD", "dDD"):
        assert _close(num[k], gen[k], NUMERICAL_RTOL), k


@pytest.fixture(scope="module")
def fresh_derivation():
    """Re-derive with sympy now (not the checked-in text) - a few seconds."""
    from tools.derive_invariants import derive

    return {n: derive(n) for n in ("iso", "ti")}


@pytest.mark.parametrize("numbering", ["iso", "ti"])
@settings(max_examples=10)
@given(**STATES)
def test_generated_module_matches_fresh_sympy_derivation(fresh_derivation, numbering, F, D, A):
    """The checked-in generated module equals a fresh derivation, numerically."""
    fresh = fresh_derivation[numbering](F, D, A)
    gen = getattr(generated, numbering)(F, D, A)
    for k in KINDS:
        assert _close(gen[k], fresh[k], EXACT_RTOL), k


def _printed_cases(errata: bool):
    return [lab for lab in PRINTED_DERIVATIVES if (lab in PRINTED_ERRATA) == errata]


@pytest.mark.parametrize("label", _printed_cases(errata=False))
@settings(max_examples=20)
@given(**STATES)
def test_printed_derivative_formula_agrees(label, F, D, A):
    """The printed component formula (label) = sympy = numerical derivative."""
    numbering, kind, n, func = PRINTED_DERIVATIVES[label]
    printed = func(F, D, A)
    gen = getattr(generated, numbering)(F, D, A)["d" + kind][n - 1]
    assert _close(printed, gen, EXACT_RTOL)
    if kind in ("F", "D"):
        grads = numerical.complex_step_gradients(F, D, A, numbering=numbering)
        num = grads[0 if kind == "F" else 1][n - 1]
        assert _close(printed, num, EXACT_RTOL)


@pytest.mark.parametrize("label", _printed_cases(errata=True))
@given(**STATES)
def test_printed_dI4_dF_of_eq4_38_is_identically_zero_and_differs(label, F, D, A):
    """(4.38) = (A.4) as printed, ``a_a (F_ik a_k - F_im a_m)``, is identically zero (the two
    terms are the same sum with renamed dummy index); the derivative of I4 = A.CA is
    ``2 a_a F_ik a_k`` (closed form, sympy and complex step agree). Printed form differs."""
    numbering, kind, n, func = PRINTED_DERIVATIVES[label]
    printed = func(F, D, A)
    gen = generated.ti(F, D, A)["dF"][3]
    num = numerical.complex_step_gradients(F, D, A, numbering="ti")[0][3]
    corrected = 2 * np.outer(F @ A, A)
    assert np.all(printed == 0.0)
    assert _close(corrected, gen, EXACT_RTOL) and _close(corrected, num, EXACT_RTOL)
    # printed form differs: |dI4/dF| = 2 |F A| >= 2 sigma_min(F) > 0
    assert np.max(np.abs(gen)) > 0.1


def test_every_appendix_formula_repeats_its_chapter_formula():
    """App. A.1 repeats (4.35)-(4.51) and A.2 repeats (2.75)-(2.92): 17 + 18 labels."""
    assert len(SAME_FORMULA) == 35
    for app, chap in SAME_FORMULA.items():
        assert PRINTED_DERIVATIVES[app] == PRINTED_DERIVATIVES[chap]


def test_catalogue_statuses_every_printed_derivative_formula():
    """Each printed label has a catalogue entry (claim, or the erratum for A.4/4.38); Ch. 4
    labels are covered by their App. A.1 twin."""
    from debench.reference.catalogue import load

    entries = {e.id: e for e in load() if e.file == "ch2_appendix.toml"}
    labels = {str(e.parameters.get("label")) for e in entries.values()}
    for lab in PRINTED_DERIVATIVES:
        if lab in PRINTED_ERRATA:
            assert PRINTED_ERRATA[lab] in entries
        elif lab.startswith("4."):
            twin = {v: k for k, v in SAME_FORMULA.items()}[lab]
            assert twin in labels, lab
        else:
            assert lab in labels, lab


def test_frozen_reference_state_derivatives():
    """At F = I, D_L = e3: dI1/dF = 2I, dI3/dF = 2I, dI5/dD = 2 e3 (hand values)."""
    d = closed_form.derivatives(np.eye(3), np.array([0.0, 0.0, 1.0]), numbering="iso")
    np.testing.assert_array_equal(d.dF[0], 2 * np.eye(3))
    np.testing.assert_allclose(d.dF[2], 2 * np.eye(3), rtol=1e-15)
    np.testing.assert_array_equal(d.dD[4], [0.0, 0.0, 2.0])
    np.testing.assert_array_equal(d.I, [3.0, 3.0, 1.0, 1.0, 1.0, 1.0])


@given(lam=st.floats(0.5, 3.0), D2=st.floats(-2.0, 2.0))
def test_equibiaxial_invariants_4_23_to_4_27_and_energy_4_28(lam, D2):
    """With l1 = l3 = lam, l2 = lam^-2, A = e2, D_L = D2 e2 (Sec. 4.3.3): I1 = 2 lam^2 +
    lam^-4, I2 = 2 lam^-2 + lam^4, I4 = lam^-4, I5 = lam^-4 D2^2, I6 = D2^2 (4.23)-(4.27),
    and the energy (4.22) reduces to (4.28)."""
    from debench.models.materials import TransverselyIsotropicNeoHookean

    F = np.diag([lam, lam**-2, lam])
    D = np.array([0.0, D2, 0.0])
    A = np.array([0.0, 1.0, 0.0])
    I = closed_form.invariants(F, D, A, numbering="ti")
    expected = [2 * lam**2 + lam**-4, 2 * lam**-2 + lam**4, 1.0, lam**-4, lam**-4 * D2**2,
                D2**2]
    np.testing.assert_allclose(I, expected, rtol=1e-13, atol=1e-13)
    mat = TransverselyIsotropicNeoHookean(mu=1.3, xi=5.0, alpha=0.4, beta=0.5, eps=0.9)
    W428 = (mat.mu / 2 * (2 * lam**2 + lam**-4 - 3)
            + mat.mu / 2 * mat.xi * (lam**-8 - 2 * lam**-4 + 1)
            + (mat.alpha + mat.beta * lam**-4) * D2**2 / (2 * mat.eps))
    assert mat.energy(F, D) == pytest.approx(W428, rel=1e-12, abs=1e-12)


@given(l1=st.floats(0.5, 3.0), l2=st.floats(0.5, 3.0), l3=st.floats(0.5, 3.0),
       D=lagrangian_displacements(2.0))
def test_principal_invariants_4_12_to_4_17(l1, l2, l3, D):
    """Diagonal F = diag(l1, l2, l3), A = e2: I1 = sum l^2, I2 = sum of pairwise products of
    l^2, I4 = C22 = l2^2, I5 = sum l_k^2 D_k^2 (4.16 with D_L = D2 e2), I6 = D.D."""
    F = np.diag([l1, l2, l3])
    A = np.array([0.0, 1.0, 0.0])
    I = closed_form.invariants(F, D, A, numbering="ti")
    s = np.array([l1, l2, l3]) ** 2
    expected = [s.sum(), s[1] * s[2] + s[2] * s[0] + s[0] * s[1], s.prod(), s[1],
                s @ D**2, D @ D]
    np.testing.assert_allclose(I, expected, rtol=1e-13)
