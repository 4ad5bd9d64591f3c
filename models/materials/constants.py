"""Physical constants and tabulated thesis parameters, defined once for every model.

Every chapter and every finite-element model takes these from here (through
``debench.models.materials``); no other module writes the numbers.

* :data:`VACUUM_PERMITTIVITY` -- the value printed with eq. (3.27) (thesis p. 34),
  8.85e-12 F/m; the CODATA value 8.8541878128e-12 differs by 4.7e-4 relative, far below
  every printed digit it enters.
* :data:`VHB_SHEAR_MODULUS`, :data:`VHB_GENT_JM` -- the Gent parameters of VHB 4910 of
  Chapter 3 (Sec. 3.3.3): mu = 51 kPa, Jm = 120.
* :data:`EPS_R_ASSUMED` -- relative permittivity of VHB 4910, not printed in the thesis
  (assumption ``ch2.assumption.eps_r``).
* :data:`TABLE_3_1` -- the Zhao-Suo factors c of (3.27) fitted to experiments (Table 3.1).
* Table 5.1 (thesis p. 88): the neo-Hookean shear and bulk moduli (5.15)-(5.17) and the
  three-term Ogden parameters (5.26). Table 5.1 gives one bulk modulus; the Ogden model
  uses it too (assumption ``ch2.assumption.ogden_bulk_modulus``).
"""

from __future__ import annotations

VACUUM_PERMITTIVITY = 8.85e-12
"""F/m, the value printed with eq. (3.27) (thesis p. 34)."""

EPS_R_ASSUMED = 4.7
"""Relative permittivity of VHB 4910 (assumption: the thesis does not print it)."""

VHB_SHEAR_MODULUS = 51e3
"""Pa, shear modulus mu of VHB 4910 in the Gent model (3.23), Sec. 3.3.3."""

VHB_GENT_JM = 120.0
"""Gent locking parameter Jm of VHB 4910 (3.23), Sec. 3.3.3."""

TABLE_3_1 = (
    (55, -0.0073), (62, -0.0107), (59, -0.0236), (57, -0.0241), (74, -0.0275),
    (62, -0.0317), (56, -0.053), (61, -0.0777), (53, -0.0823), (58, -0.0892),
)
"""Table 3.1: (experimental-data reference number, Zhao-Suo factor c of (3.27))."""

TABLE_5_1_NH_SHEAR_MODULUS = 156000.0
"""Pa, Table 5.1 neo-Hookean mu (C10 = mu/2, eq. (5.16))."""

TABLE_5_1_BULK_MODULUS = 7748003.92
"""Pa, Table 5.1 bulk modulus k (D1 = 2/k, eq. (5.17))."""

TABLE_5_1_OGDEN_ALPHAS = (1.293, 2.3252, 2.561)
"""Table 5.1 Ogden exponents alpha_p of eq. (5.26)."""

TABLE_5_1_OGDEN_MUS = (8580.0, 84300.0, -23300.0)
"""Pa, Table 5.1 Ogden moduli mu_p of eq. (5.26) (convention 2 mu_p/alpha_p^2)."""

OGDEN_DELTA = 1e-3
"""Default half-width of the averaged spectral perturbation with which the NGSolve path
evaluates (5.26) (:mod:`debench.models.materials.ngsolve_forms`): a numerical parameter,
energy error O(delta^2) ~ 1e-6 relative."""

__all__ = [
    "EPS_R_ASSUMED", "OGDEN_DELTA", "TABLE_3_1", "TABLE_5_1_BULK_MODULUS",
    "TABLE_5_1_NH_SHEAR_MODULUS", "TABLE_5_1_OGDEN_ALPHAS", "TABLE_5_1_OGDEN_MUS",
    "VACUUM_PERMITTIVITY",
]
