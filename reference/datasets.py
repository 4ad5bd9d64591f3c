"""One writer and one reader for debench netCDF datasets.

Convention (every chapter uses it, nothing else writes ``.nc`` files):

* Global attributes follow CF-1.10 and ACDD-1.3: ``Conventions``, ``title``,
  ``summary``, ``references``, ``history``, ``source``, ``date_created``,
  ``creator_name``, ``license``, ``keywords``, the discovery attributes of
  :func:`debench.reference.standards.acdd_attributes` (``id``, ``institution``,
  ``publisher_*``, ``project``, ``processing_level``, ...), plus debench provenance: ``git_commit``,
  ``package_versions`` (JSON), ``command`` and ``parameters`` (JSON of the model
  parameters; each scalar also as ``param_<name>``).
* Every data variable and every coordinate carries ``long_name`` and
  ``coverage_content_type``; every numeric one carries ``units`` (UDUNITS strings, ``"1"``
  for dimensionless). Coordinate variables carry no ``_FillValue`` (CF 2.5.1).
* Files are listed in ``MANIFEST.json`` of their directory with a sha256. Reading a file
  verifies the checksum and the required attributes and raises :class:`DatasetError`
  otherwise. A curated file is never overwritten unless ``overwrite=True``.

Writes: one step seen from any reader
-------------------------------------
A dataset lives in two places, its file and its manifest entry, and no file system
replaces two files in one step. The writer therefore commits in two phases with the
intent recorded first, all under an inter-process lock on the directory
(``LOCK_NAME``, a ``flock`` lock through ``filelock``, released by the kernel when a
writer dies, so a ``kill -9`` never leaves the directory locked):

1. *Recover*: finish or roll back what a killed writer left (see :func:`recover`) and
   remove stale temporary files. Under the lock no other writer is active, so every
   temporary file found is stale.
2. *Write* the data to a unique temporary file ``.<name>.<pid>.<random>.tmp.nc`` in the
   same directory, ``fsync`` it, read it back and compare every numeric variable, and
   take its sha256.
3. *Intent*: record ``pending[<name>.nc] = {sha256, temp, ...}`` in the manifest.
4. *Install*: ``os.replace`` the temporary file over ``<name>.nc`` (atomic), ``fsync``
   the directory.
5. *Commit*: move the pending record to ``files`` in the manifest.

Every manifest update is itself write-new (unique name) -> ``fsync`` -> ``os.replace``,
so the manifest is never half-written. A reader accepts a file whose sha256 is the
listed one *or* the pending one, hence at every instant (a kill between any two steps
included) the file on disk is the old or the new version and verifies. A reader that
finds the manifest and the file disagree (a write completed between its two reads)
re-reads once under the lock, finishing an interrupted write on the way when it may
write the directory, before it fails. Readers take no lock otherwise, so a read-only
installed data directory reads as before.

The manifest, the lock, the durability steps and the recovery are
``debench.reference.manifest``; this module puts the protocol together.

Alternatives considered: per-file sidecar checksums with a manifest rebuilt from them
move the two-file problem to the sidecar and the data file; a lock with two plain
renames loses the old version when killed between them (the new file is then rejected
against the old checksum). The pending record closes that window.

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
import importlib.resources
import json
import os
import re
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
from debench.reference import __version__, manifest
from debench.reference.manifest import (
    LOCK_NAME,
    MANIFEST_NAME,
    WRITE_DATA_COMMAND,
    DatasetError,
    DatasetWriteError,
    is_temporary,
    sha256,
)
from debench.reference.provenance import command_line, git_commit, package_versions_json
from debench.reference.standards import acdd_attributes, coverage_content_type

__all__ = [
    "CONVENTIONS", "DATA_DIR_ENV", "LOCK_NAME", "MANIFEST_NAME", "REQUIRED_GLOBAL_ATTRS",
    "REQUIRED_NUMERIC_ATTRS", "REQUIRED_VARIABLE_ATTRS", "THESIS_REFERENCE",
    "WRITE_DATA_COMMAND", "DataProblem", "DatasetError", "DatasetWriteError",
    "check_attributes", "data_dir", "dataset_parameters", "is_temporary", "read_dataset",
    "read_manifest", "recover", "sha256", "variable_attrs", "verify_directory",
    "write_dataset",
]

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


@dataclass(frozen=True)
class DataProblem:
    """One problem with a data directory, as ``debench verify`` reports it.

    Attributes
    ----------
    file
        The file concerned (a name inside the directory, or the directory itself).
    reason
        What is wrong, and where it says so, how to fix it.
    kind
        Always ``"data"`` (distinguishes these records from catalogue entries).
    """

    file: str
    reason: str
    kind: str = "data"

    def __str__(self) -> str:
        return f"{self.file}: {self.reason}"

    def as_json(self) -> dict[str, Any]:
        """The record ``debench verify --json`` appends to its array of entries."""
        return {"kind": self.kind, "id": f"data:{self.file}", "file": self.file,
                "reason": self.reason}

    @classmethod
    def coerce(cls, problem: DataProblem | str) -> DataProblem:
        """A record from a record or from a ``"<file>.nc: reason"`` line."""
        if isinstance(problem, DataProblem):
            return problem
        match = re.match(r"^(\S+\.nc):? (.*)$", problem, flags=re.DOTALL)
        return cls(match[1], match[2]) if match else cls("", problem)


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
            f"data_dir= to read another directory); `{WRITE_DATA_COMMAND}` "
            "regenerates the curated datasets from a source checkout")


# --------------------------------------------------------------------------- manifest
def read_manifest(directory: Path) -> dict[str, dict[str, Any]]:
    """The committed entries of a directory's manifest, ``{file name: metadata}``.

    Every entry has a ``sha256``; an entry without one raises :class:`DatasetError`
    naming the file.
    """
    return manifest.read_body(directory)[0]


def recover(directory: Path | None = None) -> list[str]:
    """Finish or roll back writes that a killed process left, and clean stale temporaries.

    A write killed after its intent was recorded is completed when the new file is in
    place (its checksum matches the pending record) and rolled back otherwise; every
    temporary file is removed. Writers do this before each write; call it to tidy a
    directory by hand. Returns what was done, one line per action.
    """
    directory = Path(directory) if directory is not None else data_dir()
    if not directory.is_dir():
        return []
    with manifest.write_lock(directory):
        return manifest.recover_locked(directory)


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
def variable_attrs(long_name: str, units: str = "1", atol: float | None = None,
                   rtol: float | None = None, **extra) -> dict:
    """CF attributes of a dataset variable: ``long_name``, ``units``, any ``extra`` ones, and
    the accuracy a regeneration is held to (``accuracy_atol`` / ``accuracy_rtol``, read by
    ``debench.reference.regeneration.regeneration_tolerance``) when given."""
    out = {"long_name": long_name, "units": units, **extra}
    if atol is not None:
        out["accuracy_atol"] = atol
    if rtol is not None:
        out["accuracy_rtol"] = rtol
    return out


def _with_provenance(ds: xr.Dataset, name: str, *, now: str, command: str, title: str,
                     summary: str, references: str, keywords: str,
                     parameters: Mapping[str, Any]) -> xr.Dataset:
    """A copy of ``ds`` with the global attributes of the convention (CF, ACDD, debench
    provenance, ``param_<name>`` per parameter), every variable's
    ``coverage_content_type`` and no ``_FillValue`` on a coordinate variable; checked."""
    out = ds.copy()
    out.attrs.update({
        "Conventions": CONVENTIONS,
        "title": title,
        "summary": summary,
        "references": references,
        "source": f"debench {__version__} (models + reference packages)",
        "history": f"{now} created by: {command}",
        "date_created": now,
        "creator_name": "debench developers",
        "license": "CC-BY-4.0",
        "keywords": keywords,
        "git_commit": git_commit(),
        "package_versions": package_versions_json(),
        "command": command,
        "parameters": json.dumps(dict(parameters), sort_keys=True, default=str),
        **acdd_attributes(name, now),
    })
    for key, value in parameters.items():
        out.attrs[f"param_{key}"] = _scalar_attr(value)
    for vname, var in out.variables.items():
        var.attrs.setdefault("coverage_content_type",
                             coverage_content_type(vname, is_coordinate=vname in out.coords))
        if vname in out.dims and np.issubdtype(var.dtype, np.floating):
            var.encoding["_FillValue"] = None  # CF 2.5.1: never on a coordinate variable
    check_attributes(out)
    return out


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
    """Write ``ds`` to ``<out_dir>/<name>.nc`` with full provenance, atomically with its
    manifest entry (the protocol is in the module docstring).

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

    Raises
    ------
    FileExistsError
        The file exists and ``overwrite`` is false (checked under the lock, so of two
        concurrent writers of a new dataset exactly one succeeds).
    DatasetError
        ``ds`` lacks a required attribute, or the read-back differs.
    DatasetWriteError
        The disk is full, the directory is not writable, or the lock was not obtained;
        the message says which version of the file is in place (the previous one unless
        the failure came after the new file was installed).
    """
    if not _NAME.match(name):
        raise ValueError(f"dataset name {name!r} must match {_NAME.pattern}")
    out_dir = Path(out_dir) if out_dir is not None else data_dir()
    check_attributes(ds, require_global=False)

    now = _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat()
    cmd = command if command is not None else command_line()
    out = _with_provenance(ds, name, now=now, command=cmd, title=title, summary=summary,
                           references=references, keywords=keywords, parameters=parameters)

    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise DatasetWriteError(f"cannot create the data directory {out_dir} "
                                f"({exc.strerror or exc}); nothing was written",
                                exc.errno) from exc
    path = out_dir / f"{name}.nc"
    with manifest.write_lock(out_dir):
        manifest.recover_locked(out_dir)
        if path.exists() and not overwrite:
            raise FileExistsError(f"{path} exists; pass overwrite=True to replace a curated file")
        meta = {"title": title, "command": cmd, "git_commit": out.attrs["git_commit"],
                "date_created": now}
        try:
            _install(out, path, meta)
        except BaseException as exc:
            _abandon(out_dir, path, meta, exc)
            raise  # _abandon raises for an OSError; anything else goes on as it was
    return path


def _install(out: xr.Dataset, path: Path, meta: dict[str, Any]) -> None:
    """Steps 2-5 of the write protocol (the directory lock is held)."""
    directory = path.parent
    tmp = manifest.unique_path(directory, f".{path.stem}", ".tmp.nc")
    meta["temp"] = tmp.name
    out.to_netcdf(tmp, engine="netcdf4")
    manifest.fsync_file(tmp)
    with xr.open_dataset(tmp, engine="netcdf4") as back:
        back.load()
    check_attributes(back)
    for var in out.data_vars:
        if _is_numeric(out[var]):
            try:
                np.testing.assert_array_equal(back[var].values, out[var].values)
            except AssertionError as exc:
                raise DatasetError(f"{path.name}: read-back of {var!r} differs from what "
                                   "was written; nothing was installed") from exc
    meta["sha256"] = manifest.sha256(tmp)
    meta["bytes"] = tmp.stat().st_size
    files, pending = manifest.read_body(directory)
    pending[path.name] = dict(meta)
    manifest.write_manifest(directory, files, pending)                   # 3. intent
    os.replace(tmp, path)                                        # 4. install
    manifest.fsync_dir(directory)
    files[path.name] = {k: v for k, v in meta.items() if k != "temp"}
    del pending[path.name]
    manifest.write_manifest(directory, files, pending)                   # 5. commit


def _abandon(directory: Path, path: Path, meta: dict[str, Any], exc: BaseException) -> None:
    """Clean up after a failed write (lock held) and say what is left in place."""
    with contextlib.suppress(Exception):  # best effort: the next writer recovers anyway
        manifest.recover_locked(directory)
    if isinstance(exc, DatasetError) or not isinstance(exc, OSError | RuntimeError):
        return  # already clear (or an interrupt): re-raised as it is
    installed = "sha256" in meta and path.exists() and manifest.sha256(path) == meta["sha256"]
    state = ("the new version was installed" if installed else
             "the previous version is intact" if path.exists() else "no file was left")
    raise DatasetWriteError(
        f"cannot write {path.name} into {directory}: {getattr(exc, 'strerror', None) or exc}; "
        f"{state} and temporary files were removed", getattr(exc, "errno", None)) from exc


def _accepted_checksums(fname: str, files: Mapping[str, Any], pending: Mapping[str, Any]
                        ) -> list[str]:
    return [section[fname]["sha256"] for section in (files, pending) if fname in section]


def _identity(path: Path) -> tuple[int, int, int]:
    st = path.stat()
    return st.st_ino, st.st_size, st.st_mtime_ns


def _read_verified(path: Path) -> tuple[xr.Dataset, bool]:
    """One verified read: listed checksum, unchanged file while read, attributes.

    Returns the dataset and whether it matched only the checksum of a pending write.
    """
    try:
        before = _identity(path)
    except FileNotFoundError:
        raise DatasetError(f"{path.name}: no such dataset; "
                           f"{_missing_data_hint(path.parent)}") from None
    files, pending = manifest.read_body(path.parent)
    accepted = _accepted_checksums(path.name, files, pending)
    if not accepted:
        raise DatasetError(f"{path.name} is not listed in {path.parent / MANIFEST_NAME}")
    actual = manifest.sha256(path)
    if actual not in accepted:
        raise DatasetError(
            f"{path.name}: sha256 {actual[:12]}… does not match manifest {accepted[0][:12]}… "
            "(file modified or half-written)")
    pending = actual != accepted[0] or path.name not in files
    key = (str(path.resolve()), actual)
    if key in _VERIFIED:               # the same bytes, verified before: a private copy
        return _VERIFIED[key].copy(deep=True), pending
    with xr.open_dataset(path, engine="netcdf4") as ds:
        ds = ds.load()
    if _identity(path) != before:
        raise DatasetError(f"{path.name}: replaced while being read")
    check_attributes(ds)
    _VERIFIED[key] = ds.copy(deep=True)
    return ds, pending


_VERIFIED: dict[tuple[str, str], xr.Dataset] = {}
"""Datasets already read and verified in this process, keyed on (resolved path, sha256 of
the file's bytes): a later read of the same bytes (its checksum is recomputed and checked
against the manifest every time) returns a deep copy instead of parsing the netCDF file
again, so no caller sees another's modifications."""


