"""Kinematics of the axisymmetric model as NGSolve coefficient functions.

The deformation gradient and referential field of a state and of a wavenumber-n
perturbation, in cylindrical components ordered (r, theta, z), exactly as the formulation
of :mod:`debench.models.buckling.axisym` writes them: ``F = Gx G0^-1`` with the gradient
``Gx`` of the current position over the flat section and the inverse lift ``G0^-1``, and
``E_L = -G0^-T (p_R, 0, p_Z)``.
"""

from __future__ import annotations

import ngsolve as ngs


def mat3(rows) -> ngs.CoefficientFunction:
    """A 3 x 3 coefficient function from its rows."""
    return ngs.CoefficientFunction(tuple(c for row in rows for c in row), dims=(3, 3))


def vec3(c) -> ngs.CoefficientFunction:
    """A 3-vector coefficient function from its components."""
    return ngs.CoefficientFunction(tuple(c))


def lift_inverse(w0p) -> ngs.CoefficientFunction:
    """``G0^-1`` of the lift ``(R, Z) -> (R, Z + w0(R))`` with slope ``w0p = w0'``."""
    w = w0p
    return mat3([[1, 0, 0], [0, 1, 0], [-w, 0, 1]])


def section_gradient(ur, uz, R, w0p) -> ngs.CoefficientFunction:
    """``Gx``: the gradient of the current position over the flat section of the
    axisymmetric displacements ``ur``, ``uz`` at radius ``R`` (``G0`` at zero displacement)."""
    g = ngs.grad
    return mat3([[1 + g(ur)[0], 0, g(ur)[1]],
                 [0, 1 + ur / R, 0],
                 [w0p + g(uz)[0], 0, 1 + g(uz)[1]]])


def referential_field(ginv, p) -> ngs.CoefficientFunction:
    """``E_L = -G0^-T (p_R, 0, p_Z)`` of the (scaled) potential ``p``, ``ginv`` = G0^-1."""
    g = ngs.grad
    return -(ginv.trans * vec3((g(p)[0], 0, g(p)[1])))


def perturbation_gradients(n: int, U, V, gU, gV, W, R):
    """``(dGx_cos, dGx_sin)``: the cos and sin groups of the gradient perturbation of
    wavenumber ``n`` with amplitudes U, V, W (``gU``, ``gV``: the gradients of U and V)."""
    g = ngs.grad
    dGc = mat3([[gU[0], 0, gU[1]], [0, (U + n * V) / R, 0], [g(W)[0], 0, g(W)[1]]])
    dGs = mat3([[0, -(n * U + V) / R, 0], [gV[0], 0, gV[1]], [0, -n * W / R, 0]])
    return dGc, dGs


def perturbation_fields(n: int, ginv, Q, R):
    """``(dE_cos, dE_sin)``: the cos and sin groups of the referential-field perturbation
    of wavenumber ``n`` with potential amplitude Q."""
    return referential_field(ginv, Q), vec3((0, n * Q / R, 0))
