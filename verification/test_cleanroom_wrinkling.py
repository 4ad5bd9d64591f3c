"""The clean room of ch5_wrinkling (verification/cleanroom/wrinkling.py: the Ogden film at
a = 20 t0, the axisymmetric path by bordered Newton, the wavenumber-n condensed tangent)
passes ``debench check`` at its own, measured accuracy on the wavenumbers its default run
computes (n = 6, 7, 8, declared ``--partial``), finds n = 7 first, its Ogden Hessian is
the finite-difference derivative of its gradient, and two refined discretisations pass
``debench check`` at the reference's stated accuracy for every wavenumber with a reference
value (n = 6..12, slow).

Measured (full path to the voltage maximum, n = 6..12; P = order, n_r radial intervals x
n_z layers, L corner refinements; process CPU seconds, one thread, on a loaded 2-core
machine; "ratio" the largest |clean room - reference| / stated accuracy over n = 6..12):

    disc        dofs  CPU s  w_cross, n = 6 .. 12                                   ratio
    P3 40x2 L2  2982    54   7.15737 7.10670 7.28377 7.53331 7.82679 8.16996 8.61232  1.29
    P4 40x2 L2  5115    92   7.15631 7.10609 7.28304 7.53234 7.82545 8.16801 8.60907  0.092
    P4 40x2 L4  5931   122   7.15636 7.10611 7.28305 7.53234 7.82545 8.16800 8.60904  0.084
    P3 60x3 L3  6132    82   7.15608 7.10597 7.28299 7.53236 7.82554 8.16816 8.60918  0.185
    P4 40x4 L2  9027   185   7.15624 7.10606 7.28299 7.53226 7.82533 8.16782 8.60873  0.036
    P3 80x4 L4 10335   224   7.15602 7.10594 7.28293 7.53225 7.82537 8.16790 8.60875  0.134
    P4 60x3 L3 10623   271   7.15626 7.10607 7.28300 7.53227 7.82535 8.16785 8.60875  0.027
    P4 80x4 L4 18003   511   7.15623 7.10605 7.28298 7.53225 7.82532 8.16781 8.60870  0.045
    reference                7.15632 7.10610 7.28302 7.53229 7.82536 8.16786 8.60882
    stated accuracy          2.3e-3  1.2e-3  1.1e-3  1.1e-3  1.3e-3  1.6e-3  2.7e-3

    disc        v_cross, n = 6 .. 12                                      ratio
    P3 40x2 L2  0.399760 0.397649 0.404882 0.414355 0.424304 0.434142 0.443810  1.17
    P4 40x2 L2  0.399702 0.397609 0.404840 0.414309 0.424253 0.434086 0.443748  0.099
    P4 40x2 L4  0.399702 0.397608 0.404839 0.414308 0.424252 0.434085 0.443747  0.078
    P3 60x3 L3  0.399699 0.397611 0.404844 0.414315 0.424260 0.434093 0.443752  0.237
    P4 40x4 L2  0.399696 0.397604 0.404835 0.414303 0.424247 0.434079 0.443741  0.035
    P3 80x4 L4  0.399692 0.397605 0.404838 0.414308 0.424252 0.434084 0.443743  0.078
    P4 60x3 L3  0.399697 0.397605 0.404836 0.414305 0.424248 0.434080 0.443741  0.023
    P4 80x4 L4  0.399695 0.397604 0.404835 0.414303 0.424246 0.434079 0.443740  0.043
    reference   0.399699 0.397606 0.404836 0.414305 0.424248 0.434081 0.443743
    stated      1.1e-4   6.4e-5   5.5e-5   5.2e-5   5.2e-5   5.3e-5   5.8e-5

The layers matter most at P4 (40x2 -> 40x4 L2: n = 12 moves 3.4e-4 in w, 7.4e-6 in v;
60x3 L3 -> 80x4 L4: <= 5.0e-5 and 1.8e-6), the corner refinements little (L2 -> L4 at
40x2: <= 5.0e-5 in w, 1.3e-6 in v); P4 40x4 L2 -> P4 80x4 L4 changes w by <= 2.6e-5 and
v by <= 4.4e-7, P3 -> P4 at 80x4 L4 w by <= 2.2e-4 (n = 6) and v by <= 5.5e-6. The
finest (P4 80x4 L4) lies 3.4e-5 .. 1.2e-4 below the reference in w and 1.3e-6 .. 3.4e-6
below in v (<= 0.045 of the stated accuracy): more than its own last changes, far less
than the stated accuracy. P4 60x3 L3 stopped on a Newton iterate with det F <= 0 on its
path before such an iterate became a failed Newton, answered by a shorter step
(``Film.at_deflection``); the row is the run since. P3 40x2 L2 (the run of the other two
slow tests) exceeds the stated accuracy at n = 10, 11, 12 (w and v): only its own P2 -> P3
change is claimed for it below: P2 40x2 L2 (1419 dofs, 19 s CPU) gave w_cross 7.17955 /
7.13320 / 7.31287 and v_cross 0.400258 / 0.398347 / 0.405600 for n = 6 / 7 / 8. The P3
40x2 L2 row was timed before the wavenumbers shared the state's energy Hessian; since, P3
40x2 L2 computes all fourteen wavenumbers in 62 s CPU and finds a zero exactly for n =
6..12 (the same values), none for n = 1..5, 13, 14.

The wavenumbers without a reference value (n = 1..5, 13, 14: no zero before the voltage
maximum, v_max 0.456071 at w 10.477 in the reference) were computed on three
discretisations: P3 40x2 L2 and P4 40x4 L2 find no zero for any of them, as the
reference; P3 80x4 L4 (434 s CPU for all fourteen) finds one for n = 13 at w 9.73091,
v 0.454945, shortly before the maximum. That zero is the clean room's, not the film's.
On meshes whose 20 or 40 strips in the last t0 before the rim are narrow for their layers
(0.05 t0 under 4 or 8 layers, 0.025 t0 under 8 or 16; P3 80x4 L4 has 0.05 under 4) the
axisymmetric state develops, from w ~ 9 on, an oscillation with the element period at the
top electrode next to the clamp (R 19.4 .. 19.7, Z > 0.9): |u_z,R minus a smooth fit|
grows from 0.045 at w 9.0 to 0.79 at 9.8 on P4 40x4 with 20 strips (about 6e-3, the fit's
floor, on smooth meshes), the largest principal stretch there is 1.76 against 1.07. It is
not a material instability (the condensed acoustic tensor stays >= 0.42) nor an
axisymmetric mode (the n = 0 tangent's lowest eigenvalues are global, >= 4.5e-4): a
different discrete equilibrium (the smooth state carried onto that mesh and re-converged by
load homotopy meets a fold at 12 % load). It lowers lambda_13 by up to 1.5e-4, to a zero
at w 9.578 (20 strips under 4 layers) or 9.679 (40 under 8); the n = 13 mode itself is the
same smooth 13-wave wrinkle on both kinds of mesh (0.2 % of its mass beyond R = 19), and
the smooth state carried onto the oscillating mesh gives the smooth eigenvalue there
(+8.29e-5 against -6.37e-5 at w 9.8; quadrature order + 4 and P3 change nothing). Three
oscillation-free meshes of different resolution (P4: 10 strips under 4 layers; 20 under
16; 20 under 16 with the top rim corner refined once more, 44739 dofs) agree on lambda_13
to 4e-7 at every w, minimum +8.4e-5 near w 9.8, no zero (the reference: +9.4e-5 .. 1.06e-4;
that difference is not explained). Why narrow strips let the state oscillate is not
established; a plausible reading: the potential is maximised in the saddle point, so an
under-resolved potential softens the discrete system, and narrow, tall triangles follow a
short radial wavelength at the electrode but not its equally fast decay through the
thickness. The crossings of n = 6..12 lie before w 8.61, where every mesh's state agrees;
``test_wavenumber_thirteen_does_not_cross_before_the_voltage_maximum`` asserts n = 13 on
the oscillation-free P4 40x4 L2.
"""

