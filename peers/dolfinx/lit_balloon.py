"""DOLFINx adapter: lit_balloon, the dielectric-elastomer balloon (thin spherical
neo-Hookean or Gent ideal-dielectric membrane under internal pressure and voltage): the
pressure curves, their extrema at fixed voltage and the voltage limit at fixed pressure.

Written as a DOLFINx user writes it, from the problem page alone
(``debench problems lit_balloon --markdown``), with no debench code: an axisymmetric
membrane finite-element model of the sphere on its meridian.

* Kinematics: radial maps x = rho(Theta) e_r(Theta) of the mid-surface (reference radius
  R = 1, polar angle 0 <= Theta <= pi on ``create_interval``, no tangential displacement);
  lam1 = sqrt(rho^2 + rho'^2) (meridian), lam2 = rho (hoop), lam3 = 1/(lam1 lam2).
* The energy in UFL, per 2 pi mu H R^2: Pi = int [W(I1) - vbar^2/2 lam1^2 lam2^2] sin dTheta
  - pbar/3 int rho^3 sin dTheta, W = (I1 - 3)/2 (neo-Hookean) or -Jm/2 ln(1 - (I1 - 3)/Jm)
  (Gent); the electric term is -(1/2) eps (Phi/h)^2 per current volume, h = H lam3, i.e.
  -(1/2) eps Phi^2 lam1^2 lam2^2/H per reference area (the page's -(1/2) C Phi^2 for the
  uniform sphere). Its three pieces (mechanical, electric per vbar^2, volume) are
  differentiated by ``ufl.derivative`` into residual vectors and tangent matrices.
* Stretch control at rho = lam (the uniform inflation lies in the Lagrange space): pbar is
  the multiplier that makes the discrete residual F_mech + vbar^2 F_el - pbar V' vanish
  (least squares over all dofs); the part of the residual it leaves is measured (it is the
  test that the uniform state is the discrete equilibrium: quadrature cancels because
  rho' = 0, so only round-off remains), as is the change over the refinement sequence.
* Extrema of pbar at fixed vbar: zeros of dpbar/dlam along the stretch-controlled
  discrete branch rho = lam, from the UFL tangent K applied to the branch direction:
  K 1 - dpbar/dlam V' = 0 in least squares (no finite differences; not the bordered
  tangent solve with the volume prescribed, which is singular where the net tension
  vanishes: at pbar = 0 and the voltage limit K is zero in every non-uniform direction),
  bracketed by a scan in lam (step 0.01), refined by a regula falsi (Illinois; scipy is
  not in this venv). Voltage limit at fixed pbar: vbar^2 the multiplier instead (column
  F_el), its first + to - zero where vbar^2 > 0.
* A full nonlinear solve as a check: PETSc SNES (Newton, LU) at the dead pressure found,
  from rho = lam (1 + 0.001 P2(cos Theta)), at every 20th stretch of the 18 pbar curves;
  the adapter counts the states it returns to the uniform one, lands elsewhere, or does
  not converge (the uniform state is not isolated where the net tension vanishes).
* Resolution: P3 x 16, P2 x 32, P2 x 8 cells; the coarsest is written (the uniform state
  is exact on every mesh; refinement adds only round-off: the computed rho' of the
  constant is ~eps/h), 3 x the largest change over the sequence stated as its accuracy.
"""

from __future__ import annotations  # noqa: I001 - dolfinx_solver must precede dolfinx

import argparse
import json
import math
import time
from pathlib import Path

import dolfinx_solver  # the wheel's package first: it loads MPI ahead of dolfinx and PETSc
import dolfinx
import dolfinx.fem
import numpy as np
import ufl
from mpi4py import MPI

#: refinement sequence (degree, cells); the last is written. The coarsest is written: the
#: uniform state is exact on every mesh, and refinement adds round-off only (the computed
#: rho' of the constant is ~eps/h, its term in the residual ~eps/h^2 relative)
SEQUENCE = ((3, 16), (2, 32), (2, 8))
SAFETY = 3.0
#: floors of the stated accuracy (rtol for |value| >= SMALL, atol below SMALL)
RTOL_FLOOR, ATOL_FLOOR, SMALL = 1e-13, 3e-14, 1e-3
SCAN = 0.01
#: the check's non-uniform start rho = lam (1 + START P2(cos Theta)), at every SAMPLE-th
#: stretch of each pbar curve
START, SAMPLE = 1e-3, 20
XTOL = 1e-15
QUANTITIES = ("pbar", "lam_pmax", "pbar_max", "lam_pmin", "pbar_min", "lam_vmax", "vbar_max")