@contextlib.contextmanager
def _recovered(directory: Path) -> Iterator[None]:
    """Hold the directory lock (when the directory allows it: else go on unlocked), finish
    any interrupted write, and keep the lock for the body: no writer replaces a file
    while the body reads it. Never fails a read."""
    with manifest.reader_lock(directory) as locked:
        if locked:
            with contextlib.suppress(OSError, DatasetError):  # lockable, not writable
                manifest.recover_locked(directory)
        yield


def _tidy(directory: Path) -> None:
    """Recover under the lock when the directory allows it; never fails a read."""
    with _recovered(directory):
        pass


def read_dataset(name: str | Path, *, data_dir: Path | None = None,
                 verify: bool = True) -> xr.Dataset:
    """Read a dataset, verifying its manifest checksum and required attributes.

    ``name`` is a stem (``"ch3_voltage_stretch"``) looked up in ``data_dir`` or a path.
    Raises :class:`DatasetError` if the file is not in the manifest, its checksum differs
    (tampered or half-written), or a required attribute is missing. When the first look
    fails, the read is repeated once holding the directory lock, after finishing any
    interrupted write (when the directory is writable): a write that completed between
    reading the manifest and reading the file is not an error. A file accepted through
    the checksum of an interrupted write gets its manifest entry completed the same way.
    """
    path = Path(name)
    if path.suffix != ".nc":
        path = (Path(data_dir) if data_dir is not None else globals()["data_dir"]()) / f"{name}.nc"
    if not verify:
        if not path.exists():
            raise DatasetError(f"{path.name}: no such dataset; "
                               f"{_missing_data_hint(path.parent)}")
        with xr.open_dataset(path, engine="netcdf4") as ds:
            return ds.load()
    if not path.exists():
        raise DatasetError(f"{path.name}: no such dataset; {_missing_data_hint(path.parent)}")
    try:
        ds, pending = _read_verified(path)
    except DatasetError:
        with _recovered(path.parent):       # the second look: no writer can interleave
            ds, pending = _read_verified(path)
    if pending:  # a write was interrupted between installing and listing: list it
        _tidy(path.parent)
    return ds


