"""The library energies as NGSolve ``CoefficientFunction`` s (third evaluation path).

Import on demand (``import debench.models.materials.ngsolve_forms``): it imports ``ngsolve``.

A library material builds its energy ``W`` from CF arguments ``F`` (3x3) and ``D_L``
(3-vector) through its own protocol method
(:meth:`~debench.models.materials.protocol.Material.energy_expression`) evaluated
with the NGSolve namespace :data:`NGSOLVE`: the one expression of
:mod:`debench.models.materials.energies` (this module writes no energy of its own and asks
no material which class it is); stress and moduli follow from NGSolve's symbolic
differentiation::

    F = CoefficientFunction(..., dims=(3, 3)).MakeVariable()
    D = CoefficientFunction(...).MakeVariable()
    W = energy_cf(material, F, D)            # material.energy_expression(F, D, xp=NGSOLVE)
    P, E_L = W.Diff(F), W.Diff(D)           # (2.27), (2.28)
    AA, AAA, A = P.Diff(F), P.Diff(D), E_L.Diff(D)   # (2.65)-(2.67)

The namespaces differ only in how they evaluate the eigenvalue power sums of Ogden (5.26)
(``spectral``): :data:`NGSOLVE` (and :func:`regularised` with another delta) by the
averaged perturbation below, :data:`AXISYMMETRIC` exactly at axisymmetric states, and
:func:`about` to second order about an axisymmetric state; invariant-based energies read
the same in all of them.

The Chapter 5 finite-element model (:mod:`debench.models.buckling.fem`) uses
:func:`mechanical_energy_cf` with ``F = Id(3) + Grad(u)`` for the mechanical part and
:func:`ideal_dielectric_enthalpy` for the partial Legendre transform of (5.9) in the
referential field. :func:`evaluate` evaluates a library material this way at one state
(used by the verification suite to cross-check the numpy chain rule).

Ogden (5.26) at repeated principal stretches
--------------------------------------------
NGSolve CFs have no symmetric eigen-decomposition, and the closed-form (trigonometric)
eigenvalues of ``Cbar`` have a singular derivative (0 * inf) exactly at repeated
eigenvalues -- the reference state and the flat pre-buckled film (lam1 = lam2, thesis
§5.2.2.2). The namespace :data:`NGSOLVE` evaluates (5.26) at ``Cbar + delta P`` and
``Cbar - delta P`` for a fixed traceless ``P = diag(1, 0, -1)`` in a frame rotated away
from the model axes and averages: the odd term cancels, the energy is that of (5.26) up to
O(delta^2) (relative ~1e-6 for the default :data:`OGDEN_DELTA`), and every evaluated
matrix has distinct eigenvalues, so symbolic differentiation gives finite, accurate stresses
and tangents without the case distinction (5.37)-(5.50).
"""

from __future__ import annotations

import dataclasses
import math

import ngsolve as ng
import numpy as np
from debench.models.materials import energies as E
from debench.models.materials.constants import OGDEN_DELTA
from debench.models.materials.library import OgdenIdealDielectric
from netgen.csg import unit_cube


def _vector(values):
    return ng.CoefficientFunction(tuple(float(x) for x in values))


def _unavailable_spectral(M, energy):
    raise NotImplementedError("this namespace has no eigenvalue power sums")


_BASE = E.MathNamespace(
    name="ngsolve", det=ng.Det, trace=ng.Trace, inv=ng.Inv, transpose=lambda A: A.trans,
    matmul=lambda A, B: A * B, inner=ng.InnerProduct, log1p=lambda x: ng.log(1 + x),
    vector=_vector, spectral=_unavailable_spectral)


def regularised(delta: float = OGDEN_DELTA) -> E.MathNamespace:
    """The NGSolve namespace whose ``spectral`` is the averaged perturbation of half-width
    ``delta`` (module docstring; error O(delta^2))."""
    if not 0 < delta < 0.1:
        raise ValueError(f"delta = {delta!r} must lie in (0, 0.1)")

    def spectral(M, energy):
        P = ng.CoefficientFunction(tuple(_perturbation_direction().ravel()), dims=(3, 3))
        w = 0
        for sign in (1.0, -1.0):    # 0.5: the mean of the +- delta pair
            eigenvalues = symmetric_eigenvalues(M + sign * delta * P)
            w = w + 0.5 * energy(lambda b, c=eigenvalues: sum(x**b for x in c))
        return w

    return dataclasses.replace(_BASE, spectral=spectral)


