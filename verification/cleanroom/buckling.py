"""Clean-room ch5_critical_voltage, written from its ``debench problems ID --markdown`` page
only (numpy, scipy and scikit-fem; nothing from debench).

The page: a flat circular film 0 <= R <= a = 10 t0, 0 <= Z <= t0, compressible neo-Hookean
(5.15)-(5.17) or three-term Ogden (5.26) ideal dielectric (5.9), clamped over its whole rim
face R = a, electrodes on both faces (phi = 0 at Z = 0, phi = Phi at Z = t0), rim face
insulated. The flat state is the saddle point of int Omega dV with the electric enthalpy

    Omega(F, E_L) = W_mech(F) - (eps/2) J C^-1 : (E_L x E_L),   E_L = -Grad phi,

reached by continuation in Phi from 0; v_cr is the first Phi/t0 sqrt(eps/mu_ref) at which
the lowest eigenvalue of the fixed-voltage tangent condensed over the potential,
S = K_uu - K_up K_pp^-1 K_pu, crosses zero in the axisymmetric wavenumber n = 0.
The page's second quantity, v_cr_n1 (wavenumber n = 1), is computed by the sibling clean
room ``buckling_n1`` on these flat states (``critical_voltage`` and
``converged_critical_voltage`` take the film type whose lambda_1 they track).

Units: lengths in t0, stresses in mu_ref, permittivity in eps, so Phi itself is v.

Axisymmetric kinematics in (R, Theta, Z), displacement (u_r(R, Z), 0, u_z(R, Z)):

    F = [[1 + u_r,R, 0, u_r,Z], [0, 1 + u_r/R, 0], [u_z,R, 0, 1 + u_z,Z]]

(the hoop stretch 1 + u_r/R), E_L = -(phi_R, 0, phi_Z), volume element 2 pi R dR dZ (the
2 pi drops out), u_r = 0 on the axis R = 0. For n = 0 the perturbations (U, W, Q) live in
the same space as the flat state (the torsional V decouples and is not part of the cos
family), so S_0 is the Newton tangent itself condensed over the potential.

Derivatives: Omega is a function of the seven numbers g = (u_r,R, u_r,Z, u_r/R, u_z,R,
u_z,Z, phi_R, phi_Z) at each quadrature point; its gradient and Hessian in g are carried
exactly (to round-off) by second-order forward differentiation (``Jet``). The Ogden sum of
the in-plane (R, Z) principal stretches, f(m + d) + f(m - d) with m = tr C_b / 2 and
d^2 = m^2 - det C_b, is even in d: near d = 0 (the undeformed state has repeated
stretches) it is evaluated by its Taylor series in d^2, elsewhere directly, so it is exact
everywhere without regularisation.

Finite elements: Lagrange triangles of order p (scikit-fem ElementTriP2/P3/P4) for u_r,
u_z and phi on a tensor mesh (uniform radially, or graded geometrically towards the rim),
refined ``levels`` times at the two clamped corners (R, Z) = (a, 0), (a, t0), where the
stress is singular; the mesh is mirror-symmetric about the mid-plane, and each Newton
iterate is projected on the mid-plane-symmetric states (the flat state is one; the n = 0
bending mode is not, and without the projection Newton near v_cr slides onto the buckled
branch).

Measured convergence (neo-Hookean, P4 unless said; N x M = radial intervals x layers,
L = corner refinements; CPU per solve on a loaded 2-core machine, one thread):

* the corner singularity dominates. At 16 x 4: L = 6, 9, 12, 15 give 0.2202715702,
  0.2202708466, 0.2202707908, 0.2202707867 (changes 7.2e-7, 5.6e-8, 4.1e-9: a factor
  ~13.5 per three refinements, so L = 15 is converged in L to ~3e-10).
* element shape matters: at fixed L = 6, 40 x 4 gives 0.2202721662, 40 x 8 0.2202710073,
  80 x 4 0.2202787263 (the rim zone's elements 0.05 wide, 0.25 tall), 40 x 4 graded
  (ratio 0.5) 0.2203068015. Only the meshes with square rim-zone elements, N x N/4,
  refine systematically: at L = 6, N = 16, 24, 32, 48 give 0.2202715702, 0.2202712081,
  0.2202710431, 0.2202708923 (rate 1.26 and 1.27 through the two triples, limits
  0.2202706655 and 0.2202706681).
* the converged sequence (converged_critical_voltage: N = 16, 24, 32, 40, L = 15; the
  levels after the first started 1e-5 below the previous v_cr: 12-17 Newton iterations
  instead of the 26-35 of a continuation from v = 0):

  ===========  ==============  ==============  ==============  ==============
  N x N/4      16 x 4          24 x 6          32 x 8          40 x 10
  dofs         6555            10515           16011           23043
  nh_t1        0.2202707867    0.2202707320    0.2202707090    0.2202706970
  CPU s        16              15              31              46
  ogden_t1     0.1471540629    0.1471540236    0.1471540068    0.1471539984
  CPU s        27              36              59              70
  ===========  ==============  ==============  ==============  ==============

  neo-Hookean: rates 1.48 (16, 24, 32) and 1.58 (24, 32, 40), limits 0.2202706655 and
  0.2202706688: v_cr = 0.2202706688 +- 9.9e-9 (3 x the change of the limit);
  Ogden: rates 1.45, 1.68, limits 0.1471539744, 0.1471539798: v_cr = 0.1471539798 +-
  1.6e-8. Total 108 s and 192 s CPU. The rate ~1.5, far below P4's smooth 8, is
  presumably the clamped-free corners' (a singular r^lambda resolved by the elements
  around the refined zone, whose size scales with 1/N at fixed L).
  N = 8 (8 x 2: 0.2202708941, 0.1471541397) is pre-asymptotic (rate 0.25 through 8, 16,
  24). Repeat runs agree to 4e-11 to 1.5e-10 per level (ARPACK's random start vector; root
  tolerance 1e-10 relative) and to 1.4e-9 in the limit: a second run gave 0.2202706674 +-
  7.7e-9 and 0.1471539785 +- 1.3e-8 (268 s CPU for both cases), within the estimates.
* previous measurements (40 radial intervals, L = 6): P2 4 layers 0.2204084, P3 4 layers
  0.2202792, P3 8 layers 0.2202723, P4 4 layers 0.2202722, P4 8 layers 0.2202710 (3.4e-7
  above the converged value; 4 -> 8 layers changes it by 1.2e-6, so no single one of
  these resolves the corners to the reference's 2e-7); P2 40 x 4: 6 -> 10 corner
  refinements moves v_cr by 6.8e-7.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.optimize import brentq
from scipy.spatial import cKDTree
from skfem import (
    Basis,
    BilinearForm,
    ElementTriP2,
    ElementTriP3,
    ElementTriP4,
    LinearForm,
    MeshTri,
    condense,
)

MU_REF = 156000.0
K_BULK = 7748003.92 / MU_REF
ASPECT = 10.0
#: the two cases of the page: Ogden (alpha_p, mu_p / mu_ref) or neo-Hookean mu / mu_ref
OGDEN = ((1.293, 8580.0 / MU_REF), (2.3252, 84300.0 / MU_REF), (2.561, -23300.0 / MU_REF))
CASES = ("nh_t1", "ogden_t1")
ELEMENTS = {2: ElementTriP2, 3: ElementTriP3, 4: ElementTriP4}
#: Ogden in-plane sum: the Taylor series in d^2 is used where d^2 < SERIES_CUT m^2; its
#: terms fall by >= SERIES_CUT per order, so SERIES_TERMS = 12 truncates below 1e-16
SERIES_CUT = 0.04
SERIES_TERMS = 12
#: Newton on the flat state stops when the increment is below this fraction of the
#: solution's size (quadratic convergence: the next step would be ~1e-20)
NEWTON_RTOL = 1e-10
MAX_NEWTON = 25
#: secant / bisection on lambda_1(v) stops when the bracket is this narrow relative to v
ROOT_RTOL = 1e-10
MAX_ROOT = 60
#: LOBPCG residual norms accepted relative to lambda_1(0): the certificate compares the
#: smallest eigenvalue with the tracked one to 1e-6 lambda_1(0)
LOBPCG_RTOL = 1e-5
#: a dof or node lies on a face (R = 0, R = a, Z = 0, Z = 1) within this fraction of the
#: mesh's smallest element height (twice the area over the longest edge): a point off the
#: face is at least that height / p away from it (Lagrange dofs sit at barycentric
#: coordinates k/p, p <= 4), points on it are there to round-off (1e-15 a). No fixed
#: tolerance serves every mesh: graded, corner-refined ones have interior dofs within 1e-5
#: of R = a
FACE_TOL_FRACTION = 1e-3


class Jet:
    """A value with its gradient and Hessian in the seven g components (second-order
    forward differentiation): value (...), grad (7, ...), hess (7, 7, ...)."""

    __slots__ = ("v", "g", "h")

    def __init__(self, v, g, h):
        self.v, self.g, self.h = v, g, h

    @staticmethod
    def seed(values):
        """The seven independent variables g_k = values[k]."""
        n = len(values)
        shape = np.shape(values[0])
        out = []
        for k, val in enumerate(values):
            g = np.zeros((n, *shape))
            g[k] = 1.0
            out.append(Jet(np.asarray(val, dtype=float), g, np.zeros((n, n, *shape))))
        return out

    def _lift(self, other):
        return other if isinstance(other, Jet) else None

    def __add__(self, other):
        o = self._lift(other)
        if o is None:
            return Jet(self.v + other, self.g, self.h)
        return Jet(self.v + o.v, self.g + o.g, self.h + o.h)

    __radd__ = __add__

    def __neg__(self):
        return Jet(-self.v, -self.g, -self.h)

    def __sub__(self, other):
        return self + (-other)

    def __rsub__(self, other):
        return (-self) + other

    def __mul__(self, other):
        o = self._lift(other)
        if o is None:
            return Jet(self.v * other, self.g * other, self.h * other)
        outer = self.g[:, None] * o.g[None, :]
        return Jet(self.v * o.v, self.v * o.g + o.v * self.g,
                   self.v * o.h + o.v * self.h + outer + np.swapaxes(outer, 0, 1))

    __rmul__ = __mul__

    def unary(self, f, f1, f2):
        """f(self) by the chain rule, given f, f' and f'' at self.v."""
        return Jet(f, f1 * self.g, f1 * self.h + f2 * self.g[:, None] * self.g[None, :])

    def __pow__(self, p: float):
        v = self.v
        return self.unary(v**p, p * v ** (p - 1), p * (p - 1) * v ** (p - 2))

    def __truediv__(self, other):
        o = self._lift(other)
        if o is None:
            return self * (1.0 / other)
        return self * o**-1.0

    def where(self, mask, other):
        """self where mask, else other (elementwise)."""
        return Jet(np.where(mask, self.v, other.v), np.where(mask, self.g, other.g),
                   np.where(mask, self.h, other.h))


