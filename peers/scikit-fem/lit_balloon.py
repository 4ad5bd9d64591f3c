"""scikit-fem adapter of lit_balloon: the dielectric-elastomer balloon (thin spherical
neo-Hookean or Gent ideal-dielectric membrane under internal pressure and voltage).

    python peers/run.py scikit-fem lit_balloon --label membrane-p3-pbar -- --quantity pbar
    python peers/scikit-fem/adapter.py lit_balloon --out DIR --quantity lam_pmax  # by hand

Written from the problem page alone (``debench problems lit_balloon --markdown``) with
numpy, scipy and scikit-fem, no debench code: an axisymmetric membrane finite-element model
of the sphere on its meridian.

* Kinematics: the sphere's deformation restricted to radial maps x = rho(Theta) e_r(Theta)
  of the mid-surface (reference radius R = 1, reference polar angle 0 <= Theta <= pi, no
  tangential displacement); meridional stretch lam1 = sqrt(rho^2 + rho'^2), hoop stretch
  lam2 = rho, thickness stretch lam3 = 1/(lam1 lam2) (incompressible, plane stress).
* Energy per 2 pi mu H R^2 (normalised): int [W(I1)/mu - vbar^2/2 lam1^2 lam2^2] sin dTheta
  - pbar/3 int rho^3 sin dTheta, I1 = lam1^2 + lam2^2 + lam3^2, W the neo-Hookean (I1 - 3)/2
  or the Gent -Jm/2 ln(1 - (I1 - 3)/Jm); the electric term is -(1/2) eps (Phi/h)^2 per current
  volume (h = H lam3), i.e. -(1/2) eps Phi^2 lam1^2 lam2^2/H per reference area, which is the
  page's -(1/2) C Phi^2 with C = 4 pi eps R^2 lam^4/H for the uniform sphere.
* Discretisation: rho in Lagrange P2 (``ElementLineP2``) or Pp (``ElementLinePp``) on a
  uniform ``MeshLine`` of [0, pi]; the energy density's gradient in (rho, rho') written out,
  its Hessian by complex step on that gradient at the quadrature points (exact to
  round-off); residual (``LinearForm``) and tangent (``BilinearForm``) assembled with sin
  Theta weights; nothing imposed at the poles (natural conditions).
* Stretch control at rho = lam (the uniform inflation lies in the Lagrange space): pbar is
  the multiplier that annuls the assembled residual F_mech + vbar^2 F_el - pbar V' (least
  squares over the dofs); the residual it leaves is measured (round-off if the uniform
  state is the discrete equilibrium: with rho' = 0 every dof's equation is the same
  pointwise one times int phi_i sin, so quadrature cancels), as is the change over the
  refinement sequence: the discrete equilibrium reproduces the membrane equations up to
  quadrature and round-off, measured, not assumed.
* A genuine nonlinear solve as a check: Newton on the bordered system (rho, pbar) with the
  volume (1/3) int rho^3 sin dTheta prescribed as lam^3 times the discrete volume of the
  unit sphere (pbar its Lagrange multiplier), from the non-uniform start
  rho = lam (1 + 0.001 P2(cos Theta)), pbar = 0, at every 20th stretch of the 18 pbar
  curves; the adapter counts the states it returns to and those it does not (the uniform
  state is not isolated everywhere: at zero net tension the membrane has no stiffness
  against non-uniform meridians, and other radial equilibria may exist at the same
  volume). Its steps are minimum-norm (lstsq, singular values below 1e-12 of the largest
  left out).
* Extrema of pbar at fixed vbar: zeros of dpbar/dlam along the stretch-controlled discrete
  branch rho = lam, from the tangent applied to the branch direction:
  K 1 - dpbar/dlam V' = 0 in least squares (no finite differences; not the bordered
  tangent solve, which is singular where the net tension vanishes: at pbar = 0 and the
  voltage limit the tangent is zero in every non-uniform direction); bracketed by a scan
  (step 0.01), refined by Brent (scipy brentq). Voltage limit at fixed pbar: the same with
  vbar^2 as the multiplier (column F_el), its first + to - zero where vbar^2 > 0.
"""

