"""The Chapter 5 imperfection-sensitivity study: the meshes and seed amplitudes of the
wavenumber-1 seeded paths (their task: :func:`imperfect_path_task`)
and the pre-registered reading of their voltage maxima (:func:`wrinkling_governs`,
:func:`drop_exponent`) that the builder's dataset and the producers share."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import xarray as xr
from debench.models.buckling.parameters import Discretisation, Plate
from debench.reference.studies.ch5 import CASES, material
from debench.reference.tasks import limit_threads

LEVELS = {False: (), True: (2.5, 2.0)}
"""In-plane mesh sizes / t0 (50 and 63 quadratic elements around the rim): the two finest
meshes of the wrinkling search that reach its bifurcation at a cost of minutes per path;
on h = 2.5 t0 the perfect path passes it (the lowest n = 1 eigenvalue dips to 3e-5 of its
maximum and recovers), on h = 2 t0 it turns there: the seed decides the branch on both."""
AMPLITUDES = (2e-3, 8e-3, 3.2e-2)
"""Peak amplitudes / t0 of the wavenumber-1 seed: 2 to 32 times the thesis' axisymmetric
imperfection, in ratios of 4 (a power law of the voltage drop is fitted over them)."""
W_SPLIT = 9.0
"""Centre deflection / t0 that separates failure at the wrinkling bifurcation (its zero
lies at 7.6-7.95 t0 on the meshes h <= 3 t0) from failure at a later limit point (the
axisymmetric limit points of the meshes that pass the bifurcation lie at 10.2-11.7 t0)."""


def drop_exponent(v_max) -> float:
    """Exponent p of the voltage drop v_c - v_max ~ C amplitude^p from three maxima at
    amplitudes in the constant ratio q of :data:`AMPLITUDES`: successive drops grow by
    q^p, so p = log(d2 / d1) / log q whatever v_c (2/3 for a symmetric unstable
    bifurcation, 1/2 for an asymmetric one); NaN unless both drops are positive."""
    v = np.asarray(v_max, float)
    q = AMPLITUDES[1] / AMPLITUDES[0]
    d1, d2 = v[0] - v[1], v[1] - v[2]
    if not (np.isfinite(d1) and np.isfinite(d2) and d1 > 0 and d2 > 0):
        return math.nan
    return float(np.log(d2 / d1) / np.log(q))


def wrinkling_governs(ds: xr.Dataset) -> str:
    """The pre-registered reading of the study: ``"governs"`` when on every mesh every seeded
    path has its voltage maximum before :data:`W_SPLIT` and the maxima fall as the seed
    grows; ``"passed"`` when on every mesh the smallest seed's path has no maximum before
    :data:`W_SPLIT`; ``"undecided"`` otherwise."""
    w = ds.w_at_v_max.values
    v = ds.v_max.values
    early = np.isfinite(w) & (w < W_SPLIT)
    falling = np.all(np.diff(v, axis=1) < 0, axis=1)
    if np.all(early) and np.all(falling):
        return "governs"
    if not np.any(early[:, 0]):
        return "passed"
    return "undecided"


CASE = "ogden_t0p5"
ASPECT = 20.0
WAVENUMBER = 1
"""The seeded mode: the first non-axisymmetric mode whose eigenvalue reaches zero along
the radius/thickness 20 path on the finest meshes (``ch5_wrinkling.nc``)."""
LAYERS = 1
ORDER = 2
DV_MAX = 0.02
EIG_EVERY = 4
"""Eigen-analysis every 4th path point (1.6 t0 of deflection) and at the first point past
the voltage maximum (what becomes unstable there)."""
C_MAX = 14.0
"""Centre deflection / t0 where a path without a voltage maximum stops: beyond the
axisymmetric limit points of the perfect film (10.2-11.7 t0 on the meshes that pass the
wrinkling bifurcation)."""


def imperfect_path_task(h_rel: float, amplitude: float) -> dict:
    """The path of the film with a wavenumber-1 seed of peak ``amplitude`` t0 on the mesh of
    in-plane size ``h_rel`` t0, as plain data (the RampResult fields; a Dask task)."""

    from debench.models.buckling.solver import voltage_ramp
    limit_threads()
    mat_name, t0 = CASES[CASE]
    plate = Plate(thickness=t0, aspect=ASPECT, wrinkle_imperfection=amplitude,
                  wrinkle_wavenumber=WAVENUMBER)
    r = voltage_ramp(plate, material(mat_name),
                     Discretisation(h_rel=h_rel, layers=LAYERS, order=ORDER),
                     dv_max=DV_MAX, eig_every=EIG_EVERY, c_max=C_MAX, stop_on_stall=True)
    return {f.name: getattr(r, f.name) for f in dataclasses.fields(r)}