class Membrane:
    """The meridian [0, pi], Lagrange P``degree`` for rho; the forms of one material."""

    def __init__(self, degree: int, cells: int, Jm: float):
        mesh = dolfinx.mesh.create_interval(MPI.COMM_SELF, cells, [0.0, math.pi])
        V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree))
        self.rho = dolfinx.fem.Function(V)
        self.ndofs = V.dofmap.index_map.size_local
        rho, v, du = self.rho, ufl.TestFunction(V), ufl.TrialFunction(V)
        theta = ufl.SpatialCoordinate(mesh)[0]
        dx = ufl.Measure("dx", domain=mesh, metadata={"quadrature_degree": 2 * degree + 4})
        l1sq = rho ** 2 + rho.dx(0) ** 2
        l2sq = rho ** 2
        I1 = l1sq + l2sq + 1 / (l1sq * l2sq)
        if math.isinf(Jm):
            W = (I1 - 3) / 2
        else:
            jm = dolfinx.fem.Constant(mesh, float(Jm))
            W = -jm / 2 * ufl.ln(1 - (I1 - 3) / jm)
        w = ufl.sin(theta)
        energies = {"mech": W * w * dx, "el": -0.5 * l1sq * l2sq * w * dx,
                    "vol": rho ** 3 / 3 * w * dx}
        self.F = {k: dolfinx.fem.form(ufl.derivative(e, rho, v)) for k, e in energies.items()}
        self.K = {k: dolfinx.fem.form(ufl.derivative(ufl.derivative(e, rho, v), rho, du))
                  for k, e in energies.items()}
        one = dolfinx.fem.Function(V)
        one.interpolate(lambda x: np.ones_like(x[0]))
        self.one = one.x.array.copy()
        bump = dolfinx.fem.Function(V)  # P2(cos Theta), the check's non-uniform start
        bump.interpolate(lambda x: 0.5 * (3.0 * np.cos(x[0]) ** 2 - 1.0))
        self.bump = bump.x.array.copy()
        # the check: the whole residual at a dead pressure, for SNES
        self.c_v2 = dolfinx.fem.Constant(mesh, 0.0)
        self.c_p = dolfinx.fem.Constant(mesh, 0.0)
        total = energies["mech"] + self.c_v2 * energies["el"] - self.c_p * energies["vol"]
        self.residual = ufl.derivative(total, rho, v)
        self.jacobian = ufl.derivative(self.residual, rho, du)
        self._snes = None

    def set(self, lam):
        self.rho.x.array[:] = lam * self.one

    def vectors(self):
        return {k: dolfinx.fem.assemble_vector(f).array.copy() for k, f in self.F.items()}

    def matrices(self):
        return {k: dolfinx.fem.assemble_matrix(f).to_dense() for k, f in self.K.items()}

    def snes(self, lam, v2, p):
        """The check: PETSc SNES (Newton, basic line search, LU) at the dead pressure p and
        voltage v2 from rho = lam (1 + START P2(cos Theta)); the converged rho, or None."""
        import dolfinx.fem.petsc

        if self._snes is None:
            self._snes = dolfinx.fem.petsc.NonlinearProblem(
                self.residual, self.rho, bcs=[], J=self.jacobian,
                petsc_options_prefix=f"balloon{id(self)}_",
                petsc_options={"snes_type": "newtonls", "snes_linesearch_type": "basic",
                               "snes_rtol": 1e-12, "snes_atol": 1e-13, "snes_stol": 0.0,
                               "snes_max_it": 60, "ksp_type": "preonly", "pc_type": "lu"})
        self.c_v2.value, self.c_p.value = v2, p
        self.rho.x.array[:] = lam * (self.one + START * self.bump)
        self._snes.solve()
        ok = self._snes.solver.getConvergedReason() > 0
        rho = self.rho.x.array.copy()
        return rho if ok and np.all(np.isfinite(rho)) else None

    def pressure(self, lam, v2):
        """pbar at rho = lam from the discrete residual, its derivative along the branch,
        and the residual it leaves."""
        return self._multiplier(lam, lambda F: F["mech"] + v2 * F["el"],
                                lambda F: -F["vol"],
                                lambda K, x: K["mech"] + v2 * K["el"] - x * K["vol"])

    def voltage(self, lam, p):
        """vbar^2 at rho = lam and fixed pbar from the discrete residual, its derivative
        along the branch, and the residual it leaves."""
        return self._multiplier(lam, lambda F: F["mech"] - p * F["vol"],
                                lambda F: F["el"],
                                lambda K, x: K["mech"] + x * K["el"] - p * K["vol"])

    def _multiplier(self, lam, fixed, column, tangent):
        """The multiplier x annulling fixed(F) + x column(F) in least squares at rho = lam,
        the residual it leaves relative to its terms (or to a unit multiplier's term where
        all vanish), and dx/dlam along rho = lam 1 (every state of it a discrete
        equilibrium): K 1 + column dx/dlam = 0 in least squares. Not the bordered tangent
        solve [K, column; V'^T, 0]: at zero net tension (pbar = 0 at the voltage limit) K
        vanishes in every non-uniform direction and that system is singular."""
        self.set(lam)
        F = self.vectors()
        f, col = fixed(F), column(F)
        x = -float(col @ f) / float(col @ col)
        r = f + x * col
        scale = (np.max(np.abs(F["mech"])) + np.max(np.abs(f - F["mech"]))
                 + max(abs(x), 1.0) * np.max(np.abs(col)))
        left = float(np.max(np.abs(r)) / scale)
        K = tangent(self.matrices(), x)
        dx = -float(col @ (K @ self.one)) / float(col @ col)
        return x, dx, left


