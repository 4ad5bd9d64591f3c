"""Method 2: 1D finite elements through the thickness (no exponential ansatz).

The incremental fields are psi = Psi(x2) exp(i k x1), phi = Phi(x2) exp(i k x1) with
u = (psi_2, -psi_1) (exactly incompressible) and Ddot_L0 = (phi_2, -phi_1) (exactly
divergence free). The incremental energy per wavelength is the Hermitian form

    Pi[Psi, Phi] = int_{-h/2}^{h/2} z^H S z dx2,
    z = (i Psi', Psi'', Psi, -i Psi', Phi', -i Phi)   (k = 1 after scaling x2 by k),

with S the energy matrix of :func:`debench.models.plate.coefficients.energy_matrix` (moduli of
(4.29)-(4.31) pushed forward, plus the base-pressure term). Traction-free faces and
equipotential electrodes (tangential incremental field zero, the charge free to
redistribute: charge control fixes only the total charge) are the *natural* boundary
conditions of Pi, so no boundary row is imposed: the discretisation does not use
(4.69)-(4.80) or the roots (4.64)-(4.66).

Discretisation: Hermite cubic elements for Psi (C1, needed for Psi'') and continuous
quadratic Lagrange elements for Phi on a mesh graded towards the faces (boundary layers
of width 1/(k s) when k h is large). Energy-norm error O(N^-2) gives eigenvalue and
critical-stretch errors O(N^-4) (asserted in the verification suite).

Stability criterion: the plate is stable iff Pi > 0 (the D_L formulation is a
minimum principle), i.e. iff all eigenvalues omega of K v = omega M v are positive
(M = I: the crossings do not depend on M, and the identity avoids the
ill-conditioned L2 Gram matrix of the Hermite basis). lam_cr is where an eigenvalue
crosses zero; the number of negative eigenvalues (the inertia) brackets the crossings
on a lam grid and brentq refines the crossing eigenvalue.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
from debench.models import validation as v
from debench.models.errors import ConvergenceError
from debench.models.numerics.roots import SECANT_STEP, Memo, bracketed_root, zero_near
from debench.models.plate.coefficients import PlateParams, _strongly_elliptic, energy_matrix

#: default number of elements through the thickness
N_ELEMENTS = 24
_GAUSS = np.polynomial.legendre.leggauss(5)

# z = sum_m Cpsi[m] D^m Psi + sum_m Cphi[m] D^m Phi   (D = d/deta, eta = k x2)
_CPSI = np.zeros((3, 6), complex)
_CPSI[0, 2] = 1.0             # L21 = Psi
_CPSI[1, 0] = 1j              # L11 = i Psi'
_CPSI[1, 3] = -1j             # L22 = -i Psi'
_CPSI[2, 1] = 1.0             # L12 = Psi''
_CPHI = np.zeros((2, 6), complex)
_CPHI[0, 5] = -1j             # Dd2 = -i Phi
_CPHI[1, 4] = 1.0             # Dd1 = Phi'


def elements_for(t: float) -> int:
    """Number of elements resolving a plate of scaled thickness t = k h.

    Thin plates need few elements (no boundary layer) and are limited by rounding (the
    bending terms scale like t^-3 N^4); thick plates need ~3 elements per unit of t for
    the boundary layers exp(-s k x2). Measured: error <~ 1e-6 in lam for t in [0.1, 20].
    ``t`` finite and > 0.
    """
    t = v.positive("t", t)
    if t < 0.5:
        return 6
    if t < 1.0:
        return 8
    return int(min(64, 12 + 3 * (t - 1.0)))


def grading(t: float) -> float:
    """Mesh grading towards the faces, a smooth function of t = k h.

    Thick plates (large t) have boundary layers of width ~1/(s t); thin plates do not and
    a uniform mesh keeps the t^-3 bending terms well conditioned. Smooth in t so that the
    discrete eigenvalues vary continuously along a lam scan (t = kH lam^-2). ``t`` finite
    and > 0.
    """
    t = v.positive("t", t)
    return 0.8 * t / (t + 4.0)


def _nodes(n: int, g: float) -> np.ndarray:
    """Nodes on [-1/2, 1/2]: a fixed smooth map of a uniform grid, graded to the faces."""
    u = np.linspace(-0.5, 0.5, n + 1)
    return (1 - g) * u + g * 0.5 * np.sin(np.pi * u)


def _gram(n: int, g: float):
    """Gram matrices int D^m N_i D^k N_j dzeta on [-1/2, 1/2] (zeta = x2/h).

    Returns (G_pp[3,3], G_pf[3,2], G_ff[2,2]) as dense arrays, dofs ordered
    [Psi dofs (2 per node: value, zeta-slope), Phi dofs (nodes then mid-points)].
    """
    x = _nodes(n, g)
    npsi, nphi = 2 * (n + 1), 2 * n + 1
    gp, gw = _GAUSS
    xi = 0.5 * (gp + 1)[None, :]
    he = np.diff(x)[:, None]                       # (n, 1)
    ww = 0.5 * gw[None, :] * he                    # (n, nq)
    one = np.ones_like(he)
    H = np.stack([(1 - 3 * xi**2 + 2 * xi**3) * one, he * (xi - 2 * xi**2 + xi**3),
                  (3 * xi**2 - 2 * xi**3) * one, he * (-xi**2 + xi**3)], axis=1)
    H1 = np.stack([(-6 * xi + 6 * xi**2) / he, (1 - 4 * xi + 3 * xi**2) * one,
                   (6 * xi - 6 * xi**2) / he, (-2 * xi + 3 * xi**2) * one], axis=1)
    H2 = np.stack([(-6 + 12 * xi) / he**2, (-4 + 6 * xi) / he, (6 - 12 * xi) / he**2,
                   (-2 + 6 * xi) / he], axis=1)
    P = np.stack([(1 - xi) * (1 - 2 * xi) * one, 4 * xi * (1 - xi) * one,
                  xi * (2 * xi - 1) * one], axis=1)
    P1 = np.stack([(-3 + 4 * xi) / he, (4 - 8 * xi) / he, (4 * xi - 1) / he], axis=1)
    e = np.arange(n)[:, None]
    ip = np.hstack([2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3])      # (n, 4)
    iF = np.hstack([e, n + 1 + e, e + 1])                          # (n, 3)
    dpsi, dphi = np.stack((H, H1, H2)), np.stack((P, P1))   # (m, e, a, q)

    def assemble(A, B, ia, ib, size):
        """All derivative pairs (m, k) at once: G[m, k] = sum_e N_a^(m) N_b^(k) w."""
        ma, kb = A.shape[0] * A.shape[2], B.shape[0] * B.shape[2]
        Aw = (A * ww[None, :, None, :]).transpose(1, 0, 2, 3).reshape(n, ma, -1)
        Bt = B.transpose(1, 3, 0, 2).reshape(n, -1, kb)
        loc = (Aw @ Bt).reshape(n, A.shape[0], A.shape[2], B.shape[0], B.shape[2])
        loc = loc.transpose(1, 3, 0, 2, 4)              # (m, k, e, a, b)
        # scatter-add into every (m, k) plane at once (contributions summed in element
        # order, as np.add.at would)
        planes = A.shape[0] * B.shape[0]
        idx = (ia[:, :, None] * size[1] + ib[:, None, :]).ravel()
        idx = (np.arange(planes)[:, None] * (size[0] * size[1]) + idx[None, :]).ravel()
        out = np.bincount(idx, weights=loc.reshape(-1), minlength=planes * size[0] * size[1])
        return out.reshape((A.shape[0], B.shape[0]) + size)

    Gpp = assemble(dpsi, dpsi, ip, ip, (npsi, npsi))
    Gpf = assemble(dpsi, dphi, ip, iF, (npsi, nphi))
    Gff = assemble(dphi, dphi, iF, iF, (nphi, nphi))
    return Gpp, Gpf, Gff


@v.finite_result
def stiffness(lam: float, kH: float, params: PlateParams, n: int = N_ELEMENTS):
    """Hermitian stiffness K(lam, kH) and Gram (mass) matrix M of the discretisation.

    ``lam``, ``kH`` finite scalars > 0; ``n >= 2`` elements.
    """
    lam = v.positive("lam", lam)
    kH = v.positive("kH", kH)
    if not (isinstance(lam, float) and isinstance(kH, float)):
        raise TypeError(f"lam and kH must be scalars, got {lam!r}, {kH!r}")
    v.instance("params", params, PlateParams)
    v.integer_at_least("n", n, 2)
    t = kH * lam**-2  # k h
    S = energy_matrix(np.asarray(lam, float), params)
    Gpp, Gpf, Gff = _gram(n, grading(t))
    npsi, nphi = Gpp.shape[2], Gff.shape[2]
    K = np.zeros((npsi + nphi, npsi + nphi), complex)
    # eta = t zeta: D_eta^m = t^-m D_zeta^m, d eta = t d zeta; the coefficient of the
    # block G[m, k] is c_mk t^(1-m-k) with c_mk = C[m]^H S C[k]
    S = np.asarray(S)
    cpp = _CPSI.conj() @ S @ _CPSI.T
    cpf = _CPSI.conj() @ S @ _CPHI.T
    cff = _CPHI.conj() @ S @ _CPHI.T
    tp = t ** (1.0 - np.arange(3))                 # t^(1-m), m = 0, 1, 2

    def contract(c, G):
        """sum_mk c[m, k] G[m, k] (complex c, real G: two real matrix-vector products)."""
        w = c.reshape(-1)
        G2 = G.reshape(w.size, -1)
        return ((w.real @ G2) + 1j * (w.imag @ G2)).reshape(G.shape[2:])

    K[:npsi, :npsi] = contract(cpp * tp[:, None] / t * tp[None, :], Gpp)
    blk = contract(cpf * tp[:, None] / t * tp[None, :2], Gpf)
    K[:npsi, npsi:] = blk
    K[npsi:, :npsi] = blk.conj().T
    K[npsi:, npsi:] = contract(cff * tp[:2, None] / t * tp[None, :2], Gff)
    # The zero crossings do not depend on the SPD matrix M; the L2 Gram matrix of the
    # Hermite basis is ill conditioned (slope dofs ~ he^3) and amplified rounding to
    # ~1e-5 in omega, so the identity is used (omega = eigenvalues of K itself).
    M = np.eye(npsi + nphi)
    return K, M


@v.finite_result
def eigenvalues(lam: float, kH: float, params: PlateParams, n: int = N_ELEMENTS,
                count: int | None = None) -> np.ndarray:
    """Ascending eigenvalues omega of K v = omega M v (all, or the ``count`` lowest).

    ``count`` None or an integer in [1, number of dofs = 4 n + 3].
    """
    return _eigenvalues(lam, kH, params, n, count)[0]


def _eigenvalues(lam, kH, params, n, count):
    """(:func:`eigenvalues`, their round-off eps ||K||_1)."""
    K, _ = stiffness(lam, kH, params, n)
    roundoff = np.finfo(float).eps * np.linalg.norm(K, 1)
    if count is not None:
        v.integer_at_least("count", count, 1)
        if count > K.shape[0]:
            raise ValueError(f"count must be <= the number of dofs {K.shape[0]} "
                             f"(4 n + 3, n = {n}), got {count}")
    if count is None:
        return sla.eigh(K, eigvals_only=True), roundoff
    # K is banded once its dofs are ordered along the thickness (node: Psi, Psi', Phi;
    # then the Phi mid-point dof): the selected eigenvalues of the band (LAPACK hbevx)
    # cost O(N b^2) instead of O(N^3)
    perm, bw = _band_order(n)
    Kp = K[np.ix_(perm, perm)]
    N = K.shape[0]
    band = np.zeros((bw + 1, N), complex)
    for d in range(bw + 1):
        band[d, :N - d] = np.diagonal(Kp, -d)
    return sla.eig_banded(band, lower=True, eigvals_only=True, select="i",
                          select_range=(0, count - 1)), roundoff


def _band_order(n: int):
    """Permutation of the dofs [Psi (2 per node), Phi nodes, Phi mid-points] that orders
    them along the thickness, and the half-bandwidth of K in that order (an element
    couples the 7 consecutive dofs of its two nodes and its mid-point)."""
    npsi = 2 * (n + 1)
    perm = []
    for i in range(n + 1):
        perm += [2 * i, 2 * i + 1, npsi + i]
        if i < n:
            perm.append(npsi + n + 1 + i)
    return np.array(perm), 6


def _negative_eigenvalues(K) -> int | None:
    """Number of negative eigenvalues of the Hermitian matrix ``K`` by Sylvester's law of
    inertia: those of D in the Bunch-Kaufman factorisation P K P^H = L D L^H (LAPACK
    hetrf, lower; sytrf for a real K), D block diagonal with real 1 x 1 and Hermitian
    2 x 2 blocks (a 2 x 2 block with det < 0 holds one negative eigenvalue, with det > 0
    two of the sign of its diagonal). About a seventh of the cost of the eigenvalues of a
    dense K; exact for K + E with ||E|| ~ eps ||K|| (the factorisation is backward stable),
    so the count is that of the eigenvalues except where one lies within round-off of
    zero. None where D
    is singular (a zero 1 x 1 pivot or 2 x 2 determinant): the factorisation does not
    decide the count there."""
    # real symmetric K: the same factorisation is sytrf (LAPACK has no real hetrf)
    kind = "he" if np.iscomplexobj(K) else "sy"
    hetrf, hetrf_lwork = sla.get_lapack_funcs((f"{kind}trf", f"{kind}trf_lwork"), (K,))
    lu, ipiv, info = hetrf(K, lower=1, lwork=sla.lapack._compute_lwork(hetrf_lwork,
                                                                      K.shape[0], lower=1))
    if info < 0:
        raise ValueError(f"hetrf: argument {-info} invalid")
    d = np.real(np.diagonal(lu))
    # a 2 x 2 block at rows (k, k + 1) is marked by ipiv[k] = ipiv[k + 1] < 0 (lower), and
    # only those rows are marked: the marked rows come in consecutive pairs
    marked = np.flatnonzero(ipiv < 0)
    first = marked[0::2]
    if not np.array_equal(marked[1::2], first + 1):
        raise ValueError(f"hetrf: unexpected pivot blocks {ipiv}")
    one = np.ones(len(ipiv), bool)
    one[marked] = False
    a, c = d[first], d[first + 1]
    det = a * c - np.abs(np.diagonal(lu, -1)[first]) ** 2
    if np.any(d[one] == 0.0) or np.any(det == 0.0) or not np.all(np.isfinite(d)):
        return None
    return int(np.count_nonzero(d[one] < 0) + np.count_nonzero(det < 0)
               + 2 * np.count_nonzero((det > 0) & (a < 0)))


@dataclass(frozen=True)
class FemRoots:
    kH: float
    lam: np.ndarray
    index: tuple[int, ...]  # which eigenvalue (ascending) crosses zero


@v.finite_result
def critical_stretches(kH: float, params: PlateParams, *, window=(0.4, 8.0),
                       n_scan: int = 400, n: int = N_ELEMENTS, max_index: int = 8,
                       grid=None) -> FemRoots:
    """All lam in ``window`` where an eigenvalue of K v = omega M v crosses zero.

    The inertia (number of negative eigenvalues among the ``max_index`` lowest) is
    evaluated on a geometric lam grid; where it changes by one the crossing eigenvalue
    is refined with brentq. Non-elliptic lam (``strongly_elliptic`` false) are skipped.
    ``window`` (0 < lo < hi), ``n_scan >= 2`` (or ``grid``: an increasing array of
    stretches > 0), ``n >= 2``, ``1 <= max_index <= 4 n + 3``.
    """
    kH = v.positive("kH", kH)
    v.instance("params", params, PlateParams)
    v.integer_at_least("n", n, 2)
    v.integer_at_least("max_index", max_index, 1)
    if max_index > 4 * n + 3:
        raise ValueError(f"max_index must be <= the number of dofs {4 * n + 3}, got "
                         f"{max_index}")
    if grid is None:
        lo, hi = v.window("window", window)
        g = np.geomspace(lo, hi, v.integer_at_least("n_scan", n_scan, 2))
    else:
        g = np.asarray(v.positive("grid", grid), float)
        if g.ndim != 1 or g.size < 2 or np.any(np.diff(g) <= 0):
            raise ValueError("grid must be an increasing 1-D array of >= 2 stretches")
    ell = _strongly_elliptic(g, params)
    ev = np.array([eigenvalues(x, kH, params, n, max_index) if e else
                   np.full(max_index, np.nan) for x, e in zip(g, ell, strict=True)])
    neg = np.sum(ev < 0, axis=1)
    lams, idx = [], []

    def inertia(x):
        return int(np.sum(eigenvalues(x, kH, params, n, max_index) < 0))

    def crossings(lo, hi, nlo, nhi, depth=0):
        """(lo, hi, j) with exactly one crossing of eigenvalue j, by recursive splitting."""
        if nlo == nhi:
            return []
        if abs(nlo - nhi) == 1:
            return [(lo, hi, min(nlo, nhi))]
        if depth > 6:
            raise ConvergenceError(f"{abs(nlo - nhi)} eigenvalues cross zero in "
                                   f"[{lo}, {hi}] at kH={kH}: not separable")
        sub = np.geomspace(lo, hi, 9)
        ns = [nlo] + [inertia(x) for x in sub[1:-1]] + [nhi]
        out = []
        for a, b, na, nb in zip(sub[:-1], sub[1:], ns[:-1], ns[1:], strict=True):
            out += crossings(a, b, na, nb, depth + 1)
        return out

    for i in range(len(g) - 1):
        if not (ell[i] and ell[i + 1]) or neg[i] == neg[i + 1]:
            continue
        for lo, hi, j in crossings(g[i], g[i + 1], int(neg[i]), int(neg[i + 1])):
            def fj(x, j=j):
                return eigenvalues(x, kH, params, n, j + 1)[j]

            lams.append(bracketed_root(fj, lo, hi, xtol=XTOL_SCAN,
                                       what=f"FE eigenvalue {j} at kH={kH}").root)
            idx.append(int(j))
    return FemRoots(kH, np.asarray(lams), tuple(idx))


#: root tolerance of :func:`refine_root` where the eigenvalue is resolved
XTOL_ROOT = 1e-14
#: root tolerance in lam of the crossings of :func:`critical_stretches`: the tolerance of
#: the determinant roots they are compared with (ansatz.XTOL), far below the 1e-5 to which
#: the two methods must agree
XTOL_SCAN = 1e-13


@v.finite_result
def refine_root(lam0: float, kH: float, params: PlateParams, n: int, *, index: int,
                rel: float = 0.02) -> float:
    """The zero of eigenvalue ``index`` near ``lam0`` (bracket lam0 (1 +- rel)), located to
    ``XTOL_ROOT`` or to the root's round-off, whichever is larger.

    Secant steps start at ``lam0`` (an estimate, e.g. the determinant root) and brentq
    finishes on the narrowest interval where the eigenvalue changed sign
    (:func:`debench.models.numerics.roots.zero_near`). The root's round-off is the
    eigenvalue's, eps ||K||_1, over its slope (the first secant: lam0 and
    lam0 (1 + SECANT_STEP)): within it the computed eigenvalue's sign is round-off (thin
    plates: K ~ t^-3, measured +-2e-11 at k h = 0.14), so a narrower bracket would only
    pick one of its random sign changes. ``lam0 > 0``, ``index >= 0``, ``rel`` in
    (0, 1); ConvergenceError when the eigenvalue does not change sign on the bracket or
    brentq fails.
    """
    v.positive("lam0", lam0)
    v.integer_at_least("index", index, 0)
    v.tolerance("rel", rel)
    v.integer_at_least("n", n, 2)
    if index >= 4 * n + 3:
        raise ValueError(f"index must be < the number of dofs {4 * n + 3}, got {index}")
    roundoff = {}

    def fj(x):
        e, roundoff[x] = _eigenvalues(x, kH, params, n, index + 1)
        return e[index]

    lo, hi = lam0 * (1 - rel), lam0 * (1 + rel)
    fm = Memo(fj)
    x0, x1 = float(lam0), float(lam0 * (1 + SECANT_STEP))
    xtol = XTOL_ROOT
    if lo < x0 < hi and lo < x1 < hi:
        slope = abs(fm(x1) - fm(x0)) / (x1 - x0)
        if slope > 0:
            xtol = max(XTOL_ROOT, max(roundoff.values()) / slope)
    return zero_near(fm, lam0, lo, hi, xtol, what=f"eigenvalue {index}").root
