"""Voltage-stretch curves of circle A and their failure events (Zeng 2020, Sec. 3.5).

The annulus problem does not involve the voltage nor c (only lambda^(A) enters B through
(3.31)), so one annulus *branch* -- the interface stress T1^(B)(R_A) as a function of the
circle-A stretch lambda, computed once per (lamP, R_B/R_A, Jm, equilibrium) -- serves every
c and every eps_r: ``Phibar^2 = (s(lam) - lam T1B)/(lam^4 K(lam))`` (see
:mod:`debench.models.circular.circle_a`). The branch is traced by the vectorised shooting method
(:mod:`debench.models.circular.shooting`), parametrised by the radial stretch at the frame.

Failure events on a curve (each located by a safeguarded secant (Illinois) iteration on
the shooting parameter, to :data:`~debench.models.circular.events.EVENT_XTOL` relative,
with exact complex-step derivatives, :mod:`debench.models.circular.events`):

* ``pullin``: a local maximum of Phibar(lambda) -- the electromechanical instability;
* ``minimum``: the local minimum that follows it (Gent stiffening, Zhao, Hong & Suo 2007);
* ``loss_of_tension``: sigma1^(A) = 0, i.e. T1^(B)(R_A) = 0 (Sec. 3.5.3) -- independent of
  c by construction;
* ``breakdown``: Phibar = sqrt(eps_bar/mu) E_B(lambda)/lambda^2 (Sec. 3.5.5), crossed from
  below;
* ``locking``: the locking stretch of circle A, 2 lam^2 + lam^-4 - 3 = Jm for Gent (3.23)
  (bisection to machine precision; for another elastomer the end of its admissible
  equibiaxial states), reported as the failure only when none of the above occurs first
  (Phibar -> inf there, so breakdown normally precedes it);
* ``end``: the end of the admissible annulus branch, likewise;
* ``permittivity``: the stretch where the factor K = 1 + c(5 lam/2 - 2) of (3.30) reaches
  0 (c < 0; Phibar undefined beyond), likewise (breakdown normally precedes it).

The *failure* is the first of pullin, loss_of_tension, breakdown along increasing lambda
(the thesis terminates its curves there, Sec. 3.5.3-3.5.5); ``lam_max`` and its Phibar are
the failure point (Fig. 3.9).

The material is the annulus' (:class:`~debench.models.circular.params.Annulus`): the
thesis' Gent (3.23) of ``Jm`` in its closed forms, or any library ``elastomer`` through its
membrane law (:mod:`debench.models.circular.law`), in circle A (3.30) and annulus B alike;
stresses and Phibar are then per unit the elastomer's shear modulus.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field

import numpy as np
from debench.models import validation as v
from debench.models.errors import ConvergenceError
from scipy.interpolate import PchipInterpolator

from . import circle_a, params
from .events import EVENT_KINDS, _locate_gen
from .lockstep import Request, run
from .params import Annulus, CircularActuator
from .shooting import DEFAULT_STEPS, _interface_state, _interface_state_gen, q_for_stretch

#: the events that end a curve (the film fails there)
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


def _scan_state(annulus: Annulus, q, steps: int, lamP, membrane=None):
    """Interface stretch and T1 for shooting parameters q, without sensitivities (a real
    integration: the real parts of the complex-step one up to rounding, measured
    < 1e-13 relative; the scan only places the grid, whose points are exact solutions)."""
    return run(_scan_state_gen(annulus, q, steps, lamP, membrane))


def _scan_state_gen(annulus: Annulus, q, steps: int, lamP, membrane=None):
    """:func:`_scan_state` as a :func:`~debench.models.circular.lockstep.lockstep`
    solver."""
    q = np.asarray(q, float)
    l1, l2 = yield Request.of(annulus, q, steps, lamP, membrane)
    l1, l2 = l1.reshape(q.shape), l2.reshape(q.shape)
    with np.errstate(all="ignore"):  # NaN marks inadmissible trajectories, by design
        s1, *_ = annulus.law.stresses(l1, l2)
        return l2, s1 / l1


def _scan(annulus: Annulus, steps: int, n: int = 160):
    """Coarse scan of the shooting parameter: q = lamP - delta, delta geometric."""
    delta = np.concatenate([[0.0], np.geomspace(1e-8, 0.95, n - 1) * annulus.lamP])
    q = annulus.lamP - delta
    lam, T1 = _scan_state(annulus, q, steps, None)
    ok = np.isfinite(lam) & np.isfinite(T1)
    first_bad = np.argmin(ok) if not ok.all() else len(ok)
    keep = slice(0, first_bad)
    lam, q = lam[keep], q[keep]
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
    n, steps
        Grid points (>= 4) and RK4 steps (>= 4).
    lam_end
        None or a finite stretch > lamP.
    """
    v.instance("annulus", annulus, Annulus)
    v.integer_at_least("n", n, 4)
    v.integer_at_least("steps", steps, 4)
    if lam_end is not None:
        v.in_range("lam_end", lam_end, annulus.lamP, math.inf, lo_open=True, hi_open=True)
    if lam is not None:
        lam = v.array("lam", lam)
        if lam.ndim != 1 or lam.size < 1:
            raise ValueError(f"lam must be a non-empty 1-D array, got shape {lam.shape}")
    lam_scan, q_scan = _scan(annulus, steps)
    top = min(lam_scan[-1], 0.999 * annulus.law.locking_stretch())
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
    st = _interface_state(annulus, q, steps=steps)
    if not np.all(np.isfinite(st.lam)) or np.any(np.diff(st.lam) <= 0):
        raise ConvergenceError(f"annulus branch of {annulus}: non-monotone or inadmissible "
                               "points on the interpolated grid")
    return Branch(annulus=annulus, lam=st.lam, q=q, lam1=st.lam1, T1=st.T1, dlam=st.dlam,
                  dT1=st.dT1, lam_end=float(min(lam_end, top)), steps=steps)


