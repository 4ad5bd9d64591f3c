"""Derived Chapter 3 quantities: states at a given voltage, thresholds, failure sweeps.

Definitions (catalogued as ch3.assumption.* entries):

* *pull-in suppressed* (Sec. 3.5.2): the voltage-stretch curve Phibar(lambda) has no
  interior local maximum on (lamP, lambda_LoT], i.e. ``min dPhibar^2/dlambda >= 0`` there
  (``definition="before_loss_of_tension"``, the thesis' "curves terminated at loss of
  tension", Sec. 3.5.3). The alternative ``definition="monotonic"`` asks for no local
  maximum on the whole traced branch (the local maximum and minimum merge: a cusp).
* the stretch at a voltage: the first (stable) solution on the rising branch.
"""

from __future__ import annotations

import math

import numpy as np
from debench.models import validation as v
from debench.models.errors import ConvergenceError
from debench.models.numerics.newton import SCALAR_STEP_RTOL
from debench.models.numerics.roots import bracketed_root
from scipy.interpolate import CubicHermiteSpline

from . import circle_a
from .actuator import Branch, _branches_gen, branch, curves
from .lockstep import run
from .params import Annulus, CircularActuator
from .shooting import DEFAULT_STEPS, _interface_state, _interface_state_gen, q_for_stretch

DEFINITIONS = ("before_loss_of_tension", "monotonic")
#: absolute tolerance of the outer brentq searches over lamP or c (values printed to
#: 2-3 significant digits; 1e-10 is far below that and above the ~1e-9 relative
#: discretisation error of the inner solves, see test_ch3_solvers)
OUTER_XTOL = 1e-10


def dphibar2_dlam(br: Branch, c: float) -> np.ndarray:
    """d(Phibar^2)/d lambda on the branch grid (exact q-derivatives, complex step).

    ``c`` finite, with the factor K = 1 + c(5 lam/2 - 2) of (3.30) > 0 on the whole
    branch (trace the branch with a smaller ``lam_end`` otherwise).
    """
    v.instance("br", br, Branch)
    v.finite("c", c)
    K = circle_a._K(br.lam, c)
    if not np.all(K > 0):
        raise ValueError(f"c = {c} makes K = 1 + c(5 lam/2 - 2) of (3.30) non-positive at "
                         f"lam >= {(2 - 1 / c) / 2.5:.6g} on this branch (Phibar undefined "
                         f"there): trace the branch with lam_end below it")
    return _dphibar2_dlam(br, c)


def dphibar2_dlam_continued(br: Branch, c: float) -> np.ndarray:
    """d(Phibar^2)/d lambda at every point of the branch grid, including the points where
    the factor K = 1 + c(5 lam/2 - 2) of (3.30) is not positive.

    Where K > 0 the values are those of :func:`dphibar2_dlam`. Where K <= 0 no real
    voltage holds circle A (Phibar is undefined, the curves end at the ``permittivity``
    event) and the values are those of the expression Phibar^2 = (s - lam T1)/(lam^4 K)
    continued past its pole at K = 0 (inf where K = 0 on a grid point). A test helper,
    not a physical quantity there: the pull-in residual of the failure-event tests is
    scaled by the largest finite slope along the whole traced branch. ``c`` finite.
    """
    v.instance("br", br, Branch)
    v.finite("c", c)
    return _dphibar2_dlam(br, c)     # K = 0 -> inf, as documented


def _dphibar2_dlam(br: Branch, c: float) -> np.ndarray:
    h = 1e-30
    with np.errstate(divide="ignore", invalid="ignore"):  # K = 0 -> inf, masked by callers
        p2c = circle_a._p2(br.lam + 1j * h * br.dlam, br.T1 + 1j * h * br.dT1,
                                      c, br.annulus.law)
    return (p2c.imag / h) / br.dlam


