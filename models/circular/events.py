"""Failure events on the annulus branch, located on the shooting parameter (Sec. 3.5).

An event is a zero of a function of the shooting parameter q (the radial stretch at the
frame, :mod:`debench.models.circular.shooting`), vectorised over events of any kind, c,
eps_r and pre-stretch (:func:`event_function`):

* ``pullin``/``minimum``: d(Phibar^2)/d lambda (exact, complex step through the integrator);
* ``loss_of_tension``: T1^(B)(R_A);
* ``breakdown``: Phibar^2 - Phibar_B^2.

:func:`locate` brackets every zero to ``EVENT_XTOL`` relative in q by one vectorised
Illinois (safeguarded secant) iteration, certified at the end by the signs on both sides
of the iterate; all events of compatible annuli share one shooting integration per
iteration (the iteration is a :mod:`~debench.models.circular.lockstep` solver).
"""

from __future__ import annotations

import numpy as np
from debench.models import validation as v
from debench.models.errors import ConvergenceError

from . import circle_a
from .lockstep import run
from .params import Annulus
from .shooting import DEFAULT_STEPS, _interface_state_gen

#: relative tolerance on the shooting parameter q for event location: machine precision
#: level (q ~ 1, |d lambda/dq| ~ 1e2, so lambda is located to ~1e-12)
EVENT_XTOL = 1e-14
#: event location: once the last secant step is below CERTIFY_AFTER |q| (superlinear
#: convergence puts the next iterate far below xtol), the iterate x is replaced by the
#: pair x -+ CERTIFY xtol |x| whose signs certify the root within xtol
CERTIFY_AFTER = 1e-5
CERTIFY = 0.45
EVENT_KINDS = ("pullin", "minimum", "loss_of_tension", "breakdown")


@v.finite_result
def event_function(kinds, annulus, q, c, eps_r, mu, steps=DEFAULT_STEPS, lamP=None):
    """Functions whose zeros are the events, vectorised over (kind, q, c, eps_r).

    ``pullin``/``minimum``: d(Phibar^2)/d lambda (exact, complex step through the
    integrator); ``loss_of_tension``: T1^(B)(R_A); ``breakdown``: Phibar^2 - Phibar_B^2.
    ``kinds`` among ``EVENT_KINDS``, ``q > 0`` finite, ``c`` finite, ``eps_r > 0``,
    ``mu > 0``, ``steps >= 4``, ``lamP`` (per-event pre-stretch, else the annulus') > 0;
    ValueError when a trajectory is inadmissible (no annulus state for that q).
    """
    v.instance("annulus", annulus, Annulus)
    v.integer_at_least("steps", steps, 4)
    v.positive("q", q)
    v.finite("c", c)
    v.positive("eps_r", eps_r)
    v.positive("mu", mu)
    if lamP is not None:
        v.positive("lamP", lamP)
    if np.any(~np.isin(np.asarray(kinds), EVENT_KINDS)):
        raise ValueError(f"kinds must be among {EVENT_KINDS}, got {kinds!r}")
    return _event_values(kinds, annulus, q, c, eps_r, mu, steps, lamP)[0]


def _event_values(kinds, annulus, q, c, eps_r, mu, steps, lamP=None, membrane=None):
    """:func:`event_function` and the interface state (lam, T1) it was computed from
    (``lamP``, ``membrane``: per-event overrides of the annulus, see
    :func:`~debench.models.circular.integrator.integrate`)."""
    return run(_event_values_gen(kinds, annulus, q, c, eps_r, mu, steps, lamP, membrane))


def _event_values_gen(kinds, annulus, q, c, eps_r, mu, steps, lamP=None, membrane=None):
    """:func:`_event_values` as a :func:`~debench.models.circular.lockstep.lockstep`
    solver."""
    kinds = np.asarray(kinds)
    bad = ~np.isin(kinds, EVENT_KINDS)
    if bad.any():
        raise ValueError(f"unknown event kind {kinds[bad][0]!r}; expected one of {EVENT_KINDS}")
    st = yield from _interface_state_gen(annulus, q, steps=steps, lamP=lamP,
                                         membrane=membrane)
    p2c = circle_a._p2(st.lam_c, st.T1_c, c, annulus.law)
    deriv = (p2c.imag / 1e-30) / st.dlam
    brk = p2c.real - circle_a._breakdown(st.lam, eps_r, mu) ** 2
    f = np.where(kinds == "loss_of_tension", st.T1,
                 np.where(kinds == "breakdown", brk, deriv))
    return f, st.lam, st.T1


