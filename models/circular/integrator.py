"""The inward RK4 integration of annulus B, vectorised over shooting parameters.

The kernels of :mod:`debench.models.circular.shooting` (which checks the arguments and
turns inadmissible trajectories into errors): no argument checks here, NaN marks an
inadmissible trajectory. In ``t = ln(R/R_A)`` the annulus ODE is (3.34)-(3.35)
(equilibrium as printed, (3.33)) or the thin-membrane balance d(R T1)/dR = T2, with the
Gent stresses of (3.36)-(3.37) (per unit mu):

    sigma_i = g (lambda_i^2 - lambda_1^-2 lambda_2^-2),  g = 1/(1 - (I1 - 3)/Jm),

``1/g`` the library's Gent lock margin
(:func:`~debench.models.materials.energies.gent_lock_margin`; the optimised kernels fuse it
into in-place operations and are tested equal to the reference transcription).

* :func:`~debench.models.circular.law.gent_stresses`, :func:`rhs_reference`: the stresses
  and the right-hand side written
  term by term (the reference transcription);
* :func:`rhs`: the same right-hand side with the Gent factor cancelled, for Python
  scalars and numpy arrays alike (and its stacked form for the array path);
* :func:`integrate`: classical fixed-step RK4 from the frame (t = T) to the interface
  (t = 0) for every shooting parameter at once, real or complex (complex-step
  sensitivities), with per-trajectory pre-stretch and balance; small batches in scalar
  arithmetic, large ones in pieces;
* :func:`integrate_reference`: the plain RK4 loop over :func:`rhs_reference`, which
  :func:`integrate` optimises (same steps, same results to rounding; tests compare them).

These are the kernels of the Gent default (the annulus'
:attr:`~debench.models.circular.params.Annulus.law` a
:class:`~debench.models.circular.law.GentLaw`). For any other library elastomer
(:class:`~debench.models.circular.law.ElastomerLaw`) :func:`integrate` runs the plain loop
of :func:`integrate_reference` on the law's stresses and their derivatives: the same
(3.34)-(3.35) or membrane balance, the same RK4 steps.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .law import gent_stresses
from .params import Annulus

#: Default RK4 steps in t. Discretisation error (order 4, test_ch3_solvers), measured
#: against 3200 steps for lamP in 1.1..5 up to lambda = 7.5: <= 8e-6 absolute in T1/mu and
#: <= 1.3e-6 relative in lambda_1(R_A), the worst case being lamP = 3 beyond loss of
#: tension; loss of tension itself moves by 1e-6. Far below the printed digits of any
#: thesis value; cross-checks against collocation use 4x more steps.
DEFAULT_STEPS = 200


def _grid(T: float, steps: int) -> np.ndarray:
    """Uniform t nodes from T down to 0 (graded grids were tried: no gain, see notes)."""
    return np.linspace(T, 0.0, steps + 1)


def rhs_reference(l1, l2, kappa, membrane):
    """The right-hand side written term by term from (3.34)-(3.37) (the reference
    transcription that :func:`rhs` rearranges; tests compare them)."""
    return _rhs_of_stresses(gent_stresses(l1, l2, kappa), l1, l2, membrane)


def _rhs_of_stresses(st, l1, l2, membrane):
    """d(lambda_1, lambda_2)/dt, the margin and the slope from the stresses ``st`` =
    (s1, s2, ds1/dl1, ds1/dl2, margin) of any membrane law
    (:mod:`debench.models.circular.law`): (3.34)-(3.35), or the thin-membrane balance
    where ``membrane`` (a bool, or a bool array broadcast with the stretches) is true."""
    s1, s2, s1_1, s1_2, den = st
    d12 = l1 - l2
    if isinstance(membrane, np.ndarray):
        f1m, _, _, slm = _rhs_of_stresses(st, l1, l2, True)
        f1p, _, _, slp = _rhs_of_stresses(st, l1, l2, False)
        return np.where(membrane, f1m, f1p), d12, den, np.where(membrane, slm, slp)
    if membrane:
        T1 = s1 / l1
        T1_1 = (s1_1 - T1) / l1
        f1 = (s2 / l2 - T1 - (s1_2 / l1) * d12) / T1_1
        slope = T1_1
    else:
        f1 = (l1 * (s2 - s1) - s1_2 * d12 * l2) / (l2 * s1_1)
        slope = s1_1
    return f1, d12, den, slope


def rhs(l1, l2, kappa, membrane):
    """d(lambda_1, lambda_2)/dt, the Gent factor 1 - (I1-3)/Jm (None when kappa = 0) and a
    quantity with the sign of the radial slope (d sigma1/d l1, or dT1/dl1 for the membrane
    balance) where the Gent factor is positive: the admissibility checks of the integrator.

    The terms of :func:`rhs_reference` with the common factor g = 1/(1 - (I1-3)/Jm)
    cancelled: with J = (l1 l2)^-2, d sigma1/d l1 = 2 g A1 and d sigma1/d l2 = 2 g A2,
    ``A1 = l1 + J/l1 + kappa sigma1 (l1 - J/l1)``, ``A2 = J/l2 + kappa sigma1 (l2 - J/l2)``,
    so that (3.34) reads ``f1 = -(l1 - l2)(l1 (l1 + l2) + 2 A2 l2)/(2 l2 A1)`` and the
    membrane balance ``f1 = (l1 (l2^2 - J)/l2 - (l1^2 - J) - 2 A2 (l1 - l2))/(2 A1 -
    (l1^2 - J)/l1)``. Written with in-place operations (fewer temporaries); works on numpy
    arrays and on Python scalars alike (the small-batch path of the integrator; the array
    path evaluates the same terms on the stacked state, :func:`_rhs_stacked`).
    ``membrane``: a bool (the membrane balance, else (3.33) as printed).
    """
    i1 = 1.0 / l1
    i2 = 1.0 / l2
    J = i1 * i2
    J *= J
    l1s = l1 * l1
    a1 = l1s - J
    Jl1 = J * i1
    Jl2 = J * i2
    d12 = l1 - l2
    if kappa:
        den = l2 * l2
        den += l1s
        den += J
        den *= -kappa
        den += 1.0 + 3.0 * kappa    # the library's gent_lock_margin, fused in place
        ks1 = a1 * kappa
        ks1 /= den                  # kappa sigma1
        A1 = l1 - Jl1
        A1 *= ks1
        A1 += l1
        A1 += Jl1
        A2 = l2 - Jl2
        A2 *= ks1
        A2 += Jl2
    else:
        den = None
        A1 = l1 + Jl1
        A2 = Jl2
    if membrane:
        f1, slope = _membrane_f1(l1, l2, i1, i2, J, a1, A1, A2, d12)
    else:
        f1, slope = _printed_f1(l1, l2, A1, A2, d12)
    return f1, d12, den, slope


def _printed_f1(l1, l2, A1, A2, d12):
    """(3.34): f1 = -(l1 - l2)(l1 (l1 + l2) + 2 A2 l2)/(2 l2 A1), and A1 (slope sign)."""
    num = l1 + l2
    num *= l1
    t = A2 * l2
    num += t
    num += t
    num *= d12
    B = l2 * A1
    f1 = num / B
    f1 *= -0.5
    return f1, A1


def _membrane_f1(l1, l2, i1, i2, J, a1, A1, A2, d12):
    """Membrane balance: f1 = (l1 (l2^2 - J)/l2 - a1 - 2 A2 d12)/(2 A1 - a1/l1), and a
    quantity with the sign of dT1/dl1."""
    num = l2 * l2
    num -= J
    num *= i2
    num *= l1
    num -= a1
    t = A2 * d12
    num -= t
    num -= t
    B = A1 + A1
    t = a1 * i1
    B -= t                      # 2 A1 - a1/l1 = l1 dT1/dl1 / g
    return num / B, B * l1



#: batches of at most this many trajectories are integrated one by one in Python scalar
#: arithmetic (the same :func:`rhs`): a numpy call costs ~1 us whatever the array size, so
#: the ~35,000 calls of one vectorised integration (~25 ms) outweigh the scalar loop
#: (~1.5 ms per trajectory) below this size (measured on the 2-core reference machine)
SCALAR_BATCH = 16


@dataclass(frozen=True)
class _Split:
    """A 1-D batch whose first ``k`` trajectories use (3.33) as printed and the rest the
    membrane balance (the integrator orders a mixed batch so)."""

    k: int


def _membrane_flags(annulus: Annulus, membrane, shape):
    """The balance per trajectory: a bool when uniform, else a bool array of ``shape``
    (``membrane`` None: the annulus' own equilibrium)."""
    if membrane is None:
        return annulus.equilibrium == "membrane"
    if isinstance(membrane, _Split):
        return membrane
    m = np.broadcast_to(np.asarray(membrane, bool), shape)
    if m.size == 0:
        return annulus.equilibrium == "membrane"
    return bool(m.flat[0]) if (m.all() or not m.any()) else m


def _start(annulus: Annulus, q, steps: int, lamP, profile: bool):
    """Initial state of an inward integration: (l1, l2) at R_A, the grid in t = ln(R/R_A),
    the inadmissible starts, and the profile arrays (None without ``profile``)."""
    dtype = np.complex128 if np.iscomplexobj(q) else np.float64
    l1 = q.astype(dtype, copy=True)
    # lamP (array like q) batches annuli that differ only in the pre-stretch (3.38)
    l2 = np.full_like(l1, annulus.lamP) if lamP is None else (
        np.broadcast_to(np.asarray(lamP, float), l1.shape).astype(dtype))
    tgrid = _grid(np.log(annulus.radius_ratio), steps)
    bad = ~(l1.real > 0)
    P1 = P2 = None
    if profile:
        P1 = np.empty((steps + 1,) + l1.shape, dtype)
        P2 = np.empty_like(P1)
        P1[0], P2[0] = l1, l2
    return l1, l2, tgrid, bad, P1, P2


def integrate(annulus: Annulus, q, *, steps: int = DEFAULT_STEPS,
              profile: bool = False, lamP=None, membrane=None):
    """RK4 from t = T (lambda_1 = q, lambda_2 = lamP) to t = 0, without checks (those of
    :func:`~debench.models.circular.shooting.integrate_inward`): NaN marks inadmissible
    trajectories. Returns (l1, l2) at t = 0 (arrays like q, complex if q is); with
    ``profile=True`` also t and the (steps+1, ...) arrays.

    Admissibility: the energy is defined (Gent: 1 - (I1-3)/Jm > 0; any other elastomer:
    finite on its real domain) and the radial equation elliptic (slope > 0) at every RK4
    stage, and lambda_1 > 0 at R_A. ``lamP`` and
    ``membrane`` (bool array: thin-membrane balance, else (3.33) as printed), broadcast
    with q, override the annulus' pre-stretch and equilibrium per trajectory, so that
    annuli differing only in these are integrated in one batch.
    """
    q = np.asarray(q)
    membrane = _membrane_flags(annulus, membrane, q.shape)
    if not annulus.law.fused:
        # a library elastomer (not the Gent closed forms): the plain loop over its law
        return integrate_reference(annulus, q, steps=steps, profile=profile, lamP=lamP,
                                   membrane=membrane)
    if not profile and q.size <= SCALAR_BATCH:
        return _integrate_scalars(annulus, q, steps, lamP, membrane)
    if isinstance(membrane, np.ndarray):
        # a mixed batch: integrate it ordered (printed first), then restore the order
        order = np.argsort(membrane.ravel(), kind="stable")
        lp = np.broadcast_to(np.asarray(annulus.lamP if lamP is None else lamP, float),
                             q.shape).ravel()[order]
        out = integrate(annulus, q.ravel()[order], steps=steps, profile=profile,
                                lamP=lp, membrane=_Split(int(np.sum(~membrane))))
        back = np.empty_like(order)
        back[order] = np.arange(order.size)
        if profile:
            l1, l2, t, P1, P2 = out
            return (l1[back].reshape(q.shape), l2[back].reshape(q.shape), t,
                    P1[:, back].reshape(P1.shape[:1] + q.shape),
                    P2[:, back].reshape(P2.shape[:1] + q.shape))
        return out[0][back].reshape(q.shape), out[1][back].reshape(q.shape)
    limit = CHUNK_BYTES // (2 * q.dtype.itemsize)
    if not profile and q.ndim == 1 and q.size > limit:
        return _integrate_chunks(annulus, q, steps, lamP, membrane, limit)
    l1, l2, tgrid, bad, P1, P2 = _start(annulus, q, steps, lamP, profile)
    kappa = annulus.kappa
    worst = np.full(l1.shape, np.inf)   # running minimum of the admissibility quantities
    # the number of leading trajectories that use (3.33) as printed
    k_printed = membrane.k if isinstance(membrane, _Split) else (0 if membrane else None)
    Y = np.stack([l1, l2])              # the state (lambda_1, lambda_2), stacked
    K = [np.empty_like(Y) for _ in range(4)]
    with np.errstate(all="ignore"):
        for k in range(steps):
            h = tgrid[k + 1] - tgrid[k]
            hh = 0.5 * h
            a = _rhs_stacked(Y, kappa, k_printed, K[0], worst)
            Z = hh * a
            Z += Y
            b = _rhs_stacked(Z, kappa, k_printed, K[1], worst)
            Z = hh * b
            Z += Y
            c = _rhs_stacked(Z, kappa, k_printed, K[2], worst)
            Z = h * c
            Z += Y
            e = _rhs_stacked(Z, kappa, k_printed, K[3], worst)
            b += c
            b *= 2.0
            b += a
            b += e
            b *= h / 6
            Y = Y + b
            if profile:
                P1[k + 1], P2[k + 1] = Y[0], Y[1]
        _rhs_stacked(Y, kappa, k_printed, K[0], worst)
        l1, l2 = Y[0, ...], Y[1, ...]
        bad |= ~(worst > 0) | ~(l1.real > 0) | ~np.isfinite(l1.real) | ~np.isfinite(l2.real)
    l1 = np.where(bad, np.nan, l1)
    l2 = np.where(bad, np.nan, l2)
    if profile:
        return l1, l2, tgrid, P1, P2
    return l1, l2


#: largest stacked state (2 x batch values) integrated in one piece, in bytes: numpy
#: allocates every temporary of the right-hand side through malloc, and glibc serves
#: requests of 128 KiB and more by a fresh mmap (zeroed pages, a page fault per 4 KiB), so
#: that one step of a larger batch costs several times its arithmetic (measured on the
#: 2-core reference machine, 200 steps: 2 x 6000 complex values 0.99 s CPU in one piece,
#: 0.27 s with the threshold raised; 0.24 s as two pieces of 3000). Larger batches are
#: integrated in consecutive pieces below this size (elementwise: identical results).
CHUNK_BYTES = 128_000


def _integrate_chunks(annulus, q, steps, lamP, membrane, limit):
    """:func:`integrate` of a 1-D batch in consecutive pieces of equal size, at most
    ``limit`` trajectories (``membrane``: a bool or a :class:`_Split` of the whole batch).
    Equal pieces of a batch above ``limit`` hold at least ``limit / 2`` trajectories, so
    that none falls to the scalar path (whose rounding differs in the last bit)."""
    lp = None if lamP is None else np.broadcast_to(np.asarray(lamP, float), q.shape)
    l1, l2 = [], []
    cuts = np.linspace(0, q.size, -(-q.size // limit) + 1).round().astype(int)
    for s, e in zip(cuts[:-1], cuts[1:], strict=True):
        mem = (np.arange(s, e) >= membrane.k) if isinstance(membrane, _Split) else membrane
        a, b = integrate(annulus, q[s:e], steps=steps,
                                 lamP=None if lp is None else lp[s:e], membrane=mem)
        l1.append(a)
        l2.append(b)
    return np.concatenate(l1), np.concatenate(l2)


def _rhs_stacked(Y, kappa, k_printed, out, worst):
    """:func:`rhs` on the stacked state ``Y = (lambda_1, lambda_2)`` (shape (2, ...)),
    written into ``out`` (same shape), with the admissibility quantities folded into the
    running minimum ``worst`` (the Gent factor and the slope, as the integrator checks).

    The same factored terms as :func:`rhs`, evaluated with fewer array operations (the
    integrator's cost at small batches is the per-operation overhead): 1/lambda_i from
    one reciprocal of lambda_1 lambda_2, A1 and A2 as one stacked expression, and the
    (3.34) numerator as 2 A2 l2 + l1^2 + l1 l2. ``k_printed``: None when every
    trajectory uses (3.33) as printed, else the number of leading (1-D) trajectories
    that do (the rest: the membrane balance).
    """
    l1, l2 = Y[0, ...], Y[1, ...]     # views (0-d too)
    L = Y * Y                         # lambda_i^2
    P = l1 * l2
    R = np.reciprocal(P)
    J = R * R                         # (l1 l2)^-2 = lambda_3^2
    JI = Y[::-1] * R                  # 1/lambda_i
    invs = JI.copy() if k_printed is not None else None   # the membrane balance's
    JI *= J                           # J/lambda_i
    d12 = np.subtract(l1, l2, out=out[1, ...])
    a1 = L[0] - J
    if kappa:
        den = L[0] + L[1]
        den += J
        den *= -kappa
        den += 1.0 + 3.0 * kappa      # the library's gent_lock_margin, fused in place
        ks1 = a1 * kappa
        ks1 /= den                    # kappa sigma1
        np.minimum(worst, den.real, out=worst)
        D = Y - JI
        D *= ks1
        D += JI
    else:
        D = JI.copy()
    D[0] += l1                        # D = (A1, A2)
    A1, A2 = D[0, ...], D[1, ...]
    if k_printed is None or k_printed > 0:     # (3.34)
        s = Ellipsis if k_printed is None else slice(0, k_printed)
        num = A2[s] * l2[s]
        num += num
        num += L[0][s]
        num += P[s]
        num *= d12[s]
        B = A1[s] * l2[s]
        B *= -2.0
        np.divide(num, B, out=out[0, ...][s])
        w = worst[s]
        np.minimum(w, A1[s].real, out=w)
    if k_printed == 0 or (k_printed is not None and k_printed < l1.shape[0]):
        s = Ellipsis if k_printed == 0 else slice(k_printed, None)   # membrane balance
        x1, a1s = l1[s], a1[s]
        num = L[1][s] - J[s]
        num *= invs[1][s]
        num *= x1
        num -= a1s
        t = A2[s] * d12[s]
        t += t
        num -= t
        B = A1[s] + A1[s]
        t = a1s * invs[0][s]
        B -= t                        # 2 A1 - a1/l1 = l1 dT1/dl1 / g
        np.divide(num, B, out=out[0, ...][s])
        B *= x1
        w = worst[s]
        np.minimum(w, B.real, out=w)
    return out


def _integrate_scalars(annulus: Annulus, q: np.ndarray, steps: int, lamP, membrane):
    """:func:`integrate` for a small batch, one trajectory at a time in Python
    scalar arithmetic (same RK4 steps, same :func:`rhs`, same admissibility rule)."""
    cplx = np.iscomplexobj(q)
    conv = complex if cplx else float
    lp = np.broadcast_to(np.asarray(annulus.lamP if lamP is None else lamP, float), q.shape)
    mem = np.broadcast_to(np.asarray(membrane, bool), q.shape)
    kappa = annulus.kappa
    tgrid = _grid(np.log(annulus.radius_ratio), steps)
    hs = [float(tgrid[k + 1] - tgrid[k]) for k in range(steps)]
    out1 = np.full(q.shape, np.nan, np.complex128 if cplx else np.float64)
    out2 = out1.copy()

    def f(x1, x2):
        f1, f2, d, s = rhs(x1, x2, kappa, membrane)
        if not (s.real > 0 and (d is None or d.real > 0)):
            raise _Inadmissible
        return f1, f2

    for idx in np.ndindex(q.shape):
        l1, l2 = conv(q[idx]), conv(lp[idx])
        membrane = bool(mem[idx])
        try:
            if not l1.real > 0:
                raise _Inadmissible
            for h in hs:
                hh = 0.5 * h
                a1, a2 = f(l1, l2)
                b1, b2 = f(l1 + hh * a1, l2 + hh * a2)
                c1, c2 = f(l1 + hh * b1, l2 + hh * b2)
                e1, e2 = f(l1 + h * c1, l2 + h * c2)
                l1 = l1 + h / 6 * (a1 + 2.0 * (b1 + c1) + e1)
                l2 = l2 + h / 6 * (a2 + 2.0 * (b2 + c2) + e2)
            f(l1, l2)
            if not (l1.real > 0 and math.isfinite(l1.real) and math.isfinite(l2.real)):
                raise _Inadmissible
        except (_Inadmissible, ZeroDivisionError, OverflowError):
            continue   # NaN: no annulus state for this q
        out1[idx], out2[idx] = l1, l2
    return out1, out2


class _Inadmissible(Exception):
    """A trajectory left the admissible set (internal to :func:`_integrate_scalars`)."""


def integrate_reference(annulus: Annulus, q, *, steps: int = DEFAULT_STEPS,
                        profile: bool = False, lamP=None, membrane=None):
    """The plain RK4 loop over the right-hand side written term by term
    (:func:`rhs_reference` with the stresses of the annulus'
    :attr:`~debench.models.circular.params.Annulus.law`): the transcription that
    :func:`integrate` optimises for the Gent closed forms (same steps, same results to
    rounding; tests and benchmarks compare them), and :func:`integrate` itself for any
    other library elastomer. ``lamP``, ``membrane`` as in :func:`integrate`."""
    q = np.asarray(q)
    l1, l2, tgrid, bad, P1, P2 = _start(annulus, q, steps, lamP, profile)
    law = annulus.law
    membrane = _membrane_flags(annulus, membrane, q.shape)

    def f(x1, x2):
        return _rhs_of_stresses(law.stresses(x1, x2), x1, x2, membrane)

    with np.errstate(all="ignore"):
        # admissibility: energy defined (den > 0) and radial equation elliptic
        # (slope > 0) at every stage; tracked as a running minimum (real parts)
        worst = np.full(l1.shape, np.inf)
        for k in range(steps):
            h = tgrid[k + 1] - tgrid[k]
            a1, a2, d, s = f(l1, l2)
            worst = np.minimum(worst, np.minimum(d.real, s.real))
            b1, b2, d, s = f(l1 + 0.5 * h * a1, l2 + 0.5 * h * a2)
            worst = np.minimum(worst, np.minimum(d.real, s.real))
            c1, c2, d, s = f(l1 + 0.5 * h * b1, l2 + 0.5 * h * b2)
            worst = np.minimum(worst, np.minimum(d.real, s.real))
            e1, e2, d, s = f(l1 + h * c1, l2 + h * c2)
            worst = np.minimum(worst, np.minimum(d.real, s.real))
            l1 = l1 + h / 6 * (a1 + 2 * b1 + 2 * c1 + e1)
            l2 = l2 + h / 6 * (a2 + 2 * b2 + 2 * c2 + e2)
            if profile:
                P1[k + 1], P2[k + 1] = l1, l2
        _, _, d, s = f(l1, l2)
        worst = np.minimum(worst, np.minimum(d.real, s.real))
        bad |= ~(worst > 0) | ~(l1.real > 0) | ~np.isfinite(l1.real) | ~np.isfinite(l2.real)
    l1 = np.where(bad, np.nan, l1)
    l2 = np.where(bad, np.nan, l2)
    if profile:
        return l1, l2, tgrid, P1, P2
    return l1, l2