@v.finite_result
def state_at_voltage(br: Branch, c: float, phibar: float) -> dict:
    """Circle-A stretch and interface state at a given Phibar on the rising branch.

    Returns a dict with lam (= lambda^(A) = lambda_2^(B)(R_A)), lam1B (lambda_1^(B)(R_A)),
    lam3A = lam^-2, lam3B = 1/(lam1B lam), q. ``c`` finite (K(lamP) > 0), ``phibar``
    finite and >= 0; ValueError if Phibar is not reached on the branch.
    """
    v.instance("br", br, Branch)
    v.nonnegative("phibar", phibar)
    CircularActuator(br.annulus, c=v.finite("c", c))
    return _states_at_voltage(br, [c], phibar)[0]


def _states_at_voltage(br: Branch, cs, phibar: float) -> list[dict]:
    """:func:`state_at_voltage` for several c on one branch, in one vectorised iteration
    (see :func:`states_at_voltage_many`)."""
    cs = list(cs)
    return _states_at_voltage_many([br] * len(cs), cs, [phibar] * len(cs))


def _listed(name: str, x) -> list:
    """``x`` (a sequence, not a string) as a list; TypeError naming ``name`` otherwise."""
    if isinstance(x, str | bytes) or not hasattr(x, "__iter__"):
        raise TypeError(f"{name} must be a sequence, got {x!r:.60}")
    return list(x)


@v.finite_result
def states_at_voltage_many(brs, cs, phibars) -> list[dict]:
    """:func:`state_at_voltage` for the triples ``(brs[k], cs[k], phibars[k])``, in one
    vectorised iteration.

    The branches may differ in the pre-stretch and the equilibrium variant (same R_B/R_A,
    Jm and RK4 steps, ValueError otherwise): their shooting integrations are done
    together, with per-trajectory pre-stretch and balance. Every triple follows exactly
    the iteration of :func:`state_at_voltage` (same bracket, same safeguarded Newton
    steps, same stopping rule) and has its argument checks: ``brs``, ``cs``, ``phibars``
    sequences of one length, every ``cs[k]`` finite with K(lamP) > 0, every
    ``phibars[k]`` finite and >= 0. ValueError if a Phibar is not reached,
    ConvergenceError if an iteration does not converge.
    """
    brs, cs, phibars = (_listed(n, x) for n, x in
                        (("brs", brs), ("cs", cs), ("phibars", phibars)))
    if not len(brs) == len(cs) == len(phibars):
        raise ValueError(f"brs, cs and phibars must have one length, got {len(brs)}, "
                         f"{len(cs)} and {len(phibars)}")
    for br, c, phibar in zip(brs, cs, phibars, strict=True):
        v.instance("brs[k]", br, Branch)
        v.nonnegative("phibars[k]", phibar)
        CircularActuator(br.annulus, c=v.finite("cs[k]", c))
    return _states_at_voltage_many(brs, cs, phibars)


def _states_at_voltage_many(brs, cs, phibars) -> list[dict]:
    """:func:`states_at_voltage_many` without its argument checks (callers validate)."""
    if not brs:
        return []
    return run(_states_at_voltage_gen(brs, cs, phibars))