def branches(annuli, *, n=300, steps: int = DEFAULT_STEPS) -> list[Branch]:
    """Batched :func:`branch` (default grids) for annuli differing only in lamP and the
    equilibrium variant: one scan and one grid integration for all of them.

    ``n`` is the number of grid points (>= 4) of every branch, or one such number per
    annulus; an annulus listed several times (with different ``n``) is scanned once.
    """
    return run(branches_solver(annuli, n=n, steps=steps))


def branches_solver(annuli, *, n=300, steps: int = DEFAULT_STEPS):
    """:func:`branches` as a :func:`~debench.models.circular.lockstep.lockstep` solver,
    its arguments checked at the call (as :func:`branches`'): a real scan, then the grid
    integration; it returns the branches. ``lockstep.run(branches_solver(...))`` runs it
    alone."""
    if isinstance(annuli, str | bytes) or not hasattr(annuli, "__iter__"):
        raise TypeError(f"annuli must be an iterable of Annulus, got {annuli!r}")
    annuli = list(annuli)
    for a in annuli:
        v.instance("annuli[i]", a, Annulus)
    ns = [n] * len(annuli) if isinstance(n, numbers.Integral) else list(n)
    if len(ns) != len(annuli):
        raise ValueError(f"n must be an integer or one per annulus ({len(annuli)}), "
                         f"got {len(ns)} values")
    for k in ns:
        v.integer_at_least("n", k, 4)
    v.integer_at_least("steps", steps, 4)
    if annuli:
        a0 = annuli[0]
        if any((a.radius_ratio, a.law) != (a0.radius_ratio, a0.law) for a in annuli):
            raise ValueError("branches(): annuli must differ only in lamP and equilibrium")
    return _branches_gen(annuli, ns, steps)


