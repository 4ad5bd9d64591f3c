"""Every dataset the writer produces passes the IOOS compliance-checker: all CF-1.10 checks,
and the ACDD-1.3 highly recommended and recommended attributes present where they apply.

The checker is the real tool (``compliance-checker`` in the ``test`` extra), run on files
the one writer (:func:`debench.reference.datasets.write_dataset`) writes now: a small
representative dataset, and the contents of every curated dataset re-written through the
writer. The curated files as shipped are checked too (about 15 s).
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from debench.reference import standards
from debench.reference.datasets import data_dir, read_dataset, read_manifest, write_dataset

#: Checks that crash inside compliance-checker 6.1 on valid files, with the reason. The
#: strict-monotonicity check subtracts coordinate values and raises ``TypeError`` on a
#: string-valued dimension coordinate (catalogue entry ids, material names); the test
#: then checks the monotonicity of the numeric coordinate variables itself.
KNOWN_CHECKER_ERRORS = {
    "cf:1.10:check_coordinate_variables_strict_monotonicity":
        "TypeError on string-valued coordinate variables",
}
#: Curated datasets re-written in the default run: one per chapter and shape (string
#: coordinates, a 4-d array, NaN-padded curves, the value stores); the rest with --full.
DEFAULT_SUBSET = ("ch2_kernel_reference_states", "ch3_voltage_stretch", "ch4_fig4_2_curves",
                  "ch5_methods", "thesis_values")


def _curated_names() -> list[str]:
    return sorted(f.removesuffix(".nc") for f in read_manifest(data_dir()))


def _assert_standards(path) -> None:
    found = standards.check_file(path)
    unexpected = {k: v for k, v in found.checker_errors.items() if k not in KNOWN_CHECKER_ERRORS}
    assert not unexpected, f"{path.name}: the checker crashed: {unexpected}"
    assert not found.cf_failures, f"{path.name}: CF-1.10 failures {found.cf_failures}"
    assert not found.acdd_missing, (f"{path.name}: ACDD attributes missing that apply: "
                                    f"{sorted(found.acdd_missing)}")
    assert not found.acdd_failures, f"{path.name}: ACDD failures {found.acdd_failures}"
    cf = found.scores["cf:1.10"]
    assert cf[0] == cf[1] > 0, f"{path.name}: CF-1.10 score {cf}"
    if found.checker_errors:  # the crashed check, done here
        with xr.open_dataset(path) as ds:
            for dim in ds.dims:
                if dim in ds.coords and np.issubdtype(ds[dim].dtype, np.number):
                    step = np.diff(ds[dim].values)
                    assert np.all(step > 0) or np.all(step < 0), \
                        f"{path.name}: coordinate {dim!r} not strictly monotonic"


def _rewrite(name: str, out_dir):
    """The contents of curated dataset ``name`` written again by the current writer."""
    if name == "ch2_kernel_reference_states":  # cheap to recompute: the current names
        from debench.reference.builders import ch2_appendix

        ds, src = ch2_appendix.compute(), read_dataset(name)
    else:
        src = read_dataset(name)
        ds = src.copy()
        ds.attrs = {}
        for var in ds.variables.values():
            var.attrs.pop("coverage_content_type", None)
    params = {k: v for k, v in src.attrs.items() if k.startswith("param_")}
    return write_dataset(ds, name, title=src.attrs["title"], summary=src.attrs["summary"],
                         references=src.attrs["references"], parameters=params,
                         command="verification/test_standards.py", out_dir=out_dir)


def test_a_small_dataset_from_the_writer_passes_cf_and_acdd(tmp_path):
    """A curve with NaN, an error estimate, a printed value, a string and a float
    coordinate, and ``p``-like names: all CF checks pass, the applicable ACDD attributes are
    present, and each variable gets the ACDD ``coverage_content_type`` of its role."""
    lam = np.array([1.0, 1.5, 2.0])
    ds = xr.Dataset(
        {"phibar": (("case", "lam"), [[0.1, 0.2, np.nan], [0.1, 0.3, 0.4]],
                    {"units": "1", "long_name": "normalised voltage"}),
         "phibar_error": ("case", [1e-6, 2e-6], {"units": "1", "long_name": "error bound"}),
         "phibar_printed": ("case", [0.2, 0.3], {"units": "1", "long_name": "thesis value"})},
        coords={"lam": ("lam", lam, {"units": "1", "long_name": "stretch"}),
                "case": ("case", ["a", "b"], {"long_name": "case"})})
    path = write_dataset(ds, "ch0_example", title="t", summary="s", parameters={"mu": 51e3},
                         out_dir=tmp_path)
    _assert_standards(path)
    back = read_dataset(path)
    kinds = {n: back[n].attrs["coverage_content_type"] for n in back.variables}
    assert kinds == {"phibar": "modelResult", "phibar_error": "qualityInformation",
                     "phibar_printed": "referenceInformation", "lam": "coordinate",
                     "case": "coordinate"}
    import netCDF4

    with netCDF4.Dataset(path) as nc:
        assert "_FillValue" not in nc.variables["lam"].ncattrs()
        assert "_FillValue" in nc.variables["phibar"].ncattrs()  # the NaN of the curve


def test_no_two_curated_variables_differ_only_by_case():
    """CF 2.3: names differ by more than case (the checker's rule), for every curated
    dataset as the current builders name its variables (the kernel one recomputed)."""
    from debench.reference.builders import ch2_appendix

    for name in _curated_names():
        ds = ch2_appendix.compute() if name == "ch2_kernel_reference_states" \
            else read_dataset(name)
        lower = [str(v).lower() for v in ds.variables]
        assert len(lower) == len(set(lower)), f"{name}: names differ only by case"


@pytest.mark.parametrize("name", DEFAULT_SUBSET)
def test_curated_contents_written_by_the_writer_pass_cf_and_acdd(name, tmp_path):
    """A representative subset of the curated datasets, re-written by the writer."""
    _assert_standards(_rewrite(name, tmp_path))


@pytest.mark.slow
def test_every_curated_dataset_written_by_the_writer_passes_cf_and_acdd(tmp_path):
    """Every curated dataset, re-written by the writer, passes the checker."""
    for name in _curated_names():
        _assert_standards(_rewrite(name, tmp_path))


@pytest.mark.parametrize("name", _curated_names())
def test_every_curated_file_passes_cf_and_acdd(name):
    """The curated files as shipped (after regeneration by the current writer), one test
    per file (so that parallel workers share them)."""
    _assert_standards(data_dir() / f"{name}.nc")
