"""Clean-room ch5_wrinkling, written from its ``debench problems ID --markdown`` page only:
numpy, scipy, scikit-fem and the sibling clean rooms ``buckling`` (the Table 5.1 constants,
the Jet and the condensed-tangent eigenvalue search) and ``pullin`` (the voltage- and
deflection-controlled Newton of the lifted body); nothing from debench.

The page: the circular film 0 <= R <= a = 20 t0, lifted by the imperfection w0(R) = 1e-3 t0
(1 - R^2/a^2)^2 (w0(R) <= Z <= t0 + w0(R)), compressible three-term Ogden (5.26) ideal
dielectric (5.9), clamped over its rim face, electrodes on both faces (phi = 0 bottom,
Phi top), rim insulated. The state is the axisymmetric saddle point of int Omega dV,

    Omega(F, E_L) = W_mech(F) - (1/2) J C^-1 : (E_L x E_L),   E_L = -Grad phi,

(lengths in t0, stresses in mu_ref, permittivity in eps, so Phi is v), followed from Phi = 0
through its voltage maximum. Along it, for each wavenumber n = 1..14, the lowest eigenvalue
of the condensed fixed-voltage tangent S_n (the second variation of int Omega dV for the
perturbation u_R = U cos n Theta, u_Theta = V sin n Theta, u_Z = W cos n Theta, phi = Q cos
n Theta, Q = 0 on both electrodes, condensed over Q) is followed; w_cross(n) and v_cross(n)
are the top-surface centre deflection and the voltage at its first zero (none if it stays
positive up to the voltage maximum).

The energy (``enthalpy``) is written once as a function of the full F (3 x 3, in the
cylindrical basis at the material point) and E_L (3): the mechanical part is a spectral
function of C = F^T F, phi(c1, c2, c3) of its eigenvalues c_i,

    phi = sum_p 2 mu_p/alpha_p^2 (J^(-alpha_p/3) sum_i c_i^(alpha_p/2) - 3) + k/2 (J - 1)^2,

J = sqrt(c1 c2 c3) = det F; its gradient dphi/dC = Q diag(phi_i) Q^T and its second
derivative by Lewis' formula for spectral functions,

    d2phi[H1, H2] = sum_ij phi_ij H1^_ii H2^_jj + sum_{i != j} G_ij H1^_ij H2^_ij,
    H^ = Q^T H Q,  G_ij = (phi_i - phi_j)/(c_i - c_j),

with G_ij, a divided difference of one smooth function of one c (below), evaluated without
cancellation for close or equal c_i, c_j (the undeformed film and the axis have repeated
eigenvalues); then d2W[dF1, dF2] = d2phi[dC1, dC2] + 2 dphi/dC : (dF1^T dF2), dC = dF^T F +
F^T dF. The electric part's gradient is analytic (e = F^-T E_L, m = C^-1 E_L:
d/dF = -(1/2) J (e.e) F^-T + J e x m, d/dE_L = -J m) and its Hessian is the complex-step
derivative of that gradient (exact to round-off).

Kinematics (physical cylindrical components, Theta derivatives by the wavenumber): the
axisymmetric state has F = [[1 + u_r,R, 0, u_r,Z], [0, 1 + u_r/R, 0], [u_z,R, 0, 1 + u_z,Z]]
and E_L = -(phi_R, 0, phi_Z); the perturbation of wavenumber n has the cos-amplitudes

    dF_RR = U,R, dF_RZ = U,Z, dF_TT = (U + n V)/R, dF_ZR = W,R, dF_ZZ = W,Z,
    dE_R = -Q,R, dE_Z = -Q,Z

and the sin-amplitudes

    dF_RT = -(n U + V)/R, dF_TR = V,R, dF_TZ = V,Z, dF_ZT = -n W/R, dE_T = n Q/R,

and the Theta integral of the second variation is pi (sum over the cos block of H + the sin
block of H) (the mixed cos sin terms integrate to zero; at an axisymmetric state the mixed
block of H vanishes anyway, by the Theta -> -Theta reflection). On the lifted body d/dR =
d/dRh - w0'(Rh) d/dZh on the flat mesh (the exact map of ``pullin``). Axis regularity (the
page's, derived from smooth Cartesian fields: n = 1 is a uniform in-plane translation
there, u_R = c cos Theta, u_Theta = -c sin Theta): n = 1: U + V = 0 (V eliminated as -U at
the axis dofs), W = Q = 0; n >= 2: U = V = W = Q = 0. Rim: U = V = W = 0. Mass int (U^2 +
V^2 + W^2) R dR dZ.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from skfem import Basis, BilinearForm, MeshTri

from . import buckling, pullin

ASPECT = 20.0
IMPERFECTION = 1e-3
K_BULK = buckling.K_BULK
OGDEN = buckling.OGDEN
CASES = ("ogden_r20",)
WAVENUMBERS = tuple(range(1, 15))
#: complex-step increment of the electric Hessian (the derivative's error is ~h^2: none)
CSTEP = 1e-30
#: divided differences x^p: exact ratio expm1(p t)/expm1(t) of t = log(x/y) (no
#: cancellation for t -> 0); t = 0 exactly gives the limit p
#: flattened index of F_ab is 3 a + b (a, b = R, Theta, Z); E_L components 9, 10, 11
EVEN = (0, 2, 4, 6, 8, 9, 11)
ODD = (1, 3, 5, 7, 10)
#: the seven axisymmetric g = (u_r,R, u_r,Z, u_r/R, u_z,R, u_z,Z, phi_R, phi_Z) as
#: components of (F, E_L): index and sign (F = I + ..., E_L = -Grad phi)
AXI = ((0, 1.0), (2, 1.0), (4, 1.0), (6, 1.0), (8, 1.0), (9, -1.0), (11, -1.0))


def _power_dd(x, y, p):
    """(x^p - y^p)/(x - y) for x, y > 0, accurate for x -> y (limit p y^(p-1))."""
    t = np.log(x / y)
    safe = np.where(t == 0.0, 1.0, t)
    ratio = np.where(t == 0.0, p, np.expm1(p * safe) / np.expm1(safe))
    return y ** (p - 1) * ratio


def _spectral(c, terms=OGDEN):
    """phi_i (..., 3), phi_ij (..., 3, 3) and G_ij (..., 3, 3; diagonal unused) of the
    mechanical energy as a function of the eigenvalues c (..., 3) of C (module
    docstring), the Ogden terms (alpha_p, mu_p / mu_ref) ``terms``. Each Ogden term
    k P T, P = (c1 c2 c3)^s, s = -alpha/6, T = sum c^beta,
    beta = alpha/2: phi_i = k P h(c_i), h(x) = beta x^(beta-1) + s T/x, so G_ij =
    k P (beta DD[x^(beta-1)] - s T/(c_i c_j)); the volumetric k/2 (J - 1)^2 likewise."""
    prod = c[..., 0] * c[..., 1] * c[..., 2]
    J = np.sqrt(prod)
    ci, cj = c[..., :, None], c[..., None, :]
    eye = np.eye(3)
    d1 = np.zeros(c.shape)
    d2 = np.zeros(c.shape + (3,))
    G = np.zeros(c.shape + (3,))
    for alpha, mu in terms:
        k, s, beta = 2 * mu / alpha**2, -alpha / 6, alpha / 2
        P = prod**s
        T = np.sum(c**beta, axis=-1)
        Pk, Tk = P[..., None], T[..., None]
        d1 += k * Pk * (beta * c ** (beta - 1) + s * Tk / c)
        Pk2, Tk2 = Pk[..., None], Tk[..., None]
        d2 += k * Pk2 * (s * beta * (ci ** (beta - 1) / cj + cj ** (beta - 1) / ci)
                         + s * s * Tk2 / (ci * cj)
                         + eye * (beta * (beta - 1) * ci ** (beta - 2) - s * Tk2 / ci**2))
        G += k * Pk2 * (beta * _power_dd(ci, cj, beta - 1) - s * Tk2 / (ci * cj))
    Jk, Jk2 = J[..., None], J[..., None, None]
    d1 += K_BULK * (Jk - 1) * Jk / (2 * c)
    d2 += K_BULK * (Jk2 * (2 * Jk2 - 1) / (4 * ci * cj) - eye * (Jk2 - 1) * Jk2 / (2 * ci**2))
    G += -K_BULK * (Jk2 - 1) * Jk2 / (2 * ci * cj)
    return d1, d2, G


def _det_inv(F):
    """det F and F^-1 of (..., 3, 3) by cofactors (complex-safe, vectorised)."""
    a = F
    cof = np.stack([
        np.stack([a[..., 1, 1] * a[..., 2, 2] - a[..., 1, 2] * a[..., 2, 1],
                  a[..., 1, 2] * a[..., 2, 0] - a[..., 1, 0] * a[..., 2, 2],
                  a[..., 1, 0] * a[..., 2, 1] - a[..., 1, 1] * a[..., 2, 0]], axis=-1),
        np.stack([a[..., 0, 2] * a[..., 2, 1] - a[..., 0, 1] * a[..., 2, 2],
                  a[..., 0, 0] * a[..., 2, 2] - a[..., 0, 2] * a[..., 2, 0],
                  a[..., 0, 1] * a[..., 2, 0] - a[..., 0, 0] * a[..., 2, 1]], axis=-1),
        np.stack([a[..., 0, 1] * a[..., 1, 2] - a[..., 0, 2] * a[..., 1, 1],
                  a[..., 0, 2] * a[..., 1, 0] - a[..., 0, 0] * a[..., 1, 2],
                  a[..., 0, 0] * a[..., 1, 1] - a[..., 0, 1] * a[..., 1, 0]], axis=-1)],
        axis=-2)
    J = np.sum(a[..., 0, :] * cof[..., 0, :], axis=-1)
    return J, np.swapaxes(cof, -1, -2) / J[..., None, None]


def _electric_gradient(F, E):
    """Gradient of -(1/2) J C^-1 : (E x E) in (F, E): (..., 12), complex-safe."""
    J, Finv = _det_inv(F)
    e = np.einsum("...ji,...j->...i", Finv, E)  # F^-T E
    m = np.einsum("...ij,...j->...i", Finv, e)  # F^-1 e = C^-1 E
    ee = np.sum(e * e, axis=-1)
    dF = (-0.5 * (J * ee)[..., None, None] * np.swapaxes(Finv, -1, -2)
          + J[..., None, None] * e[..., :, None] * m[..., None, :])
    dE = -J[..., None] * m
    return np.concatenate((dF.reshape(*F.shape[:-2], 9), dE), axis=-1)


def enthalpy(F, E, directions=range(12), terms=OGDEN):
    """Omega per mu_ref (module docstring) at F (..., 3, 3), E_L (..., 3), the Ogden terms
    (alpha_p, mu_p / mu_ref) ``terms`` (the neo-Hookean (5.15) is the one term (2, mu /
    mu_ref): 2 mu/alpha^2 (J^(-2/3) I1 - 3) = mu/2 (J^(-2/3) I1 - 3)): its value
    (...), gradient (..., 12) and Hessian (..., 12, 12) in (F_ab at 3 a + b, E_L at 9 +
    i); the Hessian's rows of the electric part only at ``directions`` (the others
    zero: the axisymmetric path needs AXI only). Raises ValueError where det F <= 0 or
    the input is not finite."""
    F, E = np.asarray(F, dtype=float), np.asarray(E, dtype=float)
    if not (np.all(np.isfinite(F)) and np.all(np.isfinite(E))):
        raise ValueError("enthalpy: F and E_L must be finite")
    J, Finv = _det_inv(F)
    if np.any(J <= 0):
        raise ValueError(f"enthalpy: det F must be > 0, got min {np.min(J)}")
    C = np.swapaxes(F, -1, -2) @ F
    c, Q = np.linalg.eigh(C)
    d1, d2, G = _spectral(c, terms)
    psi = np.einsum("...ik,...k,...jk->...ij", Q, d1, Q)  # dphi/dC
    # the value
    val = K_BULK / 2 * (J - 1) ** 2
    for alpha, mu in terms:
        val = val + 2 * mu / alpha**2 * (J ** (-alpha / 3) * np.sum(c ** (alpha / 2), -1) - 3)
    e = np.einsum("...ji,...j->...i", Finv, E)
    val = val - 0.5 * J * np.sum(e * e, axis=-1)
    # mechanical gradient P = 2 F dphi/dC and Hessian (Lewis)
    grad = np.zeros(F.shape[:-2] + (12,))
    grad[..., :9] = (2 * F @ psi).reshape(*F.shape[:-2], 9)
    FQ = F @ Q
    # C^ of the direction dF = e_a e_b^T: Q[b, i] FQ[a, j] + FQ[a, i] Q[b, j]
    A = (Q[..., None, :, :, None] * FQ[..., :, None, None, :]
         + FQ[..., :, None, :, None] * Q[..., None, :, None, :])  # (..., a, b, i, j)
    A = A.reshape(*F.shape[:-2], 9, 3, 3)
    diag = np.diagonal(A, axis1=-2, axis2=-1)  # (..., 9, 3)
    off = (G * (1 - np.eye(3)))[..., None, :, :]
    A9 = A.reshape(*F.shape[:-2], 9, 9)
    hess = np.zeros(F.shape[:-2] + (12, 12))
    hess[..., :9, :9] = ((diag @ d2) @ np.swapaxes(diag, -1, -2)
                         + (A * off).reshape(A9.shape) @ np.swapaxes(A9, -1, -2))
    # 2 dphi/dC : (dF_ab^T dF_cd) = 2 delta_ac psi_bd
    hess[..., :9, :9] += 2 * np.einsum("ac,...bd->...abcd", np.eye(3), psi).reshape(
        *F.shape[:-2], 9, 9)
    # electric part: analytic gradient, complex-step Hessian
    grad += _electric_gradient(F, E)
    x0 = np.concatenate((F.reshape(*F.shape[:-2], 9), E), axis=-1).astype(complex)
    for k in directions:
        x = x0.copy()
        x[..., k] += 1j * CSTEP
        g = _electric_gradient(x[..., :9].reshape(F.shape), x[..., 9:])
        hess[..., k, :] += g.imag / CSTEP
    return val, grad, hess


def w0(R):
    """The imperfection w0(R) = 1e-3 (1 - R^2/a^2)^2 (in t0), a = 20."""
    return IMPERFECTION * (1 - (R / ASPECT) ** 2) ** 2


def w0_slope(R):
    """w0'(R) = -4e-3 R/a^2 (1 - R^2/a^2)."""
    return -4 * IMPERFECTION * R / ASPECT**2 * (1 - (R / ASPECT) ** 2)


