"""Chapter 5 constitutive layer: the electric enthalpy, one constitutive truth, flat film.

Claims checked (thesis Zeng 2020, §5.2.2):

* the enthalpy ``Omega(F, E_L) = W_mech - eps/2 J C^-1:(E_L x E_L)`` used by the NGSolve
  model is the partial Legendre transform of the ideal dielectric (5.9)
  ``W_ele = I5/(2 eps J)``: ``Omega = W - E_L.D_L`` at ``E_L = dW/dD_L`` (5.13), and
  ``-dOmega/dE_L = D_L``;
* the NGSolve energies assembled by :mod:`debench.models.buckling.fem` (the library's
  NGSolve path) equal the library's numpy path (:mod:`debench.models.materials`) at
  sample points, including equal principal stretches where the Ogden model (5.26) needs
  care (§5.2.2.2);
* the homogeneous clamped film (the pre-buckled state) satisfies sigma_33 = 0 with the
  in-plane compression equal to the Maxwell stress eps E^2 up to the compressibility
  correction; the principal Kirchhoff stresses it is solved with (the library's stress)
  equal the closed forms written out independently (Eq. 5.27 and its neo-Hookean analogue).
"""

from __future__ import annotations

import numpy as np
import pytest
from debench.models.buckling import analytic
from debench.models.buckling.parameters import MU_REF, NeoHookean, Ogden
from debench.models.materials import NeoHookeanIdealDielectric, OgdenIdealDielectric, cauchy_stress
from debench.models.materials.constants import EPS_R_ASSUMED, VACUUM_PERMITTIVITY

EPS = EPS_R_ASSUMED * VACUUM_PERMITTIVITY
# algebraic identities evaluated in double precision on O(1) data: a few hundred ulp
IDENTITY_RTOL = 1e-10
# symmetric spectral perturbation of the Ogden CF energy: error O(delta^2) = 1e-6 relative
# to mu (delta = 1e-3); 1e-5 leaves room for the O(delta^2) constant (<= 10)
OGDEN_PERTURBATION_RTOL = 1e-5
# central finite difference with step 1e-6 on O(1) functions: truncation ~1e-12, round-off
# ~1e-10
FD_ATOL = 1e-7

PAIRS = [(NeoHookean(), NeoHookeanIdealDielectric(eps=EPS)),
         (Ogden(), OgdenIdealDielectric(eps=EPS))]


def _samples():
    rng = np.random.default_rng(5)
    out = [np.eye(3), np.diag([1.0, 1.0, 0.97]), np.diag([1.2, 1.2, 0.7]),
           np.diag([1.3, 0.9, 0.9])]
    for _ in range(4):
        A = np.eye(3) + 0.25 * rng.standard_normal((3, 3))
        if np.linalg.det(A) < 0.3:
            A = np.eye(3) + 0.1 * rng.standard_normal((3, 3))
        out.append(A)
    return out


@pytest.mark.parametrize("F", _samples())
@pytest.mark.parametrize("pair", PAIRS, ids=["nh", "ogden"])
def test_enthalpy_is_partial_legendre_transform_of_ideal_dielectric_5_9(F, pair):
    """Omega(F,E_L) = W(F,D_L) - E_L.D_L with D_L = eps J C^-1 E_L, and E_L = dW/dD_L
    there (5.13) (W from the constitutive kernel, Omega from debench.models.buckling)."""
    ours, kernel = pair
    E_L = np.array([0.3, -0.2, 1.1]) * 1e7
    J = np.linalg.det(F)
    C = F.T @ F
    D_L = EPS * J * np.linalg.solve(C, E_L)
    legendre = kernel.energy(F, D_L) - E_L @ D_L
    omega = analytic.enthalpy_numpy(F, E_L, ours, EPS)
    assert omega == pytest.approx(legendre, rel=IDENTITY_RTOL, abs=1e-9 * MU_REF)
    assert np.allclose(kernel.response(F, D_L, second=False).E_L, E_L, rtol=IDENTITY_RTOL)
    # -dOmega/dE_L = D_L (central differences, scaled)
    h = 1e-6 * np.linalg.norm(E_L)
    dO = [(analytic.enthalpy_numpy(F, E_L + h * e, ours, EPS)
           - analytic.enthalpy_numpy(F, E_L - h * e, ours, EPS)) / (2 * h) for e in np.eye(3)]
    assert np.allclose(-np.array(dO), D_L, rtol=1e-6, atol=FD_ATOL * np.abs(D_L).max())


@pytest.mark.parametrize("F", _samples())
@pytest.mark.parametrize("pair", PAIRS, ids=["nh", "ogden"])
def test_ngsolve_energy_equals_constitutive_kernel(F, pair):
    """One constitutive truth: the CoefficientFunction energies of debench.models.buckling.energy
    ((5.15), (5.26) + k/2 (J-1)^2, enthalpy) equal debench.models.materials at sample points,
    including F = I and equal in-plane stretches (the flat pre-buckled state)."""
    from debench.models.buckling import energy
    ours, kernel = pair
    E_hat = np.array([0.1, 0.05, 0.3])          # E_L sqrt(eps/mu_ref)
    w_mech, omega = energy.energies_at(F, E_hat, ours)
    w_kernel = kernel.energy(F, np.zeros(3))
    tol = IDENTITY_RTOL if isinstance(ours, NeoHookean) else OGDEN_PERTURBATION_RTOL
    assert np.isfinite(w_mech)
    assert w_mech == pytest.approx(w_kernel, rel=tol, abs=tol * ours.shear_modulus)
    E_L = E_hat * np.sqrt(MU_REF / EPS)
    D_L = EPS * np.linalg.det(F) * np.linalg.solve(F.T @ F, E_L)
    legendre = kernel.energy(F, D_L) - E_L @ D_L
    assert omega * MU_REF == pytest.approx(legendre, rel=tol, abs=tol * ours.shear_modulus)


