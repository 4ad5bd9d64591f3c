"""The axisymmetric (body-of-revolution) Chapter 5 model: kinematics, regularity, decoupling,
certified spectra, convergence, and agreement with the independent 3D model.

Claims checked (module docstring of :mod:`debench.models.buckling.axisym`):
the lifted reference body is stress free; the n = 0 torsion block decouples exactly; the
axis conditions per wavenumber are imposed; eigenvalues are certified by inertia counts;
the critical voltage converges monotonically in p; it is scale invariant; the voltage
maximum of the imperfect path is where the wavenumber-0 eigenvalue changes sign; and the
3D model's eigenvalues of wavenumbers 0 and 1 approach the axisymmetric ones from above.
"""

from __future__ import annotations

import functools
import math

import ngsolve as ngs
import numpy as np
import pytest
from debench.models.buckling import axisym as ax
from debench.models.buckling.analytic import KIRCHHOFF_N1_RATIO, critical_voltage_plate
from debench.models.buckling.axisym import linalg as ax_linalg
from debench.models.buckling.axisym import model as ax_model
from debench.models.buckling.axisym import path as ax_path
from debench.models.buckling.axisym.path import ZERO_STALL_COUNT, ZERO_STALL_W, ZERO_WTOL
from debench.models.buckling.axisym.spectra import EIG_RTOL
from debench.models.buckling.parameters import NeoHookean, Ogden, Plate
from debench.models.errors import ConvergenceError
from debench.models.numerics import newton as newton_policy
from debench.models.numerics import secants

pytestmark = pytest.mark.fe

COARSE = ax.AxisymDiscretisation(order=2, n_r=6, edge_layers=2, face_layers=2)
"""A cheap discretisation for the structural tests (about 1,500 state DOFs)."""

ROUNDOFF = 1e-12
"""Relative bound for quantities that vanish exactly in exact arithmetic (assembly sums of
O(100) terms of size |K| carry ~1e-14 relative round-off)."""


@pytest.fixture(scope="module", autouse=True)
def _one_thread():
    ngs.SetNumThreads(1)


@functools.cache
def nh_critical(disc: ax.AxisymDiscretisation) -> ax.AxisymCritical:
    """The wavenumber-0 critical voltage of the 1 mm neo-Hookean film on ``disc`` from the
    default start, solved once per test process for the tests that read it (read-only)."""
    return ax.critical_voltage(Plate(), NeoHookean(), disc)


def test_lifted_reference_body_is_stress_free():
    """The imperfection enters through the exact map G0 (det 1): at u = 0, v = 0 the
    residual vanishes, whatever the lift amplitude."""
    m = ax.AxisymModel(Plate(imperfection=0.05), NeoHookean(), COARSE)
    m.set_voltage(0.0)
    assert m.residual_norm() <= ROUNDOFF


def test_torsion_decouples_from_the_axisymmetric_block_at_n0():
    """For n = 0 the sin group is torsion (V alone) and the cos group (U, W, Q) the
    axisymmetric tangent: their coupling block is exactly zero at any axisymmetric state."""
    m = ax.AxisymModel(Plate(), Ogden(), COARSE)
    m.set_voltage(0.15)
    m.newton()
    K, _, _, _ = m.mode_matrices(0)
    blocks = m.mode_blocks(0)
    V = blocks == 1
    other = ~V
    coupling = abs(K[V][:, other]).max()
    assert coupling <= ROUNDOFF * abs(K).max()
    assert abs(K[V][:, V]).max() > 0


@pytest.mark.parametrize("n, zero_on_axis", [(0, (0, 1)), (1, (0, 2, 3)), (2, (0, 1, 2, 3)),
                                             (5, (0, 1, 2, 3))])
def test_axis_regularity_conditions_per_wavenumber(n, zero_on_axis):
    """Axis conditions (single-valued, finite-energy fields at R = 0): n = 0: U = V = 0;
    n = 1: S = U + V = 0, W = Q = 0 (D = U - V free); n >= 2: U = V = W = Q = 0. Block k of
    the perturbation space is fixed on the axis exactly for the listed k."""
    m = ax.AxisymModel(Plate(), NeoHookean(), COARSE)
    fixed = m.axis_fixed_blocks(n)
    assert fixed == set(zero_on_axis)


def test_spectrum_is_certified_and_refuses_a_shift_that_misses_the_lowest_eigenvalue():
    """The inertia count certifies the lowest eigenvalue; asked to search about a shift next
    midway between the second and third eigenvalues (the two nearest are then those), the count
    finds the missed lowest one and raises."""
    m = ax.AxisymModel(Plate(), NeoHookean(), COARSE, with_imperfection=False)
    m.set_voltage(0.1)
    m.newton()
    s = m.spectrum(0, nev=3)
    assert s.below == 0 and s.lam[0] > 0 and np.all(s.residual < EIG_RTOL)
    with pytest.raises(ConvergenceError, match="below the lowest computed"):
        m.spectrum(0, nev=1, sigma=0.5 * float(s.lam[1] + s.lam[2]))


