"""Clean-room lit_bilayer, written from its ``debench problems lit_bilayer --markdown`` page
only (numpy, scipy and scikit-fem; nothing from debench).

The page: a plane-strain strip 0 <= X <= L = 10 H, 0 <= Y <= H, a passive layer
0 <= Y <= H/2 and an active one H/2 <= Y <= H, both the compressible neo-Hookean
mu/2 (J^(-2/3) I1 - 3) + k/2 (J - 1)^2 (k/mu = 7748003.92/156000), the active layer an ideal
dielectric between the electrodes Y = H/2 (phi = 0) and Y = H (phi = Phi); the end X = 0 a
sliding clamp (u_X = 0) with u_Y = 0 at (0, H/2); everything else traction free and
insulated. Units: lengths in H, stresses in mu, potentials in H sqrt(mu/eps), so the top
potential is v/2 with v = (Phi/h_a) sqrt(eps/mu), h_a = H/2.

Weak form (my own derivation). With the in-plane block F = [[1 + ux_X, ux_Y],
[uy_X, 1 + uy_Y]] (F_33 = 1), J = det F, I1 = |F|^2 + 1 and the referential field
E = -Grad phi, the electric enthalpy per reference area is

    Omega = 1/2 (J^(-2/3) I1 - 3) + k/2 (J - 1)^2 - 1/2 J |F^-T Grad phi|^2

(the last term only in the active layer; the passive layer is grounded on both faces, so
phi = 0 there and including it changes nothing). Its gradient in
g = (ux_X, ux_Y, uy_X, uy_Y, phi_X, phi_Y):

    dOmega/dF = J^(-2/3) (F - I1/3 F^-T) + k (J - 1) J F^-T
                - 1/2 J |e|^2 F^-T + J e (x) (F^-1 e),      e = F^-T Grad phi,
    dOmega/dGrad phi = -J F^-1 e,

and its Hessian by complex-step differentiation of this gradient (exact to round-off:
every operation is analytic). Newton on the saddle point (min in u, max in phi) with a
backtracking line search on the residual norm; continuation in v in steps of 0.025.

Finite elements: Lagrange triangles P_p (scikit-fem ElementTriP2..P4) for ux, uy and phi on
a tensor mesh (each rectangle cut in two), ``nx`` columns and ``ny`` rows per layer,
the column at X = L and the rows at the interface graded geometrically ``levels`` times by
0.2 (the free end of the interface, where the active layer's Maxwell stress meets the
passive layer, is the one singular point).

Outputs: w = u_Y(L, 0) (the bottom corner of the free end) and
theta = atan2(-(dx), H + dy) with (dx, dy) = u(L, H) - u(L, 0).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from skfem import Basis, BilinearForm, ElementTriP2, ElementTriP3, ElementTriP4, LinearForm, MeshTri

LENGTH = 10.0
PASSIVE = 0.5
KAPPA = 7748003.92 / 156000.0
GRADING = 0.2
STEP = 0.025
NEWTON_RTOL = 1e-10
NEWTON_ATOL = 1e-12
NEWTON_STOL = 1e-12  # a Newton update this small (relative) is converged
MAX_NEWTON = 40
HALVINGS = 12
CS = 1e-30  # complex step
ELEMENTS = {2: ElementTriP2, 3: ElementTriP3, 4: ElementTriP4}


def _graded(lo, hi, n, levels, at_lo, at_hi):
    x = np.linspace(lo, hi, n + 1)
    h = (hi - lo) / n
    inner = h * GRADING ** np.arange(levels, 0, -1)
    parts = [x] + ([lo + inner] if at_lo else []) + ([hi - inner] if at_hi else [])
    return np.unique(np.concatenate(parts))


def mesh(nx: int = 20, ny: int = 2, levels: int = 2) -> MeshTri:
    xs = _graded(0.0, LENGTH, nx, levels, False, True)
    ys = np.concatenate([_graded(0.0, PASSIVE, ny, levels, False, True),
                         _graded(PASSIVE, 1.0, ny, levels, True, False)[1:]])
    return MeshTri.init_tensor(xs, ys)


def gradient(g, active):
    """dOmega/dg at the quadrature points: g has shape (6, ...), active a 0/1 array."""
    a, b, c, d, px, py = g
    F11, F12, F21, F22 = 1 + a, b, c, 1 + d
    J = F11 * F22 - F12 * F21
    # F^-T = [[F22, -F21], [-F12, F11]] / J
    iT11, iT12, iT21, iT22 = F22 / J, -F21 / J, -F12 / J, F11 / J
    I1 = F11**2 + F12**2 + F21**2 + F22**2 + 1.0
    Jm = J ** (-2.0 / 3.0)
    Pm = [Jm * (F - I1 / 3.0 * iT) + KAPPA * (J - 1.0) * J * iT
          for F, iT in ((F11, iT11), (F12, iT12), (F21, iT21), (F22, iT22))]
    e1 = iT11 * px + iT12 * py
    e2 = iT21 * px + iT22 * py
    # F^-1 e = (F^-T)^T e
    f1 = iT11 * e1 + iT21 * e2
    f2 = iT12 * e1 + iT22 * e2
    ee = e1 * e1 + e2 * e2
    Pe = [-0.5 * J * ee * iT11 + J * e1 * f1, -0.5 * J * ee * iT12 + J * e1 * f2,
          -0.5 * J * ee * iT21 + J * e2 * f1, -0.5 * J * ee * iT22 + J * e2 * f2]
    out = [Pm[i] + active * Pe[i] for i in range(4)]
    out += [active * (-J * f1), active * (-J * f2)]
    return np.array(out)


def hessian(g, active):
    """d2Omega/dg2 by complex step of :func:`gradient` (exact to round-off)."""
    H = np.empty((6,) + g.shape)
    for k in range(6):
        gc = g.astype(complex)
        gc[k] = gc[k] + 1j * CS
        H[:, k] = gradient(gc, active).imag / CS
    return H


#: the g-components of each field: 0 ux, 1 uy, 2 phi -> (g index, derivative direction)
FIELD_G = (((0, 0), (1, 1)), ((2, 0), (3, 1)), ((4, 0), (5, 1)))


def _block(a, b):
    @BilinearForm
    def form(u, v, w):
        H = np.asarray(w.H)
        out = 0.0
        for k, dk in FIELD_G[a]:
            for l, dl in FIELD_G[b]:
                out = out + H[k, l] * v.grad[dk] * u.grad[dl]
        return out
    return form


def _res(a):
    @LinearForm
    def form(v, w):
        G = np.asarray(w.G)
        return sum(G[k] * v.grad[dk] for k, dk in FIELD_G[a])
    return form


BLOCKS = {(a, b): _block(a, b) for a in range(3) for b in range(a, 3)}
RESIDUALS = tuple(_res(a) for a in range(3))


class Result:
    """Tip values at each voltage of one discretisation, its size and Newton count."""

    def __init__(self, order, levels, voltages, tip_deflection, tip_rotation, ndofs,
                 newton_iterations):
        self.order, self.levels, self.voltages = order, levels, voltages
        self.tip_deflection, self.tip_rotation = tip_deflection, tip_rotation
        self.ndofs, self.newton_iterations = ndofs, newton_iterations


class Strip:
    def __init__(self, order=3, nx=20, ny=2, levels=2):
        self.order, self.levels = order, levels
        self.mesh = mesh(nx, ny, levels)
        self.basis = Basis(self.mesh, ELEMENTS[order](), intorder=2 * order)
        n = self.n = self.basis.N
        x = self.basis.doflocs
        tol = 1e-9
        clamp = np.flatnonzero(np.abs(x[0]) < tol)
        pin = np.flatnonzero((np.abs(x[0]) < tol) & (np.abs(x[1] - PASSIVE) < tol))
        self.top = np.flatnonzero(np.abs(x[1] - 1.0) < tol)
        grounded = np.flatnonzero(x[1] < PASSIVE + tol)  # interface and passive layer
        assert pin.size == 1
        self.D = np.unique(np.concatenate([clamp, n + pin, 2 * n + grounded,
                                           2 * n + self.top]))
        self.free = np.setdiff1d(np.arange(3 * n), self.D)
        mid = np.asarray(self.basis.global_coordinates())[1]
        # the active layer: elements above the interface (its quadrature points)
        self.active = (mid.mean(axis=1, keepdims=True) > PASSIVE).astype(float) \
            * np.ones_like(mid)
        self.tip_bot = int(np.flatnonzero((np.abs(x[0] - LENGTH) < tol)
                                          & (np.abs(x[1]) < tol))[0])
        self.tip_top = int(np.flatnonzero((np.abs(x[0] - LENGTH) < tol)
                                          & (np.abs(x[1] - 1.0) < tol))[0])
        self.iterations = 0

    def _g(self, x):
        n = self.n
        f = [self.basis.interpolate(x[i * n:(i + 1) * n]) for i in range(3)]
        return np.array([f[0].grad[0], f[0].grad[1], f[1].grad[0], f[1].grad[1],
                         f[2].grad[0], f[2].grad[1]])

    def residual(self, x):
        G = gradient(self._g(x), self.active)
        return np.concatenate([r.assemble(self.basis, G=G) for r in RESIDUALS])

    def tangent(self, x):
        H = hessian(self._g(x), self.active)
        blocks = [[None] * 3 for _ in range(3)]
        for (a, b), form in BLOCKS.items():
            blocks[a][b] = form.assemble(self.basis, H=H)
            if a != b:
                blocks[b][a] = blocks[a][b].T
        return sp.bmat(blocks, format="csc")

    def equilibrium(self, x, v):
        x = x.copy()
        x[2 * self.n + self.top] = v * (1.0 - PASSIVE)
        f = self.free
        r = self.residual(x)
        r0 = rn = np.linalg.norm(r[f])
        for _ in range(MAX_NEWTON):
            if rn <= max(NEWTON_RTOL * r0, NEWTON_ATOL):
                return x
            K = self.tangent(x)
            dx = spla.spsolve(K[f][:, f], r[f])
            self.iterations += 1
            if np.max(np.abs(dx)) <= NEWTON_STOL * max(1.0, np.max(np.abs(x))):
                # the update is at round-off: converged (the residual's own floor)
                x[f] -= dx
                return x
            alpha = 1.0
            for _ in range(HALVINGS + 1):
                trial = x.copy()
                trial[f] -= alpha * dx
                with np.errstate(all="ignore"):
                    rt = self.residual(trial)
                rtn = np.linalg.norm(rt[f])
                if np.isfinite(rtn) and rtn < rn:
                    break
                alpha *= 0.5
            else:
                raise RuntimeError(f"no residual decrease at v = {v}")
            x, r, rn = trial, rt, rtn
        raise RuntimeError(f"Newton did not converge at v = {v} (residual {rn:.3e})")

    def tip(self, x):
        n = self.n
        ux, uy = x[:n], x[n:2 * n]
        dx = ux[self.tip_top] - ux[self.tip_bot]
        dy = 1.0 + uy[self.tip_top] - uy[self.tip_bot]
        return float(uy[self.tip_bot]), float(np.arctan2(-dx, dy))


def solve(voltages, order=3, nx=20, ny=2, levels=2) -> Result:
    s = Strip(order, nx, ny, levels)
    path, marks, v0 = [], [], 0.0
    for v in voltages:
        k = max(1, int(np.ceil((v - v0) / STEP - 1e-12)))
        path += list(np.linspace(v0, v, k + 1)[1:])
        marks.append(len(path) - 1)
        v0 = v
    x_prev = x = np.zeros(3 * s.n)
    v_prev = v_last = 0.0
    out = []
    for i, v in enumerate(path):
        # linear extrapolation of the last two states
        guess = x if i == 0 else x + (x - x_prev) * (v - v_last) / (v_last - v_prev)
        x_new = s.equilibrium(guess, v)
        x_prev, x, v_prev, v_last = x, x_new, v_last, v
        if i in marks:
            out.append(s.tip(x))
    out = np.array(out)
    return Result(order, levels, np.asarray(voltages, float), out[:, 0], out[:, 1],
                  int(s.free.size), s.iterations)
