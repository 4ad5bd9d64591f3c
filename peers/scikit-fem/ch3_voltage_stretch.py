"""scikit-fem adapter of ch3_voltage_stretch: the consistent membrane model of the
pre-stretched circular actuator by 1D finite elements in the radial coordinate.

    python peers/run.py scikit-fem ch3_voltage_stretch            # in the pinned venv
    python peers/scikit-fem/adapter.py ch3_voltage_stretch --out DIR   # by hand

Model (the problem page): the passive Gent annulus R_A = 1 <= R <= R_B = 15 (incompressible,
plane stress, mu = 1) has the energy int W(l1, l2) R dR with l1 = r', l2 = r/R; its weak
form int (T1 v' + T2 v/R) R dR = 0 is the membrane balance d(R T1)/dR = T2. The deformed
radius r(R) is the unknown (Lagrange elements of order p on a MeshLine graded towards
R_A), with r(R_A) = lambda_a, r(R_B) = lamP R_B, solved by Newton along lambda_a from the
homogeneous pre-stretch r = lamP R. T1_B(R_A) is the reaction of the inner Dirichlet dof
(the weak form's boundary term -R_A T1(R_A): superconvergent, no derivative of the
discrete solution), and Phibar^2 = (s(lambda_a) - lambda_a T1_B(R_A)) / (lambda_a^4 K),
s = (lam^2 - lam^-4)/(1 - (2 lam^2 + lam^-4 - 3)/Jm), K = 1 + c (5 lam/2 - 2).
"""

from __future__ import annotations

import _common
import numpy as np
import skfem
from skfem import (
    Basis,
    BilinearForm,
    ElementLineP2,
    ElementLinePp,
    LinearForm,
    MeshLine,
    condense,
    solve,
)

PROBLEM = "ch3_voltage_stretch"
#: the page's parameters (used when no --problem-json is given)
DEFAULTS = {"Jm": 120.0, "radius_ratio": 15.0,
            "lamP": [1.1, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0],
            "c": [0.0, -0.02, -0.04, -0.053, -0.06, -0.08, -0.1]}
#: default discretisation: order and elements (the convergence study in the README and
#: --study: changes of Phibar below 1e-12 between this and twice the elements)
ORDER, ELEMENTS, GRADING = 4, 48, 4.0
#: Newton stops when the increment is below this fraction of the outer radius
NEWTON_RTOL = 1e-13
MAX_NEWTON = 30
#: step halvings of lambda_a allowed where Newton fails from the last solution
MAX_HALVINGS = 12
#: |Phibar^2| below this (relative to s) is zero: s - lam T1 cancels at lambda_a = lamP
ROUND_OFF = 1e-11


def gent(l1, l2, Jm):
    """Plane-stress incompressible Gent membrane per mu: T1 = dW/dl1, T2 = dW/dl2 and the
    second derivatives W11, W12, W22 of W = -(Jm/2) ln(1 - (I - 3)/Jm),
    I = l1^2 + l2^2 + (l1 l2)^-2."""
    i = l1**2 + l2**2 + (l1 * l2) ** -2
    g = 1 - (i - 3) / Jm
    if np.any(g <= 0) or np.any(l1 <= 0) or np.any(l2 <= 0):
        raise FloatingPointError("state outside the Gent domain (lock or l <= 0)")
    wi, wii = 0.5 / g, 0.5 / (Jm * g**2)
    i1 = 2 * l1 - 2 * l1**-3 * l2**-2
    i2 = 2 * l2 - 2 * l1**-2 * l2**-3
    i11 = 2 + 6 * l1**-4 * l2**-2
    i22 = 2 + 6 * l1**-2 * l2**-4
    i12 = 4 * l1**-3 * l2**-3
    return (wi * i1, wi * i2, wii * i1 * i1 + wi * i11, wii * i1 * i2 + wi * i12,
            wii * i2 * i2 + wi * i22)


@LinearForm
def residual(v, w):
    R = w.x[0]
    t1, t2, *_ = gent(w.r.grad[0], w.r / R, w.Jm)
    return (t1 * v.grad[0] + t2 * v / R) * R


@BilinearForm
def tangent(u, v, w):
    R = w.x[0]
    _, _, w11, w12, w22 = gent(w.r.grad[0], w.r / R, w.Jm)
    return (w11 * u.grad[0] * v.grad[0] + w12 * (u.grad[0] * v + u * v.grad[0]) / R
            + w22 * u * v / R**2) * R