def test_critical_voltage_converges_monotonically_in_the_order():
    """p = 2, 3, 4 on one graded mesh: v_cr decreases (conforming refinement of a
    Rayleigh quotient) and the changes contract by at least a factor 4 (measured 19 and
    10; the corner singularities limit the rate)."""
    vs = [ax.critical_voltage(Plate(), NeoHookean(),
                              ax.AxisymDiscretisation(order=p, n_r=6, edge_layers=3,
                                                      face_layers=3)).v for p in (2, 3, 4)]
    d1, d2 = vs[0] - vs[1], vs[1] - vs[2]
    assert d1 > 0 and d2 > 0
    assert d1 / d2 > 4.0


def test_a_start_next_to_the_root_saves_flat_state_solves_and_keeps_the_root():
    """The secant started at a neighbouring discretisation's value with a step of 1e-3
    (the plan's seeding) reaches the same root in three flat-state solves instead of four
    or five; the roots agree within the regeneration tolerance of the plan's voltages
    (measured 1e-11 .. 1.3e-8 on orders 3-4)."""
    from debench.reference.builders.ch5_axisym import REGEN_ATOL, SEED_STEP

    coarse = nh_critical(COARSE)
    fine = ax.AxisymDiscretisation(order=3, n_r=6, edge_layers=2, face_layers=2)
    cold = ax.critical_voltage(Plate(), NeoHookean(), fine)
    warm = ax.critical_voltage(Plate(), NeoHookean(), fine, v_start=coarse.v,
                               start_step=SEED_STEP)
    assert len(warm.history) == 3 < len(cold.history)
    assert abs(warm.v - cold.v) < REGEN_ATOL


def test_critical_voltage_is_scale_invariant():
    """The normalised problem depends on the aspect ratio only: t0 = 1 mm and 0.5 mm give
    the same v_cr to the secant's accuracy (vtol ~1e-13) times the conditioning (1e-9)."""
    assert Plate().thickness == 1e-3
    a = nh_critical(COARSE).v
    b = ax.critical_voltage(Plate(thickness=0.5e-3), NeoHookean(), COARSE).v
    assert b == pytest.approx(a, rel=1e-9)


#: the critical voltage's reproducibility: REPEAT_ATOL of the curated plan (1e-10, 10x the
#: secant's bound); an eigenvalue at a stagnated flat state moved it by 2.8e-9
START_BITS_ATOL = 1e-10


def test_the_critical_voltage_does_not_depend_on_the_last_bits_of_its_start():
    """Six starts 1e-13 apart on the coarse mesh give one critical voltage to 1e-10. The
    secant's last evaluation can land within ~1e-11 of the root, where the flat state's
    Newton stagnates along the near-null mode (measured: one start in six, its eigenvalue
    8.5e-11 against ~1e-12, v off by 2.8e-9); such an evaluation is not used for the
    root."""
    v0 = critical_voltage_plate(NeoHookean(), Plate().aspect)
    # k = 0 is the default start (the plate estimate v0)
    vs = [nh_critical(COARSE).v] + [
        ax.critical_voltage(Plate(), NeoHookean(), COARSE, v_start=v0 * (1 + k * 1e-13)).v
        for k in range(1, 6)]
    assert max(vs) - min(vs) <= START_BITS_ATOL, vs


def test_wavenumber_one_critical_voltage_tends_to_the_kirchhoff_ratio_from_below():
    """The first bifurcation of the flat clamped film is axisymmetric; n = 1 follows at the
    Kirchhoff ratio j_{2,1}/j_{1,1} = 1.34030 of thin clamped plates under equibiaxial
    compression, lowered by transverse shear, which softens the shorter n = 1 wave more, by
    O((t0/R)^2). Measured at order 3: 1.32566 (R/t0 = 10), 1.33658 (20), 1.33937 (40): the
    gap 1.46e-2, 3.7e-3, 9.3e-4 falls 3.95x and 3.98x per halving of t0/R."""
    kirchhoff = KIRCHHOFF_N1_RATIO
    gaps = []
    for aspect in (10.0, 20.0):
        d = ax.AxisymDiscretisation(order=3, n_r=int(0.8 * aspect), edge_layers=3,
                                    face_layers=3)
        v0 = ax.critical_voltage(Plate(aspect=aspect), NeoHookean(), d, n=0).v
        v1 = ax.critical_voltage(Plate(aspect=aspect), NeoHookean(), d, n=1, v_start=1.3 * v0).v
        gaps.append(kirchhoff - v1 / v0)
    assert 0 < gaps[1] < gaps[0] < 0.03
    # the O((t0/R)^2) shear correction: 4 per halving; 3..5 allows its own O((t0/R)^2) change
    assert 3.0 < gaps[0] / gaps[1] < 5.0


