"""lit_balloon: the reference (closed forms of debench.models.balloon, stored by the builder)
is confirmed by the clean room (verification/cleanroom/balloon.py: the equilibrium derived
from the sphere's energy by 30-digit numerical differentiation, the extrema by 30-digit
root finding), every stored value at the problem's STATED accuracy; and the clean room's
values written as a stranger's results files pass ``debench check`` first try, with full
coverage.

The closed forms themselves are checked at their special values: the neo-Hookean balloon's
pressure maximum at lam = 7^(1/6) (Zhu, Cai & Suo 2010), its voltage limit at zero
pressure = the free membrane's pull-in (lam = 2^(1/3), Zhao & Suo 2007), Laplace's law.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from debench.models import balloon
from debench.reference import cli, problems, problems_reference
from debench.reference.datasets import read_dataset

from verification.cleanroom import balloon as cr

PROBLEM = "lit_balloon"
#: the extremum quantities by their selector and the clean-room result keys
EXTREMA = {"lam_pmax": ("max", 0), "pbar_max": ("max", 1), "lam_pmin": ("min", 0),
           "pbar_min": ("min", 1)}
#: round-off of the double-precision closed forms at the scale of their terms: the
#: special-value tests below are exact up to a few ulp of values of order 1
ROUNDOFF = 1e-14


def _inf(jm: float):
    return None if math.isinf(jm) else float(jm)


@pytest.fixture(scope="module")
def ds():
    return read_dataset(PROBLEM)


@pytest.fixture(scope="module")
def cleanroom(ds):
    """The clean room's values at every stored point (its own curves at the stored
    stretches, its own extrema and limit points)."""
    out = {"pbar": {}, "extrema": {}, "limit": {}}
    for jm in ds.Jm.values:
        lam = ds.lam.sel(Jm=jm).values
        for vb in ds.vbar.values:
            out["pbar"][jm, vb] = np.array([float(cr.pressure(x, vb, _inf(jm)))
                                            for x in lam])
            out["extrema"][jm, vb] = cr.pressure_extrema(vb, _inf(jm))
        for pf in ds.pbar_fixed.values:
            out["limit"][jm, pf] = cr.voltage_limit(pf, _inf(jm))
    return out


def _tolerance(name, coords):
    p = problems.get(PROBLEM)
    return problems_reference.reference_at(p, p.quantity(name), coords)


def test_pressure_curves_match_the_clean_room_at_the_stated_accuracy(ds, cleanroom):
    """pbar on all 18 curves (3 Jm x 6 vbar, 401 stretches each): |reference - clean
    room| <= atol + rtol |reference| (measured <= 3.4e-14 absolute, 1.0e-13 relative where
    |pbar| > 1e-3)."""
    worst = 0.0
    for (jm, vb), exact in cleanroom["pbar"].items():
        lam = ds.lam.sel(Jm=jm).values
        ref = _tolerance("pbar", {"Jm": jm, "vbar": vb, "lam": lam})
        assert np.array_equal(ref.value, ds.pbar.sel(Jm=jm, vbar=vb).values)
        err = np.abs(ref.value - exact)
        assert np.all(err <= ref.tolerance), (jm, vb, err.max())
        worst = max(worst, float(err.max()))
    assert worst > 0  # the two computations are not one


def test_pressure_extrema_match_the_clean_room_at_the_stated_accuracy(ds, cleanroom):
    """lam_pmax, pbar_max, lam_pmin, pbar_min at every (Jm, vbar): the same extrema exist
    (no minimum for neo-Hookean) and agree within each quantity's stated accuracy."""
    for (jm, vb), found in cleanroom["extrema"].items():
        for name, (kind, k) in EXTREMA.items():
            stored = float(ds[name].sel(Jm=jm, vbar=vb))
            if found[kind] is None:
                assert math.isnan(stored), (name, jm, vb)
                continue
            exact = float(found[kind][k])
            tol = _tolerance(name, {"Jm": jm, "vbar": vb}).tolerance[0]
            assert abs(stored - exact) <= tol, (name, jm, vb, stored - exact)
    assert all(cleanroom["extrema"][math.inf, vb]["min"] is None for vb in ds.vbar.values)


def test_voltage_limit_points_match_the_clean_room_at_the_stated_accuracy(ds, cleanroom):
    """lam_vmax and vbar_max at every (Jm, pbar_fixed) within the stated accuracy."""
    for (jm, pf), found in cleanroom["limit"].items():
        assert found is not None
        for name, k in (("lam_vmax", 0), ("vbar_max", 1)):
            stored = float(ds[name].sel(Jm=jm, pbar_fixed=pf))
            tol = _tolerance(name, {"Jm": jm, "pbar_fixed": pf}).tolerance[0]
            assert abs(stored - float(found[k])) <= tol, (name, jm, pf)


def _csv(path, header, rows):
    path.write_text(header + "\n" + "\n".join(",".join(repr(float(x)) for x in r)
                                              for r in rows) + "\n")
    return str(path)


