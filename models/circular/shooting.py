"""Annulus B by shooting from the frame inwards, with complex-step sensitivities.

Method (independent of :mod:`debench.models.circular.collocation`: no shared code beyond the
parameter dataclass). In ``t = ln(R/R_A)``, ``t in [0, T]``, ``T = ln(R_B/R_A)``, the
annulus ODE is (3.34)-(3.35) (``equilibrium="printed"``) or the thin-membrane balance
d(R T1)/dR = T2 (``"membrane"``). At the frame lambda_2(T) = lamP (3.38) is known; the
radial stretch there, ``q = lambda_1(T)``, is the shooting parameter. Integrating inwards
with the classical fixed-step Runge-Kutta method (order 4) gives, for every q at once
(vectorised over arrays of q), the interface state lambda = lambda_2(0) (= lambda^(A),
3.31) and lambda_1(0), hence T1^(B)(R_A). The branch is thus parametrised by q and needs
no Newton iteration; the stretch of circle A is a computed output.

Sensitivities d/dq of every output are obtained exactly (to rounding) by the complex-step
method applied to the discrete integrator, q -> q + i h, h = 1e-30: they are the
derivatives of the discrete solution, which is what event location needs.

Stress functions here are hand-written from (3.36)-(3.37) (Gent, per unit mu):
    sigma_i = g (lambda_i^2 - lambda_1^-2 lambda_2^-2),  g = 1/(1 - (I1 - 3)/Jm).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from debench.models import validation as v
from debench.models.errors import ConvergenceError

from .params import Annulus

#: Default RK4 steps in t. Discretisation error (order 4, test_ch3_solvers), measured
#: against 3200 steps for lamP in 1.1..5 up to lambda = 7.5: <= 8e-6 absolute in T1/mu and
#: <= 1.3e-6 relative in lambda_1(R_A), the worst case being lamP = 3 beyond loss of
#: tension; loss of tension itself moves by 1e-6. Far below the printed digits of any
#: thesis value; cross-checks against collocation use 4x more steps.
DEFAULT_STEPS = 200
CSTEP = 1e-30


def _grid(T: float, steps: int) -> np.ndarray:
    """Uniform t nodes from T down to 0 (graded grids were tried: no gain, see notes)."""
    return np.linspace(T, 0.0, steps + 1)


def _stresses(l1, l2, kappa):
    """sigma1, sigma2, d sigma1/d l1, d sigma1/d l2 (3.36)-(3.37) per mu, and 1 - (I1-3)/Jm."""
    l1s = l1 * l1
    l2s = l2 * l2
    J = 1.0 / (l1s * l2s)                    # lambda_3^2
    den = 1.0 - kappa * (l1s + l2s + J - 3.0)
    g = 1.0 / den
    a1 = l1s - J
    s1 = g * a1
    s2 = g * (l2s - J)
    Jl1 = J / l1
    Jl2 = J / l2
    if kappa:
        ga = kappa * g * s1                  # a1 kappa g^2
        s1_1 = 2 * (g * (l1 + Jl1) + ga * (l1 - Jl1))
        s1_2 = 2 * (g * Jl2 + ga * (l2 - Jl2))
    else:
        s1_1 = 2 * (l1 + Jl1)
        s1_2 = 2 * Jl2
    return s1, s2, s1_1, s1_2, den


def _rhs_reference(l1, l2, kappa, membrane):
    """The right-hand side written term by term from (3.34)-(3.37) (the reference
    transcription that :func:`_rhs` rearranges; tests compare them)."""
    s1, s2, s1_1, s1_2, den = _stresses(l1, l2, kappa)
    d12 = l1 - l2
    if membrane:
        T1 = s1 / l1
        T1_1 = (s1_1 - T1) / l1
        f1 = (s2 / l2 - T1 - (s1_2 / l1) * d12) / T1_1
        slope = T1_1
    else:
        f1 = (l1 * (s2 - s1) - s1_2 * d12 * l2) / (l2 * s1_1)
        slope = s1_1
    return f1, d12, den, slope


def _rhs(l1, l2, kappa, membrane):
    """d(lambda_1, lambda_2)/dt, the Gent factor 1 - (I1-3)/Jm (None when kappa = 0) and a
    quantity with the sign of the radial slope (d sigma1/d l1, or dT1/dl1 for the membrane
    balance) where the Gent factor is positive: the admissibility checks of the integrator.

    The terms of :func:`_rhs_reference` with the common factor g = 1/(1 - (I1-3)/Jm)
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
        den += 1.0 + 3.0 * kappa
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