@pytest.fixture(scope="module")
def nh_path():
    """The imperfect neo-Hookean film's path through its voltage maximum (w ~ 5.5 t0), on a
    cheap discretisation: the model and its records 0.4 t0 apart."""
    m = ax.AxisymModel(Plate(imperfection=0.01), NeoHookean(),
                       ax.AxisymDiscretisation(order=2, n_r=8, edge_layers=3, face_layers=3))
    pts = ax.follow_path(m, 8.0, v_switch=0.18, dv=0.03, dw_max=0.5, wavenumbers=(0,),
                         record_every=0.4)
    return m, pts


def test_voltage_maximum_is_where_the_axisymmetric_eigenvalue_changes_sign(nh_path):
    """Deflection control through the pull-in: dv/dw changes sign between the same two
    recorded states as the wavenumber-0 eigenvalue of the tangent at fixed voltage (a
    limit point of the voltage is a singular tangent at fixed voltage)."""
    m, pts = nh_path
    v = np.array([p.v for p in pts])
    lam0 = np.array([p.lam[0] for p in pts])
    assert lam0[-1] < 0 <= lam0[-2]
    k = len(v) - 1
    assert v[k] < v[k - 1] or v[k - 1] - v[k - 2] < v[k - 2] - v[k - 3]
    top = ax.zero_crossing(m, pts, 0)
    # the zero of lambda_0 is the voltage maximum: no recorded state lies above it (up to
    # the Newton tolerance of the voltage, ~1e-12)
    assert top is not None and top.v >= v.max() - 1e-10
    assert pts[-2].w < top.w < pts[-1].w


@pytest.mark.parametrize("fraction", [1 / 6, 5 / 6])
def test_the_state_at_a_prescribed_deflection_does_not_depend_on_the_start(nh_path, fraction):
    """Deflection control to one deflection between the two records about the voltage
    maximum, once from each: the same state (the wavenumber-0 direction is soft there, so
    a state that stopped at the Newton tolerance would differ from the other start's by
    ~residual / stiffness: measured without the final polishing step 9e-9 relative in the
    voltage and 4.7e-8 in the state at these two deflections; with it 7e-16 and 2.5e-14)."""
    m, pts = nh_path
    a, b = pts[-3], pts[-1]
    w = a.w + fraction * (b.w - a.w)
    reached = []
    for start in (a, b):
        ax_path.deflect_from(m, (start.state, start.v), start.w, w)
        reached.append((m.v, m.state()))
    (va, xa), (vb, xb) = reached
    # 1e-12: 40x the measured round-off spread of the polished states (2.5e-14), 1e4 below
    # the spread of states stopped at the Newton tolerance
    assert abs(va - vb) <= 1e-12 * abs(va)
    assert np.linalg.norm(xa - xb) <= 1e-12 * np.linalg.norm(xa)


@pytest.mark.slow
@pytest.mark.parametrize("w_stall, ends", [(5.7, True), (4.0, False)])
def test_a_stalled_path_ends_only_past_the_voltage_maximum(w_stall, ends, monkeypatch):
    """A path that cannot be continued (every deflection-controlled solve beyond
    ``w_stall`` fails, as at a clamped corner reaching the edge of the material's domain)
    ends at its last converged state when that state is past the voltage maximum (its
    wavenumber-0 eigenvalue negative; the maximum of this film lies near w = 5.55 t0, the
    last step before the stall ends beyond it) and raises ConvergenceError when the stall
    comes before it. Records 3 t0 apart, so that no record falls between the maximum and
    the stall."""
    m = ax.AxisymModel(Plate(imperfection=0.01), NeoHookean(),
                       ax.AxisymDiscretisation(order=2, n_r=8, edge_layers=3, face_layers=3))
    solve = m.newton_deflection

    def stalls(c, **kw):
        if c > w_stall:
            raise ConvergenceError(f"stalled at c = {c}")
        return solve(c, **kw)

    monkeypatch.setattr(m, "newton_deflection", stalls)
    follow = functools.partial(ax.follow_path, m, 8.0, v_switch=0.18, dv=0.03, dw_max=0.5,
                               wavenumbers=(0,), record_every=3.0)
    if not ends:
        with pytest.raises(ConvergenceError, match="stalled"):
            follow()
        return
    pts = follow()
    # the last state: the last converged one before the stall, past the maximum
    assert pts[-1].w <= w_stall and pts[-1].lam[0] < 0 <= pts[-2].lam[0]
    # the maximum located between the two records 3 t0 apart: the secant's trial states
    # stay inside them (unguarded, one went to w = 5.92 t0, past this film's own stall
    # near 5.86 t0, and failed)
    monkeypatch.setattr(m, "newton_deflection", solve)
    top = ax.zero_crossing(m, pts, 0)
    assert top is not None and pts[-2].w < top.w < pts[-1].w