def _branches_gen(annuli, ns, steps):
    """:func:`branches_solver` after its checks (``ns`` one grid size per annulus): a real
    scan, then the grid integration."""
    if not annuli:
        return []
    a0 = annuli[0]
    scanned = list(dict.fromkeys(annuli))          # each distinct annulus scanned once
    mem = np.array([a.equilibrium == "membrane" for a in scanned])
    m = 160
    delta = np.concatenate([[0.0], np.geomspace(1e-8, 0.95, m - 1)])
    lamP = np.repeat([a.lamP for a in scanned], m)
    q_scan = lamP - np.tile(delta, len(scanned)) * lamP
    lam_scan, T1_scan = yield from _scan_state_gen(a0, q_scan, steps, lamP,
                                                   np.repeat(mem, m))
    interp = {}
    for k, a in enumerate(scanned):
        sl = slice(k * m, (k + 1) * m)
        lam_k, q_k = lam_scan[sl], q_scan[sl]
        ok = np.isfinite(lam_k) & np.isfinite(T1_scan[sl])
        first_bad = np.argmin(ok) if not ok.all() else m
        lam_k, q_k = lam_k[:first_bad], q_k[:first_bad]
        if lam_k.size < 4 or np.any(np.diff(lam_k) <= 0):
            raise ConvergenceError(f"annulus branch for {a} is not monotone in the shooting "
                                   "parameter (or too short)")
        top = min(lam_k[-1], 0.999 * a.law.locking_stretch())
        interp[a] = (PchipInterpolator(lam_k, q_k), top)
    qs, lps, tops = [], [], []
    for a, nk in zip(annuli, ns, strict=True):
        pchip, top = interp[a]
        q = pchip(np.linspace(a.lamP, top, nk))
        q[0] = a.lamP
        qs.append(q)
        lps.append(np.full(nk, a.lamP))
        tops.append(top)
    q = np.concatenate(qs)
    st = yield from _interface_state_gen(
        a0, q, steps=steps, lamP=np.concatenate(lps),
        membrane=np.repeat([a.equilibrium == "membrane" for a in annuli], ns))
    out = []
    ends = np.cumsum([0, *ns])
    for k, a in enumerate(annuli):
        sl = slice(ends[k], ends[k + 1])
        if not np.all(np.isfinite(st.lam[sl])) or np.any(np.diff(st.lam[sl]) <= 0):
            raise ConvergenceError(f"annulus branch of {a}: non-monotone or inadmissible "
                                   "points on the interpolated grid")
        out.append(Branch(annulus=a, lam=st.lam[sl], q=q[sl], lam1=st.lam1[sl],
                          T1=st.T1[sl], dlam=st.dlam[sl], dT1=st.dT1[sl],
                          lam_end=float(tops[k]), steps=steps))
    return out


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


def curves(br: Branch, cs, *, eps_r=None, mu: float | None = None,
           steps: int | None = None) -> list[Curve]:
    """Voltage-stretch curves for several c on one annulus branch, events located.

    ``eps_r`` is a scalar or one value per c (sensitivity studies in one batch).
    """
    return curves_many([(br, cs, eps_r)], mu=mu, steps=steps)[0]


def curves_many(jobs, *, mu: float | None = None, steps: int | None = None):
    """Batched :func:`curves`: ``jobs`` is a list of ``(branch, cs, eps_r)``.

    Branches that differ only in the pre-stretch and the equilibrium variant (same Jm,
    R_B/R_A, steps) share one vectorised event location: one shooting integration per
    Illinois iteration for all their events.

    Every (branch, c, eps_r) must make a valid :class:`CircularActuator` (c finite with
    K(lamP) > 0, eps_r > 0); ``mu > 0``; ``steps`` None or >= 4. Where the permittivity
    factor K = 1 + c(5 lam/2 - 2) of (3.30) vanishes on the branch, Phibar is undefined
    beyond it (NaN in ``phibar``); if no other failure occurs first, the curve ends there
    with the failure kind ``"permittivity"``.
    """
    return run(_curves_many_solver(jobs, mu=mu, steps=steps))


def _curves_many_solver(jobs, *, mu: float | None = None, steps: int | None = None):
    """:func:`curves_many` as a :func:`~debench.models.circular.lockstep.lockstep`
    solver (arguments checked here, at the call)."""
    mu = params.MU_VHB if mu is None else v.positive("mu", mu)
    if steps is not None:
        v.integer_at_least("steps", steps, 4)
    if isinstance(jobs, str | bytes) or not hasattr(jobs, "__iter__"):
        raise TypeError(f"jobs must be a list of (branch, cs, eps_r), got {jobs!r}")
    checked, actuators = [], []
    for job in jobs:
        if not (isinstance(job, tuple | list) and len(job) == 3):
            raise TypeError(f"each job must be a tuple (branch, cs, eps_r), got {job!r:.80}")
        br, cs, eps_r = job
        v.instance("branch", br, Branch)
        if isinstance(cs, str | bytes) or not hasattr(cs, "__iter__"):
            raise TypeError(f"cs must be a sequence of numbers, got {cs!r}")
        cs = list(cs)
        cs_ = np.atleast_1d(v.finite("cs", cs)) if cs else []
        eps_r_ = params.EPS_R_ASSUMED if eps_r is None else eps_r
        eps_rs = np.broadcast_to(v.positive("eps_r", eps_r_), (len(cs_),))
        # validated once here; the curves below carry these actuators
        actuators.append([CircularActuator(br.annulus, c=float(c), eps_r=float(e), mu=mu)
                          for c, e in zip(cs_, eps_rs, strict=True)])
        checked.append((br, cs, eps_r))
    return _curves_many_gen(checked, actuators, mu, steps)


