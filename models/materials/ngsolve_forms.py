"""The library energies as NGSolve ``CoefficientFunction`` s (third evaluation path).

Import on demand (``import debench.models.materials.ngsolve_forms``): it imports ``ngsolve``.

One function per energy builds ``W`` from CF arguments ``F`` (3x3) and ``D_L`` (3-vector)
and the parameters, by evaluating the one expression of the energy in
:mod:`debench.models.materials.energies` with the NGSolve namespace :data:`NGSOLVE` (this
module writes no energy of its own); stress and moduli follow from NGSolve's symbolic
differentiation::

    F = CoefficientFunction(..., dims=(3, 3)).MakeVariable()
    D = CoefficientFunction(...).MakeVariable()
    W = neo_hookean_ideal_dielectric(F, D, mu=..., k=..., eps=...)
    P, E_L = W.Diff(F), W.Diff(D)           # (2.27), (2.28)
    AA, AAA, A = P.Diff(F), P.Diff(D), E_L.Diff(D)   # (2.65)-(2.67)

The Chapter 5 finite-element model (:mod:`debench.models.buckling.fem`) uses these
functions with ``F = Id(3) + Grad(u)``: :func:`mechanical_energy_cf` for the mechanical
part and :func:`ideal_dielectric_enthalpy` for the partial Legendre transform of (5.9) in
the referential field. :func:`evaluate` evaluates a library material this way at one state
(used by the verification suite to cross-check the numpy chain rule).

Ogden (5.26) at repeated principal stretches
--------------------------------------------
NGSolve CFs have no symmetric eigen-decomposition, and the closed-form (trigonometric)
eigenvalues of ``Cbar`` have a singular derivative (0 * inf) exactly at repeated
eigenvalues -- the reference state and the flat pre-buckled film (lam1 = lam2, thesis
§5.2.2.2). :func:`ogden_mechanical` evaluates (5.26) at ``Cbar + delta P`` and
``Cbar - delta P`` for a fixed traceless ``P = diag(1, 0, -1)`` in a frame rotated away
from the model axes and averages: the odd term cancels, the energy is that of (5.26) up to
O(delta^2) (relative ~1e-6 for the default :data:`OGDEN_DELTA`), and every evaluated
matrix has distinct eigenvalues, so symbolic differentiation gives finite, accurate stresses
and tangents without the case distinction (5.37)-(5.50).
"""

from __future__ import annotations

import math

import ngsolve as ng
import numpy as np
from debench.models.materials import energies as E
from debench.models.materials.constants import OGDEN_DELTA

NGSOLVE = E.MathNamespace(
    name="ngsolve", det=ng.Det, trace=ng.Trace, inv=ng.Inv, transpose=lambda A: A.trans,
    matmul=lambda A, B: A * B, inner=ng.InnerProduct, log1p=lambda x: ng.log(1 + x))
"""The NGSolve namespace of :mod:`debench.models.materials.energies` (CoefficientFunctions)."""


def gent_ideal_dielectric(F, D_L, *, mu, Jm, eps):
    """(3.23) + I5/(2 eps): ``-mu Jm/2 log(1 - (I1 - 3)/Jm) + I5/(2 eps)`` (incompressible)."""
    I = E.invariants(F, D_L, xp=NGSOLVE)
    return E.gent_ideal_dielectric(I["I1"], I["DCD"], mu=mu, Jm=Jm, eps=eps, xp=NGSOLVE)


def neo_hookean_mechanical(F, *, mu, k):
    """(5.15)-(5.17): ``mu/2 (J^{-2/3} I1 - 3) + k/2 (J - 1)^2`` (C10 = mu/2, D1 = 2/k)."""
    I = E.invariants(F, xp=NGSOLVE)
    return E.neo_hookean(I["I1"], I["J"], mu=mu, k=k)


def symmetric_eigenvalues(M):
    """Closed-form eigenvalues of a symmetric 3x3 CF matrix with distinct eigenvalues
    (trigonometric solution of the characteristic cubic)."""
    m = ng.Trace(M) / 3
    dev = M - m * ng.Id(3)
    p = ng.sqrt(ng.InnerProduct(dev, dev) / 6)
    r = ng.Det(dev) / (2 * p**3)
    r = ng.IfPos(r - 1, 1, ng.IfPos(-1 - r, -1, r))
    phi = ng.acos(r) / 3
    return [m + 2 * p * ng.cos(phi + 2 * math.pi * j / 3) for j in range(3)]


