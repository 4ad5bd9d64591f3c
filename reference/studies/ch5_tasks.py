"""The finite-element tasks of the Chapter 5 study (:mod:`debench.reference.studies.ch5`,
built by :mod:`debench.reference.builders.ch5` and the radius/thickness 20 studies) and the
settings they depend on.

The task cache of :func:`debench.reference.tasks.run_tasks` keys on the source of
the module that defines a task: the cases, the material choice and the discretisation
settings below are the inputs of the FE results, while the analysis, fits and figures live
in the builders, whose edits leave finished tasks valid.
"""

from __future__ import annotations

import dataclasses
import time

from debench.models.buckling.parameters import Discretisation, Plate
from debench.models.materials import material as library_material
from debench.reference.tasks import limit_threads

CASES = {  # name: (material, thickness [m])
    "nh_t1": ("nh", 1e-3),
    "ogden_t1": ("ogden", 1e-3),
    "ogden_t0p5": ("ogden", 0.5e-3),
}
ORDER = 2
"""Polynomial order of the displacement (quadratic prisms)."""
EIG_EVERY = 4
"""Eigen-analysis every 4th converged path point of a ramp."""
RAMP_DV_MAX = 0.02  # largest voltage step of the ramps (normalised): >= 3 points in the
                    # Southwell window 0.4-0.9 v_cr of the Ogden case (v_cr ~ 0.17)


def material(name):
    """The Table 5.1 material of a case's material name (``"nh"``, ``"ogden"`` or any name
    of the library registry); ``ValueError`` naming the valid names otherwise."""
    return library_material(name)


def critical_task(case: str, h_rel: float, layers: int = 1, aspect: float = 10.0) -> dict:
    """One critical-voltage computation as plain data (a Dask task)."""
    from debench.models.buckling.solver import critical_voltage
    limit_threads()
    mat_name, t0 = CASES[case]
    start = time.perf_counter()
    r = critical_voltage(Plate(thickness=t0, aspect=aspect), material(mat_name),
                         Discretisation(h_rel=h_rel, layers=layers, order=ORDER))
    return {"v": r.v, "ndof": r.ndof, "nelements": r.nelements, "eig_residual": r.eig_residual,
            "newton_residual": r.newton_residual, "seconds": time.perf_counter() - start}


def ramp_task(case: str, h_rel: float, eig_every: int = EIG_EVERY,
              dv_max: float = RAMP_DV_MAX, layers: int = 1, aspect: float = 10.0) -> dict:
    """One voltage ramp as plain data (a Dask task): the RampResult fields."""

    from debench.models.buckling.solver import voltage_ramp
    limit_threads()
    mat_name, t0 = CASES[case]
    r = voltage_ramp(Plate(thickness=t0, aspect=aspect), material(mat_name),
                     Discretisation(h_rel=h_rel, layers=layers, order=ORDER),
                     dv_max=dv_max, eig_every=eig_every)
    return {f.name: getattr(r, f.name) for f in dataclasses.fields(r)}


WRINKLING_CASE = "ogden_t0p5"
WRINKLING_ASPECT = 20.0
WRINKLING_LAYERS = 1
WRINKLING_EIG_EVERY = 1
"""Eigen-analysis at every path point of the radius/thickness 20 ramps: the path steps
0.4 t0 in deflection there, and the lowest non-axisymmetric eigenvalue dips close to zero
over ~1-2 t0, so sparser records could step over a short excursion below zero. An
eigen-analysis costs ~1/10 of the Newton steps of one path point."""
WRINKLING_DV_MAX = 0.02


def wrinkling_task(h_rel: float, eig_every: int) -> dict:
    """One radius/thickness 20 ramp of the 0.5 mm Ogden film (the wrinkling search of
    :mod:`debench.reference.builders.ch5_wrinkling`) as plain data (a Dask task): the
    RampResult fields, with the eigen-analysis every ``eig_every`` path points; a path
    that stalls before a voltage maximum is kept (``stop_on_stall``)."""

    from debench.models.buckling.solver import voltage_ramp
    limit_threads()
    mat_name, t0 = CASES[WRINKLING_CASE]
    r = voltage_ramp(Plate(thickness=t0, aspect=WRINKLING_ASPECT), material(mat_name),
                     Discretisation(h_rel=h_rel, layers=WRINKLING_LAYERS, order=ORDER),
                     dv_max=WRINKLING_DV_MAX, eig_every=eig_every, stop_on_stall=True)
    return {f.name: getattr(r, f.name) for f in dataclasses.fields(r)}