def root(f, a, b):
    """A zero of f in [a, b] (f(a) f(b) < 0): regula falsi with the Illinois modification,
    the point kept tol/2 inside the bracket, until the bracket is <= XTOL + 4 eps |lam|."""
    fa, fb = f(a), f(b)
    if fa * fb > 0:
        raise RuntimeError(f"no sign change in [{a}, {b}]")
    side = 0
    for _ in range(300):
        tol = XTOL + 4 * np.finfo(float).eps * max(abs(a), abs(b))
        if b - a <= tol:
            return 0.5 * (a + b)
        c = (a * fb - b * fa) / (fb - fa)
        c = min(max(c, a + tol / 2), b - tol / 2)
        fc = f(c)
        if fc == 0:
            return c
        if fa * fc < 0:
            b, fb = c, fc
            if side == -1:
                fa /= 2
            side = -1
        else:
            a, fa = c, fc
            if side == +1:
                fb /= 2
            side = +1
    raise RuntimeError("root finding did not converge")


def first_change(f, lo, hi, sign_from, ok=lambda v: True):
    a, fa = lo, f(lo)
    while a < hi:
        b = min(a + SCAN, hi)
        fb = f(b)
        if sign_from * fa[0] > 0 and sign_from * fb[0] < 0 and ok(fa) and ok(fb):
            return a, b
        a, fa = b, fb
    raise RuntimeError(f"no sign change of the derivative in [{lo}, {hi}]")


def compute(degree, cells, q, jms, vbars, pfixed, lam_grid):
    rows, left, evals = [], 0.0, 0
    for i, Jm in enumerate(jms):
        m = Membrane(degree, cells, Jm)
        top = max(lam_grid[i])

        def P(lam, v2, m=m):
            nonlocal left, evals
            p, dp, res = m.pressure(lam, v2)
            left, evals = max(left, res), evals + 1
            return dp, p

        def Vt(lam, p, m=m):
            nonlocal left, evals
            v2, dv2, res = m.voltage(lam, p)
            left, evals = max(left, res), evals + 1
            return dv2, v2

        if q == "pbar":
            rows += [(Jm, vb, lam, P(lam, vb * vb)[1]) for vb in vbars for lam in lam_grid[i]]
        elif q in ("lam_vmax", "vbar_max"):
            for pf in pfixed:
                a, b = first_change(lambda t, pf=pf: Vt(t, pf), 1.0, top, +1,
                                    ok=lambda v: v[1] > 0)
                lam = root(lambda t, pf=pf: Vt(t, pf)[0], a, b)
                rows.append((Jm, pf, lam if q == "lam_vmax" else math.sqrt(Vt(lam, pf)[1])))
        elif not (q in ("lam_pmin", "pbar_min") and math.isinf(Jm)):
            for vb in vbars:
                def g(t, vb=vb):
                    return P(t, vb * vb)
                a, b = first_change(g, 1.0, top, +1)
                lam = root(lambda t: g(t)[0], a, b)
                if q in ("lam_pmin", "pbar_min"):
                    a, b = first_change(g, b, top, -1)
                    lam = root(lambda t: g(t)[0], a, b)
                rows.append((Jm, vb, lam if q.startswith("lam") else g(lam)[1]))
    return rows, left, evals, m.ndofs