from __future__ import annotations

import numpy as np
import pytest
from debench.reference import cli

from verification.cleanroom import buckling, pullin, wrinkling

#: the run of the two path tests (--full): P3, 40 radial intervals x 2 layers, 2 corner
#: refinements (~30 s CPU, a quarter of the default test budget: opt in)
FAST = {"order": 3, "n_r": 40, "n_z": 2, "levels": 2}
FAST_N = (6, 7, 8)
#: the measured P2 -> P3 change of n = 7 (module docstring), relative
RTOL_W = 3.7e-3
RTOL_V = 1.8e-3
#: central differences with h = 1e-6 of values O(50) (k/mu_ref): truncation + round-off
FD_ATOL = 1e-6


@pytest.fixture(scope="module")
def fast():
    return wrinkling.crossings(**FAST, wavenumbers=FAST_N)


def _csv(path, name, ns, values):
    rows = "".join(f"ogden_r20,{n},{float(v)!r}\n" for n, v in zip(ns, values, strict=True))
    path.write_text(f"case,n [1],{name} [1]\n" + rows)
    return str(path)


@pytest.mark.slow
def test_cleanroom_wrinkling_passes_check_at_its_own_accuracy(fast, tmp_path, capsys):
    """w_cross and v_cross of n = 6, 7, 8 at the measured P2 -> P3 change (partial file)."""
    assert fast.complete and np.all(np.isfinite(fast.w_cross))
    for name, values, rtol in (("w_cross", fast.w_cross, RTOL_W),
                               ("v_cross", fast.v_cross, RTOL_V)):
        path = _csv(tmp_path / f"{name}.csv", name, fast.wavenumbers, values)
        assert cli.main(["check", "ch5_wrinkling", path, "--partial",
                         "--rtol", str(rtol)]) == 0, name


