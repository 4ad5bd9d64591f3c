"""Ch. 5 printed material tangents (5.21)-(5.25) (enthalpy form, variables F and E_L) and the
Ogden eigenvalue derivatives (5.28), against central differences of the library stresses.

The library works with (F, D_L); the Ch. 5 tangents hold E_L fixed, so the reference is
``T_L(F, E_L) = dW/dF (F, D_L(F, E_L))`` with ``D_L = eps J C^-1 E_L`` (ideal dielectric
(5.9): E_L = dW/dD_L = J^-1 C D_L / eps) and ``D_L(F, E_L)`` itself, differentiated by
central differences.
"""

from __future__ import annotations

import numpy as np
from debench.models.invariants import printed as pr
from debench.models.invariants.numerical import central_difference_F
from debench.models.materials import NeoHookeanIdealDielectric, OgdenIdealDielectric, cauchy_stress
from hypothesis import given, settings
from hypothesis import strategies as st

from verification.strategies import deformation_gradients, lagrangian_displacements

FD_STEP = 1e-6
FD_RTOL = 1e-6
"""Central differences with h = 1e-6 on unit-scale data: truncation h^2 f''' ~ 1e-11,
rounding eps/h ~ 1e-10, relative to the largest tangent entry."""

MAT = NeoHookeanIdealDielectric(mu=2.0, k=30.0, eps=1.0)


def _TL_and_DL(F, E_L):
    J = np.linalg.det(F)
    D_L = MAT.eps * J * np.linalg.solve(F.T @ F, E_L)
    return MAT.response(F, D_L, second=False).P, D_L


def _mech_iso_P(F):
    """Isochoric part of (5.19): 2 C10 J^-2/3 (F - trC/3 F^-T)."""
    J = np.linalg.det(F)
    return 2 * MAT.C10 * J ** (-2 / 3) * (F - np.trace(F.T @ F) / 3 * np.linalg.inv(F).T)


def _fd_F(fun, F):
    return central_difference_F(fun, F, FD_STEP)


def _close(a, b, rtol=FD_RTOL):
    return np.max(np.abs(a - b)) <= rtol * max(1.0, np.max(np.abs(b)))


states = dict(F=deformation_gradients(0.7, 1.4), E_L=lagrangian_displacements(1.0))


@settings(max_examples=25)
@given(**states)
def test_eq5_22_to_5_25_enthalpy_tangents_agree(F, E_L):
    """(5.22) dT^elec/dF, (5.23) dT^elec/dE_L, (5.24) dD_L/dF, (5.25) dD_L/dE_L as printed
    equal central differences of the library stress and D_L at fixed E_L (or F)."""
    def T_elec(Fx, ELx=E_L):
        return _TL_and_DL(Fx, ELx)[0] - _mech_total(Fx)

    assert _close(pr.tangent_5_22(MAT.eps, F, E_L), _fd_F(T_elec, F))
    dT_dE = np.stack([(T_elec(F, E_L + FD_STEP * e) - T_elec(F, E_L - FD_STEP * e))
                      / (2 * FD_STEP) for e in np.eye(3)], axis=-1)
    assert _close(pr.tangent_5_23(MAT.eps, F, E_L), dT_dE)
    assert _close(pr.tangent_5_24(MAT.eps, F, E_L), _fd_F(lambda Fx: _TL_and_DL(Fx, E_L)[1], F))
    dD_dE = np.stack([(_TL_and_DL(F, E_L + FD_STEP * e)[1] - _TL_and_DL(F, E_L - FD_STEP * e)[1])
                      / (2 * FD_STEP) for e in np.eye(3)], axis=-1)
    assert _close(pr.tangent_5_25(MAT.eps, F, E_L), dD_dE)


def _mech_total(F):
    return MAT.response(F, np.zeros(3), second=False).P


@settings(max_examples=25)
@given(F=deformation_gradients(0.7, 1.4))
def test_eq5_21_printed_tangent_lacks_the_volumetric_term(F):
    """(5.21) as printed equals the derivative of the isochoric part of (5.19) only; the
    derivative of the full mechanical stress (with 2/D1 J (J-1) F^-T) needs the volumetric
    tangent in addition. Printed form differs (the volumetric tangent is O(k) >> C10)."""
    printed = pr.tangent_5_21(MAT.C10, F)
    assert _close(printed, _fd_F(_mech_iso_P, F))
    full = _fd_F(_mech_total, F)
    assert _close(printed + pr.tangent_5_21_volumetric(MAT.D1, F), full)
    assert np.max(np.abs(printed - full)) > 0.1 * np.max(np.abs(full))


@given(lam=st.lists(st.floats(0.7, 1.5), min_size=3, max_size=3))
def test_eq5_28_ogden_eigenvalue_derivatives_agree(lam):
    """(5.28) dtau_i/db_j = (dtau_i/dlambda_j)/(2 lambda_j) of the Ogden Kirchhoff stress,
    checked by central differences of J sigma_ii of the library Ogden model."""
    mat = OgdenIdealDielectric()
    lam = np.array(lam)

    def tau(lv):
        return np.prod(lv) * np.diag(cauchy_stress(mat, np.diag(lv), np.zeros(3)))

    fd = np.zeros((3, 3))
    for j in range(3):
        e = np.zeros(3)
        e[j] = FD_STEP
        fd[:, j] = (tau(lam + e) - tau(lam - e)) / (2 * FD_STEP) / (2 * lam[j])
    printed = pr.dtau_db_5_28(mat.alphas, mat.mus, mat.k, lam)
    assert np.max(np.abs(printed - fd)) <= FD_RTOL * np.max(np.abs(fd))
