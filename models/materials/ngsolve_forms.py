"""The library energies as NGSolve ``CoefficientFunction`` s (third evaluation path).

Import on demand (``import debench.models.materials.ngsolve_forms``): it imports ``ngsolve``.

One function per energy builds ``W`` from CF arguments ``F`` (3x3) and ``D_L`` (3-vector)
and the parameters; stress and moduli follow from NGSolve's symbolic differentiation::

    F = CoefficientFunction(..., dims=(3, 3)).MakeVariable()
    D = CoefficientFunction(...).MakeVariable()
    W = neo_hookean_ideal_dielectric(F, D, mu=..., k=..., eps=...)
    P, E_L = W.Diff(F), W.Diff(D)           # (2.27), (2.28)
    AA, AAA, A = P.Diff(F), P.Diff(D), E_L.Diff(D)   # (2.65)-(2.67)

The Chapter 5 finite-element model can use the same functions with
``F = Id(3) + Grad(u)``. :func:`evaluate` evaluates a library material this way at one
state (used by the verification suite to cross-check the numpy chain rule).

Ogden (5.26) is not provided: NGSolve CFs have no symmetric eigen-decomposition, and
closed-form eigenvalues are not differentiable at repeated eigenvalues (the reference
state).
"""

from __future__ import annotations

import ngsolve as ng
import numpy as np


def _invariants(F, D_L):
    C = F.trans * F
    I1 = ng.Trace(C)
    J = ng.Det(F)
    I5 = ng.InnerProduct(D_L, C * D_L)
    return C, I1, J, I5


def gent_ideal_dielectric(F, D_L, *, mu, Jm, eps):
    """(3.23) + I5/(2 eps): ``-mu Jm/2 log(1 - (I1 - 3)/Jm) + I5/(2 eps)`` (incompressible)."""
    _, I1, _, I5 = _invariants(F, D_L)
    return -0.5 * mu * Jm * ng.log(1 - (I1 - 3) / Jm) + I5 / (2 * eps)


def neo_hookean_ideal_dielectric(F, D_L, *, mu, k, eps):
    """(5.15) + (5.9): ``mu/2 (J^{-2/3} I1 - 3) + k/2 (J - 1)^2 + I5/(2 eps J)``."""
    _, I1, J, I5 = _invariants(F, D_L)
    return (0.5 * mu * (J ** (-2 / 3) * I1 - 3) + 0.5 * k * (J - 1) ** 2
            + I5 / (2 * eps * J))


def ideal_dielectric(F, D_L, *, eps):
    """(5.9): ``I5/(2 eps J)``."""
    _, _, J, I5 = _invariants(F, D_L)
    return I5 / (2 * eps * J)


def ti_neo_hookean_dielectric(F, D_L, *, mu, xi, alpha, beta, eps, A):
    """(4.22): ``mu/2 (I1-3) + mu xi/2 (A.CA - 1)^2 + (alpha D.D + beta D.CD)/(2 eps)``."""
    C, I1, _, I5 = _invariants(F, D_L)
    a = ng.CoefficientFunction(tuple(float(x) for x in A))
    I4 = ng.InnerProduct(a, C * a)
    I6 = ng.InnerProduct(D_L, D_L)
    return (0.5 * mu * (I1 - 3) + 0.5 * mu * xi * (I4 - 1) ** 2
            + (alpha * I6 + beta * I5) / (2 * eps))


def dorfmann_ogden_electric(F, D_L, *, alpha, beta, eps):
    """(4.20): ``(alpha D.D + beta D.CD)/(2 eps)``."""
    _, _, _, I5 = _invariants(F, D_L)
    return (alpha * ng.InnerProduct(D_L, D_L) + beta * I5) / (2 * eps)


def energy_cf(material, F, D_L):
    """The CF energy of a library material instance (dispatch on its class)."""
    from debench.models.materials import library as lib

    if isinstance(material, lib.GentIdealDielectric):
        return gent_ideal_dielectric(F, D_L, mu=material.mu, Jm=material.Jm, eps=material.eps)
    if isinstance(material, lib.NeoHookeanIdealDielectric):
        return neo_hookean_ideal_dielectric(F, D_L, mu=material.mu, k=material.k,
                                            eps=material.eps)
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
