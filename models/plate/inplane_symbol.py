"""The in-plane fibre plate's incremental symbol (beyond the thesis): the base state, the
energy matrix S of the incremental problem in the (psi, u3, phi) variables, the symbol
P(q1, q2) = B(-q)^T S B(q) of the Euler-Lagrange operator, its characteristic roots and
plane strong ellipticity. The bifurcation analyses built on them, and the derivation of
the incremental problem: :mod:`debench.models.plate.inplane`.
"""

from __future__ import annotations

import math

import numpy as np
from debench.models import validation as v
from debench.models.errors import ConvergenceError
from debench.models.plate import generated_inplane as gen
from debench.models.plate.coefficients import PlateParams

#: directions sampled on the half circle for the strong-ellipticity test
N_DIRECTIONS = 91


#: stretches the model evaluates: lam^-10 and lam^8 stay far from overflow inside
LAM_RANGE = (1e-3, 1e3)


def _check(lam, theta, params):
    lam = v.in_range("lam", lam, *LAM_RANGE)
    theta = v.finite("theta", theta)
    if not 0.0 <= theta <= 90.0:
        raise ValueError(f"theta must be in [0, 90] degrees, got {theta}")
    v.instance("params", params, PlateParams)
    if params.variant != "derived":
        raise ValueError("params.variant must be 'derived' (the in-plane model is derived "
                         f"from the energy only), got {params.variant!r}")
    return float(lam), float(theta)


def energy_matrix(lam: float, theta: float, params: PlateParams) -> np.ndarray:
    """Condensed incremental energy matrix S (8 x 8), ``theta`` in degrees [0, 90].

    2Q = z^T S z, z = (L11, L12, L21, L22, L31, L32, Ddot1, Ddot2); Ddot3 condensed out.
    """
    lam, theta = _check(lam, theta, params)
    return _S(lam, theta, params)


def _cs(theta):
    """(cos, sin) of theta in degrees, exact at 0 and 90 (exact decoupling of u3)."""
    if theta == 90.0:
        return 0.0, 1.0
    t = math.radians(theta)
    return math.cos(t), math.sin(t)


def _S(lam, theta, p):
    return gen.energy_matrix(lam, p.xi, p.alpha, p.beta, p.Dhat, *_cs(theta))


def base_state(lam: float, theta: float, params: PlateParams):
    """(p, tau11, tau33, tau13) of the base state (tau22 = 0), units of mu."""
    lam, theta = _check(lam, theta, params)
    return gen.base_state(lam, params.xi, params.alpha, params.beta, params.Dhat,
                          *_cs(theta))


def _B(q1, q2):
    """z = B(q) (Psi, U3, Phi) for fields exp(i (q1 x1 + q2 x2))."""
    B = np.zeros(np.broadcast(q1, q2).shape + (8, 3), complex)
    B[..., 0, 0] = -q1 * q2          # L11 = i q1 u1, u1 = i q2 Psi
    B[..., 1, 0] = -q2**2            # L12
    B[..., 2, 0] = q1**2             # L21 (u2 = -i q1 Psi)
    B[..., 3, 0] = q1 * q2           # L22
    B[..., 4, 1] = 1j * q1           # L31
    B[..., 5, 1] = 1j * q2           # L32
    B[..., 6, 2] = 1j * q2           # Dd1 = i q2 Phi
    B[..., 7, 2] = -1j * q1          # Dd2 = -i q1 Phi
    return B


@v.finite_result
def symbol(lam: float, theta: float, params: PlateParams, s) -> np.ndarray:
    """The symbol P(1, i s) of the incremental Euler-Lagrange operator in the unknowns
    (psi, u3, phi), for each entry of ``s``: shape ``np.shape(s) + (3, 3)``.

    P(q) = B(-q)^T S B(q), with S the energy matrix (:func:`energy_matrix`) and B(q) the
    map from the amplitudes (Psi, U3, Phi) of fields exp(i (q1 x1 + q2 x2)) to z; q = (1, i s)
    are the fields exp(i k x1 - s k x2) (k = 1). det P(1, i s) = 0 is the characteristic
    equation of :func:`characteristic_roots`; where q is real (``s`` imaginary), P is
    Hermitian. ``theta`` in degrees [0, 90]; ``s`` finite, complex allowed.
    """
    lam, theta = _check(lam, theta, params)
    s = v.finite("s", s, complex_ok=True)
    return _symbol(_S(lam, theta, params), s)


def _s_coefficients(q1):
    """(B0, B1, B2) with B(q1, i q1 s) = B0 + s B1 + s^2 B2 (the entries of B are
    monomials of degree <= 2 in q; read off exactly at s = 0, +-1)."""
    b0, bp, bm = (_B(q1, 1j * q1 * s) for s in (0.0, 1.0, -1.0))
    return b0, 0.5 * (bp - bm), 0.5 * (bp + bm) - b0


def _symbol_tensor():
    """T (64, 5 * 9): P(1, i s) = sum_k s^k P_k, P_k = (S.ravel() @ T)[k] as 3 x 3: P is
    linear in S and a polynomial of degree 4 in s, P_k = sum_{a + b = k} Bm_a^T S Bp_b
    (Bp = B(q), Bm = B(-q), q = (1, i s))."""
    bp, bm = _s_coefficients(1.0), _s_coefficients(-1.0)
    T = np.zeros((5, 3, 3, 8, 8), complex)
    for a in range(3):
        for b in range(3):
            T[a + b] += np.einsum("ia,jb->abij", bm[a], bp[b])
    return T.reshape(45, 64).T


