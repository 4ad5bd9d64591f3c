"""The Chapter 3 membrane ODE model takes any library elastomer (Zeng 2020, Sec. 3.3-3.5).

Circle A (3.28)-(3.32) and annulus B (3.33)-(3.37) with the membrane equations of state
(3.14)-(3.22): the Gent default runs the thesis' closed forms (3.36)-(3.37) in fused
kernels, any other library material (``elastomer=``) its energy expression differentiated
by a batched second-order jet (``circular.law.ElastomerLaw``). The generic path with the
library's Gent is an independent check of the closed forms; Mooney-Rivlin with C01 = 0 is
the neo-Hookean, C01 > 0 differs.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from debench.models.circular import actuator, analysis, circle_a, shooting
from debench.models.circular.law import ElastomerLaw, GentLaw
from debench.models.circular.params import Annulus, CircularActuator, membrane_law
from debench.models.materials.library import (
    MATERIALS,
    GentIdealDielectric,
    MooneyRivlinIdealDielectric,
)
from debench.models.materials.membrane import ElastomerMembrane

JM = 120.0
GENT = GentIdealDielectric(mu=1.0, Jm=JM, eps=1.0)
#: Mooney-Rivlin with C01 = 0 in units 2 C10 = 1: the incompressible neo-Hookean
MR_NH = MooneyRivlinIdealDielectric(C10=0.5, C01=0.0)
#: the library's default split of the shear modulus, 70/30 between C10 and C01
MR = MooneyRivlinIdealDielectric(C10=0.35, C01=0.15)
#: a Gent lock so far away that Gent is neo-Hookean to (I1 - 3)/Jm
JM_HUGE = 1e8

#: the generic and the fused path take the same RK4 steps on the same grid, so their
#: step errors are identical and they differ by the round-off of the right-hand side
#: (~1e-15 relative per evaluation, measured up to 3e-14 after the integration and event
#: location); asserted well above that floor, far below any discretisation error
ROUNDOFF = 1e-9
#: the stresses themselves: one evaluation of the same energy by two expressions
STRESS_ROUNDOFF = 1e-12
#: Gent of JM_HUGE against the neo-Hookean: the stresses differ by the factor
#: 1/(1 - (I1 - 3)/Jm) = 1 + O((I1 - 3)/Jm), with I1 - 3 < 50 on these curves (lambda < 3.5):
#: <= 5e-7 (measured 7e-8 on the events)
GENT_LOCK_EFFECT = 1e-6
#: RK4 steps of the curve comparisons (equal in both paths; fewer than the default to keep
#: the generic path's run short: the claim is about the law, not the discretisation)
STEPS = 100


def _states():
    rng = np.random.default_rng(3)
    return rng.uniform(0.8, 3.0, 50), rng.uniform(0.8, 3.0, 50)


def test_generic_law_reproduces_the_gent_closed_forms():
    """(3.36)-(3.37) and d sigma1/d lambda_i of the closed forms equal the library Gent
    energy (3.23) differentiated by the membrane jet, at drawn states, real and complex."""
    l1, l2 = _states()
    fused, generic = GentLaw.of_Jm(JM), ElastomerLaw(GENT)
    for shift in (0.0, 1e-30j):
        a = fused.stresses(l1 + shift, l2)
        b = generic.stresses(l1 + shift, l2)
        for x, y in zip(a[:4], b[:4], strict=True):
            np.testing.assert_allclose(y.real, x.real, rtol=STRESS_ROUNDOFF)
            if shift:   # the complex-step derivative d/dl1 through the law
                np.testing.assert_allclose(y.imag, x.imag, rtol=1e-10, atol=1e-40)
    lam = np.linspace(1.0, 6.0, 40)
    np.testing.assert_allclose(generic.equibiaxial_stress(lam), fused.equibiaxial_stress(lam),
                               rtol=STRESS_ROUNDOFF)
    assert generic.locking_stretch() == pytest.approx(fused.locking_stretch(), rel=1e-15)


@pytest.mark.parametrize("name", [k for k, m in MATERIALS.items() if m.shear_modulus > 0])
def test_membrane_jet_derivatives_match_the_elastomer_stress(name):
    """dWs/dl_i of the jet equal the elastomer's own first Piola stress
    (``ElastomerMembrane.stretching_energy_derivative``, an independent path), and the
    jet's second derivatives the complex-step derivative of its first ones."""
    mem = ElastomerMembrane(MATERIALS[name])
    l1, l2 = np.array([1.3, 2.0, 3.1]), np.array([1.1, 2.5, 0.9])
    W = mem.stretching_energy_jet(l1, l2)
    d1, d2 = mem.stretching_energy_derivative(l1, l2)
    mu = mem.shear_modulus
    # both are one evaluation of the stress: round-off of the expressions (~1e-15),
    # the elastomer's volumetric terms (k/mu ~ 1e4 times the rounding of J = 1) included
    np.testing.assert_allclose(W.d1, d1 / mu, rtol=1e-11)
    np.testing.assert_allclose(W.d2, d2 / mu, rtol=1e-11)
    h = 1e-30
    Wc = mem.stretching_energy_jet(l1 + 1j * h, l2)
    np.testing.assert_allclose(Wc.d1.imag / h, W.d11, rtol=1e-11)
    np.testing.assert_allclose(Wc.d2.imag / h, W.d12, rtol=1e-11)


