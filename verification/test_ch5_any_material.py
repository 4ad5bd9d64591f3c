"""Both Chapter 5 finite-element models take any library elastomer of the material protocol.

Claim checked: a material added to the library alone (its class and its registry entry:
the compressible Mooney-Rivlin ideal dielectric) runs in the 3D model
(:mod:`debench.models.buckling.fem`) and in the axisymmetric model
(:mod:`debench.models.buckling.axisym`) without a change to either, and with ``C01 = 0``,
``C10 = mu/2`` it is the neo-Hookean (5.15): the coarse critical voltages of the two
materials agree to round-off in each model. A genuine ``C01 > 0`` with the same initial
shear modulus gives a different (but nearby) critical voltage, so the agreement is not
that of a material the models ignore.
"""

from __future__ import annotations

import ngsolve as ngs
import pytest
from debench.models.buckling import axisym as ax
from debench.models.buckling.parameters import COARSE, NeoHookean, Plate
from debench.models.buckling.solver import critical_voltage
from debench.models.materials import material
from debench.models.materials.library import MooneyRivlinIdealDielectric

pytestmark = pytest.mark.fe

SAME_ENERGY_RTOL = 1e-9
"""The two energies are the same expression up to exact zeros (``0 * (J^{-4/3} I2 - 3)``
and its derivatives) and ``C10 = mu/2`` is exact in binary: every assembled number agrees
to round-off; the critical voltage is a secant root to ~1e-13 (``vtol``) of an eigenvalue
with conditioning ~1e3, so 1e-9 bounds what round-off can move it."""
AXISYM_COARSE = ax.AxisymDiscretisation(order=2, n_r=6, edge_layers=2, face_layers=2)
"""A cheap discretisation of the axisymmetric model (about 1,500 state DOFs)."""


def _neo_hookean_as_mooney_rivlin():
    nh = NeoHookean()
    return nh, MooneyRivlinIdealDielectric(C10=nh.mu / 2, C01=0.0, k=nh.k, eps=nh.eps)


@pytest.fixture(scope="module", autouse=True)
def _one_thread():
    ngs.SetNumThreads(1)


def test_mooney_rivlin_with_c01_zero_buckles_as_neo_hookean_in_the_3d_model():
    """3D model on COARSE: v_cr(Mooney-Rivlin, C01 = 0, C10 = mu/2) = v_cr(neo-Hookean)."""
    nh, mr = _neo_hookean_as_mooney_rivlin()
    a = critical_voltage(Plate(), nh, COARSE)
    b = critical_voltage(Plate(), mr, COARSE)
    assert b.v == pytest.approx(a.v, rel=SAME_ENERGY_RTOL)


def test_mooney_rivlin_with_c01_zero_buckles_as_neo_hookean_in_the_axisymmetric_model():
    """Axisymmetric model: the same claim, and the registry's Mooney-Rivlin (C01 > 0, the
    same initial shear modulus) buckles at a different voltage."""
    nh, mr = _neo_hookean_as_mooney_rivlin()
    a = ax.critical_voltage(Plate(), nh, AXISYM_COARSE).v
    b = ax.critical_voltage(Plate(), mr, AXISYM_COARSE).v
    assert b == pytest.approx(a, rel=SAME_ENERGY_RTOL)
    registry = material("mooney_rivlin_ideal_dielectric")
    assert registry.shear_modulus == pytest.approx(nh.mu, rel=1e-15)
    c = ax.critical_voltage(Plate(), registry, AXISYM_COARSE).v
    assert abs(c - a) > 1e-6 * a
