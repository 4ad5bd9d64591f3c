"""The finite-element task of the Chapter 5 imperfection-sensitivity study
(:mod:`debench.reference.studies.ch5_imperfection`, built by
:mod:`debench.reference.builders.ch5_imperfection`).

One task follows the Ogden film of Table 5.1 (t0 = 0.5 mm) at radius/thickness 20 with the
thesis' axisymmetric imperfection (1e-3 t0) plus a seed of the angular wavenumber-1 mode
(:class:`~debench.models.buckling.parameters.Plate`, ``wrinkle_imperfection``) to and past
its voltage maximum. The task cache of :func:`debench.reference.tasks.run_tasks`
keys on this module's source: the settings below are the inputs of the paths, the
analysis and figures live in the study and the builder, whose edits leave finished paths valid.
"""

from __future__ import annotations

import dataclasses

from debench.models.buckling.parameters import Discretisation, Plate
from debench.reference.studies.ch5_tasks import CASES, material
from debench.reference.tasks import limit_threads

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