def test_bad_inputs_raise_naming_the_argument():
    with pytest.raises(ValueError, match="order"):
        ax.AxisymDiscretisation(order=0)
    with pytest.raises(ValueError, match="grading"):
        ax.AxisymDiscretisation(grading=1.0)
    for bad in (-1, 31, 2.5):
        with pytest.raises(ValueError, match="axis_layers"):
            ax.AxisymDiscretisation(axis_layers=bad)
    with pytest.raises(ValueError, match="wrinkle_imperfection"):
        ax.AxisymModel(Plate(wrinkle_imperfection=0.01), NeoHookean(), COARSE)
    for bad in (0.0, 0.6, math.nan):
        with pytest.raises(ValueError, match="start_step"):
            ax.critical_voltage(Plate(), NeoHookean(), COARSE, start_step=bad)
    m = ax.AxisymModel(Plate(), NeoHookean(), COARSE)
    with pytest.raises(ValueError, match="n"):
        m.spectrum(-1)
    with pytest.raises(ValueError, match="v"):
        m.set_voltage(math.nan)


def test_a_stalled_deflection_solve_gives_up_after_its_stall_steps(monkeypatch):
    """With ``stall`` the deflection-controlled Newton solve raises as soon as that many
    steps in a row have not lowered its best residual (here: every correction zero), not
    after all ``maxit``; without it, only after ``maxit``."""
    m = ax.AxisymModel(Plate(), NeoHookean(), COARSE, with_imperfection=True)
    m.set_voltage(0.1)
    m.newton()
    steps = []

    def no_progress(self, K, r, g, kf, dirv, c):
        steps.append(c)
        return np.zeros(int(np.count_nonzero(self.free))), 0.0

    monkeypatch.setattr(ax_model.AxisymModel, "_bordered_step", no_progress)
    target = m.centre_deflection() + 0.1
    with pytest.raises(ConvergenceError, match="no lower residual .* in 3 steps"):
        m.newton_deflection(target, stall=3, maxit=30)
    assert len(steps) == 3
    steps.clear()
    with pytest.raises(ConvergenceError, match="after 30 steps"):
        m.newton_deflection(target, maxit=30)
    assert len(steps) == 30
    with pytest.raises(ValueError, match="stall"):
        m.newton_deflection(target, stall=0)


def test_newton_refuses_a_state_outside_the_material_domain_before_factorising(monkeypatch):
    """A state with inverted elements (u_z = -2 Z: F_zz = -1, the energy NaN) makes both Newton
    solvers raise ConvergenceError naming the non-finite residual, without a factorisation: a
    NaN matrix given to SuperLU calls BLAS with negative sizes (the OpenBLAS message "DGEMV
    parameter number 2 had an illegal value") before it fails."""
    m = ax.AxisymModel(Plate(), Ogden(), COARSE, with_imperfection=False)
    m.set_voltage(0.1)
    g = ngs.GridFunction(m.X)
    g.components[1].Set(-2.0 * ngs.y)
    inverted = np.array(g.vec.FV())

    def no_factorisation(*args, **kwargs):
        raise AssertionError("a non-finite matrix reached SuperLU")

    for module in (ax_linalg, ax_model):      # every place the model calls SuperLU
        monkeypatch.setattr(module, "splu", no_factorisation)
    for solve in (m.newton, lambda: m.newton_deflection(0.5)):
        m.set_state(inverted)
        with pytest.raises(ConvergenceError, match="non-finite residual or tangent"):
            solve()


@pytest.mark.slow
def test_a_long_deflection_jump_is_halved_inside_the_domain_and_subdivided():
    """From the Ogden film's state at w = 2 t0, one deflection-controlled solve at w = 4 t0
    takes Newton corrections whose trial states invert elements (non-finite residual): they
    are halved (counted in ``stats``), and the solve that still does not converge raises
    ConvergenceError; :func:`~debench.models.buckling.axisym.path.deflect_from` reaches the
    same deflection by subdividing the jump (the route of the secant's trial states)."""
    mat = Ogden()
    m = ax.AxisymModel(Plate(aspect=10.0), mat,
                       ax.AxisymDiscretisation(order=2, n_r=8, edge_layers=2, face_layers=2),
                       with_imperfection=True)
    vs = 0.8 * critical_voltage_plate(mat, 10.0)
    ax.follow_path(m, 2.0, v_switch=vs, dv=vs / 8, wavenumbers=(0,), stop_past_maximum=False)
    start = (m.state(), m.v)
    with pytest.raises(ConvergenceError, match="newton_deflection"):
        m.newton_deflection(4.0)
    assert m.stats["domain_halvings"] > 0
    ax_path.deflect_from(m, start, 2.0, 4.0)
    # the Newton tolerance on the centre DOF: 1e-12 t0 (newton_deflection's stopping rule)
    assert abs(m.centre_deflection() - 4.0) < 1e-10
    assert m.v > start[1]


