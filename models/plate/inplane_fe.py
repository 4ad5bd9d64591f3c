"""Fibre in the plane of the plate, method 2: finite elements through the thickness.

The incremental problem of :mod:`debench.models.plate.inplane` (fields exp(i k x1) g(x2),
unknowns the stream function psi, the antiplane displacement u3 and the electric stream
function phi) discretised by Galerkin's method on the Hermitian energy through the
thickness (Hermite cubic psi, quadratic u3 and phi, the meshes and Gram matrices of
:mod:`debench.models.plate.fem`); traction-free faces and equipotential electrodes are
natural conditions. lam_cr is where an eigenvalue of K crosses zero
(:func:`critical_stretches_fe`); method 1, the boundary determinant, is
:func:`debench.models.plate.inplane.critical_stretches_det`.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla
from debench.models import validation as v
from debench.models.errors import ConvergenceError
from debench.models.numerics.roots import bracketed_root
from debench.models.plate.coefficients import PlateParams
from debench.models.plate.fem import _gram, _negative_eigenvalues, grading
from debench.models.plate.inplane import XTOL_ROOT, _path
from debench.models.plate.inplane_symbol import _S, _check, _elliptic_grid

#: elements through the thickness (default)
N_ELEMENTS = 24

_C_PSI = np.zeros((3, 8), complex)   # z from D^m Psi
_C_PSI[1, 0] = 1j                     # L11 = i Psi'
_C_PSI[2, 1] = 1.0                    # L12 = Psi''
_C_PSI[0, 2] = 1.0                    # L21 = Psi
_C_PSI[1, 3] = -1j                    # L22 = -i Psi'
_C_U = np.zeros((2, 8), complex)
_C_U[0, 4] = 1j                       # L31 = i U3
_C_U[1, 5] = 1.0                      # L32 = U3'
_C_PHI = np.zeros((2, 8), complex)
_C_PHI[1, 6] = 1.0                    # Dd1 = Phi'
_C_PHI[0, 7] = -1j                    # Dd2 = -i Phi


def fe_stiffness(lam: float, kH: float, theta: float, params: PlateParams,
                 n: int = N_ELEMENTS) -> np.ndarray:
    """Method 2: Hermitian stiffness K(lam, kH), dofs [Psi (2(n+1)), U3, Phi (2n+1 each)]."""
    lam, theta = _check(lam, theta, params)
    kH = v.positive("kH", kH)
    v.integer_at_least("n", n, 2)
    return _K(lam, kH, theta, params, n)


#: the rows of every field stacked (Psi, U3, Phi), the derivative order of each row and
#: the rows of each field: z = sum_r _C_ALL[r] D^m(r) (field of r)
_C_ALL = np.vstack([_C_PSI, _C_U, _C_PHI])
_ORDER = np.array([0, 1, 2, 0, 1, 0, 1])
_ROWS = {"psi": slice(0, 3), "u": slice(3, 5), "phi": slice(5, 7)}


def _K(lam, kH, theta, p, n):
    S = _S(lam, theta, p)
    t = kH * lam**-2
    Gpp, Gpf, Gff = _gram(n, grading(t))
    npsi, nq = Gpp.shape[2], Gff.shape[2]
    sl = {"psi": slice(0, npsi), "u": slice(npsi, npsi + nq),
          "phi": slice(npsi + nq, npsi + 2 * nq)}
    # c[r, q] = C[r]^H S C[q] for every pair of rows; eta = t zeta: D_eta^m = t^-m
    # D_zeta^m, d eta = t d zeta
    c = _C_ALL.conj() @ S @ _C_ALL.T
    c = c * t ** (1.0 - np.add.outer(_ORDER, _ORDER))
    K = np.zeros((npsi + 2 * nq, npsi + 2 * nq), complex)
    fields = tuple(_ROWS)
    for ia, a in enumerate(fields):
        for b in fields[ia:]:
            G = Gpp if a == b == "psi" else Gpf if a == "psi" else Gff
            # sum_mk c[m, k] G[m, k]: complex weights on real Gram matrices, as two real
            # matrix products
            w = c[_ROWS[a], _ROWS[b]].reshape(-1)
            G2 = G.reshape(w.size, -1)
            blk = ((w.real @ G2) + 1j * (w.imag @ G2)).reshape(G.shape[2:])
            K[sl[a], sl[b]] = blk
            if a != b:
                K[sl[b], sl[a]] = blk.conj().T
    # the Hermitian part (the diagonal blocks are Hermitian up to round-off)
    return 0.5 * (K + K.conj().T)


def fe_eigenvalues(lam: float, kH: float, theta: float, params: PlateParams,
                   n: int = N_ELEMENTS, count: int = 6) -> np.ndarray:
    """The ``count`` lowest eigenvalues of K (ascending)."""
    K = fe_stiffness(lam, kH, theta, params, n)
    v.integer_at_least("count", count, 1)
    return sla.eigh(K, eigvals_only=True, subset_by_index=(0, count - 1))


def critical_stretches_fe(kH: float, theta: float, params: PlateParams, *,
                          window=(0.45, 0.999), n_scan: int = 120, n: int = N_ELEMENTS,
                          max_index: int = 6, Vhat: float | None = None) -> np.ndarray:
    """Method 2: every lam in ``window`` where an eigenvalue of K crosses zero.

    ``window`` and ``Vhat`` as in :func:`~.inplane.critical_stretches_det`. The inertia of
    K is counted on the grid (Bunch-Kaufman factorisations of K -+ delta I, delta the
    round-off band ROUNDOFF_FACTOR eps ||K||_1; the eigenvalues where one lies inside
    it); a crossing is refined by brentq on the eigenvalue that changes sign, to its
    round-off (eigenvalue round-off eps ||K||_1 over its secant slope on the bracket) or
    :data:`~.inplane.XTOL_ROOT`, whichever is larger. ConvergenceError
    where that eigenvalue is within :data:`ROUNDOFF_FACTOR` x the round-off of K at a
    bracket end and the root's round-off (eigenvalue round-off over its slope) exceeds
    :data:`FE_ROOT_ROUNDOFF`: thin plates in tension (t = kH lam^-2 small) make K so
    ill-conditioned (||K|| ~ n^3 t^-3) that the membrane eigenvalue drowns in round-off
    (measured at kH = 0.1, lam > 3); the determinant has no such limit.
    """
    kH = v.positive("kH", kH)
    lo, hi = v.window("window", window)
    _check(lo, theta, params)
    _check(hi, theta, params)
    path = _path(params, Vhat)
    g = np.geomspace(lo, hi, v.integer_at_least("n_scan", n_scan, 2))

    seen, counts = {}, {}

    def ev(x, j=None):
        """(lowest eigenvalues, their round-off) at x, or eigenvalue j; each stretch's
        eigenvalues are computed once per scan (brentq starts from the bracket ends)."""
        x = float(x)
        if x not in seen:
            K = _K(x, kH, theta, path(x), n)
            e = sla.eigh(K, eigvals_only=True, subset_by_index=(0, max_index - 1))
            seen[x] = (e, np.finfo(float).eps * np.linalg.norm(K, 1))
        return seen[x] if j is None else seen[x][0][j]

    def count(x):
        """Negative eigenvalues among the ``max_index`` lowest at x: the inertia of
        K -+ delta I, delta = ROUNDOFF_FACTOR eps ||K||_1, where the two agree (no
        eigenvalue within delta of zero, so each sign lies beyond round-off and the
        inertia is the count of the computed eigenvalues); else the count of the
        eigenvalues (one inside the round-off band, or a singular factor)."""
        x = float(x)
        if x not in counts:
            K = _K(x, kH, theta, path(x), n)
            delta = ROUNDOFF_FACTOR * np.finfo(float).eps * np.linalg.norm(K, 1)
            eye = np.eye(len(K))
            below, above = (_negative_eigenvalues(K + s * delta * eye) for s in (1.0, -1.0))
            counts[x] = (min(below, max_index) if below is not None and below == above
                         else int(np.sum(ev(x)[0] < 0)))
        return counts[x]

    def split(a, b, na, nb, depth=0):
        """Brackets (a, b, j) of single crossings of eigenvalue j in [a, b], ``na`` and
        ``nb`` the counts at the ends (bisect where several eigenvalues cross: close
        pairs of modes of thick plates)."""
        if na == nb:
            return []
        if abs(na - nb) == 1:
            return [(a, b, min(na, nb))]
        if depth >= MAX_SPLIT:
            raise ConvergenceError(f"{abs(na - nb)} eigenvalues cross zero in [{a}, {b}] at "
                                   f"kH={kH}, theta={theta} after {depth} bisections")
        m = 0.5 * (a + b)
        nm = count(m)
        return split(a, m, na, nm, depth + 1) + split(m, b, nm, nb, depth + 1)

    ell = _elliptic_grid(g, theta, path)
    ns = [count(x) if e else None for x, e in zip(g, ell, strict=True)]
    found = [br for i in range(len(g) - 1) if ell[i] and ell[i + 1]
             for br in split(g[i], g[i + 1], ns[i], ns[i + 1])]
    out = []
    for a, b, j in found:
        ea, eb = ev(a), ev(b)
        noise = max(ea[1], eb[1])
        # root round-off: eigenvalue round-off over its secant slope on the bracket
        spread = noise * (b - a) / max(abs(eb[0][j] - ea[0][j]), np.finfo(float).tiny)
        for e in (ea, eb):
            # an end inside the round-off band: refused unless the end merely lies
            # near the root and the slope resolves the root (grid point on the root)
            if abs(e[0][j]) < ROUNDOFF_FACTOR * e[1] and spread > FE_ROOT_ROUNDOFF:
                raise ConvergenceError(
                    f"eigenvalue crossing in [{a:.6g}, {b:.6g}] at kH={kH}, "
                    f"theta={theta} is within round-off of K (|e| = {abs(e[0][j]):.2e}, "
                    f"eps ||K|| = {e[1]:.2e}, root round-off {spread:.1e}): the FE "
                    "cannot resolve this thin plate")
        # located to the root's round-off (a narrower bracket only picks one of the
        # random sign changes inside it), or to XTOL_ROOT where that is smaller
        out.append(bracketed_root(lambda x, j=j: ev(x, j), a, b,
                                  xtol=max(XTOL_ROOT, spread), rtol=RTOL_ROOT,
                                  what=f"FE eigenvalue {j} at kH={kH}, theta={theta}"
                                  ).root)
    return np.asarray(out)


#: relative tolerance of the FE roots (brentq's floor is 4 eps = 8.9e-16): the roots are
#: resolved to their round-off or XTOL_ROOT, far above it
RTOL_ROOT = 1e-15


#: bisections of a scan interval in which several eigenvalues cross zero (modes of a
#: thick plate come in close pairs, ~exp(-kH) apart): 30 halvings reach 1e-9 x the
#: interval
MAX_SPLIT = 30


#: an eigenvalue sign change counts as a crossing only where the eigenvalue at both
#: bracket ends exceeds this multiple of eps ||K||_1 (its round-off); genuine crossings
#: measured >= 1e3 x above it on the windows of the datasets
ROUNDOFF_FACTOR = 100.0


#: largest round-off of an FE root, eps ||K||_1 / |de/dlam| (secant slope on the bracket),
#: accepted when a bracket end lies inside the ROUNDOFF_FACTOR band (a grid point within
#: ~1e-5 of the root): a tenth of the 1e-5 to which the two methods must agree, and eps
#: ||K||_1 overstates the measured eigenvalue round-off ~3x. Resolved roots measured
#: <= 1e-7 (kH = 0.25), drowned ones (thin plates in tension) >= 1e-4
FE_ROOT_ROUNDOFF = 1e-6
