"""The clean room of ch5_wrinkling (verification/cleanroom/wrinkling.py: the Ogden film at
a = 20 t0, the axisymmetric path by bordered Newton, the wavenumber-n condensed tangent)
passes ``debench check`` at its own, measured accuracy on the wavenumbers its default run
computes (n = 6, 7, 8, declared ``--partial``), finds n = 7 first, and its Ogden
Hessian is the finite-difference derivative of its gradient.

Measured (full path to the voltage maximum, 2 layers, 40 radial intervals, 2 corner
refinements): P2 (1419 dofs, 19 s CPU) w_cross 7.17955 / 7.13320 / 7.31287, v_cross
0.400258 / 0.398347 / 0.405600 for n = 6 / 7 / 8; P3 (2982 dofs, 30 s CPU) 7.15737 /
7.10670 / 7.28377, 0.399760 / 0.397649 / 0.404882. Only these two resolutions were run:
the P2 -> P3 change (n = 7: 3.7e-3 relative in w, 1.8e-3 in v) bounds the P3 error only
if the order converges monotonically, so the tolerances below are that change, not a
Roache estimate; the reference's stated accuracy (~1.5e-4 relative in w) is not claimed.
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