def _states_at_voltage_gen(brs, cs, phibars):
    """:func:`states_at_voltage_many` (non-empty ``brs``, checked arguments) as a
    :func:`~debench.models.circular.lockstep.lockstep` solver."""
    an0, steps = brs[0].annulus, brs[0].steps
    if any((b.annulus.radius_ratio, b.annulus.law, b.steps) != (an0.radius_ratio, an0.law, steps)
           for b in brs):
        raise ValueError("branches must differ only in lamP and equilibrium")
    law = an0.law
    cs = np.asarray(cs, float)
    phibars = np.asarray(phibars, float)
    lamP = np.array([b.annulus.lamP for b in brs], float)
    mem = np.array([b.annulus.equilibrium == "membrane" for b in brs])
    a, b, fa, fb = (np.empty(cs.size) for _ in range(4))
    for k, (br, c, phibar) in enumerate(zip(brs, cs, phibars, strict=True)):
        with np.errstate(divide="ignore", invalid="ignore"):  # K <= 0: NaN, no crossing
            p2 = np.where(circle_a._K(br.lam, c) > 0, circle_a._p2(br.lam, br.T1, c, law),
                          np.nan)
        f = p2 - phibar**2
        idx = np.nonzero((f[:-1] < 0) & (f[1:] >= 0))[0]
        if idx.size == 0:
            raise ValueError(f"Phibar = {phibar} is not reached on the traced branch "
                             f"(max {np.sqrt(np.nanmax(p2)):.4g})")
        j = idx[0]
        a[k], b[k], fa[k], fb[k] = br.q[j + 1], br.q[j], f[j + 1], f[j]
    q = b - fb * (b - a) / (fb - fa)
    done = np.zeros(cs.size, bool)
    for _ in range(60):
        act = np.nonzero(~done)[0]
        if not act.size:
            break
        st = yield from _interface_state_gen(an0, q[act], steps=steps, lamP=lamP[act],
                                             membrane=mem[act])
        p2c = circle_a._p2(st.lam_c, st.T1_c, cs[act], law)
        r, dr = p2c.real - phibars[act]**2, p2c.imag / 1e-30
        zero = r == 0
        done[act[zero]] = True
        act, r, dr = act[~zero], r[~zero], dr[~zero]
        lower = np.sign(r) == np.sign(fa[act])
        a[act] = np.where(lower, q[act], a[act])
        fa[act] = np.where(lower, r, fa[act])
        b[act] = np.where(lower, b[act], q[act])
        fb[act] = np.where(lower, fb[act], r)
        qn = q[act] - r / dr
        inside = (np.minimum(a[act], b[act]) < qn) & (qn < np.maximum(a[act], b[act]))
        qn = np.where(inside, qn, 0.5 * (a[act] + b[act]))
        done[act[np.abs(qn - q[act]) <= 1e-15 * np.abs(q[act])]] = True
        q[act] = qn
    else:
        if not done.all():
            raise ConvergenceError(f"state_at_voltage: no convergence for Phibar = "
                                   f"{phibars[~done]}")
    st = yield from _interface_state_gen(an0, q, steps=steps, lamP=lamP, membrane=mem)
    return [{"lam": float(lam), "lam1B": float(lam1), "lam3A": float(lam) ** -2,
             "lam3B": 1 / (float(lam1) * float(lam)), "q": float(qq)}
            for lam, lam1, qq in zip(st.lam, st.lam1, q, strict=True)]


def loss_of_tension_stretch(br: Branch) -> float:
    """Stretch at which T1^(B)(R_A) = 0 (sigma1^(A) = 0); independent of c."""
    v.instance("br", br, Branch)
    cv = curves(br, [0.0])[0]
    ev = cv.events["loss_of_tension"]
    if ev is None:
        raise ValueError(f"no loss of tension on the traced branch of {br.annulus}")
    return ev.lam


def min_slope(br: Branch, c: float, definition: str = "before_loss_of_tension",
              lam_lot: float | None = None) -> float:
    """The minimum of d(Phibar^2)/d lambda that decides whether pull-in is suppressed on
    the curve of ``c`` (Sec. 3.5.2): suppressed if and only if it is >= 0.

    Taken over the grid points of ``br`` beyond lamP where the factor
    K = 1 + c(5 lam/2 - 2) of (3.30) is positive (Phibar defined) and, for
    ``definition="before_loss_of_tension"``, up to the loss of tension: ``lam_lot``, the
    located loss-of-tension stretch when the branch is traced up to it, else the grid
    points before the first T1 <= 0. ``definition="monotonic"`` takes the whole branch
    (``lam_lot`` unused). :func:`pullin_c_threshold` and
    :func:`pullin_suppression_prestretch` find its zero in c and in lamP. ``c`` finite,
    ``lam_lot`` None or finite and > 0; ValueError when no grid point qualifies.
    """
    v.instance("br", br, Branch)
    v.finite("c", c)
    v.choice("definition", definition, DEFINITIONS)
    if lam_lot is not None:
        lam_lot = v.positive("lam_lot", lam_lot)
    return _min_slope(br, c, definition, lam_lot)


