"""Chapter 3: analytic checks nobody can tune (free membrane limits, circle A, Eq. 3.30).

* Annulus removed (T1^(B) = 0): free equibiaxial membrane; neo-Hookean ideal dielectric
  pull-in at lambda = 2^(1/3), Phibar = 0.6874 (Zhao & Suo 2007).
* Gent: local maximum and minimum of Phibar (Zhao, Hong & Suo 2007) vs sympy roots.
* Circle A stress (3.30) vs the constitutive kernel (debench.models.materials.membrane).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from debench.models.circular import circle_a, collocation, law, params, shooting
from debench.reference import catalogue
from debench.reference.producers import ch3 as producers
from scipy.optimize import brentq, minimize_scalar

from verification._loaders import load_script

#: closed forms evaluated two ways: rounding only
CLOSED_FORM_RTOL = 1e-12
#: golden-section maximum: tol 1e-12 on lambda; Phibar flat at the maximum
MAX_LOCATION_TOL = 1e-7


def _tool():
    return load_script("tools/derive_ch3.py")


def test_free_neo_hookean_membrane_matches_zhao_suo_closed_form():
    """Phibar^2 = lambda^-2 - lambda^-8 for T1B = 0, Jm -> inf, c = 0 (annulus removed)."""
    lam = np.linspace(1.0, 4.0, 50)
    np.testing.assert_allclose(circle_a.free_membrane_phibar(lam, 0.0, 0.0) ** 2,
                               lam**-2 - lam**-8, rtol=CLOSED_FORM_RTOL, atol=1e-15)


def test_free_neo_hookean_pullin_point_is_cube_root_of_two():
    res = minimize_scalar(lambda x: -float(circle_a.free_membrane_phibar(x, 0, 0)),
                          bracket=(1.1, 1.3, 1.6), tol=1e-12)
    assert res.x == pytest.approx(2 ** (1 / 3), abs=MAX_LOCATION_TOL)
    assert -res.fun == pytest.approx(2 ** (-1 / 3) * math.sqrt(0.75), rel=1e-12)


def test_literature_pullin_entries_reproduce():
    """lit.membrane.pullin_stretch_nh / pullin_voltage_nh statuses from the producers."""
    cat = catalogue.by_id()
    for key in ("lit.membrane.pullin_stretch_nh", "lit.membrane.pullin_voltage_nh"):
        assert catalogue.evaluate(cat[key]).status == "reproduced"


def test_gent_free_membrane_extrema_match_sympy_polynomial_roots():
    """Zhao, Hong & Suo (2007): the local max and min of Phibar for Jm = 120, from the model
    (brentq on the complex-step slope) vs the roots of the sympy derivative polynomial."""
    exact = _tool().gent_free_membrane_extrema(120, digits=20)
    cat = catalogue.by_id()
    ids = ("lit.membrane.gent_local_max_stretch_jm120", "lit.membrane.gent_local_max_voltage_jm120",
           "lit.membrane.gent_local_min_stretch_jm120", "lit.membrane.gent_local_min_voltage_jm120")
    got = [producers.free_membrane_gent(cat[i]).value for i in ids]
    want = [float(exact[0][0]), float(exact[0][1]), float(exact[1][0]), float(exact[1][1])]
    np.testing.assert_allclose(got, want, rtol=1e-10)


def test_circle_a_stress_matches_constitutive_kernel():
    """(3.30) (debench.models.circular) vs (3.21) evaluated by
    debench.models.materials.membrane, both the kernel's closed form and its complex-step
    differentiation of (3.20)."""
    from debench.models.materials.membrane import GentMembrane, ZhaoSuoPermittivity
    mu, eps_r = 51e3, 4.7
    for c in (0.0, -0.053):
        m = GentMembrane(mu=mu, Jm=120.0, permittivity=ZhaoSuoPermittivity(
            eps_bar=eps_r * params.EPS0, c=c))
        for lam, phibar in ((1.5, 0.3), (3.0, 0.2), (5.0, 0.25)):
            Phi_over_H = phibar * math.sqrt(mu / (eps_r * params.EPS0))
            E = Phi_over_H * lam**2
            ours = mu * float(circle_a.sigma1_circle_a(lam, phibar, c, 1 / 120))
            k1 = m.equations_of_state(lam, lam, E)[0]
            k2 = m.equations_of_state_from_energy(lam, lam, E)[0]
            assert ours == pytest.approx(k1, rel=1e-10)
            assert ours == pytest.approx(k2, rel=1e-8)


def test_annulus_stresses_match_constitutive_kernel():
    """sigma_i = lambda_i dWs/dlambda_i (3.36)-(3.37): shooting's and collocation's forms vs
    the kernel's Gent stretching energy derivative."""
    from debench.models.materials.membrane import GentMembrane
    m = GentMembrane(mu=1.0, Jm=120.0)
    rng = np.random.default_rng(0)
    l1, l2 = rng.uniform(0.4, 3.0, 20), rng.uniform(1.0, 6.0, 20)
    d1, d2 = m.stretching_energy_derivative(l1, l2)
    s1, s2, *_ = law.gent_stresses(l1, l2, 1 / 120)
    np.testing.assert_allclose(s1, l1 * d1, rtol=1e-12)
    np.testing.assert_allclose(s2, l2 * d2, rtol=1e-12)
    np.testing.assert_allclose(collocation.nominal_radial_stress(l1, l2, 1 / 120), d1,
                               rtol=1e-12)


def test_zero_voltage_at_the_prestretched_state():
    """At lambda = lamP no voltage is needed: Phibar(lamP) = 0 on every branch."""
    for lamP in (1.1, 2.0, 4.0):
        st = shooting.interface_state(params.Annulus(lamP), np.array([lamP]))
        p2 = circle_a.phibar_squared(st.lam, st.T1, -0.053, 1 / 120)
        assert abs(p2[0]) < 1e-12


def test_breakdown_line_closed_form():
    """Phibar_B = sqrt(eps_r eps0/mu) 51e6 lam^1.13/lam^2 (Sec. 3.5.5)."""
    lam = 3.0
    want = math.sqrt(4.7 * 8.85e-12 / 51e3) * 51e6 * lam**1.13 / lam**2
    assert float(circle_a.breakdown_phibar(lam, 4.7, 51e3)) == pytest.approx(want, rel=1e-14)


def test_locking_stretch_solves_gent_limit():
    lam = params.locking_stretch_equibiaxial(120.0)
    assert 2 * lam**2 + lam**-4 - 3 == pytest.approx(120.0, rel=1e-12)
    assert brentq(lambda x: 2 * x**2 + x**-4 - 123, 2, 10) == pytest.approx(lam, rel=1e-12)
