"""Fibre in the plane of the plate (beyond the thesis): incremental bifurcation, two methods.

The thesis (Sec. 4.3) puts the fibre direction A through the thickness. Here
A = (cos theta, 0, sin theta) lies in the plane of the plate, at the angle ``theta`` to
the wave vector k e1, for the transversely isotropic energy (4.22) under charge control
(Dhat fixed), equibiaxial stretch F = diag(lam, lam^-2, lam), mu = eps = 1.

Incremental problem (derived in ``tools/derive_ch4_inplane.py``): fields
exp(i k x1) g(x2), independent of x3; three displacement components. With the stream
functions u1 = psi_2, u2 = -psi_1 (incompressible), Ddot = (phi_2, -phi_1, Dd3)
(divergence free) and Dd3 eliminated by Edot3 = 0 (uniform in a periodic field), the
unknowns are (psi, u3, phi). For theta = 0 and 90 degrees u3 decouples and the problem is
the plane-strain one of the thesis with modified moduli (theta = 90: the fibre is along
x3 and drops out, the isotropic plate); for intermediate theta the fibre couples the
antiplane displacement u3 to the in-plane one.

The base state, the energy matrix, the symbol, its characteristic roots and plane strong
ellipticity are :mod:`debench.models.plate.inplane_symbol` (imported here, part of this
module's API).

Method 1 (:func:`det_function`): the eight roots s of the characteristic polynomial
det P(1, i s) = 0 (P the symbol of the Euler-Lagrange operator), amplitudes from the
adjugate of P, and the 8 x 8 determinant of the boundary rows (T0_21, T0_22, T0_23,
Edot_1) = 0 on both faces. Divided by the Vandermonde product of the roots the
determinant is a symmetric, hence ordering-free, function of the roots; its phase is
constant, and its real part after removing that phase changes sign at a bifurcation.

Method 2 (:mod:`debench.models.plate.inplane_fe`): Galerkin discretisation of the
Hermitian energy through the thickness; lam_cr is where an eigenvalue of the stiffness K
crosses zero.

Voltage control (keyword ``Vhat`` of the scans): with compliant electrodes on both faces
the incremental boundary-value problem is the one of charge control (the fibre does not
enter the electric part of (4.22)); only the base state changes, Dhat(lam) =
Vhat lam^2/(alpha lam^4 + beta) along the scan
(:func:`debench.models.plate.voltage.dhat_at_voltage`, re-derived there from (4.20)).

Stretches above 1 (equibiaxial tension) are in the range of every function: with a field
the total lateral stress tau11 of :func:`base_state` is compressive near lam = 1 and the
plate can wrinkle in tension; as kH -> 0 the critical stretch tends to the zero of
tau11 (membrane limit, :func:`membrane_limit`).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from debench.models import validation as v
from debench.models.errors import ConvergenceError
from debench.models.numerics.roots import bisect_boundary, regula_falsi_many, scan_roots
from debench.models.numerics.scan import grid_samples, refine_samples, sign_change_brackets
from debench.models.plate.ansatz import critical_stretches
from debench.models.plate.coefficients import PlateParams
from debench.models.plate.inplane_symbol import (  # noqa: F401 - the symbol's public API
    _B,
    _S,
    LAM_RANGE,
    N_DIRECTIONS,
    _check,
    _elliptic,
    _elliptic_grid,
    _roots,
    _roots_many,
    _symbol,
    base_state,
    characteristic_roots,
    energy_matrix,
    strongly_elliptic,
    symbol,
)
from debench.models.plate.voltage import critical_stretches_at_voltage, dhat_at_voltage

#: fixed real weights combining the adjugate columns into one amplitude vector (any
#: generic vector works; fixed so that the determinant is a function of the roots only).
#: adj P(s_j) = n_j m_j^T at a root, so the amplitude n_j (m_j . w) and the determinant
#: carry the factor prod_j (m_j . w), whose zeros are spurious sign changes; one can fall
#: in the same scan interval as a genuine root and hide it (seen at xi = 5, theta = 30,
#: kH = 0.80: a pair 4e-5 apart). The scan uses two weight vectors, whose spurious zeros
#: differ, and keeps the union of the roots that pass :data:`SINGULAR_TOL`.
_WS = np.array([[1.0, 0.7310, 0.5270], [0.4130, -1.0, 0.8620]])
_W = _WS[0]


def _boundary_rows(S, s, w=_W, adj=None):
    """Rows (T21, T22, T23, E1) per unit amplitude of each root, shape (..., 4, len(s));
    ``S`` (..., 8, 8) and ``s`` (..., 8) may carry a leading stack axis; ``adj``: the
    adjugate of the symbol at the roots when already known."""
    if adj is None:
        adj = _adjugate(_symbol(S, s))
    amp = adj @ w                                           # (..., n, 3)
    z = np.einsum("...nai,...ni->...na", _B(1.0, 1j * s), amp)   # (..., n, 8)
    Sz = z @ np.swapaxes(S, -1, -2)
    pdot = Sz[..., 0] + 1j * s * Sz[..., 1]                 # from x1-equilibrium
    return np.stack([Sz[..., 1], Sz[..., 3] - pdot, Sz[..., 5], Sz[..., 6]], axis=-2)


def _adjugate(M):
    """Adjugate of 3 x 3 matrices (stacked): columns r1 x r2, r2 x r0, r0 x r1 of the rows."""
    r0, r1, r2 = M[..., 0, :], M[..., 1, :], M[..., 2, :]

    def cross(a, b):
        return np.stack([a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
                         a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                         a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]], axis=-1)

    return np.stack([cross(r1, r2), cross(r2, r0), cross(r0, r1)], axis=-1)


def det_function(lam: float, kH: float, theta: float, params: PlateParams) -> complex:
    """Method 1: boundary determinant / Vandermonde(roots), complex of constant phase.

    ``kH`` is the wavenumber times the reference thickness H; the current thickness is
    h = lam^-2 H, faces at k x2 = +- t/2, t = kH lam^-2. Each column is scaled by the
    positive factor exp(-|Re s| t / 2) (symmetric in the roots, keeps the phase).
    """
    lam, theta = _check(lam, theta, params)
    kH = v.positive("kH", kH)
    return _det(lam, kH, theta, params)


def _det(lam, kH, theta, p, w=_W):
    return complex(_det_weighted(_det_parts(lam, kH, theta, p), w))


def _det_parts(lam, kH, theta, p):
    """What the determinant needs at one stretch, independent of the weight vector:
    (S, roots, adjugate of the symbol at the roots, thickness t)."""
    S = _S(lam, theta, p)
    s = _roots(S)
    return S, s, _adjugate(_symbol(S, s)), kH * lam**-2


def _det_weighted(parts, w):
    """:func:`det_function` from :func:`_det_parts` (one stretch, or stacked along a
    leading axis by :func:`_det_parts_points`) and the weight vector ``w``."""
    s = parts[1]
    i, j = np.triu_indices(8, 1)
    vd = np.prod(s[..., j] - s[..., i], axis=-1)
    return np.linalg.det(_boundary_matrix(parts, w)) / vd


def _boundary_matrix(parts, w):
    """The 8 x 8 boundary matrix (rows T21, T22, T23, E1 on the faces k x2 = -+ t/2, one
    column per characteristic root, scaled by exp(-|Re s| t / 2)) from :func:`_det_parts`
    and the weight vector ``w``; stacked like ``parts``."""
    S, s, adj, t = parts
    rows = _boundary_rows(S, s, w, adj)                     # (..., 4, 8)
    t = np.asarray(t, float)[..., None]
    scale = np.exp(-np.abs(s.real) * t / 2)
    top = rows * (np.exp(-s * t / 2) * scale)[..., None, :]
    bot = rows * (np.exp(s * t / 2) * scale)[..., None, :]
    return np.concatenate([top, bot], axis=-2)


def _singularity_ratio(M):
    """sigma_min / sigma_max of the boundary matrices ``M`` (stacked) with unit columns: a
    column scaled by a weight factor prod_j (m_j . w) keeps its direction, so the ratio
    has none of the spurious zeros of the determinant."""
    norm = np.linalg.norm(M, axis=-2, keepdims=True)
    sv = np.linalg.svd(M / np.where(norm > 0, norm, 1.0), compute_uv=False)
    return sv[..., -1] / sv[..., 0]


def _path(params: PlateParams, Vhat):
    """lam -> parameters along the scan: fixed Dhat (charge control, ``Vhat`` None) or
    Dhat(lam) = Vhat lam^2/(alpha lam^4 + beta) at fixed voltage (``params.Dhat`` must
    then be 0: the field is set by ``Vhat``)."""
    v.instance("params", params, PlateParams)
    if Vhat is None:
        return lambda lam: params
    Vhat = float(v.nonnegative("Vhat", Vhat))
    if params.Dhat != 0.0:
        raise ValueError("params.Dhat must be 0 under voltage control (the field is set by "
                         f"Vhat), got {params.Dhat}")
    return lambda lam: replace(params, Dhat=float(dhat_at_voltage(lam, Vhat, params)))


def _det_parts_points(lam, kH, theta, paths):
    """:func:`_det_parts` at points of several scans, stacked along a leading axis:
    stretch ``lam[i]`` of the scan with thickness ``kH[i]``, angle ``theta[i]`` and
    parameters ``paths[i](lam[i])``; the roots and adjugates of all points in stacked
    calls."""
    lam = np.asarray(lam, float)
    S = np.stack([_S(x, th, path(x)) for x, th, path in zip(lam, theta, paths, strict=True)])
    s = _roots_many(S)
    adj = _adjugate(_symbol(S[:, None], s))
    return S, s, adj, np.asarray(kH, float) * lam**-2


def critical_stretches_det(kH: float, theta: float, params: PlateParams, *,
                           window=(0.45, 0.999), n_scan: int = 120,
                           Vhat: float | None = None) -> np.ndarray:
    """Method 1: every lam in ``window`` where the determinant changes sign.

    Scanned on a geometric grid (strongly elliptic points only), refined down to
    :data:`W_SCAN` beside every unresolved minimum of :func:`boundary_singularity`
    (:mod:`~debench.models.numerics.scan`: two zeros in one interval cancel); every
    sign change of either weight vector is refined at once (vectorised Illinois iteration
    to :data:`XTOL_ROOT`) and kept where it passes the bifurcation filter
    (:data:`SINGULAR_TOL`, :data:`COLLISION_TOL`). A tangency is no crossing, no root.
    The phase of :func:`det_function` is taken from the largest value on the grid and
    checked constant (ConvergenceError otherwise). ``window`` may lie below 1
    (equibiaxial compression) or above 1 (tension). ``Vhat`` (>= 0): voltage control,
    Dhat = Dhat(lam) along the scan, ``params.Dhat`` must be 0.
    """
    return critical_stretches_det_many([(kH, theta, params, {"window": window,
                                                             "n_scan": n_scan,
                                                             "Vhat": Vhat})])[0]


def critical_stretches_det_many(scans) -> list[np.ndarray]:
    """:func:`critical_stretches_det` of several scans, their grid points and their
    brackets evaluated together (one stacked evaluation per refinement step for all).

    ``scans``: a sequence of ``(kH, theta, params, kwargs)`` with the keyword arguments of
    :func:`critical_stretches_det`; returns the roots of each, in order.
    """
    if isinstance(scans, (str, bytes)) or not isinstance(scans, (list, tuple)) or not all(
            isinstance(s, (list, tuple)) and len(s) == 4 and isinstance(s[3], dict)
            for s in scans):
        raise ValueError("scans must be a sequence of (kH, theta, params, kwargs) with kwargs "
                         f"a dict, got {scans!r}")
    jobs, out = [], []
    for kH, theta, params, kw in scans:
        roots, job = _det_scan(kH, theta, params, kw)
        out.append(roots)
        if job is not None:
            jobs.append((len(out) - 1, *job))
    if jobs:
        samples = _refined_samples(jobs)
        for iw, w in enumerate(_WS):
            brackets = _rotated_brackets(*samples, iw, [out[j[0]] for j in jobs])
            if brackets:
                _refine_det_brackets(jobs, brackets, w, out)
    return [np.sort(np.asarray(r, float)) for r in out]


def _det_scan(kH, theta, params, kw):
    """One scan of :func:`critical_stretches_det_many`, its arguments validated:
    ``(roots, None)`` when it is solved here (the isotropic plate), else ``([], job)``
    with ``job = (kH, theta, path, g, ell)``: the scan's grid ``g`` from its first
    strongly elliptic point on, ``ell`` the ellipticity at each point, ``path`` its
    parameters along the scan; ``job`` None when there is nothing to search (fewer than
    two such points, or the window's upper end not elliptic)."""
    kw = {"window": (0.45, 0.999), "n_scan": 120, "Vhat": None, **kw}
    kH = v.positive("kH", kH)
    lo, hi = v.window("window", kw["window"])
    _check(lo, theta, params)
    _check(hi, theta, params)
    path = _path(params, kw["Vhat"])
    if params.xi == 0.0 or theta == 90.0:
        # u3 decouples and (psi, phi) is the isotropic plate of the thesis, whose
        # roots coincide (s = +-1 twice): the Vandermonde normalisation is undefined
        # there and the parity-split determinant of debench.models.plate.ansatz is
        # used instead
        iso = PlateParams(xi=0.0, Dhat=params.Dhat, beta=params.beta, alpha=params.alpha)
        if kw["Vhat"] is None:
            r = critical_stretches(kH, iso, window=(lo, hi)).lam
        else:
            r = critical_stretches_at_voltage(kH, kw["Vhat"], iso, window=(lo, hi))[0]
        return np.sort(np.asarray(r, float)), None
    g = np.geomspace(lo, hi, v.integer_at_least("n_scan", kw["n_scan"], 2))
    ell = _elliptic_grid(g, theta, path)
    g, ell = (g[np.argmax(ell):], ell[np.argmax(ell):]) if ell.any() else (g[:0],
                                                                         ell[:0])
    if g.size >= 2 and ell[-1]:
        return [], (kH, float(theta), path, g, ell)
    return [], None


def _evaluate_points(jobs, which, x):
    """(determinant of each weight vector of :data:`_WS` (len(_WS), n), singularity ratio
    (n,)) at the stretches ``x[i]`` of the scans ``jobs[which[i]]``, in stacked calls."""
    js = [jobs[k] for k in which]
    parts = _det_parts_points(x, [j[1] for j in js], [j[2] for j in js], [j[3] for j in js])
    return (np.stack([_det_weighted(parts, w) for w in _WS]),
            _singularity_ratio(_boundary_matrix(parts, _W)))


def _refined_samples(jobs):
    """``(samples, phases)`` of the scans of ``jobs``: the samples
    (:func:`~debench.models.numerics.scan.refine_samples`: ``[x, dets (len(_WS), n),
    ratio, usable]``, NaN where not strongly elliptic) on the grid, refined to
    :data:`W_SCAN`; the phase of each
    weight's determinant, from the grid (checked constant to :data:`PHASE_TOL` there:
    near a collision of characteristic roots refined points carry more round-off)."""
    def evaluate(which, x):
        return _evaluate_points(jobs, which, x)

    samples = grid_samples([j[4] for j in jobs], [j[5] for j in jobs], evaluate)
    phases = [[_constant_phase(d[ell], PHASE_TOL, "determinant") for d in smp[1]]
              for smp, (*_, ell) in zip(samples, jobs, strict=True)]
    refine_samples(evaluate, samples, width=W_SCAN)
    return samples, phases


def _refine_det_brackets(jobs, brackets, w, out):
    """Refine the ``brackets`` of weight vector ``w`` (``(job, phase, a, b, fa, fb)``) and append
    each root to its scan's list in ``out`` when it is a bifurcation: the boundary matrix
    singular (:data:`SINGULAR_TOL`), the characteristic roots apart
    (:data:`COLLISION_TOL`), and no root of that scan within :data:`SAME_ROOT`."""
    job_of = np.array([br[0] for br in brackets])
    phases = np.array([br[1] for br in brackets])

    def f(x, active):
        js = [jobs[k] for k in job_of[active]]
        dets = _det_weighted(_det_parts_points(x, [j[1] for j in js], [j[2] for j in js],
                                               [j[3] for j in js]), w)
        return (dets * np.conj(phases[active])).real

    # every bracket of every scan refined at once (vectorised Illinois iteration,
    # the stopping rule of brentq with xtol = XTOL_ROOT)
    roots = regula_falsi_many(f, *(np.array([br[i] for br in brackets]) for i in (2, 3, 4, 5)),
                              xtol=XTOL_ROOT).root
    for k, r in zip(job_of, roots, strict=True):
        io, kH, theta, path = jobs[k][:4]
        r = float(r)
        sing, sep = _singularity_and_separation(r, kH, theta, path(r))
        if (sing < SINGULAR_TOL and sep > COLLISION_TOL
                and not any(abs(r - q) <= SAME_ROOT for q in out[io])):
            out[io].append(r)


#: relative width to which the scan is refined around an unresolved minimum of the
#: singularity ratio (:mod:`~debench.models.numerics.scan`): two zeros of the
#: determinant closer than W_SCAN lam may share one sampled interval and cancel. Distinct
#: roots of the datasets are >= 1e-5 apart, a root and a spurious zero of one weight
#: vector >= 4e-5 (measured): 1e-8 resolves both with a 1e3 margin. The refinement
#: costs ~50 evaluations per root (2 per halving from a grid interval of ~1 %)
W_SCAN = 1e-8


#: root tolerance of the determinant roots (|b - a| <= XTOL_ROOT + 4 eps |b| at
#: convergence); a determinant root's round-off is ~1e-12 (SAME_ROOT below)
XTOL_ROOT = 1e-14


#: two scans (weight vectors) find the same root to within their brentq tolerances
#: (xtol 1e-14 + rtol 1e-15) and the root's round-off (~1e-12); 1e-9 merges them while
#: distinct roots of the datasets are >= 1e-5 apart (measured)
SAME_ROOT = 1e-9


#: a sign change of the normalised determinant is a bifurcation only where the boundary
#: matrix (unit columns) is singular: sigma_min/sigma_max there is ~1e-12 (round-off of
#: the roots and rows), while the spurious sign changes (where two characteristic roots
#: collide and the Vandermonde product vanishes) have sigma_min/sigma_max >~ 1e-4
#: (measured); 1e-8 separates the two with > 1e3 margin each way
SINGULAR_TOL = 1e-8


def boundary_singularity(lam: float, kH: float, theta: float, params: PlateParams) -> float:
    """sigma_min / sigma_max of the 8 x 8 boundary matrix with unit-norm columns."""
    lam, theta = _check(lam, theta, params)
    kH = v.positive("kH", kH)
    return _singularity_and_separation(lam, kH, theta, params)[0]


def _singularity_and_separation(lam, kH, theta, p):
    """(:func:`boundary_singularity`, smallest distance between two characteristic roots
    over the largest root modulus)."""
    parts = _det_parts(lam, kH, theta, p)
    s = parts[1]
    i, j = np.triu_indices(8, 1)
    return (float(_singularity_ratio(_boundary_matrix(parts, _W))),
            float(np.min(np.abs(s[j] - s[i])) / np.max(np.abs(s))))


#: at a collision of two characteristic roots the boundary matrix has two coinciding
#: columns, so the singularity test cannot tell it from a bifurcation; the normalised
#: determinant can touch zero there (at lam = 1 under voltage control, xi = 5, theta =
#: 60: -(lam - 1)^2 up to round-off, with round-off sign changes beside it). A root is
#: accepted only where the roots stay apart: measured separations (relative to the
#: largest |s|) <= 4.4e-9 at those collisions and >= 6.6e-3 at every root of the datasets;
#: 1e-6 is > 100x from both
COLLISION_TOL = 1e-6


#: |Im| of the phase-rotated determinant relative to its largest modulus on a scan; a
#: symmetric function of the roots has exactly constant phase, so this only flags a lost
#: root (measured |Im| / max ~ 1e-10 and below); 1e-6 leaves > 1e3 margin
PHASE_TOL = 1e-6


#: relative margin above the ellipticity limit lam_E at which a compression window
#: should start (lam_E (1 + LAM_E_MARGIN)). At theta = 0 an eigenvalue of K vanishes at
#: lam_E (the mode of the vanishing L21 modulus), linearly: e ~ 0.04 kH (lam/lam_E - 1),
#: while the round-off of K grows like eps ||K||_1 ~ kH^-3 (measured,
#: :data:`~debench.models.plate.inplane_fe.N_ELEMENTS`). Above
#: :data:`~debench.models.plate.inplane_fe.ROUNDOFF_FACTOR` x that round-off it needs a
#: relative distance of 8.7e-5 at kH = 0.25 (worst case xi = 1, Dhat = 2 of xi <= 10,
#: Dhat <= 2, Vhat <= 0.5, measured; ~kH^-4 below); 1e-3 keeps > 10x over that for
#: kH >= 0.25. Wrinkling roots lie well above lam_E, so the band left out holds none of
#: the largest roots
LAM_E_MARGIN = 1e-3


#: width in lam to which :func:`ellipticity_limit` bisects the loss of strong ellipticity:
#: ~4500 ulps at lam ~ 1, far below LAM_E_MARGIN (1e-3), the margin compression windows keep
#: above it
ELLIPTICITY_XTOL = 1e-12


def ellipticity_limit(theta: float, params: PlateParams, *, window=(0.45, 0.999),
                      n_scan: int = 200, Vhat: float | None = None) -> float:
    """Largest lam in ``window`` at which plane strong ellipticity fails (compression).

    Scanned on a geometric grid and refined by bisection to 1e-12; returns the lower end
    of ``window`` when the model is strongly elliptic on the whole window. Every root of
    :func:`critical_stretches_det` /
    :func:`~debench.models.plate.inplane_fe.critical_stretches_fe` lies above it; a
    compression window starts at lam_E (1 + :data:`LAM_E_MARGIN`), where the FE
    eigenvalue that vanishes at lam_E is clear of the round-off guard.
    ``Vhat``: voltage control as in :func:`critical_stretches_det`.
    """
    lo, hi = v.window("window", window)
    _check(lo, theta, params)
    _check(hi, theta, params)
    path = _path(params, Vhat)
    g = np.geomspace(lo, hi, v.integer_at_least("n_scan", n_scan, 2))
    ell = _elliptic_grid(g, theta, path)
    if ell.all():
        return float(lo)
    if not ell[-1]:
        return float(hi)
    i = int(np.nonzero(~ell)[0][-1])
    return float(bisect_boundary(lambda m: _elliptic(m, theta, path(m)), g[i], g[i + 1],
                                 xtol=ELLIPTICITY_XTOL, what="ellipticity limit").root)


#: scan points of :func:`membrane_limit` on its window (geometric): tau11 is a polynomial
#: in lam^2 with at most a few zeros, ~2 % apart at the least on the default window
MEMBRANE_SCAN = 400
#: root tolerance of :func:`membrane_limit`: the zero to its round-off (brentq's rtol of
#: 4 eps dominates at lam ~ 1)
MEMBRANE_XTOL = 1e-15


def membrane_limit(theta: float, params: PlateParams, *, window=(0.45, 8.0),
                   Vhat: float | None = None) -> float | None:
    """kH -> 0 limit of lam_cr: the largest zero of the total lateral stress tau11.

    A thin plate wrinkles with wave vector e1 when its membrane stress along e1,
    tau11 of :func:`base_state` (tau22 = 0), becomes compressive (the bending stiffness
    vanishes with kH; tau13 does not enter for fields independent of x3):

        tau11 = lam^2 - lam^-4 + 2 xi cos^2(theta) lam^2 (lam^2 - 1) - beta Dhat^2 = 0,

    with Dhat = Dhat(lam) under voltage control. The largest sign change on a grid of
    ``window`` refined with brentq (:func:`~debench.models.numerics.roots.scan_roots`);
    None when tau11 has no sign change in ``window``.
    """
    lo, hi = v.window("window", window)
    _check(lo, theta, params)
    _check(hi, theta, params)
    path = _path(params, Vhat)

    def tau11(x):
        return base_state(x, theta, path(x))[1]

    g = np.geomspace(lo, hi, MEMBRANE_SCAN)
    found = scan_roots(tau11, g, np.array([tau11(x) for x in g]), xtol=MEMBRANE_XTOL,
                       method="brentq", select="last", what="membrane limit (tau11 = 0)")
    return float(found.root[-1]) if found.root.size else None


def _constant_phase(vals, tol, what):
    """The phase of complex samples ``vals`` of a function of constant phase: that of its
    largest value; ConvergenceError naming ``what`` where max |Im| / max |f| of the
    rotated samples exceeds ``tol``."""
    phase = vals[np.argmax(np.abs(vals))]
    phase = phase / abs(phase)
    rot = vals * np.conj(phase)
    if np.max(np.abs(rot.imag)) > tol * np.max(np.abs(rot)):
        raise ConvergenceError(f"{what} phase not constant along the scan (max |Im|/max|f| "
                               f"= {np.max(np.abs(rot.imag)) / np.max(np.abs(rot)):.2e})")
    return phase


def _rotated_brackets(samples, phases, iw, found):
    """The sampled intervals where the quantity ``iw`` of each scan, rotated by its phase
    ``phases[k][iw]``, changes sign: ``(k, phase, a, b, fa, fb)`` each. An interval holding
    a root already in ``found[k]`` is skipped: it is that root's sign change (one root per
    sampled interval), whose refinement would only find it again."""
    brackets = []
    for k, (x, vals, _, usable) in enumerate(samples):
        phase = phases[k][iw]
        f = (vals[iw] * np.conj(phase)).real
        brackets += [(k, phase, x[i], x[i + 1], f[i], f[i + 1])
                     for i in sign_change_brackets(x, f, usable=usable)
                     if not any(x[i] <= q <= x[i + 1] for q in found[k])]
    return brackets