def _curves_many_gen(jobs, actuators, mu, steps):
    """:func:`curves_many` after its checks (``actuators``: the validated actuator of
    every curve) as a :func:`~debench.models.circular.lockstep.lockstep` solver."""
    pending = []  # (job index, curve index, kind, qa, qb, c, eps_r, lamP)
    located = {}
    prepared = [_grid_events(jb, br, cs, eps_r, mu, pending, located)
                for jb, (br, cs, eps_r) in enumerate(jobs)]
    pending, copies = _shared_events(jobs, pending)
    pending = _cubic_estimates(pending)
    roots = yield from _locate_groups(jobs, pending, mu, steps, located)
    for row, rep in copies:
        ev = located[(rep[0], rep[1], rep[2])]
        if row[5] != rep[5]:      # loss of tension shared across c: Phibar at this c
            lam_, T1_ = roots[(rep[0], rep[1], rep[2])]
            p2 = circle_a._p2(lam_, T1_, row[5], jobs[row[0]][0].annulus.law)
            ev = Event(ev.kind, ev.lam, float(np.sqrt(max(p2, 0.0))), ev.q)
        located[(row[0], row[1], row[2])] = ev
    return [[_curve(actuators[jb][i], c, br, data[i], {k: located.get((jb, i, k))
                                                        for k in EVENT_KINDS})
             for i, c in enumerate(cs)]
            for jb, (br, cs, data) in enumerate(prepared)]


def _grid_events(jb, br: Branch, cs, eps_r, mu, pending, located):
    """The curves of job ``jb`` (branch ``br``, the values ``cs`` and ``eps_r``) on the
    branch grid: ``(br, cs, data)`` with ``data[i]`` = (Phibar, Phibar_B, sigma1^(A)) of
    curve i. Every event crossed between two grid points is appended to ``pending`` (its
    bracket, the event values at both ends, a secant estimate and the 4 grid values
    around it); an event known exactly is put in ``located``."""
    eps_r = params.EPS_R_ASSUMED if eps_r is None else eps_r
    an = br.annulus
    law = an.law
    cs = [float(c) for c in cs]
    eps_rs = [float(e) for e in np.broadcast_to(np.asarray(eps_r, float), (len(cs),))]
    lam = br.lam
    # every curve of this branch at once: rows are the c (and eps_r) values
    cc = np.array(cs, float)[:, None]
    PB = circle_a._breakdown(lam, np.array(eps_rs, float)[:, None], mu)
    K = circle_a._K(lam, cc)
    valid = K > 0
    Ks = np.where(valid, K, 1.0)  # Phibar is undefined where K <= 0 (masked below)
    P2 = np.where(valid, circle_a._p2(lam, br.T1, cc, law) * K / Ks, np.nan)
    h = 1e-30
    with np.errstate(divide="ignore", invalid="ignore"):
        p2c = circle_a._p2(lam + 1j * h * br.dlam, br.T1 + 1j * h * br.dT1, cc, law)
    DP2 = np.where(valid, (p2c.imag / h) / br.dlam, np.nan)
    fun = {"pullin": DP2, "minimum": DP2, "loss_of_tension": br.T1[None, :],
           "breakdown": P2 - PB**2}
    first = {}
    for kind in EVENT_KINDS:
        f = fun[kind]
        if kind in ("minimum", "breakdown"):   # crossing from below
            cross = (f[:, :-1] < 0) & (f[:, 1:] >= 0)
        else:                                   # crossing from above
            cross = (f[:, :-1] > 0) & (f[:, 1:] <= 0)
        first[kind] = np.where(cross.any(axis=1), cross.argmax(axis=1), -1)
    PHI = np.sqrt(np.maximum(P2, 0.0))
    SIG = law.equibiaxial_stress(lam) - PHI**2 * lam**4 * K
    data = []
    for i, c in enumerate(cs):
        for kind in EVENT_KINDS:
            if kind == "loss_of_tension" and an.lamP == 1.0:
                # unstretched membrane: T1 = 0 at lamP exactly (rounding leaves
                # ~1e-56, which no bracketing can resolve), compressive beyond it
                located[(jb, i, kind)] = Event(kind, 1.0, 0.0, 1.0)
                continue
            j = int(first[kind][i if first[kind].size > 1 else 0])
            if j >= 0:
                f = fun[kind][i if fun[kind].shape[0] > 1 else 0]
                # root estimate: the secant in the cell, refined below on the cubic
                # through the 4 grid values around the crossing
                x0 = br.q[j] - f[j] * (br.q[j + 1] - br.q[j]) / (f[j + 1] - f[j])
                lo_ = min(max(j - 1, 0), f.size - 4)
                pending.append((jb, i, kind, br.q[j], br.q[j + 1], c, eps_rs[i],
                                an.lamP, f[j], f[j + 1], x0, (br.lam[j], br.T1[j]),
                                (br.lam[j + 1], br.T1[j + 1]),
                                (br.q[lo_:lo_ + 4], f[lo_:lo_ + 4])))
        data.append((PHI[i], PB[i], SIG[i]))
    return br, cs, data