@pytest.mark.slow
def test_3d_eigenvalues_of_wavenumbers_0_and_1_approach_the_axisymmetric_ones():
    """At v = 0.2 on the perfect film the 3D model's lowest eigenvalue (n = 0) and its
    double second one (cos and sin of n = 1) decrease with the 3D mesh towards the
    converged axisymmetric eigenvalues of n = 0 and n = 1 (measured 3D h = 1.5, 1.0 t0:
    8.69e-4, 7.35e-4 against 5.89e-4; 8.60e-3, 7.88e-3 against 7.72e-3)."""
    from debench.models.buckling.fem import MembraneModel
    from debench.models.buckling.parameters import Discretisation

    m = ax.AxisymModel(Plate(), NeoHookean(), ax.AxisymDiscretisation(order=5),
                       with_imperfection=False)
    m.set_voltage(0.2)
    m.newton()
    ref = (m.spectrum(0, 1).lam[0], m.spectrum(1, 1).lam[0])
    errors = []
    for h in (1.5, 1.0):
        m3 = MembraneModel(Plate(), NeoHookean(), Discretisation(h_rel=h, layers=2, order=2),
                           with_imperfection=False)
        m3.set_voltage(0.2)
        m3.newton()
        w, _ = m3.lowest_eigenvalues(nev=3)
        assert w[2] - w[1] < 0.01 * w[1]          # the n = 1 pair
        errors.append((w[0] - ref[0], w[1] - ref[1]))
    (e0c, e1c), (e0f, e1f) = errors
    assert 0 < e0f < e0c and 0 < e1f < e1c


def test_no_wavenumber_is_sensitive_to_layers_towards_the_axis():
    """The axis regularity of every wavenumber admits the smooth fields, so geometric layers
    towards the axis (``axis_layers``) change the lowest eigenvalues of the flat film at
    v = 0.25 only by the small discretisation change of the extra elements (measured at
    order 3, 4 axis layers: <= 1.3e-6 relative for n = 0..3). A wavenumber-1 space that
    pins D = U - V on the axis instead of S = U + V (it excludes the sideways translation of
    the axis, which only a layer of vanishing width can mimic) gives lambda_1 4.357e-3 ->
    3.891e-3 here (-11 %), falling on with more layers."""
    lam = []
    for k in (0, 4):
        d = ax.AxisymDiscretisation(order=3, n_r=6, edge_layers=2, face_layers=2, axis_layers=k)
        m = ax.AxisymModel(Plate(), NeoHookean(), d, with_imperfection=False)
        m.set_voltage(0.25)
        m.newton()
        lam.append([m.spectrum(n, nev=1).lam[0] for n in (0, 1, 2, 3)])
    # 1e-4 relative: 80x the measured change, 1,000x below the change of a mis-pinned n = 1
    for a, b in zip(*lam, strict=True):
        assert b == pytest.approx(a, rel=1e-4)


def test_newton_next_to_the_critical_voltage_takes_its_best_iterate_when_it_oscillates():
    """The Ogden film at order 2 with 2 layers: the secant's trial voltage 0.14730354 lies
    within 1e-3 of the critical voltage, where the flat state's full Newton steps alternate
    between ~1e-13 and ~1e-9 of the load (the near-null buckling mode); without the
    stall rule Newton raised after 40 steps. The critical voltage now converges, between
    the order-3 value (measured 0.14716) and 0.1 % above it."""
    d = ax.AxisymDiscretisation(order=2, edge_layers=2, face_layers=2)
    m = ax.AxisymModel(Plate(thickness=1e-3, aspect=10.0), Ogden(), d,
                       with_imperfection=False)
    m.set_voltage(0.14730354)
    m.newton()
    assert m.last_newton.residual_rel <= ax_model.NEWTON_STAGNATION_RTOL
    r = ax.critical_voltage(Plate(thickness=1e-3, aspect=10.0), Ogden(), d)
    assert 0.14716 < r.v < 0.14716 * 1.001


def test_coupled_critical_voltage_lies_above_the_frozen_potential_and_initial_stress_ones():
    """Condensing the potential adds a positive semi-definite term to the tangent (the
    enthalpy is a maximum in the potential), so the coupled critical voltage is never below
    the frozen-potential one; the initial-stress operator (material stiffness of the unloaded
    film + the stress stiffness of the flat state) differs from the frozen-potential one only
    by the pre-buckling state's material nonlinearity and the field's share of the material
    tangent (measured at p = 3: coupled 0.220273, frozen 0.215303, initial stress 0.215372)."""
    d = ax.AxisymDiscretisation(order=2, n_r=6, edge_layers=3, face_layers=3)
    v = {t: ax.critical_voltage(Plate(), NeoHookean(), d, tangent=t).v for t in ax.TANGENTS}
    assert v["coupled"] > v["frozen_potential"] * 1.01     # the coupling: ~2.3 %
    assert v["initial_stress"] == pytest.approx(v["frozen_potential"], rel=2e-3)


