"""The regeneration check of ``debench verify`` judges each variable by its own accuracy.

:func:`debench.reference.regeneration.compare_with_curated` compares a rebuilt dataset with the
curated one; a variable that states its accuracy (``accuracy_rtol``/``accuracy_atol``, as
the in-plane and strip FE roots do) is judged by it, any other numeric variable by the
default (``REGEN_RTOL``, ``REGEN_ATOL``).
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from debench.reference.datasets import write_dataset
from debench.reference.regeneration import (
    REGEN_ATOL,
    REGEN_RTOL,
    compare_with_curated,
    regeneration_tolerance,
)

#: the stated accuracy of the test variable: looser in atol than the default, tighter in
#: rtol (values O(1)), as the FE roots of the in-plane and strip datasets
RTOL, ATOL = 1e-9, 2e-6
BASE = np.array([0.6661, 1.25, 3.5])


def _write(directory, lam_own, lam_default):
    ds = xr.Dataset(
        {"lam_own": ("i", lam_own, {"long_name": "root with a stated accuracy", "units": "1",
                                    "accuracy_rtol": RTOL, "accuracy_atol": ATOL,
                                    "accuracy_reason": "test"}),
         "lam_default": ("i", lam_default, {"long_name": "root without one", "units": "1"})},
        coords={"i": ("i", np.arange(BASE.size), {"long_name": "index", "units": "1"})})
    return write_dataset(ds, "ch4_regen_test", title="t", summary="s", parameters={"a": 1},
                         out_dir=directory, overwrite=True)


@pytest.fixture
def curated(tmp_path):
    _write(tmp_path / "curated", BASE, BASE)
    return tmp_path / "curated"


def _compare(tmp_path, curated, own_shift, default_shift):
    path = _write(tmp_path / "new", BASE + own_shift, BASE + default_shift)
    return compare_with_curated(path, curated)


def test_variable_within_its_own_accuracy_matches(tmp_path, curated):
    """A shift inside the stated atol (beyond the default rtol) passes."""
    assert "matches curated" in _compare(tmp_path, curated, 0.5 * ATOL, 0.0)


def test_variable_beyond_its_own_accuracy_differs(tmp_path, curated):
    """A shift beyond the stated accuracy fails and names only that variable."""
    line = _compare(tmp_path, curated, 2 * (ATOL + RTOL * BASE.max()), 0.0)
    assert "DIFFERS in lam_own" in line and "lam_default" not in line


def test_variable_without_accuracy_uses_the_default(tmp_path, curated):
    """Without accuracy attributes, the default rtol decides: inside passes, beyond fails."""
    inside = 0.5 * REGEN_RTOL * BASE.min()
    assert "matches curated" in _compare(tmp_path, curated, 0.0, inside)
    line = _compare(tmp_path, curated, 0.0, 2 * (REGEN_ATOL + REGEN_RTOL * BASE.max()))
    assert "DIFFERS in lam_default" in line and "lam_own" not in line


def test_regeneration_tolerance_rejects_a_void_accuracy():
    with pytest.raises(ValueError, match="accuracy_rtol"):
        regeneration_tolerance({"accuracy_rtol": 0.0, "accuracy_atol": 0.0})
    assert regeneration_tolerance({"accuracy_atol": ATOL}) == (0.0, ATOL)
    assert regeneration_tolerance({}) == (REGEN_RTOL, REGEN_ATOL)


def _write_store(directory, value, tolerance, residual, name="our_values"):
    ds = xr.Dataset(
        {"value": ("key", value, {"long_name": "value", "units": "1"}),
         "tolerance": ("key", tolerance, {"long_name": "absolute tolerance", "units": "1",
                                          "coverage_content_type": "qualityInformation"}),
         "eig_residual": ("key", residual, {"long_name": "backward error", "units": "1",
                                            "coverage_content_type": "qualityInformation"})},
        coords={"key": ("key", np.arange(len(value)), {"long_name": "key", "units": "1"})})
    return write_dataset(ds, name, title="t", summary="s", parameters={"a": 1},
                         out_dir=directory, overwrite=True)


def test_values_are_judged_by_their_stored_tolerance_and_residuals_by_size(tmp_path):
    """A value of order 1e-16 (zero to round-off) with the absolute tolerance 1e-7 of its
    method matches when regenerated 1e-9 away (the default 1e-12 floor would call it
    different); beyond its tolerance it differs. A residual of round-off size matches when
    it changes within RESIDUAL_GROWTH of its size, and differs when it grows past it."""
    from debench.reference.regeneration import RESIDUAL_GROWTH

    value, tol = np.array([1e-16, 2.0]), np.array([1e-7, 1e-7])
    res = np.array([3e-12, 6e-12])
    _write_store(tmp_path / "curated", value, tol, res)
    new = _write_store(tmp_path / "new", value + np.array([1e-9, 5e-8]), tol, 2 * res)
    assert compare_with_curated(new, tmp_path / "curated").endswith("matches curated")
    new = _write_store(tmp_path / "new", value + np.array([2e-7, 0.0]), tol, res)
    assert compare_with_curated(new, tmp_path / "curated").endswith("DIFFERS in value")
    new = _write_store(tmp_path / "new", value, tol, 2 * RESIDUAL_GROWTH * res)
    assert compare_with_curated(new, tmp_path / "curated").endswith("DIFFERS in eig_residual")
    # another dataset with a "tolerance" beside its values (the thesis values: literals
    # beside printed-digit tolerances, some NaN) is compared by the default
    _write_store(tmp_path / "curated", value, np.array([np.nan, 0.05]), res, "thesis_like")
    new = _write_store(tmp_path / "new", value, np.array([np.nan, 0.05]), res, "thesis_like")
    assert compare_with_curated(new, tmp_path / "curated").endswith("matches curated")
    new = _write_store(tmp_path / "new", value + np.array([1e-9, 0.0]),
                       np.array([np.nan, 0.05]), res, "thesis_like")
    assert compare_with_curated(new, tmp_path / "curated").endswith("DIFFERS in value")


def _cheaper_plan(tmp_path, name, select, shift):
    """The curated dataset ``name`` as a cheaper plan would write it: other parameters,
    the coordinates ``select`` only, and ``shift(ds)`` applied to its values."""
    from debench.reference.datasets import read_dataset

    ds = read_dataset(name).isel(select)
    ds = shift(ds.copy(deep=True))
    attrs = {k: v for k, v in ds.attrs.items() if k in ("title", "summary")}
    return write_dataset(ds, name, title=attrs.get("title", "t"),
                         summary=attrs.get("summary", "s"), parameters={"full": False},
                         out_dir=tmp_path, overwrite=True)


@pytest.mark.parametrize("factor, agrees", [(0.5, True), (2.0, False)])
def test_a_cheaper_plan_is_checked_within_the_sum_of_both_error_estimates(tmp_path, factor,
                                                                          agrees):
    """A default plan's converged value (here the axisymmetric pull-in voltage) agrees with
    the curated one when it lies within the sum of the two error estimates, and differs
    beyond: checked, never 'not comparable'."""
    from debench.reference.datasets import data_dir

    def shift(ds):
        bound = ds.v_max_error + ds.v_max_error
        ds["v_max_converged"] = (ds.v_max_converged + factor * bound).assign_attrs(
            ds.v_max_converged.attrs)
        return ds

    path = _cheaper_plan(tmp_path, "ch5_axisym_path", {"case": [0], "n": [0, 1, 2, 3]}, shift)
    line = compare_with_curated(path, data_dir())
    assert "not comparable" not in line and "v_max_converged" in line
    assert ("agrees with curated" in line) is agrees
    assert ("DIFFERS in v_max_converged" in line) is not agrees


@pytest.mark.parametrize("rel, agrees", [(0.5e-3, True), (2e-3, False)])
def test_a_one_mesh_plan_is_checked_on_the_mesh_both_plans_compute(tmp_path, rel, agrees):
    """The default ramps have one mesh (no error estimate): their pull-in is checked on the
    mesh the curated plan ramps too, within the vertex's stated 1e-3 relative accuracy."""
    from debench.reference.datasets import data_dir
    from debench.reference.regeneration import PULLIN_VERTEX_RTOL

    assert PULLIN_VERTEX_RTOL == 1e-3

    def shift(ds):
        ds["v_pullin_levels"] = (ds.v_pullin_levels * (1 + rel)).assign_attrs(
            ds.v_pullin_levels.attrs)
        return ds

    path = _cheaper_plan(tmp_path, "ch5_ramps", {"ramp_level": [0]}, shift)
    line = compare_with_curated(path, data_dir())
    assert "not comparable" not in line and "v_pullin_levels at ramp_level 3" in line
    assert ("agrees with curated" in line) is agrees


def test_every_curated_full_plan_dataset_is_checked_or_stated_as_not_recomputed():
    """Every curated dataset made by a --full plan is, in the default run, either checked
    against its curated values (PLAN_CHECKS) or not recomputed with the reason stated (the
    converged-only studies): no dataset of the default run is 'not comparable'."""
    import json

    from debench.reference import builds, cli
    from debench.reference.datasets import data_dir, read_dataset
    from debench.reference.regeneration import PLAN_CHECKS

    stated = {line.split(".nc:")[0] for line in builds.not_recomputed(cli.CHAPTERS, False)}
    full = set()
    for path in sorted(data_dir().glob("*.nc")):
        params = json.loads(read_dataset(path.stem).attrs.get("parameters", "{}"))
        if params.get("full") is True:
            full.add(path.stem)
    assert full and full <= set(PLAN_CHECKS) | stated, full - set(PLAN_CHECKS) - stated
    assert not set(PLAN_CHECKS) & stated