#: the wavenumbers with a reference value (a zero before the voltage maximum); the refined
#: runs compute these only (module docstring: n = 13 on P3 80 x 4)
CROSSING_N = tuple(range(6, 13))
#: two refined discretisations of the clean room, each checked at the reference's stated
#: accuracy, so that the confirmation does not rest on one mesh: P4 40 x 4, 2 corner
#: refinements (9027 dofs, 185 .. 303 s CPU over three runs on the loaded machine) and P3
#: 80 x 4, 4 refinements (10335 dofs, 224 .. 287 s); measured within 0.036 and 0.134 of the
#: stated accuracy (module docstring's table)
WRINKLING_REFINED = {"p4_40x4": {"order": 4, "n_r": 40, "n_z": 4, "levels": 2},
                     "p3_80x4": {"order": 3, "n_r": 80, "n_z": 4, "levels": 4}}


@pytest.mark.slow
@pytest.mark.parametrize("disc", list(WRINKLING_REFINED))
def test_cleanroom_wrinkling_passes_check_refined(disc, tmp_path, capsys):
    """w_cross and v_cross of every wavenumber with a reference value (n = 6..12), one file
    of both, at the reference's stated accuracy (no --rtol, full coverage)."""
    res = wrinkling.crossings(**WRINKLING_REFINED[disc], wavenumbers=CROSSING_N)
    assert res.complete and np.all(np.isfinite(res.w_cross))
    rows = "".join(f"ogden_r20,{n},{float(w)!r},{float(v)!r}\n"
                   for n, w, v in zip(res.wavenumbers, res.w_cross, res.v_cross, strict=True))
    path = tmp_path / "wrinkling.csv"
    path.write_text("case,n [1],w_cross [1],v_cross [1]\n" + rows)
    assert cli.main(["check", "ch5_wrinkling", str(path)]) == 0
    assert capsys.readouterr().out.count("coverage complete") == 2


#: a discretisation whose axisymmetric state has no element-scale oscillation at the top
#: electrode next to the clamp up to the voltage maximum (module docstring): P4, 10 rim
#: strips of 0.1 t0 under 4 layers, 2 corner refinements (9027 dofs)
SMOOTH_RIM = {"order": 4, "n_r": 40, "n_z": 4, "levels": 2, "rim": 10}
#: lambda_13's minimum on the path is +8.4e-5 on three such meshes (agreeing to 4e-7) and
#: +9.4e-5 .. 1.06e-4 in the reference; the oscillating states lower it by ~1.5e-4 (to
#: -6.4e-5): half the measured minimum separates the two
N13_MIN_LAMBDA = 4e-5


@pytest.mark.slow
def test_wavenumber_thirteen_does_not_cross_before_the_voltage_maximum():
    """n = 13 (no reference value: no zero before the voltage maximum) stays stable along
    the whole path on a discretisation whose state is free of the rim oscillation, its
    lowest eigenvalue at least N13_MIN_LAMBDA (~50 s CPU)."""
    res = wrinkling.crossings(**SMOOTH_RIM, wavenumbers=(13,))
    assert res.complete and np.isnan(res.w_cross[0])
    assert np.min(np.asarray(res.lams)[:, 0]) >= N13_MIN_LAMBDA