@pytest.mark.slow
def test_no_wrinkling_before_the_voltage_maximum_of_the_neo_hookean_film():
    """R/t0 = 10, neo-Hookean, imperfection 1e-3 t0: at the voltage maximum (pull-in) the
    lowest eigenvalue of every wavenumber n = 1..8 is positive with a margin far above its
    discretisation change (measured p = 4: min over n 0.0119 at n = 1, v = 0.67958,
    w = 5.561 t0), so the pull-in is axisymmetric."""
    m = ax.AxisymModel(Plate(), NeoHookean(), ax.AxisymDiscretisation(order=3, n_r=8))
    pts = ax.follow_path(m, 20.0, v_switch=0.17, dv=0.02, record_every=0.5,
                         wavenumbers=(0,))
    top = ax.zero_crossing(m, pts, 0)
    # the p = 4 value; p = 3 within 1 % (the critical voltage moves by 2e-5 from p = 3 to 4)
    assert top is not None and top.v == pytest.approx(0.6796, rel=1e-2)
    lam = [m.spectrum(n, 1).lam[0] for n in range(1, 9)]
    assert min(lam) > 0.005


@pytest.mark.slow
def test_a_wrinkling_crossing_does_not_depend_on_the_record_its_trial_states_start_from():
    """The Ogden R/t0 = 20 film of the path study at order 2, 6 layers: the zero of the
    wavenumber-12 eigenvalue located by :func:`~debench.models.buckling.axisym.zero_crossing`
    (trial states from the nearer of the two bracketing records) and the zero of
    lambda_12 evaluated from the upper record alone at +-1e-3 t0 about it agree. Measured
    with states stopped at the Newton tolerance: 8.634389 against 8.62952 t0 (the
    non-monotone lambda_12 from the upper record); with the polishing step both 8.629524,
    lambda_12 from the two starts within 3e-9 (the eigensolver's backward error 1e-10)."""
    from debench.reference.studies.ch5 import material
    from debench.reference.studies.ch5_axisym import PATH_FILMS as CASES
    from debench.reference.studies.ch5_axisym import PATH_N_R_PER_ASPECT as N_R_PER_ASPECT
    from debench.reference.studies.ch5_axisym import V_SWITCH

    mat_name, t0, aspect, _, w_from, spacing = CASES["ogden_r20"]
    mat = material(mat_name)
    disc = ax.AxisymDiscretisation(order=2, edge_layers=6, face_layers=6,
                                   n_r=max(1, round(N_R_PER_ASPECT * aspect)))
    m = ax.AxisymModel(Plate(thickness=t0, aspect=aspect), mat, disc, with_imperfection=True)
    v_switch = V_SWITCH * critical_voltage_plate(mat, aspect)
    pts = ax.follow_path(m, 9.2, v_switch=v_switch, dv=v_switch / 8, record_every=spacing,
                         wavenumbers=(0,), all_from=w_from, all_wavenumbers=(12,))
    zero = ax.zero_crossing(m, pts, 12)
    assert zero is not None
    upper = next(p for p in pts if 12 in p.lam and p.w > zero.w)
    lam = []
    for w in (zero.w - 1e-3, zero.w + 1e-3):
        ax_path.deflect_from(m, (upper.state, upper.v), upper.w, w)
        lam.append(m.spectrum(12, nev=1).lam[0])
    w_upper = zero.w - 1e-3 + 2e-3 * lam[0] / (lam[0] - lam[1])
    # 1e-5 t0: lambda_12's start spread (3e-9) over its slope (3.9e-3 per t0) is 1e-6 t0,
    # the linear interpolation over 2e-3 t0 adds < 1e-7; the start dependence gave 4.9e-3
    assert abs(w_upper - zero.w) < 1e-5


#: the zero finder of the path's crossings with the path's tolerances
secant_zero = functools.partial(secants.secant_zero, xtol=ZERO_WTOL, stall_width=ZERO_STALL_W,
                                stall_count=ZERO_STALL_COUNT)


def test_secant_zero_converges_on_a_smooth_function():
    """A smooth root: the secant stops on a step below ZERO_WTOL, at the root to it."""

    def f(w):
        return 1e-3 * (7.2 - w) + 1e-4 * (7.2 - w) ** 2

    ws, ls = [7.0, 7.5], [f(7.0), f(7.5)]
    k, tol = secant_zero(f, ws, ls)
    assert abs(ws[k] - 7.2) < 10 * ZERO_WTOL and tol < ZERO_WTOL


def test_secant_zero_stops_where_it_stagnates_at_the_round_off_floor():
    """A root under round-off noise of 5e-11 on a slope of 6e-4 per t0 (the Ogden R/t0 = 20,
    n = 6 crossing that wandered within 1e-7 t0): the secant returns the iterate with the
    smallest |f| once ZERO_STALL_COUNT iterates lie within ZERO_STALL_W, within the noise's
    reach of the root (noise / slope ~ 1e-7), and says how far the iterates spread."""

    rng = np.random.default_rng(1)

    def f(w):
        return 6e-4 * (7.1734317 - w) + 5e-11 * rng.standard_normal()

    ws, ls = [7.14, 7.64], [f(7.14), f(7.64)]
    k, tol = secant_zero(f, ws, ls)
    assert abs(ws[k] - 7.1734317) < 1e-6 and tol < ZERO_STALL_W