from __future__ import annotations

import argparse
import math
import sys
import time

import _common
import numpy as np
import scipy.optimize
import skfem
from skfem import Basis, BilinearForm, ElementLineP2, ElementLinePp, LinearForm, MeshLine

PROBLEM = "lit_balloon"
#: the refinement sequence (degree, elements); the last is reported
SEQUENCE = ((2, 8), (2, 32), (3, 16))
SAFETY = 3.0
#: round-off floor of the stated accuracy (double precision, 1/G <= 30 near the Gent lock)
#: (rtol for |value| >= SMALL, atol below SMALL)
FLOOR = {"rtol": 1e-13, "atol": 3e-14}
SMALL = 1e-3
CSTEP = 1e-30
SCAN = 0.01
#: Newton: converged when max |d rho|/lam < STEP_TOL, then POLISH more iterations
STEP_TOL, POLISH = 1e-12, 2
#: singular values below RCOND x the largest are left out of a Newton step (minimum norm)
RCOND = 1e-12
#: amplitude of the non-uniform start rho = lam (1 + START P2(cos Theta)) of the restart
#: experiment, and its sample (every SAMPLE-th stretch of each curve)
START, SAMPLE = 1e-3, 20
QUANTITIES = ("pbar", "lam_pmax", "pbar_max", "lam_pmin", "pbar_min", "lam_vmax", "vbar_max")


def density_gradient(a, b, Jm):
    """d/d(rho, rho') of the normalised energy density W(I1) - v2/2 lam1^2 lam2^2 at
    rho = a, rho' = b (real or complex arrays): (mechanical a, mechanical b, electric a,
    electric b), the electric part per unit v2 = vbar^2."""
    l1sq = a * a + b * b
    l2sq = a * a
    l3sq = 1.0 / (l1sq * l2sq)
    I1 = l1sq + l2sq + l3sq
    dW = 0.5 if math.isinf(Jm) else 0.5 / (1.0 - (I1 - 3.0) / Jm)
    dI1_da = 4.0 * a - l3sq * (2.0 * a / l1sq + 2.0 / a)
    dI1_db = 2.0 * b - l3sq * 2.0 * b / l1sq
    return (dW * dI1_da, dW * dI1_db,
            -0.5 * (2.0 * a * l2sq + 2.0 * a * l1sq), -0.5 * 2.0 * b * l2sq)


@LinearForm
def _residual(v, w):
    s = np.sin(w.x[0])
    return (w["ga"] * v + w["gb"] * v.grad[0]) * s


@BilinearForm
def _tangent(u, v, w):
    s = np.sin(w.x[0])
    return (w["haa"] * u * v + w["hab"] * u.grad[0] * v + w["hba"] * u * v.grad[0]
            + w["hbb"] * u.grad[0] * v.grad[0]) * s


@LinearForm
def _dvolume(v, w):  # d/drho of (1/3) int rho^3 sin
    return w["rho"] ** 2 * v * np.sin(w.x[0])


@BilinearForm
def _d2volume(u, v, w):
    return 2.0 * w["rho"] * u * v * np.sin(w.x[0])


@skfem.Functional
def _volume(w):
    return w["rho"] ** 3 / 3.0 * np.sin(w.x[0])