def dataset_parameters(ds: xr.Dataset) -> dict[str, Any]:
    """The model parameters a dataset was produced with."""
    return json.loads(ds.attrs["parameters"])


def _problem(fname: str, exc: Exception) -> DataProblem:
    """A record whose reason is the error message without its leading file name."""
    text = str(exc)
    if text.startswith(fname):
        text = text[len(fname):].lstrip(": ")
    return DataProblem(fname, text)


def verify_directory(directory: Path | None = None) -> list[DataProblem]:
    """Problems with the datasets of a directory (empty list when all verify).

    Each problem is a :class:`DataProblem` (``str()`` gives ``"file: reason"``). A
    missing directory, a directory without datasets and an empty manifest are problems
    (the fix is ``debench reproduce --write-data``); a writer's temporary files are not
    data and are never reported.
    """
    directory = Path(directory) if directory is not None else data_dir()
    fix = f"run `{WRITE_DATA_COMMAND}` to create the curated datasets"
    if not directory.is_dir():
        return [DataProblem(str(directory), f"data directory does not exist; {fix}")]
    try:
        files, pending = manifest.read_body(directory)
    except DatasetError as exc:
        return [_problem(str(directory / MANIFEST_NAME), exc)]
    on_disk = sorted(p.name for p in directory.glob("*.nc") if not is_temporary(p.name))
    # a pending entry whose file is not installed yet is not data (yet)
    listed = sorted(set(files) | (set(pending) & set(on_disk)))
    if not listed and not on_disk:
        what = "has no MANIFEST.json" if not (directory / MANIFEST_NAME).exists() \
            else "has a manifest that lists no dataset"
        return [DataProblem(str(directory), f"no datasets: the directory {what}; {fix}")]
    problems: list[DataProblem] = []
    for fname in listed:
        try:
            read_dataset(directory / fname)
        except DatasetError as exc:
            problems.append(_problem(fname, exc))
    listed_now = set(read_manifest(directory)) | set(manifest.read_body(directory)[1])
    problems += [DataProblem(f, "is not listed in the manifest")
                 for f in on_disk if f not in listed_now]
    return problems
