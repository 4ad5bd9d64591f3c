"""Membrane free energy (3.20) and equations of state (3.14)-(3.16), (3.21)-(3.22), with the
permittivities of Zhao-Suo (3.27) and Jimenez-McMeeking (3.24)-(3.26)."""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest
from debench.models.materials import (
    MEMBRANE_MODELS,
    VACUUM_PERMITTIVITY,
    GentMembrane,
    JimenezMcMeekingPermittivity,
    ZhaoSuoPermittivity,
)
from hypothesis import given
from hypothesis import strategies as st

from verification.strategies import stretches

NAMES = sorted(MEMBRANE_MODELS)
CS_RTOL = 1e-12
"""Closed form vs complex step of (3.20): both exact to rounding (no subtraction)."""
TAYLOR_MIN_RATE = 1.9
"""eps_JM - eps_ZS = O(|lambda - 1|^2) when c = -6 c0/eps0 (first-order Taylor expansion)."""


def _field(model, e):
    """A true field E (V/m) from a normalised one, e = E sqrt(eps/mu)."""
    return e * math.sqrt(model.mu / model.permittivity(1.0, 1.0))


@pytest.mark.parametrize("name", NAMES)
@given(l1=stretches(0.8, 4.0), l2=stretches(0.8, 4.0), e=st.floats(0.0, 1.0))
def test_battery_membrane_closed_form_3_21_equals_derivative_of_3_20(name, l1, l2, e):
    """(3.21), (3.22) and D = eps E equal (3.14)-(3.16) applied to (3.20) (complex step)."""
    m = MEMBRANE_MODELS[name]
    E = _field(m, e)
    closed = m.equations_of_state(l1, l2, E)
    derived = m.equations_of_state_from_energy(l1, l2, E)
    for a, b, ref in zip(closed, derived, (m.mu * l1**2, m.mu * l2**2, abs(closed[2])),
                         strict=True):
        assert abs(a - b) <= CS_RTOL * max(ref, abs(b), 1e-300)


@pytest.mark.parametrize("name", NAMES)
def test_battery_membrane_reference_state_is_stress_free(name):
    """At lambda1 = lambda2 = 1 and E = 0: W = 0 and sigma1 - sigma3 = sigma2 - sigma3 = 0."""
    m = MEMBRANE_MODELS[name]
    assert m.free_energy(1.0, 1.0, 0.0) == 0.0
    assert m.equations_of_state(1.0, 1.0, 0.0) == (0.0, 0.0, 0.0)


@pytest.mark.parametrize("name", NAMES)
def test_battery_membrane_bad_input_raises(name):
    """lambda <= 0, NaN, past the Gent lock, I4 < 0 raise ValueError naming the bound."""
    m = MEMBRANE_MODELS[name]
    with pytest.raises(ValueError, match="lambda1 must be > 0"):
        m.equations_of_state(-1.0, 1.0, 0.0)
    with pytest.raises(ValueError, match="lambda2 must be finite"):
        m.free_energy(1.0, float("nan"), 0.0)
    with pytest.raises(ValueError, match="Gent lock"):
        m.stretching_energy(8.0, 8.0)
    with pytest.raises(ValueError, match="I4"):
        m.free_energy(1.0, 1.0, -1.0)


def test_every_membrane_model_is_covered():
    """Meta-test: every test_battery_membrane_* runs over all MEMBRANE_MODELS."""
    module = sys.modules[__name__]
    fns = [getattr(module, n) for n in dir(module) if n.startswith("test_battery_membrane")]
    assert len(fns) >= 3
    for fn in fns:
        names = {v for m in fn.pytestmark if m.name == "parametrize" for v in m.args[1]}
        assert names == set(NAMES), fn.__name__


def test_zhao_suo_3_27_is_the_linearisation_of_jimenez_mcmeeking_3_26():
    """The thesis calls (3.27) a truncated Taylor expansion of (3.26): with c = -6 c0/eps0
    the difference falls like |lambda - 1|^2 (Taylor remainder rate 2)."""
    jm = JimenezMcMeekingPermittivity(eps0_bar=1.0, c0=0.01)
    zs = jm.zhao_suo_linearisation()
    hs = 1e-2 * 0.5 ** np.arange(5)
    rem = [abs(jm(1 + 0.7 * h, 1 - 0.3 * h) - zs(1 + 0.7 * h, 1 - 0.3 * h)) for h in hs]
    rate = np.polyfit(np.log(hs), np.log(rem), 1)[0]
    assert rate >= TAYLOR_MIN_RATE
    assert zs.c == pytest.approx(-0.06)


def test_jimenez_mcmeeking_components_3_24_3_26_are_isotropic_at_reference():
    """(3.24)-(3.26): eps_i = eps0 at l = 1 and the three components sum to 3 eps0."""
    jm = JimenezMcMeekingPermittivity(eps0_bar=2.0, c0=0.3)
    assert jm.components(1.0, 1.0, 1.0) == (2.0, 2.0, 2.0)
    e = jm.components(1.4, 0.9, 1 / 1.26)
    assert sum(e) == pytest.approx(6.0, rel=1e-15)


@given(l1=stretches(0.8, 3.0), l2=stretches(0.8, 3.0))
def test_permittivity_derivatives_equal_complex_step(l1, l2):
    """The closed-form d eps/d lambda of (3.26)/(3.27) equal complex-step derivatives."""
    for perm in (ZhaoSuoPermittivity(1.0, -0.05), JimenezMcMeekingPermittivity(1.0, 0.004)):
        d1, d2 = perm.derivative(l1, l2)
        h = 1e-30
        assert d1 == pytest.approx(perm(l1 + 1j * h, l2).imag / h, rel=1e-13, abs=1e-15)
        assert d2 == pytest.approx(perm(l1, l2 + 1j * h).imag / h, rel=1e-13, abs=1e-15)


def test_zhao_suo_rejects_negative_permittivity():
    """1 + c (l1 + l2 - 2) must stay > 0 (the bound is named)."""
    with pytest.raises(ValueError, match=r"1 \+ c"):
        ZhaoSuoPermittivity(c=-0.1)(8.0, 8.0)
    with pytest.raises(ValueError, match="eps_bar"):
        ZhaoSuoPermittivity(eps_bar=0.0)


def test_table_3_1_c_values_lie_in_the_stated_range():
    """'the value of c falls in the range from 0 to -0.1' (Sec. 3.3.4, Table 3.1)."""
    table = [-0.0073, -0.0107, -0.0236, -0.0241, -0.0275, -0.0317, -0.053, -0.0777,
             -0.0823, -0.0892]
    assert all(-0.1 <= c <= 0 for c in table)
    assert VACUUM_PERMITTIVITY == 8.85e-12


def test_free_energy_uses_true_field_identity():
    """(3.20): l1^2 l2^2 I4 = E^2 with I4 = E_L^2, E_L = l3 E (p. 31)."""
    m = GentMembrane()
    l1, l2, E = 1.7, 2.1, 3e7
    I4 = (E / (l1 * l2)) ** 2
    eps = m.permittivity(l1, l2)
    assert m.free_energy(l1, l2, I4) == pytest.approx(
        m.stretching_energy(l1, l2) - 0.5 * eps * E**2, rel=1e-14)
