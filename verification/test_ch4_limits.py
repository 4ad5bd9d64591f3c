"""Chapter 4 limits: kH -> inf (Biot), kH -> 0 (Euler / thin-plate asymptotics, Fig. 4.4),
and loss of strong ellipticity of the anisotropic energy (4.22).

Catalogue: lit.plate.biot_equibiaxial, lit.plate.euler_thin_limit,
ch4.ellipticity.ti_curves_well_posed, ch4.fig4_4.*.
"""

from __future__ import annotations

import numpy as np
import pytest
from debench.models.plate import PlateParams, ellipticity_limit_stretch, strongly_elliptic
from debench.models.plate.analysis import (
    biot_equibiaxial_closed_form,
    euler_coefficient_isotropic,
    half_space_limit,
    membrane_stress,
    thin_limit,
)
from debench.models.plate.ansatz import critical_stretches
from debench.models.plate.fem import eigenvalues

#: printed digits of the literature value 0.666
BIOT_PRINTED_TOL = 5e-4
#: brentq xtol 1e-13/1e-14 on smooth functions: agreement to 1e-10
ROOT_TOL = 1e-10
#: at kH = 200 the two parity roots differ from the half-space root by O(exp(-kh))
#: plus the O(1/kh) split of the near-degenerate surface modes; 1e-6 is ample
THICK_TOL = 1e-6
#: thin-plate expansion lam = 1 + C (kH)^2 + O(kH^4): at kH = 0.02..0.1 the relative
#: error of the fitted C is O(kH^2) <~ 1e-2
EULER_C_RTOL = 2e-2


def test_biot_closed_form_is_0_666():
    """r^3 + r^2 + 3r - 1 = 0 with r = lam^3 (equibiaxial): lam = 0.6661..."""
    assert biot_equibiaxial_closed_form() == pytest.approx(0.666, abs=BIOT_PRINTED_TOL)


def test_thick_limit_is_biot_surface_instability():
    """lit.plate.biot_equibiaxial: half-space determinant (method-1 rows with decaying
    modes only), method 1 at kH = 200 and method 2 at kH = 60 all give Biot's value."""
    p = PlateParams(0.0, 0.0)
    lam_b = biot_equibiaxial_closed_form()
    assert half_space_limit(p) == pytest.approx(lam_b, abs=ROOT_TOL)
    roots = critical_stretches(200.0, p, window=(0.5, 1.2)).lam
    assert roots.size == 2
    np.testing.assert_allclose(roots, lam_b, atol=THICK_TOL)
    # method 2: inertia changes between 0.99 lam_b and 1.01 lam_b at kH = 60
    n_lo = np.sum(eigenvalues(0.99 * lam_b, 60.0, p, 64, 4) < 0)
    n_hi = np.sum(eigenvalues(1.01 * lam_b, 60.0, p, 64, 4) < 0)
    assert n_lo == 2 and n_hi == 0


def test_thin_limit_is_euler_buckling_with_plate_theory_slope():
    """lit.plate.euler_thin_limit: lam_cr -> 1 as kH -> 0 (Dhat = 0, xi = 0) and
    (lam_cr - 1)/(kH)^2 -> -1/18 (Kirchhoff plate, D_b = mu h^3/3, tau11 ~ 6 mu (lam-1))."""
    p = PlateParams(0.0, 0.0)
    kHs = np.array([0.02, 0.05, 0.1])
    lam = np.array([critical_stretches(k, p).lam.max() for k in kHs])
    C = (lam - 1) / kHs**2
    np.testing.assert_allclose(C, euler_coefficient_isotropic(), rtol=EULER_C_RTOL)
    assert critical_stretches(1e-3, p).lam.max() == pytest.approx(1.0, abs=1e-6)


@pytest.mark.parametrize("variant", ["derived", "printed"])
@pytest.mark.parametrize("xi", [0.0, 5.0])
@pytest.mark.parametrize("D", [0.0, 1.0, 2.0])
def test_fig4_4_thin_limit_is_root_of_membrane_stress(variant, xi, D):
    """Fig. 4.4: lam_cr(kH -> 0) of the flexural mode = root of a - c (tau11 = 0 for a
    consistent model); method-1 roots at kH = 1e-3 converge to it like (kH)^2. (Where the
    root lies beyond the ellipticity limit of the derived model there is no curve.)"""
    p = PlateParams(xi, D, variant=variant)
    lims = thin_limit(p)
    assert lims.size >= 1
    if lims.max() > ellipticity_limit_stretch(p):
        assert critical_stretches(1e-3, p).lam.size == 0
        return
    lam = critical_stretches(1e-3, p).lam
    flex = [x for x in lam if np.min(np.abs(lims - x)) < 1e-4]
    assert flex, (lam, lims)
    assert np.min(np.abs(lims - flex[0])) < 1e-5


def test_derived_thin_limit_equals_lateral_stress_root_of_eq_4_28():
    """For the derived model a - c is exactly the lateral stress of (4.28); at Dhat = 0
    it vanishes at lam = 1 for every xi (the fibre term (I4 - 1) vanishes there), so the
    TI and isotropic upper curves start at the same lam = 1
    (cf. ch4.fig4_2.upper_curve_higher_ti)."""
    for xi in (0.0, 3.0, 5.0, 10.0):
        p = PlateParams(xi, 0.0, variant="derived")
        assert float(membrane_stress(np.array(1.0), p)) == pytest.approx(0.0, abs=1e-14)
        assert thin_limit(p).max() == pytest.approx(1.0, abs=1e-12)


@pytest.mark.parametrize("xi", [3.0, 5.0, 10.0])
def test_derived_model_loses_ellipticity_at_closed_form_stretch(xi):
    """ch4.ellipticity.ti_curves_well_posed: (4.22) with A = e2 is strongly elliptic
    (plane strain) iff lam^-4 (1 - 2 xi) + 2 xi lam^-8 > 0, i.e. lam < (2xi/(2xi-1))^(1/4);
    above it the FE energy has negative eigenvalues for every thick plate (material
    instability), while the printed coefficients remain elliptic."""
    p = PlateParams(xi, 2.0, variant="derived")
    lamE = ellipticity_limit_stretch(p)
    assert lamE == pytest.approx((2 * xi / (2 * xi - 1)) ** 0.25, rel=1e-15)
    assert bool(strongly_elliptic(np.array(lamE * (1 - 1e-9)), p))
    assert not bool(strongly_elliptic(np.array(lamE * (1 + 1e-9)), p))
    lam_in = np.linspace(0.5, 4.0, 200)
    assert np.all(strongly_elliptic(lam_in, PlateParams(xi, 2.0, variant="printed")))
    # short waves are unstable just above lam_E, with more negative eigenvalues on finer
    # meshes (no length scale: the hallmark of lost ellipticity)
    lam = lamE * 1.05
    negs = [int(np.sum(eigenvalues(lam, 40.0, p, n, 30) < 0)) for n in (16, 32, 64)]
    assert negs[0] >= 1 and negs[2] > negs[0]


def test_printed_ti_upper_curves_lie_outside_the_elliptic_region_of_eq_4_22():
    """The TI (xi = 5) upper curves computed with the printed coefficients start at
    lam = 1.29, 1.34, 1.56 (Dhat = 0, 1, 2), above lam_E = 1.0267 of the energy (4.22)."""
    lamE = ellipticity_limit_stretch(PlateParams(5.0, variant="derived"))
    for D in (0.0, 1.0, 2.0):
        assert thin_limit(PlateParams(5.0, D, variant="printed")).max() > lamE
