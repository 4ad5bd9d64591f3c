"""One writer and one reader for debench netCDF datasets.

Convention (every chapter uses it, nothing else writes ``.nc`` files):

* Global attributes follow CF-1.10 and ACDD-1.3: ``Conventions``, ``title``,
  ``summary``, ``references``, ``history``, ``source``, ``date_created``,
  ``creator_name``, ``license``, ``keywords``, plus debench provenance: ``git_commit``,
  ``package_versions`` (JSON), ``command`` and ``parameters`` (JSON of the model
  parameters; each scalar also as ``param_<name>``).
* Every data variable and every coordinate carries ``long_name``; every numeric one
  carries ``units`` (UDUNITS strings, ``"1"`` for dimensionless).
* Files are listed in ``MANIFEST.json`` of their directory with a sha256. Reading a file
  verifies the checksum and the required attributes and raises :class:`DatasetError`
  otherwise.
* Writes are atomic: write a temporary file in the same directory, read it back and
  compare, then ``os.replace``. A curated file is never overwritten unless
  ``overwrite=True``.

Examples
--------
>>> import numpy as np, xarray as xr
>>> ds = xr.Dataset(
...     {"phi": ("stretch", np.zeros(3), {"units": "1", "long_name": "normalised voltage"})},
...     coords={"stretch": ("stretch", [1.0, 2.0, 3.0],
...                         {"units": "1", "long_name": "stretch of circle A"})})
>>> path = write_dataset(ds, "example", title="t", summary="s", references="r",
...                      parameters={"mu": 51e3}, out_dir=tmp_path)  # doctest: +SKIP
>>> read_dataset("example", data_dir=tmp_path)  # doctest: +SKIP
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import hashlib
import importlib.resources
import json
import os
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
from debench.reference import __version__
from debench.reference.provenance import command_line, git_commit, package_versions_json

MANIFEST_NAME = "MANIFEST.json"
CONVENTIONS = "CF-1.10, ACDD-1.3"
THESIS_REFERENCE = (
    "Zeng, C. (2020). Deformation and stability of dielectric elastomer films used in "
    "actuators. PhD dissertation, The University of Akron."
)
REQUIRED_GLOBAL_ATTRS = (
    "Conventions", "title", "summary", "references", "history", "source", "date_created",
    "creator_name", "license", "git_commit", "package_versions", "command", "parameters",
)
REQUIRED_VARIABLE_ATTRS = ("long_name",)
REQUIRED_NUMERIC_ATTRS = ("units",)
_NAME = re.compile(r"^[a-z0-9][a-z0-9_]*$")


class DatasetError(RuntimeError):
    """A dataset is malformed, tampered with, or missing from its manifest."""


#: Environment variable that overrides where the curated datasets are read and written.
DATA_DIR_ENV = "DEBENCH_DATA_DIR"


def data_dir() -> Path:
    """The curated data directory.

    ``$DEBENCH_DATA_DIR`` when set, else the datasets shipped with the package
    (``debench.data``: the clone's ``data/`` in an editable install, the installed copy
    otherwise). Every reader and writer takes an explicit ``data_dir``/``out_dir`` too.
    """
    env = os.environ.get(DATA_DIR_ENV)
    if env:
        return Path(env)
    return Path(str(importlib.resources.files("debench.data")))


def _missing_data_hint(directory: Path) -> str:
    return (f"looked in {directory} (the packaged data; set ${DATA_DIR_ENV} or pass "
            "data_dir= to read another directory); `debench reproduce --write-data` "
            "regenerates the curated datasets from a source checkout")


def sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


# --------------------------------------------------------------------------- manifest
def read_manifest(directory: Path) -> dict[str, dict[str, Any]]:
    path = Path(directory) / MANIFEST_NAME
    if not path.exists():
        return {}
    try:
        return json.loads(path.read_text())["files"]
    except (json.JSONDecodeError, KeyError) as exc:
        raise DatasetError(f"{path}: malformed manifest ({exc})") from exc


def _write_manifest(directory: Path, files: Mapping[str, Mapping[str, Any]]) -> None:
    path = Path(directory) / MANIFEST_NAME
    tmp = path.with_name(path.name + ".tmp")
    body = {"description": "sha256 of every curated debench dataset in this directory",
            "files": {k: dict(files[k]) for k in sorted(files)}}
    tmp.write_text(json.dumps(body, indent=2, sort_keys=True) + "\n")
    os.replace(tmp, path)


# --------------------------------------------------------------------------- validation
def _is_numeric(var: xr.DataArray) -> bool:
    return np.issubdtype(var.dtype, np.number) or np.issubdtype(var.dtype, np.bool_)


def check_attributes(ds: xr.Dataset, *, require_global: bool = True) -> None:
    """Raise :class:`DatasetError` naming the first missing required attribute."""
    for name, var in {**ds.coords, **ds.data_vars}.items():
        required = REQUIRED_VARIABLE_ATTRS + (REQUIRED_NUMERIC_ATTRS if _is_numeric(var) else ())
        for attr in required:
            if attr not in var.attrs or var.attrs[attr] in ("", None):
                raise DatasetError(f"variable {name!r} lacks required attribute {attr!r}")
    if require_global:
        for attr in REQUIRED_GLOBAL_ATTRS:
            if attr not in ds.attrs or ds.attrs[attr] in ("", None):
                raise DatasetError(f"dataset lacks required global attribute {attr!r}")


def _scalar_attr(value: Any) -> Any:
    if isinstance(value, bool | np.bool_):
        return int(value)
    if isinstance(value, int | float | str | np.integer | np.floating):
        return value
    return json.dumps(value, default=str)


# --------------------------------------------------------------------------- write / read
def write_dataset(
    ds: xr.Dataset,
    name: str,
    *,
    title: str,
    summary: str,
    references: str = THESIS_REFERENCE,
    parameters: Mapping[str, Any],
    command: str | None = None,
    keywords: str = "dielectric elastomer, electroelasticity, verification benchmark",
    out_dir: Path | None = None,
    overwrite: bool = False,
) -> Path:
    """Write ``ds`` to ``<out_dir>/<name>.nc`` atomically with full provenance.

    Parameters
    ----------
    ds
        The data. Every variable and coordinate must have ``long_name`` and, if numeric,
        ``units``.
    name
        File stem, lower case ``[a-z0-9_]``; by convention ``ch3_...``, ``ch4_...``.
    parameters
        Model parameters that produced the data (stored as JSON and as ``param_*``).
    overwrite
        Replace an existing file. Curated files are never replaced silently.

    Returns
    -------
    Path of the written file. Its sha256 is recorded in the directory's manifest.
    """
    if not _NAME.match(name):
        raise ValueError(f"dataset name {name!r} must match {_NAME.pattern}")
    out_dir = Path(out_dir) if out_dir is not None else data_dir()
    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / f"{name}.nc"
    if path.exists() and not overwrite:
        raise FileExistsError(f"{path} exists; pass overwrite=True to replace a curated file")
    check_attributes(ds, require_global=False)

    now = _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat()
    cmd = command if command is not None else command_line()
    out = ds.copy()
    out.attrs.update({
        "Conventions": CONVENTIONS,
        "title": title,
        "summary": summary,
        "references": references,
        "source": f"debench {__version__} (models + reference packages)",
        "history": f"{now} created by: {cmd}",
        "date_created": now,
        "creator_name": "debench developers",
        "license": "CC-BY-4.0",
        "keywords": keywords,
        "git_commit": git_commit(),
        "package_versions": package_versions_json(),
        "command": cmd,
        "parameters": json.dumps(dict(parameters), sort_keys=True, default=str),
    })
    for key, value in parameters.items():
        out.attrs[f"param_{key}"] = _scalar_attr(value)
    check_attributes(out)

    tmp = path.with_name(f".{name}.tmp.nc")
    try:
        out.to_netcdf(tmp, engine="netcdf4")
        with xr.open_dataset(tmp, engine="netcdf4") as back:
            back.load()
        check_attributes(back)
        for var in out.data_vars:
            if _is_numeric(out[var]):
                np.testing.assert_array_equal(back[var].values, out[var].values,
                                              err_msg=f"read-back of {var!r} differs")
        digest = sha256(tmp)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()
        raise
    files = read_manifest(out_dir)
    files[path.name] = {"sha256": digest, "bytes": path.stat().st_size,
                        "title": title, "command": cmd, "git_commit": out.attrs["git_commit"],
                        "date_created": now}
    _write_manifest(out_dir, files)
    return path


def read_dataset(name: str | Path, *, data_dir: Path | None = None,
                 verify: bool = True) -> xr.Dataset:
    """Read a dataset, verifying its manifest checksum and required attributes.

    ``name`` is a stem (``"ch3_voltage_stretch"``) looked up in ``data_dir`` or a path.
    Raises :class:`DatasetError` if the file is not in the manifest, its checksum differs
    (tampered or half-written), or a required attribute is missing.
    """
    path = Path(name)
    if path.suffix != ".nc":
        path = (Path(data_dir) if data_dir is not None else globals()["data_dir"]()) / f"{name}.nc"
    if not path.exists():
        raise DatasetError(f"{path.name}: no such dataset; {_missing_data_hint(path.parent)}")
    if verify:
        files = read_manifest(path.parent)
        if path.name not in files:
            raise DatasetError(f"{path.name} is not listed in {path.parent / MANIFEST_NAME}")
        expected = files[path.name]["sha256"]
        actual = sha256(path)
        if actual != expected:
            raise DatasetError(
                f"{path.name}: sha256 {actual[:12]}… does not match manifest {expected[:12]}… "
                "(file modified or half-written)")
    with xr.open_dataset(path, engine="netcdf4") as ds:
        ds = ds.load()
    if verify:
        check_attributes(ds)
    return ds


def dataset_parameters(ds: xr.Dataset) -> dict[str, Any]:
    """The model parameters a dataset was produced with."""
    return json.loads(ds.attrs["parameters"])


def verify_directory(directory: Path | None = None) -> list[str]:
    """Problems with the datasets of a directory (empty list when all verify)."""
    directory = Path(directory) if directory is not None else data_dir()
    problems: list[str] = []
    files = read_manifest(directory)
    for fname in sorted(files):
        try:
            read_dataset(directory / fname)
        except DatasetError as exc:
            problems.append(str(exc))
    for path in sorted(directory.glob("*.nc")):
        if path.name not in files:
            problems.append(f"{path.name} is not listed in the manifest")
    return problems