def _perturbation_direction() -> np.ndarray:
    """Fixed traceless symmetric direction: diag(1, 0, -1) in a generic rotated frame."""
    cz, sz = math.cos(0.3), math.sin(0.3)
    cy, sy = math.cos(0.7), math.sin(0.7)
    cx, sx = math.cos(1.1), math.sin(1.1)
    R = (np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
         @ np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
         @ np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]]))
    return R @ np.diag([1.0, 0.0, -1.0]) @ R.T


def ogden_mechanical(F, *, alphas, mus, k, delta=OGDEN_DELTA):
    """(5.26) + k/2 (J-1)^2: ``sum_p 2 mu_p/alpha_p^2 (sum_i lb_i^alpha_p - 3)``,
    ``lb_i`` the deviatoric principal stretches, by the averaged perturbation at
    ``Cbar +- delta P`` (module docstring; error O(delta^2))."""
    if not 0 < delta < 0.1:
        raise ValueError(f"delta = {delta!r} must lie in (0, 0.1)")
    J = NGSOLVE.det(F)
    Cb = E.isochoric_right_cauchy_green(E.right_cauchy_green(F, xp=NGSOLVE), J)
    P = ng.CoefficientFunction(tuple(_perturbation_direction().ravel()), dims=(3, 3))
    w = 0
    for sign in (1.0, -1.0):
        cbar = symmetric_eigenvalues(Cb + sign * delta * P)
        for a, mu in zip(alphas, mus, strict=True):   # 0.5: the mean of the +- delta pair
            w = w + 0.5 * E.ogden_term(cbar, alpha=a, mu=mu)
    return w + E.volumetric(J, k=k)


def ideal_dielectric(F, D_L, *, eps):
    """(5.9): ``I5/(2 eps J)``."""
    I = E.invariants(F, D_L, xp=NGSOLVE)
    return E.ideal_dielectric(I["DCD"], I["J"], eps=eps)


def ideal_dielectric_enthalpy(F, E_L, *, eps):
    """Partial Legendre transform of (5.9) in the referential field ``E_L = -Grad phi``:
    ``min_D (I5/(2 eps J) - E_L.D_L) = -eps/2 J C^-1 : (E_L x E_L)``, attained at
    ``D_L = eps J C^-1 E_L`` (so that ``E_L = dW/dD_L``, eq. (5.13))."""
    return E.ideal_dielectric_enthalpy(F, E_L, eps=eps, xp=NGSOLVE)


def neo_hookean_ideal_dielectric(F, D_L, *, mu, k, eps):
    """(5.15) + (5.9): ``mu/2 (J^{-2/3} I1 - 3) + k/2 (J - 1)^2 + I5/(2 eps J)``."""
    I = E.invariants(F, D_L, xp=NGSOLVE)
    return E.neo_hookean_ideal_dielectric(I["I1"], I["J"], I["DCD"], mu=mu, k=k, eps=eps)


def ogden_ideal_dielectric(F, D_L, *, alphas, mus, k, eps, delta=OGDEN_DELTA):
    """(5.26) + k/2 (J-1)^2 + (5.9), see :func:`ogden_mechanical`."""
    return (ogden_mechanical(F, alphas=alphas, mus=mus, k=k, delta=delta)
            + ideal_dielectric(F, D_L, eps=eps))


def mechanical_energy_cf(material, F, *, delta=OGDEN_DELTA):
    """The mechanical energy (``D_L = 0``) of a library neo-Hookean or Ogden material [Pa]."""
    from debench.models.materials import library as lib

    if isinstance(material, lib.NeoHookeanIdealDielectric):
        return neo_hookean_mechanical(F, mu=material.mu, k=material.k)
    if isinstance(material, lib.OgdenIdealDielectric):
        return ogden_mechanical(F, alphas=material.alphas, mus=material.mus, k=material.k,
                                delta=delta)
    raise NotImplementedError(f"no NGSolve mechanical energy for {type(material).__name__}")


