"""Printed closed forms vs the chain rule: (2.42), (2.43), (2.69)/(4.33), (2.71)-(2.74),
(5.18)-(5.20), (5.27).

The chain rule (:mod:`debench.models.materials.kernel`) is itself checked by Taylor tests in
``test_materials_battery.py`` and by NGSolve in ``test_materials_ngsolve.py``.
"""

from __future__ import annotations

import numpy as np
import pytest
from debench.models.invariants import derivatives, invariants
from debench.models.invariants import printed as pr
from debench.models.materials import (
    MATERIALS,
    GentIdealDielectric,
    IdealDielectric,
    NeoHookeanIdealDielectric,
    OgdenIdealDielectric,
    TransverselyIsotropicNeoHookean,
    cauchy_stress,
    invariant_chain_rule,
    push_forward,
)
from hypothesis import given
from hypothesis import strategies as st

from verification.strategies import (
    deformation_gradients,
    isochoric_deformation_gradients,
    lagrangian_displacements,
)

EXACT_RTOL = 1e-11
"""Two exact expressions of the same quantity: rounding only (relative to the largest
entry; stresses up to ~10 with the drawn unit-scale coefficients)."""
FD_RTOL = 1e-6
"""Central difference, step 1e-5 on unit-scale data: truncation ~1e-10, rounding ~1e-11."""

coefficients = st.lists(st.floats(-2.0, 2.0), min_size=6, max_size=6).map(np.array)


def _sigma_chain(Wn, F, D_L, p):
    """Cauchy stress of the linear-in-invariants energy sum W_n I_n, J = 1 (2.33)."""
    r = invariant_chain_rule(0.0, Wn, np.zeros((6, 6)), F, D_L, numbering="iso", second=False)
    return r.P @ F.T - p * np.eye(3), np.linalg.solve(F.T, r.E_L)


def _close(a, b, rtol=EXACT_RTOL):
    return np.max(np.abs(a - b)) <= rtol * max(1.0, np.max(np.abs(b)))


@given(W=coefficients, F=isochoric_deformation_gradients(), D=lagrangian_displacements(1.0),
       p=st.floats(-2.0, 2.0))
def test_eq2_42_printed_form_differs_from_chain_rule(W, F, D, p):
    """(2.42) as printed lacks ``2 W5 D (x) D`` and has ``D (x) BD - BD (x) D`` for
    ``D (x) BD + BD (x) D``; the corrected form equals the chain rule (2.33) with
    (2.75)-(2.79). Printed form differs by exactly ``-2 W5 D(x)D - 4 W6 BD(x)D``."""
    W = W.copy()
    W[2] = 0.0  # incompressible: W does not depend on I3
    sig, _ = _sigma_chain(W, F, D, p)
    assert _close(pr.cauchy_2_42_corrected(W, F, D, p), sig)
    Dv = F @ D
    BD = F @ F.T @ Dv
    printed = pr.cauchy_2_42(W, F, D, p)
    assert _close(printed - sig, -2 * W[4] * np.outer(Dv, Dv) - 4 * W[5] * np.outer(BD, Dv))


def test_eq2_42_printed_stress_is_not_symmetric():
    """Frozen example: with W6 = 1 the printed (2.42) gives a non-symmetric Cauchy stress
    (its W6 term is antisymmetric), impossible for a total stress; printed form differs."""
    W = np.array([0.5, 0.0, 0.0, 0.0, 0.0, 1.0])
    F = np.diag([1.5, 1 / 1.5, 1.0])
    D = np.array([1.0, 1.0, 0.0])
    printed = pr.cauchy_2_42(W, F, D, 0.0)
    assert np.max(np.abs(printed - printed.T)) > 0.5
    sig, _ = _sigma_chain(W, F, D, 0.0)
    assert np.max(np.abs(sig - sig.T)) <= EXACT_RTOL


