"""Fibre in the plane of the plate (beyond the thesis): derivation, two methods, claims."""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest
from debench.models.errors import ConvergenceError
from debench.models.plate import PlateParams
from debench.models.plate import generated_inplane as gen
from debench.models.plate import inplane as ip
from debench.models.plate import inplane_fe as ipfe
from debench.reference.catalogue import by_id, evaluate
from debench.reference.datasets import read_dataset
from debench.reference.producers import ch4_inplane as prod
from debench.reference.studies import ch4_inplane as prod_study

ROOT = Path(__file__).resolve().parents[1]
#: generated vs re-derived entries: both evaluate the same rational functions in double
#: precision (entries O(1e2) at lam = 0.7); 1e-10 is > 100x their round-off
TOL_REDERIVE = 1e-10


def _derivation():
    spec = importlib.util.spec_from_file_location("derive_ch4_inplane",
                                                  ROOT / "tools" / "derive_ch4_inplane.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.slow
def test_generated_matches_rederivation():
    mod = _derivation()
    S, p, tau, _ = mod.derive()
    syms = (mod.lam, mod.xi, mod.al, mod.be, mod.Dh, mod.ct, mod.st)
    for lam, xi, D, th in ((0.7, 5.0, 0.0, 30.0), (1.2, 1.0, 2.0, 60.0)):
        c, s = math.cos(math.radians(th)), math.sin(math.radians(th))
        vals = dict(zip(syms, (lam, xi, 0.0, 0.5, D, c, s), strict=True))
        ref = np.array(S.subs(vals).evalf(), dtype=float)
        got = gen.energy_matrix(lam, xi, 0.0, 0.5, D, c, s)
        assert np.max(np.abs(got - ref)) < TOL_REDERIVE


def test_symbol_hermitian_and_decoupled_at_0_and_90():
    p = PlateParams(xi=5.0, Dhat=2.0)
    for th in (0.0, 90.0):
        S = ip.energy_matrix(0.9, th, p)
        assert np.all(S[4:6, :4] == 0) and np.all(S[4:6, 6:] == 0)
    S = ip.energy_matrix(0.9, 45.0, p)
    assert S[0, 4] != 0  # the fibre couples L31 to L11 at intermediate angles
    P = ip.symbol(0.9, 45.0, p, np.array([0.3j, 1.1j]))  # real q2: Hermitian
    assert np.allclose(P, np.conj(np.swapaxes(P, -1, -2)), atol=1e-12)


def test_characteristic_roots_come_in_pairs():
    s = ip.characteristic_roots(0.9, 30.0, PlateParams(xi=5.0, Dhat=1.0))
    assert s.size == 8
    # reflection x2 -> -x2: roots +- s
    assert np.max(np.min(np.abs(s[:, None] + s[None, :]), axis=1)) < 1e-8


def test_methods_agree_on_every_root():
    err, same, rows = prod_study.max_disagreement()
    assert same and len(rows) >= len(prod_study.THETAS)
    assert err <= prod_study.TOL_AGREE


@pytest.mark.slow
def test_methods_agree_with_field_and_weaker_fibre():
    for xi, D in ((1.0, 0.0), (1.0, 2.0)):
        err, same, _ = prod_study.max_disagreement(thetas=(0.0, 45.0, 60.0), xi=xi, Dhat=D)
        assert same and err <= prod_study.TOL_AGREE


def test_theta90_is_isotropic():
    assert evaluate(by_id()["ch4.beyond.inplane.theta90_is_isotropic"]).status == "reproduced"


def test_lam_cr_decreases_with_theta():
    r = evaluate(by_id()["ch4.beyond.inplane.lam_cr_decreases_with_theta"])
    assert r.status == "reproduced", r.details


def test_ellipticity_limit_closed_form():
    e = by_id()["ch4.beyond.inplane.ellipticity_limit"]
    r = evaluate(e)
    assert r.status == "reproduced"
    assert abs(r.value - prod.ellipticity_limit_closed_form(e)) < 1e-10


def test_wrinkling_before_ellipticity_loss():
    r = evaluate(by_id()["ch4.beyond.inplane.wrinkling_before_ellipticity_loss"])
    assert r.status == "reproduced", r.details


def test_every_root_is_strongly_elliptic():
    p = PlateParams(xi=prod_study.XI)
    for th in prod_study.THETAS:
        for lam in prod_study.roots(th)[0]:
            assert ip.strongly_elliptic(lam, th, p)


def test_bad_input_raises():
    p = PlateParams(xi=1.0)
    with pytest.raises(ValueError, match="theta"):
        ip.energy_matrix(0.9, 120.0, p)
    with pytest.raises(ValueError, match="lam"):
        ip.energy_matrix(-1.0, 30.0, p)
    with pytest.raises(ValueError, match="variant"):
        ip.energy_matrix(0.9, 30.0, PlateParams(xi=1.0, variant="printed"))


def test_voltage_methods_agree_on_every_root():
    """Voltage control: both methods, every root on the window, theta = 0 ... 90 deg
    (the FE solved now, and the producer's curated FE roots)."""
    err, same, rows = prod_study.voltage_agreement("live")
    assert same and len(rows) >= len(prod_study.THETAS) and err <= prod_study.TOL_AGREE, rows
    r = evaluate(by_id()["ch4.beyond.inplane.voltage_methods_agree"])
    assert r.status == "reproduced", r.details
    assert r.details["max_abs_diff"] <= prod_study.TOL_AGREE


def test_voltage_root_lies_on_the_charge_curve_of_its_own_field():
    """A root at fixed Vhat is a charge-control root at Dhat = Vhat lam^2/beta."""
    det, _ = prod_study.voltage_roots(45.0)
    lam = det[-1]
    p = PlateParams(xi=prod_study.XI, Dhat=prod_study.VHAT * lam**2 / 0.5)
    r = ip.critical_stretches_det(prod_study.KH, 45.0, p, window=(lam - 1e-3, lam + 1e-3),
                                  n_scan=8)
    # both brentq to 1e-14 on the same determinant: 1e-10 is > 1e3 x their round-off
    assert r.size == 1 and abs(r[0] - lam) < 1e-10


def test_tension_wrinkling_with_field():
    """Tension with a field: the claim holds with the FE solved now and with the
    producer's curated FE roots."""
    ok, rows, none_without_field = prod_study.tension_check("live")
    assert ok and none_without_field, rows
    r = evaluate(by_id()["ch4.beyond.inplane.tension_wrinkling"])
    assert r.status == "reproduced", r.details


def test_curated_fe_roots_are_the_live_ones():
    """Every FE root the producers read from ch4_inplane_roots.nc is the FE root solved now
    for the same window, within the accuracy of an FE root (ACCURACY: round-off of the
    eigen-solver on another BLAS), and the counts agree."""
    for case in prod_study.producer_cases():
        live, curated = prod_study.fe_roots(case), prod_study.curated_fe_roots(case)
        assert len(live) == len(curated), case
        for a, b in zip(live, curated, strict=True):
            assert abs(a - b) <= prod_study.ACCURACY.tolerance(a), (case, a, b)


def test_a_case_missing_from_the_curated_roots_raises():
    """A window the curated dataset lacks (here: the dataset without its first case) is a
    LookupError naming the regeneration, never a silent pass."""
    short = read_dataset("ch4_inplane_roots").isel(case=slice(1, None))
    with pytest.raises(LookupError, match="regenerate"):
        prod_study.curated_fe_roots(prod_study.producer_cases()[0], data=short)
    case = prod_study.producer_cases()[1]
    assert (prod_study.curated_fe_roots(case, data=short)
            == prod_study.curated_fe_roots(case, data=short))
    with pytest.raises(ValueError, match="fe_source"):
        prod_study.max_disagreement(fe_source="cache")


def test_tension_membrane_limit():
    e = by_id()["ch4.beyond.inplane.tension_membrane_limit"]
    r = evaluate(e)
    assert r.status == "reproduced", r.details
    # the model's membrane limit (generated tau11) against the independent closed form;
    # both brentq to 1e-15: 1e-12 is > 100x their round-off
    m = ip.membrane_limit(45.0, PlateParams(xi=5.0, Dhat=2.0), window=(1.0, 8.0))
    assert abs(m - r.details["closed_form"]) < 1e-12


def test_membrane_limit_under_voltage_is_the_zero_of_tau11():
    """Voltage control: tau11 = lam^2 - lam^-4 + 2 xi c^2 lam^2 (lam^2 - 1) - Vhat^2
    lam^4/beta vanishes at the membrane limit (alpha = 0, Dhat = Vhat lam^2/beta)."""
    V, xi, th = 0.2, 5.0, 60.0
    m = ip.membrane_limit(th, PlateParams(xi=xi), window=(1.0, 3.0), Vhat=V)
    c2 = math.cos(math.radians(th)) ** 2
    tau = m**2 - m**-4 + 2 * xi * c2 * m**2 * (m**2 - 1) - V**2 * m**4 / 0.5
    # O(1) terms evaluated in double precision at a root refined to 1e-15: 1e-12
    assert abs(tau) < 1e-12 and m > 1.0


def test_close_root_pair_is_not_hidden():
    """At xi = 5, theta = 30 deg, kH = 0.80 a spurious zero of the single-weight
    determinant lies 4e-5 from the bifurcation: the two-weight scan keeps the root."""
    p = PlateParams(xi=5.0)
    kh = float(np.geomspace(0.2, 8.0, 9)[3])
    det = ip.critical_stretches_det(kh, 30.0, p, window=(0.935, 0.999), n_scan=40)
    fe = ipfe.critical_stretches_fe(kh, 30.0, p, window=(0.935, 0.999), n_scan=40)
    assert det.size == fe.size == 1 and abs(det[0] - fe[0]) <= prod_study.TOL_AGREE


def test_fe_refuses_crossings_within_round_off():
    """Thin plate in tension (kH = 0.1, lam > 3): the FE eigenvalue is below eps ||K||."""
    with pytest.raises(ConvergenceError, match="round-off"):
        ipfe.critical_stretches_fe(0.1, 0.0, PlateParams(xi=5.0, Dhat=2.0),
                                   window=(3.0, 4.0), n_scan=30)


def test_fe_accepts_a_grid_point_on_a_resolved_root():
    """Voltage control, xi = 5, Vhat = 0.1, theta = 60 deg, kH = 0.25: a scan point lies
    8e-6 from the root, inside the round-off band of the eigenvalue, but the slope
    resolves the root (round-off ~1e-7): both methods agree. A root whose round-off is
    1.7e-4 (tension, Dhat = 3, kH = 0.5, theta = 80 deg) is still refused."""
    w = (0.7753712659110396, 1.5)   # lam_E (1 + LAM_E_MARGIN) of the builder
    p = PlateParams(xi=5.0)
    g = np.geomspace(*w, 40)
    e = ipfe.fe_eigenvalues(g[15], 0.25, 60.0, _on_voltage_path(p, 0.1, g[15]))
    K = ipfe.fe_stiffness(g[15], 0.25, 60.0, _on_voltage_path(p, 0.1, g[15]))
    assert np.min(np.abs(e)) < ipfe.ROUNDOFF_FACTOR * np.finfo(float).eps * np.linalg.norm(K, 1)
    fe = ipfe.critical_stretches_fe(0.25, 60.0, p, window=w, n_scan=40, Vhat=0.1)
    det = ip.critical_stretches_det(0.25, 60.0, p, window=w, n_scan=40, Vhat=0.1)
    assert det.size == fe.size == 1 and abs(det[0] - fe[0]) <= prod_study.TOL_AGREE
    with pytest.raises(ConvergenceError, match="round-off"):
        ipfe.critical_stretches_fe(0.5, 80.0, PlateParams(xi=5.0, Dhat=3.0),
                                   window=(1.0005, 2.0), n_scan=40)


def _on_voltage_path(p, Vhat, lam):
    """The parameters of the voltage-controlled path at lam (Dhat = Dhat(lam))."""
    from dataclasses import replace

    from debench.models.plate.voltage import dhat_at_voltage

    return replace(p, Dhat=float(dhat_at_voltage(lam, Vhat, p)))


def test_compression_window_clears_the_fe_round_off_at_lam_E():
    """theta = 0: an FE eigenvalue vanishes at lam_E (vanishing L21 modulus). Within
    1e-9 of lam_E it is inside the FE round-off guard; at the builder's window start
    lam_E (1 + LAM_E_MARGIN) it is > 10x above the guard in the worst case of the full
    sweep (xi = 1, Dhat = 2, smallest kH); at Dhat = 0 both methods find the wrinkling
    root on that window (with Dhat >= 1 the plate is buckled already at 0.999)."""
    from debench.reference.builders import ch4_inplane as builder

    kh = min(builder.KH_FULL)
    p = PlateParams(xi=1.0, Dhat=2.0)
    lam_e, lo = builder.window_start(0.0, p)
    assert lo == lam_e * (1 + ip.LAM_E_MARGIN)

    def nearest_and_guard(lam):
        e = ipfe.fe_eigenvalues(lam, kh, 0.0, p)
        noise = np.finfo(float).eps * np.linalg.norm(ipfe.fe_stiffness(lam, kh, 0.0, p), 1)
        return np.min(np.abs(e)), ipfe.ROUNDOFF_FACTOR * noise

    e, guard = nearest_and_guard(lam_e * (1 + 1e-9))
    assert e < guard
    e, guard = nearest_and_guard(lo)
    assert e > 10 * guard
    p = PlateParams(xi=1.0, Dhat=0.0)
    _, lo = builder.window_start(0.0, p)
    det = ip.critical_stretches_det(kh, 0.0, p, window=(lo, 0.999), n_scan=builder.N_SCAN)
    fe = ipfe.critical_stretches_fe(kh, 0.0, p, window=(lo, 0.999), n_scan=builder.N_SCAN)
    assert det.size == fe.size >= 1 and np.max(np.abs(det - fe)) <= prod_study.TOL_AGREE


def test_voltage_control_needs_zero_dhat():
    with pytest.raises(ValueError, match="Dhat"):
        ip.critical_stretches_det(2.0, 45.0, PlateParams(xi=5.0, Dhat=1.0), Vhat=0.5)
    with pytest.raises(ValueError, match="Vhat"):
        ipfe.critical_stretches_fe(2.0, 45.0, PlateParams(xi=5.0), Vhat=-0.5)


#: determinant vs FE: the FE root error is O(N^-4) in the elements (24 by default; 48
#: halve h: 1/16 of the error), measured from 1.8e-7 (kH = 3) to 1.9e-5 (kH = 8 with a
#: field, boundary layers) at 24 elements; the determinant root is the limit: with 48
#: elements the FE root moves towards it by >= 8x (measured 16.0x)
FE_RATE_MIN = 8.0


def _fe_root_with_twice_the_elements(name, ds, idx):
    """The largest FE root, 2 x N_ELEMENTS, of the window of entry ``idx`` of dataset
    ``name`` (the builder's windows and grid)."""
    from debench.reference.builders import ch4_inplane as builder

    c = {d: float(ds[d].values[i]) for d, i in zip(ds["lam_cr_det"].dims, idx, strict=True)}
    kw = {"n_scan": builder.N_SCAN, "n": 2 * ipfe.N_ELEMENTS}
    if name == "ch4_inplane_lam_cr.nc":
        p = PlateParams(xi=c["xi"], Dhat=c["Dhat"])
        kw["window"] = (builder.window_start(c["theta"], p)[1], 0.999)
    elif name == "ch4_inplane_tension.nc":
        p = PlateParams(xi=float(ds.attrs["xi"]), Dhat=c["Dhat"])
        kw["window"] = builder.TENSION_WINDOW
    else:
        p = PlateParams(xi=float(ds.attrs["xi"]))
        kw["window"] = (builder.window_start(c["theta"], p, Vhat=c["Vhat"])[1], builder.V_HI)
        kw["Vhat"] = c["Vhat"]
    return max(ipfe.critical_stretches_fe(c["kH"], c["theta"], p, **kw))


def _check_builder(paths, full):
    import xarray as xr

    by_name = {p.name: p for p in paths}
    assert "ch4_beyond_inplane.png" in by_name
    for name in ("ch4_inplane_lam_cr.nc", "ch4_inplane_tension.nc", "ch4_inplane_voltage.nc"):
        ds = xr.open_dataset(by_name[name])
        det, fe = ds["lam_cr_det"].values, ds["lam_cr_fe"].values
        assert np.array_equal(np.isnan(det), np.isnan(fe)), name
        # the methods agree to TOL_AGREE where the FE resolves the plate; where the FE
        # root error (growing with kH) exceeds it, twice the elements must bring the FE
        # root within TOL_AGREE, converging to the determinant root (FE_RATE_MIN)
        err = np.abs(det - fe)
        for idx in map(tuple, np.argwhere(err > prod_study.TOL_AGREE)):
            fine = abs(det[idx] - _fe_root_with_twice_the_elements(name, ds, idx))
            assert fine <= prod_study.TOL_AGREE and fine * FE_RATE_MIN <= err[idx], (
                name, idx, err[idx], fine)
    lc = xr.open_dataset(by_name["ch4_inplane_lam_cr.nc"])
    det = lc["lam_cr_det"].values
    lam_e = np.broadcast_to(lc["lam_E"].values[..., None], det.shape)
    assert np.all(det[np.isfinite(det)] > lam_e[np.isfinite(det)])
    te = xr.open_dataset(by_name["ch4_inplane_tension.nc"])
    # tension: every root above 1 and below the membrane limit (bending stiffens)
    t = te["lam_cr_det"].values
    memb = np.broadcast_to(te["lam_membrane"].values[..., None], t.shape)
    assert np.all(t[np.isfinite(t)] > 1) and np.all(t[np.isfinite(t)] < memb[np.isfinite(t)])
    assert xr.open_dataset(by_name["ch4_inplane_lam_cr.nc"]).attrs  # provenance written
    if full:
        # theta every 10 degrees (and the producers' 45)
        assert set(range(0, 91, 10)) <= set(lc.theta.values) and lc.theta.size == 11
        assert lc.xi.size >= 2 and lc.Dhat.size >= 2


@pytest.mark.slow
def test_builder_writes_agreeing_methods(tmp_path):
    from debench.reference.builders import ch4_inplane as builder

    _check_builder(builder.build(tmp_path), full=False)


@pytest.mark.slow
def test_builder_full_sweep(tmp_path):
    from debench.reference.builders import ch4_inplane as builder

    _check_builder(builder.build(tmp_path, full=True), full=True)


#: the batched and the one-window scans stop their refinements on brackets of XTOL_ROOT;
#: their roots agree to that and the round-off of a root (~1e-12)
TOL_BATCH = 1e-11


def test_windows_solved_together_have_the_roots_of_each_alone():
    """critical_stretches_det_many: the same roots as one scan per window (charge and
    voltage control, compression and tension, the isotropic shortcut included)."""
    cases = [prod_study.compression_case(30.0), prod_study.compression_case(90.0),
             prod_study.voltage_case(45.0), prod_study.tension_case(60.0, 2.0, 0.5)]
    scans = [(*args, kw) for args, kw in (c._args() for c in cases)]
    together = ip.critical_stretches_det_many(scans)
    for (kH, th, p, kw), roots in zip(scans, together, strict=True):
        alone = ip.critical_stretches_det(kH, th, p, **kw)
        assert roots.size == alone.size >= 1
        np.testing.assert_allclose(roots, alone, rtol=0, atol=TOL_BATCH)


def test_collision_of_characteristic_roots_is_not_a_bifurcation():
    """Voltage control, xi = 5, theta = 60, kH = 0.5 across lam = 1: two characteristic
    roots collide at lam = 1, where the normalised determinant touches zero and the
    singularity test sees two equal columns. No determinant root there; the FE (no
    characteristic roots) has the same single root."""
    p = PlateParams(xi=5.0)
    s = ip.characteristic_roots(1.0, 60.0, PlateParams(xi=5.0, Dhat=float(
        ip.dhat_at_voltage(1.0, 0.5, p))))
    sep = np.min(np.abs(s[:, None] - s[None, :])[np.triu_indices(8, 1)]) / np.max(np.abs(s))
    assert sep < ip.COLLISION_TOL
    # the producers' window, whose scan brackets the touch point with a sign change
    args, kw = prod_study.voltage_case(60.0, kH=0.5)._args()
    det = ip.critical_stretches_det(*args, **kw)
    fe = ipfe.critical_stretches_fe(*args, **kw)
    assert np.all(np.abs(det - 1.0) > 1e-3)
    assert det.size == fe.size
    np.testing.assert_allclose(det, fe, rtol=0, atol=prod_study.TOL_AGREE)


@pytest.mark.parametrize("xi, theta, kH, n_roots", [(5.0, 70.0, 3.0, 1), (1.0, 80.0, 8.0, 2)])
def test_roots_hidden_from_the_grid_are_the_fe_roots(xi, theta, kH, n_roots):
    """Full sweep, Dhat = 0, on the builder's window: (xi, theta, kH) = (5, 70, 3), a root
    beside a spurious zero of both weight vectors in one grid interval, and (1, 80, 8),
    the two close modes of a thick plate in one interval. The determinant finds every
    FE root, within TOL_AGREE, and the FE roots converge to it (O(N^-4))."""
    from debench.reference.builders import ch4_inplane as builder

    p = PlateParams(xi=xi)
    _, lo = builder.window_start(theta, p)
    kw = {"window": (lo, 0.999), "n_scan": builder.N_SCAN}
    det = ip.critical_stretches_det(kH, theta, p, **kw)
    fe = ipfe.critical_stretches_fe(kH, theta, p, **kw)
    fe48 = ipfe.critical_stretches_fe(kH, theta, p, n=48, **kw)
    assert det.size == fe.size == fe48.size == n_roots
    assert np.max(np.abs(det - fe)) <= prod_study.TOL_AGREE
    assert np.all(np.abs(det - fe48) * FE_RATE_MIN <= np.abs(det - fe))


def test_inertia_count_equals_the_eigenvalue_count_away_from_round_off():
    """The in-plane FE scan counts negative eigenvalues by the inertia of a Bunch-Kaufman
    factorisation (``fem._negative_eigenvalues``); on Hermitian and real symmetric matrices
    (1 x 1 and 2 x 2 pivots: zero diagonals force the latter) whose eigenvalues lie at
    least 1e-3 from zero, the count equals that of ``eigvalsh``, and a singular pivot gives
    None (undecided), never a count."""
    from debench.models.plate.fem import _negative_eigenvalues

    rng = np.random.default_rng(7)
    for trial in range(300):
        n = int(rng.integers(1, 30))
        Q, _ = np.linalg.qr(rng.standard_normal((n, n)) + 1j * rng.standard_normal((n, n)))
        lam = rng.uniform(1e-3, 2.0, n) * rng.choice([-1.0, 1.0], n)
        K = (Q * lam) @ Q.conj().T
        K = 0.5 * (K + K.conj().T)
        if trial % 3 == 0:
            K = K.real.copy()           # real symmetric (not similar to diag(lam))
        if trial % 5 == 0:
            np.fill_diagonal(K, 0.0)    # 2 x 2 pivots
        w = np.linalg.eigvalsh(K)
        if np.min(np.abs(w)) < 1e-9:     # an eigenvalue within round-off of zero
            continue
        assert _negative_eigenvalues(K) == int(np.count_nonzero(w < 0)), trial
    assert _negative_eigenvalues(np.zeros((3, 3))) is None