def _shared_events(jobs, pending):
    """The rows of ``pending`` to locate, and ``(row, representative)`` for each row whose
    event another row locates."""
    # an event that does not depend on eps_r (all but breakdown) is located once per
    # (branch, c) and shared by the curves of every eps_r; loss of tension (T1 = 0) does
    # not depend on c either: once per branch (its Phibar is evaluated per c)
    unique, copies = {}, []
    for row in pending:
        jb, _, kind, c_, e_ = row[0], row[1], row[2], row[5], row[6]
        key = (id(jobs[jb][0]), kind, None if kind == "loss_of_tension" else c_,
               e_ if kind == "breakdown" else None)
        if key in unique:
            copies.append((row, unique[key]))
        else:
            unique[key] = row
    return list(unique.values()), copies


def _locate_groups(jobs, pending, mu, steps, located):
    """Locate the events ``pending``, one vectorised location per group of compatible
    annuli (same R_B/R_A, Jm and steps; a lockstep solver), into ``located``; returns the
    interface states (lam, T1) at the roots."""
    # one location per group of compatible annuli
    roots = {}
    groups = {}
    for row in pending:
        an = jobs[row[0]][0].annulus
        st = jobs[row[0]][0].steps if steps is None else steps
        key = (an.radius_ratio, an.law, st)
        groups.setdefault(key, []).append(row)
    for (_, _, st), rows in groups.items():
        an0 = jobs[rows[0][0]][0].annulus
        kinds = np.array([r[2] for r in rows])
        lamPs = np.array([r[7] for r in rows])
        mem = np.array([jobs[r[0]][0].annulus.equilibrium == "membrane" for r in rows])
        qroot, lam_r, T1_r = yield from _locate_gen(
            kinds, an0, [r[3] for r in rows], [r[4] for r in rows], [r[5] for r in rows],
            [r[6] for r in rows], mu, steps=st, lamP=lamPs, fa=[r[8] for r in rows],
            fb=[r[9] for r in rows], x0=[r[10] for r in rows],
            sa=([r[11][0] for r in rows], [r[11][1] for r in rows]),
            sb=([r[12][0] for r in rows], [r[12][1] for r in rows]), membrane=mem)
        for k, r in enumerate(rows):
            p2 = circle_a._p2(lam_r[k], T1_r[k], r[5], an0.law)
            located[(r[0], r[1], r[2])] = Event(r[2], float(lam_r[k]),
                                                float(np.sqrt(max(p2, 0.0))),
                                                float(qroot[k]))
            roots[(r[0], r[1], r[2])] = (lam_r[k], T1_r[k])
    return roots


