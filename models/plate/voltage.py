"""Beyond the thesis: voltage control of the electroded plate (Sec. 4.3.1 leaves it to
"a future study").

With compliant electrodes bonded to both faces (the thesis' configuration) the exterior
field vanishes under charge *and* voltage control, and each electrode is an equipotential
surface. For an incremental mode ~ exp(i k x1), k != 0, the electrode potential must stay
uniform, hence zero: the tangential incremental field vanishes (E_L0,1 = 0) and the
traction rows are unchanged. The incremental boundary-value problem is therefore the same
as under charge control; only the base state differs. Re-derived from (4.20):

    E = F^-T dW/dD_L = (alpha F^-T D_L + beta F D_L)/eps,  E2 = (alpha lam^4 + beta) D2/eps,
    V = E2 h = (alpha lam^4 + beta) D2 H lam^-2/eps,

so at fixed Vhat = V sqrt(eps/mu)/H the displacement along a curve is
Dhat(lam) = Vhat lam^2/(alpha lam^4 + beta). lam_cr(kH) at fixed Vhat solves
det(lam, kH; Dhat(lam)) = 0 with the determinant of method 1, and is checked against the
FE eigenvalue crossing of method 2 at the same (lam, kH, Dhat(lam)).
"""

from __future__ import annotations

from dataclasses import replace
from types import SimpleNamespace

import numpy as np
from debench.models import validation as v
from debench.models.errors import ConvergenceError, require
from debench.models.numerics.roots import bracketed_root
from debench.models.plate.ansatz import (
    LAM_WINDOW,
    MIN_SCAN,
    PARITIES,
    XTOL,
    _determinant,
    _pack_roots,
    _scan_determinants,
    scan_grid,
)
from debench.models.plate.coefficients import PlateParams
from debench.models.plate.fem import eigenvalues

#: root tolerance in lam of :func:`fe_root_at_voltage`: 10x below the tolerance XTOL of
#: the determinant roots it is compared with, ~45 ulps at lam ~ 1
XTOL_FE = 1e-14


@v.finite_result
def dhat_at_voltage(lam, Vhat: float, params: PlateParams):
    """Dhat = Vhat lam^2/(alpha lam^4 + beta): the displacement at fixed voltage.

    ``lam > 0``, ``Vhat >= 0`` finite.
    """
    lam = np.asarray(v.positive("lam", lam), float)
    v.nonnegative("Vhat", Vhat)
    v.instance("params", params, PlateParams)
    return _dhat(lam, Vhat, params)


def _dhat(lam, Vhat, params):
    lam = np.asarray(lam, float)
    return Vhat * lam**2 / (params.alpha * lam**4 + params.beta)


def _params_at(lam, Vhat, params):
    """Duck-typed parameters with an array Dhat (for the vectorised determinant)."""
    return SimpleNamespace(xi=params.xi, Dhat=_dhat(lam, Vhat, params),
                           beta=params.beta, alpha=params.alpha, variant=params.variant)


def determinant_at_voltage(lam, kH, Vhat: float, params: PlateParams, parity: str):
    """The method-1 determinant at fixed voltage (Dhat = Dhat(lam)).

    Arguments as :func:`~debench.models.plate.ansatz.determinant` plus ``Vhat >= 0``;
    ValueError where the model is not strongly elliptic.
    """
    lam = np.asarray(v.positive("lam", lam), float)
    v.positive("kH", kH)
    v.nonnegative("Vhat", Vhat)
    v.instance("params", params, PlateParams)
    v.choice("parity", parity, PARITIES)
    det = _determinant_at_voltage(lam, kH, Vhat, params, parity)
    if not np.all(np.isfinite(det)):
        raise ValueError(f"lam = {v._show(lam)} is outside the strongly elliptic range at "
                         f"Vhat = {Vhat}: the bifurcation problem is ill-posed there")
    return det


def _determinant_at_voltage(lam, kH, Vhat, params, parity):
    lam = np.asarray(lam, float)
    return _determinant(lam, kH, _params_at(lam, Vhat, params), parity)