def _check(annulus, q, steps, lamP):
    v.instance("annulus", annulus, Annulus)
    v.integer_at_least("steps", steps, 4)
    q = v.positive("q", q, complex_ok=True)
    if lamP is not None:
        v.positive("lamP", lamP)
    return q


def integrate_inward(annulus: Annulus, q, *, steps: int = DEFAULT_STEPS,
                     profile: bool = False, lamP=None):
    """RK4 from t = T (lambda_1 = q, lambda_2 = lamP) to t = 0.

    Returns (l1, l2) at t = 0 (arrays like q, complex if q is). With ``profile=True``
    also returns t and the (steps+1, ...) arrays.

    Raises
    ------
    ValueError
        for bad arguments (q <= 0 or not finite, steps < 4), or when a trajectory leaves
        the admissible set (lambda_1 <= 0, Gent locking, loss of ellipticity of the radial
        equation) before R_A: no annulus state exists for that q.
    """
    _check(annulus, q, steps, lamP)
    out = _integrate_inward(annulus, q, steps=steps, profile=profile, lamP=lamP)
    _require_admissible(annulus, q, out[0])
    return out


def _require_admissible(annulus, q, l1):
    bad = ~np.isfinite(np.real(l1))
    if np.any(bad):
        raise ValueError(f"q = {v._show(np.real(np.asarray(q))[bad])} gives a trajectory that "
                         f"leaves the admissible set (Gent locking, lambda_1 <= 0 or loss "
                         f"of ellipticity) before R_A for {annulus}")


#: batches of at most this many trajectories are integrated one by one in Python scalar
#: arithmetic (the same :func:`_rhs`): a numpy call costs ~1 us whatever the array size, so
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


