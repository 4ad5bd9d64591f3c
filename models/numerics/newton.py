"""Newton iterations of every model: one stopping policy, one result, one bordered solve,
one damped driver.

The policy (every finite-element Newton of the package):

* **residual** -- converged when the residual norm over the free degrees of freedom is
  below :data:`RTOL` times its *reference*, the larger of its first value and, where the
  model has one, a physical load scale (the residual the load would cause in the undeformed
  body), so that a start already near the solution does not demand round-off;
* **round-off floor** -- or when it is below :func:`round_off_floor`, ``FLOOR_FACTOR eps
  || |K| |x| ||`` (``|K| |x|`` bounds the sum of the magnitudes of the terms summed into
  each residual entry);
* **step** -- iterations without an assembled residual norm to judge (the bordered
  continuation of Chapter 3, whose unknowns are weighted; the scalar shooting parameter)
  stop on the relative size of the full step instead: :data:`STEP_RTOL` for sparse systems
  whose condition reaches ~1e8, :data:`SCALAR_STEP_RTOL` for well-conditioned scalar
  iterations;
* non-convergence raises :class:`~debench.models.errors.ConvergenceError`; the models add
  their own stagnation rules next to singular tangents (documented where they are).

Quadratic convergence makes the choice of these tolerances cheap: the step that brings the
residual below ``RTOL`` typically takes it from ~1e-6 to ~1e-12 relative.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from debench.models import validation as val
from debench.models.errors import ConvergenceError, require

RTOL = 1e-11
"""Relative residual tolerance of every finite-element Newton (residual / reference, module
docstring). Chosen by the most demanding use, the flat state next to the critical voltage of
Chapter 5: there a state converged to 1e-11 moves the critical voltage by < 1e-11
(measured against solves to the round-off floor); the discretisation errors of every
curated value are >= 1e-9 relative."""
FLOOR_FACTOR = 100.0
"""Round-off floor factor: the residual is converged below ``FLOOR_FACTOR eps || |K| |x| ||``
(100 x allows for the quadrature sums and the nonlinear terms of the assembly)."""
STEP_RTOL = 1e-10
"""Step criterion of sparse bordered systems: the full step below ``STEP_RTOL (1 + |x|)``
(max norm). Their condition reaches ~1e8 on the finest meshes, so the relative round-off
floor of a step is ~1e-12: a margin of 100; the next step would be ~1e-20."""
SCALAR_STEP_RTOL = 1e-13
"""Step criterion of well-conditioned scalar iterations (a shooting parameter):
``|dq| <= SCALAR_STEP_RTOL |q|``; the neglected next step is O(dq^2), below rounding."""
LINE_SEARCH_HALVINGS = 12
"""Halvings of a damped step before :func:`damped_newton` gives up (a factor 4096)."""


def round_off_floor(abs_matrix, abs_state: np.ndarray, rows=None) -> float:
    """``FLOOR_FACTOR eps || (|K| |x|)[rows] ||``: the round-off floor of a residual
    assembled at the state ``x`` (``abs_matrix`` = |K|, a sparse or dense matrix with
    the magnitudes of the tangent, ``abs_state`` = |x|; ``rows`` the free rows, default
    all)."""
    y = abs_matrix @ abs_state
    if rows is not None:
        y = y[rows]
    return FLOOR_FACTOR * np.finfo(float).eps * float(np.linalg.norm(y))


def residual_converged(residual: float, reference: float, floor: float = 0.0,
                       rtol: float = RTOL) -> str | None:
    """Why a residual norm counts as converged under the policy (module docstring):
    ``"relative residual"`` (<= rtol reference), ``"floor"`` (<= floor), else None."""
    if residual <= rtol * reference:
        return "relative residual"
    if residual <= floor:
        return "floor"
    return None


@dataclass(frozen=True)
class NewtonResult:
    """What a Newton iteration did: ``iterations`` (steps taken to the stopping rule),
    the final ``residual`` norm, its ``reference`` (module docstring), the ``reason`` it
    stopped (``"relative residual"``, ``"floor"``, ``"correction"``, ``"stagnation"``,
    ...), the residual ``history`` where kept, and model-specific ``details`` (e.g. the
    round-off floor, whether a polishing step was taken)."""

    iterations: int
    residual: float
    reference: float
    reason: str
    history: tuple[float, ...] = ()
    details: dict = field(default_factory=dict)

    @property
    def residual_rel(self) -> float:
        """The final residual relative to its reference."""
        return self.residual / self.reference if self.reference > 0 else math.inf


def bordered_solve(solve: Callable[[np.ndarray], np.ndarray], column: np.ndarray,
                   row: np.ndarray, rhs_x: np.ndarray, rhs_g: float, *,
                   apply: Callable[[np.ndarray], np.ndarray] | None = None,
                   refinements: int = 0, rtol: float = 0.0,
                   what: str = "bordered solve") -> tuple[np.ndarray, float]:
    """Solve the bordered system ``[[K, column], [row^T, 0]] (dx, dl) = (rhs_x, rhs_g)`` by
    block elimination with the factorised ``K`` (``solve(b) = K^-1 b``):
    ``y2 = K^-1 column``, ``dl = (row . K^-1 rhs_x - rhs_g) / (row . y2)``,
    ``dx = K^-1 rhs_x - dl y2``. It stays regular where K alone is singular only in the
    limit; next to a voltage maximum the elimination loses digits, which ``refinements``
    steps of iterative refinement of the whole bordered residual (``apply(x) = K x``
    needed) recover, stopping below ``rtol`` |rhs_x|. A vanishing or non-finite
    ``row . y2`` (the border does not control the singular direction) raises
    ConvergenceError naming ``what``."""
    refinements = val.integer_at_least("refinements", refinements, 0)
    if refinements > 0 and apply is None:
        raise ValueError("bordered_solve: refinements > 0 need apply (K x)")
    y2 = np.asarray(solve(column), dtype=float)
    pivot = float(row @ y2)
    if pivot == 0.0 or not math.isfinite(pivot):
        raise ConvergenceError(f"{what}: singular border (row . K^-1 column = {pivot})")
    dx, dl = np.zeros_like(y2), 0.0
    rhs_x = np.asarray(rhs_x, dtype=float)
    scale = max(float(np.linalg.norm(rhs_x)), 1e-300)
    for k in range(refinements + 1):
        # the bordered residual of the current (dx, dl), corrected by one elimination;
        # refinement stops once the residual it corrected was below rtol
        ex = rhs_x - (apply(dx) + column * dl) if k else rhs_x
        eg = float(rhs_g) - float(row @ dx)
        y1 = np.asarray(solve(ex), dtype=float)
        ddl = (float(row @ y1) - eg) / pivot
        dx += y1 - ddl * y2
        dl += ddl
        if np.linalg.norm(ex) <= rtol * scale:
            break
    if not (np.all(np.isfinite(dx)) and math.isfinite(dl)):
        raise ConvergenceError(f"{what}: non-finite correction")
    return dx, dl


def damped_newton(residual: Callable[[], float], correction: Callable[[], object],
                  move: Callable[[object, float], None], *, reference: float | None = None,
                  atol: float = 0.0, rtol: float = RTOL, maxit: int = 25,
                  halvings: int = LINE_SEARCH_HALVINGS, what: str = "Newton") -> NewtonResult:
    """Newton with backtracking on the residual norm, for a model that owns its state.

    ``residual()`` returns the free residual norm at the current state (and may cache the
    residual vector for ``correction``); ``correction()`` assembles the tangent at the
    current state and returns the Newton correction ``du`` (``K du = R``, any vector type);
    ``move(du, s)`` updates the state by ``-s du`` (``s < 0`` undoes). A step ``s = 1, 1/2,
    ...`` is accepted when the residual decreases (and is finite); converged at a residual
    ``<= max(rtol reference, atol)``, ``reference`` the first residual unless given.
    Raises ConvergenceError naming ``what`` when no step decreases the residual within
    ``halvings`` halvings or when ``maxit`` steps do not converge."""
    rtol = val.tolerance("rtol", rtol)
    maxit = val.integer_at_least("maxit", maxit, 1)
    halvings = val.integer_at_least("halvings", halvings, 0)
    atol = float(val.finite("atol", atol))
    require(atol >= 0.0, f"atol must be >= 0, got {atol}")
    r = float(residual())
    if not math.isfinite(r):
        raise ConvergenceError(f"{what}: non-finite residual at the start ({r})")
    ref = r if reference is None else max(float(reference), r)
    history = [r]
    for it in range(maxit + 1):
        if r <= max(rtol * ref, atol):
            reason = "relative residual" if r <= rtol * ref else "absolute residual"
            return NewtonResult(it, r, ref, reason, tuple(history))
        if it == maxit:
            break
        du = correction()
        r_old, s = r, 1.0
        for _ in range(halvings + 1):
            move(du, s)
            r = float(residual())
            if math.isfinite(r) and r < r_old:
                break
            move(du, -s)
            s *= 0.5
        else:
            residual()           # the residual cache back at the kept state
            raise ConvergenceError(
                f"{what}: no decrease of the residual {r_old:.3e} along the Newton direction "
                f"(step halved {halvings} times)")
        history.append(r)
    raise ConvergenceError(f"{what}: residual {r:.3e} did not reach {rtol:g} x {ref:.3e} in "
                           f"{maxit} steps; residuals {[f'{h:.2e}' for h in history]}")
