# ruff: noqa
"""Frozen copy of `models/circular/shooting.py` at commit c9fb6ae (before the batched Chapter 3 pass):
the previous code path, kept only so that the benchmarks time it against the current one
in the same run. Not used by the package; imports adjusted to the package modules."""

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


from dataclasses import dataclass

import numpy as np
from debench.models import validation as v
from debench.models.errors import ConvergenceError

from debench.models.circular.params import Annulus

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


def _rhs(l1, l2, kappa, membrane):
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


def _integrate_inward(annulus: Annulus, q, *, steps: int = DEFAULT_STEPS,
                      profile: bool = False, lamP=None):
    """:func:`integrate_inward` without checks: NaN marks inadmissible trajectories."""
    q = np.asarray(q)
    dtype = np.complex128 if np.iscomplexobj(q) else np.float64
    l1 = q.astype(dtype, copy=True)
    # lamP (array like q) batches annuli that differ only in the pre-stretch (3.38)
    l2 = np.full_like(l1, annulus.lamP) if lamP is None else (
        np.broadcast_to(np.asarray(lamP, float), l1.shape).astype(dtype))
    kappa = annulus.kappa
    membrane = annulus.equilibrium == "membrane"
    tgrid = _grid(np.log(annulus.radius_ratio), steps)
    bad = ~(l1.real > 0)
    if profile:
        P1 = np.empty((steps + 1,) + l1.shape, dtype)
        P2 = np.empty_like(P1)
        P1[0], P2[0] = l1, l2
    with np.errstate(all="ignore"):
        # admissibility: Gent energy defined (den > 0) and radial equation elliptic
        # (slope > 0) at every stage; tracked as a running minimum (real parts)
        worst = np.full(l1.shape, np.inf)
        for k in range(steps):
            h = tgrid[k + 1] - tgrid[k]
            a1, a2, d, s = _rhs(l1, l2, kappa, membrane)
            worst = np.minimum(worst, np.minimum(d.real, s.real))
            b1, b2, d, s = _rhs(l1 + 0.5 * h * a1, l2 + 0.5 * h * a2, kappa, membrane)
            worst = np.minimum(worst, np.minimum(d.real, s.real))
            c1, c2, d, s = _rhs(l1 + 0.5 * h * b1, l2 + 0.5 * h * b2, kappa, membrane)
            worst = np.minimum(worst, np.minimum(d.real, s.real))
            e1, e2, d, s = _rhs(l1 + h * c1, l2 + h * c2, kappa, membrane)
            worst = np.minimum(worst, np.minimum(d.real, s.real))
            l1 = l1 + h / 6 * (a1 + 2 * b1 + 2 * c1 + e1)
            l2 = l2 + h / 6 * (a2 + 2 * b2 + 2 * c2 + e2)
            if profile:
                P1[k + 1], P2[k + 1] = l1, l2
        _, _, d, s = _rhs(l1, l2, kappa, membrane)
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


def _interface_state(annulus: Annulus, q, *, steps: int = DEFAULT_STEPS,
                     lamP=None) -> InterfaceState:
    """:func:`interface_state` without checks: NaN marks inadmissible trajectories."""
    q = np.asarray(q, dtype=float)
    l1, l2 = _integrate_inward(annulus, q + 1j * CSTEP, steps=steps, lamP=lamP)
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
