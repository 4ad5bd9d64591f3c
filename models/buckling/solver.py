"""Solvers of the Chapter 5 model: critical voltage, voltage ramp, Southwell, pull-in.

All voltages are normalised, ``v = Phi/t0 sqrt(eps/mu_ref)`` (mu_ref = 156 kPa, the
Table 5.1 shear modulus; catalogued assumption ``ch5.assumption.normalisation``);
deflections are in units of t0.  Results are small frozen dataclasses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from debench.models import validation as val
from debench.models.buckling import deflection
from debench.models.buckling.analytic import critical_voltage_plate
from debench.models.buckling.critical_result import CriticalVoltage
from debench.models.buckling.fem import MembraneModel
from debench.models.buckling.modes import deflection_asymmetry, mode_harmonics
from debench.models.buckling.parameters import Discretisation, Plate
from debench.models.buckling.ramp_result import (  # noqa: F401 - southwell: read off a ramp
    RampResult,
    southwell,
)
from debench.models.errors import ConvergenceError, require
from debench.models.materials.protocol import IdealDielectricElastomer
from debench.models.numerics.continuation import StepControl
from debench.models.numerics.secants import secant_until

CRITICAL_VTOL = 1e-6
"""The secant on lambda_1(v^2) = 0 stops when its step |dv| < CRITICAL_VTOL (normalised
voltage; v_cr ~ 0.2, so 5e-6 relative)."""


@dataclass(frozen=True, kw_only=True)
class CriticalResult(CriticalVoltage):
    """Bifurcation of the perfect flat film on the 3D prism mesh: the fields of
    :class:`~debench.models.buckling.critical_result.CriticalVoltage` (``v`` to ``vtol``,
    see :func:`critical_voltage`), and ``newton_residual``, ``newton_iterations``: the
    residual norm reached by the last Newton solve and its iterations; ``nelements``,
    ``h_rel`` (in-plane mesh size / t0), ``layers``: the mesh; ``stats``: timings and
    counts (factorisations, Newton steps, eigen-analyses).
    """

    nelements: int
    newton_residual: float = float("nan")
    newton_iterations: int = 0
    h_rel: float = float("nan")
    layers: int = 0
    stats: dict = field(default_factory=dict)


def critical_voltage(plate: Plate, mat: IdealDielectricElastomer, disc: Discretisation,
                     *, inverse: str = "sparsecholesky", reuse: bool = True,
                     eigensolver: str = "lobpcg", chord: bool = True, maxit: int = 20,
                     vtol: float = CRITICAL_VTOL) -> CriticalResult:
    """Critical normalised voltage of the perfect clamped film by linearised eigen-analysis.

    The flat pre-buckled state is equilibrated at each trial voltage (Newton, stopping on
    a residual relative to its first or at its round-off floor); the algebraically
    smallest eigenvalue of the condensed tangent stiffness at fixed voltage is driven to
    zero by the secant method in ``v^2`` (the prestress is proportional to v^2), started
    at 0.8 and 0.95 times the plate-theory estimate.

    Accuracy contract: the returned ``v`` is the zero of the lowest eigenvalue *of this
    mesh* to within ``vtol`` (default 1e-6, i.e. ~5e-6 relative): the secant stops at the
    evaluated voltage whose next secant step is below ``vtol`` (the secant converges
    superlinearly, so that step is its error to higher order);
    each eigenvalue is converged to a relative eigen-residual below ``eigen.EIG_RTOL`` (the
    achieved value is ``eig_residual``) at a Newton state whose residual is reported
    (``newton_residual``).  The secant's eigen-solves are not certified one by one; the
    final state is (inertia count,
    :meth:`~debench.models.buckling.fem.MembraneModel.lowest_eigenvalues`): no eigenvalue
    lies below the one driven to zero, so ``v`` is the first critical voltage, not a higher
    mode's (ConvergenceError otherwise).  The discretisation error is *not* included: it is
    measured by the mesh sequence of ``reference/builders/ch5.py`` (about 4 % at h = 3 t0,
    0.6 % at h = 1 t0 for one layer of quadratic prisms).

    ``inverse``, ``reuse``, ``eigensolver``, ``chord``: linear algebra of
    :class:`~debench.models.buckling.fem.MembraneModel` (``"umfpack", reuse=False,
    eigensolver="subspace", chord=False`` is the engine before the measured choice).  Raises
    ConvergenceError if the secant does not converge in ``maxit`` steps, ValueError on bad
    input.
    """
    maxit = val.integer_at_least("maxit", maxit, 1)
    vtol = val.tolerance("vtol", vtol)
    model = MembraneModel(plate, mat, disc, with_imperfection=False, inverse=inverse,
                          reuse=reuse, eigensolver=eigensolver, chord=chord)
    v_est = critical_voltage_plate(mat, plate.aspect)
    mode = [None]
    hist: list[tuple[float, float]] = []

    def lam_at(x):
        model.set_voltage(math.sqrt(x))
        model.newton()
        w, modes = model.lowest_eigenvalues(nev=1, x0=mode[0], certify=False)
        mode[0] = modes
        hist.append((math.sqrt(x), float(w[0])))
        return float(w[0])

    # the secant converges superlinearly: the error of the evaluated point is its next
    # step to within higher order, so a next step below vtol ends the iteration there
    # (without evaluating at the singular tangent itself)
    res = secant_until(lam_at, (0.8 * v_est) ** 2, (0.95 * v_est) ** 2,
                       converged=lambda x, x_next: abs(math.sqrt(x_next) - math.sqrt(x)) < vtol,
                       finish="evaluated", maxiter=maxit, bounds=(0.0, math.inf),
                       what="critical_voltage")
    return _certified_critical(model, disc, math.sqrt(res.root), hist[-1][1], mode[0],
                               res.function_calls, hist, vtol)


def _certified_critical(model: MembraneModel, disc: Discretisation, v: float, lam: float,
                        mode, iterations: int, hist, vtol: float) -> CriticalResult:
    """The :class:`CriticalResult` at the secant's last voltage ``v`` (eigenvalue ``lam``),
    once the inertia count finds no eigenvalue below the one driven to zero
    (ConvergenceError otherwise: a higher mode's crossing)."""
    lowest, _ = model.lowest_eigenvalues(nev=1, x0=mode)
    if model.last_eig["shift"] != 0.0:
        raise ConvergenceError(
            f"critical_voltage: at v = {v:.6g} the secant drove an eigenvalue to zero "
            f"with a lower one at {float(lowest[0]):.6g} (a higher mode's crossing)")
    th = model.centre_thickness()
    ln = model.last_newton
    return CriticalResult(
        v=v, e=v / th, thickness=th, ndof=model.ndof, nelements=model.nelements,
        iterations=iterations, history=tuple(hist), lam=lam,
        eig_residual=model.last_eig["residual"], newton_residual=ln.residual,
        newton_residual_rel=ln.residual_rel, newton_iterations=ln.iterations,
        vtol=vtol, h_rel=disc.h_rel, layers=disc.layers, order=disc.order,
        stats=dict(model.stats))


def voltage_ramp(plate: Plate, mat: IdealDielectricElastomer, disc: Discretisation, *,
                 v_max: float = 1.5, dv0: float = 0.02, dv_max: float = 0.02,
                 dw_max: float = 0.5, inverse: str = "sparsecholesky", reuse: bool = True,
                 eigensolver: str = "lobpcg", chord: bool = True, progress=None,
                 max_steps: int = 2000, eig_every: int = 0, v_switch: float | None = None,
                 dc: float | None = None, c_max: float | None = None,
                 drop: float = 0.01, stop_on_stall: bool = False) -> RampResult:
    """Continuation of the imperfect film to and past pull-in.

    Phase 1, voltage control (Newton in v, secant predictor) up to ``v_switch`` (default:
    1.3 x the plate-theory critical voltage) or ``v_max``.  Step control: a step is
    rejected and halved when Newton fails, when the mid-plane centre deflection *decreases* (the
    iteration slid back towards the unstable flat branch or jumped to the mirror branch),
    or when it jumps by more than ``dw_max`` t0.
    Phase 2, deflection control (bordered Newton, the voltage is an unknown): the centre
    deflection is raised in steps ``dc`` t0 (halved on failure; default 0.02 x the
    radius/thickness ratio, i.e. 0.2 t0 at the thesis' 10, since the deflections scale
    with the radius) until the voltage has dropped by ``drop`` below its maximum (pull-in =
    the voltage limit point, passed) or ``c_max`` (default 1.2 x radius/thickness); a
    singular tangent past the maximum also ends the path (``RampResult.end``); before it,
    a deflection step that cannot be completed (step below 1e-3 t0) raises
    ConvergenceError, or with ``stop_on_stall`` ends the path with ``end = "stalled before
    the limit point"`` after an eigen-analysis of the last converged state (with
    ``eig_every > 0``), which documents what made the tangent singular (e.g. a
    non-axisymmetric bifurcation); ``v_pullin`` is then None.
    The pull-in voltage is the vertex of the parabola through the three points
    around the maximum.  With ``eig_every > 0`` the three algebraically smallest
    eigenvalues of the condensed tangent (LOBPCG: negative ones at any depth) and the
    axisymmetric fraction of their modes are recorded every ``eig_every`` steps and at the
    first point past the limit point (stability, wrinkling detection).

    Accuracy contract: every recorded point is an equilibrium of this mesh whose residual
    is reported (``newton_residual``: Newton stopped on ``max|du| < 1e-9 t0``, a residual
    1e-10 times its first, or the round-off floor); the pull-in voltage is the vertex of a
    parabola through three path points around the maximum, so its error is that of the
    quadratic interpolation over steps of at most ``dc`` t0 (the bracket
    ``pullin_bracket`` = (largest computed v, v_pullin) bounds it from below; measured
    < 1e-3 relative on the coarse mesh) plus the discretisation error of the mesh (not
    included; h = 2 t0 vs 1 t0 is measured in ``reference/builders/ch5.py``).  Eigenvalues
    carry their relative eigen-residual (``eig_residual``).  A step whose tangent is
    singular (the iterate landed on a bifurcation or on the limit point) is rejected and
    retried with half the step, never passed silently.
    """
    require(v_max > 0, f"v_max must be > 0, got {v_max}")
    require(0 < dv0 <= dv_max, f"need 0 < dv0 <= dv_max, got {dv0}, {dv_max}")
    dc = 0.02 * plate.aspect if dc is None else dc
    c_max = 1.2 * plate.aspect if c_max is None else c_max
    require(dc > 0, f"dc must be > 0, got {dc}")
    require(c_max > 0, f"c_max must be > 0, got {c_max}")
    model = MembraneModel(plate, mat, disc, with_imperfection=True, inverse=inverse,
                          reuse=reuse, eigensolver=eigensolver, chord=chord)
    path = _RampPath(model, eig_every, progress)
    if v_switch is None:
        v_switch = 1.3 * critical_voltage_plate(mat, plate.aspect)
    v_switch = min(v_switch, v_max)
    path.record(0)
    states = [model.state()]
    steps = _voltage_control(path, states, v_switch, dv0, dv_max, dw_max, max_steps)
    bracket = None
    v_pull = w_pull = None
    end = "v_max"
    if v_switch < v_max:
        end = _deflection_control(path, states, steps, dc, c_max, drop, max_steps,
                                  stop_on_stall)
        v_pull, w_pull, bracket = _pullin_vertex(path.rec, end)
    return path.result(v_pull, w_pull, bracket, disc, end)


class _RampPath:
    """The points of a ramp as they are reached: the recorded quantities per point
    (``rec``) and the eigen-records (``eig``) of :class:`~.ramp_result.RampResult`."""

    def __init__(self, model: MembraneModel, eig_every: int, progress):
        self.model = model
        self.eig_every = eig_every
        self.progress = progress
        self.rec = {k: [] for k in ("v", "w", "w_mid", "thickness", "e_centre", "e_max",
                                    "its", "res", "w_asym", "n_asym")}
        self.eig = {"v": [], "w": [], "lam": [], "ax": [], "n": [], "res": []}

    def record(self, its):
        """Record the model's current state, reached in ``its`` Newton iterations (and an
        eigen-record every ``eig_every`` points)."""
        model, rec = self.model, self.rec
        rec["v"].append(model.v)
        rec["w"].append(model.centre_deflection())
        rec["w_mid"].append(model.centre_midplane_deflection())
        rec["thickness"].append(model.centre_thickness())
        rec["e_centre"].append(model.v / rec["thickness"][-1])
        rec["e_max"].append(model.max_true_field())
        amp, n = deflection_asymmetry(model)
        rec["w_asym"].append(amp)
        rec["n_asym"].append(n)
        rec["its"].append(its)
        rec["res"].append(model.last_newton.residual if its else 0.0)
        if self.eig_every and len(rec["v"]) % self.eig_every == 0:
            self.eig_record()
        if self.progress is not None:
            self.progress(model.v, rec["w"][-1])

    def eig_record(self):
        """The three lowest eigenvalues of the condensed tangent at the current state, the
        axisymmetric fraction and the dominant wavenumber of their modes."""
        # a random start every time: starting modes from the previous record can hide a
        # mode that became unstable since (MembraneModel.lowest_eigenvalues)
        model, eig = self.model, self.eig
        lam, modes = model.lowest_eigenvalues(nev=3)
        eig["res"].append(model.last_eig["residual"])
        eig["v"].append(model.v)
        eig["w"].append(self.rec["w"][-1])
        eig["lam"].append(lam)
        harm = [mode_harmonics(model, modes[:, j]) for j in range(3)]
        eig["ax"].append([float(hj[0]) for hj in harm])
        eig["n"].append([int(np.argmax(hj)) for hj in harm])

    def result(self, v_pull, w_pull, bracket, disc: Discretisation, end: str) -> RampResult:
        """The :class:`~.ramp_result.RampResult` of the recorded path."""
        model, eig = self.model, self.eig
        arr = {k: np.array(val) for k, val in self.rec.items()}
        return RampResult(
            v=arr["v"], w=arr["w"], w_mid=arr["w_mid"], thickness=arr["thickness"],
            e_centre=arr["e_centre"], e_max=arr["e_max"], newton_its=arr["its"],
            v_pullin=v_pull, w_pullin=w_pull, pullin_bracket=bracket,
            ndof=model.ndof, nelements=model.nelements, stats=dict(model.stats),
            eig_v=np.array(eig["v"]), eig_w=np.array(eig["w"]),
            eig_lam=np.array(eig["lam"]).reshape(-1, 3),
            eig_axisym=np.array(eig["ax"]).reshape(-1, 3),
            eig_wavenumber=np.array(eig["n"], dtype=np.int64).reshape(-1, 3),
            newton_residual=arr["res"], eig_residual=np.array(eig["res"]),
            w_asym=arr["w_asym"], n_asym=arr["n_asym"].astype(np.int64),
            h_rel=disc.h_rel, layers=disc.layers, order=disc.order, end=end)


def _voltage_control(path: _RampPath, states: list, v_switch, dv0, dv_max, dw_max,
                     max_steps) -> int:
    """Phase 1 of :func:`voltage_ramp`: Newton in v with a secant predictor from 0 to
    ``v_switch``, each converged state recorded and appended to ``states``; returns the
    steps taken (rejected ones included)."""
    model, rec = path.model, path.rec
    dv = StepControl(dv0, dv_max, grow=1.5, easy_iterations=4)
    v = 0.0
    steps = 0
    while v < v_switch - 1e-14:
        steps += 1
        if steps > max_steps:
            raise ConvergenceError(f"voltage_ramp: exceeded {max_steps} steps at v={v}")
        v_try = min(v + dv.size, v_switch)
        x0 = states[-1]
        if len(states) >= 2:
            h_prev = rec["v"][-1] - rec["v"][-2]
            x0 = states[-1] + (v_try - v) / h_prev * (states[-1] - states[-2])
        model.set_state(x0)
        model.set_voltage(v_try)
        ok = True
        try:
            its = model.newton().iterations
            w_new = model.centre_midplane_deflection()   # free of the symmetric thinning
            if w_new < rec["w_mid"][-1] - 1e-12 or abs(w_new - rec["w_mid"][-1]) > dw_max:
                ok = False
        except ConvergenceError:
            ok = False
        if not ok:
            model.set_state(states[-1])
            model.set_voltage(v)
            # a step is not halved below half of 1e-4 of the voltage reached
            if not dv.failed(min_size=1e-4 * max(v, 1e-2) / 2):
                raise ConvergenceError(f"voltage_ramp: step collapsed at v={v:.6g}")
            continue
        v = v_try
        path.record(its)
        states.append(model.state())
        dv.converged(its)
    return steps


def _deflection_control(path: _RampPath, states: list, steps: int, dc, c_max, drop,
                        max_steps, stop_on_stall) -> str:
    """Phase 2 of :func:`voltage_ramp`: the centre deflection raised in steps of at most
    ``dc`` (bordered Newton, the voltage an unknown) until the voltage has dropped by
    ``drop`` below its maximum or ``c_max``; ``steps``: those phase 1 took. Returns why
    the path stopped (``RampResult.end``)."""
    model, rec, eig_every = path.model, path.rec, path.eig_every
    c = deflection.control_deflection(model)
    # every converged step grows the next one, up to dc; a step is not halved below 5e-4 t0
    step = StepControl(dc, dc, grow=1.5, easy_iterations=None, min_size=5e-4)
    vmax_seen = model.v
    passed = False
    while c < c_max:
        steps += 1
        if steps > max_steps:
            raise ConvergenceError(f"voltage_ramp: exceeded {max_steps} steps at c={c}")
        x_prev, v_prev = model.state(), model.v
        try:
            its = deflection.newton_deflection(model, c + step.size).iterations
        except ConvergenceError:
            model.set_state(x_prev)
            model.set_voltage(v_prev)
            if not step.failed():
                if _past_maximum(rec["v"]):
                    return "singular past the limit point"
                if stop_on_stall:
                    if eig_every:
                        path.eig_record()
                    return "stalled before the limit point"
                raise
            continue
        c += step.size
        path.record(its)
        states.append(model.state())
        if eig_every and not passed and model.v < rec["v"][-2]:
            passed = True
            path.eig_record()   # first state past the limit point: lambda_1 < 0 expected
        vmax_seen = max(vmax_seen, model.v)
        if model.v < (1 - drop) * vmax_seen:
            return "voltage drop"
        step.converged(its)
    return "c_max"


def _pullin_vertex(rec: dict, end: str):
    """``(v_pullin, w_pullin, pullin_bracket)`` of :class:`~.ramp_result.RampResult`: the
    vertex of the parabola v(w) through the three recorded points around the voltage
    maximum (None when the maximum is not interior or the path stalled before it)."""
    vv = np.array(rec["v"])
    k = int(np.argmax(vv))
    if 0 < k < len(vv) - 1 and end != "stalled before the limit point":
        ww = np.array(rec["w"][k - 1:k + 2])
        cf = np.polyfit(ww, vv[k - 1:k + 2], 2)
        xs = -cf[1] / (2 * cf[0])
        v_pull = float(np.polyval(cf, xs))
        return v_pull, float(xs), (float(vv[k]), v_pull)
    return None, None, None


def _past_maximum(v) -> bool:
    """The recorded voltages have an interior maximum followed by a lower point: the
    limit point is bracketed by three path points."""
    v = np.asarray(v)
    k = int(np.argmax(v))
    return 0 < k < v.size - 1 and v[-1] < v[k]
