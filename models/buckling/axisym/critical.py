"""The critical voltage of the perfect flat film in one angular wavenumber (Ch. 5).

The voltage at which the lowest eigenvalue of the wavenumber-n stability operator of the
flat pre-buckling state vanishes: the flat state is equilibrated at trial voltages
(:class:`~debench.models.buckling.axisym.model.AxisymModel`) and the eigenvalue
(:meth:`~debench.models.buckling.axisym.model.AxisymModel.spectrum`) driven to zero by a
secant in ``v^2`` finished by inverse quadratic interpolation. The formulation:
:mod:`debench.models.buckling.axisym`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

from debench.models import validation as val
from debench.models.buckling.analytic import critical_voltage_plate
from debench.models.buckling.axisym.model import AxisymModel
from debench.models.buckling.axisym.section import AxisymDiscretisation
from debench.models.buckling.axisym.spectra import TANGENTS
from debench.models.buckling.critical_result import CriticalVoltage
from debench.models.buckling.parameters import Plate
from debench.models.materials.protocol import IdealDielectricElastomer
from debench.models.numerics.roots import inverse_quadratic_root, secant_step
from debench.models.numerics.secants import secant_until

CRITICAL_STEP = 1e-6
"""The secant on lambda_1(v^2) = 0 stops evaluating when its next step would be below
CRITICAL_STEP relative (closer to the singular tangent than that, the Newton solves of the
flat state lose digits); the root is then the inverse quadratic interpolation through the
last three evaluations, whose error is of the order of the product of their distances to
the root (< 1e-12 here) and is estimated by its difference from the secant root."""


@dataclass(frozen=True, kw_only=True)
class AxisymCritical(CriticalVoltage):
    """Bifurcation of the perfect flat film in wavenumber ``n``: lambda_1(S_n(v)) = 0. The
    fields of :class:`~debench.models.buckling.critical_result.CriticalVoltage` (``e`` and
    ``thickness`` at the centre), and ``n``, the stability operator ``tangent``,
    ``ndof_mode`` (the perturbation problem's degrees of freedom) and ``cpu_s``, the
    process CPU time of the solve.
    """

    n: int
    tangent: str
    ndof_mode: int
    cpu_s: float




def critical_voltage(plate: Plate, material: IdealDielectricElastomer,
                     disc: AxisymDiscretisation | None = None, *, n: int = 0,
                     v_start: float | None = None, start_step: float = 0.1,
                     maxit: int = 30, tangent: str = "coupled") -> AxisymCritical:
    """Critical normalised voltage of the perfect clamped film in wavenumber ``n``.

    The flat state (rim clamped, the nonlinear pre-buckling state with the rim's
    constraint of the thickness change) is equilibrated at each trial voltage; the
    algebraically smallest eigenvalue of the condensed tangent of wavenumber ``n`` is
    driven to zero by the secant method in ``v^2`` (the prestress grows as v^2), started at
    ``1 - start_step`` and 1 times ``v_start`` (default: the Kirchhoff plate estimate
    :func:`~debench.models.buckling.analytic.critical_voltage_plate`, ``start_step`` 0.1;
    a start from a neighbouring discretisation's ``v`` with a small step saves one or two
    of the four or five flat-state solves, the root unchanged to ``vtol``). The final state is
    certified: no eigenvalue of wavenumber ``n`` below the one driven to zero (so ``v`` is
    the first crossing of that wavenumber, not a higher mode's).

    ``tangent`` (:meth:`AxisymModel.spectrum`) chooses the stability operator: the coupled
    tangent at fixed voltage (the definition of the critical voltage), or the
    frozen-potential or initial-stress operator (the classical methods it is compared with).

    Accuracy contract: ``v`` is the zero of this discretisation's lowest eigenvalue to within
    ``vtol``, the difference between the inverse-quadratic and the secant roots of the last
    evaluations (:data:`CRITICAL_STEP`). The final state is certified by the inertia count
    of every spectrum (:meth:`AxisymModel.spectrum`). The discretisation error is measured
    by the p- and grading-sequences of the studies, not here. Raises ConvergenceError when
    the secant does not converge in ``maxit`` steps.
    """
    n = val.integer_at_least("n", n, 0)
    maxit = val.integer_at_least("maxit", maxit, 1)
    start_step = float(val.in_range("start_step", start_step, 0.0, 0.5, lo_open=True))
    val.choice("tangent", tangent, TANGENTS)
    t_cpu = time.process_time()
    model = AxisymModel(plate, material, disc, with_imperfection=False)
    v0 = critical_voltage_plate(material, plate.aspect) if v_start is None else float(
        val.positive("v_start", v_start))
    flat = _FlatFilm(model, n, tangent)
    res = secant_until(flat, ((1.0 - start_step) * v0) ** 2, v0**2,
                       converged=lambda x, x_next: abs(x_next - x) < CRITICAL_STEP * x,
                       finish="inverse_quadratic", maxiter=maxit, bounds=(0.0, math.inf),
                       what=f"critical_voltage(n={n})")
    root, x_next = res.root, res.next_iterate
    if flat.reasons[-1].startswith("stagnation") and len(flat.xs) >= 4:
        # the last flat state stopped on stagnation next to the singular tangent: its
        # eigenvalue carries the state's round-off along the near-null mode (measured:
        # lambda_1 = 8.5e-11 against ~1e-12, 2.8e-9 in v, at 6e-12 from the root on a
        # coarse mesh), so the root is finished on the three evaluations before it
        xs, fs = flat.xs, flat.fs
        root = inverse_quadratic_root(xs[-4:-1], fs[-4:-1])
        x_next = secant_step(xs[-3], fs[-3], xs[-2], fs[-2], what=f"critical_voltage(n={n})")
    v = math.sqrt(root)
    return AxisymCritical(
        n=n, v=v, tangent=tangent, thickness=model.centre_thickness(),
        e=model.centre_field(), lam=flat.history[-1][1], eig_residual=flat.last["residual"],
        newton_residual_rel=flat.last["newton"], iterations=res.function_calls,
        ndof=model.ndof, ndof_mode=flat.last["ndof"], order=model.disc.order,
        cpu_s=time.process_time() - t_cpu,
        vtol=abs(v - math.sqrt(x_next)), history=tuple(flat.history))


class _FlatFilm:
    """``lambda_1(x)``: the lowest eigenvalue of wavenumber ``n`` of the flat film at the
    voltage ``sqrt(x)``, with the (v, lambda_1) evaluated in ``history`` (and as (x,
    lambda_1) in ``xs``, ``fs``), why each flat state's Newton stopped in ``reasons``, and
    the last solve's eigen-residual, mode DOFs and Newton residual in ``last``."""

    def __init__(self, model: AxisymModel, n: int, tangent: str):
        self.model, self.n, self.tangent = model, n, tangent
        self.xs: list[float] = []
        self.fs: list[float] = []
        self.reasons: list[str] = []
        self.last: dict = {}

    @property
    def history(self) -> list[tuple[float, float]]:
        return [(math.sqrt(x), f) for x, f in zip(self.xs, self.fs, strict=True)]

    def __call__(self, x: float) -> float:
        # each trial voltage from the undeformed film: continuing from the previous state
        # carries its round-off along the near-null buckling mode into the next state
        # (measured: lambda_1 of +-2e-6 at one voltage), while Newton from the undeformed
        # film reaches the symmetric flat state in one or two steps
        model = self.model
        model.reset()
        model.set_voltage(math.sqrt(x))
        model.newton()
        spec = model.spectrum(self.n, nev=1, tangent=self.tangent)
        self.xs.append(x)
        self.fs.append(float(spec.lam[0]))
        self.reasons.append(model.last_newton.reason)
        self.last.update(residual=spec.residual, ndof=spec.ndof,
                         newton=model.last_newton.residual_rel)
        return float(spec.lam[0])
