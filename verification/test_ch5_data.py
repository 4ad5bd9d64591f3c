"""Chapter 5 curated datasets (``data/ch5_*.nc``) and catalogue statuses.

* the curated data verify (manifest checksum, CF attributes) and a cheap regeneration --
  the coarsest critical-voltage level of the neo-Hookean case -- reproduces them;
* the curated numbers satisfy the cross-method claims (eigen-analysis vs Southwell vs
  plate theory; scale invariance 0.5 mm = 1 mm);
* the curated data are a converged reference: >= 5 mesh levels up to >= 150,000 DOFs with
  >= 2 layers, a fitted limit with an error estimate from redundant levels, the observed
  order consistent with the edge singularity of the clamped film, a through-thickness
  study, the pull-in fitted over >= 3 ramp meshes, and every variable stating its accuracy;
* the wrinkling search at radius/thickness 10 gives the same outcome on every
  circumferential resolution;
* every ``ch5.*`` catalogue entry computes its ``expected_status``.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
from debench.reference import catalogue
from debench.reference.datasets import read_dataset

# secant on lambda_1(v^2) stops at |dv| < 1e-6 (debench.models.buckling.solver.CRITICAL_VTOL);
# a rerun from the same start is deterministic up to BLAS round-off
REGEN_ATOL = 2e-6
# Southwell on the ramp mesh vs eigen-analysis on the same mesh (see test_ch5_fem.py)
SOUTHWELL_RTOL = 1e-2
PLATE_THEORY_RTOL = 0.03
SCALE_RTOL = 1e-5


@pytest.fixture(scope="module")
def crit():
    return read_dataset("ch5_critical_voltage")


@pytest.fixture(scope="module")
def ramps():
    return read_dataset("ch5_ramps")


def test_regenerating_coarsest_level_reproduces_curated_critical_voltage(crit):
    """Regeneration: the coarsest mesh level of the neo-Hookean 1 mm case recomputed now
    (the model guard `debench verify` runs) equals the curated value."""
    from debench.reference.producers.ch5 import coarse_guards

    guards = {g.key: g for g in coarse_guards(cases=["nh_t1"])}
    diff = guards["ch5.guard.nh_t1.v_cr_coarse_minus_curated"]
    assert abs(diff.value) <= REGEN_ATOL, diff
    assert guards["ch5.guard.nh_t1.ndof_coarse"].value == int(
        crit.sel(case="nh_t1").ndof.values[0])


def test_curated_critical_voltage_three_methods_agree(crit):
    """Eigen-analysis (ramp mesh) vs Southwell; Richardson limit vs clamped-plate theory."""
    for case in crit.case.values:
        c = crit.sel(case=case)
        assert float(c.v_cr_southwell) == pytest.approx(float(c.v_cr_ramp_mesh), rel=SOUTHWELL_RTOL)
        assert float(c.v_cr_extrapolated) == pytest.approx(float(c.v_cr_kirchhoff),
                                                           rel=PLATE_THEORY_RTOL)
        assert np.all(np.diff(c.v_cr.values) < 0)       # monotone under refinement
        assert float(c.convergence_rate) >= 1.0


def test_curated_data_are_scale_invariant(crit, ramps):
    """0.5 mm and 1 mm coincide in normalised variables (erratum table5_2)."""
    np.testing.assert_allclose(crit.sel(case="ogden_t0p5").v_cr.values,
                               crit.sel(case="ogden_t1").v_cr.values, rtol=SCALE_RTOL)
    assert float(ramps.sel(case="ogden_t0p5").v_pullin) == pytest.approx(
        float(ramps.sel(case="ogden_t1").v_pullin), rel=SCALE_RTOL)


def test_curated_pullin_ratio(ramps):
    """§5.3.2: pull-in voltage Ogden / neo-Hookean = 0.179/0.268 = 0.668 (ratio free of the
    unstated normalisation); band from the printed digits 0.6648 .. 0.6710."""
    ratio = float(ramps.sel(case="ogden_t1").v_pullin / ramps.sel(case="nh_t1").v_pullin)
    assert 0.6648 <= ratio <= 0.6710


#: The converged reference contract: the least-squares fit has three unknowns and one more
#: level is dropped for its error estimate, so >= 5 levels; the finest mesh is of the
#: thesis' size class (>= 150,000 DOFs) with >= 2 layers of quadratic prisms
MIN_LEVELS = 5
MIN_FINEST_NDOF = 150_000
MIN_LAYERS = 2
MIN_RAMP_LEVELS = 3


def _params(ds):
    from debench.reference.datasets import dataset_parameters
    return dataset_parameters(ds)


def _curated_is_converged() -> bool:
    return bool(_params(read_dataset("ch5_critical_voltage")).get("full", False))


#: The contract of the converged run applies to the curated data, which
#: ``debench reproduce ch5 --full --write-data`` writes (the plan itself is tested in
#: test_ch5_sweeps.py). Curated data that are the coarse default fail, naming what to run:
#: the converged contract is checked in every run, never skipped.
def converged_only(test):
    @functools.wraps(test)
    def run(*args, **kwargs):
        if not _curated_is_converged():
            pytest.fail("the curated Chapter 5 data are the coarse default: the converged "
                        "contract needs `debench reproduce ch5 --full --write-data` first")
        return test(*args, **kwargs)
    return run


@converged_only
def test_curated_critical_voltage_is_a_converged_reference(crit):
    """The curated critical voltages come from the converged run (``--full``): enough
    levels, a fine enough finest mesh, an error estimate that is finite, positive and
    small against the value, and a reference within its error of the finest mesh plus
    the remaining mesh error."""
    par = _params(crit)
    assert par["full"] is True
    assert crit.sizes["level"] >= MIN_LEVELS
    assert int(par["layers"]) >= MIN_LAYERS
    assert int(crit.ndof.isel(level=-1).min()) >= MIN_FINEST_NDOF
    for case in crit.case.values:
        c = crit.sel(case=case)
        err = float(c.v_cr_reference_error)
        assert np.isfinite(err) and err > 0
        # error estimate well below the discretisation error of the coarsest level
        assert err < 0.1 * abs(float(c.v_cr.isel(level=0)) - float(c.v_cr_reference))
        assert np.all(np.diff(c.v_cr_layers.values) < 0)     # more layers: lower v_cr


#: The observed order of the three finest levels against the edge-singularity prediction
#: 2 s(nu) (models.buckling.singularity): the builder's criterion for the asymptotic range
#: (a second error term up to ~20 % of the first shifts a three-level rate by 0.25; the
#: secant tolerance 1e-6 is 0.1 % of the level differences)
from debench.models.numerics.convergence import ORDER_TOL as ORDER_ATOL  # noqa: E402


@converged_only
def test_observed_order_is_the_edge_singularity_order(crit):
    """The critical voltage converges at the order the clamped-free edge singularity of
    the film predicts for quadratic elements, 2 s(nu) with s the Williams exponent of the
    90 degree clamped-free corner at Table 5.1's Poisson ratio (not the 2p = 4 of smooth
    eigenfunctions): observed on the three finest levels of every computed case."""
    from debench.models.numerics import richardson
    from debench.reference.studies.ch5 import SCALE_COPIES, expected_order

    for case in crit.case.values:
        if case in SCALE_COPIES:
            continue
        expected = expected_order(case)
        assert expected == pytest.approx(1.2, abs=0.01)          # nu ~ 0.49-0.4955
        c = crit.sel(case=case)
        _, p = richardson(c.h_rel.values, c.v_cr.values)
        assert p == pytest.approx(expected, abs=ORDER_ATOL), case


@converged_only
def test_coarse_error_estimate_covers_the_converged_limit(crit):
    """The error bar the coarse default reports -- the three coarsest levels fitted at the
    expected order or, pre-asymptotic, with the expected order's bound
    (:func:`~debench.models.numerics.reference_fit`) -- contains
    the limit of the whole converged sequence, within the two error bars."""
    from debench.models.numerics import reference_fit
    from debench.reference.studies.ch5 import SCALE_COPIES, expected_order

    for case in crit.case.values:
        if case in SCALE_COPIES:
            continue
        c = crit.sel(case=case)
        coarse = reference_fit(c.h_rel.values[:3], c.v_cr.values[:3], expected_order(case))
        assert abs(coarse.v_inf - float(c.v_cr_extrapolated)) <= (
            coarse.error + float(c.v_cr_error)), (case, coarse, float(c.v_cr_extrapolated))


def test_every_curated_ch5_value_states_its_accuracy(crit, ramps):
    """Each reported value of the Chapter 5 datasets carries an ``accuracy`` attribute
    (the solver tolerance of its mesh, or the error variable of its limit)."""
    for ds, names in ((crit, ("v_cr", "v_cr_extrapolated", "v_cr_layers",
                              "v_cr_layer_limit", "v_cr_reference")),
                      (ramps, ("v_pullin", "w_pullin", "v_pullin_levels", "w_pullin_levels",
                               "v_pullin_extrapolated", "w_pullin_extrapolated"))):
        for name in names:
            acc = ds[name].attrs.get("accuracy", "")
            assert acc, name
            if acc.startswith("+- "):
                assert acc[3:] in ds, (name, acc)


@converged_only
def test_curated_pullin_is_fitted_over_three_ramp_meshes(ramps):
    """Pull-in voltage and deflection on >= 3 ramp meshes with a mesh limit and an error
    estimate (finite: the levels converge)."""
    assert ramps.sizes["ramp_level"] >= MIN_RAMP_LEVELS
    for case in ("nh_t1", "ogden_t1"):
        r = ramps.sel(case=case)
        for key in ("v_pullin", "w_pullin"):
            assert np.isfinite(float(r[f"{key}_error"])), (case, key)
            assert np.isfinite(float(r[f"{key}_extrapolated"])), (case, key)


@converged_only
def test_curated_wrinkling_search_agrees_across_resolutions(ramps):
    """Wrinkling search (§5.3.1, Fig. 5.5): the outcome -- a non-axisymmetric mode unstable
    before pull-in, or none -- is the same on every ramp mesh (three circumferential
    resolutions) at radius/thickness 10."""
    for case in ("nh_t1", "ogden_t1"):
        found = np.isfinite(ramps.sel(case=case).v_wrinkling_levels.values)
        assert found.all() or not found.any(), case


DIP_RATIO_R10 = 0.25
"""A non-axisymmetric eigenvalue that stays above a quarter of its largest value on the path
up to pull-in is far from a bifurcation (R/t0 = 10: 0.36; at R/t0 = 20 it reaches zero)."""
MM_WINDOW = (3.5, 4.0)
"""Centre deflections (mm, t0 = 0.5 mm) that count as "near the printed 3.64 mm": the two
finest meshes differ by 0.04 mm, the coarser ones by up to 1.4 mm."""
AT_PATH_MAXIMUM = 1e-3
"""The bifurcation sits at the voltage maximum of the path when its voltage is within this
fraction of the maximum: along the two finest paths the voltage still rises by 0.03-0.08 of
its maximum per t0 of deflection just before it, so the fraction is 0.01-0.03 t0 of
deflection, below the 0.08 t0 between the two meshes' bifurcations."""
W_AXISYMMETRIC_LIMIT = 9.0
"""Centre deflection / t0 beyond which the meshes that pass the bifurcation find their
axisymmetric limit point (measured 11.7 t0); the bifurcations lie at 7.6-7.95 t0."""


