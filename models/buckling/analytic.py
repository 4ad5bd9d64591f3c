"""Closed-form references for the Chapter 5 model (numpy only, no ngsolve).

* The principal Kirchhoff stresses of any library elastomer (from the library's stress,
  :func:`kirchhoff_principal`) and, written out independently of the library, those of
  (5.15) and (5.26) (Eq. 5.27 and its neo-Hookean analogue, :func:`kirchhoff_neo_hookean`,
  :func:`kirchhoff_ogden`): the closed-form check of the library and of the
  finite-element model.  The energies themselves come from the library
  (:mod:`debench.models.materials`).
* The ideal dielectric (5.9) ``W_ele = D_L.C D_L/(2 eps J)`` and its partial Legendre
  transform ``Omega = W_mech - eps/2 J C^-1:(E_L x E_L)`` (the library's expressions,
  :mod:`debench.models.materials.energies`, evaluated by numpy).
* The homogeneous pre-buckled state of the clamped film: in-plane stretches 1, thickness
  stretch ``s`` from the traction-free faces (sigma_33 = 0); in-plane total Cauchy stress
  ``sigma_11 = tau_1/J - eps E^2/2`` which tends to ``-eps E^2`` (the Maxwell stress) as
  k -> infinity.
* Plate theory: clamped circular plate under uniform in-plane compression N,
  ``N_K = j_{1,1}^2 D / a^2`` (Timoshenko & Gere 1961, §9.1: 14.68), and the Mindlin
  (thick-plate) correction ``N_M = N_K / (1 + N_K/(kappa G h))`` (exact relation for the
  axisymmetric clamped circular plate, Wang, Reddy & Lee 2000, *Shear deformable beams and
  plates*, Ch. 9), kappa = 5/6.
* Membrane limit of pull-in: a stress-free (zero-tension) equibiaxially stretched
  incompressible neo-Hookean membrane, ``v^2 = lam^-2 - lam^-8``, maximal at
  ``lam = 4^(1/6)``, ``v = 0.687``.
"""

from __future__ import annotations

import math

import numpy as np
from debench.models import validation as val
from debench.models.buckling.parameters import MU_REF
from debench.models.errors import ConvergenceError
from debench.models.materials import energies as E
from debench.models.materials.protocol import IdealDielectricElastomer
from debench.models.numerics.roots import bracketed_root
from scipy.special import jn_zeros

J11_SQ = float(jn_zeros(1, 1)[0] ** 2)   # 14.6820, clamped circular plate coefficient
KIRCHHOFF_N1_RATIO = float(jn_zeros(2, 1)[0] / jn_zeros(1, 1)[0])
"""1.34030: ratio of the wavenumber-1 and wavenumber-0 critical voltages of a thin clamped
circular plate under equibiaxial compression (Kirchhoff; the critical loads j_{n+1,1}^2 D / a^2
and the voltage ~ sqrt(load)); transverse shear lowers it by O((t0/a)^2)."""
KAPPA_MINDLIN = 5.0 / 6.0
S_MIN = 0.3          # smallest thickness stretch of the flat film searched (70 % thinning)
V_PLATE_MAX = 1.5    # largest normalised voltage searched for the plate-theory estimate


def _check_F(F):
    J = float(np.linalg.det(F))
    if not J > 0:
        raise ValueError(f"det F must be > 0, got {J}")
    return J


def mechanical_energy_numpy(F: np.ndarray, mat: IdealDielectricElastomer) -> float:
    """W_mech(F) [Pa] of (5.15) or (5.26) + k/2 (J-1)^2: the library energy at D_L = 0."""
    _check_F(F)
    return float(mat.energy(np.asarray(F, dtype=float), np.zeros(3)))


def _principal(stretches):
    lam = np.asarray(stretches, dtype=float)
    if lam.shape != (3,) or np.any(lam <= 0):
        raise ValueError(f"stretches must be three numbers > 0, got {lam}")
    J = float(np.prod(lam))
    return lam, J, lam * J ** (-1 / 3)


def kirchhoff_principal(stretches, mat: IdealDielectricElastomer) -> np.ndarray:
    """Principal Kirchhoff stresses ``tau_i = lambda_i dW/dlambda_i`` of the material's
    mechanical energy at ``F = diag(stretches)``: the diagonal of ``P F^T`` with the
    library's stress ``P = dW/dF`` at ``D_L = 0``."""
    lam, _, _ = _principal(stretches)
    return mat.response(np.diag(lam), np.zeros(3), second=False).P.diagonal() * lam


def kirchhoff_neo_hookean(stretches, *, mu: float, k: float) -> np.ndarray:
    """The neo-Hookean analogue of (5.27): ``mu (lb_i^2 - sum lb^2/3) + k J (J - 1)``
    (written out independently of the library)."""
    _, J, lb = _principal(stretches)
    return np.full(3, k * J * (J - 1)) + mu * (lb**2 - np.sum(lb**2) / 3)


def kirchhoff_ogden(stretches, *, alphas, mus, k: float) -> np.ndarray:
    """Eq. (5.27): ``sum_p 2 mu_p/alpha_p (lb_i^alpha_p - sum lb^alpha_p/3) + k J (J - 1)``
    (written out independently of the library)."""
    _, J, lb = _principal(stretches)
    tau = np.full(3, k * J * (J - 1))
    for a, m in zip(alphas, mus, strict=True):
        tau = tau + 2 * m / a * (lb**a - np.sum(lb**a) / 3)
    return tau


