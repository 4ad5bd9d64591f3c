"""The equilibrium path of the imperfect film and the eigenvalue crossings along it (Ch. 5).

:func:`follow_path` follows the axisymmetric path (voltage control, then centre-deflection
control through the voltage maximum) and records the lowest eigenvalue of chosen
wavenumbers at its states; :func:`zero_crossing` locates where one of them vanishes (for
n = 0 the voltage maximum, pull-in; for n >= 1 a bifurcation into wrinkles) by
:func:`~debench.models.numerics.secants.secant_zero`. The formulation:
:mod:`debench.models.buckling.axisym`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from debench.models import validation as val
from debench.models.buckling.axisym.model import AxisymModel
from debench.models.errors import ConvergenceError, require
from debench.models.numerics.continuation import StepControl
from debench.models.numerics.secants import secant_zero


@dataclass(frozen=True)
class PathPoint:
    """One converged state of the imperfect film: centre deflection ``w`` (top surface, t0),
    normalised voltage ``v``, centre thickness / t0, normalised true centre field ``e``, the
    lowest eigenvalue of each recorded wavenumber (``lam[n]``, fixed voltage), and the
    Newton residual relative to its reference."""

    w: float
    v: float
    thickness: float
    e: float
    lam: dict
    newton_residual_rel: float
    state: np.ndarray = field(repr=False, default_factory=lambda: np.zeros(0))


def _record(model: AxisymModel, wavenumbers) -> PathPoint:
    lam = {int(n): float(model.spectrum(int(n), nev=1).lam[0]) for n in wavenumbers}
    return PathPoint(w=model.centre_deflection(), v=model.v, thickness=model.centre_thickness(),
                     e=model.centre_field(), lam=lam,
                     newton_residual_rel=model.last_newton.residual_rel,
                     state=model.state())


ZERO_WTOL = 1e-9
"""The secant on lambda_n(w) = 0 stops when its step in the deflection is below ZERO_WTOL t0
(the voltage at a voltage maximum is stationary in w, so its error is second order)."""
ZERO_STALL_W = 1e-6
"""... or when it has stagnated at the eigenvalue's round-off floor: its last
ZERO_STALL_COUNT iterates all within ZERO_STALL_W t0 of each other without a step below
ZERO_WTOL. The floor: the Newton states carry round-off of ~1e-10 of the load next to the
near-singular tangent, which moves lambda_n by ~1e-11..1e-10; over its slope along the path
(1e-4..1e-3 per t0) that is 1e-7..1e-6 t0 in w (measured: an Ogden film at R/t0 = 20,
n = 6, iterates wandering within 1e-7 t0 at |lambda| ~ 5e-11). The crossing is then the
iterate with the smallest |lambda|, and ``wtol`` the spread of the stagnated iterates. A
bracket of the root (the usual case: the two recorded states about the sign change) is
closed to below ZERO_STALL_W t0, the computed signs bounding the root whatever the floor."""
ZERO_STALL_COUNT = 4
"""How many last iterates of the secant must lie within ZERO_STALL_W (and bracket the root)
for it to count as stagnated."""


@dataclass(frozen=True)
class Crossing:
    """Where the lowest eigenvalue of wavenumber ``n`` vanishes along the path: deflection
    ``w`` (t0), voltage ``v``, centre thickness; ``wtol`` the secant's last step. For n = 0
    this is the voltage maximum (pull-in)."""

    n: int
    w: float
    v: float
    thickness: float
    wtol: float


def zero_crossing(model: AxisymModel, points: list[PathPoint], n: int,
                  *, maxit: int = 30) -> Crossing | None:
    """The first zero of the wavenumber-n eigenvalue along a recorded path (None if it does
    not change sign there): secant in the deflection between the two recorded states that
    bracket the sign change, each trial state by deflection control from the nearer one."""
    n = val.integer_at_least("n", n, 0)
    pts = [p for p in points if n in p.lam]
    for a, b in zip(pts, pts[1:], strict=False):
        if a.lam[n] >= 0 > b.lam[n]:
            break
    else:
        return None
    ws, ls, states = [a.w, b.w], [a.lam[n], b.lam[n]], [(a.state, a.v), (b.state, b.v)]

    def lam_at(w_new):
        near = min(range(len(ws)), key=lambda k: abs(ws[k] - w_new))
        deflect_from(model, states[near], ws[near], w_new)
        lam = float(model.spectrum(n, nev=1).lam[0])
        states.append((model.state(), model.v))
        return lam

    k, wtol = secant_zero(lam_at, ws, ls, xtol=ZERO_WTOL, stall_width=ZERO_STALL_W,
                          stall_count=ZERO_STALL_COUNT, maxit=maxit,
                          what=f"zero_crossing(n={n})")
    model.set_state(states[k][0])
    model.v = states[k][1]
    return Crossing(n=n, w=ws[k], v=model.v, thickness=model.centre_thickness(), wtol=wtol)


def deflect_from(model: AxisymModel, start: tuple[np.ndarray, float], w0: float,
                  w_new: float, *, max_substeps: int = 16) -> None:
    """Equilibrate ``model`` at the deflection ``w_new`` from the recorded state ``start``
    (state vector, voltage) at deflection ``w0``: one deflection-controlled Newton solve, or,
    when it does not converge, 2, 4, ... ``max_substeps`` equal deflection steps from
    ``start`` (each converged state the next one's initial guess). Raises the last
    ConvergenceError when the finest subdivision fails too."""
    m = 1
    while True:
        model.set_state(start[0])
        model.v = start[1]
        try:
            for j in range(1, m + 1):
                model.newton_deflection(w0 + (w_new - w0) * j / m)
            return
        except ConvergenceError:
            if 2 * m > max_substeps:
                raise
            m *= 2


PATH_STALL_STEPS = 8
"""A deflection-controlled Newton solve of a path step gives up when that many steps have
not lowered its best residual: a step too long for the damped Newton wanders at ~1e-5 ..
1e-4 of its first residual for all NEWTON_MAXIT steps (measured near the voltage maximum of
the neo-Hookean film, order 3), while every converging solve improves at each step or
two; the path then halves the step."""
PATH_EASY_ITERATIONS = 4
"""A deflection step whose Newton solve took at most this many iterations is easy: the next
step doubles (up to the cap)."""
PATH_GROW_AFTER = 4
"""Easy deflection steps in a row after which the path lets its step grow past the size
that last failed (doubling the cap up to ``dw_max``; the cautious regrowth of
:class:`~debench.models.numerics.continuation.StepControl`): near the voltage maximum a
doubled step fails again at once (measured: every second step failed, each costing a
stalled Newton solve, on the neo-Hookean film at order 3)."""


def follow_path(model: AxisymModel, w_end: float, *, v_switch: float, dv: float = 0.01,
                dw0: float = 0.02, dw_max: float = 0.5, wavenumbers=(0, 1),
                record_every: float = 0.0, max_points: int = 2000,
                stop_past_maximum: bool = True, all_from: float = math.inf,
                all_wavenumbers=()) -> list[PathPoint]:
    """Equilibrium path of the imperfect film: voltage control up to ``v_switch`` (steps
    ``dv``), then centre-deflection control (:meth:`AxisymModel.newton_deflection`) up to
    ``w_end`` with adaptive steps (from ``dw0``, doubled after an easy step, halved after a
    failed one, which is undone; never above ``dw_max`` nor, after a failure, above the
    halved size until :data:`PATH_GROW_AFTER` easy steps in a row, so that a step that just
    failed is not tried again at once) and a secant predictor. Every
    converged state of the deflection branch is recorded with the lowest eigenvalue of each
    of ``wavenumbers`` (``record_every`` > 0: only states at least that far in w apart),
    from the deflection ``all_from`` on with those of ``all_wavenumbers`` too.
    With ``stop_past_maximum`` the path ends at the first recorded state whose wavenumber-0
    eigenvalue is negative (past the voltage maximum, where the tangent at fixed voltage
    turns indefinite), or, when a step fails from a state past the maximum (its
    wavenumber-0 eigenvalue negative), at that last converged state. Raises
    ConvergenceError when the step falls below 1e-6 t0 before the maximum."""
    v_switch = val.positive("v_switch", v_switch)
    w_end = val.finite("w_end", w_end)
    require(0 in tuple(wavenumbers) or not stop_past_maximum,
            "stop_past_maximum needs wavenumber 0 among the recorded wavenumbers")
    model.reset()
    for v in np.arange(dv, v_switch + 0.5 * dv, dv):
        model.set_voltage(float(v))
        model.newton()
    points = [_record(model, wavenumbers)]
    prev = None
    w = model.centre_deflection()
    dw = StepControl(dw0, dw_max, grow=2.0, easy_iterations=PATH_EASY_ITERATIONS,
                     min_size=1e-6, regrow_after=PATH_GROW_AFTER)
    last_w_rec = w
    while w < w_end and len(points) < max_points:
        x0, v0 = model.state(), model.v
        target = min(w + dw.size, w_end)
        if prev is not None:            # secant predictor in the deflection
            xp, vp, wp = prev
            f = (target - w) / (w - wp)
            model.set_state(x0 + f * (x0 - xp))
            model.v = v0 + f * (v0 - vp)
        try:
            its = model.newton_deflection(target, stall=PATH_STALL_STEPS).iterations
        except ConvergenceError:
            model.set_state(x0)
            model.v = v0
            if stop_past_maximum and prev is not None:
                # a step from a state past the voltage maximum failed (there the
                # deflection-controlled tangent may turn singular again, or the state reach
                # the edge of the material's domain at a clamped corner): the path ends at
                # that last converged state, which its wavenumber-0 eigenvalue at fixed
                # voltage (negative) shows past the maximum; nothing beyond it is used
                last = _record(model, wavenumbers)
                if last.lam[0] < 0:
                    points.append(last)
                    break
            if not dw.failed():
                raise
            continue
        prev, w = (x0, v0, _w_of(x0, model)), target
        dw.converged(its)
        if record_every <= 0 or w - last_w_rec >= record_every or w >= w_end:
            ns = sorted(set(wavenumbers) | (set(all_wavenumbers) if w >= all_from else set()))
            points.append(_record(model, ns))
            last_w_rec = w
            if stop_past_maximum and points[-1].lam[0] < 0:
                break
    return points


def _w_of(x: np.ndarray, model: AxisymModel) -> float:
    return float(x[model._centre_dof()]) / model.plate.thickness