def locate(kinds, annulus, qa, qb, c, eps_r, mu, *, steps=DEFAULT_STEPS,
           xtol=EVENT_XTOL, maxiter=100, lamP=None, fa=None, fb=None, x0=None):
    """Vectorised Illinois iteration for zeros bracketed in [qa, qb]; raises if it fails.

    All events (any kinds, any c, any lamP) of compatible annuli are located together: one
    shooting integration per iteration. ``fa``/``fb`` (the event functions at the bracket
    ends, if already known) and ``x0`` (an interpolated estimate of the root) save
    iterations: the bracket is first shrunk to [x0 - d, x0 + d] when it contains the root.
    Converged when ``|b - a| <= xtol |b|`` (``xtol`` a finite tolerance in (0, 1)) or the
    event function vanishes exactly; else ConvergenceError (with the bracket reached).
    """
    v.instance("annulus", annulus, Annulus)
    v.integer_at_least("steps", steps, 4)
    v.tolerance("xtol", xtol)
    v.integer_at_least("maxiter", maxiter, 1)
    v.positive("mu", mu)
    v.finite("c", c)
    v.positive("eps_r", eps_r)
    v.positive("qa", qa)
    v.positive("qb", qb)
    if np.any(~np.isin(np.asarray(kinds), EVENT_KINDS)):
        raise ValueError(f"kinds must be among {EVENT_KINDS}, got {kinds!r}")
    return _locate(kinds, annulus, qa, qb, c, eps_r, mu, steps=steps, xtol=xtol,
                   maxiter=maxiter, lamP=lamP, fa=fa, fb=fb, x0=x0)[0]


def _locate(kinds, annulus, qa, qb, c, eps_r, mu, **kw):
    """:func:`locate` without argument checks, returning ``(q, lam, T1)`` at the roots:
    the interface state of the iterate returned, kept from the iteration (no extra
    integration). ``sa``/``sb``: the states (lam, T1) at the bracket ends, when known
    with ``fa``/``fb``; ``membrane``: per-event equilibrium (bool array), as ``lamP``."""
    return run(_locate_gen(kinds, annulus, qa, qb, c, eps_r, mu, **kw))


def _locate_gen(kinds, annulus, qa, qb, c, eps_r, mu, *, steps=DEFAULT_STEPS,
                xtol=EVENT_XTOL, maxiter=100, lamP=None, fa=None, fb=None, x0=None,
                sa=None, sb=None, membrane=None):
    """:func:`_locate` as a :func:`~debench.models.circular.lockstep.lockstep` solver."""
    a = np.array(qa, float)
    b = np.array(qb, float)
    ev = _Events(np.broadcast_to(np.asarray(kinds), a.shape), annulus,
                 np.broadcast_to(c, a.shape).astype(float),
                 np.broadcast_to(eps_r, a.shape).astype(float), mu, steps,
                 None if lamP is None else np.broadcast_to(np.asarray(lamP, float), a.shape),
                 None if membrane is None
                 else np.broadcast_to(np.asarray(membrane, bool), a.shape))
    if fa is None or fb is None:
        fa, fb, sa, sb = yield from ev.at_pair(a, b)
    nan = np.full(a.shape, np.nan)
    sa = (nan, nan) if sa is None else sa   # unknown states: computed at the end if needed
    sb = (nan, nan) if sb is None else sb
    br = _Bracket(a, np.array(fa, float), *(np.array(z, float) for z in sa),
                  b, np.array(fb, float), *(np.array(z, float) for z in sb))
    if np.any(np.sign(br.fa) * np.sign(br.fb) > 0) or not np.all(np.isfinite(br.fa * br.fb)):
        raise ConvergenceError(f"events {sorted(set(ev.kinds))}: not bracketed for {annulus}")
    if x0 is not None:
        yield from _shrink_to_estimate(ev, br, x0)
    yield from _illinois(ev, br, xtol, maxiter)
    use_a = np.abs(br.fa) < np.abs(br.fb)
    q = np.where(use_a, br.a, br.b)
    lam, T1 = np.where(use_a, br.la, br.lb), np.where(use_a, br.Ta, br.Tb)
    miss = ~np.isfinite(lam)
    if miss.any():    # a root at a bracket end given without its state
        st = yield from _interface_state_gen(
            annulus, q[miss], steps=steps, lamP=None if ev.lamP is None else ev.lamP[miss],
            membrane=None if ev.membrane is None else ev.membrane[miss])
        lam[miss], T1[miss] = st.lam, st.T1
    return q, lam, T1


