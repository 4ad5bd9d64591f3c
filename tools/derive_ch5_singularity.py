"""Symbolic derivation of the clamped-free wedge determinant (plane strain, Williams 1952).

Run ``python tools/derive_ch5_singularity.py`` to re-derive and print the 4x4 boundary
matrix and its determinant; ``--check`` also compares the determinant numerically with
:func:`debench.models.buckling.singularity.characteristic_function` (which transcribes it).

Kolosov-Muskhelishvili potentials ``phi = A z^s``, ``psi = B z^s`` with A = a1 + i a2,
B = b1 + i b2, s real (the result is entire in s and continues to complex s):

    2 mu (u_x + i u_y) = kappa phi - z conj(phi') - conj(psi)
    sigma_tt + i sigma_rt = phi' + conj(phi') + (conj(z) phi'' + psi') e^(2 i theta)

Polar displacement ``u_r + i u_t = (u_x + i u_y) e^(-i theta)``. Boundary conditions
``u_r = u_t = 0`` at theta = 0 (divided by r^s) and ``sigma_tt = sigma_rt = 0`` at
theta = alpha (divided by r^(s-1)) are linear in (a1, a2, b1, b2); the determinant of the
4x4 matrix is ``s^2 D(s) / (4 mu^2)`` with

    D(s) = kappa^2 + 2 kappa + 1 - 4 kappa sin^2(alpha s) - 4 s^2 sin^2(alpha).

As a consistency check the derivation also verifies that the displacement satisfies the
plane-strain Navier equations ``(kappa - 1) lap(u) + 2 grad(div u) = 0`` (i.e.
``mu lap u + (lambda + mu) grad div u = 0`` with ``kappa = (lambda + 3 mu)/(lambda + mu)``).
"""

from __future__ import annotations

import argparse
import sys

import sympy as sp

r, th, s, al = sp.symbols("r theta s alpha", positive=True)
kap, mu = sp.symbols("kappa mu", positive=True)
x, y = sp.symbols("x y", real=True)
a1, a2, b1, b2 = sp.symbols("a1 a2 b1 b2", real=True)
COEFFS = (a1, a2, b1, b2)


def _e(m):
    """e^(i m theta) for real m, theta."""
    return sp.cos(m * th) + sp.I * sp.sin(m * th)


def fields():
    """(u_r, u_t, sigma_tt, sigma_rt) of the potentials, as real expressions."""
    A, B = a1 + sp.I * a2, b1 + sp.I * b2
    phi = A * r**s * _e(s)
    dphi = s * A * r ** (s - 1) * _e(s - 1)
    ddphi = s * (s - 1) * A * r ** (s - 2) * _e(s - 2)
    psi = B * r**s * _e(s)
    dpsi = s * B * r ** (s - 1) * _e(s - 1)
    z, zb = r * _e(1), r * _e(-1)
    u = (kap * phi - z * sp.conjugate(dphi) - sp.conjugate(psi)) / (2 * mu)
    upol = sp.expand(u * _e(-1))
    trac = sp.expand(dphi + sp.conjugate(dphi) + (zb * ddphi + dpsi) * _e(2))
    return sp.re(upol), sp.im(upol), sp.re(trac), sp.im(trac)


def derive():
    """(M, D): the 4x4 boundary matrix and ``D = det M * 4 mu^2 / s^2`` simplified."""
    ur, ut, stt, srt = fields()
    rows = [ur.subs(th, 0) / r**s, ut.subs(th, 0) / r**s,
            stt.subs(th, al) / r ** (s - 1), srt.subs(th, al) / r ** (s - 1)]
    M = sp.Matrix([[sp.simplify(sp.diff(row, c)) for c in COEFFS] for row in rows])
    D = sp.simplify(sp.expand_trig(sp.simplify(M.det() * 4 * mu**2 / s**2)))
    return M, D


def navier_residual():
    """Plane-strain Navier residual of the potentials' displacement at a numeric point
    (should vanish to round-off)."""
    ur, ut, _, _ = fields()
    ux = ur * sp.cos(th) - ut * sp.sin(th)
    uy = ur * sp.sin(th) + ut * sp.cos(th)
    sub = {r: sp.sqrt(x**2 + y**2), th: sp.atan2(y, x)}
    ux, uy = ux.subs(sub), uy.subs(sub)
    div = sp.diff(ux, x) + sp.diff(uy, y)
    res = [(kap - 1) * (sp.diff(ux, x, 2) + sp.diff(ux, y, 2)) + 2 * sp.diff(div, x),
           (kap - 1) * (sp.diff(uy, x, 2) + sp.diff(uy, y, 2)) + 2 * sp.diff(div, y)]
    point = {x: 0.7, y: 0.4, s: 0.61, kap: 1.8, mu: 1.0, a1: 0.3, a2: -1.1, b1: 0.5,
             b2: 0.9}
    return max(abs(complex(sp.N(e.subs(point), 30))) for e in res)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--check", action="store_true",
                   help="compare with the module's characteristic_function")
    args = p.parse_args(argv)
    M, D = derive()
    print("boundary matrix (rows: u_r(0), u_t(0), s_tt(alpha), s_rt(alpha)):")
    sp.pprint(M)
    print("D(s) =", D)
    print("Navier residual of the ansatz at a sample point:", navier_residual())
    if args.check:
        import math

        from debench.models.buckling.singularity import characteristic_function
        f = sp.lambdify((s, kap, al), D, "math")
        worst = 0.0
        for sv, kv, av in [(0.3, 1.0, math.pi / 2), (0.71, 1.8, 1.3), (1.7, 6.5, 3.0)]:
            worst = max(worst, abs(f(sv, kv, av) - characteristic_function(sv, kv, av)))
        print("max |D_sympy - characteristic_function| =", worst)
        return 0 if worst < 1e-12 else 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