@given(W=coefficients, F=isochoric_deformation_gradients(), D=lagrangian_displacements(1.0))
def test_eq2_43_electric_field_agrees_with_chain_rule(W, F, D):
    """(2.43) ``E = 2 (W4 B^-1 D + W5 D + W6 B D)`` = F^-T dW/dD_L (2.34)."""
    _, E = _sigma_chain(W, F, D, 0.0)
    assert _close(pr.electric_2_43(W, F, D), E)


ND = NeoHookeanIdealDielectric(mu=2.0, k=30.0, eps=1.0)  # unit-scale, same formulas


@given(F=deformation_gradients(0.7, 1.4), D=lagrangian_displacements(1.0))
def test_eq5_18_and_5_19_agree_with_chain_rule(F, D):
    """(5.18) S and (5.19) T_L of the neo-Hookean ideal dielectric = F^-1 dW/dF, dW/dF."""
    P = ND.response(F, D, second=False).P
    assert _close(pr.piola_5_19(ND.C10, ND.D1, ND.eps, F, D), P)
    assert _close(pr.pk2_5_18(ND.C10, ND.D1, ND.eps, F, D), np.linalg.solve(F, P))


@given(F=deformation_gradients(0.7, 1.4), D=lagrangian_displacements(1.0))
def test_eq5_20_printed_form_differs_corrected_agrees(F, D):
    """(5.20) as printed subtracts the scalars ``tr(B_dis)/3`` and ``D.D/(2 eps)`` from a
    tensor (identity missing); with ``I`` restored it equals J^-1 P F^T (5.12).
    Printed form differs by ``(2 C10/(3J) tr B_dis + D.D/(2 eps)) (I - ones)``."""
    sig = cauchy_stress(ND, F, D)
    assert _close(pr.cauchy_5_20_corrected(ND.C10, ND.D1, ND.eps, F, D), sig)
    J = np.linalg.det(F)
    Dv = F @ D / J
    s = 2 * ND.C10 / (3 * J) * np.trace(J ** (-2 / 3) * F @ F.T) + Dv @ Dv / (2 * ND.eps)
    printed = pr.cauchy_5_20(ND.C10, ND.D1, ND.eps, F, D)
    assert _close(printed - sig, s * (np.eye(3) - np.ones((3, 3))))


def test_eq5_20_printed_form_is_not_zero_in_the_reference_state():
    """Frozen: at F = I, D_L = 0 the printed (5.20) gives off-diagonal -2 C10 (not 0)."""
    printed = pr.cauchy_5_20(ND.C10, ND.D1, ND.eps, np.eye(3), np.zeros(3))
    assert printed[0, 1] == pytest.approx(-2 * ND.C10)


@given(l=st.lists(st.floats(0.7, 1.5), min_size=3, max_size=3))
def test_eq5_27_kirchhoff_stress_is_consistent_with_5_26_convention(l):
    """(5.27) ``tau_i = sum 2 mu_p/alpha_p J^{-a/3} (l_i^a - sum l^a/3) + k J (J - 1)`` is the
    Kirchhoff stress J sigma of (5.26) with 2 mu_p/alpha_p^2 (our spectral chain rule)."""
    mat = OgdenIdealDielectric()
    lam = np.array(l)
    J = np.prod(lam)
    tau = J * np.diag(cauchy_stress(mat, np.diag(lam), np.zeros(3)))
    tau_527 = np.zeros(3)
    for a, m in zip(mat.alphas, mat.mus, strict=True):
        tau_527 += 2 * m / a * J ** (-a / 3) * (lam**a - np.sum(lam**a) / 3)
    tau_527 += mat.k * J * (J - 1)
    assert np.max(np.abs(tau - tau_527)) <= EXACT_RTOL * max(1.0, np.max(np.abs(tau_527))) * 10


def _truncated_AAA(mat, F, D, m_from, n_from):
    """(2.69)/(4.33) as printed: sums over m, n >= m_from and n >= n_from only."""
    Aa = np.asarray(mat.A, dtype=float) if mat.numbering == "ti" else None
    d = derivatives(F, D, Aa, numbering=mat.numbering)
    _, Wn, Wmn = mat.invariant_derivatives(invariants(F, D, Aa, numbering=mat.numbering))
    ms = slice(m_from - 1, 6)
    out = np.einsum("mn,mia,nb->iab", Wmn[ms, ms], d.dF[ms], d.dD[ms])
    return out + np.einsum("n,niab->iab", Wn[n_from - 1:], d.dFD[n_from - 1:])


