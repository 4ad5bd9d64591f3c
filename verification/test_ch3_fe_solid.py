"""The thin axisymmetric solid model of the circular actuator (Zeng 2020, Ch. 3).

:mod:`debench.models.circular.fe_solid` keeps the film thickness H that the membrane
models (the analytic Chapter 3 model and :mod:`debench.models.circular.fe`) drop. These
tests check its energy against the constitutive library and its pre-stretched state
against the closed form; the thickness study (difference from the membrane FE as H -> 0)
is in ``verification/test_ch3_fe_thickness.py``.
"""

from __future__ import annotations

import math

import ngsolve as ng
import numpy as np
import pytest
from debench.models.circular.fe_solid import CircularSolidFE, SolidMesh, energy_parts, radial_nodes
from debench.models.materials.library import MooneyRivlinIdealDielectric
from debench.models.materials.membrane import GentMembrane, ZhaoSuoPermittivity

#: the solid's energy CFs and the library's numpy membrane energy evaluate the same
#: expression at a homogeneous state in double precision (~1e-15 relative); 1000x margin
ENERGY_RTOL = 1e-12
#: the pre-stretched state is homogeneous and exactly representable (u linear in R, Z):
#: Newton stops at a relative update 1e-10, so the centre stress is exact to ~1e-10
#: relative; 1e-8 is a 100x margin
PRESTRETCH_RTOL = 1e-8
SMALL_MESH = SolidMesh(n_a=2, n_b=5, nz=1)


@pytest.mark.parametrize("c", [0.0, -0.053])
def test_solid_energy_is_the_library_membrane_energy_in_a_homogeneous_state(c):
    """At F = diag(l1, l3, l2) (R, Z, theta) with l3 = 1/(l1 l2) and Grad psi = (0, 1),
    W_Gent + Phibar^2 w_e of the solid equals GentMembrane.free_energy(l1, l2, Phibar^2)
    (3.20), (3.23), (3.27)."""
    mat = GentMembrane(mu=1.0, Jm=120.0, permittivity=ZhaoSuoPermittivity(eps_bar=1.0, c=c))
    model = CircularSolidFE(2.0, 0.2, c, mesh=SMALL_MESH)
    par = [ng.Parameter(0.0) for _ in range(3)]
    F = ng.CoefficientFunction((par[0], 0, 0, 0, par[1], 0, 0, 0, par[2]), dims=(3, 3))
    wm, we = energy_parts(F, ng.CoefficientFunction((0.0, 1.0, 0.0)), c, model.elastomer)
    mip = model.mesh(0.5, 0.05)
    for l1, l2, I4 in [(1.3, 2.1, 0.04), (3.0, 2.5, 0.2), (0.9, 4.0, 0.0)]:
        for p, val in zip(par, (l1, 1 / (l1 * l2), l2), strict=True):
            p.Set(val)
        got = wm(mip) + I4 * we(mip)
        assert got == pytest.approx(mat.free_energy(l1, l2, I4), rel=ENERGY_RTOL)


@pytest.mark.parametrize("lamP", [1.25, 3.0])
def test_solid_prestretched_state_has_the_membrane_stress(lamP):
    """At zero voltage the pre-stretched film is homogeneous: circle A has the stretch
    lamP and the radial Cauchy stress sigma1 = lam1 dW/dlam1 of the library membrane
    energy (3.14), (3.23), with sigma_zz = 0 (traction-free faces)."""
    model = CircularSolidFE(lamP, 0.2, mesh=SMALL_MESH)
    s = model.solve(lamP)
    mat = GentMembrane(mu=1.0, Jm=120.0, permittivity=ZhaoSuoPermittivity(eps_bar=1.0))
    h = 1e-30
    T1 = mat.free_energy(lamP + 1j * h, lamP, 0.0).imag / h
    assert s.lam_centre == pytest.approx(lamP, rel=PRESTRETCH_RTOL)
    assert s.sigma1A == pytest.approx(lamP * T1, rel=PRESTRETCH_RTOL)
    assert abs(s.phibar2) <= PRESTRETCH_RTOL