def _min_slope(br: Branch, c: float, definition: str, lam_lot: float | None) -> float:
    """:func:`min_slope` without its argument checks."""
    with np.errstate(divide="ignore", invalid="ignore"):  # K = 0 -> inf, masked below
        d = _dphibar2_dlam(br, c)
    # only where the permittivity factor K of (3.30) is positive (Phibar finite)
    mask = np.isfinite(d) & (br.lam > br.annulus.lamP) & (
        circle_a._K(br.lam, c) > 0)
    if definition == "before_loss_of_tension":
        if lam_lot is not None:   # branch traced up to the located loss of tension
            mask &= br.lam <= lam_lot * (1 + 1e-12)
        else:                     # grid points before loss of tension (T1 > 0)
            mask &= np.cumprod(br.T1 > 0) > 0
    elif definition != "monotonic":
        raise ValueError(f"definition must be one of {DEFINITIONS}, got {definition!r}")
    if not mask.any():
        raise ValueError(f"c = {c}: no point of the branch of {br.annulus} has a positive "
                         f"factor K = 1 + c(5 lam/2 - 2) of (3.30) beyond lamP")
    return float(np.min(d[mask]))


def pullin_c_threshold(annulus: Annulus, *, definition: str = "before_loss_of_tension",
                       c_range=(-0.2, 0.0), n: int = 1500) -> float:
    """The c below which pull-in is suppressed at this pre-stretch (Sec. 3.5.2, Fig. 3.5).

    Method: brentq on c of the minimum slope of Phibar^2 over the relevant stretch range
    (dense branch, ``n`` points, refined by the branch being fixed: only circle A depends
    on c). See :func:`pullin_c_threshold_closed_form` for the independent check.
    ``c_range`` a finite window (lo < hi), ``n >= 4``; brentq to ``OUTER_XTOL``.
    """
    v.instance("annulus", annulus, Annulus)
    v.choice("definition", definition, DEFINITIONS)
    for c in v.window("c_range", c_range, lo=-math.inf):
        CircularActuator(annulus, c=c)  # K(lamP) > 0 at both ends
    v.integer_at_least("n", n, 4)
    return _c_threshold_on(branch(annulus, n=n), definition, c_range)


def _c_threshold_on(br: Branch, definition: str, c_range=(-0.2, 0.0),
                    lam_lot: float | None = None, br_lot: Branch | None = None) -> float:
    """:func:`pullin_c_threshold` on the default-grid branch ``br`` (its ``n`` points),
    without the argument checks (a caller that holds the branch shares it between the
    definitions). For ``"before_loss_of_tension"`` only: ``lam_lot``, the loss-of-tension
    stretch of this annulus when the caller has it located already (else located on
    ``br``), and ``br_lot``, the branch at ``n`` stretches uniform on [lamP, lam_lot]
    when the caller has traced it already (see :func:`_lot_grids`)."""
    if definition == "before_loss_of_tension":
        if lam_lot is None:
            lam_lot = loss_of_tension_stretch(br)
        br = br_lot if br_lot is not None else _lot_grids([br], [lam_lot])[0]
    else:
        lam_lot = None
    annulus = br.annulus
    f = lambda c: _min_slope(br, c, definition, lam_lot)  # noqa: E731
    lo, hi = c_range
    if not (f(lo) > 0 > f(hi)):
        raise ConvergenceError(f"pull-in c threshold not bracketed in {c_range} for {annulus}")
    return bracketed_root(f, lo, hi, xtol=OUTER_XTOL, what="pull-in c threshold").root