def critical_stretches_at_voltage(kH: float, Vhat: float, params: PlateParams, *,
                                  window=LAM_WINDOW, n_scan: int = 400):
    """lam_cr at fixed kH and fixed voltage Vhat (charge-free exterior, electroded plate).

    Returns (lam, parity) sorted by lam: the scan of
    :func:`~debench.models.plate.ansatz._scan_determinants` (a geometric lam grid refined
    where two roots may share an interval, every bracket refined to ``xtol = 1e-13``).
    """
    v.nonnegative("Vhat", Vhat)
    v.positive("kH", kH)
    v.instance("params", params, PlateParams)
    v.integer_at_least("n_scan", n_scan, MIN_SCAN)
    require(params.variant != "literal", "voltage control needs a consistent variant "
            "('derived' or 'printed'), got 'literal'")
    _, lams, pars = _scan(np.array([float(kH)]), Vhat, params, window, n_scan)
    order = np.argsort(lams)
    return lams[order], tuple(pars[i] for i in order)


def _scan(kH_values, Vhat, params, window, n_scan):
    """:func:`~debench.models.plate.ansatz._scan_determinants` of the voltage-controlled
    determinants on the scan grid of ``window`` and ``n_scan``."""
    grid = scan_grid(window, n_scan, params)
    K, L = np.meshgrid(kH_values, grid, indexing="ij")

    def det(lam, kH, par):
        return _determinant_at_voltage(lam, kH, Vhat, params, par)

    return _scan_determinants(det, kH_values, grid, {par: det(L, K, par) for par in PARITIES},
                             XTOL, what=f"voltage control, Vhat = {Vhat}, {params}")


def curves_at_voltage(kH_values, Vhat: float, params: PlateParams, *, window=LAM_WINDOW,
                      n_scan: int = 400, max_roots: int = 8):
    """lam_cr(kH) at fixed voltage for many kH at once: the roots of
    :func:`critical_stretches_at_voltage` at each kH, in one pass.

    The determinant is evaluated on the whole (kH, lam) scan grid in one call, refined
    and its brackets refined together (:func:`~debench.models.plate.ansatz._scan_determinants`).
    Returns (lam, parity) as :func:`~debench.models.plate.ansatz.curves`: arrays
    (len(kH_values), max_roots) of the roots sorted by lam, padded with NaN, and their
    parity codes (0 = "E", 1 = "O", -1 = none); ConvergenceError for more than
    ``max_roots`` roots at one kH. ``kH_values`` a
    non-empty 1-D array of finite values > 0, ``max_roots >= 1``.
    """
    kH_values = np.asarray(v.positive("kH_values", kH_values), float)
    if kH_values.ndim != 1 or kH_values.size == 0:
        raise ValueError(f"kH_values must be a non-empty 1-D array, got shape "
                         f"{kH_values.shape}")
    v.nonnegative("Vhat", Vhat)
    v.instance("params", params, PlateParams)
    v.integer_at_least("n_scan", n_scan, MIN_SCAN)
    v.integer_at_least("max_roots", max_roots, 1)
    require(params.variant != "literal", "voltage control needs a consistent variant "
            "('derived' or 'printed'), got 'literal'")
    rows, lams, pars = _scan(kH_values, Vhat, params, window, n_scan)
    return _pack_roots(kH_values, rows, lams, pars, max_roots,
                      f"voltage control, Vhat = {Vhat}")


@v.finite_result
def fe_root_at_voltage(lam0: float, kH: float, Vhat: float, params: PlateParams, n: int,
                       rel: float = 1e-3) -> float:
    """Method 2: the FE eigenvalue crossing near lam0 with Dhat = Dhat(lam) varying.

    ``lam0 > 0``, ``kH > 0``, ``Vhat >= 0``, ``n >= 2``, ``rel`` in (0, 1); ConvergenceError
    unless exactly one eigenvalue crosses zero on lam0 (1 +- rel).
    """
    v.positive("lam0", lam0)
    v.positive("kH", kH)
    v.nonnegative("Vhat", Vhat)
    v.instance("params", params, PlateParams)
    v.integer_at_least("n", n, 2)
    v.tolerance("rel", rel)

    def ev(x, count=8):
        p = replace(params, Dhat=float(_dhat(x, Vhat, params)))
        return eigenvalues(x, kH, p, n, count)

    lo, hi = lam0 * (1 - rel), lam0 * (1 + rel)
    n_lo, n_hi = int(np.sum(ev(lo) < 0)), int(np.sum(ev(hi) < 0))
    if abs(n_lo - n_hi) != 1:
        raise ConvergenceError(f"inertia {n_lo} -> {n_hi} near lam = {lam0} (voltage control)")
    j = min(n_lo, n_hi)
    return bracketed_root(lambda x: ev(x, j + 1)[j], lo, hi, xtol=XTOL_FE,
                          what=f"voltage-control FE eigenvalue {j}").root