def test_circle_a_voltage_stretch_curve_of_the_library_gent_equals_the_closed_form():
    """Eq. (3.30) for the free membrane and against an annulus stress: the library Gent
    equals the closed form with kappa = 1/Jm to round-off."""
    lam = np.linspace(1.0, 5.0, 81)
    np.testing.assert_allclose(circle_a.free_membrane_phibar(lam, -0.05, elastomer=GENT),
                               circle_a.free_membrane_phibar(lam, -0.05, 1 / JM),
                               rtol=STRESS_ROUNDOFF)
    np.testing.assert_allclose(circle_a.phibar_squared(lam, 0.3, -0.05, elastomer=GENT),
                               circle_a.phibar_squared(lam, 0.3, -0.05, 1 / JM),
                               rtol=STRESS_ROUNDOFF)


def test_circle_a_mooney_rivlin_c01_zero_is_neo_hookean_and_c01_stiffens():
    """Free equibiaxial membrane (3.30), T1B = 0: Mooney-Rivlin with C01 = 0 gives the
    neo-Hookean sqrt(lam^-2 - lam^-8) (Zhao & Suo 2007); C01 > 0 adds
    2 C01 (lam^4 - lam^-2)/mu to s(lam), which raises the voltage maximum (from 0.687 at
    lam = 2^(1/3) to 0.756 at lam = 1.36 for C01 = 0.3 mu)."""
    lam = np.linspace(1.0, 5.0, 81)
    exact = np.sqrt(lam**-2.0 - lam**-8.0)
    np.testing.assert_allclose(circle_a.free_membrane_phibar(lam, 0.0, elastomer=MR_NH), exact,
                               rtol=STRESS_ROUNDOFF, atol=1e-15)
    s_mr = circle_a.sigma1_circle_a(lam, 0.0, 0.0, elastomer=MR)
    s_closed = (2 * MR.C10 * (lam**2 - lam**-4) + 2 * MR.C01 * (lam**4 - lam**-2)) / (
        2 * (MR.C10 + MR.C01))
    np.testing.assert_allclose(s_mr, s_closed, rtol=STRESS_ROUNDOFF)
    phi = circle_a.free_membrane_phibar(lam, 0.0, elastomer=MR)
    assert phi.max() > 1.08 * exact.max()
    assert lam[np.argmax(phi)] > lam[np.argmax(exact)]


@pytest.mark.parametrize("equilibrium", ["printed", "membrane"])
def test_annulus_profile_of_the_library_gent_matches_the_fused_kernels(equilibrium):
    """The annulus ODE (3.34)-(3.35) (or the membrane balance) integrated inwards: the
    whole profile lambda_1(R), lambda_2(R) and the interface state with its complex-step
    sensitivities agree to round-off between the fused Gent kernels and the generic law."""
    fused = Annulus(2.0, Jm=JM, equilibrium=equilibrium)
    generic = Annulus(2.0, equilibrium=equilibrium, elastomer=GENT)
    q = np.linspace(1.85, 2.0, 21)
    a = shooting.integrate_inward(fused, q, profile=True)
    b = shooting.integrate_inward(generic, q, profile=True)
    np.testing.assert_array_equal(a[2], b[2])
    for x, y in zip(a[3:], b[3:], strict=True):
        np.testing.assert_allclose(y, x, rtol=ROUNDOFF)
    sa, sb = shooting.interface_state(fused, q), shooting.interface_state(generic, q)
    for f in ("lam", "lam1", "dlam", "dlam1", "dT1"):
        np.testing.assert_allclose(getattr(sb, f), getattr(sa, f), rtol=ROUNDOFF)
    np.testing.assert_allclose(sb.T1, sa.T1, rtol=ROUNDOFF, atol=ROUNDOFF * np.abs(sa.T1).max())


def _events(annulus, c=0.0):
    cv = actuator.curve(CircularActuator(annulus, c=c), n=100, steps=STEPS)
    return {k: cv.events[k] for k in ("pullin", "loss_of_tension")}


def _assert_events_close(ours, ref, rtol):
    for kind, e in ref.items():
        assert e is not None and ours[kind] is not None, kind
        assert ours[kind].lam == pytest.approx(e.lam, rel=rtol), kind
        assert ours[kind].phibar == pytest.approx(e.phibar, rel=rtol), kind


