"""Deflection control of the Chapter 5 finite-element model
(:class:`~debench.models.buckling.fem.MembraneModel`): the centre deflection as the
control variable and the bordered Newton that prescribes it, with the voltage as unknown
(passes voltage limit points: pull-in).
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np
from debench.models import validation as val
from debench.models.buckling.fem import NEWTON_MAXIT, NEWTON_TOL, MembraneModel
from debench.models.errors import ConvergenceError
from debench.models.numerics.newton import RTOL, NewtonResult, bordered_solve


def _control_dofs(model: MembraneModel) -> tuple[int, int]:
    """z-displacement dofs of the top and bottom vertices nearest to the centre axis."""
    t0 = model.plate.thickness
    w0 = model.lift(0.0, 0.0)
    best = {}
    for v in model.mesh.vertices:
        x, y, z = v.point
        for key, zt in (("top", t0 + w0), ("bottom", w0)):
            d = x * x + y * y + (z - zt) ** 2
            if key not in best or d < best[key][0]:
                best[key] = (d, v.nr)
    dofs = []
    for key in ("top", "bottom"):
        nrs = model.X.GetDofNrs(ngs.NodeId(ngs.VERTEX, best[key][1]))
        dofs.append(int(nrs[2]))          # (u_x, u_y, u_z, phi) of the compound space
    return dofs[0], dofs[1]


def control_deflection(model: MembraneModel) -> float:
    """Control variable of the deflection-controlled continuation: mean z-displacement of
    the top and bottom vertices nearest to the centre, / t0."""
    it, ib = model._ctrl if hasattr(model, "_ctrl") else _control_dofs(model)
    model._ctrl = (it, ib)
    x = model.gf.vec.FV().NumPy()
    return 0.5 * (x[it] + x[ib]) / model.plate.thickness


def newton_deflection(model: MembraneModel, c: float, *, tol: float = NEWTON_TOL,
                      maxit: int = NEWTON_MAXIT) -> NewtonResult:
    """Bordered Newton with the voltage as unknown and the centre deflection prescribed.

    Solves R(x, v) = 0, g(x) = c (g: :func:`control_deflection`) by block elimination
    (:func:`~debench.models.numerics.newton.bordered_solve`): ``dx = -a - dv b``,
    ``K a = R``, ``K b = dR/dv``, ``dv = (g(x) - c - g(a)) / g(b)``;
    dR/dv by a central difference, exact because R is quadratic in the potential.
    Every step assembles a new tangent (a reused one was measured not to pay here: the
    bordered iteration past buckling contracts too slowly with a stale tangent).
    Passes voltage limit points (pull-in).  Stops on the same criteria as
    :meth:`~debench.models.buckling.fem.MembraneModel.newton` (correction, residual
    relative to the first, round-off floor).  A solve at a singular tangent (the iterate
    landed on the limit point itself) raises ConvergenceError, so the continuation steps
    back.
    """
    c = float(val.finite("c", c))
    tol = val.tolerance("tol", tol)
    maxit = val.integer_at_least("maxit", maxit, 1)
    t0 = model.plate.thickness
    model._fresh = False
    control_deflection(model)
    it_, ib_ = model._ctrl
    res_p, res_m = model.res.CreateVector(), model.res.CreateVector()
    rhs = model.res.CreateVector()
    row = np.zeros(len(rhs))
    row[[it_, ib_]] = 0.5 / t0          # the control g(x) = (x_top + x_bottom) / (2 t0)

    def solve(y):
        rhs.FV().NumPy()[:] = y
        return model.solve(rhs).FV().NumPy().copy()

    r_first = model.residual_norm()
    floor = None
    for k in range(1, maxit + 1):
        v = model.v
        h = 1e-3 * max(abs(v), 0.1)
        model.set_voltage(v + h)
        model.a.Apply(model.gf.vec, res_p)
        model.set_voltage(v - h)
        model.a.Apply(model.gf.vec, res_m)
        model.set_voltage(v)
        model.a.Apply(model.gf.vec, model.res)
        rv = ((1 / (2 * h)) * (res_p - res_m)).Evaluate()
        model.assemble()
        if floor is None:
            floor = model.residual_floor()
        model.factor()
        x = model.gf.vec.FV().NumPy()
        gx = 0.5 * (x[it_] + x[ib_]) / t0
        dx, dv = bordered_solve(solve, rv.FV().NumPy().copy(), row,
                                -model.res.FV().NumPy(), c - gx,
                                what=f"bordered Newton at c={c}")
        dmax = float(np.max(np.abs(dx)))
        if not np.isfinite(dmax) or abs(dv) > 0.5:
            raise ConvergenceError(f"bordered Newton: diverged at c={c} (dv={dv:.3g})")
        x += dx
        model.set_voltage(v + dv)
        model.stats["newton_steps"] += 1
        rn = model.residual_norm()
        if dmax < tol * t0 and abs(dv) < tol:
            return model._record(k, rn, r_first, floor, "correction")
        if rn <= max(RTOL * r_first, floor) and abs(dv) < tol ** 0.5:
            return model._record(k, rn, r_first, floor, "residual")
    raise ConvergenceError(f"bordered Newton: no convergence in {maxit} steps at c={c}")
