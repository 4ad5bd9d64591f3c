"""Clean-room lit_bilayer on quadrilaterals of high order: the enthalpy, its gradient and
its complex-step Hessian of :mod:`verification.cleanroom.bilayer` (derived there from the
``debench problems lit_bilayer --markdown`` page), discretised by scikit-fem's hierarchical
tensor-product elements ``ElementQuadP(p)`` (integrated-Legendre edge and interior modes,
any p) on a graded tensor mesh of quadrilaterals. Nothing from debench.

Mesh: ``nx`` uniform columns on 0 <= X <= L and ``ny`` uniform rows per layer; the column
at the free end X = L and the two rows at the interface Y = 1/2 are each cut ``levels``
times geometrically by ``ratio`` towards the free end and the interface, so the elements
shrink geometrically towards the one singular point (L, 1/2), where the active layer's
Maxwell stress ends. With p raised on such a mesh (an hp mesh) the tip values converge
exponentially; the error is estimated from the p-sequence and from the grading sequence
(:func:`estimate`).

Assembly is the clean room's own (no scikit-fem forms): the element matrices
K_e = sum_q w_q B_q^T H_q B_q of all three fields (ux, uy, phi) as batched matrix products
of the basis gradients at the quadrature points, ``intorder`` (default 2 p + 4) the
degree of the tensor Gauss rule; the Dirichlet data (u_X = 0 on X = 0, u_Y = 0 at
(0, 1/2), phi = 0 in the passive layer and on the interface, phi = v/2 on Y = 1) are
exact in this basis (constants: the vertex modes carry them, the edge modes vanish).
Newton on the saddle point with a backtracking line search on the residual norm,
continuation in v in steps of ``STEP`` from the last two states extrapolated (linearly in
v^2: the load is quadratic in v); the tip
values are vertex modes (the edge and interior modes vanish at the vertices).

Convergence (all six voltages v = 0.05 .. 0.3; 12 x 2 per layer, 2 geometric layers of
ratio 0.15, quadrature degree 2p + 4 unless stated; the largest |value - reference| /
the reference's stated error over the voltages (dataset lit_bilayer, *_error; the stated
accuracy adds 1e-9 to it, so these ratios are slightly above those of ``debench check``),
w/H then theta; CPU seconds of one single-threaded process):

    discretisation                 dofs    w/H     theta   CPU
    Q5                             7129    2.9     4.0     13 s
    Q6                            10235    0.035   0.21    25 s
    Q7                            13901    0.24    0.087   41 s
    Q8                            18127    0.27    0.038   61 s
    Q8, quadrature degree 24      18127    0.27    0.038   66 s
    Q8, 1 geometric layer         12655    0.22    0.035   34 s
    Q8, 3 geometric layers        24239    0.27    0.037   95 s
    Q8, 3 layers of ratio 0.25    24239    0.26    0.032   95 s
    Q7, 18 x 2                    19823    0.21    0.054   57 s
    Q8, 18 x 2                    25855    0.26    0.030   83 s
    Q8, 12 x 3                    22631    0.27    0.001   89 s
    Q7, 18 x 3, 3 layers of 0.25  31142    0.27    0.019  105 s

Changes of Q8 on 12 x 2 (|difference| at v = 0.05 .. 0.3):

    w/H    p-step Q8 - Q7           7.9e-11 .. 1.1e-8
           grading, 1 -> 2 layers   4.2e-10 .. 2.4e-8
           grading, 2 -> 3 layers   1.1e-13 .. 2.6e-10
           18 x 2 - 12 x 2          9.1e-11 .. 1.9e-9
           12 x 3 - 12 x 2          9.6e-11 .. 2.4e-9
           quadrature 24 - 20       < 2e-13
    theta  p-step Q8 - Q7           1.2e-9  .. 4.3e-8
           grading, 1 -> 2 layers   1.5e-10 .. 2.0e-9
           grading, 2 -> 3 layers   4.6e-14 .. 1.0e-10
           18 x 2 - 12 x 2          2.1e-10 .. 8.4e-9
           12 x 3 - 12 x 2          9.4e-10 .. 3.5e-8
           quadrature 24 - 20       < 2e-13

Its own error estimate, per voltage 3 x the larger of the p-step and the grading step
1 -> 2 layers: 1.2e-9 .. 7.3e-8 in w/H and 3.6e-9 .. 1.3e-7 in theta, at most 0.14 and
0.15 of the reference's stated error. The refinements beyond it (3 layers, ratio 0.25,
18 columns, 3 rows per layer) move Q8 by at most 0.27 of that estimate (theta, 3 rows).
"""

from __future__ import annotations

import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from skfem import Basis, ElementQuadP, MeshQuad

from .bilayer import LENGTH, PASSIVE, gradient, hessian