NGSOLVE = regularised(OGDEN_DELTA)
"""The NGSolve namespace of :mod:`debench.models.materials.energies` (CoefficientFunctions;
Ogden's power sums by the averaged perturbation of half-width ``OGDEN_DELTA``)."""


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


def _ogden(alphas, mus, k):
    return OgdenIdealDielectric(alphas=tuple(alphas), mus=tuple(mus), k=k)


def ogden_mechanical(F, *, alphas, mus, k, delta=OGDEN_DELTA):
    """(5.26) + k/2 (J-1)^2: ``sum_p 2 mu_p/alpha_p^2 (sum_i lb_i^alpha_p - 3)``,
    ``lb_i`` the deviatoric principal stretches, by the averaged perturbation at
    ``Cbar +- delta P`` (module docstring; error O(delta^2))."""
    return _ogden(alphas, mus, k).mechanical_energy(F, xp=regularised(delta))


SERIES_U = 0.1
"""Below this relative half-gap ``u`` of two eigenvalues the closed forms of
:func:`power_pair_sum` and :func:`power_divided_difference` are replaced by their Taylor
series in ``u^2``: the closed forms lose ~eps_mach/u^k to cancellation (k <= 3 for the second
derivatives), the series of SERIES_TERMS terms is exact to ~u^(2 SERIES_TERMS) (1e-18 at
the switch; every binomial coefficient of the library's Ogden exponents is below 1)."""
SERIES_TERMS = 9


def _binomial(a: float, k: int) -> float:
    """The generalised binomial coefficient ``a (a-1) ... (a-k+1) / k!``."""
    out = 1.0
    for i in range(k):
        out *= (a - i) / (i + 1)
    return out


def _horner(coefficients, x):
    """``sum_k coefficients[k] x^k`` by Horner's rule (the shortest expression tree)."""
    out = coefficients[-1]
    for coef in reversed(coefficients[:-1]):
        out = coef + x * out
    return out


def power_pair_sum(m, s, b: float):
    """``(m + sqrt(s))^b + (m - sqrt(s))^b`` for ``0 <= s < m^2``: the power sum of the two
    eigenvalues ``m +- sqrt(s)`` of a symmetric 2x2 matrix (mean ``m``, squared half-gap
    ``s``), an even function of ``sqrt(s)`` and hence smooth in ``s`` (the series
    ``2 m^b sum_k C(b, 2k) (s/m^2)^k`` below ``s = (SERIES_U m)^2``)."""
    u2 = s / (m * m)
    series = 2 * _horner([_binomial(b, 2 * j) for j in range(SERIES_TERMS)], u2)
    u = ng.sqrt(ng.IfPos(u2 - SERIES_U**2, u2, SERIES_U**2))   # finite on both branches
    exact = (1 + u) ** b + (1 - u) ** b
    return m**b * ng.IfPos(u2 - SERIES_U**2, exact, series)


def power_divided_difference(x, y, g: float):
    """``(x^g - y^g)/(x - y)`` for ``x, y > 0``, ``g y^(g-1)`` at ``x = y``: with
    ``m = (x + y)/2``, ``u = (x - y)/(x + y)`` it is ``m^(g-1) ((1+u)^g - (1-u)^g)/(2u)``,
    the series ``m^(g-1) sum_k C(g, 2k+1) u^2k`` below ``|u| = SERIES_U``."""
    m = 0.5 * (x + y)
    u = (x - y) / (x + y)
    u2 = u * u
    series = _horner([_binomial(g, 2 * j + 1) for j in range(SERIES_TERMS)], u2)
    us = ng.IfPos(u2 - SERIES_U**2, u, SERIES_U)                # finite on both branches
    exact = ((1 + us) ** g - (1 - us) ** g) / (2 * us)
    return m ** (g - 1) * ng.IfPos(u2 - SERIES_U**2, exact, series)


