"""Iterative solvers run side by side, one shooting integration per round for all of them.

A *solver* is a generator that yields a :class:`Request` (one inward RK4 integration of
annulus B, :func:`~debench.models.circular.integrator.integrate`) and receives the
(lambda_1, lambda_2) at R_A of its trajectories, until it returns its result.
:func:`lockstep` advances many solvers together and :func:`run` one alone; the
event location, the Newton iterations on the shooting parameter and the suppression
searches of :mod:`debench.models.circular` are written as such solvers, so that a batch of
them (the chapter pass) pays the fixed cost of an integration once per round.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .integrator import integrate
from .params import Annulus


@dataclass(frozen=True)
class Request:
    """One integration a solver asks :func:`lockstep` for: RK4 from the frame inwards for
    the shooting parameters ``q`` (1-D, real or complex), with per-trajectory pre-stretch
    ``lamP`` and balance ``membrane`` (bool: thin-membrane, else (3.33) as printed) of
    annuli like ``annulus`` (its R_B/R_A and Jm), ``steps`` RK4 steps."""

    annulus: Annulus
    q: np.ndarray
    lamP: np.ndarray
    membrane: np.ndarray
    steps: int

    @classmethod
    def of(cls, annulus: Annulus, q, steps: int, lamP=None, membrane=None) -> Request:
        """The request of :func:`~debench.models.circular.integrator.integrate`
        ``(annulus, q, steps, lamP, membrane)`` (None: the annulus' own pre-stretch and
        equilibrium), flattened."""
        q = np.asarray(q)
        lp = np.broadcast_to(np.asarray(annulus.lamP if lamP is None else lamP, float),
                             q.shape)
        mb = np.broadcast_to(np.asarray(annulus.equilibrium == "membrane" if membrane is None
                                        else membrane, bool), q.shape)
        return cls(annulus, q.ravel(), lp.ravel(), mb.ravel(), int(steps))


def lockstep(solvers) -> list:
    """Run iterative solvers side by side, one shooting integration per round for all.

    Each solver is a generator that yields a :class:`Request` and receives the (lambda_1,
    lambda_2) at R_A of its trajectories (as
    :func:`~debench.models.circular.integrator.integrate`: NaN where inadmissible), until it
    returns its result. Every round integrates the pending
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
                    key = (r.annulus.radius_ratio, r.annulus.law, r.steps)
                    groups.setdefault(key, []).append(k)
            for ks in groups.values():
                reqs = [pending[k] for k in ks]
                l1, l2 = integrate(
                    reqs[0].annulus, np.concatenate([r.q for r in reqs]),
                    steps=reqs[0].steps, lamP=np.concatenate([r.lamP for r in reqs]),
                    membrane=np.concatenate([r.membrane for r in reqs]))
                ends = np.cumsum([0] + [r.q.size for r in reqs])
                for k, a, b in zip(ks, ends[:-1], ends[1:], strict=True):
                    advance(k, (l1[a:b], l2[a:b]))
    return results


def run(solver):
    """:func:`lockstep` of one solver: its result."""
    return lockstep([solver])[0]
