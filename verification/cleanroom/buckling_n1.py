"""Clean-room ch5_critical_voltage, the quantity v_cr_n1, written from its ``debench
problems ID --markdown`` page only: numpy, scipy, scikit-fem and the sibling clean rooms
``buckling`` (the flat state, its meshes, the root search and the extrapolation) and
``wrinkling`` (the energy of a full F and E_L with its exact Hessian); nothing from debench.

v_cr_n1 is the first v = Phi/t0 sqrt(eps/mu_ref) at which the lowest eigenvalue of the
fixed-voltage second variation of int Omega dV at the flat (axisymmetric, clamped) state,
condensed over the potential, S_1 = K_uu - K_uq K_qq^-1 K_qu, crosses zero for the
wavenumber-1 perturbation

    u_R = U(R, Z) cos Theta,  u_Theta = V(R, Z) sin Theta,  u_Z = W(R, Z) cos Theta,
    phi = Q(R, Z) cos Theta.

Derivation (units and the flat state as in ``buckling``). In the physical cylindrical
basis (e_R, e_Theta, e_Z) at a material point, Grad u has the rows

    (u_R,R, (u_R,Theta - u_Theta)/R, u_R,Z), (u_Theta,R, (u_Theta,Theta + u_R)/R,
    u_Theta,Z), (u_Z,R, u_Z,Theta/R, u_Z,Z),

and -Grad phi = -(phi,R, phi,Theta/R, phi,Z). The flat state does not move in Theta, so
its F and E_L are components in the same basis at the current point, and Omega is
isotropic: its Hessian H (12 x 12 in F_ab, index 3 a + b, a, b = R, Theta, Z, and E_L,
index 9 + i) at the flat state needs no change of basis. For wavenumber n the
perturbation's components are the cos-amplitudes (indices 0, 2, 4, 6, 8, 9, 11)

    dF_RR = U,R, dF_RZ = U,Z, dF_TT = (U + n V)/R, dF_ZR = W,R, dF_ZZ = W,Z,
    dE_R = -Q,R, dE_Z = -Q,Z

times cos n Theta, and the sin-amplitudes (indices 1, 3, 5, 7, 10)

    dF_RT = -(n U + V)/R, dF_TR = V,R, dF_TZ = V,Z, dF_ZT = -n W/R, dE_T = n Q/R

times sin n Theta. F is linear in u and E_L in phi, so the second variation is
int dg . H . dg dV; over Theta, cos^2 and sin^2 integrate to pi and cos sin to zero, so

    d2 = pi int (dg_c . H_cc . dg_c + dg_s . H_ss . dg_s) R dR dZ,

(H_cs vanishes at an axisymmetric state by the reflection Theta -> -Theta; it is not used).
The factor pi, common to the mass int (U^2 + V^2 + W^2) R dR dZ, is dropped.

Axis regularity for n = 1 (own derivation): near R = 0 a smooth displacement is, to
leading order, a constant Cartesian vector c e_x (the cos family; c e_y is the sin family):
u_R = c cos Theta, u_Theta = -c sin Theta, u_Z = 0 there, so at R = 0: U = c, V = -c, W = 0,
i.e. U + V = 0 and W = 0 (a sideways translation of the axis is admitted); a smooth phi is
single-valued on the axis, so Q cos Theta is Theta-independent there: Q = 0. These also
keep the hoop terms finite: (U + V)/R, -(U + V)/R (n = 1) and -W/R, Q/R are O(1) when U + V,
W and Q vanish on the axis (on Lagrange elements, vanishing at the axis dofs of an axis
edge makes the trace vanish on the whole edge, so the integrands are bounded). Implemented
by eliminating V = -U at the axis dofs and setting W = Q = 0 there. Rim (clamped): U = V =
W = 0; electrodes (fixed voltage): Q = 0 on Z = 0 and Z = 1.

The Hessian H: ``wrinkling.enthalpy`` (a spectral function of the eigenvalues of C with
Lewis' second-derivative formula, the divided differences of the Ogden powers evaluated
without cancellation, so exact at repeated principal stretches without regularisation;
the electric part by complex step). The neo-Hookean (5.15) is its single Ogden term
(alpha, mu) = (2, mu / mu_ref). On the seven axisymmetric components it equals the
``buckling`` Jet energy (Taylor series in the in-plane eigenvalue split d^2), which gives
the flat state (tested).

The eigenvalue tracked is the algebraically smallest of the CONDENSED_K eigenvalues of S_1
nearest zero (shift-invert); the root search, its certificate (LOBPCG at the lower bracket
end) and the extrapolation over the meshes N x N/4 are ``buckling``'s.

Measured convergence (P4 unless said, N x N/4 meshes refined L times at both clamped
corners; CPU per level on a loaded 2-core machine, one thread):

* corner refinements, neo-Hookean at 16 x 4: L = 12, 15, 18 give 0.2920039957,
  0.2920039913, 0.2920039910 (changes 4.4e-9, 2.6e-10), so L = 15 is converged in L to
  ~3e-10, as for n = 0.
* order, neo-Hookean at 16 x 4, L = 15: P2 0.2924990940, P3 0.2920088712, P4 0.2920039913
  (changes 4.9e-4, 4.9e-6). scikit-fem's Lagrange triangles stop at P4, and the P4 value
  still lies 1.5e-7 above the mesh-converged one (three times a geometric continuation of
  the p-changes), so the order sequence cannot carry the estimate: the mesh sequence does.
* the converged sequence (converged_critical_voltage: N = 16, 24, 32, 40, L = 15; the
  levels after the first started 1e-5 below the previous value):

  ===========  ==============  ==============  ==============  ==============
  N x N/4      16 x 4          24 x 6          32 x 8          40 x 10
  dofs         6555            10515           16011           23043
  nh_t1        0.2920039913    0.2920039214    0.2920038914    0.2920038757
  CPU s        27              24              42              79
  ogden_t1     0.1951106168    0.1951105663    0.1951105447    0.1951105334
  CPU s        39              44              71              130
  ===========  ==============  ==============  ==============  ==============

  neo-Hookean: rates 1.44 (16, 24, 32) and 1.52 (24, 32, 40), limits 0.2920038329 and
  0.2920038368: v_cr_n1 = 0.2920038368 +- 1.2e-8; Ogden: rates 1.44, 1.54, limits
  0.1951105024, 0.1951105059: v_cr_n1 = 0.1951105059 +- 1.0e-8 (173 s and 285 s CPU).
  N = 8 (8 x 2: 0.2920041277, 17 s; Ogden 0.1951107149, 22 s) is pre-asymptotic (rate
  0.24 through 8, 16, 24). A level started from v = 0 and one started 1e-5 below agree
  to 9e-12 (16 x 4: 0.2920039913 both).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from skfem import BilinearForm

from . import buckling, wrinkling

#: the wavenumber
N1 = 1
#: the Ogden terms (alpha_p, mu_p / mu_ref) of each case: the neo-Hookean is one term
TERMS = {"nh_t1": ((2.0, 1.0),), "ogden_t1": buckling.OGDEN}
#: fields of the perturbation
U, V, W, Q = range(4)
#: eigenvalues of S_1 computed nearest zero; the tracked one is the smallest of them (a
#: negative lambda_1 past the crossing is among them while |lambda_1| < lambda_4)
CONDENSED_K = 4


def components(n: int) -> tuple[tuple[tuple[int, int, float], ...], ...]:
    """The twelve (F, E_L) amplitudes of the wavenumber-n perturbation (module docstring)
    as sums of (field, kind, coefficient), kind 0 d/dR, 1 d/dZ, 2 value/R."""
    return (((U, 0, 1.0),), ((U, 2, -float(n)), (V, 2, -1.0)), ((U, 1, 1.0),),
            ((V, 0, 1.0),), ((U, 2, 1.0), (V, 2, float(n))), ((V, 1, 1.0),),
            ((W, 0, 1.0),), ((W, 2, -float(n)),), ((W, 1, 1.0),),
            ((Q, 0, -1.0),), ((Q, 2, float(n)),), ((Q, 1, -1.0),))


def block_coefficients(H, n: int):
    """C[a][b] (3, 3, ...): the coefficient of (kind i of test field a) x (kind j of trial
    field b) in dg . H . dg, cos with cos and sin with sin components only."""
    comps = components(n)
    parity = {k: k in wrinkling.EVEN for k in range(12)}
    C = {(a, b): np.zeros((3, 3) + H.shape[:-2]) for a in range(4) for b in range(4)}
    for k in range(12):
        for l in range(12):
            if parity[k] != parity[l]:
                continue
            for a, i, ca in comps[k]:
                for b, j, cb in comps[l]:
                    C[a, b][i, j] += ca * cb * H[..., k, l]
    return C


@BilinearForm
def _kind_form(u, v, w):
    """int sum_ij C_ij (kind i of v) (kind j of u) R dR dZ."""
    R = np.asarray(w.x)[0]
    C = np.asarray(w.C)
    vk = (v.grad[0], v.grad[1], v / R)
    uk = (u.grad[0], u.grad[1], u / R)
    out = 0.0
    for i in range(3):
        for j in range(3):
            out = out + C[i, j] * vk[i] * uk[j]
    return out * R


class FilmN1(buckling.Film):
    """``buckling.Film`` (the flat state) with the wavenumber-1 condensed tangent S_1:
    ``lowest_at`` and ``smallest_algebraic_at`` make ``buckling.critical_voltage`` track
    lambda_1 of S_1."""

    def __init__(self, case: str, order: int = 2, n_r: int = 40, n_z: int = 4,
                 levels: int = 6, ratio: float = 1.0):
        super().__init__(case, order, n_r, n_z, levels, ratio)
        self.terms = TERMS[case]
        N = self.n
        x = self.basis.doflocs
        tol = buckling.face_tolerance(self.mesh)
        rim = np.flatnonzero(np.abs(x[0] - buckling.ASPECT) <= tol)
        axis = np.flatnonzero(np.abs(x[0]) <= tol)
        fixed = np.unique(np.concatenate((U * N + rim, V * N + rim, W * N + rim,
                                          V * N + axis, W * N + axis, Q * N + axis,
                                          Q * N + self.bottom, Q * N + self.top)))
        free = np.setdiff1d(np.arange(4 * N), fixed)
        self.nu1 = int(np.sum(free < Q * N))
        T = sp.coo_matrix((np.ones(free.size), (free, np.arange(free.size))),
                          shape=(4 * N, free.size)).tolil()
        T[V * N + axis, np.searchsorted(free, U * N + axis)] = -1.0  # V = -U on the axis
        self.T1 = T.tocsr()
        m = buckling._mass.assemble(self.basis)
        mass = sp.block_diag((m, m, m, sp.csr_matrix((N, N)))).tocsr()
        self.M1 = (self.T1.T @ mass @ self.T1).tocsc()[:self.nu1, :self.nu1]

    def hessian(self, x):
        """The 12 x 12 Hessian of Omega (``wrinkling.enthalpy``) at the quadrature points
        of the axisymmetric state x = (u_r, u_z, phi)."""
        g = self._g(x)
        F = np.zeros(g[0].shape + (3, 3))
        F[..., 0, 0], F[..., 0, 2], F[..., 1, 1] = 1 + g[0], g[1], 1 + g[2]
        F[..., 2, 0], F[..., 2, 2] = g[3], 1 + g[4]
        E = np.stack((-g[5], np.zeros_like(g[5]), -g[6]), axis=-1)
        return wrinkling.enthalpy(F, E, terms=self.terms)[2]

    def tangent(self, x, n: int = N1, reduced: bool = True):
        """The wavenumber-n second variation (per pi) at the axisymmetric state x: on all
        4 N dofs (U, V, W, Q) (``reduced`` False), or for n = 1 on the admissible dofs
        (the displacements U, V, W first, nu1 of them, then Q)."""
        if reduced and n != N1:
            raise ValueError(f"the admissible dofs are those of n = {N1}, got n = {n}")
        C = block_coefficients(self.hessian(x), n)
        blocks = [[None] * 4 for _ in range(4)]
        for a in range(4):
            for b in range(a, 4):
                blocks[a][b] = _kind_form.assemble(self.basis, C=C[a, b])
                if b != a:
                    blocks[b][a] = blocks[a][b].T
        K = sp.bmat(blocks, format="csr")
        return (self.T1.T @ K @ self.T1).tocsc() if reduced else K

    def lowest_at(self, x, K) -> float:
        """The algebraically smallest of the CONDENSED_K eigenvalues of S_1 x = lambda M x
        nearest zero."""
        w = buckling.condensed_eigenvalues(self.tangent(x), self.nu1, self.M1, CONDENSED_K)
        return float(np.min(w))

    def smallest_algebraic_at(self, x, K, shift: float) -> np.ndarray:
        """The three smallest algebraic eigenvalues of S_1 (LOBPCG)."""
        return buckling.smallest_condensed(self.tangent(x), self.nu1, self.M1, shift)


def critical_voltage(case: str, order: int = 2, n_r: int = 40, n_z: int = 4,
                     levels: int = 6, **kw) -> buckling.Critical:
    """v_cr_n1 of ``case`` on one discretisation (``buckling.critical_voltage`` with
    the wavenumber-1 lambda_1; keywords as there)."""
    return buckling.critical_voltage(case, order, n_r, n_z, levels, film_type=FilmN1, **kw)


def converged_critical_voltage(case: str, sizes=buckling.CONVERGED_SIZES,
                               levels: int = buckling.CONVERGED_LEVELS,
                               order: int = buckling.CONVERGED_ORDER) -> buckling.Converged:
    """v_cr_n1 of ``case`` extrapolated over the meshes N x N/4
    (``buckling.converged_critical_voltage`` with the wavenumber-1 lambda_1)."""
    return buckling.converged_critical_voltage(case, sizes, levels, order, film_type=FilmN1)
