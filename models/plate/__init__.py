"""Chapter 4: incremental bifurcation of the pre-stretched (anisotropic) dielectric plate.

Two independent methods give the critical stretch lam_cr(kH):

* :mod:`debench.models.plate.ansatz` - exponential-ansatz determinant (eqs 4.61-4.82), even/odd
  split, roots bracketed on a grid and refined together by regula falsi
  (:func:`debench.models.numerics.roots.scan_roots`);
* :mod:`debench.models.plate.fem` - 1D finite elements through the thickness (Hermite-cubic
  stream function, quadratic electric stream function), lam_cr from the zero crossing of
  an eigenvalue of the generalised eigenproblem K v = omega M v.
"""

from debench.models.plate.coefficients import (
    VARIANTS,
    PlateParams,
    base_state,
    coefficients,
    ellipticity_limit_stretch,
    energy_matrix,
    strongly_elliptic,
)

__all__ = ["VARIANTS", "PlateParams", "base_state", "coefficients",
           "ellipticity_limit_stretch", "energy_matrix", "strongly_elliptic"]