def _isochoric_cauchy_green(F):
    J = NGSOLVE.det(F)
    return E.isochoric_right_cauchy_green(E.right_cauchy_green(F, xp=NGSOLVE), J), J


def _axisymmetric_spectral(Cb, energy):
    """``energy(power_sum)`` at an axisymmetric ``Cbar`` (cylindrical components): the hoop
    eigenvalue ``Cbar_tt`` and the (r, z) pair's power sum (:func:`power_pair_sum`)."""
    a, d, crz, ct = Cb[0, 0], Cb[2, 2], Cb[0, 2], Cb[1, 1]
    m = 0.5 * (a + d)
    s = 0.25 * (a - d) * (a - d) + crz * crz
    return energy(lambda b: ct**b + power_pair_sum(m, s, b))


AXISYMMETRIC = dataclasses.replace(_BASE, name="ngsolve-axisymmetric",
                                   spectral=_axisymmetric_spectral)
"""The NGSolve namespace exact at axisymmetric states (no regularisation)."""


def ogden_mechanical_axisymmetric(F, *, alphas, mus, k):
    """(5.26) + k/2 (J-1)^2, exactly, at an axisymmetric ``F`` in cylindrical components
    ``(r, theta, z)`` (its entries coupling theta with r or z are zero, so ``Cbar`` has the
    hoop eigenvalue ``Cbar_tt`` and the (r, z) block): the power sums
    ``Cbar_tt^b + power_sum_pair(m, s, b)`` with the block's mean ``m`` and squared half-gap
    ``s = ((Cbar_rr - Cbar_zz)/2)^2 + Cbar_rz^2`` (:data:`AXISYMMETRIC`).

    No eigenvector and no regularisation: the pair sum is smooth at repeated eigenvalues, so
    NGSolve's symbolic derivatives are the exact stresses and tangents of every axisymmetric
    state (for perturbations that leave the axisymmetric states:
    :func:`ogden_mechanical_about`)."""
    return _ogden(alphas, mus, k).mechanical_energy(F, xp=AXISYMMETRIC)


def axisymmetric_principal_frame(F):
    """The orthonormal eigenvectors of ``Cbar`` at an axisymmetric ``F`` (cylindrical
    components ``(r, theta, z)``), as the columns of a 3x3 CF: the (r, z) block's larger and
    smaller eigenvector and the hoop direction between them. The larger eigenvector is
    taken from the row of ``Cbar - lambda_1 I`` that has no cancellation; at a repeated
    (r, z) pair (e.g. the undeformed body) any frame is principal and ``(r, theta, z)`` is
    returned."""
    Cb, _ = _isochoric_cauchy_green(F)
    a, d, crz = Cb[0, 0], Cb[2, 2], Cb[0, 2]
    w = 0.5 * ng.IfPos(a - d, a - d, d - a) + ng.sqrt(0.25 * (a - d) * (a - d) + crz * crz)
    vr = ng.IfPos(a - d, w, crz)        # (lambda_1 - d, crz) for a >= d, else (crz, lambda_1 - a)
    vz = ng.IfPos(a - d, crz, w)
    n2 = vr * vr + vz * vz
    tiny = 1e-28 * (a * a + d * d)
    n = ng.sqrt(ng.IfPos(n2 - tiny, n2, 1.0))
    er = ng.IfPos(n2 - tiny, vr / n, 1.0)
    ez = ng.IfPos(n2 - tiny, vz / n, 0.0)
    return ng.CoefficientFunction((er, 0, -ez, 0, 1, 0, ez, 0, er), dims=(3, 3))


def about(F0) -> E.MathNamespace:
    """The NGSolve namespace whose ``spectral`` is exact to second order in ``F - F0`` about
    the axisymmetric state ``F0`` (:func:`ogden_mechanical_about`)."""
    Q = axisymmetric_principal_frame(F0)
    Cb0, _ = _isochoric_cauchy_green(F0)
    A0 = Q.trans * Cb0 * Q
    pairs = ((0, 1), (0, 2), (1, 2))

    def spectral(Cb, energy):
        A = Q.trans * Cb * Q

        def power_sum(b):
            return (sum(A[i, i] ** b for i in range(3))
                    + b * sum(A[i, j] * A[i, j]
                              * power_divided_difference(A0[i, i], A0[j, j], b - 1)
                              for i, j in pairs))

        return energy(power_sum)

    return dataclasses.replace(_BASE, name="ngsolve-about", spectral=spectral)