def test_pullin_and_loss_of_tension_of_the_library_gent_match_the_fused_kernels():
    """Pull-in (maximum of Phibar) and loss of tension (T1^(B)(R_A) = 0) of lamP = 1.5,
    c = 0 (both occur, Sec. 3.5), computed by the public API: the generic law
    reproduces the fused Gent kernels to round-off."""
    ref = _events(Annulus(1.5, Jm=JM))
    _assert_events_close(_events(Annulus(1.5, elastomer=GENT)), ref, ROUNDOFF)


def test_pullin_and_loss_of_tension_mooney_rivlin_c01_zero_is_gent_without_lock():
    """Mooney-Rivlin with C01 = 0 against Gent of Jm = 1e8 (to the Gent lock effect
    (I1 - 3)/Jm) and the neo-Hookean Gent of Jm = inf (to round-off); C01 = 0.3 mu moves
    pull-in and loss of tension by tens of per cent (measured: lambda +79 % and +68 %,
    Phibar +53 % and +63 %)."""
    mr0 = _events(Annulus(1.5, elastomer=MR_NH))
    _assert_events_close(mr0, _events(Annulus(1.5, Jm=JM_HUGE)), GENT_LOCK_EFFECT)
    _assert_events_close(mr0, _events(Annulus(1.5, Jm=math.inf)), ROUNDOFF)
    mr = _events(Annulus(1.5, elastomer=MR))
    for kind, e in mr0.items():
        assert mr[kind].lam > 1.5 * e.lam, kind
        assert mr[kind].phibar > 1.4 * e.phibar, kind


@pytest.mark.slow
def test_pullin_suppression_prestretch_of_the_library_gent_matches_the_fused_kernels():
    """The pre-stretch above which pull-in is suppressed (Sec. 3.5.2, c = 0; 2.534 on
    branches of 100 points): the generic law gives the fused kernels' root to round-off
    (measured: equal to all digits; 6 s against 0.7 s)."""
    kw = {"n": 100, "xtol": 1e-6}
    ref = analysis.pullin_suppression_prestretches(0.0, ["printed"], **kw)
    ours = analysis.pullin_suppression_prestretches(0.0, ["printed"], elastomer=GENT, **kw)
    assert ours[0] == pytest.approx(ref[0], rel=ROUNDOFF)


@pytest.mark.parametrize("name", [k for k, m in MATERIALS.items() if m.shear_modulus > 0])
def test_every_library_elastomer_gives_an_annulus_branch(name):
    """Every library material with a shear modulus is an annulus of the ODE model: the
    interface state of a few shooting parameters is finite and lambda_2(R_A) rises as the
    frame's radial stretch q falls (the branch the curves are traced on)."""
    an = Annulus(1.5, elastomer=MATERIALS[name])
    st = shooting.interface_state(an, np.array([1.5, 1.45, 1.4]), steps=40)
    assert np.all(np.isfinite(st.lam) & np.isfinite(st.T1) & np.isfinite(st.dlam))
    assert np.all(np.diff(st.lam) > 0)


def test_annulus_refuses_jm_and_elastomer_together_and_bad_materials():
    """Give Jm (the Gent law) or elastomer, not both; a non-material is refused naming the
    argument; a pre-stretch past the elastomer's lock is refused naming lamP."""
    with pytest.raises(ValueError, match="Jm.*elastomer"):
        Annulus(2.0, Jm=JM, elastomer=MR)
    with pytest.raises(TypeError, match="elastomer"):
        Annulus(2.0, elastomer="mooney_rivlin")
    with pytest.raises(ValueError, match="lamP"):
        Annulus(3.0, elastomer=GentIdealDielectric(mu=1.0, Jm=10.0, eps=1.0))
    with pytest.raises(ValueError, match="kappa.*elastomer"):
        circle_a.phibar_squared(2.0, 0.0, 0.0, 1 / JM, elastomer=GENT)
    with pytest.raises(ValueError, match="Jm.*elastomer"):
        analysis.pullin_suppression_prestretch(0.0, Jm=JM, elastomer=GENT)
    with pytest.raises(ValueError, match="kappa"):
        Annulus(2.0, elastomer=MR).kappa  # noqa: B018
    with pytest.raises(ValueError, match="elastomer"):
        membrane_law(None, MATERIALS["ideal_dielectric"])
    with pytest.raises(ValueError, match="annulus"):
        from debench.models.circular import collocation
        collocation.solve(Annulus(2.0, elastomer=MR), 2.5)


def test_the_gent_default_keeps_the_fused_law():
    """The thesis' model (Jm given or defaulted) runs the closed forms; only an elastomer
    selects the generic law."""
    assert Annulus(2.0).law == GentLaw.of_Jm(120.0) and Annulus(2.0).law.fused
    assert Annulus(2.0, Jm=math.inf).law.kappa == 0.0
    assert not Annulus(2.0, elastomer=GENT).law.fused
    assert Annulus(2.0, elastomer=GENT).Jm is None
