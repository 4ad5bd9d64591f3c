"""The finite-element task of the Chapter 5 stability-operator study on the axisymmetric
model (:mod:`debench.reference.builders.ch5_axisym_methods`): the critical voltage of the
perfect clamped film in the axisymmetric wavenumber n = 0 by the three linearised buckling
operators of :meth:`~debench.models.buckling.axisym.AxisymModel.spectrum`, and the settings
it depends on.

The task cache of :func:`debench.reference.tasks.run_tasks` keys on the source of this
module and of the study modules it imports: the film
(:mod:`debench.reference.studies.ch5_axisym`) and the operators below are the inputs of the
FE results, while the convergence analysis lives in the builder.
"""

from __future__ import annotations

from debench.models.buckling.parameters import Plate
from debench.reference.studies.ch5 import case_material
from debench.reference.studies.ch5_axisym import ASPECT, CRITICAL_N_R, THICKNESS
from debench.reference.tasks import limit_threads

TANGENTS = ("coupled", "frozen_potential", "initial_stress")
"""The stability operators (:data:`debench.models.buckling.axisym.TANGENTS`): the
condensed tangent at fixed voltage (the definition of the critical voltage), the tangent at
frozen potential (the field does not redistribute with the mode) and the classical
initial-stress operator (the unloaded film's material stiffness plus the stress stiffness
of the flat state's total second Piola-Kirchhoff stress)."""


def critical_task(case: str, tangent: str, order: int, layers: int) -> dict:
    """The critical voltage of the perfect film ``case`` (``nh_t1`` or ``ogden_t1``) in
    wavenumber 0 under the stability operator ``tangent`` on the discretisation of order
    ``order`` with ``layers`` geometric layers towards the rim and each face, as plain data
    (a Dask task): ``v``, its secant tolerance ``vtol``, the centre thickness and field of
    the flat state there, the residuals, the degrees of freedom and the CPU seconds."""
    from debench.models.buckling.axisym import AxisymDiscretisation, critical_voltage

    limit_threads()
    disc = AxisymDiscretisation(order=order, edge_layers=layers, face_layers=layers,
                                n_r=CRITICAL_N_R)
    r = critical_voltage(Plate(thickness=THICKNESS, aspect=ASPECT), case_material(case), disc,
                         n=0, tangent=tangent)
    return {"case": case, "tangent": tangent, "order": order, "layers": layers,
            "v": r.v, "vtol": r.vtol, "thickness": r.thickness, "e": r.e,
            "eig_residual": r.eig_residual, "newton_residual_rel": r.newton_residual_rel,
            "iterations": r.iterations, "ndof": r.ndof, "ndof_mode": r.ndof_mode,
            "cpu_s": r.cpu_s}
