"""Chapter 4 by 2D finite elements: the plane-strain strip over one wavelength (method 3)
against the exponential-ansatz determinant (method 1) on the cases of Figs 4.2 and 4.5,
under charge and voltage control, and against the Biot (kH -> inf) and Euler (kH -> 0)
limits.

The strip model shares no equation with the determinant: its moduli come from the
constitutive library's energy (4.22) and push-forward (2.72)-(2.73), its boundary
conditions are natural, and lam_cr is the zero of the lowest (n = 1, parity) eigenvalue
of the FE tangent. It is compared with the ``"derived"`` determinant (same energy).

Convergence study (order 3 Taylor-Hood, mesh refined by sqrt 2 per level, error against
the determinant root): the root error falls like h_e^6 (= 2 x order, eigenvalue of a
smooth mode; fitted slope asserted below). Measured coarse-mesh (level 0) errors over every
root of Figs 4.2/4.5 at kH = 0.3, 2, 10: <= 1e-6 at kH = 0.3, <= 3e-5 at kH = 2 (the
extensional mode at lam ~ 0.5, k h ~ 8), <= 3.2e-4 at kH = 10 (boundary layers).
"""

from __future__ import annotations

import numpy as np
import pytest
from debench.models.materials import IncompressibleLimit, MooneyRivlinIdealDielectric
from debench.models.plate import PlateParams, base_state, energy_matrix
from debench.models.plate import strip_fe as sfe
from debench.reference.datasets import read_dataset
from debench.reference.studies import ch4_fe as S

#: coarse-mesh agreement by kH class (the producers' check uses the same constants; their
#: derivation from the convergence study is stated there and in the module docstring)
TOL_COARSE = S.TOL_COARSE
#: finer mesh (level 2, 2x the coarse resolution): errors fall by 2^6 ~ 64 at order 6;
#: a factor 10 below the coarse tolerance keeps a ~6x margin
TOL_FINE = {k: v / 10 for k, v in TOL_COARSE.items()}
#: expected convergence order of the root (2 x polynomial order 3) and the allowance on
#: the fitted slope (pre-asymptotic levels, 4 points)
ORDER = 6.0
ORDER_TOL = 1.0
#: thin-plate limit: (1 - lam_cr)/kH^2 -> 1/18 (plate theory). Measured at kH = 0.05: the
#: determinant differs from 1/18 by 3.8e-4 relative (the O(kH^2) correction), the coarse
#: FE from the determinant by 5.5e-4 relative (root error 8e-8 divided by kH^2); 2e-3 is
#: ~2x their sum
EULER_RTOL = 2e-3
#: symmetric quadratic forms of the library moduli and of the sympy derivation agree to
#: round-off (entries ~100, eps ~2e-16): 1e-10 relative is ~1e4 x that
FORM_RTOL = 1e-10


def _tol(table, kH):
    return S.tolerance(kH, table)


@pytest.mark.parametrize("xi,D,lam", [(0.0, 0.0, 0.7), (5.0, 2.0, 0.9), (10.0, 1.0, 1.2),
                                      (3.0, 4.0, 2.5)])
def test_library_moduli_give_the_derived_incremental_energy_on_the_constraint(xi, D, lam):
    """The strip model's energy matrix (library moduli (2.65)-(2.67), push-forward
    (2.72)-(2.73), p from tau22 = 0) equals the sympy-derived S of (4.52)-(4.60) on
    tr L = 0 (they differ off the constraint by multiples of (tr L)^2 and tr L)."""
    st = sfe.base_state(lam, D, sfe.material_for(xi))
    S = energy_matrix(np.array(lam), PlateParams(xi=xi, Dhat=D, variant="derived"))
    p, _ = base_state(np.array(lam), PlateParams(xi=xi, Dhat=D, variant="derived"))
    rng = np.random.default_rng(0)
    z = rng.normal(size=(20, 6))
    z[:, 3] = -z[:, 0]
    q1, q2 = np.einsum("ka,ab,kb->k", z, st.S, z), np.einsum("ka,ab,kb->k", z, S, z)
    np.testing.assert_allclose(q1, q2, rtol=FORM_RTOL, atol=FORM_RTOL * np.abs(S).max())
    assert st.p == pytest.approx(float(p), rel=FORM_RTOL)


def test_strip_modes_are_pure_harmonics_with_small_backward_error():
    """The eigenpairs nearest zero are pure Fourier harmonics of the wavelength and
    mirror-symmetric or antisymmetric about the mid-plane; residuals at round-off."""
    m = sfe.modes(0.85, 2.0, sfe.material_for(0.0), Dhat=0.0)
    assert np.all(m.purity > 0.999)
    assert np.max(m.residual) < 1e-10
    # the n = 1 flexural pair is doubly degenerate (translation invariance)
    e = [w for w, n, p in zip(m.omega, m.n, m.parity, strict=True) if n == 1 and p == "E"]
    assert len(e) >= 2 and e[1] - e[0] < 1e-8 * abs(e[0])