def _lot_grids(brs, lam_lots) -> list[Branch]:
    """The branches of the "before_loss_of_tension" c threshold: ``brs[k].lam.size``
    stretches uniform on [lamP, lam_lots[k]], all in one batched Newton iteration
    (:func:`branches_at`)."""
    return run(_branches_at_gen(brs, [np.linspace(br.annulus.lamP, lot, br.lam.size)
                                      for br, lot in zip(brs, lam_lots, strict=True)]))




def branches_at(brs, lams, maxiter: int = 30) -> list[Branch]:
    """``branch(br.annulus, lam=lams[k])`` for every ``brs[k]``: the branches at given
    stretches, all annuli in one batched Newton iteration on q (per-trajectory pre-stretch
    and equilibrium; same R_B/R_A, Jm and RK4 steps).

    The Newton start is the shooting parameter interpolated on ``brs[k]`` itself by the
    cubic Hermite interpolant of q(lambda) with the exact slopes dq/dlambda = 1/dlam of
    the branch (measured: within 4e-14 relative of the solution on the 800-point
    c-threshold branches, where PCHIP is within 4e-11), so no scan is needed and one
    integration usually suffices. The iteration stops, as in ``q_for_stretch``, when
    every step satisfies ``|dq| <= SCALAR_STEP_RTOL |q|`` (the package's Newton policy,
    :mod:`debench.models.numerics.newton`); that last step is applied to the
    outputs of the last integration with their exact q-derivatives (lam - dlam dq, ...:
    the neglected terms are O(dq^2), below rounding) instead of integrating again, so the
    points agree with those of :func:`~debench.models.circular.actuator.branch` to that
    tolerance. ``brs`` a sequence of branches and ``lams`` one finite 1-D array of
    stretches per branch, in ``[lamP, br.lam_end]`` (ValueError); ``maxiter >= 1``;
    ConvergenceError when the iteration does not converge.
    """
    brs, lams = _listed("brs", brs), _listed("lams", lams)
    if len(brs) != len(lams):
        raise ValueError(f"lams must hold one array per branch ({len(brs)}), got "
                         f"{len(lams)}")
    for br, lam in zip(brs, lams, strict=True):
        v.instance("brs[k]", br, Branch)
        v.finite("lams[k]", lam)
    v.integer_at_least("maxiter", maxiter, 1)
    if not brs:
        return []
    return run(_branches_at_gen(brs, lams, maxiter))


def _branches_at_gen(brs, lams, maxiter: int = 30):
    """:func:`branches_at` (non-empty ``brs``) as a
    :func:`~debench.models.circular.lockstep.lockstep` solver."""
    an0, steps = brs[0].annulus, brs[0].steps
    if any((b.annulus.radius_ratio, b.annulus.law, b.steps) != (an0.radius_ratio, an0.law, steps)
           for b in brs):
        raise ValueError("branches must differ only in lamP and equilibrium")
    lams = [np.asarray(x, float) for x in lams]
    for br, lam in zip(brs, lams, strict=True):
        if lam.ndim != 1 or np.any(lam < br.annulus.lamP) or np.any(lam > br.lam_end):
            raise ValueError(f"stretches must lie in [lamP, {br.lam_end:.6g}] (the traced "
                             f"branch of {br.annulus})")
    sizes = [x.size for x in lams]
    lam = np.concatenate(lams)
    q = np.concatenate([CubicHermiteSpline(br.lam, br.q, 1 / br.dlam)(x) for br, x in
                        zip(brs, lams, strict=True)])
    lamP = np.repeat([b.annulus.lamP for b in brs], sizes)
    mem = np.repeat([b.annulus.equilibrium == "membrane" for b in brs], sizes)
    for _ in range(maxiter):
        st = yield from _interface_state_gen(an0, q, steps=steps, lamP=lamP, membrane=mem)
        r = st.lam - lam
        if np.any(~np.isfinite(r)):
            raise ConvergenceError(f"shooting: trajectory left the admissible set near "
                                   f"lam = {lam[~np.isfinite(r)][:3]}")
        dq = r / st.dlam
        q = q - dq
        if np.all(np.abs(dq) <= SCALAR_STEP_RTOL * np.abs(q)):
            break
    else:
        raise ConvergenceError(f"shooting Newton: max |dq| = {np.max(np.abs(dq)):.3g} "
                               f"after {maxiter} iterations")
    # the last Newton step applied to the outputs (first order, exact derivatives)
    lam_, lam1_, T1_ = st.lam - st.dlam * dq, st.lam1 - st.dlam1 * dq, st.T1 - st.dT1 * dq
    out, k = [], 0
    for br, n in zip(brs, sizes, strict=True):
        sl = slice(k, k + n)
        k += n
        if not np.all(np.isfinite(lam_[sl])) or np.any(np.diff(lam_[sl]) <= 0):
            raise ConvergenceError(f"annulus branch of {br.annulus}: non-monotone or "
                                   "inadmissible points")
        out.append(Branch(annulus=br.annulus, lam=lam_[sl], q=q[sl], lam1=lam1_[sl],
                          T1=T1_[sl], dlam=st.dlam[sl], dT1=st.dT1[sl],
                          lam_end=br.lam_end, steps=steps))
    return out