def mesh(n_r: int, n_z: int, levels: int, rim: int | None = None) -> MeshTri:
    """Triangle mesh of [0, a] x [0, 1]: n_z uniform layers, n_r radial intervals, ``rim``
    of them (default n_r // 4) uniform over the last thickness before the rim and the rest
    uniform over [0, a - 1], refined ``levels`` times at each clamped corner (a, 0),
    (a, 1), where the stress is singular."""
    rim = max(2, n_r // 4) if rim is None else rim
    if n_r < 4 or n_z < 1 or levels < 0 or not 1 <= rim < n_r:
        raise ValueError("mesh: need n_r >= 4, n_z >= 1, levels >= 0, 1 <= rim < n_r")
    r = np.concatenate((np.linspace(0.0, ASPECT - 1.0, n_r - rim + 1),
                        np.linspace(ASPECT - 1.0, ASPECT, rim + 1)[1:]))
    m = MeshTri.init_tensor(r, np.linspace(0.0, 1.0, n_z + 1))
    for _ in range(levels):
        corner = np.flatnonzero(np.isclose(m.p[0], ASPECT)
                                & (np.isclose(m.p[1], 0.0) | np.isclose(m.p[1], 1.0)))
        m = m.refined(np.flatnonzero(np.isin(m.t, corner).any(axis=0)))
    return m


@BilinearForm
def _mass(u, v, w):
    return u * v * w.x[0]


class Film(pullin.ImperfectFilm):
    """The discretised imperfect Ogden film at a = 20 t0 on the flat mesh of ``mesh`` (the
    exact lift of ``pullin``), its energy from ``enthalpy``: the axisymmetric path
    (Newton at fixed voltage or at fixed centre deflection, inherited from
    ``pullin.ImperfectFilm``) and the condensed tangent S_n of every wavenumber."""

    def __init__(self, case: str = "ogden_r20", order: int = 3, n_r: int = 40, n_z: int = 2,
                 levels: int = 2, rim: int | None = None):
        if case not in CASES:
            raise ValueError(f"case must be one of {CASES}, got {case!r}")
        if order not in buckling.ELEMENTS:
            raise ValueError(f"order must be one of {sorted(buckling.ELEMENTS)}, got {order}")
        for name, val in (("n_r", n_r), ("n_z", n_z), ("levels", levels)):
            if not isinstance(val, int | np.integer):
                raise TypeError(f"{name} must be an integer, got {val!r}")
        self.case = self.material = case
        self.mesh = mesh(n_r, n_z, levels, rim)
        self.basis = Basis(self.mesh, buckling.ELEMENTS[order](), intorder=2 * order + 2)
        n = self.n = self.basis.N
        x = self.basis.doflocs
        tol = buckling.face_tolerance(self.mesh)

        def on(c, val):
            return np.abs(x[c] - val) <= tol

        self.rim, self.axis = np.flatnonzero(on(0, ASPECT)), np.flatnonzero(on(0, 0.0))
        self.bottom, self.top = np.flatnonzero(on(1, 0.0)), np.flatnonzero(on(1, 1.0))
        centre = np.flatnonzero(on(0, 0.0) & on(1, 1.0))
        if centre.size != 1:
            raise RuntimeError(f"expected one dof at the top-surface centre, found {centre}")
        self.centre = n + int(centre[0])
        self.D = np.unique(np.concatenate((self.rim, self.axis, n + self.rim,
                                           2 * n + self.bottom, 2 * n + self.top)))
        self.free = np.setdiff1d(np.arange(3 * n), self.D)
        self.free_u = self.free[self.free < 2 * n]
        self.nu = self.free_u.size
        self.i_centre = int(np.searchsorted(self.free, self.centre))
        self.m = _mass.assemble(self.basis).tocsr()
        self.M = sp.block_diag((self.m, self.m)).tocsr()[self.free_u][:, self.free_u]
        self.newton_iterations = 0
        self.assemblies = 0
        R = np.asarray(self.basis.global_coordinates())[0]
        self.R = R
        self.slope = w0_slope(R)
        self._op = self._local_operator()
        self._hat = self._hat_derivatives()

    def at_deflection(self, w: float, x0, v0: float) -> pullin.State:
        """``pullin``'s bordered Newton at the centre deflection w; an iterate with det F <= 0
        at a quadrature point (an overshoot of the predictor or of Newton) is a failed
        Newton (NewtonError), which the path answers with a shorter step."""
        try:
            return super().at_deflection(w, x0, v0)
        except ValueError as e:
            raise pullin.NewtonError(f"bordered Newton at w = {w}: {e}") from e

    def _hat_derivatives(self):
        """Per local function i: value, d/dR (= d/dRh - s d/dZh) and d/dZ at the
        quadrature points (e, q)."""
        b = self.basis
        val = np.stack([np.asarray(f[0]) for f in b.basis])
        dZ = np.stack([f[0].grad[1] for f in b.basis])
        dR = np.stack([f[0].grad[0] for f in b.basis]) - self.slope[None] * dZ
        return val, dR, dZ

    def fields(self, x):
        """(F, E_L) at the quadrature points (e, q, 3, 3), (e, q, 3) of the axisymmetric
        state x."""
        B, dofs, _ = self._op
        g = np.einsum("eqkI,eI->eqk", B, x[dofs])
        F = np.zeros(g.shape[:2] + (12,))
        F[..., [0, 4, 8]] = 1.0
        for k, (i, sign) in enumerate(AXI):
            F[..., i] += sign * g[..., k]
        return F[..., :9].reshape(*g.shape[:2], 3, 3), F[..., 9:]

    def assemble(self, x):
        """Tangent K (3n x 3n) and residual r of the axisymmetric state x, from the
        gradient and Hessian of ``enthalpy`` restricted to the seven g (AXI)."""
        B, dofs, wR = self._op
        idx = [i for i, _ in AXI]
        _, grad, hess = enthalpy(*self.fields(x), directions=idx)
        sign = np.array([s for _, s in AXI])
        h7 = hess[..., idx][..., idx, :] * sign[:, None] * sign[None, :]
        g7 = grad[..., idx] * sign
        return self._scatter(B, dofs, wR, h7, g7, 3 * self.n)

    def _scatter(self, B, dofs, wR, H, g, size):
        ne, nq, _, m = B.shape
        k = B.shape[2]
        HB = (H @ B).reshape(ne, nq * k, m)
        BW = (B * wR[:, :, None, None]).reshape(ne, nq * k, m)
        Ke = np.swapaxes(BW, 1, 2) @ HB
        rows = np.repeat(dofs, m, axis=1).ravel()
        cols = np.tile(dofs, (1, m)).ravel()
        K = sp.coo_matrix((Ke.ravel(), (rows, cols)), shape=(size, size)).tocsr()
        self.assemblies += 1
        if g is None:
            return K
        re = np.einsum("eqkI,eqk->eI", B * wR[:, :, None, None], g)
        return K, np.bincount(dofs.ravel(), weights=re.ravel(), minlength=size)

    def perturbation_operator(self, n: int):
        """B_n[e, q, c, I]: the twelve (F, E_L) amplitudes c of the wavenumber-n
        perturbation (module docstring; cos amplitudes at EVEN, sin at ODD) as linear
        functions of the element's dofs I = (field, local function), fields U, V, W, Q;
        and the global dof of each (e, I) in the 4 N numbering."""
        val, dR, dZ = self._hat
        nb = val.shape[0]
        ne, nq = self.R.shape
        inv = val / self.R[None]
        B = np.zeros((ne, nq, 12, 4 * nb))
        for i in range(nb):
            U, V, W, Q = (f * nb + i for f in range(4))
            B[:, :, 0, U], B[:, :, 2, U] = dR[i], dZ[i]
            B[:, :, 4, U], B[:, :, 4, V] = inv[i], n * inv[i]
            B[:, :, 6, W], B[:, :, 8, W] = dR[i], dZ[i]
            B[:, :, 9, Q], B[:, :, 11, Q] = -dR[i], -dZ[i]
            B[:, :, 1, U], B[:, :, 1, V] = -n * inv[i], -inv[i]
            B[:, :, 3, V], B[:, :, 5, V] = dR[i], dZ[i]
            B[:, :, 7, W] = -n * inv[i]
            B[:, :, 10, Q] = n * inv[i]
        dofs = np.concatenate([f * self.n + self.basis.element_dofs.T for f in range(4)],
                              axis=1)
        return B, dofs

    def reduction(self, n: int):
        """T (4N x m, sparse): the admissible perturbations of wavenumber n in terms of
        their m free dofs, the displacements (U, V, W) first: rim U = V = W = 0, Q = 0 on
        both electrodes, and at the axis n = 1: V = -U, W = Q = 0; n >= 2: all zero;
        and the number of free displacement dofs."""
        N, ax = self.n, self.axis
        fixed = [self.rim, N + self.rim, 2 * N + self.rim, 3 * N + self.bottom,
                 3 * N + self.top, N + ax, 2 * N + ax, 3 * N + ax]
        if n >= 2:
            fixed.append(ax)
        free = np.setdiff1d(np.arange(4 * N), np.concatenate(fixed))
        nu = int(np.sum(free < 3 * N))
        T = sp.coo_matrix((np.ones(free.size), (free, np.arange(free.size))),
                          shape=(4 * N, free.size)).tolil()
        if n == 1:  # V = -U at the axis dofs (U free there)
            cols = np.searchsorted(free, ax)
            T[N + ax, cols] = -1.0
        return T.tocsr(), nu

    def state_hessian(self, x):
        """The Hessian of ``enthalpy`` (e, q, 12, 12) at the quadrature points of the
        axisymmetric state x, its mixed cos-sin blocks set to zero (module docstring): the
        same for every wavenumber."""
        _, _, hess = enthalpy(*self.fields(x))
        H = hess.copy()
        H[..., np.array(EVEN)[:, None], np.array(ODD)[None, :]] = 0.0
        H[..., np.array(ODD)[:, None], np.array(EVEN)[None, :]] = 0.0
        return H

    def tangent(self, x, n: int, H=None):
        """The wavenumber-n second variation (per pi) K_n at the axisymmetric state x on
        the admissible dofs of ``reduction`` (displacements first), the mass M_n =
        int (U^2 + V^2 + W^2) R dR dZ on the displacement dofs, and their number. ``H``:
        ``state_hessian(x)`` if already computed (shared by the wavenumbers)."""
        if not (isinstance(n, int | np.integer) and n >= 1):
            raise ValueError(f"n must be an integer >= 1, got {n!r}")
        if H is None:
            H = self.state_hessian(x)
        B, dofs = self.perturbation_operator(n)
        K = self._scatter(B, dofs, self._op[2], H, None, 4 * self.n)
        T, nu = self.reduction(n)
        Kn = (T.T @ K @ T).tocsc()
        M = sp.block_diag((self.m,) * 3 + (sp.csr_matrix((self.n, self.n)),)).tocsr()
        Mn = (T.T @ M @ T).tocsc()[:nu, :nu]
        return Kn, Mn, nu


def lowest_condensed(K, M, nu: int, k: int = 3) -> np.ndarray:
    """The k eigenvalues nearest zero of S x = lambda M x, S = K_uu - K_uq K_qq^-1 K_qu
    (K symmetric on (u, q), the first nu dofs u), by shift-invert at zero: S^-1 y is the u
    part of K^-1 (y, 0). Sorted ascending."""
    nf = K.shape[0]
    Kuu, Kuq = K[:nu, :nu], K[:nu, nu:]
    lu = spla.splu(K.tocsc())
    Kqq = []  # factorised on first use (shift-invert needs only S^-1)

    def s_mv(y):
        if not Kqq:
            Kqq.append(spla.splu(K[nu:, nu:].tocsc()))
        y = np.asarray(y).reshape(nu, -1)
        return Kuu @ y - Kuq @ Kqq[0].solve(np.asarray(Kuq.T @ y))

    def s_inv(y):
        y = np.asarray(y).reshape(nu, -1)
        rhs = np.zeros((nf, y.shape[1]))
        rhs[:nu] = y
        return lu.solve(rhs)[:nu]

    S = spla.LinearOperator((nu, nu), matvec=s_mv, matmat=s_mv, dtype=float)
    Sinv = spla.LinearOperator((nu, nu), matvec=s_inv, matmat=s_inv, dtype=float)
    w = spla.eigsh(S, k=k, M=M, sigma=0.0, OPinv=Sinv, which="LM",
                   return_eigenvectors=False, tol=1e-12)
    return np.sort(w)


#: voltage control up to V_SWITCH in V_STEPS (below the flat film's n = 0 bifurcation at
#: v ~ 0.07, where the imperfect film has deflected ~2e-3 t0 towards +Z), then deflection
#: control (``pullin``'s bordered Newton) with steps FIRST_STEP .. MAX_STEP (growth GROWTH
#: after at most FAST_NEWTON Newton iterations; halved on failure down to MIN_STEP)
V_SWITCH = 0.06
V_STEPS = 3
FIRST_STEP = 0.1
MAX_STEP = 0.5
MIN_STEP = 1e-3
GROWTH = 1.5
FAST_NEWTON = 5
#: no voltage maximum beyond this deflection (the page's crossings lie near 7..9 t0)
W_MAX = 20.0
#: each first zero is located by Illinois in w to this bracket width (the page's 1e-9 t0)
W_TOL = 1e-9
MAX_ROOT = 60


class Crossings:
    """The result of one discretisation: per wavenumber (``wavenumbers``) w_cross and
    v_cross (NaN: no zero of lambda_1(n) up to the end of the followed path), the final
    bracket in w of each located zero and lambda_1(n) at its ends, the path's records
    (w, v, dv/dw, lambda_1(n) for every n), whether the path reached the voltage
    maximum (``complete``; otherwise it stopped at ``w_stop``) and the maximum's
    bracket in w and voltage there, the size, the Newton iterations and the largest
    final residual (max norm)."""

    def __init__(self, **kw):
        self.__dict__.update(kw)

    def __repr__(self):
        return (f"Crossings(case={self.case!r}, wavenumbers={self.wavenumbers}, "
                f"w_cross={self.w_cross!r}, v_cross={self.v_cross!r}, ndofs={self.ndofs})")


def crossings(case: str = "ogden_r20", order: int = 3, n_r: int = 40, n_z: int = 2,
              levels: int = 2, rim: int | None = None, wavenumbers=WAVENUMBERS,
              w_stop: float | None = None) -> Crossings:
    """w_cross(n), v_cross(n) of ``case`` on one discretisation (Lagrange P``order``,
    ``mesh(n_r, n_z, levels, rim)``): the axisymmetric path from Phi = 0 (voltage control
    to V_SWITCH, then deflection control), lambda_1(n) (the eigenvalue of S_n nearest
    zero, of the smallest three, ``lowest_condensed``) at every state for each n in
    ``wavenumbers``; a sign change + -> - between two states is the first zero,
    located by Illinois in w (each evaluation a bordered Newton state) to W_TOL; the
    path ends at the voltage maximum (dv/dw <= 0: n without a zero there get NaN) or,
    if given, at the first state past ``w_stop`` (then NaN means: no zero up to there).
    Raises ValueError/TypeError on bad input, pullin.NewtonError when a state cannot be
    computed, RuntimeError when the path deflects towards -Z, lambda_1(n) is not
    positive at Phi = 0, or no maximum is found up to W_MAX."""
    ns = tuple(int(n) for n in wavenumbers)
    if not ns or any(n not in WAVENUMBERS for n in ns) or len(set(ns)) != len(ns):
        raise ValueError(f"wavenumbers must be distinct values in 1..14, got {wavenumbers!r}")
    if w_stop is not None and not (np.isfinite(w_stop) and 0 < w_stop <= W_MAX):
        raise ValueError(f"w_stop must be in (0, {W_MAX}], got {w_stop!r}")
    film = Film(case, order, n_r, n_z, levels, rim)

    def lam(state):
        out = []
        H = film.state_hessian(state.x)
        for n in ns:
            K, M, nu = film.tangent(state.x, n, H)
            out.append(float(lowest_condensed(K, M, nu)[0]))
        return np.array(out)

    s = film.at_voltage(0.0, film.initial(0.0))
    states, lams = [s], [lam(s)]
    if not np.all(lams[0] > 0):
        raise RuntimeError("lambda_1(n) not positive at Phi = 0: "
                           f"{dict(zip(ns, lams[0], strict=True))}")
    residual = s.residual
    for v in np.linspace(0.0, V_SWITCH, V_STEPS + 1)[1:]:
        guess = s.x.copy()
        guess[2 * film.n:] = (guess[2 * film.n:] * (v / s.v) if s.v > 0
                              else film.initial(float(v))[2 * film.n:])
        s = film.at_voltage(float(v), guess)
        residual = max(residual, s.residual)
        states.append(s)
        lams.append(lam(s))
    if not s.w > 0:
        raise RuntimeError(f"the film deflects towards -Z (w = {s.w} at v = {s.v})")
    s = film.at_deflection(s.w, s.x, s.v)
    states[-1] = s
    step, first, complete = FIRST_STEP, True, False
    while True:
        if s.w + step > W_MAX:
            raise RuntimeError(f"no voltage maximum up to w = {W_MAX}")
        w = s.w + step
        x, v = film.predict(s, w)
        if first:  # leave the steep start (dv/dw ~ 5) with the voltage held
            v = s.v
            x[2 * film.n:] = s.x[2 * film.n:]
        try:
            new = film.at_deflection(w, x, v)
        except pullin.NewtonError:
            step *= 0.5
            if step < MIN_STEP:
                raise
            continue
        first = False
        residual = max(residual, new.residual)
        if new.dvdw <= 0:
            complete, top = True, (s, new)
            break
        states.append(new)
        lams.append(lam(new))
        s = new
        if w_stop is not None and s.w >= w_stop:
            top = None
            break
        if new.iterations <= FAST_NEWTON:
            step = min(GROWTH * step, MAX_STEP)
    lams = np.array(lams)
    w_cross = np.full(len(ns), np.nan)
    v_cross = np.full(len(ns), np.nan)
    brackets = [None] * len(ns)
    for j, n in enumerate(ns):
        neg = np.flatnonzero(lams[:, j] <= 0)
        if neg.size == 0:
            continue
        i = int(neg[0])
        lo, hi = states[i - 1], states[i]
        if lo.dvdw is None or hi.dvdw is None:
            raise RuntimeError(f"n = {n}: lambda_1 changes sign under voltage control "
                               f"(v = {lo.v}..{hi.v}); not located")
        (w_cross[j], v_cross[j], brackets[j], r) = _locate(film, n, lo, hi, lams[i - 1, j],
                                                           lams[i, j])
        residual = max(residual, r)
    path = np.array([(st.w, st.v, np.nan if st.dvdw is None else st.dvdw) for st in states])
    return Crossings(case=case, wavenumbers=ns, w_cross=w_cross, v_cross=v_cross,
                     brackets=brackets, path=path, lams=lams, complete=complete,
                     max_bracket=None if top is None else (top[0].w, top[1].w),
                     v_max=None if top is None else max(top[0].v, top[1].v),
                     w_stop=w_stop, ndofs=int(3 * film.n),
                     newton_iterations=film.newton_iterations, residual=residual, film=film)


def _locate(film, n, lo, hi, flo, fhi):
    """The zero of lambda_1(n)(w) in [lo.w, hi.w] (flo > 0 >= fhi) by the Illinois variant
    of regula falsi in w, each evaluation a bordered Newton state from the nearer bracket
    end (tangent predictor); stops at W_TOL. Returns w, v (secant in the final bracket),
    the bracket (w_lo, w_hi, lambda_lo, lambda_hi) and the largest residual."""

    def lam(state):
        K, M, nu = film.tangent(state.x, n)
        return float(lowest_condensed(K, M, nu)[0])

    last, residual = 0, 0.0
    for _ in range(MAX_ROOT):
        width = hi.w - lo.w
        if width <= W_TOL:
            break
        w = lo.w - flo * width / (fhi - flo)
        w = min(max(w, lo.w + 1e-3 * width), hi.w - 1e-3 * width)
        near = lo if w - lo.w < hi.w - w else hi
        mid = film.at_deflection(w, *film.predict(near, w))
        residual = max(residual, mid.residual)
        f = lam(mid)
        if f > 0:
            lo, flo_new = mid, f
            fhi = 0.5 * fhi if last == 1 else fhi
            flo, last = flo_new, 1
        else:
            hi, fhi_new = mid, f
            flo = 0.5 * flo if last == -1 else flo
            fhi, last = fhi_new, -1
    else:
        raise RuntimeError(f"n = {n}: zero not bracketed to {W_TOL} in {MAX_ROOT} steps")
    # the true end values for the final secant (Illinois halves the stored ones)
    flo, fhi = lam(lo), lam(hi)
    t = flo / (flo - fhi)
    return (lo.w + t * (hi.w - lo.w), lo.v + t * (hi.v - lo.v), (lo.w, hi.w, flo, fhi),
            residual)