def test_curated_r20_wrinkling_search():
    """§5.3.1 / Fig. 5.5 at radius/thickness 20 (the 0.5 mm film if its model kept
    R = 10 mm; ``ch5_wrinkling.nc``), on five circumferential resolutions. The 3D finding
    (held against the converged axisymmetric path by
    ``ch5.crosscheck.axisym_vs_3d_wrinkling_r20``): on both finest meshes the
    first eigenvalue to reach zero along the path belongs to an n = 1 mode, with no
    axisymmetric mode among the three recorded there (wrinkling before pull-in, as printed),
    at a centre deflection in MM_WINDOW but outside the printed 3.64 mm plus the meshes'
    difference; the path's voltage maximum sits at that bifurcation (within
    AT_PATH_MAXIMUM), while the mesh that passes it reaches an axisymmetric limit point
    beyond W_AXISYMMETRIC_LIMIT; at the stated R/t0 = 10 the lowest non-axisymmetric
    eigenvalue stays above DIP_RATIO_R10 of its maximum up to pull-in. Every path reached
    its voltage maximum or says why it stopped."""
    from debench.reference.producers.ch5_hypotheses import wrinkling_search
    from debench.reference.studies.ch5 import lowest_nonaxisymmetric

    ds = read_dataset("ch5_wrinkling")
    assert ds.sizes["level"] >= 5 and np.all(np.diff(ds.rim_elements.values) > 0)
    found = wrinkling_search(ds)
    # the stored first instability is the catalogue's reading of the same records
    assert [str(k) for k in ds.first_kind.values] == found["first_kind"]
    np.testing.assert_array_equal(ds.w_first.values, found["w_first_over_t0"])
    np.testing.assert_array_equal(ds.n_first.values, found["n_first"])
    assert found["first"][-2:] == [True, True], found
    for lev in (-2, -1):
        assert MM_WINDOW[0] <= found["w_first_over_t0"][lev] * 0.5 <= MM_WINDOW[1], found
        assert found["n_first"][lev] == 1.0, found
        assert min(found["wavenumbers_first"][lev]) >= 1, found   # no axisymmetric mode
        assert found["v_first_over_v_max"][lev] >= 1.0 - AT_PATH_MAXIMUM, found
    passed = [k for k, kind in enumerate(found["first_kind"]) if kind == "axisymmetric"]
    assert passed and all(found["w_first_over_t0"][k] > W_AXISYMMETRIC_LIMIT for k in passed)
    assert found["path_end"][-1] == "stalled before the limit point"
    for end, vp in zip(found["path_end"], ds.v_pullin.values, strict=True):
        assert end in ("voltage drop", "singular past the limit point",
                       "stalled before the limit point"), end
        assert np.isfinite(vp) == (end != "stalled before the limit point")
    # the finest mesh's wrinkling deflection lies outside the printed 3.64 mm plus the two
    # finest meshes' difference (the converged axisymmetric path decides the catalogue's
    # verdict: ch5.hypothesis.radius_kept.wrinkling_t0p5)
    w_mm, w_mm_second = found["w_over_t0"] * 0.5, found["w_over_t0_second"] * 0.5
    assert w_mm - abs(w_mm - w_mm_second) > 3.645, found
    r10 = read_dataset("ch5_ramps").sel(case="ogden_t0p5")   # the same film at R/t0 = 10
    lam10 = lowest_nonaxisymmetric(r10.eig_lambda.values, r10.eig_wavenumber.values)
    lam10 = lam10[np.isfinite(lam10) & (r10.eig_w.values <= float(r10.w_pullin))]
    assert float(np.min(lam10) / np.max(lam10)) > DIP_RATIO_R10


