"""The Chapter 3 model as the producers read it (:mod:`debench.reference.producers.ch3`
and the qualitative checks of :mod:`debench.reference.producers.ch3_checks`).

Every branch, curve, state and profile of the catalogue's plan comes from the one memoised
chapter pass the dataset builder reads too (:func:`chapter`:
:func:`debench.models.circular.chapter_pass.chapter` for
:func:`debench.reference.studies.ch3.chapter_spec`, keyed on its parameters and the model
constants). Entries outside the plan are computed on demand, both equilibrium variants
(:data:`VARIANTS`) in one batched computation, and cached, keyed on the parameters and
:func:`model_key`.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from debench.models.circular import analysis, params
from debench.models.circular.actuator import branches, curves_many
from debench.models.circular.chapter_pass import clear_memo
from debench.models.circular.integrator import integrate
from debench.models.circular.params import Annulus
from debench.reference.studies import ch3 as study

#: the annulus equilibrium variants: Eq. (3.33) as printed, and the consistent
#: thin-membrane balance d(R T1)/dR = T2 (erratum ch3.erratum.eq_3_33)
VARIANTS = ("printed", "membrane")


def model_key() -> tuple:
    """The model constants every cached Chapter 3 result depends on (read at call time,
    so that the caches below are keyed on them and never serve a stale result)."""
    return (params.JM_VHB, params.MU_VHB, params.EPS0, params.EB_COEFF, params.EB_EXPONENT)


def chapter():
    """The chapter pass the builder uses too (:func:`debench.reference.studies.ch3.chapter_spec`,
    memoised on its parameters and the model constants): every value of the catalogue's
    plan."""
    return study.chapter_pass()


def branch(lamP: float, equilibrium: str = "printed", radius_ratio: float = 15.0):
    """The annulus branch of the chapter pass, or (outside its plan) traced on demand with
    the same grid for both variants (cached, keyed on the arguments and
    :func:`model_key`)."""
    ch = chapter()
    key = (float(lamP), equilibrium)
    if float(radius_ratio) == ch.spec.radius_ratio and key in ch.branches:
        return ch.branches[key]
    mk = model_key()
    ckey = (float(lamP), equilibrium, float(radius_ratio), mk)
    if ckey not in _BRANCHES:
        eqs = list(dict.fromkeys((equilibrium, *VARIANTS)))
        brs = branches([Annulus(float(lamP), float(radius_ratio), mk[0], eq) for eq in eqs],
                       n=ch.spec.n, steps=ch.spec.steps)
        for eq, br in zip(eqs, brs, strict=True):
            _BRANCHES[(float(lamP), eq, float(radius_ratio), mk)] = br
    return _BRANCHES[ckey]


_BRANCHES: dict = {}
_CURVES: dict = {}


def curves(lamP: float, cs: tuple, eps_r: float = params.EPS_R_ASSUMED,
            equilibrium: str = "printed"):
    """Curves for the c values ``cs``: those of the chapter pass, the others computed on
    demand in one batched location (cached per curve, keyed on the parameters and
    :func:`model_key`)."""
    return curves_at(lamP, [(float(c), float(eps_r)) for c in cs], equilibrium)


def curves_at(lamP: float, pairs, equilibrium: str = "printed"):
    """Curves for the (c, eps_r) ``pairs`` on one branch: those of the chapter pass, the
    others computed on demand in one batched location (so that a sweep over eps_r costs
    one vectorised shooting run, not one per value; cached per curve, keyed on the
    parameters and :func:`model_key`)."""
    ch = chapter()
    mk = model_key()
    keys = [(float(lamP), float(c), float(e), equilibrium) for c, e in pairs]
    missing = [k for k in dict.fromkeys(keys) if k not in ch.curves and (*k, mk) not in _CURVES]
    if missing:
        cvs = curves_many([(branch(lamP, equilibrium), [k[1] for k in missing],
                            [k[2] for k in missing])])[0]
        for k, cv in zip(missing, cvs, strict=True):
            _CURVES[(*k, mk)] = cv
    return [ch.curves[k] if k in ch.curves else _CURVES[(*k, mk)] for k in keys]


def interface_changes(lamP, phibar, c, equilibrium="printed"):
    """The % changes at the interface of the state at ``phibar`` for ``c`` against c = 0
    (Sec. 3.5.1): thickness of circle A, lambda_1, lambda_2 and lambda_3 at R_A."""
    return _interface_changes_cached(lamP, phibar, c, equilibrium, model_key())


@lru_cache(maxsize=32)
def _interface_changes_cached(lamP, phibar, c, equilibrium, mkey):
    s0 = state(lamP, equilibrium, 0.0, phibar)
    s1 = state(lamP, equilibrium, c, phibar)
    return {
        "thickness_A_increase": 100 * (s1["lam3A"] / s0["lam3A"] - 1),
        "lam1_interface_increase": 100 * (s1["lam1B"] / s0["lam1B"] - 1),
        "lam2_interface_decrease": 100 * (1 - s1["lam"] / s0["lam"]),
        "lam3_interface_decrease": 100 * (1 - s1["lam3B"] / s0["lam3B"]),
    }


def state(lamP, equilibrium, c, phibar) -> dict:
    """:func:`debench.models.circular.analysis.state_at_voltage`: the chapter pass's, or
    on its branch on demand (cached, keyed on the arguments and :func:`model_key`)."""
    key = (float(lamP), float(phibar), float(c), equilibrium)
    ch = chapter()
    if key in ch.states:
        return ch.states[key]
    return _state_cached(float(lamP), equilibrium, float(c), float(phibar), model_key())


_STATES: dict = {}


def _state_cached(lamP, equilibrium, c, phibar, mkey):
    """On a miss, the states for c = 0 (the reference of every comparison) and for both
    equilibrium variants are computed in the same vectorised iteration."""
    key = (lamP, equilibrium, c, phibar, mkey)
    if key not in _STATES:
        todo = [(eq, ci) for eq in dict.fromkeys((equilibrium, *VARIANTS))
                for ci in dict.fromkeys((0.0, c))
                if (lamP, eq, ci, phibar, mkey) not in _STATES]
        brs = [branch(lamP, eq) for eq, _ in todo]
        sts = analysis.states_at_voltage_many(brs, [ci for _, ci in todo],
                                              [phibar] * len(todo))
        for (eq, ci), st in zip(todo, sts, strict=True):
            _STATES[(lamP, eq, ci, phibar, mkey)] = st
    return _STATES[key]


_PROFILES: dict = {}


def profiles(lamP, c, phibar, equilibrium) -> tuple:
    """Stretch profiles (lambda_1, lambda_2 from R_A outwards) of the states at Phibar for
    c = 0 and ``c``: the chapter pass's, or both equilibrium variants in one integration
    on demand (cached, keyed on the arguments and :func:`model_key`)."""
    ch = chapter()
    rows = [(float(lamP), float(phibar), ci, equilibrium) for ci in (0.0, float(c))]
    if all(r in ch.profiles for r in rows):
        return tuple(ch.profiles[r][:2] for r in rows)
    mk = model_key()
    key = (float(lamP), float(c), float(phibar), mk)
    if key not in _PROFILES:
        rows = [(eq, ci) for eq in VARIANTS for ci in (0.0, float(c))]
        q = np.array([state(lamP, eq, ci, phibar)["q"] for eq, ci in rows])
        an = branch(lamP, VARIANTS[0]).annulus
        _, _, _, P1, P2 = integrate(
            an, q, profile=True, lamP=np.full(q.size, an.lamP),
            membrane=np.array([eq == "membrane" for eq, _ in rows]))
        if not (np.all(np.isfinite(P1)) and np.all(np.isfinite(P2))):
            raise ValueError(f"inadmissible annulus profile at lamP = {lamP}, "
                             f"Phibar = {phibar}")
        _PROFILES[key] = {row: (P1[::-1, k], P2[::-1, k]) for k, row in enumerate(rows)}
    prof = _PROFILES[key]
    return prof[(equilibrium, 0.0)], prof[(equilibrium, float(c))]


def loss_of_tension(lamP: float, equilibrium: str) -> float:
    """Loss-of-tension stretch on the cached branch (as
    :func:`debench.models.circular.analysis.loss_of_tension_stretch`, from the shared curves)."""
    ev = curves(lamP, (0.0,), equilibrium=equilibrium)[0].events["loss_of_tension"]
    if ev is None:
        raise ValueError(f"no loss of tension on the traced branch of lamP = {lamP} "
                         f"({equilibrium})")
    return ev.lam


def first_failures(lamP, c, eps_r=params.EPS_R_ASSUMED, equilibrium="printed"):
    """The first failures (:class:`~debench.models.circular.actuator.Event`) of c = 0 and
    of ``c`` at the pre-stretch ``lamP``."""
    cv = curves(lamP, (0.0, float(c)), eps_r, equilibrium)
    return cv[0].failure, cv[1].failure


def failure_modes(lamP, cs, eps_r=params.EPS_R_ASSUMED, equilibrium="printed"):
    """The first failure of the curve of each c in ``cs`` at the pre-stretch ``lamP``."""
    return [cv.failure for cv in curves(lamP, tuple(float(c) for c in cs), eps_r,
                                        equilibrium)]


def clear_caches() -> None:
    """Forget every memoised Chapter 3 result: this module's branches, curves, states and
    profiles and the chapter pass's memo (cold caches for benchmarks and for a model
    change within one process)."""
    for cache in (_BRANCHES, _CURVES, _STATES, _PROFILES):
        cache.clear()
    _interface_changes_cached.cache_clear()
    clear_memo()