def test_strip_fe_agrees_with_determinant_charge_control():
    """Figs 4.2(a) (xi = 5), 4.2(c) thin, 4.2(i), 4.5 (xi = 10, thick), charge
    control: every determinant root has an FE root of the same parity within the
    coarse-mesh tolerance of the convergence study."""
    _, rows = S.max_disagreement(S.CASES_FAST)
    assert rows
    bad = [(c.xi, c.load, c.kH, c.parity, c.lam_det, c.diff) for c in rows
           if abs(c.diff) > _tol(TOL_COARSE, c.kH)]
    assert not bad, bad


def test_strip_fe_agrees_with_determinant_voltage_control():
    """Voltage control (Dhat = Vhat lam^2/beta from the library's E = F^-T dW/dD_L):
    the FE roots agree with the determinant at the same voltage."""
    _, rows = S.max_disagreement(S.VOLTAGE_CASES[:1], control="voltage")
    assert len(rows) >= 2
    bad = [(c.parity, c.lam_det, c.diff) for c in rows
           if abs(c.diff) > _tol(TOL_COARSE, c.kH)]
    assert not bad, bad


def test_voltage_control_dhat_from_library_field():
    """V = E2 h with E = F^-T dW/dD_L (2.32), h = H lam^-2: Dhat = Vhat lam^2/beta
    (alpha = 0) - the library reproduces the closed form used by models/plate/voltage."""
    for lam in (0.7, 1.0, 1.6):
        d = sfe.dhat_at_voltage(lam, 0.5, sfe.material_for(5.0))
        assert d == pytest.approx(0.5 * lam**2 / 0.5, rel=1e-13)


def test_strip_fe_thin_limit_is_euler():
    """kH -> 0 (kH = 0.05, xi = Dhat = 0): (1 - lam_cr)/kH^2 -> 1/18, Euler buckling of a
    plate at vanishing membrane stress (literature entry lit.plate.euler_thin_limit)."""
    fe, det = S.euler_slope()
    assert fe == pytest.approx(1 / 18, rel=EULER_RTOL)
    assert fe == pytest.approx(det, rel=EULER_RTOL)


def test_curated_euler_limit_is_the_live_one():
    """The producer's FE root at kH = KH_EULER (ch4_fe_limits.nc) is the one solved now on
    the same mesh, within the accuracy of a recomputed FE root (ACCURACY), beside the same
    determinant root."""
    live, curated = S.limit_comparison("euler"), S.curated_limit("euler")
    assert curated.lam_det == live.lam_det and curated.level == live.level == 0
    assert abs(curated.lam_fe - live.lam_fe) <= S.ACCURACY.tolerance(live.lam_fe)


def test_a_stale_limit_row_raises():
    """A curated limit row whose determinant root is not the live one (here: moved by
    1e-6), or a missing limit, is a LookupError naming the regeneration."""
    ds = read_dataset("ch4_fe_limits")
    moved = ds.copy(deep=True)
    moved["lam_det"].values[:] += 1e-6
    with pytest.raises(LookupError, match="regenerate"):
        S.curated_limit("euler", data=moved)
    with pytest.raises(LookupError, match="regenerate"):
        S.curated_limit("euler", data=ds.isel(limit=[0]))


@pytest.mark.slow
def test_strip_fe_thick_limit_is_biot():
    """kH -> inf (kH = 20, xi = Dhat = 0): lam_cr -> 0.66614, Biot's surface instability
    (lit.plate.biot_thick_limit). The determinant at kH = 20 differs from Biot by ~1e-6;
    the coarse FE by ~1e-4 (measured). Slow (~20-40 s): the default run's kH = 10 case of
    Fig. 4.5 checks the same boundary-layer regime."""
    assert S.biot_root() == pytest.approx(S.BIOT, abs=TOL_COARSE[10.0])
    curated = S.curated_limit("biot")
    assert abs(curated.lam_fe - S.biot_root()) <= S.ACCURACY.tolerance(curated.lam_fe)


def _slope(errors, kH):
    """Fitted log-log slope of |error| against the element size 1/nx of each level."""
    h = np.array([1 / sfe.default_mesh(kH, level=lv).nx for lv in range(len(errors))])
    return np.polyfit(np.log(h), np.log(np.abs(errors)), 1)[0]


def test_strip_fe_converges_at_order_2p_thin():
    """Root error against the determinant on four meshes (sqrt 2 refinement), thin plate
    (Fig. 4.2(a), kH = 0.3): fitted slope ~ 6 = 2 x order."""
    err = [S.compare(0.0, 0.0, 0.3, level=lv)[0].diff for lv in range(4)]
    assert abs(_slope(err, 0.3) - ORDER) < ORDER_TOL, err


@pytest.mark.slow
def test_strip_fe_converges_at_order_2p_thick():
    """As above for the extensional mode at kH = 2 (k h ~ 8) and kH = 10, xi = 5."""
    for case, par in (((0.0, 0.0, 2.0), "O"), ((5.0, 0.0, 10.0), "O")):
        err = [next(c.diff for c in S.compare(*case, level=lv) if c.parity == par)
               for lv in range(4)]
        assert abs(_slope(err, case[2]) - ORDER) < ORDER_TOL, (case, err)