def test_secant_zero_keeps_its_iterates_inside_the_starting_bracket():
    """A root near one end of a strongly curved f: the pure secant's second iterate would
    leave the bracket [0, 3] (where f would be evaluated on states that no recorded one
    bounds); every evaluation stays inside it, and the root is found to ZERO_WTOL."""
    seen = []

    def f(w):
        seen.append(w)
        return math.exp(-3.0 * w) - 0.5

    ws, ls = [0.0, 3.0], [f(0.0), f(3.0)]
    k, tol = secant_zero(f, ws, ls)
    root = math.log(2.0) / 3.0
    assert abs(ws[k] - root) < 10 * ZERO_WTOL and tol < ZERO_WTOL
    assert all(0.0 <= w <= 3.0 for w in seen)
    # the unguarded secant from the same points leaves the bracket at its second step
    w1 = 3.0 - ls[1] * (3.0 - 0.0) / (ls[1] - ls[0])
    w2 = w1 - (math.exp(-3 * w1) - 0.5) * (w1 - 3.0) / ((math.exp(-3 * w1) - 0.5) - ls[1])
    assert not 0.0 <= w2 <= 3.0


def test_secant_zero_shrinks_the_bracket_from_both_sides():
    """Plain false position keeps one end of the bracket for good where f is convex over
    it (w**10 - 1 on [0, 1.3]: 30 steps leave the bracket wider than 0.1, asserted below).
    The Illinois bracket closes from both sides and finds the root to ZERO_WTOL."""

    def f(w):
        return w**10 - 1.0

    ws, ls = [0.0, 1.3], [f(0.0), f(1.3)]
    k, tol = secant_zero(f, ws, ls)
    assert abs(ws[k] - 1.0) < 10 * ZERO_WTOL and tol < ZERO_WTOL
    assert all(0.0 <= w <= 1.3 for w in ws)
    a, b = 0.0, 1.3
    for _ in range(30):
        c = a - f(a) * (b - a) / (f(b) - f(a))
        a, b = (c, b) if np.sign(f(c)) == np.sign(f(a)) else (a, c)
    assert abs(b - a) > 0.1


def test_secant_zero_brackets_a_sign_change_under_an_offset():
    """The Ogden R/t0 = 20, n = 6 crossing at order 3 with six layers: slope -7.7e-4 per t0,
    the evaluations on the two sides of the sign change offset by 6e-8 from each other
    (trial states from different recorded neighbours). The bracket closes below
    ZERO_STALL_W around the sign change and the answer lies inside it."""
    root = 7.1581892

    def f(w):
        return -7.7e-4 * (w - root) + (6e-8 if w < root else -6e-9)

    ws = [6.891483286642438, 7.641483286642438]
    ls = [f(ws[0]), f(ws[1])]
    k, tol = secant_zero(f, ws, ls)
    assert abs(ws[k] - root) <= max(tol, ZERO_WTOL) and tol < ZERO_STALL_W


def test_secant_zero_raises_on_a_function_without_a_root():
    from debench.models.errors import ConvergenceError

    with pytest.raises(ConvergenceError, match="flat secant|no convergence"):
        secant_zero(lambda w: 1.0 + 0 * w, [0.0, 1.0], [1.0, 1.0])
    with pytest.raises(ConvergenceError, match="flat secant|no convergence"):
        secant_zero(lambda w: 1.0 + w * w, [0.0, 1.0], [1.0, 2.0], maxit=5)
    # a minimum of |f| above zero: the iterates stagnate without bracketing a root
    with pytest.raises(ConvergenceError, match="flat secant|no convergence"):
        secant_zero(lambda w: 1e-12 + (w - 3.0) ** 2, [2.0, 2.5], [1.0, 0.25])


GRADED = ax.AxisymDiscretisation(order=2, n_r=6, edge_layers=6, face_layers=6)
"""A cheap discretisation with the curated plan's grading (6 layers of ratio 0.25 towards the
rim and both faces: elements of 1.2e-4 t0 next to the clamped corners)."""


def test_the_newton_reference_is_the_load_and_does_not_grow_with_the_grading():
    """Newton's reference residual is the load the voltage applies (the undeformed film under
    the uniform field): it does not change with the grading (measured 5.656e-7 .. 5.666e-7
    on 1 .. 8 layers at v = 0.2). A scale that grew with the layers (e.g. the residual of a
    potential that is zero inside the film, 4^2 per layer) made Newton stop one step early on
    the fine gradings and lowered their critical voltages by 3e-6."""
    scales = []
    for layers in (1, 3, 6):
        d = ax.AxisymDiscretisation(order=2, n_r=6, edge_layers=layers, face_layers=layers)
        m = ax.AxisymModel(Plate(), NeoHookean(), d, with_imperfection=False)
        m.set_voltage(0.2)
        scales.append(m.load_scale())
    # 1 %: the nodal forces of one traction on meshes that differ only near the rim
    assert max(scales) / min(scales) < 1.01