def _curve(act: CircularActuator, c: float, br: Branch, data, events: dict) -> Curve:
    """The curve of ``act`` (its ``c``) on ``br`` (``data``: its Phibar, Phibar_B and
    sigma1^(A) on the grid) with its located ``events`` and its failure."""
    phibar, pb, sigma1A = data
    cands = [e for k, e in events.items() if k in FAILURE_KINDS and e is not None]
    failure = min(cands, key=lambda e: e.lam) if cands else None
    lam_K = _zero_of_K(c)
    if failure is None and lam_K < br.lam_end:
        # the permittivity factor K of (3.30) reaches 0 on the branch before any
        # other failure: Phibar is undefined beyond, the model ends there
        failure = Event("permittivity", lam_K, math.nan, math.nan)
    if failure is None:
        # nothing before the end of the traced branch: Gent locking of circle A
        # (3.23) if the branch reaches it (Phibar -> inf there), else the end of
        # the admissible annulus branch
        lock = br.annulus.law.locking_stretch()
        kind = "locking" if br.lam_end >= 0.999 * lock * (1 - 1e-12) else "end"
        failure = Event(kind, float(lock if kind == "locking" else br.lam_end),
                        float("nan"), float("nan"))
    return Curve(actuator=act, lam=br.lam, phibar=phibar, sigma1A=sigma1A,
                 phibar_breakdown=pb, events=events, failure=failure)


def _cubic_estimates(rows):
    """Replace each row's secant estimate x0 (index 10) of the event root by the zero, in
    the bracketing cell, of the cubic interpolating the event function at the 4 grid
    points around it (index 13), all rows at once (a few safeguarded Newton steps on
    the interpolant from the secant estimate); the estimate only narrows the bracket
    that the iteration then refines to ``EVENT_XTOL``."""
    if not rows:
        return rows
    qq = np.array([r[13][0] for r in rows], float)
    ff = np.array([r[13][1] for r in rows], float)
    a, b = np.array([r[3] for r in rows]), np.array([r[4] for r in rows])
    x = np.array([r[10] for r in rows], float)
    ok = np.all(np.isfinite(ff), axis=1) & (qq.shape[1] == 4) & np.isfinite(x)
    if not ok.any():
        return rows
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    # monomial coefficients in (q - a), solved per row (4 x 4 Vandermonde systems)
    V = (qq[ok] - a[ok, None])[:, :, None] ** np.arange(4)
    coef = np.linalg.solve(V, ff[ok][:, :, None])[:, :, 0]
    xs = x[ok] - a[ok]
    for _ in range(8):
        p = coef[:, 0] + xs * (coef[:, 1] + xs * (coef[:, 2] + xs * coef[:, 3]))
        dp = coef[:, 1] + xs * (2 * coef[:, 2] + xs * 3 * coef[:, 3])
        with np.errstate(divide="ignore", invalid="ignore"):
            xs = xs - np.where(dp != 0, p / dp, 0.0)
    xn = xs + a[ok]
    good = np.isfinite(xn) & (xn >= lo[ok]) & (xn <= hi[ok])
    x[np.nonzero(ok)[0][good]] = xn[good]
    return [(*r[:10], float(x[k]), *r[11:]) for k, r in enumerate(rows)]


def _zero_of_K(c: float) -> float:
    """Stretch at which K = 1 + c(5 lam/2 - 2) of (3.30) vanishes (inf if never, c >= 0)."""
    return (2 - 1 / c) / 2.5 if c < 0 else math.inf


def curve(actuator: CircularActuator, *, n: int = 400, steps: int = DEFAULT_STEPS) -> Curve:
    """One voltage-stretch curve (convenience wrapper around :func:`branch`/:func:`curves`):
    circle A (3.28)-(3.32) on the annulus branch (3.33)-(3.38), with the material law of
    ``actuator.annulus`` (Gent (3.23) of ``Jm``, or its library ``elastomer``), its events
    (pull-in, loss of tension, breakdown) located."""
    v.instance("actuator", actuator, CircularActuator)
    br = branch(actuator.annulus, n=n, steps=steps)
    return curves(br, [actuator.c], eps_r=actuator.eps_r, mu=actuator.mu)[0]
