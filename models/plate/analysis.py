"""Derived quantities of Chapter 4: limits (Fig. 4.4), unstable regions (Figs 4.2, 4.3),
critical electric displacement (Fig. 4.6), and the literature limits.

All functions are pure; they use the ansatz determinant of :mod:`debench.models.plate.ansatz`
(method 1) and closed forms derived here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from types import SimpleNamespace

import numpy as np
from debench.models import validation as v
from debench.models.errors import ConvergenceError
from debench.models.numerics.roots import bisect_boundary, scan_roots
from debench.models.plate.ansatz import (
    _column,
    _determinant,
    _determinants,
    _quartic_roots,
    _row_coefficients,
    critical_stretches,
)
from debench.models.plate.coefficients import PlateParams, _strongly_elliptic, coefficients


def _params(params) -> PlateParams:
    return v.instance("params", params, PlateParams)


# --------------------------------------------------------------------------- kH -> 0
@v.finite_result
def membrane_stress(lam, params: PlateParams):
    """a - c = A0_1212 - A0_2121, which for a consistent model equals tau11 - tau22.

    For the ``"derived"`` energy (4.28) this is the lateral total stress
    lam^2 - lam^-4 - beta Dhat^2 + 2 xi lam^-4 (1 - lam^-4) (tau22 = 0). For the printed
    coefficients (4.54)-(4.56) it is lam^2 - lam^-4 - beta Dhat^2 - 2 xi lam^-8, which
    is *not* the stress of (4.28) (erratum ch4.erratum.eq4_56_c).
    """
    a, b2, c, *_ = coefficients(lam, params)
    return a - c


#: root tolerance in lam of the thin limit a - c = 0 (a rational function of lam): ~45
#: ulps at lam ~ 1
THIN_XTOL = 1e-14
#: root tolerance in lam of the half-space limit (its determinant is smooth in lam < 1):
#: ~90 ulps at lam ~ 0.5
HALF_SPACE_XTOL = 1e-14


def thin_limit(params: PlateParams, window=(0.3, 10.0), n: int = 2000) -> np.ndarray:
    """lam_cr(kH -> 0) of the flexural (psi-even) mode: the roots of a - c = 0.

    Thin-plate (Euler) limit: the buckling load vanishes like (kh)^2, so the critical
    membrane stress tends to zero. For ``"literal"`` (no energy behind it) the
    flexural method-1 roots at kH = 1e-4 are returned instead. ``window`` (0 < lo < hi),
    ``n >= 2``.
    """
    _params(params)
    window = v.window("window", window)
    v.integer_at_least("n", n, 2)
    if params.variant == "literal":
        # Not an energy formulation: the identity a - c = tau11 does not govern its thin
        # limit ((4.76) is inconsistent with (4.75)); use the method-1 flexural roots.
        return critical_stretches(1e-4, params, window=window, parities=("E",)).lam
    grid = np.geomspace(*window, n)

    def f(x):
        return membrane_stress(np.asarray(x, float), params)

    # all sign changes refined together (vectorised Illinois iteration)
    return scan_roots(f, grid, xtol=THIN_XTOL, what="thin limit (a - c = 0)").root


def euler_coefficient_isotropic() -> float:
    """d lam_cr / d (kH)^2 at kH -> 0 for xi = 0, Dhat = 0: -1/18.

    Plate theory: plane-strain bending stiffness of an incompressible plate
    D_b = 4 mu h^3/12, membrane stress tau11 ~ 6 mu (lam - 1) near lam = 1, buckling when
    -tau11 h = D_b k^2 -> 1 - lam = (kh)^2/18 (and h -> H as lam -> 1).
    """
    return -1.0 / 18.0


# --------------------------------------------------------------------------- kH -> inf
def half_space_determinant(lam, params: PlateParams):
    """Surface-instability determinant of the half-space (decaying modes only).

    ``lam > 0``; ValueError where the model is not strongly elliptic.
    """
    lam = np.asarray(v.positive("lam", lam), float)
    det = _half_space_determinant(lam, _params(params))
    if not np.all(np.isfinite(det)):
        raise ValueError(f"lam = {v._show(lam)} is outside the strongly elliptic range of "
                         f"{params}: the half-space problem is ill-posed there")
    return det


def _half_space_determinant(lam, params):
    lam = np.asarray(lam, float)
    rc = _row_coefficients(lam, params)
    s2, s3 = _quartic_roots(lam, params)
    kappa = rc[2] / rc[4] if params.variant != "literal" else params.Dhat * np.ones_like(lam)
    big = np.full_like(lam, 1e3)  # tanh(s t / 2) = 1: only exp(-s x2) survives

    def col(s):
        return _column(s, big, "E", "quartic", rc, kappa)

    c2, c3 = col(s2), col(s3)
    diff = s2 - s3
    close = np.abs(diff) < 1e-3
    dd = (c2 - c3) / np.where(close, 1.0, diff)[..., None]
    if np.any(close):
        m = 0.5 * (s2 + s3)
        dd = np.where(close[..., None], (col(m + 1e-4) - col(m - 1e-4)) / 2e-4, dd)
    c1 = _column(np.ones_like(lam, dtype=complex), big, "E", "electric", rc, kappa)
    det = np.real(np.linalg.det(np.stack([0.5 * (c2 + c3), dd, c1], axis=-1)))
    return np.where(_strongly_elliptic(lam, params) | (params.variant == "literal"), det,
                    np.nan)


def half_space_limit(params: PlateParams, window=(0.3, 0.999)) -> float:
    """Largest lam < 1 at which the half-space is marginally stable (kH -> inf limit).

    ``window`` (0 < lo < hi <= 1).
    """
    _params(params)
    lo, hi = v.window("window", window)
    if hi > 1:
        raise ValueError(f"window must lie below 1 (compression), got {window!r}")
    grid = np.linspace(hi, lo, 700)      # from the top: the first sign change is the largest
    found = scan_roots(lambda x: float(_half_space_determinant(x, params)), grid,
                       _half_space_determinant(grid, params), xtol=HALF_SPACE_XTOL,
                       method="brentq", select="first", what="half-space determinant")
    if not found.root.size:
        raise ConvergenceError(f"no half-space root in {window} for {params}")
    return float(found.root[0])


def biot_equibiaxial_closed_form() -> float:
    """Biot's surface instability of the incompressible neo-Hookean half-space.

    With r = lam1/lam2 (lam1 along the surface, lam2 normal), the condition is
    r^3 + r^2 + 3 r - 1 = 0 (Biot 1963; Dowaikh & Ogden 1990). Equibiaxial lam1 = lam3 =
    lam, lam2 = lam^-2 gives r = lam^3.
    """
    roots = np.roots([1.0, 1.0, 3.0, -1.0])
    r = float(np.real(roots[np.abs(np.imag(roots)) < 1e-12][0]))
    return r ** (1.0 / 3.0)


# --------------------------------------------------------------------------- regions
@dataclass(frozen=True)
class Region:
    """Unstable region on a (kH, lam) grid.

    ``thesis``: det6 = det_E det_O < 0 (sign relative to the stable top of the window),
    the thesis' definition ("determinant < 0", Sec. 4.4). ``physical``: at least one
    parity has an odd number of roots above lam (an eigenvalue of the incremental
    energy is negative), plus every non-elliptic point. ``nonelliptic``: the model is not
    strongly elliptic.
    """

    kH: np.ndarray
    lam: np.ndarray
    thesis: np.ndarray
    physical: np.ndarray
    nonelliptic: np.ndarray

    def area(self, which: str = "thesis") -> float:
        """Area in the (kH, lam) plane (trapezoidal rule on the grid).

        ``which``: ``"thesis"``, ``"physical"`` or ``"nonelliptic"``; ValueError when no
        stable reference exists (the region is undefined).
        """
        v.choice("which", which, ("thesis", "physical", "nonelliptic"))
        if which != "nonelliptic" and np.any(np.isnan(
                np.asarray(getattr(self, which), float))):
            raise ValueError("the unstable region is undefined: the top of the lam window "
                             "is not strongly elliptic (no stable reference)")
        m = getattr(self, which).astype(float)  # NaN if no stable reference exists
        return float(np.trapezoid(np.trapezoid(m, self.lam, axis=1), self.kH))


def region(params: PlateParams, kH, lam) -> Region:
    """Unstable region on the tensor grid ``kH`` x ``lam`` (lam ascending, top stable).

    ``kH``, ``lam`` non-empty 1-D arrays of finite values > 0, ``lam`` increasing.
    """
    _params(params)
    kH = _grid_1d("kH", kH)
    lam = _grid_1d("lam", lam)
    if np.any(np.diff(lam) <= 0):
        raise ValueError("lam must be strictly increasing")
    # both parities on the tensor grid (kH, lam) in one pass: what depends on lam only
    # is evaluated once per lam
    dE, dO = _determinants(lam[None, :], kH[:, None], params, ("E", "O"))
    ne = ~np.isfinite(dE) | ~np.isfinite(dO)
    top = lam.size - 1
    if ne[:, top].any():
        # The stable reference (large lam, all in tension) is not strongly elliptic:
        # the derived anisotropic model (4.22) for xi > 1/2. No sign reference exists.
        nan = np.full(dE.shape, np.nan)
        return Region(kH, lam, nan, nan, ne)
    sE = np.sign(dE) * np.sign(dE[:, top:top + 1])
    sO = np.sign(dO) * np.sign(dO[:, top:top + 1])
    thesis = np.where(ne, False, sE * sO < 0)
    physical = ne | (sE < 0) | (sO < 0)
    return Region(kH, lam, thesis, physical, ne)


# --------------------------------------------------------------------------- Fig 4.6
def _grid_1d(name, x) -> np.ndarray:
    x = np.asarray(v.positive(name, x), float)
    if x.ndim != 1 or x.size == 0:
        raise ValueError(f"{name} must be a non-empty 1-D array, got shape {x.shape}")
    return x


def area_curve(params: PlateParams, Dhats, kH, lam, which="thesis") -> np.ndarray:
    """Area of the unstable region (:meth:`Region.area`) for each Dhat >= 0."""
    _params(params)
    Dhats = np.atleast_1d(np.asarray(v.nonnegative("Dhats", Dhats), float))
    return np.array([region(replace(params, Dhat=float(D)), kH, lam).area(which)
                     for D in Dhats])


def critical_D_max_area(params: PlateParams, Dhats, kH, lam, which="thesis") -> float:
    """Candidate 1 for Fig. 4.6: the Dhat at which the unstable area is largest
    ("the electric field started to stabilize the plate"), refined by a parabola
    through the grid maximum and its neighbours."""
    Dhats = np.asarray(v.nonnegative("Dhats", Dhats), float)
    if Dhats.ndim != 1 or Dhats.size < 3 or np.any(np.diff(Dhats) <= 0):
        raise ValueError("Dhats must be an increasing 1-D array of >= 3 values")
    return _max_area_D(Dhats, area_curve(params, Dhats, kH, lam, which))


def _max_area_D(Dhats, A) -> float:
    """:func:`critical_D_max_area` from the areas ``A`` at ``Dhats`` (a caller that holds
    memoised areas passes them)."""
    Dhats, A = np.asarray(Dhats, float), np.asarray(A, float)
    i = int(np.argmax(A))
    if i == 0 or i == len(A) - 1:
        raise ConvergenceError(f"area maximum at the end of the Dhat range {Dhats[[0, -1]]}")
    x, y = Dhats[i - 1:i + 2], A[i - 1:i + 2]
    c2, c1, _ = np.polyfit(x, y, 2)
    return float(-c1 / (2 * c2))


#: halvings of the Dhat grid interval holding the onset of the extensional mode: its
#: spacing (0.05 with the 111 points on the default window (0.5, 6)) to 0.05 2^-40 ~ 5e-14,
#: far below the printed digits of the critical Dhat
ONSET_HALVINGS = 40


def critical_D_thin_extensional(params: PlateParams, D_window=(0.5, 6.0),
                                kH: float = 1e-3, lam_window=(0.4, 8.0)) -> float:
    """Candidate 2 for Fig. 4.6: the smallest Dhat at which an extensional (psi-odd)
    bifurcation exists for a thin plate (kH -> 0), i.e. the change of shape of the
    curves described for Figs 4.2(d)-(f)."""
    _params(params)
    D_window = v.window("D_window", D_window, lo=-math.ulp(0.0))
    v.positive("kH", kH)
    lam = np.geomspace(*v.window("lam_window", lam_window), 1500)

    def roots_flags(Ds):
        """Whether the psi-odd determinant changes sign on the lam grid, per Dhat (all
        Dhat in one evaluation: duck-typed parameters with an array Dhat; one by one for
        the literal rows, whose s = 1 mode depends on whether Dhat > 0)."""
        if params.variant == "literal":
            return np.array([bool(one_flag(D)) for D in Ds])
        pD = SimpleNamespace(xi=params.xi, Dhat=np.asarray(Ds, float)[:, None],
                             beta=params.beta, alpha=params.alpha, variant=params.variant)
        dv = _determinant(np.broadcast_to(lam, (pD.Dhat.size, lam.size)), kH, pD, "O")
        ok = np.isfinite(dv[:, :-1]) & np.isfinite(dv[:, 1:])
        return np.any(ok & (dv[:, :-1] * dv[:, 1:] < 0), axis=1)

    def one_flag(D):
        dv = _determinant(lam, kH, replace(params, Dhat=float(D)), "O")
        ok = np.isfinite(dv[:-1]) & np.isfinite(dv[1:])
        return bool(np.any(ok & (dv[:-1] * dv[1:] < 0)))

    def has_root(D):
        return one_flag(D)

    Ds = np.linspace(*D_window, 111)
    # the first grid Dhat with a root, scanning in chunks (no need to evaluate beyond it)
    i = 0
    for k in range(0, Ds.size, 16):
        flags = roots_flags(Ds[k:k + 16])
        if flags.any():
            i = k + int(np.argmax(flags))
            break
    if i == 0:
        raise ConvergenceError(f"no onset of the extensional mode in {D_window}")
    lo, hi = bisect_boundary(has_root, Ds[i - 1], Ds[i], halvings=ONSET_HALVINGS,
                             what="onset of the extensional mode").bracket
    return 0.5 * (lo + hi)