def _pair_sum(m: Jet, d2: Jet, beta: float) -> Jet:
    """(m + d)^beta + (m - d)^beta, d = sqrt(d2): the sum over the two in-plane principal
    values m +- d of C_b of x^beta, an even function of d, exact near d = 0."""
    small = np.abs(d2.v) < SERIES_CUT * m.v**2
    # series: 2 sum_k beta (beta-1) .. (beta-2k+1)/(2k)! m^(beta-2k) d2^k
    series, coeff, d2k = 2 * m**beta, 2.0, None
    for k in range(1, SERIES_TERMS + 1):
        coeff *= (beta - 2 * k + 2) * (beta - 2 * k + 1) / ((2 * k - 1) * (2 * k))
        d2k = d2 if d2k is None else d2k * d2
        series = series + coeff * (m ** (beta - 2 * k)) * d2k
    # direct: d2 replaced by a safe value where the series is used
    safe = Jet(np.where(small, 0.25 * m.v**2, d2.v), d2.g, d2.h)
    d = safe**0.5
    direct = (m + d) ** beta + (m - d) ** beta
    return series.where(small, direct)


def enthalpy(g: list[Jet], case: str) -> Jet:
    """Omega per mu_ref of the axisymmetric state g = (u_r,R, u_r,Z, u_r/R, u_z,R, u_z,Z,
    phi_R, phi_Z): W_mech (5.15)-(5.17) or (5.26) minus J C^-1 : (E x E)/2 (eq. 5.9 with
    its Legendre transform). With F_b the (R, Z) block of F and F22 the hoop stretch,
    J C^-1 : E x E = F22 |cof(F_b) E|^2 / det F_b."""
    F11, F13, F22, F31, F33 = 1 + g[0], g[1], 1 + g[2], g[3], 1 + g[4]
    e1, e3 = g[5], g[6]
    detb = F11 * F33 - F13 * F31
    J = F22 * detb
    q1 = F33 * e1 - F31 * e3
    q3 = F11 * e3 - F13 * e1
    electric = 0.5 * F22 * (q1 * q1 + q3 * q3) / detb
    volumetric = 0.5 * K_BULK * (J - 1) * (J - 1)
    trb = F11 * F11 + F13 * F13 + F31 * F31 + F33 * F33
    if case == "nh_t1":
        dev = 0.5 * ((J ** (-2.0 / 3.0)) * (trb + F22 * F22) - 3)
    elif case == "ogden_t1":
        m = 0.5 * trb
        d2 = m * m - detb * detb
        dev = 0.0
        for alpha, mu in OGDEN:
            s = F22**alpha + _pair_sum(m, d2, alpha / 2)
            dev = dev + (2 * mu / alpha**2) * ((J ** (-alpha / 3)) * s - 3)
    else:
        raise ValueError(f"case must be one of {CASES}, got {case!r}")
    return dev + volumetric - electric


