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

The right-hand sides (hand-written from (3.34)-(3.37) for the Gent default; from the
stresses of any library elastomer's membrane law, :mod:`debench.models.circular.law`,
otherwise) and the RK4 integration are in :mod:`debench.models.circular.integrator`;
the functions here check their arguments and refuse inadmissible trajectories. The
interface-state iterations are also written as :mod:`~debench.models.circular.lockstep`
solvers, so that many of them share one integration per round.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from debench.models import validation as v
from debench.models.errors import ConvergenceError
from debench.models.numerics.newton import SCALAR_STEP_RTOL

from .integrator import DEFAULT_STEPS, integrate
from .lockstep import Request, run
from .params import Annulus

#: complex-step size of the sensitivities d/dq (q -> q + i CSTEP)
CSTEP = 1e-30


def _check(annulus, q, steps, lamP):
    v.instance("annulus", annulus, Annulus)
    v.integer_at_least("steps", steps, 4)
    q = v.positive("q", q, complex_ok=True)
    if lamP is not None:
        v.positive("lamP", lamP)
    return q


def integrate_inward(annulus: Annulus, q, *, steps: int = DEFAULT_STEPS,
                     profile: bool = False, lamP=None):
    """RK4 from t = T (lambda_1 = q, lambda_2 = lamP) to t = 0: the annulus ODE
    (3.34)-(3.35) (or the membrane balance) with the stresses (3.14)-(3.15) of the
    annulus' material law: Gent (3.36)-(3.37) of ``annulus.Jm``, or the library
    ``annulus.elastomer`` (:mod:`debench.models.circular.law`).

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
    out = integrate(annulus, q, steps=steps, profile=profile, lamP=lamP)
    _require_admissible(annulus, q, out[0])
    return out


def _require_admissible(annulus, q, l1):
    bad = ~np.isfinite(np.real(l1))
    if np.any(bad):
        raise ValueError(f"q = {v._show(np.real(np.asarray(q))[bad])} gives a trajectory that "
                         f"leaves the admissible set (Gent locking, lambda_1 <= 0 or loss "
                         f"of ellipticity) before R_A for {annulus}")


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


def interface_state_solver(annulus: Annulus, q, *, steps: int = DEFAULT_STEPS, lamP=None):
    """:func:`interface_state` as a :func:`~debench.models.circular.lockstep.lockstep`
    solver, its arguments checked at the call (as :func:`interface_state`'s).

    The solver yields one (complex-step) integration request and returns the
    :class:`InterfaceState`; unlike :func:`interface_state` it does not refuse
    inadmissible trajectories: NaN marks them, so that a solver running side by side with
    others never stops them. ``lockstep.run(interface_state_solver(...))`` runs it alone.
    """
    v.finite("q", q)
    _check(annulus, q, steps, lamP)
    return _interface_state_gen(annulus, q, steps=steps, lamP=lamP)


def _interface_state(annulus: Annulus, q, *, steps: int = DEFAULT_STEPS,
                     lamP=None, membrane=None) -> InterfaceState:
    """:func:`interface_state` without checks: NaN marks inadmissible trajectories
    (``lamP``, ``membrane``: per-trajectory overrides, see
    :func:`~debench.models.circular.integrator.integrate`)."""
    return run(_interface_state_gen(annulus, q, steps=steps, lamP=lamP, membrane=membrane))


def _interface_state_gen(annulus: Annulus, q, *, steps: int = DEFAULT_STEPS,
                         lamP=None, membrane=None):
    """:func:`_interface_state` as a :func:`~debench.models.circular.lockstep.lockstep`
    solver."""
    q = np.asarray(q, dtype=float)
    l1, l2 = yield Request.of(annulus, q + 1j * CSTEP, steps, lamP, membrane)
    l1, l2 = l1.reshape(q.shape), l2.reshape(q.shape)
    with np.errstate(all="ignore"):  # NaN marks inadmissible trajectories, by design
        s1, *_ = annulus.law.stresses(l1, l2)
        T1 = s1 / l1
    return InterfaceState(q=q, lam=l2.real, lam1=l1.real, T1=T1.real,
                          dlam=l2.imag / CSTEP, dlam1=l1.imag / CSTEP,
                          dT1=T1.imag / CSTEP, lam_c=l2, T1_c=T1)


def q_for_stretch(annulus: Annulus, lam, q0, *, steps: int = DEFAULT_STEPS,
                  rtol: float = SCALAR_STEP_RTOL, maxiter: int = 30) -> np.ndarray:
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