class Annulus:
    """The discretised annulus: r(R) for a prescribed lambda_a at fixed lamP."""

    def __init__(self, lamP: float, Jm: float, ratio: float, order: int = ORDER,
                 elements: int = ELEMENTS, grading: float = GRADING):
        s = np.linspace(0.0, 1.0, elements + 1)
        nodes = 1.0 + (ratio - 1.0) * np.expm1(grading * s) / np.expm1(grading)
        element = ElementLineP2() if order == 2 else ElementLinePp(order)  # hierarchical
        self.basis = Basis(MeshLine(nodes), element, intorder=2 * order + 2)
        self.inner = int(self.basis.get_dofs(lambda x: np.isclose(x[0], 1.0)).flatten()[0])
        self.outer = int(self.basis.get_dofs(lambda x: np.isclose(x[0], ratio)).flatten()[0])
        self.D = np.array([self.inner, self.outer])
        self.lamP, self.Jm, self.ratio = lamP, Jm, ratio
        self.r = self.basis.project(lambda x: lamP * x[0])  # the homogeneous pre-stretch
        self.history: list[tuple[float, np.ndarray]] = [(lamP, self.r.copy())]

    def _system(self, r):
        w = self.basis.interpolate(r)
        return (tangent.assemble(self.basis, r=w, Jm=self.Jm),
                residual.assemble(self.basis, r=w, Jm=self.Jm))

    def solve(self, lam_a: float, depth: int = 0) -> float:
        """T1_B(R_A) at r(R_A) = lam_a: Newton from the last solution; where it fails
        (predictor outside the Gent domain, no convergence) the step from the last
        solved stretch is halved, at most MAX_HALVINGS times, then RuntimeError."""
        try:
            return self._newton(lam_a)
        except (FloatingPointError, RuntimeError):
            if depth >= MAX_HALVINGS:
                raise RuntimeError(f"no solution at lambda_a = {lam_a}, lamP = "
                                   f"{self.lamP} after {depth} step halvings") from None
            self.solve(0.5 * (self.history[-1][0] + lam_a), depth + 1)
            return self.solve(lam_a, depth + 1)

    def _newton(self, lam_a: float) -> float:
        """Newton for r with r(R_A) = lam_a (predictor: the secant through the last two
        solutions); returns T1_B(R_A). Raises if Newton does not converge."""
        (l0, r0), (l1, r1) = (self.history[-2] if len(self.history) > 1
                              else self.history[-1]), self.history[-1]
        r = r1 + (r1 - r0) * ((lam_a - l1) / (l1 - l0) if l1 != l0 else 0.0)
        r[self.inner], r[self.outer] = lam_a, self.lamP * self.ratio
        for _ in range(MAX_NEWTON):
            K, f = self._system(r)
            dr = solve(*condense(K, -f, D=self.D))
            step = 1.0
            while True:  # backtrack into the Gent domain
                try:
                    self._system(r + step * dr)
                    break
                except FloatingPointError:
                    step *= 0.5
                    if step < 1e-8:
                        raise RuntimeError(f"Newton left the Gent domain at lambda_a = "
                                           f"{lam_a}, lamP = {self.lamP}") from None
            r = r + step * dr
            if step == 1.0 and np.max(np.abs(dr)) <= NEWTON_RTOL * self.lamP * self.ratio:
                _, f = self._system(r)
                self.r = r
                self.history = [self.history[-1], (lam_a, r.copy())]
                return float(-f[self.inner])  # reaction = -R_A T1(R_A), R_A = 1
        raise RuntimeError(f"Newton did not converge at lambda_a = {lam_a}, lamP = "
                           f"{self.lamP} in {MAX_NEWTON} iterations")


def s_circle(lam, Jm):
    """True radial stress per mu of the equibiaxial Gent circle A (Eq. 3.30, no field)."""
    return (lam**2 - lam**-4) / (1 - (2 * lam**2 + lam**-4 - 3) / Jm)


def lock_stretch(Jm: float) -> float:
    """The equibiaxial Gent lock: 2 lam^2 + lam^-4 - 3 = Jm (Newton from sqrt(Jm/2))."""
    lam = np.sqrt((Jm + 3) / 2)
    for _ in range(50):
        f = 2 * lam**2 + lam**-4 - 3 - Jm
        lam_new = lam - f / (4 * lam - 4 * lam**-5)
        if abs(lam_new - lam) <= 1e-15 * lam:
            return float(lam_new)
        lam = lam_new
    raise RuntimeError("lock stretch: Newton did not converge")