def mesh(n_r: int, n_z: int, levels: int, ratio: float = 1.0) -> MeshTri:
    """Triangle mesh of [0, a] x [0, 1], mirror-symmetric about the mid-plane Z = 1/2 (so
    the discrete problem keeps the symmetry that separates the flat state from the
    bending mode): the lower half has n_z/2 uniform layers and n_r radial intervals,
    n_r/4 of them over the last thickness before the rim with sizes shrinking by
    ``ratio`` (1: uniform there too), and is refined ``levels`` times at the clamped
    corner (a, 0); the upper half is its mirror image."""
    if n_r < 4 or n_z < 2 or n_z % 2 or levels < 0 or not 0 < ratio <= 1:
        raise ValueError("mesh: need n_r >= 4, even n_z >= 2, levels >= 0, 0 < ratio <= 1")
    # rim zone of width 1 (one thickness): geometric intervals; interior uniform
    n_rim = max(2, n_r // 4)
    w = ratio ** np.arange(n_rim)
    rim = ASPECT - np.concatenate(([0.0], np.cumsum(w[::-1]) / w.sum()))[::-1]
    interior = np.linspace(0.0, ASPECT - 1.0, n_r - n_rim + 1)
    r = np.concatenate((interior, rim[1:]))
    m = MeshTri.init_tensor(r, np.linspace(0.0, 0.5, n_z // 2 + 1))
    for _ in range(levels):
        tol = face_tolerance(m)
        node = np.flatnonzero((np.abs(m.p[0] - ASPECT) <= tol) & (np.abs(m.p[1]) <= tol))
        m = m.refined(np.flatnonzero(np.isin(m.t, node).any(axis=0)))
    return m + m.mirrored((0.0, 1.0), (0.0, 0.5))


def face_tolerance(m: MeshTri) -> float:
    """Distance within which a point is on a face of mesh ``m``: FACE_TOL_FRACTION of its
    smallest element height."""
    p = m.p[:, m.t]                                    # (2, 3 vertices, elements)
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    area = 0.5 * np.abs(e1[0] * e2[1] - e1[1] * e2[0])
    longest = np.max([np.hypot(*(p[:, i] - p[:, j])) for i, j in ((0, 1), (1, 2), (2, 0))],
                     axis=0)
    return FACE_TOL_FRACTION * float(np.min(2.0 * area / longest))


def _component(f, kind: int, R):
    """g-component kinds: 0 d/dR, 1 d/dZ, 2 value/R (the hoop term)."""
    return f.grad[0] if kind == 0 else f.grad[1] if kind == 1 else f / R


#: g index -> (field, kind); fields 0 u_r, 1 u_z, 2 phi
G_MAP = ((0, 0), (0, 1), (0, 2), (1, 0), (1, 1), (2, 0), (2, 1))
FIELD_G = tuple(tuple(k for k, (f, _) in enumerate(G_MAP) if f == a) for a in range(3))


def _block_form(a: int, b: int) -> BilinearForm:
    """int v_a-components . H . u_b-components R dR dZ (test field a, trial field b)."""

    @BilinearForm
    def form(u, v, w):
        # plain arrays: indexing a DiscreteField copies the whole field each time
        R = np.asarray(w.x)[0]
        H = np.asarray(w.H)
        out = 0.0
        for k in FIELD_G[a]:
            vk = _component(v, G_MAP[k][1], R)
            for l in FIELD_G[b]:
                out = out + H[k, l] * vk * _component(u, G_MAP[l][1], R)
        return out * R

    return form


def _residual_form(a: int) -> LinearForm:
    @LinearForm
    def form(v, w):
        R = np.asarray(w.x)[0]
        d = np.asarray(w.dO)
        out = 0.0
        for k in FIELD_G[a]:
            out = out + d[k] * _component(v, G_MAP[k][1], R)
        return out * R

    return form


BLOCKS = {(a, b): _block_form(a, b) for a in range(3) for b in range(a, 3)}
RESIDUALS = tuple(_residual_form(a) for a in range(3))


@BilinearForm
def _mass(u, v, w):
    return u * v * w.x[0]


class Critical:
    """v_cr with its bracket and the certificate of the lower end (the smallest algebraic
    eigenvalue of S_0 there, by LOBPCG), the size and the Newton iterations used."""

    def __init__(self, case, v_cr, bracket, lam_at_bracket, lowest_at_lower, ndofs,
                 newton_iterations):
        self.case, self.v_cr, self.bracket = case, v_cr, bracket
        self.lam_at_bracket, self.lowest_at_lower = lam_at_bracket, lowest_at_lower
        self.ndofs, self.newton_iterations = ndofs, newton_iterations


class Film:
    """The discretised film of one case: flat states by Newton, S_0 and its spectrum."""

    def __init__(self, case: str, order: int = 2, n_r: int = 40, n_z: int = 4,
                 levels: int = 6, ratio: float = 1.0):
        if case not in CASES:
            raise ValueError(f"case must be one of {CASES}, got {case!r}")
        if order not in ELEMENTS:
            raise ValueError(f"order must be one of {sorted(ELEMENTS)}, got {order}")
        self.case = case
        self.mesh = mesh(n_r, n_z, levels, ratio)
        self.basis = Basis(self.mesh, ELEMENTS[order](), intorder=2 * order + 2)
        n = self.basis.N
        self.n = n
        x = self.basis.doflocs
        tol = face_tolerance(self.mesh)
        rim = np.flatnonzero(np.abs(x[0] - ASPECT) <= tol)
        axis = np.flatnonzero(np.abs(x[0]) <= tol)
        self.bottom = np.flatnonzero(np.abs(x[1]) <= tol)
        self.top = np.flatnonzero(np.abs(x[1] - 1.0) <= tol)
        D = np.unique(np.concatenate((rim, axis, n + rim, 2 * n + self.bottom,
                                      2 * n + self.top)))
        self.D = D
        self.free = np.setdiff1d(np.arange(3 * n), D)
        self.free_u = self.free[self.free < 2 * n]
        self.nu = self.free_u.size
        m = _mass.assemble(self.basis)
        self.M = sp.block_diag((m, m)).tocsr()[self.free_u][:, self.free_u]
        self.newton_iterations = 0
        # the mid-plane mirror of every dof: (R, Z) -> (R, 1 - Z)
        tree = cKDTree(x.T)
        dist, self.mirror = tree.query(np.stack((x[0], 1.0 - x[1]), axis=1))
        if np.max(dist) > 1e-9:
            raise RuntimeError("mesh not mirror-symmetric about Z = 1/2")

    def _g(self, x):
        n = self.n
        ur, uz, ph = (self.basis.interpolate(x[i * n:(i + 1) * n]) for i in range(3))
        R = np.asarray(self.basis.global_coordinates())[0]
        fields = (ur, uz, ph)
        return [_component(fields[f], kind, R) for f, kind in G_MAP]

    def assemble(self, x):
        """Tangent K (3n x 3n, symmetric) and residual r of the state x = (u_r, u_z, phi)."""
        om = enthalpy(Jet.seed(self._g(x)), self.case)
        blocks = [[None] * 3 for _ in range(3)]
        for (a, b), form in BLOCKS.items():
            blocks[a][b] = form.assemble(self.basis, H=om.h)
            if a != b:
                blocks[b][a] = blocks[a][b].T
        K = sp.bmat(blocks, format="csr")
        r = np.concatenate([f.assemble(self.basis, dO=om.g) for f in RESIDUALS])
        return K, r

    def initial(self, v: float):
        """The undeformed film with the linear potential v Z."""
        x = np.zeros(3 * self.n)
        x[2 * self.n:] = v * self.basis.doflocs[1]
        return x

    def symmetric(self, x, v: float):
        """The mid-plane-symmetric part of x: u_r(R, Z) even, u_z odd, phi - v/2 odd in
        Z - 1/2 (the flat state is symmetric; the n = 0 bending mode is not)."""
        n, p = self.n, self.mirror
        ur, uz, ph = x[:n], x[n:2 * n], x[2 * n:]
        return np.concatenate((0.5 * (ur + ur[p]), 0.5 * (uz - uz[p]),
                               0.5 * (ph + v - ph[p])))

    def flat_state(self, v: float, x0):
        """Newton from x0 (its Dirichlet values reset to the voltage v), each iterate
        projected on the symmetric states; raises if not converged. Returns the state and
        its tangent K."""
        x = x0.copy()
        n = self.n
        x[self.D[self.D < 2 * n]] = 0.0
        x[2 * n + self.bottom] = 0.0
        x[2 * n + self.top] = v
        for _ in range(MAX_NEWTON):
            K, r = self.assemble(x)
            dx = np.zeros_like(x)
            dx[self.free] = spla.spsolve(*condense(K, -r, D=self.D)[:2])
            x, x_old = self.symmetric(x + dx, v), x
            self.newton_iterations += 1
            if np.max(np.abs(x - x_old)) <= NEWTON_RTOL * max(1.0, np.max(np.abs(x))):
                K, _ = self.assemble(x)
                return x, K
        raise RuntimeError(f"Newton did not converge at v = {v} in {MAX_NEWTON} steps")

    def _free(self, K):
        """The free block of K (displacements first) and the number of displacements."""
        return K[self.free][:, self.free].tocsc(), self.nu

    def lowest(self, K, k: int = 3) -> float:
        """The eigenvalue of S_0 x = lambda M x nearest zero (shift-invert at 0)."""
        w = condensed_eigenvalues(*self._free(K), self.M, k)
        return float(w[np.argmin(np.abs(w))])

    def smallest_algebraic(self, K, shift: float, k: int = 3) -> np.ndarray:
        """The k smallest algebraic eigenvalues of S_0 x = lambda M x
        (``smallest_condensed``): the certificate that none lies below the tracked one."""
        return smallest_condensed(*self._free(K), self.M, shift, k)

    def lowest_at(self, x, K) -> float:
        """lambda_1 tracked by ``critical_voltage`` at the flat state x with tangent K."""
        return self.lowest(K)

    def smallest_algebraic_at(self, x, K, shift: float) -> np.ndarray:
        """The certificate of ``critical_voltage`` at the flat state x with tangent K."""
        return self.smallest_algebraic(K, shift)


def condensed_operators(Kf, nu: int, M, shift: float = 0.0):
    """S = K_uu - K_up K_pp^-1 K_pu of the symmetric free block Kf (its first nu dofs the
    displacements u, the rest the potential p) as an operator on u, and (S + shift M)^-1
    (one solve with Kf, the shift on K_uu)."""
    Kf = Kf.tocsc()
    nf = Kf.shape[0]
    Kuu, Kup = Kf[:nu, :nu], Kf[:nu, nu:]
    Kpp = spla.splu(Kf[nu:, nu:].tocsc())
    lu = spla.splu((Kf + shift * sp.block_diag((M, sp.csc_matrix((nf - nu, nf - nu))))
                    ).tocsc()) if shift else spla.splu(Kf)

    def s_mv(y):
        y = np.asarray(y).reshape(nu, -1)
        return Kuu @ y - Kup @ Kpp.solve(np.asarray(Kup.T @ y))

    def s_inv(y):
        y = np.asarray(y).reshape(nu, -1)
        rhs = np.zeros((nf, y.shape[1]))
        rhs[:nu] = y
        return lu.solve(rhs)[:nu]

    S = spla.LinearOperator((nu, nu), matvec=s_mv, matmat=s_mv, dtype=float)
    Sinv = spla.LinearOperator((nu, nu), matvec=s_inv, matmat=s_inv, dtype=float)
    return S, Sinv


def condensed_eigenvalues(Kf, nu: int, M, k: int = 3) -> np.ndarray:
    """The k eigenvalues of S x = lambda M x nearest zero (``condensed_operators``;
    shift-invert at 0, ARPACK to 1e-13)."""
    S, Sinv = condensed_operators(Kf, nu, M)
    return spla.eigsh(S, k=k, M=M, sigma=0.0, OPinv=Sinv, which="LM",
                      return_eigenvectors=False, tol=1e-13)


def smallest_condensed(Kf, nu: int, M, shift: float, k: int = 3) -> np.ndarray:
    """The k smallest algebraic eigenvalues of S x = lambda M x (LOBPCG, whose
    smallest-first search does not depend on a shift, preconditioned by (S + shift M)^-1,
    shift > 0 of the order of the eigenvalues), sorted; raises unless the smallest
    converged to LOBPCG_RTOL shift."""
    S, T = condensed_operators(Kf, nu, M, shift)
    X = np.random.default_rng(0).standard_normal((nu, k))
    w, _, res = spla.lobpcg(S, X, B=M, M=T, largest=False,
                            tol=0.1 * LOBPCG_RTOL * shift, maxiter=200,
                            retResidualNormsHistory=True)
    first = int(np.argmin(w))  # only the smallest must converge; the rest help
    if not np.all(np.isfinite(w)) or res[-1][first] > LOBPCG_RTOL * shift:
        raise RuntimeError(f"LOBPCG did not converge (residuals {res[-1]})")
    return np.sort(w)


def critical_voltage(case: str, order: int = 2, n_r: int = 40, n_z: int = 4,
                     levels: int = 6, ratio: float = 1.0, v_step: float = 0.05,
                     v_max: float = 0.6, v_start: float = 0.0,
                     film_type: type = Film) -> Critical:
    """v_cr of ``case`` on one discretisation: continuation in v from 0 by v_step until
    lambda_1 of S_0 changes sign (``film_type``: Film, or a subclass tracking another
    wavenumber's lambda_1 by its ``lowest_at`` and ``smallest_algebraic_at``), then the
    Illinois variant of regula falsi on lambda_1(v) (each evaluation a Newton solve from
    the nearer bracket end) until the
    bracket is ROOT_RTOL narrow; the lower end certified by LOBPCG.

    v_start > 0 (e.g. just below a coarser discretisation's v_cr): the continuation goes
    from v = 0 straight to v_start (Newton from the undeformed film) and steps by v_step
    from there; lambda_1 must be positive at v_start. The lower bracket end's certificate
    (no eigenvalue of S_0 below the tracked positive one) holds as without it."""
    film = film_type(case, order, n_r, n_z, levels, ratio)

    def solve(v, near):
        """Newton at v from the state near = (v', x', ...), its potential scaled by v/v'."""
        guess = near[1].copy() if near[0] > 0 else film.initial(v)
        if near[0] > 0:
            guess[2 * film.n:] *= v / near[0]
        x, K = film.flat_state(v, guess)
        return v, x, film.lowest_at(x, K)

    lo = solve(0.0, (0.0, None))
    if not lo[2] > 0:
        raise RuntimeError(f"S_0 not positive definite at v = 0 (lambda_1 = {lo[2]})")
    l_zero = lo[2]
    if v_start > 0:
        lo = solve(v_start, lo)
        if not lo[2] > 0:
            raise RuntimeError(f"lambda_1 = {lo[2]} not positive at v_start = {v_start}")
    while True:
        if lo[0] + v_step > v_max:
            raise RuntimeError(f"no sign change of lambda_1 up to v_max = {v_max}")
        hi = solve(lo[0] + v_step, lo)
        if hi[2] <= 0:
            break
        lo = hi
    # Illinois: the end kept twice in a row has its value halved in the secant
    fl, fh, last = lo[2], hi[2], 0
    for _ in range(MAX_ROOT):
        if hi[0] - lo[0] <= ROOT_RTOL * hi[0]:
            break
        width = hi[0] - lo[0]
        v = lo[0] - fl * width / (fh - fl)
        v = min(max(v, lo[0] + 1e-3 * width), hi[0] - 1e-3 * width)
        new = solve(v, lo if v - lo[0] < hi[0] - v else hi)
        if new[2] > 0:
            lo, fl = new, new[2]
            fh = fh * 0.5 if last == 1 else fh
            last = 1
        else:
            hi, fh = new, new[2]
            fl = fl * 0.5 if last == -1 else fl
            last = -1
    else:
        raise RuntimeError(f"root of lambda_1 not bracketed to {ROOT_RTOL} in {MAX_ROOT}")
    # the crossing inside the final bracket by the secant
    v_cr = lo[0] - lo[2] * (hi[0] - lo[0]) / (hi[2] - lo[2])
    # certificate: at the lower end, S_0's smallest algebraic eigenvalue is the tracked
    # one (nothing crossed unseen); its scale is lambda_1 at v = 0
    x_lo, K_lo = film.flat_state(lo[0], lo[1])
    low = film.smallest_algebraic_at(x_lo, K_lo, shift=l_zero)
    if not abs(low[0] - lo[2]) <= 1e-6 * l_zero:
        raise RuntimeError(f"lower bracket end not certified: smallest eigenvalue {low[0]}, "
                           f"tracked {lo[2]}")
    return Critical(case, float(v_cr), (lo[0], hi[0]), (lo[2], hi[2]), float(low[0]),
                    int(3 * film.n), film.newton_iterations)


#: the converged sequence (module docstring): order CONVERGED_ORDER on the meshes of N
#: radial intervals and N/4 layers (n_r = N, n_z = N/4: the rim zone's elements are
#: square), each refined CONVERGED_LEVELS times at both clamped corners, N in
#: CONVERGED_SIZES; the levels are converged in the corner refinements (at N = 16 the
#: refinements 9 -> 12 -> 15 move v_cr by 5.6e-8, then 4.1e-9: a factor 13.5 per three)
CONVERGED_ORDER = 4
CONVERGED_SIZES = (16, 24, 32, 40)
CONVERGED_LEVELS = 15
#: Roache's safety factor for an estimate not established by many grids (3)
CONVERGED_SAFETY = 3.0


def richardson(sizes, values) -> tuple[float, float]:
    """(rate r, limit v_inf) of v(N) = v_inf + C N^-r through three (N, v), N increasing;
    raises unless the two changes have one sign (monotone convergence)."""
    (n1, n2, n3), (v1, v2, v3) = sizes, values
    d1, d2 = v1 - v2, v2 - v3
    if not d1 * d2 > 0:
        raise RuntimeError(f"not monotone: {values} at N = {sizes}")
    q = d1 / d2

    def excess(r):
        return (n1**-r - n2**-r) / (n2**-r - n3**-r) - q

    rate = brentq(excess, 1e-3, 50.0)
    return float(rate), float(v3 - d2 * n3**-rate / (n2**-rate - n3**-rate))


class Converged:
    """The converged v_cr (Richardson limit of the last three levels) and its error
    estimate; the levels' values, and the rate and limit of each consecutive triple."""

    def __init__(self, case, sizes, values, fits, value, error):
        self.case, self.sizes, self.values, self.fits = case, sizes, values, fits
        self.value, self.error = value, error


def converged_critical_voltage(case: str, sizes=CONVERGED_SIZES,
                               levels: int = CONVERGED_LEVELS,
                               order: int = CONVERGED_ORDER,
                               film_type: type = Film) -> Converged:
    """v_cr of ``case`` extrapolated over the meshes N x N/4 (N in sizes, at least four):
    v(N) = v_inf + C N^-r fitted through each consecutive three levels; the value is the
    last triple's limit, its error estimate CONVERGED_SAFETY times the larger of the change
    of the limit from the previous triple and the change of the last limit when the
    previous triple's rate is used. Each level's continuation starts 1e-5 below the
    previous level's v_cr (their differences are < 1e-6). ``film_type`` as in
    ``critical_voltage``."""
    if len(sizes) < 4 or any(n % 8 for n in sizes):
        raise ValueError("converged: need >= 4 sizes, each a multiple of 8 (even n_z = N/4)")
    values = []
    for n in sizes:
        start = ({"v_start": values[-1] - 1e-5, "v_step": 2e-5, "v_max": values[-1] + 1e-3}
                 if values else {})
        values.append(critical_voltage(case, order, n, n // 4, levels, film_type=film_type,
                                       **start).v_cr)
    fits = [richardson(sizes[i:i + 3], values[i:i + 3]) for i in range(len(sizes) - 2)]
    (r_prev, v_prev), v_last = fits[-2], fits[-1][1]
    n2, n3 = sizes[-2], sizes[-1]
    d2 = values[-2] - values[-1]
    v_other_rate = values[-1] - d2 * n3**-r_prev / (n2**-r_prev - n3**-r_prev)
    error = CONVERGED_SAFETY * max(abs(v_last - v_prev), abs(v_last - v_other_rate))
    return Converged(case, tuple(sizes), values, fits, v_last, float(error))
