r"""The dielectric-elastomer bilayer strip bending under voltage (plane strain): debench's
NGSolve model of the reference problem ``lit_bilayer``.

Import on demand: it imports ``ngsolve``.

Problem
-------
In units of the total thickness H: the reference body is the rectangle
0 <= x <= L, 0 <= y <= 1, the passive layer 0 <= y <= h_p, the active layer
h_p <= y <= 1 (thickness h_a = 1 - h_p). Both layers are the compressible neo-Hookean of
Table 5.1 (eqs 5.15-5.17, ``mu/2 (J^{-2/3} I1 - 3) + k/2 (J - 1)^2``, stresses in units of
mu); the active layer is an ideal dielectric (5.9) between two electrodes: the interface
y = h_p at potential 0 and the top face y = 1 at potential phi_top = v h_a (the normalised
voltage v = (Phi/h_a) sqrt(eps/mu), potentials in units of H sqrt(mu/eps)). The passive
layer carries no field (its potential is grounded on both faces, so it is identically 0).
In plane strain F = [[1 + u_x,x, u_x,y, 0], [u_y,x, 1 + u_y,y, 0],
[0, 0, 1]] and E_L = ``-(phi_,x, phi_,y, 0)``; the equilibrium is the saddle point of

.. math::

    \Pi[u, \phi] = \int_{\Omega} W_{mech}(F)\,dA
                 - \int_{\Omega_a} \tfrac12 J\,C^{-1} : (E_L \otimes E_L)\,dA

(minimum in u, maximum in phi), with a sliding clamp at x = 0 (u_x = 0 there, u_y = 0 at
the point (0, h_p): the right half of a free strip of length 2L, no clamped corner) and
every other face traction free and insulated. A fully clamped end (u = 0 on x = 0) puts
strong stress singularities at the clamped corners of the electroded layer, where the
fixed-voltage Newton iterations fail under geometric refinement: it is not this problem.
The energies are the constitutive library's NGSolve path
(:meth:`~debench.models.materials.library.NeoHookeanIdealDielectric.mechanical_energy`,
:func:`~debench.models.materials.ngsolve_forms.ideal_dielectric_enthalpy`); residual and
tangent are NGSolve's symbolic derivatives of the energy.

Outputs at each voltage: the tip deflection ``w = u_y(L, 0)`` (the bottom corner of the
free end, in units of H, negative: the active layer lengthens and the strip bends towards
the passive side) and the tip rotation ``theta = atan2(-d_x, d_y)`` of the deformed end-face
chord ``d = (x + u)(L, 1) - (x + u)(L, 0)`` (radians, counter-clockwise positive).

Discretisation
--------------
Quadrilaterals with Lagrange (tensor-product) elements of degree ``order`` for both
displacement components and the potential; a structured base mesh (``nx`` cells along x,
``ny`` per layer), graded geometrically ``levels`` times (ratio :data:`HP_FACTOR`) towards
the free end of the interface (L, h_p), where the active layer's Maxwell stress ends (the
one singular point, a mild logarithmic one). :func:`converged` runs a plan of (order,
levels) and states the error of the top discretisation by
:func:`~debench.models.numerics.convergence.p_grading_estimate`.

Load path: continuation in v from 0 in steps of at most :data:`MAX_STEP`, each state by
Newton (with a backtracking line search on the free residual) from the linear extrapolation
of the two previous ones (:func:`~debench.models.numerics.newton.damped_newton`, the
package's Newton policy); a step that does not converge raises
:class:`~debench.models.errors.ConvergenceError`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import ngsolve as ng
import numpy as np
from debench.models import validation as val
from debench.models.materials import ngsolve_forms as forms
from debench.models.materials.constants import (
    TABLE_5_1_BULK_MODULUS,
    TABLE_5_1_NH_SHEAR_MODULUS,
)
from debench.models.materials.library import NeoHookeanIdealDielectric
from debench.models.numerics import p_grading_estimate
from debench.models.numerics.newton import damped_newton
from netgen.meshing import Element0D, Element1D, Element2D, MeshPoint, Pnt
from netgen.meshing import Mesh as NGMesh

NEWTON_ATOL = 1e-12
"""Absolute floor of the free residual (energies per mu H^2; round-off of the assembly)."""
NEWTON_MAXIT = 25
"""Newton steps allowed per voltage (from the extrapolated start it takes 2-4)."""
MAX_STEP = 0.025
"""Largest voltage step of the continuation (normalised v)."""
HP_FACTOR = 0.2
"""Ratio of the geometric mesh layers towards the clamped corners."""
#: the reference plan of :func:`converged`, (order, levels): the top (6, 2), its p-steps
#: (5, 2) and (4, 2) (three orders: Roache's factor 1.25) and its grading step (6, 1).
#: Measured (v = 0.3, orders 3 .. 6 at two layers): the rotation changes by 5.3e-5, 7.0e-6,
#: 7.5e-7 per order (about 9x less each), one layer more changes it by ~1e-7 at order 4
PLAN = ((4, 2), (5, 2), (6, 1), (6, 2))
#: what each tip value is reproducible to (Newton tolerance, point evaluation): the floor
#: of the error estimate
ERROR_FLOOR = 1e-9
#: the coarse plan the default-run test solves (seconds): top (3, 1), its p-step (2, 1)
#: and its grading step (3, 0); two orders: Roache's factor 3
COARSE_PLAN = ((2, 1), (3, 0), (3, 1))


@dataclass(frozen=True)
class BilayerParameters:
    """Geometry and materials, lengths in units of the total thickness H.

    ``length`` L/H; ``passive`` h_p/H (the active layer is the rest); ``bulk_ratio`` k/mu
    of both layers (Table 5.1: 7748003.92/156000); ``nx`` base cells along x; ``ny`` base
    cells through each layer."""

    length: float = 10.0
    passive: float = 0.5
    bulk_ratio: float = TABLE_5_1_BULK_MODULUS / TABLE_5_1_NH_SHEAR_MODULUS
    nx: int = 20
    ny: int = 2

    def __post_init__(self):
        val.positive("length", self.length)
        val.in_range("passive", self.passive, 0.0, 1.0, lo_open=True, hi_open=True)
        val.positive("bulk_ratio", self.bulk_ratio)
        val.integer_at_least("nx", self.nx, 1)
        val.integer_at_least("ny", self.ny, 2)


@dataclass(frozen=True)
class BilayerResult:
    """One discretisation along the load path: the tip values at each voltage of
    ``voltages``, the free DOFs, the Newton iterations and the last free residual of each
    voltage step (all steps, requested and intermediate)."""

    order: int
    levels: int
    voltages: np.ndarray
    tip_deflection: np.ndarray
    tip_rotation: np.ndarray
    ndof: int
    iterations: tuple[int, ...] = field(default_factory=tuple)
    residuals: tuple[float, ...] = field(default_factory=tuple)


def _graded(lo: float, hi: float, n: int, levels: int, *, at_lo: bool, at_hi: bool):
    """``n`` uniform cells on [lo, hi], the first (``at_lo``) and the last (``at_hi``)
    replaced by ``levels`` + 1 cells shrinking geometrically by :data:`HP_FACTOR`
    towards the end."""
    x = np.linspace(lo, hi, n + 1)
    h = (hi - lo) / n
    inner = h * HP_FACTOR ** np.arange(levels, 0, -1)
    parts = [x]
    if at_lo:
        parts.append(lo + inner)
    if at_hi:
        parts.append(hi - inner)
    return np.unique(np.concatenate(parts))


def mesh(params: BilayerParameters, levels: int):
    """The structured quadrilateral mesh: regions ``passive``/``active``, boundaries
    ``clamp`` (x = 0), ``end`` (x = L), ``bottom``, ``interface``, ``top``, the point
    ``pin`` (0, h_p). ``nx`` cells along x and ``ny`` through each layer, with ``levels``
    geometric layers (ratio :data:`HP_FACTOR`) in the last cell along x and in the two cells
    beside the interface: a tensor-product geometric mesh at (L, h_p)."""
    L, hp, nx, ny = params.length, params.passive, params.nx, params.ny
    xs = _graded(0.0, L, nx, levels, at_lo=False, at_hi=True)
    y_p = _graded(0.0, hp, ny, levels, at_lo=False, at_hi=True)
    y_a = _graded(hp, 1.0, ny, levels, at_lo=True, at_hi=False)
    ys = np.concatenate([y_p, y_a[1:]])
    n_p = y_p.size - 1  # rows of the passive layer
    mx, my = xs.size - 1, ys.size - 1
    m = NGMesh(dim=2)
    pid = [[m.Add(MeshPoint(Pnt(float(x), float(y), 0.0))) for x in xs] for y in ys]
    regions = [m.AddRegion(name, dim=2) for name in ("passive", "active")]
    bnd = {name: m.AddRegion(name, dim=1)
           for name in ("bottom", "end", "top", "clamp", "interface")}
    for j in range(my):
        for i in range(mx):
            m.Add(Element2D(regions[int(j >= n_p)],
                            [pid[j][i], pid[j][i + 1], pid[j + 1][i + 1], pid[j + 1][i]]))
    for i in range(mx):
        m.Add(Element1D([pid[0][i], pid[0][i + 1]], index=bnd["bottom"]))
        m.Add(Element1D([pid[my][i + 1], pid[my][i]], index=bnd["top"]))
        m.Add(Element1D([pid[n_p][i], pid[n_p][i + 1]], index=bnd["interface"]))
    for j in range(my):
        m.Add(Element1D([pid[j][mx], pid[j + 1][mx]], index=bnd["end"]))
        m.Add(Element1D([pid[j + 1][0], pid[j][0]], index=bnd["clamp"]))
    m.Add(Element0D(pid[n_p][0], index=1))
    m.SetCD2Name(1, "pin")
    return ng.Mesh(m)


def _energy(params: BilayerParameters, ux, uy, phi):
    gx, gy, gp = ng.grad(ux), ng.grad(uy), ng.grad(phi)
    F = ng.CoefficientFunction((1 + gx[0], gx[1], 0,
                                gy[0], 1 + gy[1], 0,
                                0, 0, 1), dims=(3, 3))
    EL = ng.CoefficientFunction((-gp[0], -gp[1], 0))
    # the library's neo-Hookean in units of mu (its mechanical energy does not read eps)
    material = NeoHookeanIdealDielectric(mu=1.0, k=params.bulk_ratio, eps=1.0)
    mech = material.mechanical_energy(F, xp=forms.NGSOLVE)
    elec = forms.ideal_dielectric_enthalpy(F, EL, eps=1.0)
    return mech, elec


def solve(voltages, *, order: int, levels: int,
          params: BilayerParameters | None = None,
          inverse: str = "umfpack", on_state=None) -> BilayerResult:
    """The tip deflection and rotation at each normalised voltage of ``voltages``
    (increasing, > 0) with elements of degree ``order`` on the mesh with ``levels``
    geometric layers (module docstring). ConvergenceError when a Newton step of the
    continuation does not converge. ``on_state(v, a, gf, free)``, if given, is called
    after each converged step (every voltage of the path) with the NGSolve bilinear form,
    the state and the free dofs (diagnostics such as the stability of the state)."""
    params = params or BilayerParameters()
    order = val.integer_at_least("order", order, 1)
    levels = val.integer_at_least("levels", levels, 0)
    v_req = np.asarray([val.positive("voltages[i]", v) for v in voltages], float)
    if v_req.size == 0 or np.any(np.diff(v_req) <= 0):
        raise ValueError(f"voltages must be increasing and non-empty, got {v_req.tolist()}")
    ng.SetNumThreads(1)
    msh = mesh(params, levels)
    Ux = ng.H1(msh, order=order, dirichlet="clamp")
    Uy = ng.H1(msh, order=order, dirichlet_bbnd="pin")
    # the potential on the whole body, grounded on both faces of the passive layer: there
    # it is identically 0 (the zero data of a problem linear in phi at fixed u), so the
    # passive layer carries no field and the enthalpy needs no restriction to the active one
    Q = ng.H1(msh, order=order, dirichlet="bottom|interface|top")
    X = Ux * Uy * Q
    (ux, uy, phi) = X.TrialFunction()
    mech, elec = _energy(params, ux, uy, phi)
    a = ng.BilinearForm(X, symmetric=True)
    a += ng.Variation((mech + elec).Compile() * ng.dx)
    gf = ng.GridFunction(X)
    free = X.FreeDofs()
    mask = np.array(list(free), dtype=bool)
    res = gf.vec.CreateVector()
    du = gf.vec.CreateVector()
    top_bnd = msh.Boundaries("top")
    ha = 1.0 - params.passive

    def residual():
        a.Apply(gf.vec, res)
        return float(np.linalg.norm(res.FV().NumPy()[mask]))

    def correction():
        a.AssembleLinearization(gf.vec)
        du.data = a.mat.Inverse(free, inverse=inverse) * res
        return du

    def move(step, s):
        gf.vec.data -= s * step

    # the path: every requested voltage, with intermediate steps of at most MAX_STEP
    path, requested = [], []
    v_prev = 0.0
    for v in v_req:
        n = max(1, math.ceil((v - v_prev) / MAX_STEP - 1e-12))
        path += list(np.linspace(v_prev, v, n + 1)[1:])
        requested.append(len(path) - 1)
        v_prev = v
    history = [np.zeros(len(gf.vec)), np.zeros(len(gf.vec))]
    v_hist = [0.0, 0.0]
    iters, resid, tips = [], [], []
    for k, v in enumerate(path):
        # start: linear extrapolation of the last two states (the first step: the
        # undeformed state), with the new electrode potential on the top face
        if k >= 1:
            s = (v - v_hist[-1]) / (v_hist[-1] - v_hist[-2]) if k >= 2 else v / v_hist[-1]
            start = history[-1] + s * (history[-1] - history[-2])
        else:
            start = history[-1]
        gf.vec.FV().NumPy()[:] = start
        gf.components[2].Set(ng.CoefficientFunction(v * ha), definedon=top_bnd)
        # backtracking on the free residual: the slender strip's soft bending mode makes
        # full steps overshoot at large rotations; near the solution the full step is
        # taken (quadratic convergence)
        result = damped_newton(
            residual, correction, move, atol=NEWTON_ATOL, maxit=NEWTON_MAXIT,
            what=f"bilayer Newton (order {order}, levels {levels}) at v = {v:.6g}")
        it, r = result.iterations, result.residual
        iters.append(it)
        resid.append(r)
        state = gf.vec.FV().NumPy().copy()
        history = [history[-1], state]
        v_hist = [v_hist[-1], v]
        if on_state is not None:
            on_state(v, a, gf, free)
        if k in requested:
            tips.append(_tip(msh, gf.components[0], gf.components[1], params))
    tips = np.array(tips)
    return BilayerResult(order=order, levels=levels, voltages=v_req,
                         tip_deflection=tips[:, 0], tip_rotation=tips[:, 1],
                         ndof=int(mask.sum()), iterations=tuple(iters),
                         residuals=tuple(resid))


def _tip(msh, ux, uy, params: BilayerParameters) -> tuple[float, float]:
    """(w, theta) of the displacement (ux, uy) (module docstring)."""
    L = params.length
    bot, top = msh(L, 0.0), msh(L, 1.0)
    dx = ux(top) - ux(bot)
    dy = 1.0 + uy(top) - uy(bot)
    return float(uy(bot)), float(math.atan2(-dx, dy))


@dataclass(frozen=True)
class BilayerConverged:
    """The converged tip values at each voltage and their error estimates, with every
    discretisation of the plan (``results``, in plan order)."""

    voltages: np.ndarray
    tip_deflection: np.ndarray
    tip_deflection_error: np.ndarray
    tip_rotation: np.ndarray
    tip_rotation_error: np.ndarray
    plan: tuple[tuple[int, int], ...]
    results: tuple[BilayerResult, ...]


def converged(voltages, *, plan=PLAN, params: BilayerParameters | None = None,
              floor: float = ERROR_FLOOR) -> BilayerConverged:
    """:func:`solve` on each (order, levels) of ``plan``; the values of the top
    discretisation and the error estimate of
    :func:`~debench.models.numerics.convergence.p_grading_estimate` (Roache's safety
    factor times the larger of the last p-step and the last grading step, at least
    ``floor``)."""
    plan = tuple((int(p), int(lv)) for p, lv in plan)
    results = tuple(solve(voltages, order=p, levels=lv, params=params) for p, lv in plan)
    est = {}
    for name in ("tip_deflection", "tip_rotation"):
        vals = np.stack([getattr(r, name) for r in results], axis=-1)
        est[name] = p_grading_estimate(vals, plan, floor=floor)
    return BilayerConverged(
        voltages=results[0].voltages,
        tip_deflection=np.asarray(est["tip_deflection"].value),
        tip_deflection_error=np.asarray(est["tip_deflection"].error),
        tip_rotation=np.asarray(est["tip_rotation"].value),
        tip_rotation_error=np.asarray(est["tip_rotation"].error),
        plan=plan, results=results)
