"""One chain rule: energy -> stress, electric field, electroelastic moduli.

Invariant-based energies ``W(I1, ..., I6)`` supply ``W``, ``W_n = dW/dI_n`` and
``W_mn = d2W/dI_m dI_n``; then (thesis eqs (2.27)-(2.28), (2.65)-(2.70), summed over all
six invariants)::

    P_{ia}      = dW/dF_{ia}      = sum_n W_n dI_n/dF_{ia}                (T = P^T, 2.27)
    E_{L a}     = dW/dD_{La}      = sum_n W_n dI_n/dD_{La}                (2.28)
    AA_{iajb}   = sum_mn W_mn dI_m/dF_ia dI_n/dF_jb + sum_n W_n d2I_n/dF_ia dF_jb   (2.68)
    AAA_{iab}   = sum_mn W_mn dI_m/dF_ia dI_n/dD_b  + sum_n W_n d2I_n/dF_ia dD_b    (2.69)
    A_{ab}      = sum_mn W_mn dI_m/dD_a dI_n/dD_b   + sum_n W_n d2I_n/dD_a dD_b     (2.70)

(The thesis prints (2.69) with ``m`` from 4 and (4.33) with ``m`` from 5; those truncated
sums drop the coupling ``W_mn`` of mechanical and electrical invariants, which vanishes for
the energies of Ch. 3-4 but not for the compressible ideal dielectric (5.9): see
catalogue ``ch2.moduli.eq2_69_truncated_sum``.)

Principal-stretch energies (Ogden, eq. (5.26)) are isotropic functions of the eigenvalues
``c_k`` of C; their C-derivatives use the spectral formula with divided differences
``(phi_k - phi_l)/(c_k - c_l)`` evaluated without cancellation (equal eigenvalues exact).

Index conventions: ``P[i, a] = dW/dF_{ia}`` (first Piola; the thesis' nominal stress is
``T = P^T``), ``AA[i, a, j, b]`` = thesis' ``calA_{a i b j}``, ``AAA[i, a, b]`` = thesis'
``bbA_{a i b}``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from debench.models import validation as v
from debench.models.invariants import derivatives

_RESPONSE_SHAPES = {"P": (3, 3), "E_L": (3,), "AA": (3, 3, 3, 3), "AAA": (3, 3, 3),
                    "A": (3, 3)}


@dataclass(frozen=True)
class Response:
    """Energy and its first and second derivatives at one state (F, D_L).

    Attributes
    ----------
    W : float
        energy density (J/m^3 for SI parameters).
    P : ndarray (3, 3)
        ``dW/dF`` (first Piola stress without the pressure term), ``P[i, a]``.
    E_L : ndarray (3,)
        ``dW/dD_L`` (Lagrangian electric field, eq. (2.28)).
    AA, AAA, A : ndarray
        moduli (2.65)-(2.67): ``AA[i,a,j,b]``, ``AAA[i,a,b]``, ``A[a,b]``
        (zeros when computed with ``second=False``).
    """

    W: float
    P: np.ndarray
    E_L: np.ndarray
    AA: np.ndarray
    AAA: np.ndarray
    A: np.ndarray

    def __post_init__(self):
        for name in ("W", "P", "E_L", "AA", "AAA", "A"):
            value = getattr(self, name)
            v.finite(f"Response.{name}", value)
            if name != "W" and np.shape(value) != _RESPONSE_SHAPES[name]:
                raise ValueError(f"Response.{name} must have shape "
                                 f"{_RESPONSE_SHAPES[name]}, got {np.shape(value)}")

    def __add__(self, other: Response) -> Response:
        return Response(self.W + other.W, self.P + other.P, self.E_L + other.E_L,
                        self.AA + other.AA, self.AAA + other.AAA, self.A + other.A)


def invariant_chain_rule(W: float, W_n: np.ndarray, W_mn: np.ndarray, F, D_L, A=None, *,
                         numbering: str, second: bool = True) -> Response:
    """Apply (2.27)-(2.28), (2.68)-(2.70) to an invariant-based energy (full sums).

    ``W`` finite, ``W_n`` a finite 6-vector, ``W_mn`` a finite (6, 6) array; the state
    is checked by :func:`~debench.models.invariants.validate_state`. A non-finite result
    (overflow at an extreme state) raises ValueError.
    """
    v.finite("W", W)
    W_n = v.vector("W_n", W_n, 6)
    W_mn = v.array("W_mn", W_mn, (6, 6))
    d = derivatives(F, D_L, A, numbering=numbering, second=second)
    P = np.einsum("n,nia->ia", W_n, d.dF)
    E_L = np.einsum("n,na->a", W_n, d.dD)
    if not second:
        return Response(W, P, E_L, np.zeros((3, 3, 3, 3)), np.zeros((3, 3, 3)), np.zeros((3, 3)))
    AA = (np.einsum("mn,mia,njb->iajb", W_mn, d.dF, d.dF)
          + np.einsum("n,niajb->iajb", W_n, d.dFF))
    AAA = (np.einsum("mn,mia,nb->iab", W_mn, d.dF, d.dD)
           + np.einsum("n,niab->iab", W_n, d.dFD))
    Amat = (np.einsum("mn,ma,nb->ab", W_mn, d.dD, d.dD)
            + np.einsum("n,nab->ab", W_n, d.dDD))
    return Response(W, P, E_L, AA, AAA, Amat)


def divided_difference_power(x: np.ndarray, y: np.ndarray, q: float) -> np.ndarray:
    """``(x**q - y**q)/(x - y)`` for x, y > 0, exact limit ``q y**(q-1)`` at x = y.

    Written as ``y**q expm1(q log1p((x-y)/y))/(x-y)`` so that nearly equal arguments lose
    no digits. ``x``, ``y`` must be finite and > 0, ``q`` finite; a result that overflows
    raises ValueError.
    """
    v.positive("x", x)
    v.positive("y", y)
    v.finite("q", q)
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    h = x - y
    out = np.empty(np.broadcast(x, y).shape)
    small = np.abs(h) <= 1e-300 + 0 * y
    with np.errstate(divide="ignore", invalid="ignore"):
        r = y**q * np.expm1(q * np.log1p(h / y)) / h
        out[...] = np.where(small, q * y ** (q - 1), r)
    if not np.all(np.isfinite(out)):
        raise ValueError(f"divided_difference_power overflows for q = {q} at these x, y")
    return out


@v.finite_result
def spectral_response(phi, F, *, second: bool = True) -> Response:
    """Stress and moduli of an isotropic energy of the eigenvalues of C (no D_L).

    Parameters
    ----------
    phi : callable
        ``phi(c) -> (W, phi_k (3,), phi_kl (3, 3), theta (3, 3))`` where ``c`` are the
        eigenvalues of C, ``phi_k = dW/dc_k``, ``phi_kl`` its Hessian and
        ``theta[k, l] = (phi_k - phi_l)/(c_k - c_l)`` (its limit at equal eigenvalues),
        computed by the caller without cancellation.

    Notes
    -----
    ``dW/dC = sum_k phi_k n_k (x) n_k`` and, for a symmetric increment H,
    ``d(dW/dC)[H] = sum_kl phi_kl H_ll N_k + 1/2 sum_{k!=l} theta_kl H_kl (n_k n_l + n_l n_k)``.
    Then ``P = 2 F dW/dC`` and ``AA_iajb = 2 d_ij G_ba + 2 F_ig (K_gadb F_jd + K_gabe F_je)``.

    ``F`` is checked (finite (3, 3), ``det F > 0``); a non-finite energy or derivative
    from ``phi`` raises ValueError (through :class:`Response`).
    """
    if not callable(phi):
        raise TypeError(f"phi must be callable, got {phi!r}")
    F = np.asarray(v.deformation_gradient("F", F), dtype=float)
    C = F.T @ F
    c, n = np.linalg.eigh(C)
    W, phik, phikl, theta = phi(c)
    G = np.einsum("k,gk,ak->ga", phik, n, n)
    P = 2 * F @ G
    zD = np.zeros(3)
    if not second:
        return Response(W, P, zD, np.zeros((3, 3, 3, 3)), np.zeros((3, 3, 3)), np.zeros((3, 3)))
    K = np.einsum("kl,gk,ak,dl,bl->gadb", phikl, n, n, n, n)
    off = theta * (1 - np.eye(3))
    K += 0.5 * (np.einsum("kl,gk,al,dk,bl->gadb", off, n, n, n, n)
                + np.einsum("kl,gl,ak,dk,bl->gadb", off, n, n, n, n))
    I = np.eye(3)
    AA = (2 * np.einsum("ij,ba->iajb", I, G)
          + 2 * np.einsum("ig,gadb,jd->iajb", F, K, F)
          + 2 * np.einsum("ig,gabe,je->iajb", F, K, F))
    return Response(W, P, zD, AA, np.zeros((3, 3, 3)), np.zeros((3, 3)))
