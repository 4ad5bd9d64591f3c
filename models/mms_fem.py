"""debench's NGSolve solver of the manufactured electro-elastic problem (:mod:`debench.models.mms`).

Import on demand: it imports ``ngsolve``.

The discrete problem is the saddle point of ``int (Omega(F, -Grad phi) - b.u + q phi) dV``
(minimum in ``u``, maximum in ``phi``) over Lagrange elements of degree ``order`` for every
component of ``u`` and for ``phi`` on a uniform simplicial mesh (each of the ``n x n``
squares of the unit square cut along a diagonal, or the ``n^3`` cubes of the unit cube cut
into tetrahedra, ``h = 1/n``), with ``u`` and ``phi``
prescribed on the whole boundary by NGSolve's boundary interpolation of the exact fields.
``Omega`` is built from the constitutive library's NGSolve path
(the library neo-Hookean's ``mechanical_energy`` or the library's Gent and volumetric
energies, and
:func:`~debench.models.materials.ngsolve_forms.ideal_dielectric_enthalpy`); ``b`` and ``q``
are the generated formulas of :mod:`debench.models.mms_generated` evaluated as NGSolve
CoefficientFunctions; residual and tangent are NGSolve's symbolic derivatives of the
energy. Axisymmetric: ``F_TT = 1 + u_R/R`` and the volume element ``R dR dZ``.

Newton from the solution of the problem linearised at the undeformed state
(:func:`~debench.models.numerics.newton.damped_newton`) stops when the residual on the free
degrees of freedom has dropped by :data:`~debench.models.numerics.newton.RTOL` (the
discretisation errors measured are >= 1e-9 relative, so the algebraic error is negligible);
otherwise it raises :class:`~debench.models.errors.ConvergenceError`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import ngsolve as ng
import numpy as np
from debench.models import validation as val
from debench.models.materials import energies as E
from debench.models.materials import ngsolve_forms as forms
from debench.models.materials.library import NeoHookeanIdealDielectric
from debench.models.mms import ManufacturedSolution
from debench.models.numerics.newton import damped_newton
from ngsolve.meshes import MakeStructured2DMesh, MakeStructured3DMesh

NEWTON_MAXIT = 20
"""Newton steps allowed (from the linearised solution it takes 4-6)."""
QUADRATURE_EXTRA = 4
"""Error integrals use quadrature of degree 2 order + QUADRATURE_EXTRA: the exact fields
are not polynomials; 4 extra degrees keep the quadrature error far below the FE error."""
GEOMETRIES_SOLVED = ("plane_strain", "axisymmetric", "three_d")


@dataclass(frozen=True)
class MMSResult:
    """One solve: mesh size, DOFs, errors against the exact fields, Newton history.

    ``errors`` has ``u_L2``, ``u_H1``, ``phi_L2``, ``phi_H1`` (the H1 entries are the
    seminorms ``||Grad(u_h - u)||``, axisymmetric ones weighted by R).
    """

    order: int
    n: int
    h: float
    ndof: int
    errors: dict[str, float]
    iterations: int
    residuals: tuple[float, ...] = field(default_factory=tuple)


def _mesh(n: int, dim: int):
    if dim == 3:
        return MakeStructured3DMesh(hexes=False, nx=n, ny=n, nz=n)
    return MakeStructured2DMesh(quads=False, nx=n, ny=n)


def _kinematics(geometry, u, p, R):
    gu, gp = ng.grad(u), ng.grad(p)
    if geometry == "three_d":
        return ng.Id(3) + gu, -gp
    if geometry == "plane_strain":
        F = ng.CoefficientFunction((1 + gu[0, 0], gu[0, 1], 0,
                                    gu[1, 0], 1 + gu[1, 1], 0,
                                    0, 0, 1), dims=(3, 3))
        EL = ng.CoefficientFunction((-gp[0], -gp[1], 0))
    else:
        F = ng.CoefficientFunction((1 + gu[0, 0], 0, gu[0, 1],
                                    0, 1 + u[0] / R, 0,
                                    gu[1, 0], 0, 1 + gu[1, 1]), dims=(3, 3))
        EL = ng.CoefficientFunction((-gp[0], 0, -gp[1]))
    return F, EL


def _mechanical(solution: ManufacturedSolution, F):
    if solution.material == "neo_hookean":
        return NeoHookeanIdealDielectric(mu=1.0, k=solution.kappa).mechanical_energy(
            F, xp=forms.NGSOLVE)
    inv = E.invariants(F, xp=forms.NGSOLVE)
    I1bar = inv["J"] ** (-2 / 3) * inv["I1"]
    return (E.gent(I1bar, mu=1.0, Jm=solution.Jm, xp=forms.NGSOLVE)
            + E.volumetric(inv["J"], k=solution.kappa))


def solve(solution: ManufacturedSolution, order: int, n: int, *,
          inverse: str = "sparsecholesky") -> MMSResult:
    """Solve the manufactured problem of ``solution`` with Lagrange elements of degree
    ``order`` on the uniform mesh with ``n`` intervals per side and measure the errors
    (module docstring).

    Parameters
    ----------
    solution : ManufacturedSolution
        geometry "plane_strain", "axisymmetric" ((R, Z) = (x, y) of the mesh) or
        "three_d".
    order : int
        polynomial degree p >= 1 of u and phi.
    n : int
        intervals per side (>= 2), h = 1/n.
    inverse : str
        NGSolve direct solver of the (indefinite, saddle-point) tangent.
    """
    val.instance("solution", solution, ManufacturedSolution)
    val.choice("solution.geometry", solution.geometry, GEOMETRIES_SOLVED)
    order = val.integer_at_least("order", order, 1)
    n = val.integer_at_least("n", n, 2)
    d = solution.dim
    mesh = _mesh(n, d)
    # R in 1/R (F_TT, b, q): NGSolve's vectorised quadrature pads its point sets with
    # zero-weight points at the origin, where 1/R is NaN (and 0 x NaN = NaN); quadrature
    # points have R > 0. The fields themselves (boundary data on the axis) use R = x.
    R = ng.IfPos(ng.x, ng.x, 1.0)
    xyz = (ng.x, ng.y, ng.z)[:d]
    exact = solution.evaluate(*xyz, ns=ng)
    loads = solution.evaluate(R, ng.y, ns=ng) if solution.geometry == "axisymmetric" else exact
    u_ex = ng.CoefficientFunction(tuple(exact["u"]))
    phi_ex = exact["phi"]
    gu_ex = ng.CoefficientFunction(tuple(c for row in exact["grad_u"] for c in row),
                                   dims=(d, d))
    gp_ex = ng.CoefficientFunction(tuple(exact["grad_phi"]))
    # compiled: the data are DAGs of shared subexpressions, which NGSolve's uncompiled
    # evaluation walks as trees (measured at p = 2, h = 1/16: 15 s per solve, 0.7 s so)
    b = ng.CoefficientFunction(tuple(loads["b"])).Compile()
    q = loads["q"].Compile()

    V = ng.VectorH1(mesh, order=order, dirichlet=".*")
    Q = ng.H1(mesh, order=order, dirichlet=".*")
    X = V * Q
    (u, p) = X.TrialFunction()
    F, EL = _kinematics(solution.geometry, u, p, R)
    density = _mechanical(solution, F) + forms.ideal_dielectric_enthalpy(F, EL, eps=1.0)
    weight = ng.x if solution.geometry == "axisymmetric" else 1
    a = ng.BilinearForm(X, symmetric=True)
    a += ng.Variation(density.Compile() * weight * ng.dx)
    # the loads of the energy's - b.u + q phi, assembled once (the data are not polynomials:
    # QUADRATURE_EXTRA more degrees)
    (v, w) = X.TestFunction()
    f = ng.LinearForm(X)
    f += (ng.InnerProduct(b, v) - q * w) * weight * ng.dx(bonus_intorder=QUADRATURE_EXTRA)
    f.Assemble()

    gf = ng.GridFunction(X)
    free = np.array(list(X.FreeDofs()), dtype=bool)
    res = gf.vec.CreateVector()
    du = gf.vec.CreateVector()

    def residual(vec):
        a.Apply(vec, res)
        res.data -= f.vec
        return float(np.linalg.norm(res.FV().NumPy()[free]))

    # start: the linearisation at the undeformed, unpolarised state with the boundary data
    # (a smooth extension of the data into the domain; zero interior values with non-zero
    # boundary values put O(data/h) gradients into the boundary elements)
    lift = ng.GridFunction(X)
    lift.components[0].Set(u_ex, ng.BND)
    lift.components[1].Set(phi_ex, ng.BND)
    a.AssembleLinearization(gf.vec)
    residual(gf.vec)
    res.data += a.mat * lift.vec
    gf.vec.data = lift.vec - a.mat.Inverse(X.FreeDofs(), inverse=inverse) * res
    inverse_of = X.FreeDofs()

    def correction():
        a.AssembleLinearization(gf.vec)
        residual(gf.vec)
        du.data = a.mat.Inverse(inverse_of, inverse=inverse) * res
        return du

    def move(step, s):
        gf.vec.data -= s * step

    result = damped_newton(lambda: residual(gf.vec), correction, move, maxit=NEWTON_MAXIT,
                           what=f"MMS Newton ({solution.name}, order {order}, n {n})")
    history = list(result.history)

    uh, ph = gf.components
    io = 2 * order + QUADRATURE_EXTRA

    def norm(cf):
        return math.sqrt(max(ng.Integrate(ng.InnerProduct(cf, cf) * weight, mesh, order=io),
                             0.0))

    errors = {"u_L2": norm(uh - u_ex), "u_H1": norm(ng.grad(uh) - gu_ex),
              "phi_L2": norm(ph - phi_ex), "phi_H1": norm(ng.grad(ph) - gp_ex)}
    return MMSResult(order=order, n=n, h=1.0 / n, ndof=int(free.sum()), errors=errors,
                     iterations=len(history) - 1, residuals=tuple(history))


def convergence(solution: ManufacturedSolution, order: int, ns=(4, 8, 16, 32), **kw):
    """:func:`solve` on each mesh of ``ns`` (increasing), a list of :class:`MMSResult`."""
    ns = [val.integer_at_least("ns[i]", k, 2) for k in ns]
    if any(b <= a for a, b in zip(ns, ns[1:], strict=False)):
        raise ValueError(f"ns must be strictly increasing, got {ns}")
    return [solve(solution, order, k, **kw) for k in ns]