def ogden_mechanical_about(F, F0, *, alphas, mus, k):
    """(5.26) + k/2 (J-1)^2 to second order in ``F - F0`` about an axisymmetric state ``F0``
    (cylindrical components): with the principal frame ``Q`` of ``Cbar(F0)``
    (:func:`axisymmetric_principal_frame`), its eigenvalues ``l_i`` and
    ``A = Q^T Cbar(F) Q``, the power sums ``sum_i A_ii^b + b sum_{i<j} A_ij^2
    (l_i^(b-1) - l_j^(b-1))/(l_i - l_j)``.

    The eigenvalues of ``A`` are ``A_ii + sum_j A_ij^2/(A_ii - A_jj) + O(|A_offdiag|^3)``
    (second-order perturbation theory) and ``A_ij = O(F - F0)`` off the diagonal, so the pair
    terms (divided differences of ``d(c^b)/dc`` at the state,
    :func:`power_divided_difference`) carry the energy of the off-diagonal part, also at
    repeated eigenvalues, where their limit is the second derivative. The energy and its
    first and second derivatives at ``F0`` are those of (5.26): the stability operators of
    the Ogden film without regularisation, for perturbations that leave the axisymmetric
    states (``F0 = Id(3)``: about the undeformed body). The pair factors depend on ``F0``
    only, so derivatives in ``F`` do not expand them."""
    return _ogden(alphas, mus, k).mechanical_energy(F, xp=about(F0))


def ideal_dielectric_enthalpy(F, E_L, *, eps):
    """Partial Legendre transform of (5.9) in the referential field ``E_L = -Grad phi``:
    ``min_D (I5/(2 eps J) - E_L.D_L) = -eps/2 J C^-1 : (E_L x E_L)``, attained at
    ``D_L = eps J C^-1 E_L`` (so that ``E_L = dW/dD_L``, eq. (5.13))."""
    return E.ideal_dielectric_enthalpy(F, E_L, eps=eps, xp=NGSOLVE)


def _protocol_method(material, name: str):
    method = getattr(material, name, None)
    if method is None:
        raise NotImplementedError(f"no NGSolve form for {type(material).__name__}: it does "
                                  f"not follow the material protocol ({name})")
    return method


def energy_cf(material, F, D_L, *, xp=None):
    """The CF energy ``W(F, D_L)`` of a library material (its ``energy_expression`` in the
    namespace ``xp``, default :data:`NGSOLVE`)."""
    return _protocol_method(material, "energy_expression")(F, D_L, xp=xp or NGSOLVE)


def mechanical_energy_cf(material, F, *, delta=OGDEN_DELTA):
    """The mechanical energy ``W(F, 0)`` of a library material [Pa] (its
    ``mechanical_energy``; spectral energies regularised with half-width ``delta``)."""
    return _protocol_method(material, "mechanical_energy")(F, xp=regularised(delta))


def axisymmetric_mechanical_energy(material, F, about_state=None):
    """The mechanical energy of a library material [Pa] in the axisymmetric models, exact
    (no regularisation): at an axisymmetric ``F`` (cylindrical components, ``about_state``
    None, :data:`AXISYMMETRIC`) or to second order in ``F - about_state`` about that
    axisymmetric state (:func:`about`; invariant-based energies are exact everywhere and
    ignore it)."""
    return _protocol_method(material, "mechanical_energy")(F, xp=axisymmetric(about_state))


def axisymmetric(about_state=None) -> E.MathNamespace:
    """The namespace of the axisymmetric models: :data:`AXISYMMETRIC` (``about_state``
    None) or :func:`about` the axisymmetric state ``about_state``."""
    return AXISYMMETRIC if about_state is None else about(about_state)


class _Evaluator:
    """Parameters + symbolic derivatives built once per material (cheap re-evaluation)."""

    def __init__(self, material):
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
