"""Third evaluation path: NGSolve symbolic differentiation (CoefficientFunction.Diff) of the
same energies equals the numpy chain rule (2.27)-(2.28), (2.65)-(2.70)."""

from __future__ import annotations

import numpy as np
import pytest
from debench.models.materials import MATERIALS
from hypothesis import given, settings
from hypothesis import strategies as st

from verification.strategies import (
    deformation_gradients,
    isochoric_deformation_gradients,
    lagrangian_displacements,
)

ng_forms = pytest.importorskip("debench.models.materials.ngsolve_forms")

pytestmark = pytest.mark.fe

NGSOLVE_RTOL = 1e-10
"""Two exact evaluations (NGSolve's expression-tree derivative vs closed-form chain
rule); rounding in ~100 operations, relative to the largest entry of each array."""
WITHOUT_NGSOLVE_FORM = {"ogden_ideal_dielectric"}
"""NGSolve CFs have no eigen-decomposition; Ogden (5.26) is cross-checked by Taylor tests
and finite differences only (test_materials_battery.py)."""
NAMES = sorted(set(MATERIALS) - WITHOUT_NGSOLVE_FORM)


@pytest.mark.parametrize("name", NAMES)
@settings(max_examples=10)
@given(data=st.data())
def test_ngsolve_diff_equals_numpy_chain_rule(name, data):
    """W, dW/dF, dW/dD_L and the three moduli agree at drawn states."""
    mat = MATERIALS[name]
    F = data.draw(isochoric_deformation_gradients(0.7, 1.6) if mat.incompressible
                  else deformation_gradients(0.8, 1.3))
    D = data.draw(lagrangian_displacements(1.0)) * np.sqrt(mat.eps * (mat.shear_modulus or 1e5))
    ref = mat.response(F, D)
    got = ng_forms.evaluate(mat, F, D)
    for k in ("W", "P", "E_L", "AA", "AAA", "A"):
        a, b = np.asarray(getattr(ref, k)), got[k]
        scale = max(np.max(np.abs(a)), 1e-300)
        assert np.max(np.abs(a - b)) <= NGSOLVE_RTOL * scale + 1e-300, k


def test_materials_without_ngsolve_form_say_so():
    """Every registry material has an NGSolve form or is listed, and Ogden raises clearly."""
    assert set(MATERIALS) == set(NAMES) | WITHOUT_NGSOLVE_FORM
    import ngsolve as ng

    F = ng.CoefficientFunction(tuple(np.eye(3).ravel()), dims=(3, 3))
    with pytest.raises(NotImplementedError, match="Ogden"):
        ng_forms.energy_cf(MATERIALS["ogden_ideal_dielectric"], F,
                           ng.CoefficientFunction((0, 0, 0)))