@pytest.mark.slow
@pytest.mark.parametrize("case", S.CASES_FULL)
def test_strip_fe_agrees_with_determinant_all_cases_fine(case):
    """Every case of Figs 4.2 and 4.5 at kH = 0.3, 2, 10 on the level-2 mesh."""
    rows = S.compare(*case, level=2)
    bad = [(c.parity, c.lam_det, c.diff) for c in rows if abs(c.diff) > _tol(TOL_FINE, c.kH)]
    assert not bad, bad


@pytest.mark.slow
def test_strip_fe_agrees_with_determinant_voltage_control_all():
    _, rows = S.max_disagreement(S.VOLTAGE_CASES, control="voltage", level=1)
    bad = [(c.xi, c.parity, c.lam_det, c.diff) for c in rows
           if abs(c.diff) > _tol(TOL_COARSE, c.kH)]
    assert not bad, bad


def test_bad_inputs_raise_naming_the_argument():
    """The strip model validates at its boundary: each bad input is a ValueError that
    names the argument (checked before any finite-element work)."""
    from debench.models.plate import strip_fe

    mat = strip_fe.material_for(5.0)
    cases = [
        (lambda: strip_fe.default_mesh(0.0), "kH"),
        (lambda: strip_fe.default_mesh(2.0, level=-1), "level"),
        (lambda: strip_fe.base_state(-1.0, 0.0, mat), "lam"),
        (lambda: strip_fe.base_state(1.2, float("nan"), mat), "Dhat"),
        (lambda: strip_fe.dhat_at_voltage(1.2, -1.0, mat), "Vhat"),
        (lambda: strip_fe.critical_stretch(2.0, (1.0, 1.2), "X", mat, Dhat=0.0), "parity"),
        (lambda: strip_fe.modes(1.2, 2.0, mat), "Dhat"),
    ]
    for call, name in cases:
        with pytest.raises(ValueError, match=name):
            call()


def test_strip_root_from_the_determinant_root_is_the_bracketed_one():
    """Secant steps started at the determinant root (the producers' search) find the
    zero a search of the whole bracket finds, to the root tolerance, in fewer eigen-solves
    (thin isotropic case of Fig. 4.2(c), coarse mesh)."""
    xi, D, kH = 0.0, 2.0, 0.3
    lam, par = next(zip(*S.determinant_roots(xi, D, kH, "charge"), strict=True))
    br = (lam * (1 - S.BRACKET), lam * (1 + S.BRACKET))
    kw = dict(Dhat=D, mesh=sfe.default_mesh(kH))
    mat = sfe.material_for(xi)
    plain = sfe.critical_stretch(kH, br, par, mat, **kw)
    fast = sfe.critical_stretch(kH, br, par, mat, guess=float(lam), **kw)
    assert abs(fast.lam - plain.lam) <= 2 * sfe.XTOL
    assert fast.evaluations < plain.evaluations


def test_strip_fe_takes_any_library_elastomer():
    """The strip model takes any library elastomer in its incompressible limit
    (:class:`~debench.models.materials.IncompressibleLimit`) with no change to it: the
    compressible Mooney-Rivlin with C01 = 0, C10 = 1/2 and the ideal dielectric I5/(2 eps)
    at eps = 2 is, on J = 1, the isotropic energy (4.22) (xi = 0, beta/eps = 1/2) of the
    thin case of Fig. 4.2(c). Their energies differ off the constraint, which the Taylor-Hood
    pair holds only weakly, so their roots agree to the strip's discretisation error (the
    coarse tolerance), not to round-off; both agree with the determinant root. C01 > 0 at
    the same shear modulus is another plate: its lowest eigenvalue differs by > 10 %."""
    xi, D, kH = 0.0, 2.0, 0.3
    lam, par = next(zip(*S.determinant_roots(xi, D, kH, "charge"), strict=True))
    br = (lam * (1 - S.BRACKET), lam * (1 + S.BRACKET))
    kw = dict(Dhat=D, mesh=sfe.default_mesh(kH))
    tol = _tol(TOL_COARSE, kH)
    ti = sfe.critical_stretch(kH, br, par, sfe.material_for(xi), guess=float(lam), **kw)
    nh = IncompressibleLimit(MooneyRivlinIdealDielectric(C10=0.5, C01=0.0, k=50.0, eps=2.0))
    mr = sfe.critical_stretch(kH, br, par, nh, guess=float(lam), **kw)
    assert abs(mr.lam - ti.lam) <= tol and abs(mr.lam - lam) <= tol
    other = IncompressibleLimit(MooneyRivlinIdealDielectric(C10=0.35, C01=0.15, k=50.0,
                                                            eps=2.0))
    w_ti, w_mr = (np.sort(sfe.modes(1.2, kH, m, Dhat=D, mesh=kw["mesh"]).omega)[0]
                  for m in (sfe.material_for(xi), other))
    assert abs(w_mr - w_ti) > 0.1 * abs(w_ti)