def restarts(degree, cells, jms, vbars, lam_grid) -> dict:
    """The check at the dead pressure of the uniform state: where SNES from the non-uniform
    start lands (back to rho = lam within 1e-9, elsewhere, or no convergence)."""
    n = {"uniform": 0, "other": 0, "failed": 0}
    for i, Jm in enumerate(jms):
        m = Membrane(degree, cells, Jm)
        for vb in vbars:
            for lam in lam_grid[i][::SAMPLE]:
                p = m.pressure(lam, vb * vb)[0]
                rho = m.snes(lam, vb * vb, p)
                n["failed" if rho is None else "uniform"
                  if np.max(np.abs(rho - lam * m.one)) < 1e-9 else "other"] += 1
    return n


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--problem-json", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--label", default="default")
    ap.add_argument("--quantity", default="pbar", choices=QUANTITIES)
    a = ap.parse_args()
    doc = json.loads(Path(a.problem_json).read_text())
    par = doc["spec"]["parameters"]
    jms = [math.inf if j in (None, "inf") else float(j) for j in par["Jm"]["value"]]
    vbars = [float(v) for v in par["vbar"]["value"]]
    pfixed = [float(v) for v in par["pbar_fixed"]["value"]]
    ref = doc["reference"]["pbar"]  # the stretch grid of the curves (not their values)
    grids = dict(zip([math.inf if j is None else float(j) for j in ref["coords"]["Jm"]],
                     ref["along"]["values"], strict=True))
    lam_grid = [[float(x) for x in grids[j]] for j in jms]
    q = a.quantity
    t0 = time.perf_counter()
    runs, notes = [], []
    for degree, cells in SEQUENCE:
        rows, left, evals, ndofs = compute(degree, cells, q, jms, vbars, pfixed, lam_grid)
        runs.append(rows)
        notes.append(f"P{degree} x {cells} ({ndofs} dofs): residual left {left:.1e}")
        print(f"P{degree} x {cells}: {len(rows)} values from {evals} states, residual left "
              f"by the multiplier <= {left:.2e} of its terms, {time.perf_counter() - t0:.1f} s",
              flush=True)
    t1 = time.perf_counter()
    rs = restarts(*SEQUENCE[-1], jms, vbars, lam_grid)
    restart = (f"SNES at the pressure of the uniform state from rho = lam (1 + {START:g} "
               f"P2(cos Theta)), every {SAMPLE}th stretch of the 18 pbar curves "
               f"({sum(rs.values())} states, P{SEQUENCE[-1][0]} x {SEQUENCE[-1][1]}): back "
               f"to the uniform state {rs['uniform']}, another equilibrium {rs['other']}, "
               f"no convergence {rs['failed']}")
    print(f"{restart} ({time.perf_counter() - t1:.1f} s)", flush=True)
    vals = np.array([[r[-1] for r in rows] for rows in runs])
    best = vals[-1]
    change = np.max(np.abs(vals[:-1] - best), axis=0)
    small = np.abs(best) < SMALL  # pbar near its zero crossings: judged absolutely
    rel = float(np.max(change[~small] / np.abs(best[~small]), initial=0.0))
    near0 = float(np.max(change[small], initial=0.0))
    absmax = float(np.max(change))
    print(f"largest change over the sequence: {absmax:.2e} absolute, {rel:.2e} relative "
          f"where |value| >= {SMALL:g}, {near0:.2e} absolute below")
    coords = ("Jm [1],vbar [1],lam [1]" if q == "pbar" else
              "Jm [1],pbar_fixed [1]" if q in ("lam_vmax", "vbar_max") else "Jm [1],vbar [1]")
    out = Path(a.out)
    tmp = out / ".results.csv.tmp"
    with tmp.open("w") as fh:
        fh.write(f"{coords},{q} [1]\n")
        for r, v in zip(runs[-1], best, strict=True):
            cells = ["inf" if math.isinf(r[0]) else repr(float(r[0]))]
            cells += [repr(float(x)) for x in r[1:-1]] + [repr(float(v))]
            fh.write(",".join(cells) + "\n")
    tmp.replace(out / "results.csv")
    degree, cells = SEQUENCE[-1]
    seq = "; ".join(notes)
    what = {"pbar": "pbar at every stretch of the page's grid",
            "lam_pmax": "the first + to - zero of dpbar/dlam",
            "pbar_max": "pbar at the first + to - zero of dpbar/dlam (local maximum)",
            "lam_pmin": "the next - to + zero of dpbar/dlam (Gent)",
            "pbar_min": "pbar at the next - to + zero of dpbar/dlam (local minimum, Gent)",
            "lam_vmax": "the first + to - zero of d(vbar^2)/dlam at fixed pbar with "
                        "vbar^2 > 0",
            "vbar_max": "vbar at the first + to - zero of d(vbar^2)/dlam at fixed pbar "
                        "(voltage limit point)"}[q]
    meta = {
        "quantity": q,
        "code": {"name": "DOLFINx", "version": dolfinx.__version__,
                 "commit_or_release": f"dolfinx-solver-real {dolfinx_solver.__version__} "
                                      f"(packages the DOLFINx {dolfinx_solver.RELEASE} release)",
                 "url": "https://github.com/FEniCS/dolfinx", "license": "LGPL-3.0-or-later"},
        "method": {
            "description": "axisymmetric membrane finite-element model of the sphere on its "
                           "meridian: radial maps rho(Theta) (no tangential displacement), "
                           "lam1 = sqrt(rho^2 + rho'^2)/R, lam2 = rho/R, lam3 = 1/(lam1 lam2);"
                           " UFL energy per reference area H W(I1) (neo-Hookean or Gent) - "
                           "eps Phi^2 lam1^2 lam2^2/(2H) minus the pressure work p V, "
                           "V = (2 pi/3) int rho^3 sin dTheta; residuals and tangents by "
                           "ufl.derivative; stretch control at rho = lam R: the pressure (or "
                           "vbar^2 at fixed pbar) is the multiplier that annuls the discrete "
                           "residual; branch derivatives from the tangent applied to "
                           f"drho/dlam = 1 (least squares); {what}. The uniform inflation "
                           "lies in the finite-element space, so the discrete equilibrium "
                           "reproduces the membrane equations up to quadrature and round-off: "
                           "measured (the residual the multiplier leaves, and a change of at "
                           f"most {absmax:.1e} over the refinement sequence), not assumed. "
                           f"Check by a full nonlinear solve: {restart}",
            "discretisation": f"Lagrange P{degree} for rho on create_interval [0, pi]; "
                              f"quadrature degree {2 * degree + 4} with sin Theta weights",
            "mesh_or_resolution": f"{cells} uniform cells on [0, pi]; sequence {seq}; the "
                                  "coarsest is written: the uniform state is exact on every "
                                  "mesh and refinement adds only round-off (the computed "
                                  "rho' of the constant is ~eps/h, its residual term "
                                  "~eps/h^2 relative: the residual left grows with 1/h^2)",
            "solver": "least-squares multiplier of the assembled residual at the uniform "
                      "state; its branch derivative from K 1 (least squares); extrema and "
                      "limit points bracketed by a scan in lam (step "
                      f"{SCAN:g}) and refined by regula falsi (Illinois) in the bracket",
            "tolerances": f"root finding |bracket| <= {XTOL:g} + 4 eps |lam|; the check's SNES: "
                          "snes_rtol 1e-12, snes_atol 1e-13 (residual), 60 iterations at most",
            "physics_differences": "none (the thin membrane H/R -> 0 of the page; "
                                   "deformations restricted to radial maps, which contain "
                                   "the uniform state)",
        },
    }
    check = {"rtol": max(SAFETY * rel, RTOL_FLOOR)}
    reason = (f"{SAFETY:g} x the largest relative change of the written values over the "
              f"refinement sequence ({seq}: {rel:.1e} relative where |value| >= {SMALL:g}), "
              f"floored at {RTOL_FLOOR:g}")
    if small.any():
        check["atol"] = max(SAFETY * near0, ATOL_FLOOR)
        reason += (f"; atol {SAFETY:g} x the largest absolute change where |value| < "
                   f"{SMALL:g} ({near0:.1e}), floored at {ATOL_FLOOR:g}")
    check["reason"] = reason + (": the floors are the double-precision round-off of the "
                                "same arithmetic (terms up to ~60 near the Gent lock, "
                                "amplified by 1/G <= 30)")
    meta["check"] = check
    (out / "adapter.json").write_text(json.dumps(meta, indent=1))
    print(f"done in {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main()