def test_cleanroom_balloon_passes_check_first_try(ds, cleanroom, tmp_path, capsys):
    """The files a stranger writes (the curves at the published stretches; the pressure
    maxima; the minima, without rows where there is none; the voltage limit points): each
    passes ``debench check`` with complete coverage of each quantity."""
    rows = [(jm, vb, x, y) for (jm, vb), ys in cleanroom["pbar"].items()
            for x, y in zip(ds.lam.sel(Jm=jm).values, ys, strict=True)]
    curves = _csv(tmp_path / "pbar.csv", "Jm [1],vbar [1],lam [1],pbar [1]", rows)
    files = [(curves, 1)]
    for kind in ("max", "min"):   # no rows where there is no minimum (neo-Hookean)
        rows = [(jm, vb, *f[kind]) for (jm, vb), f in cleanroom["extrema"].items()
                if f[kind] is not None]
        files.append((_csv(tmp_path / f"{kind}.csv", f"Jm [1],vbar [1],lam_p{kind} [1],"
                           f"pbar_{kind} [1]", rows), 2))
    rows = [(jm, pf, *f) for (jm, pf), f in cleanroom["limit"].items()]
    files.append((_csv(tmp_path / "limit.csv", "Jm [1],pbar_fixed [1],lam_vmax [1],"
                       "vbar_max [1]", rows), 2))
    for path, n in files:
        assert cli.main(["check", PROBLEM, path]) == 0, path
        assert capsys.readouterr().out.count("coverage complete") == n, path


def test_check_refuses_a_modelling_error(ds, tmp_path, capsys):
    """The neo-Hookean curve at vbar = 0.3 with the Maxwell stress halved (a common slip:
    eps E^2/2) fails the check."""
    lam = ds.lam.sel(Jm=math.inf).values
    wrong = 2 * (lam**-1 - lam**-7) - 0.3**2 * lam
    path = _csv(tmp_path / "wrong.csv", "Jm [1],vbar [1],lam [1],pbar [1]",
                [(math.inf, 0.3, x, y) for x, y in zip(lam, wrong, strict=True)])
    assert cli.main(["check", PROBLEM, path, "--partial"]) == 1


# ------------------------------------------------------------------ the closed forms
def test_neo_hookean_pressure_maximum_is_at_seventh_root_sixth():
    """vbar = 0: d/dlam 2(lam^-1 - lam^-7) = 0 at lam = 7^(1/6), pbar = (12/7) 7^(-1/6)."""
    e = balloon.pressure_extrema(0.0)
    assert e.minimum is None
    assert e.maximum.lam == pytest.approx(7 ** (1 / 6), rel=ROUNDOFF)
    assert e.maximum.value == pytest.approx(12 / 7 * 7 ** (-1 / 6), rel=ROUNDOFF)


def test_voltage_limit_at_zero_pressure_is_the_free_membrane_pull_in():
    """pbar = 0: vbar^2 = lam^-2 - lam^-8, the free equibiaxial membrane (Zhao & Suo 2007):
    maximum at lam = 2^(1/3), vbar = sqrt(2^(-2/3) - 2^(-8/3))."""
    e = balloon.voltage_limit(0.0)
    assert e.lam == pytest.approx(2 ** (1 / 3), rel=ROUNDOFF)
    assert e.value == pytest.approx(math.sqrt(2 ** (-2 / 3) - 2 ** (-8 / 3)), rel=ROUNDOFF)


def test_pressure_is_laplaces_law_with_the_maxwell_stress():
    """p r/(2h) = sigma - eps E^2 with sigma = (lam/2) dW/dlam (by central differences of
    the Gent energy, step 1e-5: error ~1e-10 relative) and E = Phi/h."""
    jm, vb = 50.0, 0.3
    lam = np.linspace(1.1, 4.5, 9)

    def w(x):
        return -jm / 2 * np.log(1 - (2 * x**2 + x**-4 - 3) / jm)

    step = 1e-5
    sigma = lam / 2 * (w(lam + step) - w(lam - step)) / (2 * step)
    maxwell = vb**2 * lam**4
    pbar = balloon.pressure(lam, vb, jm)
    assert np.allclose(pbar * lam**3 / 2, sigma - maxwell, rtol=1e-8, atol=1e-9)


@pytest.mark.parametrize("call, message", [
    (lambda: balloon.pressure(0.9, 0.1), r"lam must lie in \[1, inf\)"),
    (lambda: balloon.pressure(7.1, 0.1, 97.2), "past the Gent locking stretch 7.07812"),
    (lambda: balloon.pressure(2.0, -0.1), "vbar must be >= 0"),
    (lambda: balloon.pressure(2.0, 0.1, 0.0), "Jm must be > 0"),
    (lambda: balloon.voltage_limit(math.nan), "pbar must be finite"),
    (lambda: balloon.pressure_extrema(0.1, -5.0), "Jm must be > 0"),
])
def test_bad_input_raises_naming_the_argument_and_bound(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_dataset_regenerates_from_the_model(ds):
    """The curated dataset is what the builder computes now (bit for bit)."""
    from debench.reference.builders import lit_balloon

    fresh = lit_balloon.compute()
    for name in fresh.data_vars:
        np.testing.assert_array_equal(fresh[name].values, ds[name].values, err_msg=name)


def test_page_states_the_stored_window_and_locking_stretches(ds):
    """The numbers the page quotes for the window of pbar (the last stored stretch of each
    Gent curve) and the locking stretches are the dataset's and the model's."""
    q = problems.get(PROBLEM).quantity("pbar")
    text = q.domain["window"] + " ".join(e["why"] for e in q.domain["excluded"])
    for jm in (97.2, 50.0):
        assert f"{float(ds.lam.sel(Jm=jm).values[-1]):.4f} for Jm = {jm:g}" in text
        assert f"{balloon.locking_stretch(jm):.4f} for Jm = {jm:g}" in text
    assert float(ds.lam.sel(Jm=math.inf).values[-1]) == 8.0 and "lam <= 8" in text