def enthalpy_numpy(F, EL, mat, eps) -> float:
    """Omega(F, E_L) = W_mech - eps/2 J C^-1 : (E_L x E_L), the Legendre transform of (5.9)."""
    _check_F(F)
    F = np.asarray(F, dtype=float)
    return mechanical_energy_numpy(F, mat) + float(
        E.ideal_dielectric_enthalpy(F, np.asarray(EL, dtype=float), eps=eps, xp=E.NUMPY))


# --------------------------------------------------------------------------- flat film
def homogeneous_film(v: float, mat: IdealDielectricElastomer, mu_ref: float = MU_REF) -> dict:
    """Clamped homogeneous film at normalised voltage ``v = Phi/t0 sqrt(eps/mu_ref)``.

    F = diag(1, 1, s); the thickness stretch ``s`` solves sigma_33 = 0:
    ``tau_3(1,1,s)/s + (eps/2) E^2 = 0`` with true field ``E = Phi/(s t0)``.
    Returns s, the scaled true field e = v/s and the total in-plane Cauchy stress / mu_ref.
    """
    if not (v >= 0 and math.isfinite(v)):
        raise ValueError(f"v must be finite and >= 0, got {v}")
    mu_ref = val.positive("mu_ref", mu_ref)

    def g(s):
        return kirchhoff_principal([1, 1, s], mat)[2] / s / mu_ref + 0.5 * (v / s) ** 2

    if v > 0 and not g(S_MIN) < 0:
        raise ValueError(f"v = {v:.6g} is past the thinning limit of the clamped film "
                         f"(no traction-free thickness stretch above {S_MIN})")
    s = (bracketed_root(g, S_MIN, 1.0 + 1e-12, xtol=1e-15, rtol=1e-15,
                        what="homogeneous_film: thickness stretch").root if v > 0 else 1.0)
    e = v / s
    tau = kirchhoff_principal([1, 1, s], mat)
    sig11 = tau[0] / s / mu_ref - 0.5 * e**2
    return {"s": s, "e": e, "sigma11": sig11, "maxwell": -e**2}


# --------------------------------------------------------------------------- plates
def plate_constants(mat: IdealDielectricElastomer):
    """Small-strain E, nu, G of the material (G = initial shear modulus, k the bulk
    modulus)."""
    G, k = mat.shear_modulus, mat.bulk_modulus
    E = 9 * k * G / (3 * k + G)
    nu = (3 * k - 2 * G) / (2 * (3 * k + G))
    return E, nu, G


def clamped_plate_critical_stress(mat, aspect: float, *, mindlin: bool = True) -> float:
    """Critical uniform in-plane compressive stress [Pa] of the clamped circular plate.

    Kirchhoff: ``sigma_K = j11^2 D/(a^2 h)``, ``D = E h^3 / (12 (1 - nu^2))``,
    i.e. ``sigma_K = j11^2 E / (12 (1 - nu^2) aspect^2)``; Mindlin correction
    ``sigma_M = sigma_K / (1 + sigma_K / (kappa G))``.
    """
    if aspect <= 0:
        raise ValueError(f"aspect must be > 0, got {aspect}")
    E, nu, G = plate_constants(mat)
    sk = J11_SQ * E / (12 * (1 - nu**2) * aspect**2)
    return sk / (1 + sk / (KAPPA_MINDLIN * G)) if mindlin else sk


def critical_voltage_plate(mat, aspect: float, *, mindlin: bool = True,
                           mu_ref: float = MU_REF) -> float:
    """Normalised voltage at which the homogeneous film's in-plane compression reaches
    the clamped-plate critical stress (plate theory estimate of the FE eigen-analysis)."""
    mu_ref = val.positive("mu_ref", mu_ref)
    target = -clamped_plate_critical_stress(mat, aspect, mindlin=mindlin) / mu_ref

    def gap(v):
        try:
            return homogeneous_film(v, mat, mu_ref)["sigma11"] - target
        except ValueError:          # past the thinning limit: the film is crushed, counted
            return target - 1.0     # as compressed beyond the critical stress (finite)

    if not gap(1e-6) > 0:
        raise ValueError(f"the plate is unstable at zero voltage (critical in-plane stress "
                         f"{target:.3g} mu_ref >= 0)")
    hi = V_PLATE_MAX
    if not gap(hi) < 0:
        raise ConvergenceError(
            f"critical_voltage_plate: the flat film's compression does not reach the plate's "
            f"critical stress {-target:.3g} mu_ref for v up to {hi} (material "
            f"{type(mat).__name__} with shear modulus {mat.shear_modulus:.6g} Pa, k = "
            f"{mat.bulk_modulus:.6g} Pa: a bulk modulus this close to the shear modulus thins "
            "the film instead of compressing it in-plane)")
    return bracketed_root(gap, 1e-6, hi, xtol=1e-14, what="critical_voltage_plate").root


def membrane_pullin_nh() -> tuple[float, float]:
    """(v, lam) of the zero-tension equibiaxial incompressible neo-Hookean membrane."""
    lam = 4 ** (1 / 6)
    return math.sqrt(lam**-2 - lam**-8), lam
