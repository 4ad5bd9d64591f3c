"""Symbolic derivation of the Chapter 4 incremental plate problem from the energy (4.22).

Run ``python tools/derive_ch4.py`` to re-derive everything and regenerate
``models/plate/generated.py``; ``python tools/derive_ch4.py --check`` only prints the
comparison with the printed equations (no file written).

What is derived (units: mu = eps = 1, so D_hat = D2 / sqrt(mu eps) is simply D2):

1. Referential moduli (4.29)-(4.31) by differentiating
   W = 1/2 (I1 - 3) + xi/2 (I4 - 1)^2 + (alpha I6 + beta I5)/2,  I4 = A.CA, A = e2,
   I5 = D_L.C D_L, I6 = D_L.D_L   (eq. 4.22, Ch. 4 numbering),
   at F = diag(lam, lam^-2, lam), D_L = (0, lam^2 D_hat, 0) (so D = F D_L = D_hat e2).
2. The base pressure p from tau22 = 0 (no exterior field between charged electrodes),
   and the lateral total stress tau11.
3. The incremental energy density 2Q = d^2/dt^2 [W(F_t, D_L,t) - p det(I + tL)] with
   F_t = (I + tL)F, D_L,t = D_L + t F^-1 Ddot_L0 (push-forward of Dorfmann-Ogden), i.e.
   Q = 1/2 [A0_jisk L_ij L_ks + 2 G0_jik L_ij Ddot_k + K0_ij Ddot_i Ddot_j + p L_ij L_ji],
   restricted to plane strain: the 6x6 matrix S over z = (L11, L12, L21, L22, Dd1, Dd2).
4. The symbol of the Euler-Lagrange operator for u = (psi_2, -psi_1), Ddot = (phi_2,
   -phi_1): coefficients a, 2b, c, d, e, f, g of (4.52)-(4.53).
5. The characteristic polynomial (4.63) and the boundary rows (4.69)-(4.71) from the
   incremental traction T0_2i and the tangential field E_L0,1 on the electrodes.

Every comparison with the printed thesis forms is printed; differences are errata
catalogued in ``reference/catalogue/ch4.toml``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import sympy as sp

OUT = Path(__file__).resolve().parents[1] / "models" / "plate" / "generated.py"

lam, xi, al, be, Dh = sp.symbols("lam xi alpha beta Dhat", positive=True)
s, A, B = sp.symbols("s A B")


def energy():
    F = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"F{i + 1}{j + 1}"))
    DL = sp.Matrix(3, 1, lambda i, j: sp.Symbol(f"DL{i + 1}"))
    C = F.T * F
    a_vec = sp.Matrix([0, 1, 0])
    I1 = C.trace()
    I4 = (a_vec.T * C * a_vec)[0]
    I5 = (DL.T * C * DL)[0]
    I6 = (DL.T * DL)[0]
    W = sp.Rational(1, 2) * (I1 - 3) + xi / 2 * (I4 - 1) ** 2 + (al * I6 + be * I5) / 2
    return W, F, DL


def derive():
    W, F, DL = energy()
    F0 = sp.diag(lam, lam**-2, lam)
    DL0 = sp.Matrix([0, lam**2 * Dh, 0])
    base = {F[i, j]: F0[i, j] for i in range(3) for j in range(3)}
    base.update({DL[i]: DL0[i] for i in range(3)})
    dWdF = sp.Matrix(3, 3, lambda i, a: sp.diff(W, F[i, a]))
    tau = (F * dWdF.T).subs(base)  # tau_ij = F_ia dW/dF_ja (+ -p delta_ij)
    p = sp.simplify(tau[1, 1])
    tau11 = sp.simplify(tau[0, 0] - p)
    L = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"L{i + 1}{j + 1}"))
    Dd = sp.Matrix(3, 1, lambda i, j: sp.Symbol(f"Dd{i + 1}"))
    t = sp.Symbol("t")
    Ft = (sp.eye(3) + t * L) * F0
    DLt = DL0 + t * F0.inv() * Dd
    sub = {F[i, j]: Ft[i, j] for i in range(3) for j in range(3)}
    sub.update({DL[i]: DLt[i] for i in range(3)})
    Wt = W.subs(sub) - p * (sp.eye(3) + t * L).det()
    Q2 = sp.expand(sp.diff(Wt, t, 2).subs(t, 0))
    plane = {L[0, 2]: 0, L[1, 2]: 0, L[2, 0]: 0, L[2, 1]: 0, L[2, 2]: 0, Dd[2]: 0}
    Q2 = sp.expand(Q2.subs(plane))
    z = [L[0, 0], L[0, 1], L[1, 0], L[1, 1], Dd[0], Dd[1]]
    S = sp.Matrix(6, 6, lambda a, b: sp.simplify(sp.diff(Q2, z[a], z[b]) / 2))
    return S, p, tau11


def symbol(S):
    """P(q) = B(-q)^T S B(q) for psi, phi ~ exp(i q.x)."""
    q1, q2 = sp.symbols("q1 q2")
    I = sp.I

    def Bm(q1, q2):
        return sp.Matrix([[-q1 * q2, 0], [-q2**2, 0], [q1**2, 0], [q1 * q2, 0],
                          [0, I * q2], [0, -I * q1]])

    P = (Bm(-q1, -q2).T * S * Bm(q1, q2)).applyfunc(sp.expand)
    coeff = {
        "a": P[0, 0].coeff(q1, 4).coeff(q2, 0),
        "b2": P[0, 0].coeff(q1, 2).coeff(q2, 2),
        "c": P[0, 0].coeff(q2, 4).coeff(q1, 0),
        # thesis (4.52): (e-d) phi_112 + d phi_222 -> -i[(e-d) q1^2 q2 + d q2^3]
        "d": sp.I * P[0, 1].coeff(q2, 3).coeff(q1, 0),
        "e_minus_d": sp.I * P[0, 1].coeff(q1, 2).coeff(q2, 1),
        "f": P[1, 1].coeff(q2, 2).coeff(q1, 0),
        "g": P[1, 1].coeff(q1, 2).coeff(q2, 0),
    }
    coeff = {k: sp.simplify(v) for k, v in coeff.items()}
    coeff["e"] = sp.simplify(coeff["e_minus_d"] + coeff["d"])
    return P, q1, q2, coeff


def rows(S):
    """Incremental T0_21, T0_22 (with pdot from x1-equilibrium) and E_L0,1 on x2 = const."""
    I = sp.I
    q1, q2 = 1, I * s  # psi = A exp(i x1 - s x2), phi = B exp(...) (k = 1)
    z = sp.Matrix([-q1 * q2 * A, -q2**2 * A, q1**2 * A, q1 * q2 * A, I * q2 * B, -I * q1 * B])
    Sz = (S * z).applyfunc(sp.expand)
    pdot = sp.expand((I * q1 * Sz[0] + I * q2 * Sz[1]) / (I * q1))
    return sp.expand(Sz[1]), sp.expand((Sz[3] - pdot) / I), sp.expand(Sz[4])


def printed():
    """The thesis' printed coefficients (4.54)-(4.60) (mu = eps = 1)."""
    return {"a": lam**2, "b2": lam**2 + lam**-4 + be * Dh**2 + 6 * xi * lam**-8,
            "c": lam**-4 + be * Dh**2 + 2 * xi * lam**-8, "d": be * Dh, "e": 2 * be * Dh,
            "f": al * lam**-2 + be, "g": al * lam**4 + be}


