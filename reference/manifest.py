"""The manifest of a data directory, its lock and the recovery of interrupted writes: the
storage layer under the one dataset writer and reader (:mod:`debench.reference.datasets`,
whose module docstring gives the write protocol these pieces implement).

A directory's ``MANIFEST.json`` lists every dataset with its sha256 (``files``) and the
intent of a write under way (``pending``); it is replaced in one step
(:func:`write_manifest`), under the directory's ``flock`` lock (:func:`write_lock`), and
:func:`recover_locked` finishes or rolls back what a killed writer left.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import re
import secrets
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

import filelock

MANIFEST_NAME = "MANIFEST.json"
#: The inter-process lock of a data directory (kept: deleting a flock file races).
LOCK_NAME = ".MANIFEST.json.lock"
#: Seconds a writer (or a reader re-checking) waits for the directory lock. A write holds
#: it for one netCDF serialisation of a dataset of at most a few MB (well under a second);
#: minutes of waiting mean a hung process, which the error then names.
LOCK_TIMEOUT_S = 300.0
_SHA256 = re.compile(r"^[0-9a-f]{64}$")
#: Temporary files of the writer (any generation of it): ``.<name>[.<pid>.<hex>].tmp.nc``
#: and ``MANIFEST.json[.<pid>.<hex>].tmp``. Never data, never reported as unlisted.
_TEMP = re.compile(r"^(\.[^/]+\.tmp\.nc|MANIFEST\.json(\.[^/]+)?\.tmp)$")
#: The command that (re)creates the curated datasets.
WRITE_DATA_COMMAND = "debench reproduce --write-data"


class DatasetError(RuntimeError):
    """A dataset is malformed, tampered with, or missing from its manifest."""


class DatasetWriteError(DatasetError):
    """A write failed (disk full, directory not writable, lock not obtained).

    The message says which version of the file is in place afterwards; ``errno`` is that
    of the underlying :class:`OSError` (``None`` when there is none).
    """

    def __init__(self, message: str, errno: int | None = None):
        super().__init__(message)
        self.errno = errno


def sha256(path: Path) -> str:
    """The sha256 of a file (hex digest), read in 1 MiB blocks."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def is_temporary(name: str) -> bool:
    """Whether ``name`` is a writer's temporary file (stale unless a write is under way)."""
    return bool(_TEMP.match(name))


# --------------------------------------------------------------------------- durability
def fsync_file(path: Path) -> None:
    """Flush a written file to the disk."""
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def fsync_dir(directory: Path) -> None:
    """Make a rename durable; not every platform can open a directory (then skip)."""
    try:
        fd = os.open(directory, os.O_RDONLY)
    except OSError:
        return
    try:
        with contextlib.suppress(OSError):
            os.fsync(fd)
    finally:
        os.close(fd)


def unique_path(directory: Path, stem: str, suffix: str) -> Path:
    """A name no other writer uses: ``<stem>.<pid>.<random hex><suffix>`` in ``directory``."""
    return directory / f"{stem}.{os.getpid()}.{secrets.token_hex(4)}{suffix}"


# --------------------------------------------------------------------------- lock
@contextlib.contextmanager
def write_lock(directory: Path) -> Iterator[None]:
    """The directory's lock for a writer; :class:`DatasetWriteError` when not obtained."""
    lock = filelock.FileLock(str(directory / LOCK_NAME), timeout=LOCK_TIMEOUT_S)
    try:
        lock.acquire()
    except filelock.Timeout as exc:
        raise DatasetWriteError(
            f"{directory}: another writer has held {LOCK_NAME} for more than "
            f"{LOCK_TIMEOUT_S:g} s; nothing was written") from exc
    except OSError as exc:
        raise DatasetWriteError(
            f"{directory}: cannot lock the directory for writing ({exc.strerror or exc}); "
            "nothing was written", exc.errno) from exc
    try:
        yield
    finally:
        lock.release()


@contextlib.contextmanager
def reader_lock(directory: Path) -> Iterator[bool]:
    """The lock for a reader's second look: ``True`` when held, ``False`` when the
    directory cannot be locked (read-only install), in which case the read goes on."""
    lock = filelock.FileLock(str(directory / LOCK_NAME), timeout=LOCK_TIMEOUT_S)
    try:
        lock.acquire()
        held = True
    except (OSError, filelock.Timeout):
        held = False
    try:
        yield held
    finally:
        if held:
            lock.release()


# --------------------------------------------------------------------------- manifest
def _validate_entries(path: Path, files: Any, section: str) -> dict[str, dict[str, Any]]:
    if not isinstance(files, dict):
        raise DatasetError(f"{path}: malformed manifest ({section!r} is not an object)")
    for fname, meta in files.items():
        if not isinstance(meta, dict) or "sha256" not in meta:
            raise DatasetError(f"{path}: the entry of {fname} has no sha256; "
                               f"regenerate it with `{WRITE_DATA_COMMAND}`")
        if not isinstance(meta["sha256"], str) or not _SHA256.match(meta["sha256"]):
            raise DatasetError(f"{path}: the entry of {fname} has a malformed sha256 "
                               f"{meta['sha256']!r} (64 lower-case hex digits expected)")
    return files


def read_body(directory: Path) -> tuple[dict[str, dict[str, Any]], dict[str, dict[str, Any]]]:
    """``(files, pending)`` of a directory's manifest (both empty when there is none)."""
    path = Path(directory) / MANIFEST_NAME
    try:
        text = path.read_text()
    except FileNotFoundError:
        return {}, {}
    try:
        body = json.loads(text)
        files = body["files"]
    except (json.JSONDecodeError, KeyError, TypeError) as exc:
        raise DatasetError(f"{path}: malformed manifest ({exc})") from exc
    return (_validate_entries(path, files, "files"),
            _validate_entries(path, body.get("pending", {}), "pending"))


def write_manifest(directory: Path, files: Mapping[str, Mapping[str, Any]],
                    pending: Mapping[str, Mapping[str, Any]] | None = None) -> None:
    """Replace the manifest in one step: unique temporary file, fsync, rename."""
    directory = Path(directory)
    body: dict[str, Any] = {
        "description": "sha256 of every curated debench dataset in this directory",
        "files": {k: dict(files[k]) for k in sorted(files)}}
    if pending:
        body["pending"] = {k: dict(pending[k]) for k in sorted(pending)}
    tmp = unique_path(directory, MANIFEST_NAME, ".tmp")
    try:
        with open(tmp, "w") as fh:
            fh.write(json.dumps(body, indent=2, sort_keys=True) + "\n")
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, directory / MANIFEST_NAME)
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise
    fsync_dir(directory)


def recover_locked(directory: Path) -> list[str]:
    """Finish or roll back interrupted writes and remove stale temporaries (lock held)."""
    actions: list[str] = []
    files, pending = read_body(directory)
    for fname, meta in sorted(pending.items()):
        final = directory / fname
        if final.exists() and sha256(final) == meta["sha256"]:
            files[fname] = {k: v for k, v in meta.items() if k != "temp"}
            actions.append(f"{fname}: completed an interrupted write (new version listed)")
        else:
            actions.append(f"{fname}: rolled back an interrupted write (previous version kept)")
    if pending:
        write_manifest(directory, files)
    for path in sorted(directory.iterdir()):
        if is_temporary(path.name):
            with contextlib.suppress(FileNotFoundError):
                path.unlink()
            actions.append(f"{path.name}: removed a stale temporary file")
    return actions
