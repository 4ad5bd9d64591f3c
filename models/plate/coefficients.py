"""Coefficients of the incremental plate problem (thesis Sec. 4.3.3, eqs 4.52-4.60).

Units: mu = eps = 1 throughout, i.e. stresses and moduli are divided by mu, electric
displacements by sqrt(mu eps) (``Dhat`` = D2/sqrt(mu eps), thesis below (4.77)), so that
the problem depends on (lam, xi, alpha, beta, Dhat) only. D2 = lam^-2 D_L2 is the
Eulerian electric displacement; charge control keeps it fixed while lam varies.

Three *variants* of the coefficients are provided so that every erratum's consequence
can be shown:

``"derived"``
    a, 2b, c, d, e, f, g derived symbolically from the energy (4.22)
    (``tools/derive_ch4.py`` -> :mod:`debench.models.plate.generated`). Differs from print by
    -2 xi lam^-4 in 2b and c (errata ``ch4.erratum.eq4_55_b`` / ``eq4_56_c``).
``"printed"``
    (4.54)-(4.60) as printed, used in a *consistent* formulation (roots, amplitude
    relations and boundary rows re-derived from these coefficients).
``"literal"``
    the equations the thesis says it substituted, taken literally: roots (4.64)-(4.66),
    boundary rows (4.75)-(4.80) (no beta; 6 xi lam^-8 in (4.76)) and amplitude relations
    (4.81)-(4.82) (B = 0 for s = +-1). Only the ansatz determinant (method 1) can use it:
    it is not the Euler-Lagrange system of any quadratic energy.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass

import numpy as np
from debench.models import validation as v
from debench.models.errors import require
from debench.models.plate.generated import base_state as _base_state
from debench.models.plate.generated import derived_coefficients

#: forms of the equations: derived from (4.22), the printed coefficients (4.54)-(4.60) used
#: consistently, the literal printed equations (4.64)-(4.66), (4.75)-(4.82) (module docstring)
VARIANTS = ("derived", "printed", "literal")


@dataclass(frozen=True)
class PlateParams:
    """Material and loading parameters of the plate (thesis Sec. 4.4).

    Parameters
    ----------
    xi
        Anisotropy parameter of (4.21), >= 0 (thesis: 0, 3, 5, 10).
    Dhat
        Dimensionless Eulerian electric displacement D2/sqrt(mu eps), >= 0.
    beta, alpha
        Electric constants of (4.20); thesis Sec. 4.4: alpha = 0, beta = 0.5.
    variant
        ``"derived"`` | ``"printed"`` | ``"literal"`` (see module docstring).
    """

    xi: float = 0.0
    Dhat: float = 0.0
    beta: float = 0.5
    alpha: float = 0.0
    variant: str = "derived"

    def __post_init__(self):
        for name in ("xi", "Dhat", "beta", "alpha"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, numbers.Real):
                raise TypeError(f"{name} must be a real number, got {value!r}")
            v.finite(name, value)
        require(self.xi >= 0, f"xi must be >= 0, got {self.xi}")
        require(self.Dhat >= 0, f"Dhat must be >= 0, got {self.Dhat}")
        require(self.beta > 0, f"beta must be > 0, got {self.beta}")
        require(self.alpha >= 0, f"alpha must be >= 0, got {self.alpha}")
        require(self.variant in VARIANTS, f"variant must be one of {VARIANTS}, got "
                f"{self.variant!r}")


def _check_lam(lam):
    lam = np.asarray(v.finite("lam", lam), dtype=float)
    require(bool(np.all(lam > 0)), f"lam must be finite and > 0, got min {np.min(lam)}")
    return lam


def _check_params(params) -> PlateParams:
    return v.instance("params", params, PlateParams)


@v.finite_result
def printed_coefficients(lam, xi, alpha, beta, Dhat):
    """(a, 2b, c, d, e, f, g) exactly as printed in (4.54)-(4.60), mu = eps = 1.

    ``lam > 0``, ``xi, alpha, Dhat >= 0``, ``beta > 0``, all finite.
    """
    lam = _check_lam(lam)
    for name, value in (("xi", xi), ("alpha", alpha), ("Dhat", Dhat)):
        v.nonnegative(name, value)
    v.positive("beta", beta)
    return _printed_coefficients(lam, xi, alpha, beta, Dhat)


def _printed_coefficients(lam, xi, alpha, beta, Dhat):
    a = lam**2
    b2 = lam**2 + lam**-4 + beta * Dhat**2 + 6 * xi * lam**-8
    c = lam**-4 + beta * Dhat**2 + 2 * xi * lam**-8
    d = beta * Dhat * np.ones_like(lam)
    e = 2 * beta * Dhat * np.ones_like(lam)
    f = alpha * lam**-2 + beta
    g = alpha * lam**4 + beta
    return a, b2, c, d, e, f, g


@v.finite_result
def coefficients(lam, params: PlateParams):
    """Coefficients (a, 2b, c, d, e, f, g) of (4.52)-(4.53) for the chosen variant.

    For ``"literal"`` these are the coefficients the literal rows (4.75)-(4.77) imply
    with beta = 1 in the rows (see :func:`~debench.models.plate.ansatz.row_coefficients`);
    the interior equations are those of ``"printed"``.
    """
    return _coefficients(_check_lam(lam), _check_params(params))


def _coefficients(lam, p):
    """:func:`coefficients` without checks (``p`` may carry an array ``Dhat``)."""
    lam = np.asarray(lam, dtype=float)
    if p.variant == "derived":
        out = derived_coefficients(lam, p.xi, p.alpha, p.beta, p.Dhat)
        return tuple(np.broadcast_to(np.asarray(x, float), lam.shape) for x in out)
    return _printed_coefficients(lam, p.xi, p.alpha, p.beta, p.Dhat)


@v.finite_result
def energy_matrix(lam, params: PlateParams) -> np.ndarray:
    """Plane-strain incremental energy matrix S, shape ``lam.shape + (6, 6)``.

    ``2Q = z^T S z`` with z = (L11, L12, L21, L22, Ddot_L0,1, Ddot_L0,2), L = grad u in the
    current configuration, Ddot_L0 the pushed-forward increment of D_L; it contains the
    push-forward moduli A0, Gamma0, K0 of (4.29)-(4.31) and the base-pressure term
    p L_ij L_ji. Its entries are functions of a, 2b, c, d, e, f, g only (verified
    symbolically in ``tools/derive_ch4.py``)::

        [[a, 0, 0, -c, 0, 0], [0, c, c, 0, d, 0], [0, c, a, 0, d, 0],
         [-c, 0, 0, 2b - a, 0, e], [0, d, d, 0, f, 0], [0, 0, 0, e, 0, g]]
    """
    lam = _check_lam(lam)
    if _check_params(params).variant == "literal":
        raise ValueError("variant 'literal' has no energy matrix (not an energy "
                         "formulation); use 'derived' or 'printed'")
    a, b2, c, d, e, f, g = _coefficients(lam, params)
    z = np.zeros_like(a)
    S = np.array([[a, z, z, -c, z, z], [z, c, c, z, d, z], [z, c, a, z, d, z],
                  [-c, z, z, b2 - a, z, e], [z, d, d, z, f, z], [z, z, z, e, z, g]])
    return np.moveaxis(S, (0, 1), (-2, -1))


@v.finite_result
def base_state(lam, params: PlateParams):
    """Base pressure p (from tau22 = 0) and lateral total Cauchy stress tau11 / mu.

    Derived from (4.22) (:func:`debench.models.plate.generated.base_state`): for the
    ``"derived"`` energy tau11 = lam^2 - lam^-4 - beta Dhat^2 + 2 xi lam^-4 (1 - lam^-4).
    """
    lam = _check_lam(lam)
    _check_params(params)
    return _base_state(lam, params.xi, params.alpha, params.beta, params.Dhat)


@v.finite_result
def reduced_quartic(lam, params: PlateParams):
    """Coefficients (qa, qb, qc) of the mechanical quartic qc s^4 - qb s^2 + qa = 0.

    With alpha = 0 the characteristic equation (4.63) is
    (s^2 - 1) [qc s^4 - qb s^2 + qa] = 0 with qa = a, qb = 2b - d^2/f, qc = c - d^2/f:
    Dhat and beta drop out. For ``"literal"`` the printed (4.63) times lam^2.
    """
    return _reduced_quartic(_check_lam(lam), _check_params(params))


def _reduced_quartic(lam, p, coef=None):
    """:func:`reduced_quartic` without checks; ``coef``: :func:`_coefficients` of
    ``(lam, p)`` when the caller holds them."""
    lam = np.asarray(lam, dtype=float)
    if p.variant == "literal":
        return lam**2, lam**2 + lam**-4 + 6 * p.xi * lam**-8, lam**-4 + 2 * p.xi * lam**-8
    a, b2, c, d, e, f, g = _coefficients(lam, p) if coef is None else coef
    return a, b2 - d**2 / f, c - d**2 / f


def strongly_elliptic(lam, params: PlateParams):
    """Plane-strain strong ellipticity of the incremental energy (electric part condensed).

    The acoustic-type form a n1^4 + (2b - d^2/f) n1^2 n2^2 + (c - d^2/f) n2^4 must be
    positive for every direction n (alpha = 0). Holds iff qa > 0, qc > 0 and
    qb > -2 sqrt(qa qc).
    """
    return _strongly_elliptic(_check_lam(lam), _check_params(params))


def _strongly_elliptic(lam, params, quartic=None):
    """:func:`strongly_elliptic` without checks; ``quartic``: :func:`_reduced_quartic` of
    ``(lam, params)`` when the caller holds it."""
    qa, qb, qc = _reduced_quartic(lam, params) if quartic is None else quartic
    with np.errstate(invalid="ignore"):
        return (qa > 0) & (qc > 0) & (qb > -2 * np.sqrt(np.abs(qa * qc)))


def ellipticity_limit_stretch(params: PlateParams) -> float:
    """Stretch lam_E > 1 above which the derived anisotropic model is not strongly elliptic.

    For ``"derived"``: qc = lam^-4 (1 - 2 xi) + 2 xi lam^-8 < 0 iff lam^4 > 2 xi/(2 xi - 1)
    (xi > 1/2). Returns ``inf`` when the model is elliptic for every lam >= 1.
    """
    _check_params(params)
    if params.variant != "derived" or params.xi <= 0.5:
        return float("inf")
    return float((2 * params.xi / (2 * params.xi - 1)) ** 0.25)