def generic_rows(cf):
    """(4.69)-(4.71) written with coefficients a..g."""
    r1 = cf["c"] * (1 + s**2) * A - cf["d"] * s * B
    r2 = (cf["b2"] + cf["c"] - cf["c"] * s**2) * s * A - (cf["e"] - cf["d"] * s**2) * B
    r3 = cf["d"] * (1 + s**2) * A - cf["f"] * s * B
    return r1, r2, r3


def report(S, p, tau11, coeff):
    out = []
    pr = printed()
    out.append("== coefficients (4.54)-(4.60): derived minus printed")
    for k in ("a", "b2", "c", "d", "e", "f", "g"):
        out.append(f"  {k}: derived = {sp.simplify(coeff[k])};  derived - printed = "
                   f"{sp.simplify(coeff[k] - pr[k])}")
    P, q1, q2, _ = symbol(S)
    out.append("== characteristic polynomial (alpha = 0), det P(1, i s) * lam^-2 / beta")
    det = sp.factor(sp.expand(P.subs({q1: 1, q2: sp.I * s}).det().subs(al, 0)))
    out.append(f"  {det}")
    printed_bicubic = (s**2 - 1) * ((lam**-6 + 2 * xi * lam**-10) * s**4
                                    - (1 + lam**-6 + 6 * xi * lam**-10) * s**2 + 1)
    ratio = sp.simplify(det / printed_bicubic)
    out.append(f"  derived / printed (4.63) = {ratio}  (constant iff (4.63) is right)")
    r_der = rows(S)
    r_gen = generic_rows(coeff)
    for name, rd, rg in zip(("(4.69) T21", "(4.70) T22", "(4.71) E1"), r_der, r_gen,
                            strict=True):
        out.append(f"  {name}: derived row - generic row with derived a..g = "
                   f"{sp.simplify(rd - rg)}")
    out.append(f"== base state: p = {p};  tau11 (tau22 = 0) = {sp.factor(tau11)}")
    return "\n".join(out)