class Membrane:
    """The discretised meridian: assembly of the residual pieces and the tangent."""

    def __init__(self, degree: int, elements: int):
        mesh = MeshLine(np.linspace(0.0, math.pi, elements + 1))
        elem = ElementLineP2() if degree == 2 else ElementLinePp(degree)
        self.basis = Basis(mesh, elem, intorder=2 * degree + 4)
        self.ndofs = self.basis.N
        # the constant 1 and the start's bump P2(cos Theta) in the element's own dofs
        # (ElementLinePp is hierarchical: 1 at the vertex dofs, 0 at the interior ones)
        one = self.basis.project(lambda x: np.ones_like(x[0]))
        self.one = np.where(np.abs(one) < 1e-9, 0.0, np.where(np.abs(one - 1) < 1e-9, 1.0,
                                                               np.nan))
        if not np.all(np.isfinite(self.one)):
            raise RuntimeError("the constant is not 0/1 in the element's dofs")
        self.bump = self.basis.project(lambda x: 0.5 * (3.0 * np.cos(x[0]) ** 2 - 1.0))
        self.vol1 = self.volume(self.one)

    def pieces(self, rho, Jm):
        """(mechanical force, electric force per v2, V', K_mech, K_el per v2, V'')."""
        f = self.basis.interpolate(rho)
        a, b = f.value, f.grad[0]
        g = density_gradient(a, b, Jm)
        ha = density_gradient(a + 1j * CSTEP, b, Jm)
        hb = density_gradient(a, b + 1j * CSTEP, Jm)
        out = []
        for k in (0, 2):  # mechanical, electric
            out.append(_residual.assemble(self.basis, ga=g[k], gb=g[k + 1]))
        vp = _dvolume.assemble(self.basis, rho=f)
        mats = []
        for k in (0, 2):
            mats.append(_tangent.assemble(
                self.basis, haa=ha[k].imag / CSTEP, hab=hb[k].imag / CSTEP,
                hba=ha[k + 1].imag / CSTEP, hbb=hb[k + 1].imag / CSTEP).toarray())
        vpp = _d2volume.assemble(self.basis, rho=f).toarray()
        return out[0], out[1], vp, mats[0], mats[1], vpp

    def volume(self, rho):
        return _volume.assemble(self.basis, rho=self.basis.interpolate(rho))

    def system(self, rho, Jm, v2=None, p=None, x=0.0):
        """Residual, tangent and multiplier column at rho: with v2 given the multiplier x is
        the pressure (r = F_mech + v2 F_el - x V'), with p given it is v2
        (r = F_mech + x F_el - p V'); also F_mech and V'."""
        fm, fe, vp, km, ke, vpp = self.pieces(rho, Jm)
        if p is None:
            return fm + v2 * fe - x * vp, km + v2 * ke - x * vpp, -vp, fm, vp
        return fm + x * fe - p * vp, km + x * ke - p * vpp, fe, fm, vp

    def uniform(self, lam, Jm, *, v2=None, p=None):
        """The stretch-controlled state rho = lam: the multiplier (pbar, or vbar^2 at fixed
        pbar) that annuls the discrete residual (least squares over the dofs), the residual
        it leaves (max |r| relative to its terms: round-off if the uniform state is the
        discrete equilibrium), and the multiplier's derivative along the branch."""
        rho = lam * self.one
        r0, _, col, fm, _ = self.system(rho, Jm, v2=v2, p=p)
        x = -float(col @ r0) / float(col @ col)
        r, K, col, fm, _ = self.system(rho, Jm, v2=v2, p=p, x=x)
        # the residual left, relative to the size of its terms (or of a unit multiplier's
        # term, where all vanish: lam = 1 without voltage)
        scale = (np.max(np.abs(fm)) + np.max(np.abs(r0 - fm))
                 + max(abs(x), 1.0) * np.max(np.abs(col)))
        left = float(np.max(np.abs(r)) / scale)
        # along the branch rho = lam 1 (each state a discrete equilibrium):
        # K 1 + col dx/dlam = 0, in least squares; not the bordered tangent solve, which is
        # singular where the net tension vanishes (pbar = 0 at the voltage limit: the
        # tangent is zero in every non-uniform direction)
        dx = -float(col @ (K @ self.one)) / float(col @ col)
        return x, dx, left

    def newton(self, lam, Jm, v2):
        """Newton on the bordered system (rho, pbar) at the prescribed volume lam^3 vol(1)
        from the non-uniform start rho = lam (1 + START P2(cos Theta)), pbar = 0;
        minimum-norm steps (lstsq, RCOND). Returns (rho, pbar, iterations)."""
        rho = lam * (self.one + START * self.bump)
        x, n, target = 0.0, self.ndofs, lam ** 3 * self.vol1
        it, small = 0, 0
        while True:
            r, K, col, _, vp = self.system(rho, Jm, v2=v2, x=x)
            A = np.zeros((n + 1, n + 1))
            A[:n, :n], A[:n, n], A[n, :n] = K, col, vp
            rhs = -np.append(r, self.volume(rho) - target)
            d = np.linalg.lstsq(A, rhs, rcond=RCOND)[0]
            rho += d[:n]
            x += d[n]
            it += 1
            step = float(np.max(np.abs(d[:n]))) / lam
            if not np.isfinite(step):
                raise RuntimeError(f"Newton diverged at lam = {lam}")
            small = small + 1 if (small or step < STEP_TOL) else 0
            if small > POLISH:  # converged, then POLISH more steps at round-off
                return rho, x, it
            if it > 60:
                raise RuntimeError(f"Newton did not converge at lam = {lam} (step {step})")