def ti_neo_hookean_dielectric(F, D_L, *, mu, xi, alpha, beta, eps, A):
    """(4.22): ``mu/2 (I1-3) + mu xi/2 (A.CA - 1)^2 + (alpha D.D + beta D.CD)/(2 eps)``."""
    a = ng.CoefficientFunction(tuple(float(x) for x in A))
    I = E.invariants(F, D_L, a, xp=NGSOLVE)
    return E.ti_neo_hookean_dielectric(I["I1"], I["ACA"], I["DD"], I["DCD"], mu=mu, xi=xi,
                                       alpha=alpha, beta=beta, eps=eps)


def dorfmann_ogden_electric(F, D_L, *, alpha, beta, eps):
    """(4.20): ``(alpha D.D + beta D.CD)/(2 eps)``."""
    I = E.invariants(F, D_L, xp=NGSOLVE)
    return E.dorfmann_ogden_electric(I["DD"], I["DCD"], alpha=alpha, beta=beta, eps=eps)


def energy_cf(material, F, D_L):
    """The CF energy of a library material instance (dispatch on its class)."""
    from debench.models.materials import library as lib

    if isinstance(material, lib.GentIdealDielectric):
        return gent_ideal_dielectric(F, D_L, mu=material.mu, Jm=material.Jm, eps=material.eps)
    if isinstance(material, lib.NeoHookeanIdealDielectric):
        return neo_hookean_ideal_dielectric(F, D_L, mu=material.mu, k=material.k,
                                            eps=material.eps)
    if isinstance(material, lib.OgdenIdealDielectric):
        return ogden_ideal_dielectric(F, D_L, alphas=material.alphas, mus=material.mus,
                                      k=material.k, eps=material.eps)
    if isinstance(material, lib.IdealDielectric):
        return ideal_dielectric(F, D_L, eps=material.eps)
    if isinstance(material, lib.DorfmannOgdenElectric):
        return dorfmann_ogden_electric(F, D_L, alpha=material.alpha, beta=material.beta,
                                       eps=material.eps)
    if isinstance(material, lib.TransverselyIsotropicNeoHookean):
        return ti_neo_hookean_dielectric(F, D_L, mu=material.mu, xi=material.xi,
                                         alpha=material.alpha, beta=material.beta,
                                         eps=material.eps, A=material.A)
    raise NotImplementedError(f"no NGSolve form for {type(material).__name__}")


class _Evaluator:
    """Parameters + symbolic derivatives built once per material (cheap re-evaluation)."""

    def __init__(self, material):
        from netgen.csg import unit_cube

        self._mesh = ng.Mesh(unit_cube.GenerateMesh(maxh=1.0))  # only to host a point
        self.Fp = [ng.Parameter(0.0) for _ in range(9)]
        self.Dp = [ng.Parameter(0.0) for _ in range(3)]
        F = ng.CoefficientFunction(tuple(self.Fp), dims=(3, 3)).MakeVariable()
        D = ng.CoefficientFunction(tuple(self.Dp)).MakeVariable()
        W = energy_cf(material, F, D)
        P = W.Diff(F)
        EL = W.Diff(D)
        self.cfs = {"W": W, "P": P, "E_L": EL, "AA": P.Diff(F), "AAA": P.Diff(D),
                    "A": EL.Diff(D)}

    def __call__(self, F, D_L):
        for p, v in zip(self.Fp, np.asarray(F, dtype=float).ravel(), strict=True):
            p.Set(float(v))
        for p, v in zip(self.Dp, np.asarray(D_L, dtype=float), strict=True):
            p.Set(float(v))
        mip = self._mesh(0.25, 0.25, 0.25)
        shapes = {"W": (), "P": (3, 3), "E_L": (3,), "AA": (3, 3, 3, 3), "AAA": (3, 3, 3),
                  "A": (3, 3)}
        return {k: np.array(cf(mip)).reshape(shapes[k]) for k, cf in self.cfs.items()}


_CACHE: dict = {}


def evaluate(material, F, D_L) -> dict:
    """``W, P, E_L, AA, AAA, A`` of a library material by NGSolve symbolic differentiation.

    Uses one thread (``ngsolve.SetNumThreads(1)``). Index layout as
    :class:`debench.models.materials.kernel.Response`.
    """
    ng.SetNumThreads(1)
    key = material
    if key not in _CACHE:
        _CACHE[key] = _Evaluator(material)
    return _CACHE[key](F, D_L)