@pytest.mark.parametrize("mat", [NeoHookean(), Ogden()], ids=["nh", "ogden"])
@pytest.mark.parametrize("v", [0.05, 0.2, 0.5])
def test_homogeneous_clamped_film_is_traction_free_and_compressed_by_maxwell_stress(mat, v):
    """Pre-buckled state F = diag(1,1,s): sigma_33 = 0 and sigma_11 = -eps E^2 up to the
    compressibility correction -- closed-form principal stresses (5.27) versus the kernel's
    Cauchy stress (2.33) with D_L = eps J C^-1 E_L."""
    h = analytic.homogeneous_film(v, mat)
    s = h["s"]
    F = np.diag([1.0, 1.0, s])
    E_L = np.array([0.0, 0.0, v]) * np.sqrt(MU_REF / EPS)
    D_L = EPS * s * np.linalg.solve(F.T @ F, E_L)
    kern = (NeoHookeanIdealDielectric(eps=EPS) if isinstance(mat, NeoHookean)
            else OgdenIdealDielectric(eps=EPS))
    sig = cauchy_stress(kern, F, D_L) / MU_REF
    assert sig[2, 2] == pytest.approx(0.0, abs=1e-9)
    assert sig[0, 0] == pytest.approx(h["sigma11"], rel=1e-8)
    # stationarity of the enthalpy in s: dOmega/ds = 0 (traction-free faces)
    ds = 1e-6

    def omega(t):
        return analytic.enthalpy_numpy(np.diag([1, 1, t]), E_L, mat, EPS) / MU_REF

    assert (omega(s + ds) - omega(s - ds)) / (2 * ds) == pytest.approx(0.0, abs=FD_ATOL)
    # compressibility correction: |sigma_11| < eps E^2 and within k-induced O(mu/k)
    assert -h["sigma11"] < h["e"] ** 2
    assert -h["sigma11"] / h["e"] ** 2 == pytest.approx(1.0, abs=5 * mat.shear_modulus / mat.k)


@pytest.mark.parametrize("stretches", [(1.0, 1.0, 1.0), (1.0, 1.0, 0.8), (1.3, 0.9, 0.85),
                                       (0.7, 1.4, 1.1)])
def test_library_principal_kirchhoff_stresses_equal_the_closed_forms(stretches):
    """``tau_i = lambda_i dW/dlambda_i`` from the library's stress
    (:func:`analytic.kirchhoff_principal`, used for the homogeneous film) equals Eq. (5.27)
    for Ogden and its neo-Hookean analogue, written out independently, to IDENTITY_RTOL of
    the shear modulus."""
    nh, og = NeoHookean(), Ogden()
    closed = {"nh": analytic.kirchhoff_neo_hookean(stretches, mu=nh.mu, k=nh.k),
              "ogden": analytic.kirchhoff_ogden(stretches, alphas=og.alphas, mus=og.mus,
                                                k=og.k)}
    for name, mat in (("nh", nh), ("ogden", og)):
        got = analytic.kirchhoff_principal(stretches, mat)
        assert np.max(np.abs(got - closed[name])) <= IDENTITY_RTOL * mat.bulk_modulus, name


def test_homogeneous_film_tends_to_maxwell_stress_when_incompressible():
    """k -> infinity: sigma_11 -> -eps E^2 exactly and s -> 1 (the thesis' J = 1, §5.3)."""
    mat = NeoHookean(k=1e6 * 156000.0)
    h = analytic.homogeneous_film(0.3, mat)
    assert h["s"] == pytest.approx(1.0, abs=1e-6)
    assert h["sigma11"] == pytest.approx(-h["e"] ** 2, rel=1e-5)


def test_clamped_plate_coefficient_is_first_zero_of_j1_squared():
    """Timoshenko & Gere (1961) §9.1: clamped circular plate N_cr = 14.68 D/a^2, the square
    of the first zero of J1 (3.8317)."""
    assert analytic.J11_SQ == pytest.approx(14.68, abs=0.005)


def test_bad_inputs_raise_naming_the_bound():
    with pytest.raises(ValueError, match="mu must be > 0"):
        NeoHookean(mu=-1.0)
    with pytest.raises(ValueError, match="mu_ref"):
        analytic.homogeneous_film(0.1, NeoHookean(), mu_ref=-1.0)
    with pytest.raises(ValueError, match="v must be finite"):
        analytic.homogeneous_film(float("nan"), NeoHookean())
    from debench.models.buckling.parameters import Plate
    with pytest.raises(ValueError, match="aspect"):
        Plate(aspect=1.0)