class _Events:
    """The events of one location (arrays over the events) and their evaluation."""

    def __init__(self, kinds, annulus, c, eps_r, mu, steps, lamP, membrane):
        self.kinds, self.annulus, self.c, self.eps_r = kinds, annulus, c, eps_r
        self.mu, self.steps, self.lamP, self.membrane = mu, steps, lamP, membrane

    def at(self, idx, x):
        """Event values and states (f, lam, T1) of the events ``idx`` at the points ``x``,
        in one integration (a :func:`~debench.models.circular.lockstep.lockstep` solver)."""
        return (yield from _event_values_gen(
            self.kinds[idx], self.annulus, x, self.c[idx], self.eps_r[idx], self.mu,
            self.steps, None if self.lamP is None else self.lamP[idx],
            None if self.membrane is None else self.membrane[idx]))

    def at_pair(self, x, y):
        """Event values and states at two points per event, in one integration."""
        n = x.size
        every = np.arange(n)
        f, lam, T1 = yield from self.at(np.concatenate([every, every]),
                                        np.concatenate([x, y]))
        return f[:n], f[n:], (lam[:n], T1[:n]), (lam[n:], T1[n:])


class _Bracket:
    """Brackets [a, b] of the events with the event values and states (lam, T1) at both
    ends (NaN states: not known), updated in place by the iteration."""

    def __init__(self, a, fa, la, Ta, b, fb, lb, Tb):
        self.a, self.fa, self.la, self.Ta = a, fa, la, Ta
        self.b, self.fb, self.lb, self.Tb = b, fb, lb, Tb

    def lo_hi(self):
        return np.minimum(self.a, self.b), np.maximum(self.a, self.b)


def _shrink_to_estimate(ev: _Events, br: _Bracket, x0):
    """Shrink every bracket to [x0 - d, x0 + d], d = 1e-4 |b - a|, where that tight
    bracket holds the root (one integration; keeps a as the 'lo' side)."""
    lo_, hi_ = br.lo_hi()
    x0 = np.clip(np.asarray(x0, float), lo_, hi_)
    d = 1e-4 * np.abs(br.b - br.a)
    lo = np.clip(x0 - d, lo_, hi_)
    hi = np.clip(x0 + d, lo_, hi_)
    flo, fhi, slo, shi = yield from ev.at_pair(lo, hi)
    ok = np.isfinite(flo) & np.isfinite(fhi) & (np.sign(flo) * np.sign(fhi) <= 0)
    # shrink to the tight bracket where it holds the root (keeps a as 'lo' side)
    br.a, br.fa = np.where(ok, lo, br.a), np.where(ok, flo, br.fa)
    br.la, br.Ta = np.where(ok, slo[0], br.la), np.where(ok, slo[1], br.Ta)
    br.b, br.fb = np.where(ok, hi, br.b), np.where(ok, fhi, br.fb)
    br.lb, br.Tb = np.where(ok, shi[0], br.lb), np.where(ok, shi[1], br.Tb)


def _illinois(ev: _Events, br: _Bracket, xtol, maxiter):
    """The Illinois iteration on the brackets ``br`` (updated in place) until every one is
    below ``xtol`` relative or its event function vanishes at an end; ConvergenceError
    after ``maxiter`` iterations."""
    side = np.zeros(br.a.shape, int)
    step = np.full(br.a.shape, np.inf)     # size of each element's last secant step
    for _ in range(maxiter):
        done = (np.abs(br.b - br.a) <= xtol * np.abs(br.b)) | (br.fa == 0) | (br.fb == 0)
        if done.all():
            return
        x = np.where(done, br.b, br.b - br.fb * (br.b - br.a) / (br.fb - br.fa))
        x = np.clip(x, *br.lo_hi())
        m = ~done
        x, fx, lx, Tx = yield from _evaluate_or_certify(ev, br, x, m, step, xtol)
        step = np.where(m, np.abs(x - br.b), step)
        side = _illinois_update(br, m, side, x, fx, lx, Tx)
    raise ConvergenceError(f"events: Illinois did not reach xtol={xtol} in {maxiter} "
                           f"iterations (max bracket {np.max(np.abs(br.b - br.a)):.3g})")


