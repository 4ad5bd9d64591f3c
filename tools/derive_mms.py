#!/usr/bin/env python
"""Derive the manufactured solution of compressible nonlinear electro-elasticity with
sympy, and write ``models/mms_generated.py`` and ``reference/mms_electroelastic_formulas.json``.

Usage::

    python tools/derive_mms.py            # regenerate the checked-in module and JSON
    python tools/derive_mms.py --check    # derive and compare numerically, no write

The model (normalised: stresses by the shear modulus mu, the potential by
sqrt(mu/eps) x length, so that eps = mu = 1) is the Chapter 5 electric enthalpy::

    Omega(F, E_L) = W_mech(F) - 1/2 J C^-1 : (E_L x E_L),      E_L = -Grad phi,
    neo-Hookean:  W_mech = 1/2 (J^(-2/3) I1 - 3) + kappa/2 (J - 1)^2
    Gent:         W_mech = -Jm/2 log(1 - (J^(-2/3) I1 - 3)/Jm) + kappa/2 (J - 1)^2

with ``kappa = k/mu`` and ``Jm`` kept as symbols. The equations are ``Div P + b = 0``
(``P = dOmega/dF``) and ``Div D_L = q`` (``D_L = -dOmega/dE_L = J C^-1 E_L``); the body
force ``b`` and the free charge ``q`` are derived here from the manufactured ``u``, ``phi``
of :data:`FIELDS` (plane strain on the unit square, axisymmetric on (R, Z) in [0, 1]^2
including the axis, 3D on the unit cube). In the axisymmetric case the components are in
the orthonormal cylindrical basis (R, Theta, Z) and::

    (Div P)_R = d_R P_RR + d_Z P_RZ + (P_RR - P_TT)/R,  (Div P)_Z = d_R P_ZR + d_Z P_ZZ + P_ZR/R,
    Div D_L  = d_R D_R + d_Z D_Z + D_R/R.

One derivation, three outputs: the generated Python module (the formula strings executed
in a math namespace, numpy or NGSolve), the formula strings themselves (Python syntax for
UFL / NGSolve / numpy, and C99 via ``sympy.ccode``), in the module and in the JSON file a
user reads without installing debench. ``verification/test_mms.py`` re-derives with
:func:`derive` (sympy ``lambdify``) and compares *numerically* with the checked-in module
- never the text.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import sympy as sp

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "models" / "mms_generated.py"
OUT_JSON = ROOT / "reference" / "mms_electroelastic_formulas.json"

GEOMETRIES = ("plane_strain", "axisymmetric", "three_d")
MATERIALS = ("neo_hookean", "gent")
COORDS = {"plane_strain": ("X", "Y"), "axisymmetric": ("R", "Z"), "three_d": ("X", "Y", "Z")}
KAPPA, JM = sp.symbols("kappa Jm", positive=True)


def _c(*names):
    return sp.symbols(names, real=True)


def fields(geometry: str):
    """The manufactured displacement components and potential (sympy), and coordinates.

    Amplitudes 1/20 (displacements) and 1/10 (potential): displacement gradients and
    normalised fields of O(0.1-0.5), J in [0.71, 1.55] (checked by the tests on a grid).
    Every field is non-zero on the boundary (the Dirichlet data are not trivial). The
    axisymmetric fields are regular on the axis: u_R odd in R, u_Z and phi even.
    """
    pi, sin, cos = sp.pi, sp.sin, sp.cos
    h = sp.Rational(1, 20)
    t = sp.Rational(1, 10)
    if geometry == "plane_strain":
        X, Y = _c("X", "Y")
        u = [h * sin(pi * X) * cos(pi * Y),
             h * (cos(pi * X / 2) * sin(pi * Y) + X**2 * Y)]
        phi = t * (sin(pi * X) * sin(pi * Y) + X + Y / 2)
        return (X, Y), u, phi
    if geometry == "axisymmetric":
        R, Z = _c("R", "Z")
        u = [h * R * cos(pi * R / 2) * cos(pi * Z),
             h * (cos(pi * R) * sin(pi * Z) + R**2 * Z)]
        phi = t * (cos(pi * R) * sin(pi * Z) + Z + R**2 / 2)
        return (R, Z), u, phi
    if geometry == "three_d":
        X, Y, Z = _c("X", "Y", "Z")
        u = [h * sin(pi * X) * cos(pi * Y) * cos(pi * Z / 2),
             h * (cos(pi * X / 2) * sin(pi * Y) * cos(pi * Z) + X**2 * Y),
             h * (cos(pi * X) * cos(pi * Y / 2) * sin(pi * Z) + Y * Z**2)]
        phi = t * (sin(pi * X) * sin(pi * Y) * sin(pi * Z) + X + Y / 2 + Z / 3)
        return (X, Y, Z), u, phi
    raise ValueError(f"geometry must be one of {GEOMETRIES}, got {geometry!r}")


def enthalpy(F, E, material: str):
    """Omega(F, E_L) normalised by mu (module docstring), for a 3x3 sympy ``F``
    (``C^-1 = adj(F) adj(F)^T / J^2``)."""
    J = F.det(method="berkowitz")
    C = F.T * F
    adjF = F.adjugate()
    I1bar = J ** sp.Rational(-2, 3) * C.trace()
    if material == "neo_hookean":
        W = (I1bar - 3) / 2
    elif material == "gent":
        W = -JM / 2 * sp.log(1 - (I1bar - 3) / JM)
    else:
        raise ValueError(f"material must be one of {MATERIALS}, got {material!r}")
    a = adjF.T * E          # J F^-T E_L, so that J C^-1 : (E x E) = |a|^2 / J
    return W + KAPPA / 2 * (J - 1) ** 2 - (a.T * a)[0] / (2 * J)


#: the entries of F and E_L that are not identically 0 or 1, per geometry
ACTIVE = {
    "plane_strain": ((0, 0), (0, 1), (1, 0), (1, 1)),
    "axisymmetric": ((0, 0), (0, 2), (1, 1), (2, 0), (2, 2)),
    "three_d": tuple((i, j) for i in range(3) for j in range(3)),
}
ACTIVE_E = {"plane_strain": (0, 1), "axisymmetric": (0, 2), "three_d": (0, 1, 2)}


def kinematics(geometry: str):
    """F (3x3) and E_L (3) of the manufactured fields, and the coordinates."""
    x, u, phi = fields(geometry)
    if geometry == "plane_strain":
        X, Y = x
        F = sp.Matrix([[1 + sp.diff(u[0], X), sp.diff(u[0], Y), 0],
                       [sp.diff(u[1], X), 1 + sp.diff(u[1], Y), 0],
                       [0, 0, 1]])
        E = sp.Matrix([-sp.diff(phi, X), -sp.diff(phi, Y), 0])
    elif geometry == "axisymmetric":
        R, Z = x
        F = sp.Matrix([[1 + sp.diff(u[0], R), 0, sp.diff(u[0], Z)],
                       [0, 1 + u[0] / R, 0],
                       [sp.diff(u[1], R), 0, 1 + sp.diff(u[1], Z)]])
        E = sp.Matrix([-sp.diff(phi, R), 0, -sp.diff(phi, Z)])
    else:
        F = sp.eye(3) + sp.Matrix(3, 3, lambda i, j: sp.diff(u[i], x[j]))
        E = sp.Matrix([-sp.diff(phi, xj) for xj in x])
    return x, u, phi, F, E


def expressions(geometry: str, material: str) -> dict:
    """Sympy expressions: u, phi, grad_u, grad_phi, J of the coordinates; ``kinematic``
    (ordered ``{symbol: expression of the coordinates}``: the active entries ``Fij`` of F,
    ``Ei`` of E_L and their partial derivatives ``Fij_X``, ``Ei_X`` ...); b, q as
    expressions of those symbols (the divergence by the chain rule,
    ``d_J P_iJ = dP_iJ/dF_kL F_kL,J + dP_iJ/dE_k E_k,J``)."""
    x, u, phi, Fx, Ex = kinematics(geometry)
    Fs = sp.Matrix(3, 3, lambda i, j: Fx[i, j])
    Es = sp.Matrix(3, 1, lambda i, _: Ex[i])
    kin = {}
    for i, j in ACTIVE[geometry]:
        Fs[i, j] = sp.Symbol(f"F{i}{j}")
        kin[Fs[i, j]] = Fx[i, j]
    for i in ACTIVE_E[geometry]:
        Es[i] = sp.Symbol(f"E{i}")
        kin[Es[i]] = Ex[i]
    active = list(kin)
    for a in active:
        for xj in x:
            kin[sp.Symbol(f"{a}_{xj}")] = sp.diff(kin[a], xj)
    Om = enthalpy(Fs, Es, material)

    def div_term(expr, xj):
        return sum(sp.diff(expr, a) * sp.Symbol(f"{a}_{xj}") for a in active)

    if geometry == "plane_strain":
        P = {(i, j): sp.diff(Om, Fs[i, j]) for i in range(2) for j in range(2)}
        D = [-sp.diff(Om, Es[k]) for k in range(2)]
        b = [-sum(div_term(P[i, j], x[j]) for j in range(2)) for i in range(2)]
        q = sum(div_term(D[j], x[j]) for j in range(2))
    elif geometry == "axisymmetric":
        R, Z = x
        P = {ij: sp.diff(Om, Fs[ij]) for ij in ACTIVE[geometry]}
        D0, D2 = -sp.diff(Om, Es[0]), -sp.diff(Om, Es[2])
        b = [-(div_term(P[0, 0], R) + div_term(P[0, 2], Z) + (P[0, 0] - P[1, 1]) / R),
             -(div_term(P[2, 0], R) + div_term(P[2, 2], Z) + P[2, 0] / R)]
        q = div_term(D0, R) + div_term(D2, Z) + D0 / R
    else:
        P = {(i, j): sp.diff(Om, Fs[i, j]) for i in range(3) for j in range(3)}
        D = [-sp.diff(Om, Es[k]) for k in range(3)]
        b = [-sum(div_term(P[i, j], x[j]) for j in range(3)) for i in range(3)]
        q = sum(div_term(D[j], x[j]) for j in range(3))
    return {"u": u, "phi": phi,
            "grad_u": [[sp.diff(ui, xj) for xj in x] for ui in u],
            "grad_phi": [sp.diff(phi, xj) for xj in x],
            "J": Fx.det(method="berkowitz"), "kinematic": kin, "b": b, "q": q}


OUTPUTS = ("u", "phi", "grad_u", "grad_phi", "J", "b", "q")


def _flat(ex: dict) -> tuple[list, dict]:
    flat, where = [], {}
    for k in OUTPUTS:
        v = ex[k]
        if k == "grad_u":
            n = len(v)
            items = [e for row in v for e in row]
            where[k] = (len(flat), len(items), (n, len(v[0])))
        elif isinstance(v, list):
            items = list(v)
            where[k] = (len(flat), len(items), (len(v),))
        else:
            items = [v]
            where[k] = (len(flat), 1, ())
        flat.extend(items)
    return flat, where


def derive(geometry: str, material: str):
    """A numpy function ``f(*coords, kappa, Jm) -> dict`` lambdified from a fresh derivation
    (the kinematic symbols evaluated first, then b and q in them)."""
    import numpy as np

    ex = expressions(geometry, material)
    x = fields(geometry)[0]
    kin = ex["kinematic"]
    fkin = sp.lambdify(x, list(kin.values()), modules="numpy")
    fbq = sp.lambdify([*x, *kin, KAPPA, JM], [*ex["b"], ex["q"]], modules="numpy")
    direct = {k: v for k, v in ex.items() if k not in ("kinematic", "b", "q")}
    flat, where = _flat(direct | {"b": [], "q": 0})
    fdirect = sp.lambdify(x, flat, modules="numpy")

    def f(*coords, kappa, Jm=1.0):
        shape = np.broadcast(*coords).shape
        full = [np.broadcast_to(np.asarray(v, dtype=float), shape) for v in fdirect(*coords)]
        out = {}
        for k, (lo, n, shp) in where.items():
            if k in ("b", "q"):
                continue
            part = np.array(full[lo:lo + n])
            out[k] = part.reshape(shp + shape) if shp else part[0]
        kv = [np.broadcast_to(np.asarray(v, dtype=float), shape) for v in fkin(*coords)]
        bq = [np.broadcast_to(np.asarray(v, dtype=float), shape)
              for v in fbq(*coords, *kv, kappa, Jm)]
        out["b"] = np.array(bq[:-1])
        out["q"] = bq[-1]
        return out

    return f


def formulas(geometry: str, material: str) -> dict:
    """Formula strings: ``{"coordinates", "parameters", "python": {...}, "c": {...}}``.

    Each language holds ``assignments`` (ordered ``[name, expression]`` pairs to be
    evaluated first: the entries of F and E_L and their derivatives, then the common
    subexpressions of ``b`` and ``q``) and the expressions of
    ``u``, ``phi``, ``grad_u``, ``grad_phi``, ``J``, ``b``, ``q`` in the coordinates and
    the parameters. Python syntax uses ``sin``, ``cos``, ``pi``, ``**``; C99 uses
    ``sin``, ``cos``, ``M_PI``, ``pow``.
    """
    ex = expressions(geometry, material)
    x = fields(geometry)[0]
    repl, reduced = sp.cse([*ex["b"], ex["q"]], symbols=sp.numbered_symbols("t"),
                           optimizations="basic")
    repl = list(ex["kinematic"].items()) + repl
    nb = len(ex["b"])
    body = dict(ex, b=reduced[:nb], q=reduced[nb])

    def emit(printer):
        out = {"assignments": [[str(s), printer(e)] for s, e in repl]}
        for k in OUTPUTS:
            v = body[k]
            if k == "grad_u":
                out[k] = [[printer(e) for e in row] for row in v]
            elif isinstance(v, list):
                out[k] = [printer(e) for e in v]
            else:
                out[k] = printer(v)
        return out

    params = ["kappa"] + (["Jm"] if material == "gent" else [])
    return {"coordinates": [str(c) for c in x], "parameters": params,
            "python": emit(str), "c": emit(lambda e: sp.ccode(e, standard="c99"))}


def generate() -> tuple[str, dict]:
    """The source of ``models/mms_generated.py`` and the JSON document."""
    doc = {"generator": f"tools/derive_mms.py (sympy {sp.__version__})",
           "model": ("Omega(F, E_L) = W_mech(F) - 1/2 J C^-1 : (E_L x E_L), E_L = -Grad phi; "
                     "neo_hookean W_mech = 1/2 (J^(-2/3) I1 - 3) + kappa/2 (J - 1)^2; gent "
                     "W_mech = -Jm/2 log(1 - (J^(-2/3) I1 - 3)/Jm) + kappa/2 (J - 1)^2; "
                     "normalised by mu (stresses) and sqrt(mu/eps) x length (potential)"),
           "equations": ("Div P + b = 0, P = dOmega/dF; Div D_L = q, D_L = -dOmega/dE_L; "
                         "axisymmetric: components in the cylindrical basis (R, Theta, Z)"),
           "cases": {}}
    lines = [
        '"""Manufactured electro-elastic solution generated by sympy - DO NOT EDIT.',
        "",
        f"Generator: tools/derive_mms.py (sympy {sp.__version__}).",
        "Regenerate with ``python tools/derive_mms.py``; verified numerically against a fresh",
        "derivation by verification/test_mms.py. The public API is :mod:`debench.models.mms`.",
        "",
        "Each function evaluates the Python formula strings of ``FORMULAS`` (the same text",
        "the JSON file ships) in the math namespace ``ns``: ``numpy`` (arrays) or ``ngsolve``",
        "(CoefficientFunctions of ngsolve.x, y, z).",
        '"""',
        "",
        "# ruff: noqa",
        "import math",
        "",
        "pi = math.pi",
        "",
    ]
    for g in GEOMETRIES:
        for m in MATERIALS:
            f = formulas(g, m)
            name = f"{g}_{m}"
            doc["cases"][name] = f
            py = f["python"]
            args = ", ".join(f["coordinates"])
            kw = ", ".join(f["parameters"])
            lines.append(f"def {name}({args}, *, {kw}, ns):")
            lines.append(f'    """{g}, {m}: dict of u, phi, grad_u, grad_phi, J, b, q."""')
            lines.append("    sin, cos = ns.sin, ns.cos")
            for s, e in py["assignments"]:
                lines.append(f"    {s} = {e}")
            lines.append("    return {")
            for k in OUTPUTS:
                v = py[k]
                if k == "grad_u":
                    rows = ", ".join("[" + ", ".join(r) + "]" for r in v)
                    lines.append(f"        {k!r}: [{rows}],")
                elif isinstance(v, list):
                    lines.append(f"        {k!r}: [{', '.join(v)}],")
                else:
                    lines.append(f"        {k!r}: {v},")
            lines.append("    }")
            lines.append("")
            lines.append("")
    lines.append("FORMULAS = " + repr(doc["cases"]))
    return "\n".join(lines).rstrip() + "\n", doc


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--check", action="store_true", help="compare with a fresh derivation")
    args = ap.parse_args(argv)
    if args.check:
        import numpy as np
        from debench.models import mms_generated

        rng = np.random.default_rng(2)
        worst = 0.0
        for g in GEOMETRIES:
            for m in MATERIALS:
                pts = [rng.uniform(0.05, 0.95, 20) for _ in COORDS[g]]
                fresh = derive(g, m)(*pts, kappa=10.0, Jm=50.0)
                kw = {"kappa": 10.0} | ({"Jm": 50.0} if m == "gent" else {})
                gen = getattr(mms_generated, f"{g}_{m}")(*pts, ns=np, **kw)
                for k in OUTPUTS:
                    a, b = np.asarray(fresh[k]), np.broadcast_to(np.asarray(gen[k], float),
                                                                  np.shape(fresh[k]))
                    worst = max(worst, float(np.max(np.abs(a - b))))
        print(f"max |fresh - generated| = {worst:.3e}")
        return 0 if worst < 1e-9 else 1
    src, doc = generate()
    OUT.write_text(src)
    OUT_JSON.write_text(json.dumps(doc, indent=1) + "\n")
    print(f"wrote {OUT} and {OUT_JSON}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
