"""The whole Chapter 3 computation in one batched pass, memoised on its parameters.

Every result of the chapter -- the annulus branches of both equilibrium variants (Eq. 3.33
as printed and the thin-membrane balance), the voltage-stretch curves and their failure
events (Secs 3.5.2-3.5.5, Figs 3.4-3.9), the states at a voltage with their annulus
profiles (Sec. 3.5.1, Figs 3.2-3.3), the interface states at given stretches (Sec. 3.5.4),
the loss-of-tension stretches, the pull-in c thresholds (Fig. 3.5) and the suppression
pre-stretches (Sec. 3.5.2) -- is computed by :func:`chapter` from a :class:`ChapterSpec`
alone: one scan and one grid integration for every branch of every variant (the grids of
the c thresholds and the suppression search's bracket ends included), then the iterative
solvers side by side (:func:`~debench.models.circular.lockstep.lockstep`: the location of
every event of every curve, the Newton iterations of the states and stretches and the
suppression searches share one integration per round), then the profiles and the
branches up to loss of tension of the c thresholds. The dataset builder and the catalogue
producers read the same :class:`Chapter`, so that a command computes each branch, curve
and root once. Every result is the one the one-annulus public functions give, to the
tolerance of their iterations (``verification/test_ch3_chapter.py``).

:func:`chapter` is pure: its result depends on the specification only (model constants
included, :func:`current_constants`) and is memoised on it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from . import analysis, circle_a, params
from .actuator import _curves_many_solver, branches, curves_many
from .integrator import integrate
from .lockstep import lockstep
from .params import Annulus

VARIANTS = params.EQUILIBRIUM_VARIANTS
#: the pre-stretches that bracket the suppression pre-stretch (those of
#: :func:`~debench.models.circular.analysis.pullin_suppression_prestretch`)
SUPPRESSION_BRACKET = (2.0, 3.2)


def current_constants() -> tuple:
    """(Jm, mu, eps0, E_B coefficient, E_B exponent, assumed eps_r) as the model reads them
    now: part of every :class:`ChapterSpec`, so that a memoised result is never served for
    other constants."""
    return (params.JM_VHB, params.MU_VHB, params.EPS0, params.EB_COEFF,
            params.EB_EXPONENT, params.EPS_R_ASSUMED)


@dataclass(frozen=True)
class ChapterSpec:
    """What the Chapter 3 results are computed for (every field hashable: the memo key).

    Curves (``(lamP, c, eps_r, equilibrium)``; only those with K(lamP) > 0, Eq. 3.30):

    * ``lamPs`` x ``cs``: both variants, the assumed eps_r (Figs 3.4-3.8);
    * ``sweep_lamPs`` x ``sweep_cs``: both variants, the assumed eps_r (Fig. 3.9);
    * ``eps_rs`` (eps_r study): ``lamPs`` x ``eps_cs`` and ``sweep_lamPs`` x ``sweep_cs``,
      equilibrium as printed.

    Other results, each for both variants: ``states`` ``(lamP, phibar, c)``: the states at
    Phibar for c and for c = 0 and their annulus profiles; ``stretches`` ``(lamP,
    stretch)``: the interface state at that circle-A stretch; ``c_threshold_lamPs``: the
    pull-in c threshold for both definitions on branches of ``c_threshold_n`` points;
    ``suppression_cs``: the suppression pre-stretch ("before_loss_of_tension", branches of
    ``suppression_n`` points, bracketed to ``suppression_xtol``).

    ``n`` grid points and ``steps`` RK4 steps of every branch, ``radius_ratio`` R_B/R_A,
    ``constants`` :func:`current_constants` (Jm, mu, eps0, E_B law, assumed eps_r).
    """

    lamPs: tuple
    cs: tuple
    sweep_lamPs: tuple = ()
    sweep_cs: tuple = ()
    eps_rs: tuple = ()
    eps_cs: tuple = ()
    states: tuple = ()
    stretches: tuple = ()
    c_threshold_lamPs: tuple = ()
    c_threshold_n: int = 800
    suppression_cs: tuple = ()
    suppression_n: int = 200
    suppression_xtol: float = 1e-6
    n: int = 300
    steps: int = 200
    radius_ratio: float = 15.0
    constants: tuple = field(default_factory=current_constants)

    @property
    def Jm(self) -> float:
        return self.constants[0]

    @property
    def mu(self) -> float:
        return self.constants[1]

    @property
    def eps_r(self) -> float:
        return self.constants[5]

    def curve_keys(self) -> list[tuple]:
        """``(lamP, c, eps_r, equilibrium)`` of every curve, admissible ones only."""
        e0 = float(self.eps_r)
        want = []
        for eq in VARIANTS:
            want += [(lp, c, e0, eq) for lp in self.lamPs for c in self.cs]
            want += [(lp, c, e0, eq) for lp in self.sweep_lamPs for c in self.sweep_cs]
        want += [(lp, c, e, "printed") for lp in self.lamPs for c in self.eps_cs
                 for e in self.eps_rs]
        want += [(lp, c, e, "printed") for lp in self.sweep_lamPs for c in self.sweep_cs
                 for e in self.eps_rs]
        keys = [(float(lp), float(c), float(e), eq) for lp, c, e, eq in want]
        return [k for k in dict.fromkeys(keys) if circle_a._K(k[0], k[1]) > 0]


@dataclass(frozen=True)
class Chapter:
    """The results of :func:`chapter` (read-only by convention: shared by every caller).

    ``branches[(lamP, equilibrium)]``: :class:`~debench.models.circular.actuator.Branch`
    of ``spec.n`` points;
    ``curves[(lamP, c, eps_r, equilibrium)]``: :class:`~debench.models.circular.actuator.Curve`;
    ``states[(lamP, phibar, c, equilibrium)]``: dict as
    :func:`~debench.models.circular.analysis.state_at_voltage` (c = 0 included);
    ``profiles[(lamP, phibar, c, equilibrium)]``: (lambda_1, lambda_2) from R_A to R_B and
    the reference radii R/R_A; ``stretch_states[(lamP, stretch, equilibrium)]``: (lam,
    T1) at R_A; ``c_thresholds[(lamP, definition, equilibrium)]``;
    ``suppression[(c, equilibrium)]``.
    """

    spec: ChapterSpec
    branches: dict
    curves: dict
    states: dict
    profiles: dict
    stretch_states: dict
    c_thresholds: dict
    suppression: dict


def chapter(spec: ChapterSpec) -> Chapter:
    """The Chapter 3 results for ``spec``, computed once per specification (memoised)."""
    if not isinstance(spec, ChapterSpec):
        raise TypeError(f"spec must be a ChapterSpec, got {spec!r:.80}")
    return _chapter(spec)


@lru_cache(maxsize=4)
def _chapter(spec: ChapterSpec) -> Chapter:
    return _compute(spec)


def clear_memo() -> None:
    """Forget every memoised chapter pass (the next :func:`chapter` call computes: what a
    cold-start benchmark times)."""
    _chapter.cache_clear()


def _annulus(spec: ChapterSpec, lamP: float, eq: str) -> Annulus:
    return Annulus(float(lamP), float(spec.radius_ratio), float(spec.Jm), eq)


def _compute(spec: ChapterSpec) -> Chapter:
    keys = spec.curve_keys()
    lamPs = sorted({k[0] for k in keys} | {s[0] for s in spec.states}
                   | {s[0] for s in spec.stretches} | set(spec.c_threshold_lamPs))
    # one scan and one grid integration: the default grids of every pre-stretch and
    # variant, and the c-threshold grids (same scans)
    fam = [(float(lp), eq) for eq in VARIANTS for lp in lamPs]
    ct = [(float(lp), eq) for eq in VARIANTS for lp in spec.c_threshold_lamPs]
    # the suppression search's bracket ends (its branches do not depend on c)
    sp = [(float(x), eq) for x in SUPPRESSION_BRACKET for eq in VARIANTS] \
        if spec.suppression_cs else []
    brs = branches([_annulus(spec, lp, eq) for lp, eq in fam + ct + sp],
                   n=([spec.n] * len(fam) + [spec.c_threshold_n] * len(ct)
                      + [spec.suppression_n] * len(sp)), steps=spec.steps)
    family = dict(zip(fam, brs[:len(fam)], strict=True))
    ct_branches = dict(zip(ct, brs[len(fam):len(fam) + len(ct)], strict=True))
    sp_branches = brs[len(fam) + len(ct):]
    # the iterative solvers side by side, one integration per round for all of them:
    # every event of every curve, the states at a voltage, the interface states at given
    # stretches and the suppression searches
    groups: dict = {}
    for k in keys:
        groups.setdefault((k[0], k[3]), []).append(k)
    solvers = [_curves_many_solver([(family[g], [k[1] for k in ks], [k[2] for k in ks])
                                    for g, ks in groups.items()],
                                   mu=spec.mu, steps=spec.steps)]
    rows = _state_rows(spec, family)
    if rows:
        solvers.append(analysis._states_at_voltage_gen(
            [family[(r[0], r[3])] for r in rows], [r[2] for r in rows], [r[1] for r in rows]))
    srows = [(float(lp), float(x), eq) for lp, x in spec.stretches for eq in VARIANTS]
    if srows:
        solvers.append(analysis._branches_at_gen([family[(r[0], r[2])] for r in srows],
                                                 [np.array([r[1]]) for r in srows]))
    solvers += [analysis._suppression_solver(
        float(c), VARIANTS, radius_ratio=spec.radius_ratio, Jm=spec.Jm,
        bracket=SUPPRESSION_BRACKET, n=spec.suppression_n, xtol=spec.suppression_xtol,
        bracket_branches=sp_branches) for c in spec.suppression_cs]
    res = lockstep(solvers)
    curves = {k: cv for ks, cvs in zip(groups.values(), res[0], strict=True)
              for k, cv in zip(ks, cvs, strict=True)}
    k = 1
    states, profiles = {}, {}
    if rows:
        states = dict(zip(rows, res[k], strict=True))
        profiles = _profiles(spec, rows, res[k])
        k += 1
    stretch_states = {}
    if srows:
        stretch_states = {r: (float(b.lam[0]), float(b.T1[0]))
                          for r, b in zip(srows, res[k], strict=True)}
        k += 1
    suppression = {(float(c), eq): x for c, xs in zip(spec.suppression_cs, res[k:],
                                                      strict=True)
                   for eq, x in zip(VARIANTS, xs, strict=True)}
    c_thresholds = _c_thresholds(spec, ct_branches, curves, family)
    return Chapter(spec=spec, branches=family, curves=curves, states=states,
                   profiles=profiles, stretch_states=stretch_states,
                   c_thresholds=c_thresholds, suppression=suppression)


def _state_rows(spec: ChapterSpec, family: dict) -> list[tuple]:
    """(lamP, Phibar, c, variant) of the states at a voltage: c and c = 0, both variants
    (the public function's check of c made here)."""
    rows = list(dict.fromkeys((float(lp), float(ph), float(ci), eq)
                              for lp, ph, c in spec.states for eq in VARIANTS
                              for ci in (0.0, c)))
    for lp, _, ci, eq in rows:
        params.CircularActuator(family[(lp, eq)].annulus, c=ci)
    return rows


def _profiles(spec: ChapterSpec, rows, sts) -> dict:
    """The annulus profiles of the states at a voltage, in one integration."""
    an0 = Annulus(rows[0][0], float(spec.radius_ratio), float(spec.Jm), rows[0][3])
    _, _, t, P1, P2 = integrate(
        an0, np.array([s["q"] for s in sts]), profile=True, steps=spec.steps,
        lamP=np.array([r[0] for r in rows]),
        membrane=np.array([r[3] == "membrane" for r in rows]))
    if not (np.all(np.isfinite(P1)) and np.all(np.isfinite(P2))):
        raise ValueError(f"inadmissible annulus profile for the states {rows}")
    rho = np.exp(t[::-1])
    return {r: (P1[::-1, k], P2[::-1, k], rho) for k, r in enumerate(rows)}


def _c_thresholds(spec, ct_branches, curves, family) -> dict:
    """Both definitions of the pull-in c threshold, both variants: the branches up to the
    loss of tension (located on the c = 0 curves) traced in one Newton iteration."""
    out = {}
    if not spec.c_threshold_lamPs:
        return out
    e0 = float(spec.eps_r)
    rows = [(float(lp), eq) for lp in spec.c_threshold_lamPs for eq in VARIANTS]
    lots = []
    for lp, eq in rows:
        cv = curves.get((lp, 0.0, e0, eq))
        if cv is None:
            cv = curves_many([(family[(lp, eq)], [0.0], None)], mu=spec.mu,
                             steps=spec.steps)[0][0]
        ev = cv.events["loss_of_tension"]
        if ev is None:
            raise ValueError(f"no loss of tension on the traced branch of lamP = {lp} "
                             f"({eq})")
        lots.append(ev.lam)
    brs = [ct_branches[r] for r in rows]
    br_lots = analysis._lot_grids(brs, lots)
    for r, br, lot, bl in zip(rows, brs, lots, br_lots, strict=True):
        out[(r[0], "monotonic", r[1])] = analysis._c_threshold_on(br, "monotonic")
        out[(r[0], "before_loss_of_tension", r[1])] = analysis._c_threshold_on(
            br, "before_loss_of_tension", lam_lot=lot, br_lot=bl)
    return out