def first_sign_change(f, lo, hi, sign_from, ok=lambda v: True):
    """The first [a, b] in a scan of step SCAN from lo where f (a tuple's [0]) changes
    sign from ``sign_from`` to its opposite (with ok(value) at both ends)."""
    a = lo
    fa = f(a)
    while a < hi:
        b = min(a + SCAN, hi)
        fb = f(b)
        if (sign_from * fa[0] > 0 and sign_from * fb[0] < 0 and ok(fa) and ok(fb)):
            return a, b
        a, fa = b, fb
    raise RuntimeError(f"no sign change of the derivative in [{lo}, {hi}]")


def restarts(model: Membrane, jms, vbars, lam_grid) -> dict:
    """Newton from the non-uniform start at every SAMPLE-th stretch of each pbar curve:
    counts of the states it returns to (max |rho - lam| < 1e-9 and pbar within 1e-12
    relative of the uniform state's), of other equilibria it lands on, of failures."""
    n = {"uniform": 0, "other": 0, "failed": 0}
    for i, Jm in enumerate(jms):
        for vb in vbars:
            for lam in lam_grid[i][::SAMPLE]:
                p0 = model.uniform(lam, Jm, v2=vb * vb)[0]
                try:
                    rho, p, _ = model.newton(lam, Jm, vb * vb)
                except (RuntimeError, np.linalg.LinAlgError):
                    n["failed"] += 1
                    continue
                same = (np.max(np.abs(rho - lam * model.one)) < 1e-9
                        and abs(p - p0) <= 1e-12 * max(abs(p0), 1.0))
                n["uniform" if same else "other"] += 1
    return n


