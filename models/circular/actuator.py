"""Voltage-stretch curves of circle A and their failure events (Zeng 2020, Sec. 3.5).

The annulus problem does not involve the voltage nor c (only lambda^(A) enters B through
(3.31)), so one annulus *branch* -- the interface stress T1^(B)(R_A) as a function of the
circle-A stretch lambda, computed once per (lamP, R_B/R_A, Jm, equilibrium) -- serves every
c and every eps_r: ``Phibar^2 = (s(lam) - lam T1B)/(lam^4 K(lam))`` (see
:mod:`models.circular.circle_a`). The branch is traced by the vectorised shooting method
(:mod:`models.circular.shooting`), parametrised by the radial stretch at the frame.

Failure events on a curve (each located by a safeguarded secant (Illinois) iteration on
the shooting parameter, to ``EVENT_XTOL`` relative, with exact complex-step derivatives):

* ``pullin``: a local maximum of Phibar(lambda) -- the electromechanical instability;
* ``minimum``: the local minimum that follows it (Gent stiffening, Zhao, Hong & Suo 2007);
* ``loss_of_tension``: sigma1^(A) = 0, i.e. T1^(B)(R_A) = 0 (Sec. 3.5.3) -- independent of
  c by construction;
* ``breakdown``: Phibar = sqrt(eps_bar/mu) E_B(lambda)/lambda^2 (Sec. 3.5.5), crossed from
  below;
* ``end``: the end of the traced branch (Gent locking / loss of admissibility).

The *failure* is the first of pullin, loss_of_tension, breakdown along increasing lambda
(the thesis terminates its curves there, Sec. 3.5.3-3.5.5); ``lam_max`` and its Phibar are
the failure point (Fig. 3.9).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.interpolate import PchipInterpolator

from models.errors import ConvergenceError

from . import circle_a
from .params import Annulus, CircularActuator, locking_stretch_equibiaxial
from .shooting import DEFAULT_STEPS, interface_state, q_for_stretch

#: relative tolerance on the shooting parameter q for event location: machine precision
#: level (q ~ 1, |d lambda/dq| ~ 1e2, so lambda is located to ~1e-12)
EVENT_XTOL = 1e-14
EVENT_KINDS = ("pullin", "minimum", "loss_of_tension", "breakdown")
FAILURE_KINDS = ("pullin", "loss_of_tension", "breakdown")


@dataclass(frozen=True)
class Branch:
    """Annulus solution along the continuation in the circle-A stretch (c-independent).

    Arrays over the stretch grid ``lam`` (= lambda^(A) = lambda_2^(B)(R_A)): ``q`` shooting
    parameter lambda_1(R_B); ``lam1`` = lambda_1^(B)(R_A); ``T1`` = T1^(B)(R_A)/mu;
    ``dlam``, ``dT1`` their q-derivatives; ``lam_end``: last admissible stretch traced.
    """

    annulus: Annulus
    lam: np.ndarray
    q: np.ndarray
    lam1: np.ndarray
    T1: np.ndarray
    dlam: np.ndarray
    dT1: np.ndarray
    lam_end: float
    steps: int

    @property
    def dT1_dlam(self) -> np.ndarray:
        return self.dT1 / self.dlam


def _scan(annulus: Annulus, steps: int, n: int = 160):
    """Coarse scan of the shooting parameter: q = lamP - delta, delta geometric."""
    delta = np.concatenate([[0.0], np.geomspace(1e-8, 0.95, n - 1) * annulus.lamP])
    st = interface_state(annulus, annulus.lamP - delta, steps=steps)
    ok = np.isfinite(st.lam) & np.isfinite(st.T1)
    first_bad = np.argmin(ok) if not ok.all() else len(ok)
    keep = slice(0, first_bad)
    lam, q = st.lam[keep], st.q[keep]
    if lam.size < 4 or np.any(np.diff(lam) <= 0):
        raise ConvergenceError(
            f"annulus branch for {annulus} is not monotone in the shooting parameter "
            "(or too short): cannot parametrise it by the circle-A stretch")
    return lam, q


def branch(annulus: Annulus, lam=None, *, n: int = 300, lam_end: float | None = None,
           steps: int = DEFAULT_STEPS) -> Branch:
    """Trace the annulus branch (vectorised shooting, no Newton iteration by default).

    Parameters
    ----------
    lam
        Exact stretches of circle A (>= lamP) at which to solve (Newton polish of the
        shooting parameter). Default: ``n`` points whose shooting parameters are
        interpolated from a coarse scan so that the stretches are nearly uniform from lamP
        to ``lam_end`` (default: the last admissible stretch, at most 0.999 of the
        circle-A Gent locking stretch); the points are exact solutions either way.
    """
    lam_scan, q_scan = _scan(annulus, steps)
    top = min(lam_scan[-1], 0.999 * locking_stretch_equibiaxial(annulus.Jm))
    if lam_end is None:
        lam_end = top
    if lam is None:
        target = np.linspace(annulus.lamP, min(lam_end, lam_scan[-1]), n)
        q = PchipInterpolator(lam_scan, q_scan)(target)
        q[0] = annulus.lamP
    else:
        lam = np.asarray(lam, dtype=float)
        if np.any(lam < annulus.lamP) or np.any(lam > top):
            raise ValueError(
                f"stretches must lie in [lamP, {top:.6g}] (the admissible branch of "
                f"{annulus}, below the circle-A Gent locking stretch); got "
                f"[{lam.min():.6g}, {lam.max():.6g}]")
        q0 = PchipInterpolator(lam_scan, q_scan)(lam)
        q = q_for_stretch(annulus, lam, q0, steps=steps)
    st = interface_state(annulus, q, steps=steps)
    if not np.all(np.isfinite(st.lam)) or np.any(np.diff(st.lam) <= 0):
        raise ConvergenceError(f"annulus branch of {annulus}: non-monotone or inadmissible "
                               "points on the interpolated grid")
    return Branch(annulus=annulus, lam=st.lam, q=q, lam1=st.lam1, T1=st.T1, dlam=st.dlam,
                  dT1=st.dT1, lam_end=float(min(lam_end, top)), steps=steps)


@dataclass(frozen=True)
class Event:
    """A failure event located on a voltage-stretch curve."""

    kind: str
    lam: float
    phibar: float
    q: float


@dataclass(frozen=True)
class Curve:
    """A voltage-stretch curve of circle A (Figs 3.4, 3.5, 3.7, 3.8) and its events.

    ``events[kind]`` is the first event of that kind along increasing lambda (or None);
    ``failure`` the first of :data:`FAILURE_KINDS`; ``lam_max``/``phibar_max`` its point.
    """

    actuator: CircularActuator
    lam: np.ndarray
    phibar: np.ndarray
    sigma1A: np.ndarray
    phibar_breakdown: np.ndarray
    events: dict = field(default_factory=dict)
    failure: Event | None = None

    @property
    def lam_max(self) -> float:
        return self.failure.lam if self.failure else math.nan

    @property
    def phibar_max(self) -> float:
        return self.failure.phibar if self.failure else math.nan

    @property
    def pullin_suppressed(self) -> bool:
        """No interior maximum of Phibar before loss of tension (definition, catalogued)."""
        p, lot = self.events.get("pullin"), self.events.get("loss_of_tension")
        return p is None or (lot is not None and p.lam >= lot.lam)


def _event_function(kinds, annulus, q, c, eps_r, mu, steps):
    """Functions whose zeros are the events, vectorised over (kind, q, c, eps_r).

    ``pullin``/``minimum``: d(Phibar^2)/d lambda (exact, complex step through the
    integrator); ``loss_of_tension``: T1^(B)(R_A); ``breakdown``: Phibar^2 - Phibar_B^2.
    """
    kinds = np.asarray(kinds)
    bad = ~np.isin(kinds, EVENT_KINDS)
    if bad.any():
        raise ValueError(f"unknown event kind {kinds[bad][0]!r}; expected one of {EVENT_KINDS}")
    st = interface_state(annulus, q, steps=steps)
    p2c = circle_a.phibar_squared(st.lam_c, st.T1_c, c, annulus.kappa)
    deriv = (p2c.imag / 1e-30) / st.dlam
    brk = p2c.real - circle_a.breakdown_phibar(st.lam, eps_r, mu) ** 2
    return np.where(kinds == "loss_of_tension", st.T1,
                    np.where(kinds == "breakdown", brk, deriv))


def locate(kinds, annulus, qa, qb, c, eps_r, mu, *, steps=DEFAULT_STEPS,
           xtol=EVENT_XTOL, maxiter=100):
    """Vectorised Illinois iteration for zeros bracketed in [qa, qb]; raises if it fails.

    All events (any kinds, any c) of one annulus are located together: one shooting
    integration per iteration.
    """
    a = np.array(qa, float)
    b = np.array(qb, float)
    kinds = np.broadcast_to(np.asarray(kinds), a.shape)
    c = np.broadcast_to(c, a.shape).astype(float)
    eps_r = np.broadcast_to(eps_r, a.shape).astype(float)
    fab = _event_function(np.concatenate([kinds, kinds]), annulus, np.concatenate([a, b]),
                          np.concatenate([c, c]), np.concatenate([eps_r, eps_r]), mu, steps)
    fa, fb = fab[: a.size], fab[a.size:]
    if np.any(np.sign(fa) * np.sign(fb) > 0) or not np.all(np.isfinite(fa * fb)):
        raise ConvergenceError(f"events {sorted(set(kinds))}: not bracketed for {annulus}")
    side = np.zeros(a.shape, int)
    for _ in range(maxiter):
        done = (np.abs(b - a) <= xtol * np.abs(b)) | (fa == 0) | (fb == 0)
        if done.all():
            break
        x = np.where(done, b, b - fb * (b - a) / (fb - fa))
        x = np.clip(x, np.minimum(a, b), np.maximum(a, b))
        fx = _event_function(kinds, annulus, x, c, eps_r, mu, steps)
        if not np.all(np.isfinite(fx)):
            raise ConvergenceError(f"events: non-finite residual during location for {annulus}")
        same = np.sign(fx) == np.sign(fb)
        # Illinois: keep the bracket, halve the stale end's function value
        new_a = np.where(same, a, b)
        new_fa = np.where(same, np.where(side == 1, fa / 2, fa), fb)
        side = np.where(same, 1, -1)
        a, fa = np.where(done, a, new_a), np.where(done, fa, new_fa)
        b, fb = np.where(done, b, x), np.where(done, fb, fx)
    else:
        raise ConvergenceError(f"events: Illinois did not reach xtol={xtol} in {maxiter} "
                               f"iterations (max bracket {np.max(np.abs(b - a)):.3g})")
    return np.where(np.abs(fa) < np.abs(fb), a, b)


def curves(br: Branch, cs, *, eps_r=None, mu: float | None = None,
           steps: int | None = None) -> list[Curve]:
    """Voltage-stretch curves for several c on one annulus branch, events located.

    ``eps_r`` is a scalar or one value per c (sensitivity studies in one batch).
    """
    from .params import EPS_R_ASSUMED, MU_VHB
    eps_r = EPS_R_ASSUMED if eps_r is None else eps_r
    mu = MU_VHB if mu is None else mu
    steps = br.steps if steps is None else steps
    an = br.annulus
    kappa = an.kappa
    cs = [float(c) for c in cs]
    eps_rs = [float(e) for e in np.broadcast_to(np.asarray(eps_r, float), (len(cs),))]
    actuators = [CircularActuator(an, c=c, eps_r=e, mu=mu) for c, e in zip(cs, eps_rs,
                                                                          strict=True)]
    out = []
    # dense-grid data and brackets, per c
    brackets = {k: [] for k in EVENT_KINDS}  # (curve index, qa, qb)
    data = []
    lam = br.lam
    for i, c in enumerate(cs):
        pb = circle_a.breakdown_phibar(lam, eps_rs[i], mu)
        K = circle_a.electrostriction_factor(lam, c)
        valid = K > 0
        Ks = np.where(valid, K, 1.0)  # Phibar is undefined where K <= 0 (masked below)
        p2 = np.where(valid, circle_a.phibar_squared(lam, br.T1, c, kappa) * K / Ks, np.nan)
        # d(Phibar^2)/dlam from the exact q-derivatives
        h = 1e-30
        with np.errstate(divide="ignore", invalid="ignore"):
            p2c = circle_a.phibar_squared(lam + 1j * h * br.dlam, br.T1 + 1j * h * br.dT1, c,
                                          kappa)
        dp2 = np.where(valid, (p2c.imag / h) / br.dlam, np.nan)
        fun = {"pullin": dp2, "minimum": dp2, "loss_of_tension": br.T1,
               "breakdown": p2 - pb**2}
        for kind in EVENT_KINDS:
            f = fun[kind]
            if kind == "minimum":
                idx = np.nonzero((f[:-1] < 0) & (f[1:] >= 0))[0]
            elif kind == "pullin":
                idx = np.nonzero((f[:-1] > 0) & (f[1:] <= 0))[0]
            elif kind == "loss_of_tension":
                idx = np.nonzero((f[:-1] > 0) & (f[1:] <= 0))[0]
            else:  # breakdown crossed from below
                idx = np.nonzero((f[:-1] < 0) & (f[1:] >= 0))[0]
            if idx.size:
                j = idx[0]
                brackets[kind].append((i, br.q[j], br.q[j + 1]))
        data.append((np.sqrt(np.maximum(p2, 0.0)), pb))
    located = {k: {} for k in EVENT_KINDS}
    rows = [(kind, *r) for kind, rs in brackets.items() for r in rs]
    if rows:
        kinds = np.array([r[0] for r in rows])
        idx = [r[1] for r in rows]
        qroot = locate(kinds, an, [r[2] for r in rows], [r[3] for r in rows],
                       [cs[i] for i in idx], [eps_rs[i] for i in idx], mu, steps=steps)
        st = interface_state(an, qroot, steps=steps)
        for k, i in enumerate(idx):
            p2 = circle_a.phibar_squared(st.lam[k], st.T1[k], cs[i], kappa)
            located[kinds[k]][i] = Event(str(kinds[k]), float(st.lam[k]),
                                         float(np.sqrt(max(p2, 0.0))), float(qroot[k]))
    for i, act in enumerate(actuators):
        phibar, pb = data[i]
        events = {k: located[k].get(i) for k in EVENT_KINDS}
        cands = [e for k, e in events.items() if k in FAILURE_KINDS and e is not None]
        failure = min(cands, key=lambda e: e.lam) if cands else None
        sigma1A = circle_a.sigma1_circle_a(lam, phibar, act.c, kappa)
        out.append(Curve(actuator=act, lam=lam, phibar=phibar, sigma1A=sigma1A,
                         phibar_breakdown=pb, events=events, failure=failure))
    return out


def curve(actuator: CircularActuator, *, n: int = 400, steps: int = DEFAULT_STEPS) -> Curve:
    """One voltage-stretch curve (convenience wrapper around :func:`branch`/:func:`curves`)."""
    br = branch(actuator.annulus, n=n, steps=steps)
    return curves(br, [actuator.c], eps_r=actuator.eps_r, mu=actuator.mu)[0]