_SYMBOL_T = _symbol_tensor()


def _symbol(S, s):
    """P(1, i s) = B(-q)^T S B(q), q = (1, i s), for an array of s (broadcast against the
    leading axes of S): its polynomial coefficients in s from S in one product
    (:func:`_symbol_tensor`), evaluated by Horner's rule."""
    s = np.asarray(s, complex)[..., None, None]
    S = np.asarray(S)
    c = (S.reshape(S.shape[:-2] + (64,)) @ _SYMBOL_T).reshape(S.shape[:-2] + (5, 3, 3))
    P = c[..., 4, :, :]
    for k in (3, 2, 1, 0):
        P = P * s + c[..., k, :, :]
    return P


def _char_poly(S):
    """Coefficients (highest first) of det P(1, i s), degree 8, by exact interpolation."""
    nodes = np.exp(2j * np.pi * np.arange(9) / 9) * 1.3
    vals = np.linalg.det(_symbol(S, nodes))
    coef = np.linalg.solve(np.vander(nodes, 9), vals)
    return coef


def characteristic_roots(lam: float, theta: float, params: PlateParams) -> np.ndarray:
    """The eight roots s of det P(1, i s) = 0 (fields exp(i k x1 - s k x2)), sorted."""
    lam, theta = _check(lam, theta, params)
    return _roots(_S(lam, theta, params))


def _roots(S):
    r = np.roots(_char_poly(S))
    if r.size != 8:
        raise ConvergenceError(f"characteristic polynomial has {r.size} roots, expected 8")
    return _polish(S, r)


def _polish(S, r):
    """Newton on the determinant (np.roots error ~ eps * cond), then sorted; ``S`` and
    ``r`` may carry a leading stack axis (one symbol per row of roots)."""
    for _ in range(3):
        h = 1e-7 * (1 + np.abs(r))
        f = np.linalg.det(_symbol(S, r))
        df = (np.linalg.det(_symbol(S, r + h)) - np.linalg.det(_symbol(S, r - h))) / (2 * h)
        r = r - f / df
    if r.ndim == 1:
        return r[np.lexsort((r.imag, r.real))]
    return np.stack([x[np.lexsort((x.imag, x.real))] for x in r])


def _roots_many(S):
    """:func:`_roots` for a stack of energy matrices ``S`` (n, 8, 8): the characteristic
    polynomials and their companion eigenvalues (as :func:`numpy.roots` computes them)
    in stacked calls; a polynomial with a vanishing end coefficient goes through
    :func:`_roots`."""
    nodes = np.exp(2j * np.pi * np.arange(9) / 9) * 1.3
    vals = np.linalg.det(_symbol(S[:, None], nodes))                      # (n, 9)
    V = np.broadcast_to(np.vander(nodes, 9), (len(S), 9, 9))
    coef = np.linalg.solve(V, vals[..., None])[..., 0]                     # (n, 9)
    if np.any(coef[:, 0] == 0) or np.any(coef[:, -1] == 0):
        return np.stack([_roots(x) for x in S])
    comp = np.zeros((len(S), 8, 8), complex)
    comp[:, 1:, :-1] = np.eye(7)
    comp[:, 0, :] = -coef[:, 1:] / coef[:, :1]
    return _polish(S[:, None], np.linalg.eigvals(comp))


def strongly_elliptic(lam: float, theta: float, params: PlateParams) -> bool:
    """Plane strong ellipticity: P(n) positive definite for every unit n in (x1, x2).

    P(n) = B(-n)^T S B(n) is the Hermitian symbol of the incremental energy in the
    (psi, u3, phi) variables; sampled at :data:`N_DIRECTIONS` directions on the half circle
    (P(-n) = conj P(n)). Directions with a component along x3 are not tested (the fields
    do not depend on x3).
    """
    lam, theta = _check(lam, theta, params)
    return _elliptic(lam, theta, params)


_ANG = np.linspace(0.0, np.pi, N_DIRECTIONS, endpoint=False)
_B_PLUS = _B(np.cos(_ANG), np.sin(_ANG))
_B_MINUS_T = np.swapaxes(_B(-np.cos(_ANG), -np.sin(_ANG)), -1, -2)


def _elliptic(lam, theta, p):
    P = _B_MINUS_T @ _S(lam, theta, p) @ _B_PLUS
    P = 0.5 * (P + np.conj(np.swapaxes(P, -1, -2)))
    return bool(np.all(np.linalg.eigvalsh(P)[..., 0] > 0))


#: P(n) = B(-n)^T S B(n) at every direction of _ANG is linear in S: (S.ravel() @ _DIR_T)
#: reshaped to (dirs, 3, 3)
_DIR_T = np.einsum("dai,djb->ijdab", _B_MINUS_T, _B_PLUS).reshape(64, -1)


def _elliptic_grid(g, theta, path) -> np.ndarray:
    """:func:`_elliptic` at every stretch of the grid ``g`` (parameters ``path(lam)``),
    all symbols in one product and one stacked eigenvalue call."""
    S = np.stack([_S(x, theta, path(x)) for x in g])               # (n, 8, 8)
    P = (S.reshape(len(g), 64) @ _DIR_T).reshape(len(g), N_DIRECTIONS, 3, 3)
    P = 0.5 * (P + np.conj(np.swapaxes(P, -1, -2)))
    return np.all(np.linalg.eigvalsh(P)[..., 0] > 0, axis=-1)