def test_solid_mesh_has_square_elements_at_the_electrode_edge():
    """R_A = 1 is a node, the elements beside it are H/(2 nz) wide, sizes never shrink
    away from it by more than the grading allows, and the ends are 0 and R_B."""
    m = SolidMesh(n_a=4, n_b=20, nz=2, grading=0.3)
    H = 0.05
    R = radial_nodes(H, 15.0, m)
    k = int(np.argmin(np.abs(R - 1.0)))
    assert R[k] == 1.0 and R[0] == 0.0 and R[-1] == 15.0
    h = np.diff(R)
    assert h[k - 1] == pytest.approx(H / 4) and h[k] == pytest.approx(H / 4)
    assert np.all(h > 0)
    assert np.all(h[1:] / h[:-1] < 1 + m.grading * 15 + 1) and math.isfinite(h.max())


def test_solid_rejects_bad_input():
    with pytest.raises(ValueError, match="lamP"):
        CircularSolidFE(0.9, 0.1)
    with pytest.raises(ValueError, match="thickness"):
        CircularSolidFE(2.0, 0.0)
    with pytest.raises(ValueError, match="permittivity"):
        CircularSolidFE(3.0, 0.1, c=-0.6)
    with pytest.raises(ValueError, match="nz"):
        SolidMesh(nz=0)
    with pytest.raises(ValueError, match="penalty"):
        CircularSolidFE(2.0, 0.1, mesh=SMALL_MESH, penalty=0.0)


#: central differences of the residual with step DIFF_STEP (relative to the state's scale
#: 1): truncation ~h^2 |r'''| ~ 1e-12 x the penalty 1e5 and round-off ~eps |r|/h ~ 1e-10 x
#: |r| ~ 1e-5 relative to |J v| ~ 1e2; TANGENT_RTOL is 10x that
DIFF_STEP = 1e-6
TANGENT_RTOL = 1e-4


def test_solid_bordered_tangent_is_the_derivative_of_the_residual():
    """The bordered Newton matrix of the solid ([dR/dx_free, dR/dPhibar^2] on the equation
    rows) and its load column dR/dx_load, as Newton and the continuation assemble them,
    are the derivative of the residual along a random direction (central differences) at
    a state under voltage (lamP = 3, edge stretch 3.2, Phibar^2 > 0)."""
    model = CircularSolidFE(3.0, 0.2, mesh=SMALL_MESH)
    s = model.solve(3.2)
    assert s.phibar2 > 0
    M, col = model.bordered(s.x, s.phibar2)
    E, F, i = model._E, model._F, model._i
    rng = np.random.default_rng(0)
    v = rng.standard_normal(len(F) + 1)

    def res(t):
        x = s.x.copy()
        x[F] += t * v[:-1]
        return model._system(x, s.phibar2 + t * v[-1])[0][E]

    fd = (res(DIFF_STEP) - res(-DIFF_STEP)) / (2 * DIFF_STEP)
    got = M @ v
    assert np.max(np.abs(got - fd)) <= TANGENT_RTOL * np.max(np.abs(got))

    def res_load(t):
        x = s.x.copy()
        x[i] += t
        return model._system(x, s.phibar2)[0][E]

    fd = (res_load(DIFF_STEP) - res_load(-DIFF_STEP)) / (2 * DIFF_STEP)
    assert np.max(np.abs(col - fd)) <= TANGENT_RTOL * np.max(np.abs(col))


def test_solid_takes_any_library_elastomer():
    """A library elastomer passed as ``elastomer`` runs in the solid model with no change to
    it: the compressible Mooney-Rivlin (any units: the model divides by its shear modulus)
    in its incompressible limit on a state at a voltage. With C01 = 0 it is the neo-Hookean,
    the Gent default with Jm -> infinity (Jm = 1e8: (I1 - 3)/(2 Jm) < 1e-7 relative on this
    state, so 1e-6 bounds the difference); C01 > 0 at the same shear modulus differs."""
    def state(**kw):
        return CircularSolidFE(1.25, 0.2, mesh=SMALL_MESH, **kw).solve(1.3)

    gent = state(Jm=1e8)
    nh = state(elastomer=MooneyRivlinIdealDielectric(C10=0.5e5, C01=0.0, k=5e6))
    assert nh.phibar2 == pytest.approx(gent.phibar2, rel=1e-6)
    mr = state(elastomer=MooneyRivlinIdealDielectric(C10=0.35, C01=0.15, k=50.0))
    assert abs(mr.phibar2 - nh.phibar2) > 1e-3 * nh.phibar2
    with pytest.raises(ValueError, match="Jm"):
        CircularSolidFE(1.25, 0.2, Jm=120.0, elastomer=MooneyRivlinIdealDielectric())
