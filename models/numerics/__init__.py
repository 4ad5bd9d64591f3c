"""Shared numerics of every chapter: scalar roots (:mod:`.roots`: bracketed, secant (also
stopped before a small step), near an estimate, many brackets at once, grid scans),
adaptive sign-change scans that do not lose close zeros (:mod:`.scan`), Newton's stopping
policy, result, bordered solve and damped driver (:mod:`.newton`), the step control of
path following (:mod:`.continuation`), and mesh-convergence and limit fits with Roache's
grid convergence index (:mod:`.convergence`).

Each routine is tested once on synthetic problems with known answers, through every method
(``verification/test_numerics.py``), the way SciPy's ``test_zeros`` runs one collection of
functions with known roots through every root finder.
"""

from debench.models.numerics.continuation import StepControl
from debench.models.numerics.convergence import (
    GCI,
    LimitFit,
    LogLogFit,
    PGradingEstimate,
    ThreePointFit,
    asymptotic_fit,
    convergence_fit,
    gci,
    gci_safety,
    level_fit,
    loglog_order,
    p_grading_estimate,
    p_grading_safety,
    propagated_accuracy,
    reference_fit,
    richardson,
    two_term_limits,
)
from debench.models.numerics.newton import (
    NewtonResult,
    bordered_solve,
    damped_newton,
    residual_converged,
    round_off_floor,
)
from debench.models.numerics.roots import (
    Memo,
    RootResult,
    ScanRoots,
    bisect_boundary,
    bracketed_root,
    regula_falsi_many,
    scan_roots,
    secant,
    zero_near,
)
from debench.models.numerics.scan import (
    grid_brackets,
    grid_samples,
    refine_samples,
    refinement_points,
    scan_brackets,
    sign_change_brackets,
)
from debench.models.numerics.secants import secant_until, secant_zero

__all__ = [
    "GCI",
    "LimitFit",
    "LogLogFit",
    "Memo",
    "NewtonResult",
    "PGradingEstimate",
    "RootResult",
    "ScanRoots",
    "StepControl",
    "ThreePointFit",
    "asymptotic_fit",
    "bisect_boundary",
    "bordered_solve",
    "bracketed_root",
    "convergence_fit",
    "damped_newton",
    "gci",
    "gci_safety",
    "grid_brackets",
    "grid_samples",
    "level_fit",
    "loglog_order",
    "p_grading_estimate",
    "p_grading_safety",
    "propagated_accuracy",
    "reference_fit",
    "refine_samples",
    "refinement_points",
    "regula_falsi_many",
    "residual_converged",
    "richardson",
    "round_off_floor",
    "scan_brackets",
    "scan_roots",
    "secant",
    "secant_until",
    "secant_zero",
    "sign_change_brackets",
    "two_term_limits",
    "zero_near",
]
