"""Edge singularity of the clamped film and the mesh-convergence order it implies.

The Chapter 5 film (§5.2.3, Table 5.1) is clamped on its lateral face ``r = a`` and free
on its top and bottom faces: in every meridian plane the boundary has a 90 degree corner
with one face clamped (``u = 0``) and one face traction-free. Near a smooth edge a 3D
elastic field separates into a plane-strain (in-plane) part and an antiplane part with the
exponents of the 2D wedge of the same opening (Williams 1952; Kondrat'ev 1967; Dauge
1988, *Elliptic boundary value problems on corner domains*, LNM 1341), displacement
``u ~ r^s f(theta)``, stress ``~ r^(s-1)``.

Plane strain (Williams 1952, J. Appl. Mech. 19, 526-528, clamped-free case). Kolosov-
Muskhelishvili potentials ``phi = A z^s``, ``psi = B z^s`` (A, B complex, s real for the
derivation) give

    2 mu (u_x + i u_y) = kappa phi - z conj(phi') - conj(psi),
    sigma_tt + i sigma_rt = phi' + conj(phi') + (conj(z) phi'' + psi') e^(2 i theta),

``kappa = 3 - 4 nu`` (plane strain). ``u_r = u_t = 0`` on ``theta = 0`` and
``sigma_tt = sigma_rt = 0`` on ``theta = alpha`` are four real linear equations in
(Re A, Im A, Re B, Im B); their determinant (derived with sympy by
``tools/derive_ch5_singularity.py``) is ``s^2 D(s) / (4 mu^2)`` with

    D(s) = (kappa + 1)^2 - 4 kappa sin^2(alpha s) - 4 s^2 sin^2(alpha)
         = kappa^2 + 1 + 2 kappa cos(2 alpha s) - 4 s^2 sin^2(alpha).

The factor ``s^2`` is the rigid translation (s = 0), excluded by ``s > 0``. The 4x4
matrix is entire in ``s`` and the fields it multiplies satisfy the Navier equations
identically in ``s``, so complex zeros of ``D`` are eigenvalues too (``u`` is then the real
part of ``r^s f(theta)``, ``r^Re(s)`` times an oscillation in ``log r``); zeros come in
conjugate pairs because ``D`` is real on the real axis.

Incompressibility. The formulas hold at ``nu = 0.5`` (``kappa = 1``): ``div u = (kappa - 1)
Re(phi') / mu`` vanishes and the stresses do not contain kappa (the mean stress is the
pressure, finite). At 90 degrees ``D = 0`` reduces to ``cos(pi s / 2) = s``.

Antiplane part: ``u_z = r^s sin(s theta)`` with ``cos(s alpha) = 0``, ``s = pi/(2 alpha)``,
``3 pi/(2 alpha)``, ... At 90 degrees these are 1, 3, 5, ... with the harmonic polynomials
``Im z^n`` as eigenfunctions: smooth, no singularity. The in-plane exponent governs.

Integer exponents. At a simple root ``s = n`` (integer) the field built from ``A z^n``,
``B z^n`` is a polynomial in (x, y): smooth, representable by degree-n elements, no
singularity (at ``nu = 0`` and 90 degrees, ``s = 1`` is ``u = (0, y)``: the clamped face is
``y = 0`` and ``sigma_xx = lambda_L div u`` vanishes on the free face ``x = 0`` when
``lambda_L = 0``). :func:`edge_singularity_exponent` skips such roots.

Two independent methods give the spectrum:

* :func:`williams_eigenvalues`: zeros of ``D`` (real ones bracketed by ``brentq``, complex
  ones by Newton's method from a grid of starts, all of them counted by the argument
  principle on a rectangle that provably contains every zero with ``0 < Re s <= s_max``).
* :func:`williams_eigenvalues_collocation`: the Navier equations for
  ``u = r^s (U, V)(theta)`` with the scaled pressure ``q = div u / (1 - 2 nu) =
  r^(s-1) Q(theta)`` (finite at ``nu = 0.5``) by Chebyshev collocation in theta
  (Trefethen 2000, *Spectral Methods in MATLAB*); a quadratic eigenvalue problem in
  ``s``, linearised and solved densely.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg as sla
from debench.models import validation as val
from debench.models.buckling.parameters import MAX_ORDER
from debench.models.errors import ConvergenceError
from debench.models.numerics.roots import bracketed_root

__all__ = [
    "INTEGER_TOL", "MATCH_RTOL", "characteristic_function", "edge_singularity_exponent",
    "expected_eigenvalue_order", "kolosov_constant", "poisson_ratio", "williams_eigenvalues",
    "williams_eigenvalues_collocation",
]

S_MAX_LIMIT = 8.0
"""Largest ``s_max`` accepted: twice the highest polynomial order of the Chapter 5
discretisation (4); beyond it the rectangle searched grows without purpose."""
NEWTON_STEP_TOL = 1e-14
"""Relative Newton step at which a complex zero counts as converged: ~50 ulp of |s|."""
REAL_IMAG_TOL = 1e-9
"""A zero with |Im s| below this is real (bracketed on the axis instead): Newton lands on
real zeros with |Im s| ~ 1e-16."""
SAME_ROOT_TOL = 1e-8
"""Two zeros closer than this are one (Newton from different starts converges to the same
zero within ~1e-14)."""
INTEGER_TOL = 1e-10
"""An exponent within this of an integer is that integer (a polynomial eigenfunction):
``brentq`` locates the zero to ~1e-15, the collocation to ~1e-12."""
MULTIPLE_TOL = 1e-6
"""Collocation eigenvalues closer than this are one multiple eigenvalue: round-off splits a
double eigenvalue by ~sqrt(eps) ~ 1e-8, distinct Williams exponents differ by O(0.1)."""
MATCH_RTOL = 1e-8
"""Collocation eigenvalues accepted as converged when the n- and 3n/2-point spectra agree
to this (spectral accuracy reaches ~1e-12 for n = 40 on the smooth eigenfunctions; the
discretisation's spurious modes move by O(1) between resolutions)."""
PHASE_STEP_MAX = math.pi / 4
"""Largest phase change of D between neighbouring contour samples trusted by the winding
count (any step below pi is unambiguous; pi/4 leaves margin)."""


def kolosov_constant(nu: float) -> float:
    """Plane-strain Kolosov constant ``kappa = 3 - 4 nu`` (1 at incompressibility)."""
    nu = val.in_range("nu", nu, -1.0, 0.5, lo_open=True)
    return 3.0 - 4.0 * nu


def poisson_ratio(shear_modulus: float, bulk_modulus: float) -> float:
    """Small-strain Poisson ratio ``nu = (3k - 2 mu) / (2 (3k + mu))``.

    Table 5.1 (``mu = 156000 Pa``, ``k = 7748003.92 Pa``) gives ``nu = 0.49``.
    """
    mu = val.positive("shear_modulus", shear_modulus)
    k = val.positive("bulk_modulus", bulk_modulus)
    return (3.0 * k - 2.0 * mu) / (2.0 * (3.0 * k + mu))


def characteristic_function(s, kappa: float, angle: float = math.pi / 2):
    """``D(s) = (kappa + 1)^2 - 4 kappa sin^2(angle s) - 4 s^2 sin^2(angle)``.

    The clamped-free plane-strain wedge determinant without its factor ``s^2/(4 mu^2)``
    (module docstring, ``tools/derive_ch5_singularity.py``). ``s`` may be complex or an
    array; ``kappa`` in ``[1, 7)``.
    """
    s = val.finite("s", s, complex_ok=True)
    kappa = val.in_range("kappa", kappa, 1.0, 7.0, hi_open=True)
    angle = _angle(angle)
    return _d(s, kappa, angle)


def _angle(angle) -> float:
    return val.in_range("angle", angle, 0.0, 2.0 * math.pi, lo_open=True)


def _d(s, kappa, angle):
    return (kappa + 1.0) ** 2 - 4.0 * kappa * np.sin(angle * s) ** 2 \
        - 4.0 * s**2 * math.sin(angle) ** 2


def _dd(s, kappa, angle):
    """dD/ds."""
    return -4.0 * kappa * angle * np.sin(2.0 * angle * s) - 8.0 * s * math.sin(angle) ** 2


def _imag_bound(kappa: float, angle: float, x_max: float) -> float:
    """``Y`` with ``D(x + iy) != 0`` for ``0 <= x <= x_max``, ``|y| >= Y``.

    ``|sin(a s)|^2 = sin^2(a x) + sinh^2(a y)`` gives ``|D| >= g(y) = 2 kappa (cosh(2 a y)
    - 1) - (kappa + 1)^2 - 4 (x_max^2 + y^2) sin^2 a``; ``g''`` increases with ``y``, so
    once ``g, g', g'' > 0`` they stay positive.
    """
    s2 = math.sin(angle) ** 2
    c = (kappa + 1.0) ** 2 + 4.0 * x_max**2 * s2

    def g(y):
        return (2 * kappa * (math.cosh(2 * angle * y) - 1) - c - 4 * y * y * s2,
                4 * kappa * angle * math.sinh(2 * angle * y) - 8 * y * s2,
                8 * kappa * angle**2 * math.cosh(2 * angle * y) - 8 * s2)

    y = 0.25
    while not all(v > 0 for v in g(y)):
        y *= 1.25
    return y


def _winding_number(f, corners) -> int:
    """Number of zeros of the entire function ``f`` inside the closed polygon ``corners``
    (argument principle: total phase change / 2 pi), sampling each edge until no phase step
    exceeds :data:`PHASE_STEP_MAX`."""
    n = 512
    while n <= 2**18:
        pts = np.concatenate([a + (b - a) * np.linspace(0.0, 1.0, n, endpoint=False)
                              for a, b in zip(corners, corners[1:] + corners[:1],
                                              strict=True)])
        vals = f(pts)
        steps = np.angle(np.roll(vals, -1) / vals)
        if np.all(np.isfinite(steps)) and np.max(np.abs(steps)) < PHASE_STEP_MAX:
            total = float(np.sum(steps)) / (2.0 * math.pi)
            return int(round(total))
        n *= 2
    raise ConvergenceError("williams_eigenvalues: the argument-principle contour passes "
                           "through or too close to a zero of D; no reliable count")


def williams_eigenvalues(nu: float, angle: float = math.pi / 2, *,
                         s_max: float = 1.0) -> np.ndarray:
    """Zeros of :func:`characteristic_function` with ``0 < Re s <= s_max``, ``Im s >= 0``.

    Parameters
    ----------
    nu : float
        Poisson ratio in ``(-1, 0.5]`` (plane strain, ``kappa = 3 - 4 nu``).
    angle : float
        Wedge opening in ``(0, 2 pi]`` [rad]; the clamped face is ``theta = 0``.
    s_max : float
        Largest real part returned, in ``(0, 8]``.

    Returns
    -------
    numpy.ndarray
        Complex zeros sorted by real part, one of each conjugate pair (``Im s > 0``);
        a multiple zero is listed once.

    Notes
    -----
    Real zeros: sign changes of ``D`` on a grid of ``(0, X]`` bracketed by ``brentq``.
    Complex zeros: Newton's method (analytic ``D'``) from a grid of starts in the upper
    half of ``[0, X] x [0, Y]``; ``Y`` from a lower bound of ``|D|`` (no zero beyond).
    Completeness: the argument principle counts the zeros in ``[0, X] x [-Y, Y]``
    (``D(iy) > 0``, so none lies on the left edge), ``X`` slightly above ``s_max``; the
    count must equal ``n_real + 2 n_complex``, else ``ConvergenceError`` (e.g. a double
    real zero, which ``brentq`` cannot bracket).
    """
    kappa = kolosov_constant(nu)
    angle = _angle(angle)
    s_max = val.in_range("s_max", s_max, 0.0, S_MAX_LIMIT, lo_open=True)

    def f(s):
        return _d(s, kappa, angle)

    x_hi = s_max * (1.0 + 2.0**-5)          # right edge, off any root at s_max itself
    y_hi = _imag_bound(kappa, angle, x_hi)
    count = _winding_number(f, [complex(0.0, -y_hi), complex(x_hi, -y_hi),
                                complex(x_hi, y_hi), complex(0.0, y_hi)])
    # real zeros: sign changes on a fine grid (spacing << distance between zeros of D,
    # whose oscillation period on the axis is pi/angle >= 1/2)
    xs = np.linspace(0.0, x_hi, 4001)
    ds = f(xs)
    real = []
    for a, b, da, db in zip(xs[:-1], xs[1:], ds[:-1], ds[1:], strict=True):
        if db == 0.0:
            real.append(b)
        elif da * db < 0:
            real.append(bracketed_root(f, a, b, xtol=1e-15, rtol=4 * np.finfo(float).eps,
                                       what="williams_eigenvalues: real zero").root)
    # complex zeros (upper half): Newton from a grid of starts
    cplx: list[complex] = []
    if count > len(real):
        for x0 in np.linspace(0.05 * x_hi, x_hi, 12):
            for y0 in np.linspace(0.05 * y_hi, y_hi, 24):
                z = _newton(complex(x0, y0), kappa, angle)
                if (z is None or abs(z.imag) < REAL_IMAG_TOL or not 0 < z.real <= x_hi
                        or abs(z.imag) > y_hi):
                    continue
                z = complex(z.real, abs(z.imag))
                if all(abs(z - w) > SAME_ROOT_TOL for w in cplx):
                    cplx.append(z)
    if len(real) + 2 * len(cplx) != count:
        raise ConvergenceError(
            f"williams_eigenvalues: argument principle counts {count} zeros with "
            f"0 < Re s <= {x_hi:.6g}, found {len(real)} real and {len(cplx)} complex pairs "
            f"(nu = {nu}, angle = {angle}); a multiple zero?")
    roots = np.array([complex(r, 0.0) for r in real] + cplx, dtype=complex)
    roots = roots[roots.real <= s_max]
    return roots[np.argsort(roots.real, kind="stable")]


def _newton(z: complex, kappa: float, angle: float) -> complex | None:
    for _ in range(60):
        d, dd = complex(_d(z, kappa, angle)), complex(_dd(z, kappa, angle))
        if dd == 0 or not np.isfinite(d):
            return None
        step = d / dd
        z -= step
        if abs(step) <= NEWTON_STEP_TOL * max(1.0, abs(z)):
            return z
    return None


def _chebyshev(n: int):
    """Chebyshev-Gauss-Lobatto points ``x_j = cos(pi j / n)`` and the differentiation
    matrix (Trefethen 2000, *Spectral Methods in MATLAB*, cheb.m)."""
    x = np.cos(np.pi * np.arange(n + 1) / n)
    c = np.hstack([2.0, np.ones(n - 1), 2.0]) * (-1.0) ** np.arange(n + 1)
    dx = x[:, None] - x[None, :]
    dm = np.outer(c, 1.0 / c) / (dx + np.eye(n + 1))
    return x, dm - np.diag(dm.sum(axis=1))


def _collocation_spectrum(nu: float, angle: float, n: int) -> np.ndarray:
    """Eigenvalues ``s`` of the collocated quadratic problem (all of them, unfiltered).

    Unknowns: ``U, V`` at the ``n + 1`` Chebyshev-Gauss-Lobatto points ``theta = angle
    (1 - x)/2`` (theta = 0 clamped, theta = angle free) and ``Q``, a polynomial of degree
    ``n - 2`` given by its values at the ``n - 1`` interior points (the P_n - P_(n-2)
    pairing of spectral Stokes solvers: an equal-order ``Q`` has a spurious pressure-only
    mode at ``s = 1`` when ``nu = 0.5``). With ``S_ij = sigma_ij / (mu r^(s-1))``:
    ``S_rr = 2 nu Q + 2 s U``, ``S_tt = 2 nu Q + 2 (U + V')``, ``S_rt = U' + (s - 1) V``
    (``lambda_L div u / mu = 2 nu Q``). Rows: equilibrium in polar coordinates,
    ``s S_rr + S_rt' - S_tt = 0`` and ``(s + 1) S_rt + S_tt' = 0``, at the interior points;
    ``U = V = 0`` at theta = 0 and ``S_tt = S_rt = 0`` at theta = angle; the constraint
    ``(s + 1) U + V' - (1 - 2 nu) Q = 0`` at the interior points.
    """
    x, dm = _chebyshev(n)
    d1 = -2.0 / angle * dm                   # d/dtheta at the points
    d2 = d1 @ d1
    m = n + 1
    inner = np.arange(1, n)
    # Q: Chebyshev coefficients <- values at the interior points; evaluate and
    # differentiate at all points
    vin = np.polynomial.chebyshev.chebvander(x[inner], n - 2)
    vall = np.polynomial.chebyshev.chebvander(x, n - 2)
    dvall = np.stack([np.polynomial.chebyshev.chebval(
        x, np.polynomial.chebyshev.chebder(np.eye(n - 1)[k])) for k in range(n - 1)], axis=1)
    q_all = np.linalg.solve(vin.T, vall.T).T              # Q at all points
    dq_all = -2.0 / angle * np.linalg.solve(vin.T, dvall.T).T
    eye = np.eye(m)
    nq = n - 1
    size = 2 * m + nq
    cols = (slice(0, m), slice(m, 2 * m), slice(2 * m, size))
    mats = [np.zeros((size, size)) for _ in range(3)]     # coefficients of s^0, s^1, s^2

    def put(k, rows, j, block):
        mats[k][rows, cols[j]] += block

    r1, r2, r3 = inner, m + inner, 2 * m + np.arange(nq)
    # s S_rr + S_rt' - S_tt = 2 s^2 U + 2 nu s Q + U'' + s V' - V' - 2 nu Q - 2 U - 2 V'
    put(2, r1, 0, 2 * eye[inner])
    put(1, r1, 2, 2 * nu * q_all[inner])
    put(1, r1, 1, d1[inner])
    put(0, r1, 0, (d2 - 2 * eye)[inner])
    put(0, r1, 1, -3 * d1[inner])
    put(0, r1, 2, -2 * nu * q_all[inner])
    # (s + 1) S_rt + S_tt' = (s + 1) U' + (s^2 - 1) V + 2 nu Q' + 2 U' + 2 V''
    put(1, r2, 0, d1[inner])
    put(0, r2, 0, 3 * d1[inner])
    put(2, r2, 1, eye[inner])
    put(0, r2, 1, (2 * d2 - eye)[inner])
    put(0, r2, 2, 2 * nu * dq_all[inner])
    # (s + 1) U + V' - (1 - 2 nu) Q = 0
    put(1, r3, 0, eye[inner])
    put(0, r3, 0, eye[inner])
    put(0, r3, 1, d1[inner])
    put(0, r3, 2, -(1 - 2 * nu) * np.eye(nq))
    last = m - 1
    mats[0][0, 0] = 1.0                                    # U(0) = 0
    mats[0][m, m] = 1.0                                    # V(0) = 0
    mats[0][last, last] = 2.0                              # S_tt(angle) = 0
    mats[0][last, cols[1]] = 2 * d1[last]
    mats[0][last, cols[2]] = 2 * nu * q_all[last]
    mats[0][m + last, cols[0]] = d1[last]                  # S_rt(angle) = 0
    mats[0][m + last, m + last] = -1.0
    mats[1][m + last, m + last] = 1.0
    a = np.block([[np.zeros((size, size)), np.eye(size)], [-mats[0], -mats[1]]])
    b = np.block([[np.eye(size), np.zeros((size, size))],
                  [np.zeros((size, size)), mats[2]]])
    w = sla.eig(a, b, right=False)
    return w[np.isfinite(w)]


def williams_eigenvalues_collocation(nu: float, angle: float = math.pi / 2, *,
                                     s_max: float = 1.0, n: int = 32) -> np.ndarray:
    """The same eigenvalues as :func:`williams_eigenvalues`, from the Navier equations.

    Chebyshev collocation of ``u = r^s (U, V)(theta)``, ``q = r^(s-1) Q(theta)`` (see
    the module docstring and ``_collocation_spectrum``) with ``n`` and ``3n/2`` intervals;
    an eigenvalue is kept when both resolutions have it (to :data:`MATCH_RTOL`): the
    discretisation's own (unresolved) eigenvalues move between resolutions and drop out.
    No closed form is used. Eigenvalues whose eigenfunctions the coarser resolution does
    not resolve (wide wedges with large ``s_max``) are missing: raise ``n`` there; at 90
    and 180 degrees with ``s_max <= 3`` the default resolves all of them.

    Parameters
    ----------
    nu, angle, s_max :
        As in :func:`williams_eigenvalues`.
    n : int
        Collocation intervals of the coarser resolution, in ``[8, 200]``.

    Returns
    -------
    numpy.ndarray
        Complex eigenvalues with ``0 < Re s <= s_max`` and ``Im s >= 0``, sorted by real
        part; a multiple eigenvalue is listed once.
    """
    nu = val.in_range("nu", nu, -1.0, 0.5, lo_open=True)
    angle = _angle(angle)
    s_max = val.in_range("s_max", s_max, 0.0, S_MAX_LIMIT, lo_open=True)
    n = val.integer_at_least("n", n, 8)
    if n > 200:
        raise ValueError(f"n must be <= 200 (a dense eigenproblem of size 6(n+1)), got {n}")
    spectra = []
    for nn in (n, n + n // 2):
        w = _collocation_spectrum(nu, angle, nn)
        keep = (w.real > 0) & (w.imag >= -REAL_IMAG_TOL) & (w.real <= s_max * (1 + 2.0**-5))
        spectra.append(w[keep])
    coarse, fine = spectra
    out = [z for z in fine
           if coarse.size and np.min(np.abs(coarse - z)) <= MATCH_RTOL * max(1.0, abs(z))]
    merged: list[complex] = []
    for z in out:                 # a multiple eigenvalue is listed once
        z = complex(z.real, 0.0) if abs(z.imag) < REAL_IMAG_TOL else complex(z)
        if all(abs(z - w) > MULTIPLE_TOL for w in merged):
            merged.append(z)
    out = np.array(merged, dtype=complex)
    out = out[out.real <= s_max]
    return out[np.argsort(out.real, kind="stable")]


def edge_singularity_exponent(nu: float, angle: float = math.pi / 2, *, cap: float = 1.0,
                              method: str = "characteristic") -> float:
    """Smallest real part ``s`` of the clamped-free Williams exponents, capped at ``cap``.

    Displacement ``~ r^s``, stress ``~ r^(s-1)`` at the edge where a clamped face meets a
    traction-free face at ``angle`` (plane strain, module docstring). With the default
    ``cap = 1`` this is the exponent in ``(0, 1]`` of the stress singularity; ``1`` means
    no eigenvalue has ``Re s < 1`` (bounded stress).

    Parameters
    ----------
    nu : float
        Poisson ratio in ``(-1, 0.5]``; 0.5 is the incompressible limit (``kappa = 1``).
    angle : float
        Wedge opening in ``(0, 2 pi]`` [rad]; 90 degrees for the Chapter 5 film.
    cap : float
        Exponents above ``cap`` are reported as ``cap``; in ``(0, 8]``.
    method : {"characteristic", "collocation"}
        Zeros of the closed-form determinant (:func:`williams_eigenvalues`) or the
        collocated Navier equations (:func:`williams_eigenvalues_collocation`).

    Returns
    -------
    float
        ``min(Re s, cap)`` over the eigenvalues that are not positive integers.

    Notes
    -----
    Complex eigenvalues ``s = a + i b`` (``nu < 0`` at 90 degrees; every ``nu`` at 180
    degrees, ``s = 1/2 + i log(kappa)/(2 pi)``) give ``u ~ r^a`` times an oscillation in
    ``log r``; the regularity of the field, hence the finite-element error, is set by
    ``a = Re s``, which is what is returned. Integer eigenvalues (simple zeros) belong to
    polynomial fields and are skipped: they limit neither the regularity nor the
    convergence of elements of that degree.

    At 90 degrees: ``s = 1`` at ``nu = 0`` (the polynomial root; the next one is 1.352),
    0.7112 at 0.3, 0.5999 at 0.49 (Table 5.1) and 0.5946 at 0.5 (``cos(pi s/2) = s``).
    """
    cap = val.in_range("cap", cap, 0.0, S_MAX_LIMIT, lo_open=True)
    method = val.choice("method", method, ("characteristic", "collocation"))
    if method == "characteristic":
        roots = williams_eigenvalues(nu, angle, s_max=cap)
    else:
        roots = williams_eigenvalues_collocation(nu, angle, s_max=cap)
    singular = [z.real for z in roots
                if not (abs(z.imag) < REAL_IMAG_TOL
                        and abs(z.real - round(z.real)) < INTEGER_TOL)]
    return float(min(singular, default=cap))


def expected_eigenvalue_order(nu: float, order: int = 2, angle: float = math.pi / 2) -> float:
    """Asymptotic order ``p`` of ``v_h - v ~ C h^p`` for the critical voltage:
    ``p = 2 min(s, order)``, ``s`` = :func:`edge_singularity_exponent` (with ``cap =
    order``).

    Why twice the energy-norm rate: for a symmetric (self-adjoint) eigenproblem the
    eigenvalue error is the squared energy-norm error of the eigenfunction,
    ``lambda_h - lambda ~ ||u - u_h||_E^2`` (Strang & Fix 1973, *An Analysis of the Finite
    Element Method*, Ch. 6; Babuska & Osborn 1991, *Eigenvalue problems*, Handbook of
    Numerical Analysis II, 641-787). On quasi-uniform meshes of degree-``order``
    elements the energy-norm error of a field ``~ r^s`` at an edge is ``h^min(s, order)``
    (the eigenfunction is in ``H^(1 + s - eps)`` only), so the eigenvalue error is
    ``h^(2 min(s, order))``. The critical voltage is a smooth function of the eigenvalue
    of the tangent stiffness near the bifurcation, so it inherits the order.

    Parameters
    ----------
    nu : float
        Poisson ratio in ``(-1, 0.5]`` (Table 5.1: 0.49).
    order : int
        Polynomial degree of the elements, ``1 <= order <= 4``.
    angle : float
        Edge opening [rad], 90 degrees for the Chapter 5 film.

    Returns
    -------
    float
        The asymptotic order ``p``; 1.1998 for Table 5.1 (``nu = 0.49``, quadratic prisms).

    Notes
    -----
    Caveats. This is the rate in the asymptotic range of the singular term only: on
    coarse meshes, when the singular coefficient is small (the clamped edge carries
    little of the buckling mode's energy) or when the smooth part of the error (order
    ``2 order``) still dominates, the observed order lies between ``p`` and
    ``2 order``; near-incompressible locking (nu = 0.49 with quadratic prisms) and the
    finite prestress of the pre-buckled state, neither in the linear wedge analysis,
    perturb the pre-asymptotic rate further. The 3D edge is curved, which changes the
    coefficients but not the exponents (Dauge 1988).
    """
    order = val.integer_at_least("order", order, 1)
    if order > MAX_ORDER:
        raise ValueError(f"order must be <= {MAX_ORDER}, got {order}")
    return 2.0 * edge_singularity_exponent(nu, angle, cap=float(order))