@given(F=isochoric_deformation_gradients(), D=lagrangian_displacements(1.0))
def test_eq2_69_and_4_33_truncated_sums_are_exact_for_thesis_incompressible_energies(F, D):
    """(2.69) (m, n from 4) and (4.33) (m, n from 5) drop W_mn couplings between mechanical
    and electrical invariants; for Gent + ideal dielectric and (4.22) those vanish."""
    for mat, m0 in ((GentIdealDielectric(mu=1.0, eps=1.0), 4),
                    (TransverselyIsotropicNeoHookean(), 5)):
        full = mat.response(F, D).AAA
        assert _close(_truncated_AAA(mat, F, D, m0, m0), full)


def test_eq2_69_truncated_sum_misses_the_J_coupling_of_the_ideal_dielectric_5_9():
    """For the compressible ideal dielectric (5.9), W = I5/(2 eps sqrt(I3)) has W_35 != 0;
    the (2.69) sum from m = 4 misses it at J != 1 (printed form incomplete in general)."""
    mat = IdealDielectric(eps=1.0)
    F = np.diag([1.2, 1.1, 0.9])
    D = np.array([0.3, -0.2, 0.5])
    full = mat.response(F, D).AAA
    trunc = _truncated_AAA(mat, F, D, 4, 4)
    assert np.max(np.abs(full - trunc)) > 0.05 * np.max(np.abs(full))


@pytest.mark.parametrize("name", sorted(MATERIALS))
@given(data=st.data())
def test_push_forward_moduli_2_72_2_73_give_the_spatial_increments(name, data):
    """(2.72)-(2.73): Tdot0 = AA0 L + AAA0 DdotL0 and EdotL0 = AAA0^T L + A0 DdotL0 with
    Tdot0 = J^-1 F Tdot, DdotL0 = J^-1 F DdotL, EdotL0 = F^-T EdotL (2.54)-(2.56)."""
    mat = MATERIALS[name]
    F = data.draw(deformation_gradients(0.8, 1.3, isochoric=mat.incompressible))
    sD = np.sqrt(mat.eps * (mat.shear_modulus or 1e5))
    D = data.draw(lagrangian_displacements(1.0)) * sD
    L = np.array(data.draw(st.lists(st.floats(-1, 1), min_size=9, max_size=9))).reshape(3, 3)
    DL0 = data.draw(lagrangian_displacements(1.0)) * sD
    r = mat.response(F, D)
    J = np.linalg.det(F)
    Fdot = L @ F
    DLdot = J * np.linalg.solve(F, DL0)
    Tdot = (np.einsum("iajb,jb->ai", r.AA, Fdot) + np.einsum("iab,b->ai", r.AAA, DLdot))
    ELdot = np.einsum("iab,ia->b", r.AAA, Fdot) + r.A @ DLdot
    AA0, AAA0, A0 = push_forward(F, r.AA, r.AAA, r.A)
    Tdot0 = np.einsum("ipjq,jq->pi", AA0, L) + np.einsum("ipq,q->pi", AAA0, DL0)
    EL0 = np.einsum("ipq,ip->q", AAA0, L) + A0 @ DL0
    assert _close(Tdot0, F @ Tdot / J, 1e-10)
    assert np.max(np.abs(EL0 - np.linalg.solve(F.T, ELdot))) <= 1e-10 * max(
        np.max(np.abs(ELdot)), 1e-300) + 1e-300


