"""Third evaluation path: NGSolve symbolic differentiation (CoefficientFunction.Diff) of the
same energies equals the numpy chain rule (2.27)-(2.28), (2.65)-(2.70)."""

from __future__ import annotations

import numpy as np
import pytest
from debench.models.materials import MATERIALS
from debench.models.materials import ngsolve_forms as ng_forms
from hypothesis import given, settings
from hypothesis import strategies as st

from verification.strategies import (
    deformation_gradients,
    isochoric_deformation_gradients,
    lagrangian_displacements,
)

pytestmark = pytest.mark.fe

NGSOLVE_RTOL = 1e-10
"""Two exact evaluations (NGSolve's expression-tree derivative vs closed-form chain
rule); rounding in ~100 operations, relative to the largest entry of each array."""
OGDEN_PERTURBATION_RTOL = 1e-5
"""The NGSolve path evaluates Ogden (5.26) by the averaged spectral perturbation
(delta = 1e-3): error O(delta^2) = 1e-6 times a constant <= 10 (measured 6e-8 on W, 1e-8 on
P, 1e-9 on AA at drawn states), against the numpy spectral formula."""
NAMES = sorted(MATERIALS)


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
    rtol = OGDEN_PERTURBATION_RTOL if name == "ogden_ideal_dielectric" else NGSOLVE_RTOL
    for k in ("W", "P", "E_L", "AA", "AAA", "A"):
        a, b = np.asarray(getattr(ref, k)), got[k]
        scale = max(np.max(np.abs(a)), 1e-300)
        assert np.max(np.abs(a - b)) <= rtol * scale + 1e-300, k


@pytest.mark.parametrize("F", [np.eye(3), np.diag([1.1, 1.1, 1 / 1.21]),
                               np.diag([1.0, 1.0, 0.97])], ids=["identity", "equibiaxial",
                                                                "flat_film"])
def test_ngsolve_ogden_is_accurate_at_repeated_principal_stretches(F):
    """(5.26) at repeated stretches (reference state, flat pre-buckled film, §5.2.2.2):
    the averaged perturbation gives finite stress and moduli equal to the numpy spectral
    formula (whose divided differences handle equal eigenvalues)."""
    mat = MATERIALS["ogden_ideal_dielectric"]
    ref = mat.response(F, np.zeros(3))
    got = ng_forms.evaluate(mat, F, np.zeros(3))
    for k in ("W", "P", "AA"):
        a, b = np.asarray(getattr(ref, k)), got[k]
        scale = max(np.max(np.abs(a)), mat.shear_modulus)
        assert np.max(np.abs(a - b)) <= OGDEN_PERTURBATION_RTOL * scale, k


def test_unsupported_material_raises_naming_its_class():
    """A material without an NGSolve form raises NotImplementedError naming it."""
    import ngsolve as ng

    class Unknown:
        pass

    F = ng.CoefficientFunction(tuple(np.eye(3).ravel()), dims=(3, 3))
    with pytest.raises(NotImplementedError, match="Unknown"):
        ng_forms.energy_cf(Unknown(), F, ng.CoefficientFunction((0, 0, 0)))