@pytest.mark.slow
def test_wavenumber_seven_is_first(fast):
    """n = 7 loses stability first (before 6 and 8), before the voltage maximum."""
    assert fast.wavenumbers[int(np.argmin(fast.w_cross))] == 7
    assert np.max(fast.w_cross) < fast.max_bracket[0]
    for b in fast.brackets:
        assert b[1] - b[0] <= 1e-8 and b[2] > 0 >= b[3]


def test_ogden_hessian_is_the_derivative_of_its_gradient():
    """Gradient = central differences of the value, Hessian = of the gradient (random
    states, the identity and an axisymmetric one with repeated eigenvalues)."""
    rng = np.random.default_rng(1)
    F = np.eye(3) + 0.2 * rng.standard_normal((5, 3, 3))
    F[0] = np.eye(3)
    F[1] = np.diag([1.1, 1.1, 0.8])
    E = 0.3 * rng.standard_normal((5, 3))
    _, g, H = wrinkling.enthalpy(F, E)
    x0, h = np.concatenate((F.reshape(5, 9), E), 1), 1e-6
    for k in range(12):
        xp, xm = x0.copy(), x0.copy()
        xp[:, k] += h
        xm[:, k] -= h
        vp, gp, _ = wrinkling.enthalpy(xp[:, :9].reshape(5, 3, 3), xp[:, 9:])
        vm, gm, _ = wrinkling.enthalpy(xm[:, :9].reshape(5, 3, 3), xm[:, 9:])
        assert np.max(np.abs((vp - vm) / (2 * h) - g[:, k])) < FD_ATOL
        assert np.max(np.abs((gp - gm) / (2 * h) - H[:, k])) < FD_ATOL


def test_axisymmetric_restriction_equals_the_buckling_jet():
    """Restricted to the seven axisymmetric g, the spectral energy equals the buckling
    clean room's forward-mode (Jet) Ogden energy, value, gradient and Hessian to round-off."""
    rng = np.random.default_rng(2)
    gg = [0.1 * rng.standard_normal(4) for _ in range(7)]
    F, E = np.tile(np.eye(3), (4, 1, 1)), np.zeros((4, 3))
    for k, (i, s) in enumerate(wrinkling.AXI):
        if i < 9:
            F.reshape(4, 9)[:, i] += s * gg[k]
        else:
            E[:, i - 9] = s * gg[k]
    v, g, H = wrinkling.enthalpy(F, E)
    om = buckling.enthalpy(buckling.Jet.seed(gg), "ogden_t1")
    idx = [i for i, _ in wrinkling.AXI]
    sg = np.array([s for _, s in wrinkling.AXI])
    assert np.max(np.abs(v - om.v)) < 1e-12
    assert np.max(np.abs(g[:, idx] * sg - om.g.T)) < 1e-12
    assert np.max(np.abs(H[:, idx][:, :, idx] * sg[:, None] * sg - np.moveaxis(om.h, 2, 0))) < 1e-11


def test_an_inverted_iterate_is_a_failed_newton():
    """A Newton iterate with det F <= 0 somewhere (an overshoot) raises NewtonError, which
    the path answers with a shorter step, not the energy's ValueError."""
    film = wrinkling.Film(order=2, n_r=8, n_z=1, levels=0)
    x = film.initial(0.0)
    x[:film.n] = -2.0 * film.basis.doflocs[0]  # u_r = -2 R: hoop stretch -1
    with pytest.raises(pullin.NewtonError, match="det F must be > 0"):
        film.at_deflection(0.0, x, 0.0)


def test_crossings_refuse_bad_input():
    with pytest.raises(ValueError, match="wavenumbers must be"):
        wrinkling.crossings(order=2, n_r=8, n_z=1, levels=0, wavenumbers=(0,))
    with pytest.raises(ValueError, match="case must be one of"):
        wrinkling.Film("nh_r10")
    with pytest.raises(ValueError, match="det F must be > 0"):
        wrinkling.enthalpy(-np.eye(3), np.zeros(3))