def pullin_c_threshold_closed_form(annulus: Annulus) -> float:
    """c at which d(Phibar^2)/d lambda = 0 exactly at loss of tension (T1 = 0).

    With s = s(lam), K = 1 + cA, A = 5 lam/2 - 2 (3.30) and T1(lam_L) = 0:
    (s' - lam T1') K = s (4K/lam + 5c/2), linear in c:
    c = (4s/lam - s' + lam T1') / ((s' - lam T1') A - 4 s A/lam - 5 s/2).
    Valid when the slope first vanishes at the loss-of-tension end (checked in tests).
    """
    v.instance("annulus", annulus, Annulus)
    br = branch(annulus, n=200)
    lam_L = loss_of_tension_stretch(br)
    q = q_for_stretch(annulus, np.array([lam_L]),
                      np.interp(lam_L, br.lam, br.q))
    st = _interface_state(annulus, q, steps=br.steps)
    dT1 = float(st.dT1[0] / st.dlam[0])
    law = annulus.law
    h = 1e-30
    s = float(law.equibiaxial_stress(lam_L))
    ds = float(law.equibiaxial_stress(lam_L + 1j * h).imag / h)
    A = 2.5 * lam_L - 2
    num = 4 * s / lam_L - ds + lam_L * dT1
    den = (ds - lam_L * dT1) * A - 4 * s * A / lam_L - 2.5 * s
    return num / den


def pullin_suppression_prestretch(c: float = 0.0, *, radius_ratio: float = 15.0,
                                  Jm: float | None = None, equilibrium: str = "printed",
                                  definition: str = "before_loss_of_tension",
                                  bracket=(2.0, 3.2), n: int = 800,
                                  xtol: float = 1e-8, elastomer=None) -> float:
    """The pre-stretch above which pull-in is suppressed (Sec. 3.5.2: 2.53 for c = 0).

    ``Jm``: the Gent parameter (None: ``params.JM_VHB``, read
    at the call); ``elastomer``: any library material instead (give one of them, see
    :class:`~debench.models.circular.params.Annulus`).

    ``bracket`` a window of pre-stretches >= 1 (each builds an :class:`Annulus`, so the
    geometry and material arguments are validated there), ``n >= 4``, ``xtol`` a finite
    tolerance in (0, 1) on lamP; brentq failures raise ConvergenceError.
    """
    v.finite("c", c)
    v.choice("definition", definition, DEFINITIONS)
    lo, hi = v.window("bracket", bracket, lo=-math.inf)
    v.integer_at_least("n", n, 4)
    v.tolerance("xtol", xtol)
    CircularActuator(Annulus(lo, radius_ratio, Jm, equilibrium, elastomer), c=c)
    CircularActuator(Annulus(hi, radius_ratio, Jm, equilibrium, elastomer), c=c)

    def f(lamP):
        an = Annulus(lamP, radius_ratio, Jm, equilibrium, elastomer)
        br = branch(an, n=n)
        return _min_slope(br, c, definition, None)

    if not (f(lo) < 0 < f(hi)):
        raise ConvergenceError(f"suppression pre-stretch not bracketed in {bracket}")
    return bracketed_root(f, lo, hi, xtol=xtol, what="suppression pre-stretch").root