def test_curated_r20_imperfection_sensitivity():
    """§5.3.1 ("fails at a lower achievable deformation") at radius/thickness 20, films with
    a wavenumber-1 seed (``ch5_imperfection.nc``). The finding
    (``ch5.hypothesis.radius_kept.wrinkling_failure_t0p5``, unexplained): the reading fixed
    before the data is "undecided"; with the two smaller seeds the first instability at
    fixed voltage is an n = 1 mode before W_SPLIT on both meshes, but on h = 2 t0 the path
    turns there while on h = 2.5 t0 the voltage still rises; the largest seed passes on
    both meshes; the maxima on h = 2 t0 rise with the seed (no imperfection sensitivity of
    the seeded mode)."""
    from debench.reference.producers.ch5_hypotheses import hypothesis_wrinkling_failure
    from debench.reference.studies.ch5_imperfection import W_SPLIT, wrinkling_governs

    ds = read_dataset("ch5_imperfection")
    assert list(ds.h_rel.values) == [2.5, 2.0] and ds.sizes["amplitude"] == 3
    assert wrinkling_governs(ds) == "undecided"
    entry = next(e for e in CH5 if e.id == "ch5.hypothesis.radius_kept.wrinkling_failure_t0p5")
    out = hypothesis_wrinkling_failure(entry)
    d = out.details
    assert out.status == "unexplained" and d["reading"] == "undecided"
    for lev in (0, 1):
        for j in (0, 1):
            assert d["first_kind"][lev][j] == "non-axisymmetric" and d["first_n"][lev][j] == 1
            # on the wrinkling side of the reading's split (fixed before the data)
            assert MM_WINDOW[0] / 0.5 <= d["first_w_over_t0"][lev][j] < W_SPLIT, d
    # h = 2 t0: the smaller seeds' paths turn at their first instability, to within the
    # deflection step there (~0.01 t0); h = 2.5 t0: they stall with the voltage rising
    for j in (0, 1):
        assert abs(d["w_at_v_max_over_t0"][1][j] - d["first_w_over_t0"][1][j]) < 0.02, d
        assert d["path_end"][0][j] == "stalled before the limit point", d
    assert np.all(np.diff(ds.v_max.values[1]) > 0), d["v_max"]
    assert ds.w_at_v_max.values[0, 2] > W_SPLIT > ds.w_at_v_max.values[1, 2], d
    # the largest seed on h = 2.5 t0 passes the bifurcation and becomes unstable first at
    # its axisymmetric limit point, past the voltage maximum
    assert d["first_kind"][0][2] == "axisymmetric", d
    assert d["first_w_over_t0"][0][2] > ds.w_at_v_max.values[0, 2], d