def _evaluate_or_certify(ev: _Events, br: _Bracket, x, m, step, xtol):
    """The event values at the iterates ``x`` of the active events ``m`` (one
    integration): ``(x, f, lam, T1)`` of the iterate, and ``m`` cleared where the root
    was certified (the bracket then becomes [x - eps, x + eps])."""
    # once the secant steps are small, the next iterate is accurate to far below
    # xtol: evaluate x -+ eps instead of x (eps = CERTIFY xtol |x|), whose signs
    # certify the root within xtol in the same integration (else the inner one is
    # the iterate)
    lo, hi = br.lo_hi()
    cert = m & (step <= CERTIFY_AFTER * np.abs(br.b))
    eps = CERTIFY * xtol * np.abs(x)
    xm = np.clip(x - eps, lo, hi)
    xp = np.clip(x + eps, lo, hi)
    plain = m & ~cert
    ip, ic = np.nonzero(plain)[0], np.nonzero(cert)[0]
    idx = np.concatenate([ip, ic, ic])
    f_, l_, T_ = yield from ev.at(idx, np.concatenate([x[ip], xm[ic], xp[ic]]))
    if not np.all(np.isfinite(f_)):
        raise ConvergenceError(f"events: non-finite residual during location for "
                               f"{ev.annulus}")
    fx, lx, Tx = np.zeros_like(x), br.lb.copy(), br.Tb.copy()
    n1, n2 = ip.size, ip.size + ic.size
    fx[ip], lx[ip], Tx[ip] = f_[:n1], l_[:n1], T_[:n1]
    if ic.size:
        fm, fp = f_[n1:n2], f_[n2:]
        split = np.sign(fm) != np.sign(fp)
        # certified: the bracket becomes [x - eps, x + eps]
        ks = ic[split]
        br.a[ks], br.fa[ks], br.la[ks], br.Ta[ks] = xm[ks], fm[split], \
            l_[n1:n2][split], T_[n1:n2][split]
        br.b[ks], br.fb[ks], br.lb[ks], br.Tb[ks] = xp[ks], fp[split], l_[n2:][split], \
            T_[n2:][split]
        m[ks] = False
        # not certified: both on one side; the iterate is the one nearer the root
        keep = ~split
        kn = ic[keep]
        toward_a = (np.sign(fm[keep]) == np.sign(br.fb[kn])) == (br.a[kn] < br.b[kn])
        pick = np.where(toward_a, 0, 1)     # 0: x - eps, 1: x + eps
        x[kn] = np.where(pick == 0, xm[kn], xp[kn])
        fx[kn] = np.where(pick == 0, fm[keep], fp[keep])
        lx[kn] = np.where(pick == 0, l_[n1:n2][keep], l_[n2:][keep])
        Tx[kn] = np.where(pick == 0, T_[n1:n2][keep], T_[n2:][keep])
    return x, fx, lx, Tx


def _illinois_update(br: _Bracket, upd, side, x, fx, lx, Tx):
    """One Illinois update of the brackets ``upd`` by the iterate (x, f, lam, T1): the
    new end replaces b; the bracket is kept, and the stale end's function value halved
    when the same end is kept twice. Returns the side of each bracket's last update."""
    same = np.sign(fx) == np.sign(br.fb)
    # Illinois: keep the bracket, halve the stale end's function value
    new_a = np.where(same, br.a, br.b)
    new_fa = np.where(same, np.where(side == 1, br.fa / 2, br.fa), br.fb)
    new_la, new_Ta = np.where(same, br.la, br.lb), np.where(same, br.Ta, br.Tb)
    side = np.where(upd, np.where(same, 1, -1), side)
    br.a, br.fa = np.where(upd, new_a, br.a), np.where(upd, new_fa, br.fa)
    br.la, br.Ta = np.where(upd, new_la, br.la), np.where(upd, new_Ta, br.Ta)
    br.b, br.fb = np.where(upd, x, br.b), np.where(upd, fx, br.fb)
    br.lb, br.Tb = np.where(upd, lx, br.lb), np.where(upd, Tx, br.Tb)
    return side