def test_the_critical_voltage_does_not_move_when_the_flat_states_are_solved_to_round_off(
        monkeypatch):
    """On the curated plan's grading the flat states of the secant, solved to the stopping
    rule of AxisymModel.newton or to round-off (relative residual 1e-15, floor factor 1),
    give the same critical voltage to 1e-10 (measured 3e-16 at order 2 with 6 layers; 3.0e-6
    when Newton's reference grew with the grading and the rule stopped one step early)."""
    base = nh_critical(GRADED).v        # solved before the patches below
    newton = ax.AxisymModel.newton
    monkeypatch.setattr(newton_policy, "FLOOR_FACTOR", 1.0)
    monkeypatch.setattr(ax.AxisymModel, "newton",
                        lambda self, **kw: newton(self, **{**kw, "rtol": 1e-15}))
    tight = ax.critical_voltage(Plate(), NeoHookean(), GRADED).v
    # 1e-10: the secant's own tolerance (vtol ~1e-12) times 100
    assert tight == pytest.approx(base, abs=1e-10)


@pytest.mark.parametrize("n", [0, 1])
@pytest.mark.parametrize("tangent", ax.TANGENTS)
def test_the_rayleigh_quotients_are_the_pencil_eigenvalues(n, tangent):
    """The eigenvalues of a spectrum are the Rayleigh quotients of its eigenvectors with the
    second variation integrated at the quadrature points; on a coarse mesh, where the
    assembled pencil's round-off is small, they equal the pencil's eigenvalues: the
    quotients' quadrature is that of the assembly (measured <= 4e-11 relative)."""
    m = ax.AxisymModel(Plate(), NeoHookean(), COARSE, with_imperfection=False)
    m.set_voltage(0.15)
    m.newton()
    s = m.spectrum(n, nev=2, tangent=tangent)
    # 1e-9: the pencil eigenvalues' backward error (EIG_RTOL 1e-10) over the gap to zero
    np.testing.assert_allclose(s.lam, s.lam_matrix, rtol=1e-9)


@pytest.mark.parametrize(("material", "n"), [(NeoHookean(), 0), (NeoHookean(), 2), (Ogden(), 2)],
                         ids=["nh-0", "nh-2", "ogden-2"])
def test_the_second_variation_is_the_symbolic_second_derivative(material, n):
    """The numerator of the Rayleigh quotients (NGSolve's automatic differentiation of the
    perturbation energy in one global unknown t, assembled at the quadrature points) equals
    the integral of the symbolic ``d^2/dt^2 energy(t x)|_0`` of the same energy (NGSolve's
    ``Diff`` twice) at the same quadrature: two differentiations of one expression, for a
    smooth random perturbation at a loaded state."""
    m = ax.AxisymModel(Plate(), material, COARSE, with_imperfection=False)
    m.set_voltage(0.6 * critical_voltage_plate(material, Plate().aspect))
    m.newton()
    x, q, at_zero, _ = m._second_variation(n, "coupled")
    x.vec.FV().NumPy()[:] = np.random.default_rng(1).standard_normal(x.space.ndof)
    q.AssembleLinearization(at_zero.vec)
    ad = ax_linalg.csr_of(q.mat, 1)[0, 0]
    t = ngs.Parameter(0.0)
    energy = m._perturbation_energy(n, "coupled", *x.components, t)
    order = 2 * COARSE.order
    symbolic = ngs.Integrate((energy.Diff(t).Diff(t) * m.R).Compile(), m.mesh, order=order)
    # 1e-12 relative: both sum the same quadrature of the same second derivative; they
    # differ in the order of the floating-point operations only
    # (measured <= 1.2e-16; the symbolic Ogden derivative alone costs ~5 s: one wavenumber)
    assert ad == pytest.approx(symbolic, rel=1e-12)


def test_the_critical_voltage_does_not_depend_on_the_secant_start():
    """The refined eigenvalue (a Rayleigh quotient free of the assembled matrices'
    cancellation) makes the root reproducible: two starts on the curated plan's grading agree
    to 1e-10 (measured 7e-16 at order 2 with 6 layers), where the matrix eigenvalues
    scattered by ~1e-9 of the bending scale next to the root (~3e-8 in v at order 4 with
    8 layers)."""
    a = nh_critical(GRADED)
    b = ax.critical_voltage(Plate(), NeoHookean(), GRADED, v_start=1.001 * a.v,
                            start_step=0.01)
    # 1e-10: 100x the secant's stopping tolerance in v (vtol)
    assert b.v == pytest.approx(a.v, abs=1e-10)
