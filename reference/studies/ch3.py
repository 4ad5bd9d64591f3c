"""The Chapter 3 study: the plan of the circular actuator's computation (pre-stretches,
c values, grids, the solver settings) and the one memoised chapter pass on it
(:func:`chapter_pass`) that the builder's datasets and the producers' catalogue values
share."""

from __future__ import annotations

import numpy as np
from debench.models.circular import params
from debench.models.circular.chapter_pass import Chapter, ChapterSpec, chapter
from debench.models.circular.shooting import DEFAULT_STEPS

LAMP_CURVES = (1.1, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0)
C_CURVES = (0.0, -0.02, -0.04, -0.053, -0.06, -0.08, -0.1)
LAMP_SWEEP = (1.25, 2.0, 3.0)
#: relative permittivities of the sensitivity study (the assumption ch3.assumption.eps_r)
EPS_R = (3.5, 4.05, 4.2, 4.7, 5.5)
RADIUS_RATIO = 15.0
#: the state of Figs 3.2-3.3: (lamP, Phibar, c), profiles for c and c = 0
PROFILE_STATE = (3.0, 0.2, params.C_WISSLER_MAZZA)
#: what the Chapter 3 catalogue entries compute besides the datasets' curves
#: (``reference/catalogue/ch3.toml``), in the same pass: the c values of Table 3.1's
#: extremes (loss of tension independent of c), the stretches of the voltage-increase
#: claims (lamP, stretch), the pre-stretches of the pull-in c thresholds and the c of the
#: suppression pre-stretch, with the branch points and the bracket the entries use. An
#: entry outside this plan is computed on demand by its producer.
CATALOGUE_C = (-0.0073, -0.0892)
CATALOGUE_STRETCHES = ((3.0, 4.5), (4.0, 5.0))
CATALOGUE_C_THRESHOLD_LAMP = (1.25,)
C_THRESHOLD_POINTS = 800
CATALOGUE_SUPPRESSION_C = (0.0,)
SUPPRESSION_POINTS = 200
SUPPRESSION_XTOL = 1e-6


def settings(full: bool) -> dict:
    """Resolution of a build: branch points, c-sweep points and RK4 steps."""
    return {"n": 800 if full else 300, "n_c": 201 if full else 41,
            "steps": 4 * DEFAULT_STEPS if full else DEFAULT_STEPS}


def chapter_spec(full: bool = False) -> ChapterSpec:
    """The Chapter 3 computation of a command: every curve of the datasets and, at the
    default resolution, every value of the catalogue (:data:`CATALOGUE_C` ...), so that
    the builder and the producers share one memoised :func:`chapter` pass."""
    s = settings(full)
    extra = not full
    return ChapterSpec(
        lamPs=LAMP_CURVES,
        cs=tuple(sorted(set(C_CURVES) | (set(CATALOGUE_C) if extra else set()), reverse=True)),
        sweep_lamPs=LAMP_SWEEP, sweep_cs=tuple(float(c) for c in c_grid(full)),
        eps_rs=EPS_R, eps_cs=(0.0, params.C_WISSLER_MAZZA), states=(PROFILE_STATE,),
        stretches=CATALOGUE_STRETCHES if extra else (),
        c_threshold_lamPs=CATALOGUE_C_THRESHOLD_LAMP if extra else (),
        c_threshold_n=C_THRESHOLD_POINTS,
        suppression_cs=CATALOGUE_SUPPRESSION_C if extra else (),
        suppression_n=SUPPRESSION_POINTS, suppression_xtol=SUPPRESSION_XTOL,
        n=s["n"], steps=s["steps"], radius_ratio=RADIUS_RATIO)


def chapter_pass(full: bool = False) -> Chapter:
    """The memoised chapter pass of :func:`chapter_spec` (builder and producers share it)."""
    return chapter(chapter_spec(full))


def c_grid(full: bool) -> np.ndarray:
    """The c grid of the Fig. 3.9 sweeps (Table 3.1's range 0 .. -0.1)."""
    return np.linspace(0.0, -0.1, settings(full)["n_c"])
