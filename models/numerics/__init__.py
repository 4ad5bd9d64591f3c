"""Shared numerics of every chapter: bracketed roots (:mod:`.roots`) and mesh-convergence
and limit fits with Roache's grid convergence index (:mod:`.convergence`).

Each routine is tested once on synthetic problems with known answers, through every method
(``verification/test_numerics.py``), the way SciPy's ``test_zeros`` runs one collection of
functions with known roots through every root finder.
"""

from debench.models.numerics.convergence import (
    GCI,
    LimitFit,
    PGradingEstimate,
    ThreePointFit,
    asymptotic_fit,
    convergence_fit,
    gci,
    gci_safety,
    level_fit,
    p_grading_estimate,
    p_grading_safety,
    propagated_accuracy,
    reference_fit,
    richardson,
    two_term_limits,
)
from debench.models.numerics.roots import Memo, checked_brentq, regula_falsi_many, zero_near

__all__ = [
    "GCI",
    "LimitFit",
    "Memo",
    "PGradingEstimate",
    "ThreePointFit",
    "asymptotic_fit",
    "checked_brentq",
    "convergence_fit",
    "gci",
    "gci_safety",
    "level_fit",
    "p_grading_estimate",
    "p_grading_safety",
    "propagated_accuracy",
    "reference_fit",
    "regula_falsi_many",
    "richardson",
    "two_term_limits",
    "zero_near",
]