def generate(S, p, tau11, coeff) -> str:
    # The structure S(a, 2b, c, d, e, f, g) used by debench.models.plate is checked here.
    a, b2, c, d, e, f, g = (coeff[k] for k in ("a", "b2", "c", "d", "e", "f", "g"))
    S_struct = sp.Matrix([[a, 0, 0, -c, 0, 0], [0, c, c, 0, d, 0], [0, c, a, 0, d, 0],
                          [-c, 0, 0, b2 - a, 0, e], [0, d, d, 0, f, 0], [0, 0, 0, e, 0, g]])
    diff = (S - S_struct).applyfunc(sp.simplify)
    if diff != sp.zeros(6, 6):
        raise SystemExit(f"S does not have the assumed structure: {diff}")
    lines = [
        '"""GENERATED by tools/derive_ch4.py (sympy ' + sp.__version__ + ') - do not edit.',
        "",
        "Coefficients a, 2b, c, d, e, f, g of the incremental equations (4.52)-(4.53),",
        "derived from the energy (4.22) with mu = eps = 1 (D_hat = D2/sqrt(mu eps)), and the",
        "base-state pressure p (tau22 = 0) and lateral total stress tau11.",
        "The plane-strain incremental energy matrix is S(a, 2b, c, d, e, f, g), see",
        "debench.models.plate.coefficients.energy_matrix. A test re-derives these numerically.",
        '"""',
        "",
        "from __future__ import annotations",
        "",
        "",
        "def derived_coefficients(lam, xi, alpha, beta, Dhat):",
        '    """(a, 2b, c, d, e, f, g) of (4.52)-(4.53) derived from (4.22)."""',
    ]
    for k, v in zip(("a", "b2", "c", "d", "e", "f", "g"), (a, b2, c, d, e, f, g),
                    strict=True):
        lines.append(f"    {k} = {sp.pycode(sp.simplify(v))}")
    lines += ["    return a, b2, c, d, e, f, g", "", "",
              "def base_state(lam, xi, alpha, beta, Dhat):",
              '    """(p, tau11): base pressure from tau22 = 0 and lateral total stress."""',
              f"    p = {sp.pycode(p)}",
              f"    tau11 = {sp.pycode(sp.simplify(tau11))}",
              "    return p, tau11", ""]
    return "\n".join(lines).replace("lam", "lam")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--check", action="store_true", help="print only, do not write")
    args = ap.parse_args(argv)
    S, p, tau11 = derive()
    _, _, _, coeff = symbol(S)
    print(report(S, p, tau11, coeff))
    if not args.check:
        OUT.write_text(generate(S, p, tau11, coeff))
        print(f"wrote {OUT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