def compute(model: Membrane, quantity: str, jms, vbars, pfixed, lam_grid):
    """Rows (coordinates..., value), the largest residual left at the uniform states, the
    number of states evaluated."""
    rows, worst, count = [], 0.0, 0

    def state(lam, Jm, **kw):
        nonlocal worst, count
        x, dx, left = model.uniform(lam, Jm, **kw)
        worst, count = max(worst, left), count + 1
        return x, dx

    for i, Jm in enumerate(jms):
        top = max(lam_grid[i])
        if quantity == "pbar":
            for vb in vbars:
                for lam in lam_grid[i]:
                    rows.append((Jm, vb, lam, state(lam, Jm, v2=vb * vb)[0]))
            continue
        if quantity in ("lam_vmax", "vbar_max"):
            for pf in pfixed:
                def dv(lam, Jm=Jm, pf=pf):
                    x, dx = state(lam, Jm, p=pf)
                    return dx, x
                a, b = first_sign_change(dv, 1.0, top, +1, ok=lambda v: v[1] > 0)
                lam = scipy.optimize.brentq(lambda t: dv(t)[0], a, b, xtol=1e-15,
                                            rtol=1e-15, maxiter=200)
                x = state(lam, Jm, p=pf)[0]
                rows.append((Jm, pf, lam if quantity == "lam_vmax" else math.sqrt(x)))
            continue
        if quantity in ("lam_pmin", "pbar_min") and math.isinf(Jm):
            continue  # no minimum without stiffening (the page: leave those rows out)
        for vb in vbars:
            def dp(lam, Jm=Jm, vb=vb):
                x, dx = state(lam, Jm, v2=vb * vb)
                return dx, x
            a, b = first_sign_change(dp, 1.0, top, +1)
            lam = scipy.optimize.brentq(lambda t: dp(t)[0], a, b, xtol=1e-15, rtol=1e-15,
                                        maxiter=200)
            if quantity in ("lam_pmin", "pbar_min"):
                a, b = first_sign_change(dp, b, top, -1)
                lam = scipy.optimize.brentq(lambda t: dp(t)[0], a, b, xtol=1e-15,
                                            rtol=1e-15, maxiter=200)
            x = state(lam, Jm, v2=vb * vb)[0]
            rows.append((Jm, vb, lam if quantity.startswith("lam") else x))
    return rows, worst, count


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    extra = argparse.ArgumentParser(add_help=False)
    extra.add_argument("--quantity", default="pbar", choices=QUANTITIES)
    own, rest = extra.parse_known_args(argv)
    a = _common.arguments(PROBLEM, rest)
    doc = _common.problem_json(a.problem_json)
    q = own.quantity
    if doc:
        par = doc["spec"]["parameters"]
        jms = [math.inf if j in (None, "inf") else float(j) for j in par["Jm"]["value"]]
        vbars = [float(v) for v in par["vbar"]["value"]]
        pfixed = [float(v) for v in par["pbar_fixed"]["value"]]
        ref = doc["reference"]["pbar"]
        grid_jm = [math.inf if j is None else float(j) for j in ref["coords"]["Jm"]]
        grids = dict(zip(grid_jm, ref["along"]["values"], strict=True))
        lam_grid = [[float(x) for x in grids[j]] for j in jms]
    else:  # the page's parameters and window, 401 uniform stretches
        jms, vbars = [math.inf, 97.2, 50.0], [0.0, 0.1, 0.2, 0.3, 0.4, 0.5]
        pfixed = [0.0, 0.25, 0.5, 0.75, 1.0, 1.2]
        tops = [8.0, 1 + 0.98 * (7.0781 - 1), 1 + 0.98 * (5.1477 - 1)]
        lam_grid = [np.linspace(1.0, t, 401).tolist() for t in tops]
    runs, notes = [], []
    for degree, elements in SEQUENCE:  # the last model is the reported one
        t0 = time.perf_counter()
        model = Membrane(degree, elements)
        rows, left, count = compute(model, q, jms, vbars, pfixed, lam_grid)
        runs.append(rows)
        notes.append(f"P{degree} x {elements} ({model.ndofs} dofs): residual left "
                     f"{left:.1e}")
        print(f"P{degree} x {elements}: {len(rows)} values from {count} states, residual "
              f"left by the multiplier <= {left:.2e} of its terms, "
              f"{time.perf_counter() - t0:.1f} s", flush=True)
    t0 = time.perf_counter()
    with np.errstate(all="ignore"):
        rs = restarts(model, jms, vbars, lam_grid)
    restart = (f"Newton from rho = lam (1 + {START:g} P2(cos Theta)) at every {SAMPLE}th "
               f"stretch of the 18 pbar curves ({sum(rs.values())} states, P{degree} x "
               f"{elements}): back to the uniform state {rs['uniform']}, another "
               f"equilibrium {rs['other']}, no convergence {rs['failed']}")
    print(f"{restart} ({time.perf_counter() - t0:.1f} s)", flush=True)
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
    out_rows = [("inf" if math.isinf(r[0]) else r[0], *r[1:-1], float(v))
                for r, v in zip(runs[-1], best, strict=True)]
    _common.write_results(a.out, f"{coords},{q} [1]", out_rows)
    seq = "; ".join(notes)
    check = {"rtol": max(SAFETY * rel, FLOOR["rtol"])}
    reason = (f"{SAFETY:g} x the largest relative change of the reported values over the "
              f"refinement sequence ({seq}: {rel:.1e} relative where |value| >= {SMALL:g}), "
              f"floored at {FLOOR['rtol']:g}")
    if small.any():
        check["atol"] = max(SAFETY * near0, FLOOR["atol"])
        reason += (f"; atol {SAFETY:g} x the largest absolute change where |value| < "
                   f"{SMALL:g} ({near0:.1e}), floored at {FLOOR['atol']:g}")
    check["reason"] = reason + (": the floors are the double-precision round-off of the "
                                "same arithmetic (terms up to ~60 near the Gent lock, "
                                "amplified by 1/G <= 30)")
    what = {"pbar": "the pressure of the stretch-controlled equilibrium at every stretch of "
                    "the page's grid",
            "lam_pmax": "the stretch where dpbar/dlam = 0 first changes sign from + to -",
            "pbar_max": "pbar at that stretch (the local maximum)",
            "lam_pmin": "the stretch of the next - to + zero of dpbar/dlam (Gent)",
            "pbar_min": "pbar at that stretch (the local minimum, Gent)",
            "lam_vmax": "the stretch where d(vbar^2)/dlam at fixed pbar first changes sign "
                        "from + to - with vbar^2 > 0",
            "vbar_max": "vbar at that stretch (the voltage limit point)"}[q]
    _common.write_adapter_json(a.out, quantity=q, method={
        "description": "axisymmetric membrane finite-element model of the sphere on its "
                       "meridian: radial maps rho(Theta) of the mid-surface (no tangential "
                       "displacement), lam1 = sqrt(rho^2 + rho'^2)/R, lam2 = rho/R, "
                       "lam3 = 1/(lam1 lam2); energy per reference area H W(I1) (neo-Hookean "
                       "or Gent) - eps Phi^2 lam1^2 lam2^2/(2H) (the -(1/2) eps (Phi/h)^2 per "
                       "current volume) minus the dead-pressure work p V, "
                       "V = (2 pi/3) int rho^3 sin dTheta; stretch control by the prescribed "
                       "volume, the pressure its Lagrange multiplier (vbar^2 the "
                       "multiplier at fixed pbar), evaluated at rho = lam R as the multiplier "
                       f"that annuls the assembled residual; {what}. The uniform inflation "
                       "lies in the finite-element space, so the discrete equilibrium "
                       "reproduces the membrane equations up to quadrature and round-off: "
                       "measured, not assumed (the residual the multiplier leaves is listed "
                       "per discretisation; the values change by at most "
                       f"{absmax:.1e} over the refinement sequence). Check by a full "
                       f"nonlinear solve: {restart} (the uniform state is not isolated "
                       "where the net tension vanishes; the quantities are those of the "
                       "uniform branch)",
        "discretisation": f"Lagrange P{degree} (skfem "
                          + ("ElementLineP2" if degree == 2 else f"ElementLinePp({degree})")
                          + f") for rho on [0, pi]; Gauss quadrature of order {2 * degree + 4}"
                          " with sin Theta weights; the energy density's gradient written "
                          "out, its Hessian by complex step (step 1e-30, exact to "
                          "round-off); extrema: derivatives of the multiplier along the "
                          "uniform branch from the tangent applied to drho/dlam = 1 (no "
                          "finite differences)",
        "mesh_or_resolution": f"uniform MeshLine of {elements} elements on [0, pi]; sequence "
                              f"{seq}",
        "solver": "multiplier: least squares of the assembled residual at rho = lam R; "
                  "extrema and limit points: bracketed by a scan in lam (step 0.01), then "
                  "scipy brentq on the branch derivative; the check: Newton on the "
                  "bordered system (rho, pbar) with minimum-norm steps (numpy lstsq, rcond "
                  f"{RCOND:g})",
        "tolerances": "brentq xtol 1e-15, rtol 1e-15; check Newton: max |d rho|/lam < "
                      f"{STEP_TOL:g}, then {POLISH} more iterations (at round-off)",
        "physics_differences": "none (the thin membrane H/R -> 0 of the page; deformations "
                               "restricted to radial maps, which contain the uniform state)"},
        check=check,
        code_version=skfem.__version__)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