def _paths(name):
    """(label, w, v, eig_w, eig_v, eig_lam) of every recorded path of a curated dataset."""
    ds = read_dataset(name)
    lam = ds["eig_lam"] if "eig_lam" in ds else ds["eig_lambda"]
    outer = ds.v.dims[:-1]
    for idx in np.ndindex(*(ds.sizes[d] for d in outer)):
        sel = dict(zip(outer, idx, strict=True))
        yield (f"{name}{list(idx)}", ds.w[sel].values, ds.v[sel].values,
               ds.eig_w[sel].values, ds.eig_v[sel].values, lam[sel].values)


@pytest.mark.parametrize("name", ["ch5_ramps", "ch5_wrinkling", "ch5_imperfection"])
def test_curated_records_past_a_voltage_maximum_show_the_unstable_mode(name):
    """Past a path's voltage maximum at least one eigenvalue of the tangent at fixed voltage
    is negative (the determinant changes sign at the maximum): no curated eigen-record
    there may show only positive eigenvalues (which is what an eigen-solver that missed
    the unstable mode records). At least one path of each dataset has records past its
    maximum, so the check is not empty."""
    from debench.reference.studies.ch5 import stable_records_past_voltage_maximum

    checked = 0
    for label, w, v, ew, ev, lam in _paths(name):
        bad = stable_records_past_voltage_maximum(w, v, ew, ev, lam)
        assert bad.size == 0, (label, ew[bad], lam[bad])
        k = int(np.nanargmax(v))
        checked += int(np.sum(np.isfinite(ew) & (ew > w[k]) & (ev < v[k])))
    assert checked > 0