#: continuation step in v (the states between the stored voltages)
STEP = 0.025
#: Newton stops when its update is this small (max norm; the tip values are O(1) and the
#: iteration converges quadratically, so the error left is ~ its square, far below 1e-10)
NEWTON_STEP_TOL = 1e-11
MAX_NEWTON = 40
#: an update below this is taken in full even when the residual does not decrease (it is
#: then at its round-off floor, ~1e-13 measured): Newton's last updates were measured at
#: 3e-8 .. 4e-7 (residual 1e-9 .. 1e-7), then 1e-15 .. 1e-12; a larger update must decrease it
ROUNDOFF_STEP = 1e-8
HALVINGS = 12
#: the stored voltages of the problem
VOLTAGES = (0.05, 0.1, 0.15, 0.2, 0.25, 0.3)


def _graded(lo, hi, n, levels, ratio, at_lo, at_hi):
    x = np.linspace(lo, hi, n + 1)
    h = (hi - lo) / n
    inner = h * ratio ** np.arange(levels, 0, -1)
    parts = [x] + ([lo + inner] if at_lo else []) + ([hi - inner] if at_hi else [])
    return np.unique(np.concatenate(parts))


def mesh(nx: int, ny: int, levels: int, ratio: float) -> MeshQuad:
    """The graded tensor mesh of quadrilaterals (see the module docstring)."""
    xs = _graded(0.0, LENGTH, nx, levels, ratio, False, True)
    ys = np.concatenate([_graded(0.0, PASSIVE, ny, levels, ratio, False, True),
                         _graded(PASSIVE, 1.0, ny, levels, ratio, True, False)[1:]])
    return MeshQuad.init_tensor(xs, ys)


class Result:
    """Tip values at each voltage of one discretisation, its size, Newton count and CPU."""

    def __init__(self, disc, voltages, tip_deflection, tip_rotation, ndofs, iterations, cpu):
        self.disc, self.voltages = disc, np.asarray(voltages, float)
        self.tip_deflection, self.tip_rotation = tip_deflection, tip_rotation
        self.ndofs, self.newton_iterations, self.cpu_seconds = ndofs, iterations, cpu