#: the lockstep suppression search certifies its iterate x once the last step is below
#: this many xtol (superlinear convergence then puts x far inside xtol of the root): it
#: evaluates x moved by SUPPRESSION_CERTIFY xtol away from the retained end b instead of
#: x itself; a sign change between b and that point (closer than xtol) brackets the root
#: and x within xtol, so x is returned; else that point is the iterate
SUPPRESSION_CERTIFY_AFTER = 1000.0
SUPPRESSION_CERTIFY = 0.45


def pullin_suppression_prestretches(c: float, equilibria, *, radius_ratio: float = 15.0,
                                    Jm: float | None = None,
                                    definition: str = "before_loss_of_tension",
                                    bracket=(2.0, 3.2), n: int = 800, xtol: float = 1e-6,
                                    bracket_branches=None, elastomer=None) -> list[float]:
    """:func:`pullin_suppression_prestretch` for several equilibrium variants at once,
    one value per entry of ``equilibria`` (a sequence of variant names).

    The same function of lamP (:func:`min_slope` on the branch of ``n`` points) is solved
    for every variant in lockstep, each iteration tracing the branches of all variants in
    one batched integration; each root is bracketed to ``xtol`` (default 1e-6, where
    :func:`pullin_suppression_prestretch` has 1e-8), so both agree within ``xtol``.
    ``bracket_branches``: the branches of ``n`` points at the bracket ends, when the
    caller traced them already (every variant at ``bracket[0]``, then every variant at
    ``bracket[1]``; ValueError if they are not those). The other arguments are checked
    as in :func:`pullin_suppression_prestretch` (``Jm`` or ``elastomer``); ConvergenceError
    when a bracket does not hold a sign change or does not shrink.
    """
    return run(_suppression_solver(c, equilibria, radius_ratio=radius_ratio, Jm=Jm,
                                   definition=definition, bracket=bracket, n=n, xtol=xtol,
                                   bracket_branches=bracket_branches, elastomer=elastomer))


def _suppression_solver(c: float, equilibria, *, radius_ratio: float = 15.0,
                        Jm: float | None = None, definition: str = "before_loss_of_tension",
                        bracket=(2.0, 3.2), n: int = 800,
                        xtol: float = 1e-6, bracket_branches=None, elastomer=None):
    """:func:`pullin_suppression_prestretches` as a
    :func:`~debench.models.circular.lockstep.lockstep` solver (arguments checked here).

    The same function of lamP (minimum slope on the branch of ``n`` points) is solved for
    every variant in lockstep by a vectorised Anderson-Bjorck iteration (regula falsi
    with scaling of the retained end): each iteration traces the branches of all variants
    in one batched integration (:func:`branches`). Once the steps are small, the iterate
    is certified by the signs at x -+ :data:`SUPPRESSION_CERTIFY` xtol. The root of each
    is bracketed to ``xtol`` (as brentq's, so both agree within ``xtol``); ConvergenceError
    when a bracket does not hold a sign change or does not shrink. ``bracket_branches``:
    the branches of ``n`` points at the bracket ends, when the caller traced them already
    (every variant at ``bracket[0]``, then every variant at ``bracket[1]``).
    """
    v.finite("c", c)
    v.choice("definition", definition, DEFINITIONS)
    lo, hi = v.window("bracket", bracket, lo=-math.inf)
    v.integer_at_least("n", n, 4)
    v.tolerance("xtol", xtol)
    eqs = _listed("equilibria", equilibria)
    for eq in eqs:
        CircularActuator(Annulus(lo, radius_ratio, Jm, eq, elastomer), c=c)
        CircularActuator(Annulus(hi, radius_ratio, Jm, eq, elastomer), c=c)
    if bracket_branches is not None:
        bracket_branches = _listed("bracket_branches", bracket_branches)
        for b in bracket_branches:
            v.instance("bracket_branches[k]", b, Branch)

    return _suppression_gen(c, eqs, radius_ratio, Jm, definition, lo, hi, n, xtol, bracket,
                            bracket_branches, elastomer)