def test_stable_records_past_voltage_maximum_flags_only_records_past_the_maximum():
    from debench.reference.studies.ch5 import stable_records_past_voltage_maximum as check

    w = np.array([0.0, 1.0, 2.0, 3.0, 4.0, np.nan])
    v = np.array([0.0, 0.5, 0.8, 0.7, 0.6, np.nan])
    ew = np.array([1.0, 3.0, 4.0, np.nan])
    ev = np.array([0.5, 0.7, 0.6, np.nan])
    lam = np.array([[0.1, 0.2], [-0.1, 0.2], [0.1, 0.2], [np.nan, np.nan]])
    assert check(w, v, ew, ev, lam).tolist() == [2]       # the positive record past it
    lam[2, 0] = -0.2
    assert check(w, v, ew, ev, lam).size == 0
    # a rising path has no maximum to be past
    assert check(w, np.linspace(0, 1, 6), ew, ev, lam).size == 0
    with pytest.raises(ValueError, match="eig_lam"):
        check(w, v, ew, ev, lam[:2])


def test_propagated_accuracy_bounds_the_change_of_derived_values():
    """First-order bound, one input at a time: exact for a linear function, and it bounds
    the change when every input moves by its accuracy at once (ratio of two values)."""
    from debench.models.numerics import propagated_accuracy

    x, dx = np.array([2.0, 3.0]), np.array([1e-3, 2e-3])
    assert np.allclose(propagated_accuracy(lambda y: y[0] - 2 * y[1], x, dx), 5e-3,
                       rtol=1e-9)
    bound = propagated_accuracy(lambda y: y[1] / y[0], x, dx)
    for sign in ((1, -1), (-1, 1), (1, 1)):
        moved = (x[1] + sign[1] * dx[1]) / (x[0] + sign[0] * dx[0])
        # second-order terms (dx/x)^2 ~ 1e-6 of the bound are below the 1.01 margin
        assert abs(moved - x[1] / x[0]) <= 1.01 * bound


CH5 = [e for e in catalogue.load() if e.file == "ch5.toml"]


@pytest.mark.parametrize("entry", CH5, ids=[e.id for e in CH5])
def test_ch5_catalogue_entry_has_expected_status(entry):
    r = catalogue.evaluate(entry)
    assert r.status == entry.expected_status, (r.value, r.diagnosis)