def _integrate_inward(annulus: Annulus, q, *, steps: int = DEFAULT_STEPS,
                      profile: bool = False, lamP=None, membrane=None):
    """:func:`integrate_inward` without checks: NaN marks inadmissible trajectories.

    Admissibility: the Gent energy is defined (1 - (I1-3)/Jm > 0) and the radial equation
    elliptic (slope > 0) at every RK4 stage, and lambda_1 > 0 at R_A. ``lamP`` and
    ``membrane`` (bool array: thin-membrane balance, else (3.33) as printed), broadcast
    with q, override the annulus' pre-stretch and equilibrium per trajectory, so that
    annuli differing only in these are integrated in one batch.
    """
    q = np.asarray(q)
    membrane = _membrane_flags(annulus, membrane, q.shape)
    if not profile and q.size <= SCALAR_BATCH:
        return _integrate_scalars(annulus, q, steps, lamP, membrane)
    if isinstance(membrane, np.ndarray):
        # a mixed batch: integrate it ordered (printed first), then restore the order
        order = np.argsort(membrane.ravel(), kind="stable")
        lp = np.broadcast_to(np.asarray(annulus.lamP if lamP is None else lamP, float),
                             q.shape).ravel()[order]
        out = _integrate_inward(annulus, q.ravel()[order], steps=steps, profile=profile,
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
    """:func:`_integrate_inward` of a 1-D batch in consecutive pieces of equal size, at most
    ``limit`` trajectories (``membrane``: a bool or a :class:`_Split` of the whole batch).
    Equal pieces of a batch above ``limit`` hold at least ``limit / 2`` trajectories, so
    that none falls to the scalar path (whose rounding differs in the last bit)."""
    lp = None if lamP is None else np.broadcast_to(np.asarray(lamP, float), q.shape)
    l1, l2 = [], []
    cuts = np.linspace(0, q.size, -(-q.size // limit) + 1).round().astype(int)
    for s, e in zip(cuts[:-1], cuts[1:], strict=True):
        mem = (np.arange(s, e) >= membrane.k) if isinstance(membrane, _Split) else membrane
        a, b = _integrate_inward(annulus, q[s:e], steps=steps,
                                 lamP=None if lp is None else lp[s:e], membrane=mem)
        l1.append(a)
        l2.append(b)
    return np.concatenate(l1), np.concatenate(l2)


def _rhs_stacked(Y, kappa, k_printed, out, worst):
    """:func:`_rhs` on the stacked state ``Y = (lambda_1, lambda_2)`` (shape (2, ...)),
    written into ``out`` (same shape), with the admissibility quantities folded into the
    running minimum ``worst`` (the Gent factor and the slope, as the integrator checks).

    The same factored terms as :func:`_rhs`, evaluated with fewer array operations (the
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
        den += 1.0 + 3.0 * kappa      # 1 - (I1 - 3)/Jm
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
    """:func:`_integrate_inward` for a small batch, one trajectory at a time in Python
    scalar arithmetic (same RK4 steps, same :func:`_rhs`, same admissibility rule)."""
    cplx = np.iscomplexobj(q)
    conv = complex if cplx else float
    lp = np.broadcast_to(np.asarray(annulus.lamP if lamP is None else lamP, float), q.shape)
    mem = np.broadcast_to(np.asarray(membrane, bool), q.shape)
    kappa = annulus.kappa
    tgrid = _grid(np.log(annulus.radius_ratio), steps)
    hs = [float(tgrid[k + 1] - tgrid[k]) for k in range(steps)]
    out1 = np.full(q.shape, np.nan, np.complex128 if cplx else np.float64)
    out2 = out1.copy()

    def rhs(x1, x2):
        f1, f2, d, s = _rhs(x1, x2, kappa, membrane)
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
                a1, a2 = rhs(l1, l2)
                b1, b2 = rhs(l1 + hh * a1, l2 + hh * a2)
                c1, c2 = rhs(l1 + hh * b1, l2 + hh * b2)
                e1, e2 = rhs(l1 + h * c1, l2 + h * c2)
                l1 = l1 + h / 6 * (a1 + 2.0 * (b1 + c1) + e1)
                l2 = l2 + h / 6 * (a2 + 2.0 * (b2 + c2) + e2)
            rhs(l1, l2)
            if not (l1.real > 0 and math.isfinite(l1.real) and math.isfinite(l2.real)):
                raise _Inadmissible
        except (_Inadmissible, ZeroDivisionError, OverflowError):
            continue   # NaN: no annulus state for this q
        out1[idx], out2[idx] = l1, l2
    return out1, out2


class _Inadmissible(Exception):
    """A trajectory left the admissible set (internal to :func:`_integrate_scalars`)."""


def _integrate_inward_reference(annulus: Annulus, q, *, steps: int = DEFAULT_STEPS,
                      profile: bool = False, lamP=None):
    """The plain RK4 loop over :func:`_rhs_reference` (the transcription that
    :func:`_integrate_inward` optimises; kept for the tests and benchmarks that compare
    them: same steps, same results to rounding)."""
    q = np.asarray(q)
    l1, l2, tgrid, bad, P1, P2 = _start(annulus, q, steps, lamP, profile)
    kappa = annulus.kappa
    membrane = annulus.equilibrium == "membrane"
    with np.errstate(all="ignore"):
        # admissibility: Gent energy defined (den > 0) and radial equation elliptic
        # (slope > 0) at every stage; tracked as a running minimum (real parts)
        worst = np.full(l1.shape, np.inf)
        for k in range(steps):
            h = tgrid[k + 1] - tgrid[k]
            a1, a2, d, s = _rhs_reference(l1, l2, kappa, membrane)
            worst = np.minimum(worst, np.minimum(d.real, s.real))
            b1, b2, d, s = _rhs_reference(l1 + 0.5 * h * a1, l2 + 0.5 * h * a2, kappa, membrane)
            worst = np.minimum(worst, np.minimum(d.real, s.real))
            c1, c2, d, s = _rhs_reference(l1 + 0.5 * h * b1, l2 + 0.5 * h * b2, kappa, membrane)
            worst = np.minimum(worst, np.minimum(d.real, s.real))
            e1, e2, d, s = _rhs_reference(l1 + h * c1, l2 + h * c2, kappa, membrane)
            worst = np.minimum(worst, np.minimum(d.real, s.real))
            l1 = l1 + h / 6 * (a1 + 2 * b1 + 2 * c1 + e1)
            l2 = l2 + h / 6 * (a2 + 2 * b2 + 2 * c2 + e2)
            if profile:
                P1[k + 1], P2[k + 1] = l1, l2
        _, _, d, s = _rhs_reference(l1, l2, kappa, membrane)
        worst = np.minimum(worst, np.minimum(d.real, s.real))
        bad |= ~(worst > 0) | ~(l1.real > 0) | ~np.isfinite(l1.real) | ~np.isfinite(l2.real)
    l1 = np.where(bad, np.nan, l1)
    l2 = np.where(bad, np.nan, l2)
    if profile:
        return l1, l2, tgrid, P1, P2
    return l1, l2



@dataclass(frozen=True)
class InterfaceState:
    """Annulus state at R = R_A for shooting parameters q (arrays), with d/dq.

    ``lam`` is lambda_2^(B)(R_A) = stretch of circle A (3.31); ``lam1`` is
    lambda_1^(B)(R_A); ``T1`` = sigma1^(B)/lambda_1 at R_A per unit mu (3.17).
    ``dlam``, ``dlam1``, ``dT1`` are their derivatives with respect to q.
    """

    q: np.ndarray
    lam: np.ndarray
    lam1: np.ndarray
    T1: np.ndarray
    dlam: np.ndarray
    dlam1: np.ndarray
    dT1: np.ndarray
    lam_c: np.ndarray    # complex-perturbed values, for chaining complex-step derivatives
    T1_c: np.ndarray


def interface_state(annulus: Annulus, q, *, steps: int = DEFAULT_STEPS,
                    lamP=None) -> InterfaceState:
    """Interface state and its exact q-sensitivities (complex step through RK4).

    ``lamP`` (optional, broadcast with q) overrides ``annulus.lamP`` per trajectory.
    Raises ValueError for bad arguments or an inadmissible trajectory (see
    :func:`integrate_inward`).
    """
    v.finite("q", q)
    _check(annulus, q, steps, lamP)
    st = _interface_state(annulus, q, steps=steps, lamP=lamP)
    _require_admissible(annulus, q, st.lam1 + st.lam + st.T1)
    return st


@dataclass(frozen=True)
class _Request:
    """One integration a solver asks :func:`_lockstep` for: RK4 from the frame inwards for
    the shooting parameters ``q`` (1-D, real or complex), with per-trajectory pre-stretch
    ``lamP`` and balance ``membrane`` (bool: thin-membrane, else (3.33) as printed) of
    annuli like ``annulus`` (its R_B/R_A and Jm), ``steps`` RK4 steps."""

    annulus: Annulus
    q: np.ndarray
    lamP: np.ndarray
    membrane: np.ndarray
    steps: int

    @classmethod
    def of(cls, annulus: Annulus, q, steps: int, lamP=None, membrane=None) -> _Request:
        """The request of :func:`_integrate_inward` ``(annulus, q, steps, lamP, membrane)``
        (None: the annulus' own pre-stretch and equilibrium), flattened."""
        q = np.asarray(q)
        lp = np.broadcast_to(np.asarray(annulus.lamP if lamP is None else lamP, float),
                             q.shape)
        mb = np.broadcast_to(np.asarray(annulus.equilibrium == "membrane" if membrane is None
                                        else membrane, bool), q.shape)
        return cls(annulus, q.ravel(), lp.ravel(), mb.ravel(), int(steps))


def _lockstep(solvers) -> list:
    """Run iterative solvers side by side, one shooting integration per round for all.

    Each solver is a generator that yields a :class:`_Request` and receives the (lambda_1,
    lambda_2) at R_A of its trajectories (as :func:`_integrate_inward`: NaN where
    inadmissible), until it returns its result. Every round integrates the pending
    requests of all solvers together (grouped by real/complex, R_B/R_A, Jm and steps:
    real ones first, so that a solver may follow a real integration by a complex one in
    the same round): the fixed cost of an integration (~30 ms of numpy calls for 200
    steps, whatever the batch) is paid once per round instead of once per solver and
    iteration. Returns the solvers' results in order; a solver's exception propagates.
    """
    solvers = list(solvers)
    results = [None] * len(solvers)
    pending: dict = {}

    def advance(k, value):
        try:
            pending[k] = solvers[k].send(value)
        except StopIteration as stop:
            pending.pop(k, None)
            results[k] = stop.value

    for k in range(len(solvers)):
        advance(k, None)
    while pending:
        for cplx in (False, True):
            groups: dict = {}
            for k, r in pending.items():
                if np.iscomplexobj(r.q) == cplx:
                    key = (r.annulus.radius_ratio, r.annulus.Jm, r.steps)
                    groups.setdefault(key, []).append(k)
            for ks in groups.values():
                reqs = [pending[k] for k in ks]
                l1, l2 = _integrate_inward(
                    reqs[0].annulus, np.concatenate([r.q for r in reqs]),
                    steps=reqs[0].steps, lamP=np.concatenate([r.lamP for r in reqs]),
                    membrane=np.concatenate([r.membrane for r in reqs]))
                ends = np.cumsum([0] + [r.q.size for r in reqs])
                for k, a, b in zip(ks, ends[:-1], ends[1:], strict=True):
                    advance(k, (l1[a:b], l2[a:b]))
    return results


def _run(solver):
    """:func:`_lockstep` of one solver: its result."""
    return _lockstep([solver])[0]


def _interface_state(annulus: Annulus, q, *, steps: int = DEFAULT_STEPS,
                     lamP=None, membrane=None) -> InterfaceState:
    """:func:`interface_state` without checks: NaN marks inadmissible trajectories
    (``lamP``, ``membrane``: per-trajectory overrides, see :func:`_integrate_inward`)."""
    return _run(_interface_state_gen(annulus, q, steps=steps, lamP=lamP, membrane=membrane))


def _interface_state_gen(annulus: Annulus, q, *, steps: int = DEFAULT_STEPS,
                         lamP=None, membrane=None):
    """:func:`_interface_state` as a :func:`_lockstep` solver."""
    q = np.asarray(q, dtype=float)
    l1, l2 = yield _Request.of(annulus, q + 1j * CSTEP, steps, lamP, membrane)
    l1, l2 = l1.reshape(q.shape), l2.reshape(q.shape)
    with np.errstate(all="ignore"):  # NaN marks inadmissible trajectories, by design
        s1, *_ = _stresses(l1, l2, annulus.kappa)
        T1 = s1 / l1
    return InterfaceState(q=q, lam=l2.real, lam1=l1.real, T1=T1.real,
                          dlam=l2.imag / CSTEP, dlam1=l1.imag / CSTEP,
                          dT1=T1.imag / CSTEP, lam_c=l2, T1_c=T1)


def q_for_stretch(annulus: Annulus, lam, q0, *, steps: int = DEFAULT_STEPS,
                  rtol: float = 1e-13, maxiter: int = 30) -> np.ndarray:
    """Newton on q so that lambda_2(R_A) = lam (vectorised); raises ConvergenceError.

    Converged when every Newton step satisfies ``|dq| <= rtol |q|`` (``rtol`` a finite
    tolerance in (0, 1), ``maxiter >= 1``); ``lam >= 1`` and ``q0 > 0`` finite.
    """
    v.instance("annulus", annulus, Annulus)
    lam = np.asarray(v.at_least("lam", lam, 1.0), dtype=float)
    q0 = v.positive("q0", q0)
    v.integer_at_least("steps", steps, 4)
    v.tolerance("rtol", rtol)
    v.integer_at_least("maxiter", maxiter, 1)
    q = np.array(q0, dtype=float) * np.ones_like(lam)
    for _ in range(maxiter):
        st = _interface_state(annulus, q, steps=steps)
        r = st.lam - lam
        if np.any(~np.isfinite(r)):
            raise ConvergenceError(
                f"shooting: trajectory left the admissible set for {annulus} near "
                f"lam = {lam[~np.isfinite(r)][:3]}")
        dq = r / st.dlam
        q = q - dq
        if np.all(np.abs(dq) <= rtol * np.abs(q)):
            return q
    raise ConvergenceError(f"shooting Newton: max |dq| = {np.max(np.abs(dq)):.3g} after "
                           f"{maxiter} iterations for {annulus}")