def _suppression_gen(c, eqs, radius_ratio, Jm, definition, lo, hi, n, xtol, bracket,
                     bracket_branches, elastomer=None):
    """:func:`pullin_suppression_prestretches` after its checks, as a
    :func:`~debench.models.circular.lockstep.lockstep` solver (``Jm`` None and no
    ``elastomer``: ``params.JM_VHB``)."""

    def f(lamPs, which):
        ans = [Annulus(float(x), radius_ratio, Jm, eqs[k], elastomer)
               for x, k in zip(lamPs, which, strict=True)]
        brs = yield from _branches_gen(ans, [n] * len(ans), DEFAULT_STEPS)
        return slopes(brs)

    def slopes(brs):
        return np.array([_min_slope(br, c, definition, None) for br in brs])

    m = len(eqs)
    idx = np.arange(m)
    if bracket_branches is not None:
        want = [Annulus(float(x), radius_ratio, Jm, eq, elastomer) for x in (lo, hi)
                for eq in eqs]
        got = list(bracket_branches)
        if [b.annulus for b in got] != want or any(b.lam.size != n for b in got):
            raise ValueError(f"bracket_branches must be the {n}-point branches of {want}")
        vals = slopes(got)
    else:
        vals = yield from f(np.r_[np.full(m, lo), np.full(m, hi)], np.r_[idx, idx])
    a, b = np.full(m, float(lo)), np.full(m, float(hi))
    fa, fb = vals[:m], vals[m:]
    if not (np.all(fa < 0) and np.all(fb > 0)):
        raise ConvergenceError(f"suppression pre-stretch not bracketed in {bracket}")
    step = np.full(m, np.inf)         # each variant's last step
    done = np.zeros(m, bool)
    root = 0.5 * (a + b)
    for _ in range(200):
        act = np.nonzero(~done & (np.abs(b - a) > xtol))[0]
        if not act.size:
            return [float(r) if d else float(0.5 * (x + y))
                    for r, d, x, y in zip(root, done, a, b, strict=True)]
        lo_, hi_ = np.minimum(a[act], b[act]), np.maximum(a[act], b[act])
        x = b[act] - fb[act] * (b[act] - a[act]) / (fb[act] - fa[act])
        x = np.clip(x, lo_, hi_)
        cert = step[act] <= SUPPRESSION_CERTIFY_AFTER * xtol
        away = np.sign(x - b[act])
        away = np.where(away == 0, np.sign(a[act] - b[act]), away)
        xe = np.where(cert, np.clip(x + away * SUPPRESSION_CERTIFY * xtol, lo_, hi_), x)
        fx = yield from f(xe, act)
        ok = cert & (np.sign(fx) != np.sign(fb[act])) & (np.abs(xe - b[act]) <= xtol)
        root[act[ok]], done[act[ok]] = x[ok], True
        step[act] = np.abs(xe - b[act])
        same = np.sign(fx) == np.sign(fb[act])
        # Anderson-Bjorck: keep the bracket; when the same end is kept, scale its value
        # by 1 - f(x)/f(b) (by 1/2 where that is not positive)
        g = 1 - fx / fb[act]
        g = np.where(g > 0, g, 0.5)
        fa[act] = np.where(same, fa[act] * g, fb[act])
        a[act] = np.where(same, a[act], b[act])
        b[act], fb[act] = xe, fx
    raise ConvergenceError(f"suppression pre-stretch: no bracket below xtol={xtol}")