def test_eq2_73_left_side_is_the_pushed_forward_field_not_E_L():
    """(2.73) prints ``Edot_L`` on the left; the right side AAA0^T L + A0 DdotL0 equals
    ``Edot_L0 = F^-T Edot_L`` (2.54), which differs from Edot_L unless F is orthogonal.
    Printed form differs (frozen example)."""
    mat = MATERIALS["ti_neo_hookean_dielectric"]
    F = np.diag([1.5, 1 / 1.5**2, 1.5])
    D = np.array([0.0, 0.7, 0.0])
    L = np.zeros((3, 3))
    DL0 = np.array([0.0, 1.0, 0.0])
    r = mat.response(F, D)
    _, AAA0, A0 = push_forward(F, r.AA, r.AAA, r.A)
    rhs = np.einsum("ipq,ip->q", AAA0, L) + A0 @ DL0
    ELdot = r.A @ np.linalg.solve(F, DL0)
    assert np.allclose(rhs, np.linalg.solve(F.T, ELdot), rtol=1e-12)
    assert not np.allclose(rhs, ELdot, rtol=0.1)


@given(F=isochoric_deformation_gradients(0.8, 1.3), D=lagrangian_displacements(1.0),
       L=st.lists(st.floats(-1, 1), min_size=9, max_size=9),
       DL0=lagrangian_displacements(1.0), p=st.floats(-2, 2), pdot=st.floats(-2, 2))
def test_eq2_71_and_2_74_incompressible_increments_equal_derivative_of_T(F, D, L, DL0, p, pdot):
    """(2.71) Tdot = AA Fdot + AAA DdotL + p F^-1 Fdot F^-1 - pdot F^-1 and (2.74)
    Tdot0 = AA0 L + AAA0 DdotL0 + p L - pdot I equal the t-derivative of
    T = dW/dF^T - p F^-1 along F(t) = (I + t L) F, D_L + t F^-1 DdotL0, p + t pdot."""
    mat = TransverselyIsotropicNeoHookean()
    L = np.array(L).reshape(3, 3)
    DLdot = np.linalg.solve(F, DL0)

    def T(t):
        Ft = (np.eye(3) + t * L) @ F
        return (mat.response(Ft, D + t * DLdot, second=False).P.T
                - (p + t * pdot) * np.linalg.inv(Ft))

    h = 1e-5
    Tdot_fd = (T(h) - T(-h)) / (2 * h)
    r = mat.response(F, D)
    Fdot = L @ F
    Fi = np.linalg.inv(F)
    Tdot = (np.einsum("iajb,jb->ai", r.AA, Fdot) + np.einsum("iab,b->ai", r.AAA, DLdot)
            + p * Fi @ Fdot @ Fi - pdot * Fi)
    assert _close(Tdot, Tdot_fd, FD_RTOL)
    AA0, AAA0, _ = push_forward(F, r.AA, r.AAA, r.A)
    Tdot0 = (np.einsum("ipjq,jq->pi", AA0, L) + np.einsum("ipq,q->pi", AAA0, DL0)
             + p * L - pdot * np.eye(3))
    assert _close(Tdot0, F @ Tdot_fd, FD_RTOL)


@given(F=isochoric_deformation_gradients(), D=lagrangian_displacements(1.0),
       dF=st.lists(st.floats(-1, 1), min_size=9, max_size=9),
       dD=st.lists(st.floats(-1, 1), min_size=3, max_size=3))
def test_ti_model_with_alpha_term_stress_is_the_energy_derivative(F, D, dF, dD):
    """The thesis uses alpha = 0; with alpha != 0 the I6 = D.D term of (4.20)/(4.22) must
    also differentiate correctly: central differences of W equal P:dF + E_L.dD."""
    mat = TransverselyIsotropicNeoHookean(alpha=0.7, beta=0.5)
    dF = np.array(dF).reshape(3, 3)
    dD = np.array(dD)
    r = mat.response(F, D)
    h = 1e-5
    fd = (mat.energy(F + h * dF, D + h * dD) - mat.energy(F - h * dF, D - h * dD)) / (2 * h)
    assert fd == pytest.approx(np.sum(r.P * dF) + r.E_L @ dD, rel=FD_RTOL, abs=FD_RTOL)