class Strip:
    def __init__(self, order=6, nx=12, ny=2, levels=3, ratio=0.15, intorder=None):
        self.mesh = m = mesh(nx, ny, levels, ratio)
        self.basis = b = Basis(m, ElementQuadP(order),
                               intorder=2 * order + 4 if intorder is None else intorder)
        n = self.n = b.N
        nb = b.Nbfun
        # basis gradients at the quadrature points: (elements, 2 * points, basis functions)
        g = np.array([b.basis[i][0].grad for i in range(nb)])   # (nb, 2, nel, nq)
        self.w = np.asarray(b.dx)                                 # (nel, nq)
        self.dphi = g                                             # (nb, 2, nel, nq)
        self.edofs = b.element_dofs.T                             # (nel, nb)
        nel = self.edofs.shape[0]
        mid = m.p[:, m.t].mean(axis=1)
        act = (mid[1] > PASSIVE).astype(float)
        self.active = act[:, None] * np.ones_like(self.w)
        # the global indices of the 3 x 3 field blocks of every element matrix
        full = np.concatenate([self.edofs + k * n for k in range(3)], axis=1)  # (nel, 3nb)
        self.rows = np.repeat(full[:, :, None], 3 * nb, axis=2).ravel()
        self.cols = np.repeat(full[:, None, :], 3 * nb, axis=1).ravel()
        self.full = full
        tol = 1e-9
        clamp = b.get_dofs(m.facets_satisfying(lambda x: np.abs(x[0]) < tol)).all()
        node = np.flatnonzero((np.abs(m.p[0]) < tol) & (np.abs(m.p[1] - PASSIVE) < tol))
        assert node.size == 1
        pin = b.nodal_dofs[0, node]
        top_f = m.facets_satisfying(lambda x: np.abs(x[1] - 1.0) < tol)
        top = b.get_dofs(top_f).all()
        top_nodes = np.unique(m.facets[:, top_f])
        self.top_vertex = b.nodal_dofs[0, top_nodes]
        grounded = np.unique(self.edofs[act == 0.0])   # passive elements, interface included
        self.D = np.unique(np.concatenate([clamp, n + pin, 2 * n + grounded, 2 * n + top]))
        self.free = np.setdiff1d(np.arange(3 * n), self.D)
        corner = [np.flatnonzero((np.abs(m.p[0] - LENGTH) < tol) & (np.abs(m.p[1] - y) < tol))
                  for y in (0.0, 1.0)]
        self.tip_bot, self.tip_top = (int(b.nodal_dofs[0, c[0]]) for c in corner)
        self.iterations = 0
        self.nel = nel

    def _g(self, x):
        """(ux_X, ux_Y, uy_X, uy_Y, phi_X, phi_Y) at the quadrature points."""
        out = []
        for k in range(3):
            xe = x[k * self.n:(k + 1) * self.n][self.edofs]            # (nel, nb)
            out.append(np.einsum("ideq,ei->deq", self.dphi, xe))
        return np.concatenate(out)                                      # (6, nel, nq)

    def residual(self, x):
        G = gradient(self._g(x), self.active) * self.w                 # (6, nel, nq)
        r = np.zeros(3 * self.n)
        for k in range(3):
            re = np.einsum("deq,ideq->ei", G[2 * k:2 * k + 2], self.dphi)
            np.add.at(r, self.edofs + k * self.n, re)
        return r

    def tangent(self, x):
        H = hessian(self._g(x), self.active) * self.w                  # (6, 6, nel, nq)
        nb, nel, nq = self.dphi.shape[0], self.nel, self.w.shape[1]
        B = self.dphi.transpose(2, 1, 3, 0).reshape(nel, 2 * nq, nb)  # rows: (d, q)
        Ke = np.empty((nel, 3 * nb, 3 * nb))
        for a in range(3):
            for c in range(a, 3):
                Hac = H[2 * a:2 * a + 2, 2 * c:2 * c + 2]               # (2, 2, nel, nq)
                # (H B_c)[e, (d, q), j] = sum_l H[d, l, e, q] B_c[e, (l, q), j]
                Bc = B.reshape(nel, 2, nq, nb)
                HB = np.einsum("dleq,elqj->edqj", Hac, Bc).reshape(nel, 2 * nq, nb)
                blk = np.matmul(B.transpose(0, 2, 1), HB)               # (nel, nb, nb)
                Ke[:, a * nb:(a + 1) * nb, c * nb:(c + 1) * nb] = blk
                if a != c:
                    Ke[:, c * nb:(c + 1) * nb, a * nb:(a + 1) * nb] = blk.transpose(0, 2, 1)
        N = 3 * self.n
        return sp.csc_matrix((Ke.ravel(), (self.rows, self.cols)), shape=(N, N))

    def equilibrium(self, x, v):
        x = x.copy()
        x[2 * self.n + self.top_vertex] = v * (1.0 - PASSIVE)
        f = self.free
        r = self.residual(x)
        rn = np.linalg.norm(r[f])
        for _ in range(MAX_NEWTON):
            K = self.tangent(x)
            dx = spla.splu(K[f][:, f], permc_spec="MMD_AT_PLUS_A",
                            diag_pivot_thresh=0.0).solve(r[f])
            self.iterations += 1
            if np.max(np.abs(dx)) <= NEWTON_STEP_TOL:
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
                if np.max(np.abs(dx)) > ROUNDOFF_STEP:
                    raise RuntimeError(f"no residual decrease at v = {v}")
                # the residual is at its round-off floor: the (tiny) full step is taken
                trial = x.copy()
                trial[f] -= dx
                rt = self.residual(trial)
                rtn = np.linalg.norm(rt[f])
            x, r, rn = trial, rt, rtn
        raise RuntimeError(f"Newton did not converge at v = {v} (residual {rn:.3e})")

    def tip(self, x):
        n = self.n
        ux, uy = x[:n], x[n:2 * n]
        dx = ux[self.tip_top] - ux[self.tip_bot]
        dy = 1.0 + uy[self.tip_top] - uy[self.tip_bot]
        return float(uy[self.tip_bot]), float(np.arctan2(-dx, dy))


def solve(voltages=VOLTAGES, order=6, nx=12, ny=2, levels=3, ratio=0.15,
          intorder=None) -> Result:
    """Tip deflection w/H and rotation at the increasing ``voltages`` on one discretisation
    (the continuation passes through every multiple of STEP below them)."""
    t0 = time.process_time()
    s = Strip(order, nx, ny, levels, ratio, intorder)
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
        # the load (Maxwell stress) is quadratic in v: extrapolate the last two states
        # linearly in v^2
        guess = x if i == 0 else \
            x + (x - x_prev) * (v**2 - v_last**2) / (v_last**2 - v_prev**2)
        x_new = s.equilibrium(guess, v)
        x_prev, x, v_prev, v_last = x, x_new, v_last, v
        if i in marks:
            out.append(s.tip(x))
    out = np.array(out)
    disc = {"order": order, "nx": nx, "ny": ny, "levels": levels, "ratio": ratio,
            "intorder": 2 * order + 4 if intorder is None else intorder}
    return Result(disc, voltages, out[:, 0], out[:, 1], int(s.free.size), s.iterations,
                  time.process_time() - t0)
