"""Solvers of the Chapter 5 model: critical voltage, voltage ramp, Southwell, pull-in.

All voltages are normalised, ``v = Phi/t0 sqrt(eps/mu_ref)`` (mu_ref = 156 kPa, the
Table 5.1 shear modulus; catalogued assumption ``ch5.assumption.normalisation``);
deflections are in units of t0.  Results are small frozen dataclasses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from debench.models.buckling.analytic import critical_voltage_plate
from debench.models.buckling.fem import MembraneModel, mode_axisymmetry
from debench.models.buckling.parameters import Discretisation, NeoHookean, Ogden, Plate
from debench.models.errors import ConvergenceError, require

CRITICAL_VTOL = 1e-6     # secant on lambda_1(v^2) = 0 stops when |dv| < this


@dataclass(frozen=True)
class CriticalResult:
    """Bifurcation of the perfect flat film: lambda_1(S(v_cr)) = 0."""

    v: float                      # normalised critical voltage
    e: float                      # normalised true field at v (flat film)
    thickness: float              # thickness stretch of the flat film at v
    ndof: int
    nelements: int
    iterations: int
    history: tuple = field(default=())


def critical_voltage(plate: Plate, mat: NeoHookean | Ogden, disc: Discretisation,
                     *, inverse: str = "umfpack", maxit: int = 20) -> CriticalResult:
    """Critical normalised voltage of the perfect clamped film by linearised eigen-analysis.

    The flat pre-buckled state is equilibrated at each trial voltage (Newton); the
    smallest eigenvalue of the condensed tangent stiffness at fixed voltage is driven to
    zero by the secant method in ``v^2`` (the prestress is proportional to v^2).  Raises
    ConvergenceError if the secant does not converge in ``maxit`` steps.
    """
    model = MembraneModel(plate, mat, disc, with_imperfection=False, inverse=inverse)
    v_est = critical_voltage_plate(mat, plate.aspect)

    def lam_at(v):
        model.set_voltage(v)
        model.newton()
        w, _ = model.lowest_eigenvalues(nev=1)
        return float(w[0])

    xs = [(0.8 * v_est) ** 2, (0.95 * v_est) ** 2]
    ls = [lam_at(math.sqrt(x)) for x in xs]
    hist = [(math.sqrt(x), lv) for x, lv in zip(xs, ls, strict=True)]
    for it in range(maxit):
        x_new = xs[-1] - ls[-1] * (xs[-1] - xs[-2]) / (ls[-1] - ls[-2])
        if not (x_new > 0 and math.isfinite(x_new)):
            raise ConvergenceError(f"critical_voltage: secant left the domain (v^2={x_new})")
        l_new = lam_at(math.sqrt(x_new))
        hist.append((math.sqrt(x_new), l_new))
        dv = abs(math.sqrt(x_new) - math.sqrt(xs[-1]))
        xs.append(x_new)
        ls.append(l_new)
        if dv < CRITICAL_VTOL or l_new == 0.0:
            v = math.sqrt(x_new)
            return CriticalResult(v=v, e=v / model.centre_thickness(),
                                  thickness=model.centre_thickness(), ndof=model.ndof,
                                  nelements=model.nelements, iterations=it + 3,
                                  history=tuple(hist))
    raise ConvergenceError(f"critical_voltage: secant did not converge in {maxit} steps: {hist}")


@dataclass(frozen=True)
class RampResult:
    """Voltage-controlled ramp of the imperfect film.

    Arrays along the converged path: ``v`` normalised voltage, ``w`` centre deflection of
    the top surface / t0, ``thickness`` centre thickness / t0, ``e_centre`` normalised
    true field at the centre, ``e_max`` largest sampled true field.  The path continues a
    little past the voltage maximum (deflection control).  ``v_pullin``, ``w_pullin``: the
    limit point (vertex of the parabola v(w) through the three points around the maximum;
    None if not reached); ``pullin_bracket`` = (largest computed v, v_pullin).
    """

    v: np.ndarray
    w: np.ndarray
    w_mid: np.ndarray
    thickness: np.ndarray
    e_centre: np.ndarray
    e_max: np.ndarray
    newton_its: np.ndarray
    v_pullin: float | None
    w_pullin: float | None
    pullin_bracket: tuple[float, float] | None
    ndof: int
    nelements: int
    stats: dict
    eig_v: np.ndarray = field(default_factory=lambda: np.zeros(0))
    eig_w: np.ndarray = field(default_factory=lambda: np.zeros(0))
    eig_lam: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    eig_axisym: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))

    def wrinkling_onset(self, axisym_max: float = 0.5):
        """First recorded state where a non-axisymmetric mode (n = 0 fraction below
        ``axisym_max``) has a negative eigenvalue: (v, w) interpolated linearly between the
        last stable and the first unstable record, or None."""
        prev = None
        for i in range(len(self.eig_v)):
            bad = (self.eig_lam[i] < 0) & (self.eig_axisym[i] < axisym_max)
            if np.any(bad):
                if prev is None:
                    return float(self.eig_v[i]), float(self.eig_w[i])
                lam0 = np.min(np.where(self.eig_axisym[prev] < axisym_max,
                                       self.eig_lam[prev], np.inf))
                lam1 = np.min(self.eig_lam[i][bad])
                f = lam0 / (lam0 - lam1) if np.isfinite(lam0) else 1.0
                return (float(self.eig_v[prev] + f * (self.eig_v[i] - self.eig_v[prev])),
                        float(self.eig_w[prev] + f * (self.eig_w[i] - self.eig_w[prev])))
            prev = i
        return None


EIG_SHIFT = 0.05   # shift of the path eigen-analysis: returns the algebraically smallest
                   # eigenvalues of S when they exceed -0.05 (lambda ~ 1e-2 here)


def voltage_ramp(plate: Plate, mat: NeoHookean | Ogden, disc: Discretisation, *,
                 v_max: float = 1.5, dv0: float = 0.02, dv_max: float = 0.02,
                 dw_max: float = 0.5, inverse: str = "umfpack", progress=None,
                 max_steps: int = 2000, eig_every: int = 0, v_switch: float | None = None,
                 dc: float = 0.2, c_max: float = 12.0, drop: float = 0.01) -> RampResult:
    """Continuation of the imperfect film to and past pull-in.

    Phase 1, voltage control (Newton in v, secant predictor) up to ``v_switch`` (default:
    1.3 x the plate-theory critical voltage) or ``v_max``.  Step control: a step is
    rejected and halved when Newton fails, when the mid-plane centre deflection *decreases* (the
    iteration slid back towards the unstable flat branch or jumped to the mirror branch),
    or when it jumps by more than ``dw_max`` t0.
    Phase 2, deflection control (bordered Newton, the voltage is an unknown): the centre
    deflection is raised in steps ``dc`` t0 (halved on failure) until the voltage has
    dropped by ``drop`` below its maximum (pull-in = the voltage limit point, passed) or
    ``c_max``.  The pull-in voltage is the vertex of the parabola through the three points
    around the maximum.  With ``eig_every > 0`` the three algebraically smallest
    eigenvalues of the condensed tangent (shift EIG_SHIFT) and the axisymmetric fraction of
    their modes are recorded every ``eig_every`` steps (stability, wrinkling detection).
    """
    require(v_max > 0, f"v_max must be > 0, got {v_max}")
    require(0 < dv0 <= dv_max, f"need 0 < dv0 <= dv_max, got {dv0}, {dv_max}")
    require(dc > 0, f"dc must be > 0, got {dc}")
    from debench.models.buckling.fem import control_deflection, newton_deflection
    model = MembraneModel(plate, mat, disc, with_imperfection=True, inverse=inverse)
    rec = {k: [] for k in ("v", "w", "w_mid", "thickness", "e_centre", "e_max", "its")}
    eig = {"v": [], "w": [], "lam": [], "ax": []}
    if v_switch is None:
        v_switch = 1.3 * critical_voltage_plate(mat, plate.aspect)
    v_switch = min(v_switch, v_max)

    def record(its):
        rec["v"].append(model.v)
        rec["w"].append(model.centre_deflection())
        rec["w_mid"].append(model.centre_midplane_deflection())
        rec["thickness"].append(model.centre_thickness())
        rec["e_centre"].append(model.v / rec["thickness"][-1])
        rec["e_max"].append(model.max_true_field())
        rec["its"].append(its)
        if eig_every and len(rec["v"]) % eig_every == 0:
            eig_record()
        if progress is not None:
            progress(model.v, rec["w"][-1])

    def eig_record():
        lam, modes = model.lowest_eigenvalues(nev=3, shift=EIG_SHIFT)
        eig["v"].append(model.v)
        eig["w"].append(rec["w"][-1])
        eig["lam"].append(lam)
        eig["ax"].append([mode_axisymmetry(model, modes[:, j]) for j in range(3)])

    record(0)
    states = [model.state()]
    dv = dv0
    v = 0.0
    steps = 0
    while v < v_switch - 1e-14:
        steps += 1
        if steps > max_steps:
            raise ConvergenceError(f"voltage_ramp: exceeded {max_steps} steps at v={v}")
        v_try = min(v + dv, v_switch)
        x0 = states[-1]
        if len(states) >= 2:
            h_prev = rec["v"][-1] - rec["v"][-2]
            x0 = states[-1] + (v_try - v) / h_prev * (states[-1] - states[-2])
        model.set_state(x0)
        model.set_voltage(v_try)
        ok = True
        try:
            its = model.newton()
            w_new = model.centre_midplane_deflection()   # free of the symmetric thinning
            if w_new < rec["w_mid"][-1] - 1e-12 or abs(w_new - rec["w_mid"][-1]) > dw_max:
                ok = False
        except ConvergenceError:
            ok = False
        if not ok:
            model.set_state(states[-1])
            model.set_voltage(v)
            if dv < 1e-4 * max(v, 1e-2):
                raise ConvergenceError(f"voltage_ramp: step collapsed at v={v:.6g}")
            dv /= 2
            continue
        v = v_try
        record(its)
        states.append(model.state())
        if its <= 4:
            dv = min(dv * 1.5, dv_max)

    bracket = None
    v_pull = w_pull = None
    if v_switch < v_max:
        c = control_deflection(model)
        step = dc
        cs = [c]
        vmax_seen = model.v
        passed = False
        while c < c_max:
            steps += 1
            if steps > max_steps:
                raise ConvergenceError(f"voltage_ramp: exceeded {max_steps} steps at c={c}")
            x_prev, v_prev = model.state(), model.v
            try:
                its = newton_deflection(model, c + step)
            except ConvergenceError:
                model.set_state(x_prev)
                model.set_voltage(v_prev)
                if step < 1e-3:
                    raise
                step /= 2
                continue
            c += step
            cs.append(c)
            record(its)
            states.append(model.state())
            if eig_every and not passed and model.v < rec["v"][-2]:
                passed = True
                eig_record()      # first state past the limit point: lambda_1 < 0 expected
            vmax_seen = max(vmax_seen, model.v)
            if model.v < (1 - drop) * vmax_seen:
                break
            step = min(step * 1.5, dc)
        vv = np.array(rec["v"])
        k = int(np.argmax(vv))
        if 0 < k < len(vv) - 1:
            ww = np.array(rec["w"][k - 1:k + 2])
            cf = np.polyfit(ww, vv[k - 1:k + 2], 2)
            xs = -cf[1] / (2 * cf[0])
            v_pull = float(np.polyval(cf, xs))
            w_pull = float(xs)
            bracket = (float(vv[k]), v_pull)
    arr = {k: np.array(val) for k, val in rec.items()}
    return RampResult(v=arr["v"], w=arr["w"], w_mid=arr["w_mid"], thickness=arr["thickness"],
                      e_centre=arr["e_centre"], e_max=arr["e_max"], newton_its=arr["its"],
                      v_pullin=v_pull, w_pullin=w_pull, pullin_bracket=bracket,
                      ndof=model.ndof, nelements=model.nelements, stats=dict(model.stats),
                      eig_v=np.array(eig["v"]), eig_w=np.array(eig["w"]),
                      eig_lam=np.array(eig["lam"]).reshape(-1, 3),
                      eig_axisym=np.array(eig["ax"]).reshape(-1, 3))


def southwell(v: np.ndarray, w_mid: np.ndarray, *, v_guess: float, window=(0.4, 0.9)) -> float:
    """Critical voltage from the pre-critical ramp by the Southwell plot.

    For an imperfect plate under a load P proportional to v^2 the additional mid-plane
    deflection is ``d = w_imp P/(P_cr - P)``, so ``d/P = d/P_cr + w_imp/P_cr``: the slope
    of d/P versus d is 1/P_cr.  ``w_mid`` (mean of top and bottom centre deflections) is
    free of the symmetric thinning of the film.  Points with
    ``window[0] < v/v_guess < window[1]`` are fitted.
    """
    v = np.asarray(v)
    d = np.asarray(w_mid)
    require(len(v) == len(d) and len(v) > 3, "need > 3 ramp points")
    require(v_guess > 0, f"v_guess must be > 0, got {v_guess}")
    sel = (v > window[0] * v_guess) & (v < window[1] * v_guess)
    require(np.count_nonzero(sel) >= 3, f"Southwell window {window} holds < 3 points")
    P = v[sel] ** 2
    slope, _ = np.polyfit(d[sel], d[sel] / P, 1)
    if not slope > 0:
        raise ConvergenceError(f"Southwell fit has non-positive slope {slope}")
    return float(math.sqrt(1.0 / slope))
