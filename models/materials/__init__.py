"""The constitutive library of debench: energies W(F, D_L) and their derivatives.

Stable numpy API (other chapters cross-check against it)
--------------------------------------------------------
Materials are frozen parameter dataclasses (validated on construction: non-positive
moduli or NaN raise ``ValueError`` naming the bound) with

``mat.energy(F, D_L) -> float``
    the energy density; ``det F <= 0``, NaN, a stretch past the Gent lock raise ValueError.
``mat.response(F, D_L, second=True) -> Response``
    ``W``, ``P = dW/dF`` (``P[i, a]``; nominal stress T = P^T), ``E_L = dW/dD_L``, and the
    moduli ``AA[i,a,j,b]``, ``AAA[i,a,b]``, ``A[a,b]`` of eqs (2.65)-(2.67) - all by one
    chain rule over the invariants (2.68)-(2.70) (Ogden: spectral formula).

``mat.incompressible``, ``mat.numbering`` (``"iso"`` or ``"ti"``), ``mat.shear_modulus``,
``mat.bulk_modulus``, ``mat.check_admissible(F, D_L)``; every backend (numpy, NGSolve)
evaluates the one expression ``mat.energy_expression(F, D_L, xp=...)`` (and
``mat.mechanical_energy(F, xp=...)``): the protocol :class:`Material`.

Functions (:mod:`debench.models.materials.response`): :func:`first_piola`, :func:`cauchy_stress`
(2.31/2.33, with p), :func:`electric_field` (2.32/2.34), :func:`eulerian_displacement`,
:func:`moduli`, :func:`push_forward` (2.72-2.73), :func:`pressure_from_traction_free_face`.

Materials
---------
Thesis parameters as defaults; the one registry by name is :data:`MATERIALS`, looked up by
:func:`material`, which raises ``ValueError`` naming the valid names.

==========================================  ========================================================
:class:`GentIdealDielectric`                (3.23) mu = 51 kPa, Jm = 120 + I5/(2 eps);
                                            incompressible
:class:`NeoHookeanIdealDielectric`          (5.15)+(5.9), C10 = mu/2, D1 = 2/k; Table 5.1
                                            mu = 156000 Pa, k = 7748003.92 Pa; compressible
:class:`OgdenIdealDielectric`               (5.26)+(5.9), 2 mu_p/alpha_p^2 convention (as printed,
                                            consistent with (5.27)); Table 5.1 alpha = 1.293,
                                            2.3252, 2.561, mu = 8580, 84300, -23300 Pa; initial
                                            shear modulus sum mu_p = 69580 Pa; bulk k of the
                                            neo-Hookean (assumed)
:class:`MooneyRivlinIdealDielectric`        C10 (J^{-2/3} I1 - 3) + C01 (J^{-4/3} I2 - 3) +
                                            k/2 (J-1)^2 + (5.9); not a thesis material
                                            (C01 = 0: neo-Hookean with mu = 2 C10)
:class:`IdealDielectric`                    (5.9) W = I5/(2 eps J)
:class:`DorfmannOgdenElectric`              (4.20) (alpha D_L.D_L + beta D_L.C D_L)/(2 eps)
:class:`TransverselyIsotropicNeoHookean`    (4.22) mu/2 (I1-3) + mu xi/2 (I4-1)^2 +
                                            (alpha I6 + beta I5)/(2 eps), ti numbering, A = (0,1,0)
==========================================  ========================================================

Membrane (Ch. 3, :mod:`debench.models.materials.membrane`): :class:`GentMembrane` with
:class:`ZhaoSuoPermittivity` (3.27) or :class:`JimenezMcMeekingPermittivity` (3.24-3.26):
free energy (3.20), equations of state (3.21)-(3.22) in closed form and from (3.14)-(3.16).

Permittivity: the thesis does not print eps_r for VHB 4910; the defaults use eps_r = 4.7
(assumption ``ch2.assumption.eps_r`` in the catalogue). Pass ``eps`` explicitly.

NGSolve: :mod:`debench.models.materials.ngsolve_forms` (imported on demand) builds the same
energies as ``CoefficientFunction`` s for ``.Diff``.

Example
-------
>>> import numpy as np
>>> from debench.models.materials import NeoHookeanIdealDielectric, cauchy_stress
>>> mat = NeoHookeanIdealDielectric()
>>> float(np.abs(cauchy_stress(mat, np.eye(3), np.zeros(3))).max())
0.0
"""

from __future__ import annotations

from debench.models.materials.constants import EPS_R_ASSUMED, TABLE_3_1
from debench.models.materials.kernel import Response, invariant_chain_rule, spectral_response
from debench.models.materials.library import (
    ALIASES,
    MATERIALS,
    THESIS_MATERIALS,
    VACUUM_PERMITTIVITY,
    DorfmannOgdenElectric,
    GentIdealDielectric,
    IdealDielectric,
    MooneyRivlinIdealDielectric,
    NeoHookeanIdealDielectric,
    OgdenIdealDielectric,
    TransverselyIsotropicNeoHookean,
    material,
)
from debench.models.materials.membrane import (
    GentMembrane,
    JimenezMcMeekingPermittivity,
    ZhaoSuoPermittivity,
)
from debench.models.materials.protocol import (
    IdealDielectricElastomer,
    IncompressibleLimit,
    Material,
)
from debench.models.materials.response import (
    cauchy_stress,
    electric_field,
    eulerian_displacement,
    first_piola,
    moduli,
    pressure_from_traction_free_face,
    push_forward,
)

_C_TABLE_3_1 = dict(TABLE_3_1)[59]  # c = -0.0236 of Table 3.1 (data of ref. [59])

MEMBRANE_MODELS = {
    "gent_membrane_zhao_suo": GentMembrane(permittivity=ZhaoSuoPermittivity(c=_C_TABLE_3_1)),
    "gent_membrane_jimenez_mcmeeking": GentMembrane(
        permittivity=JimenezMcMeekingPermittivity(
            c0=-_C_TABLE_3_1 * EPS_R_ASSUMED * VACUUM_PERMITTIVITY / 6)),
}
"""Membrane models of Ch. 3 (c = -0.0236 from Table 3.1; c0 is the JM coefficient whose
linearisation gives the same c)."""

__all__ = [
    "ALIASES", "MATERIALS", "MEMBRANE_MODELS", "THESIS_MATERIALS", "VACUUM_PERMITTIVITY",
    "DorfmannOgdenElectric", "GentIdealDielectric",
    "GentMembrane", "IdealDielectric", "IdealDielectricElastomer",
    "IncompressibleLimit", "JimenezMcMeekingPermittivity", "Material",
    "MooneyRivlinIdealDielectric",
    "NeoHookeanIdealDielectric", "OgdenIdealDielectric", "Response",
    "TransverselyIsotropicNeoHookean", "ZhaoSuoPermittivity", "cauchy_stress",
    "electric_field", "eulerian_displacement", "first_piola", "invariant_chain_rule",
    "material", "moduli", "pressure_from_traction_free_face", "push_forward",
    "spectral_response",
]