def curve(lamP, stretches, cs, Jm, ratio, **disc):
    """Phibar at every stretch (increasing from lamP) and c: array (len(cs), len(stretches)),
    NaN where K <= 0."""
    ann = Annulus(lamP, Jm, ratio, **disc)
    out = np.full((len(cs), len(stretches)), np.nan)
    for j, lam in enumerate(stretches):
        t1 = ann.solve(lam)
        num = s_circle(lam, Jm) - lam * t1
        if abs(num) <= ROUND_OFF * abs(s_circle(lam, Jm)):
            num = 0.0
        if num < 0:
            raise RuntimeError(f"Phibar^2 < 0 at lambda_a = {lam}, lamP = {lamP}: "
                               f"{num}")
        for i, c in enumerate(cs):
            k = 1 + c * (2.5 * lam - 2)
            if k > 0:
                out[i, j] = np.sqrt(num / (lam**4 * k))
    return out


def grid(doc, params):
    """The stretches of each lamP: the reference's own (from --problem-json), else 300
    points from lamP to 0.999 lam_lock (1 - 2e-6), the page's stored range."""
    if doc is not None:
        ref = doc["reference"]["phibar"]
        along = np.asarray(ref["along"]["values"], dtype=float)
        return {lp: along[i][np.isfinite(along[i])] for i, lp in
                enumerate(ref["coords"]["lamP"])}
    top = 0.999 * lock_stretch(params["Jm"]) * (1 - 2e-6)
    return {lp: np.linspace(lp, top, 300) for lp in params["lamP"]}


def parameters(doc):
    if doc is None:
        return dict(DEFAULTS)
    spec = {p["name"]: p["value"] for p in _common.spec_parameters(doc)}
    return {k: spec[k] for k in DEFAULTS}


def compute(doc, **disc):
    """Rows (lamP, c, lambda_a, phibar) of every curve, K <= 0 points left out."""
    params = parameters(doc)
    rows = []
    for lamP, lams in grid(doc, params).items():
        ph = curve(lamP, lams, params["c"], params["Jm"], params["radius_ratio"], **disc)
        for i, c in enumerate(params["c"]):
            rows += [(lamP, c, float(x), float(y)) for x, y in zip(lams, ph[i], strict=True)
                     if np.isfinite(y)]
    return rows


def main(argv=None):
    a = _common.arguments(PROBLEM, argv)
    doc = _common.problem_json(a.problem_json)
    fine = dict(order=ORDER, elements=2 * ELEMENTS, grading=GRADING)
    rows = compute(doc)
    ref_rows = compute(doc, **fine)
    diff = max(abs(r[3] - q[3]) for r, q in zip(rows, ref_rows, strict=True))
    _common.write_results(a.out, "lamP [1],c [1],lambda_a [1],phibar [1]", rows)
    _common.write_adapter_json(a.out, quantity="phibar", method={
        "description": "consistent membrane model of the pre-stretched actuator: Gent annulus "
                       "B by 1D finite elements in the reference radius (weak form of "
                       "d(R T1)/dR = T2, unknown the deformed radius r(R)), circle A "
                       "homogeneous; Phibar from the radial force balance at R_A with "
                       "T1_B(R_A) the reaction of the inner Dirichlet dof",
        "discretisation": f"Lagrange ElementLinePp({ORDER}) on MeshLine, {ELEMENTS} "
                          f"elements graded exponentially towards R_A (factor {GRADING}); "
                          f"quadrature order {2 * ORDER + 2}",
        "mesh_or_resolution": f"{ELEMENTS} elements on 1 <= R <= 15; stretch control along "
                              "the reference grid of lambda_a (300 points per lamP)",
        "solver": "Newton on r(R) (skfem condense + solve, scipy sparse direct), secant "
                  "predictor along lambda_a, backtracking into the Gent domain",
        "tolerances": f"Newton increment <= {NEWTON_RTOL} x outer radius; max |Phibar "
                      f"change| at {2 * ELEMENTS} elements: {diff:.2e}",
        "physics_differences": "none"},
        check={"atol": max(10 * diff, 1e-12),
               "reason": f"10 x the largest change of Phibar when the elements are doubled "
                         f"({diff:.2e}) at every point"},
        code_version=skfem.__version__)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
