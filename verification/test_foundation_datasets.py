"""The dataset convention (debench.reference.datasets): provenance, checksums, atomic writes."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr
from debench.reference import datasets, manifest
from debench.reference.datasets import DatasetError, read_dataset, write_dataset
from xarray.testing import assert_identical

PARAMS = {"mu": 51e3, "Jm": 120.0, "c": -0.053, "label": "test"}


def small_dataset() -> xr.Dataset:
    lam = np.linspace(1.0, 3.0, 7)
    return xr.Dataset(
        {"phi": ("stretch", np.sqrt(lam**-2 - lam**-8),
                 {"units": "1", "long_name": "normalised voltage"}),
         "mode": ("stretch", np.array(["a"] * 7, dtype=object), {"long_name": "mode label"})},
        coords={"stretch": ("stretch", lam, {"units": "1", "long_name": "stretch of circle A"})},
    )


def write(tmp_path, **kw):
    return write_dataset(small_dataset(), "example", title="t", summary="s",
                         parameters=PARAMS, out_dir=tmp_path, command="pytest", **kw)


def test_round_trip_is_identical_including_attributes(tmp_path):
    path = write(tmp_path)
    back = read_dataset("example", data_dir=tmp_path)
    with xr.open_dataset(path) as raw:
        assert_identical(back, raw.load())
    # the writer adds only the ACDD coverage_content_type to each variable's attributes
    added = back[["phi", "mode"]].drop_attrs(deep=False)
    for name in [*added.data_vars, *added.coords]:
        assert added[name].attrs.pop("coverage_content_type")
    assert_identical(added, small_dataset().drop_attrs(deep=False))


def test_provenance_attributes_are_recorded(tmp_path):
    back = read_dataset(write(tmp_path))
    assert back.attrs["Conventions"] == "CF-1.10, ACDD-1.3"
    assert json.loads(back.attrs["parameters"]) == PARAMS
    assert back.attrs["param_Jm"] == 120.0
    assert "numpy" in json.loads(back.attrs["package_versions"])
    assert back.attrs["command"] == "pytest"
    assert back.attrs["git_commit"]
    manifest = datasets.read_manifest(tmp_path)
    assert manifest["example.nc"]["sha256"] == datasets.sha256(tmp_path / "example.nc")


def test_tampered_file_is_rejected(tmp_path):
    path = write(tmp_path)
    with xr.open_dataset(path) as ds:
        tampered = ds.load()
    tampered["phi"] = tampered["phi"] * 1.001
    tampered.to_netcdf(path)  # bypasses the writer: checksum no longer matches
    with pytest.raises(DatasetError, match="does not match manifest"):
        read_dataset(path)


def test_file_missing_from_manifest_is_rejected(tmp_path):
    path = write(tmp_path)
    (tmp_path / datasets.MANIFEST_NAME).unlink()
    with pytest.raises(DatasetError, match="not listed"):
        read_dataset(path)


def test_missing_variable_attribute_is_rejected_on_write(tmp_path):
    ds = small_dataset()
    del ds["phi"].attrs["units"]
    with pytest.raises(DatasetError, match="'phi' lacks required attribute 'units'"):
        write_dataset(ds, "bad", title="t", summary="s", parameters={}, out_dir=tmp_path)
    assert not (tmp_path / "bad.nc").exists()


def test_missing_global_attribute_is_rejected_on_read(tmp_path):
    path = write(tmp_path)
    with xr.open_dataset(path) as ds:
        stripped = ds.load()
    del stripped.attrs["references"]
    stripped.to_netcdf(path)
    files = datasets.read_manifest(tmp_path)
    files["example.nc"]["sha256"] = datasets.sha256(path)  # a consistent checksum ...
    manifest.write_manifest(tmp_path, files)
    with pytest.raises(DatasetError, match="global attribute 'references'"):
        read_dataset(path)  # ... but the provenance is incomplete


def test_curated_file_is_not_overwritten_without_flag(tmp_path):
    write(tmp_path)
    with pytest.raises(FileExistsError, match="overwrite=True"):
        write(tmp_path)
    write(tmp_path, overwrite=True)


def test_interrupted_write_leaves_old_file_intact(tmp_path, monkeypatch):
    path = write(tmp_path)
    before = path.read_bytes()

    def crash(self, target, *args, **kwargs):
        with open(target, "wb") as fh:  # a half-written temporary file ...
            fh.write(b"CDF\x01 half")
        raise KeyboardInterrupt("power cut")  # ... then the process dies

    monkeypatch.setattr(xr.Dataset, "to_netcdf", crash)
    with pytest.raises(KeyboardInterrupt):
        write(tmp_path, overwrite=True)
    monkeypatch.undo()
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir() if p.name != datasets.LOCK_NAME) == [
        datasets.MANIFEST_NAME, "example.nc"]
    read_dataset(path)  # still verifies


def test_bad_dataset_name_is_rejected(tmp_path):
    with pytest.raises(ValueError, match="must match"):
        write_dataset(small_dataset(), "Bad Name", title="t", summary="s", parameters={},
                      out_dir=tmp_path)


def test_curated_directory_verifies():
    """Every curated file in data/ matches its manifest checksum and carries provenance."""
    assert datasets.verify_directory() == []


def test_data_card_is_current():
    """data/README.md is generated from the curated files; regenerate with
    `debench report --datacard`."""
    from debench.reference import datacard

    assert (datasets.data_dir() / "README.md").read_text() == datacard.render()
