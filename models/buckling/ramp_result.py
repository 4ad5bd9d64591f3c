"""What a voltage ramp of the imperfect clamped film returns
(:func:`debench.models.buckling.solver.voltage_ramp`), and the Southwell estimate of the
critical voltage read off its pre-critical part. Plain data and numpy: a stored ramp is
read and estimated without the finite-element model."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from debench.models.errors import ConvergenceError, require


@dataclass(frozen=True)
class RampResult:
    """Voltage-controlled ramp of the imperfect film.

    Arrays along the converged path: ``v`` normalised voltage, ``w`` centre deflection of
    the top surface / t0, ``thickness`` centre thickness / t0, ``e_centre`` normalised
    true field at the centre, ``e_max`` largest sampled true field, ``w_asym`` and
    ``n_asym`` the amplitude / t0 and wavenumber of the largest non-axisymmetric harmonic of
    the deflection on the mid-plane circle r = R/2
    (:func:`~debench.models.buckling.modes.deflection_asymmetry`).  The path continues a
    little past the voltage maximum (deflection control).  ``v_pullin``, ``w_pullin``: the
    limit point (vertex of the parabola v(w) through the three points around the maximum;
    None if not reached); ``pullin_bracket`` = (largest computed v, v_pullin).
    What was achieved: ``newton_its`` and ``newton_residual`` (residual norm reached) per
    point, ``eig_residual`` per eigen-record, the mesh (``ndof``, ``nelements``,
    ``h_rel``, ``layers``, ``order``) and ``stats`` (timings, factorisations, Newton
    steps, eigen-analyses).  ``end`` says why the path stopped: ``"v_max"`` (voltage
    control reached ``v_max``), ``"voltage drop"`` (the voltage fell ``drop`` below its
    maximum), ``"c_max"``, ``"singular past the limit point"`` (past the maximum the
    deflection-controlled tangent became singular: a second eigenvalue of the tangent
    crossed zero, a bifurcation of the controlled path; the maximum is bracketed), or
    ``"stalled before the limit point"`` (only with ``stop_on_stall``).
    """

    v: np.ndarray
    w: np.ndarray
    w_mid: np.ndarray
    thickness: np.ndarray
    e_centre: np.ndarray
    e_max: np.ndarray
    newton_its: np.ndarray
    v_pullin: float | None
    w_pullin: float | None
    pullin_bracket: tuple[float, float] | None
    ndof: int
    nelements: int
    stats: dict
    eig_v: np.ndarray = field(default_factory=lambda: np.zeros(0))
    eig_w: np.ndarray = field(default_factory=lambda: np.zeros(0))
    eig_lam: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    eig_axisym: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    eig_wavenumber: np.ndarray = field(default_factory=lambda: np.zeros((0, 3), np.int64))
    newton_residual: np.ndarray = field(default_factory=lambda: np.zeros(0))
    eig_residual: np.ndarray = field(default_factory=lambda: np.zeros(0))
    w_asym: np.ndarray = field(default_factory=lambda: np.zeros(0))
    n_asym: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    h_rel: float = float("nan")
    layers: int = 0
    order: int = 0
    end: str = ""


def southwell(v: np.ndarray, w_mid: np.ndarray, *, v_guess: float, window=(0.4, 0.9)) -> float:
    """Critical voltage from the pre-critical ramp by the Southwell plot.

    For an imperfect plate under a load P proportional to v^2 the additional mid-plane
    deflection is ``d = w_imp P/(P_cr - P)``, so ``d/P = d/P_cr + w_imp/P_cr``: the slope
    of d/P versus d is 1/P_cr.  ``w_mid`` (mean of top and bottom centre deflections) is
    free of the symmetric thinning of the film.  Points with
    ``window[0] < v/v_guess < window[1]`` are fitted.
    """
    v = np.asarray(v)
    d = np.asarray(w_mid)
    require(len(v) == len(d) and len(v) > 3, "need > 3 ramp points")
    require(v_guess > 0, f"v_guess must be > 0, got {v_guess}")
    sel = (v > window[0] * v_guess) & (v < window[1] * v_guess)
    require(np.count_nonzero(sel) >= 3, f"Southwell window {window} holds < 3 points")
    P = v[sel] ** 2
    slope, _ = np.polyfit(d[sel], d[sel] / P, 1)
    if not slope > 0:
        raise ConvergenceError(f"Southwell fit has non-positive slope {slope}")
    return float(math.sqrt(1.0 / slope))
