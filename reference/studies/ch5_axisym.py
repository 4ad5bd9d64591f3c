"""The Chapter 5 axisymmetric studies in one table: the films, the discretisations each
study runs (its plan: the default build and ``full``) and the cheap settings that
``debench verify`` recomputes. The builders (:mod:`~debench.reference.builders.ch5_axisym`,
:mod:`~debench.reference.builders.ch5_axisym_path`,
:mod:`~debench.reference.builders.ch5_axisym_methods`), their tasks and the producers read
them from here, so that a plan changes in this file only.

A discretisation (:class:`~debench.models.buckling.axisym.AxisymDiscretisation`) is the
polynomial order p of every field and L geometric layers (ratio 0.25) towards the clamped
rim (a rim zone of one thickness) and towards each face, on ``n_r`` equal radial elements
of [0, a - t0] and two elements through the thickness; the plans below name (p, L) and
``n_r``, the rest is the class's default.
"""

from __future__ import annotations

THICKNESS = 1e-3
"""Thickness t0 [m] of the perfect films of the critical-voltage studies (Table 5.1's 1 mm
film; the normalised voltages are scale-free)."""
ASPECT = 10.0
"""Radius / thickness of the perfect films (the stated geometry of Section 5.3)."""
CRITICAL_N_R = 10
"""Equal radial elements on [0, a - t0] of the critical-voltage studies (elements of
1.9 t0 at R/t0 = 10)."""

CRITICAL = {
    False: {"cases": ("nh_t1", "ogden_t1"), "wavenumbers": (0, 1),
            "orders": (3, 4), "layers": (4, 6)},
    True: {"cases": ("nh_t1", "ogden_t1"), "wavenumbers": (0, 1),
           "orders": (4, 5, 6), "layers": (6, 8)},
}
"""The critical voltages of the perfect film (builder ``ch5_axisym``): every order with
every layer count, per case and wavenumber."""
CRITICAL_GUARD = (2, 3)
"""(order, layers) of the guard solve: the n = 0 critical voltage of each film on this
cheap discretisation (about 1 and 2 s of CPU, measured), stored as ``v_cr_guard`` so that
``debench verify`` can recompute it and, with the stored correction to the converged
value, the reported critical voltage (:func:`~debench.reference.producers.ch5.
axisym_coarse_guards`)."""

METHODS = {
    False: {"cases": ("nh_t1",), "discs": ((2, 3), (3, 3), (3, 2))},
    True: {"cases": ("nh_t1",), "discs": ((3, 6), (4, 6), (5, 6), (5, 4))},
}
"""The stability-operator study (builder ``ch5_axisym_methods``): (order, layers) per case."""

PATH_FILMS = {
    # name: (material, thickness t0 [m], radius/thickness, wavenumbers recorded,
    #        deflection / t0 from which they are recorded, record spacing / t0)
    "nh_r10": ("nh", 1e-3, 10.0, tuple(range(1, 9)), 1.0, 0.5),
    "ogden_r10": ("ogden", 1e-3, 10.0, tuple(range(1, 9)), 1.0, 0.5),
    "ogden_r20": ("ogden", 0.5e-3, 20.0, tuple(range(1, 15)), 5.0, 0.5),
}
"""The imperfect films of the path study: Table 5.1 neo-Hookean and Ogden at R/t0 = 10 (the
stated geometry, t0 = 1 mm) and the Ogden film at R/t0 = 20 (t0 = 0.5 mm with the radius
R = 10 mm kept). Wavenumbers 1..8 at R/t0 = 10 (their lowest eigenvalues at the voltage
maximum grow with n from n = 1 on: the minimum over n is inside the range) and 1..14 at
R/t0 = 20 (the unstable band at the voltage maximum is n = 6..12, n = 5 and 13 stable: the
range contains the band and a stable wavenumber on either side)."""
PATH_N_R_PER_ASPECT = 0.8
"""Equal radial elements on [0, a - t0] of the path study: 0.8 per unit of R/t0 (elements
of ~1.1-1.2 t0)."""
PATH = {
    False: {"cases": ("nh_r10",), "discs": ((2, 3), (3, 3), (3, 2)), "n_max": 4},
    True: {"cases": ("nh_r10", "ogden_r10", "ogden_r20"),
           "discs": ((2, 6), (3, 6), (4, 6), (4, 4)), "n_max": None},
}
"""The path study (builder ``ch5_axisym_path``): its films, (order, layers) and the largest
wavenumber recorded (None: every wavenumber of the film)."""
PATH_GUARD = ("nh_r10", 2, 1, 0)
"""The path guard (case, order, layers, largest wavenumber): the path task on its cheapest
setting, the neo-Hookean film at R/t0 = 10 at order 2 with one geometric layer and the
axisymmetric eigenvalue only (~9 s CPU: 318 tangent assemblies of 567 DOFs along the path
and the secant to the maximum)."""
