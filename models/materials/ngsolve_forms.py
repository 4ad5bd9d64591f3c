"""The library energies as NGSolve ``CoefficientFunction`` s (third evaluation path).

Import on demand (``import debench.models.materials.ngsolve_forms``): it imports ``ngsolve``.

One function per energy builds ``W`` from CF arguments ``F`` (3x3) and ``D_L`` (3-vector)
and the parameters; stress and moduli follow from NGSolve's symbolic differentiation::

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
from debench.models.materials.constants import OGDEN_DELTA


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


def neo_hookean_mechanical(F, *, mu, k):
    """(5.15)-(5.17): ``mu/2 (J^{-2/3} I1 - 3) + k/2 (J - 1)^2`` (C10 = mu/2, D1 = 2/k)."""
    J = ng.Det(F)
    return 0.5 * mu * (J ** (-2 / 3) * ng.Trace(F.trans * F) - 3) + 0.5 * k * (J - 1) ** 2


def _sym_eigs(M):
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
    J = ng.Det(F)
    Cb = J ** (-2 / 3) * (F.trans * F)
    P = ng.CoefficientFunction(tuple(_perturbation_direction().ravel()), dims=(3, 3))
    w = 0
    for sign in (1.0, -1.0):
        eigs = _sym_eigs(Cb + sign * delta * P)
        for a, mu in zip(alphas, mus, strict=True):
            w = w + mu / a**2 * (sum(e ** (a / 2) for e in eigs) - 3)   # 0.5 * 2 mu/a^2
    return w + 0.5 * k * (J - 1) ** 2


def ideal_dielectric(F, D_L, *, eps):
    """(5.9): ``I5/(2 eps J)``."""
    _, _, J, I5 = _invariants(F, D_L)
    return I5 / (2 * eps * J)


def ideal_dielectric_enthalpy(F, E_L, *, eps):
    """Partial Legendre transform of (5.9) in the referential field ``E_L = -Grad phi``:
    ``min_D (I5/(2 eps J) - E_L.D_L) = -eps/2 J C^-1 : (E_L x E_L)``, attained at
    ``D_L = eps J C^-1 E_L`` (so that ``E_L = dW/dD_L``, eq. (5.13))."""
    C = F.trans * F
    return -0.5 * eps * ng.Det(F) * ng.InnerProduct(ng.Inv(C) * E_L, E_L)


def neo_hookean_ideal_dielectric(F, D_L, *, mu, k, eps):
    """(5.15) + (5.9): ``mu/2 (J^{-2/3} I1 - 3) + k/2 (J - 1)^2 + I5/(2 eps J)``."""
    return neo_hookean_mechanical(F, mu=mu, k=k) + ideal_dielectric(F, D_L, eps=eps)


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
