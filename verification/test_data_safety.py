"""No write loses data: kills, concurrent writers, full disk, read-only directories.

The claim (DESIGN.md, "Data carries provenance"; ``debench.reference.datasets``): a dataset
and its manifest entry change in one step seen from any reader. Whatever happens to a
writer, the file on disk is the previous or the new version, it reads back verified, and
the manifest lists it with a matching sha256. Writers are real processes (forked, so the
imports are paid once) killed with SIGKILL, not mocks; only the failures a test cannot
provoke for real (a full disk, a directory that root can still write) are simulated.
"""

from __future__ import annotations

import errno
import json
import multiprocessing
import os
import random
import signal
import stat
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from debench.reference import datasets, manifest
from debench.reference.datasets import (
    DatasetError,
    DatasetWriteError,
    read_dataset,
    read_manifest,
    verify_directory,
    write_dataset,
)

if "fork" not in multiprocessing.get_all_start_methods():  # pragma: no cover - Windows
    pytest.skip("the process tests fork writers", allow_module_level=True)

FORK = multiprocessing.get_context("fork")
#: Random kills: how many (default run, ``--full``), and the seed that fixes their moments.
N_RANDOM_KILLS, N_RANDOM_KILLS_FULL = 20, 200
KILL_SEED = 20261122
#: Longest random delay before the kill, s: a few writes of the small test dataset
#: (about 20-50 ms each here), so kills land in every phase of a write.
MAX_KILL_DELAY_S = 0.25
#: Concurrent writers of different datasets, and datasets each: 8 x 6 = 48 entries in the
#: default run (about 6 s: the lock serialises the writes), 8 x 12 = 96 with ``--full``.
N_WRITERS, N_PER_WRITER, N_PER_WRITER_FULL = 8, 6, 12
#: Seconds any forked writer may take before the test calls it hung (a write takes well
#: under a second; the lock serialises at most 96 of them).
JOIN_TIMEOUT_S = 120.0
KILLED = -signal.SIGKILL


def dataset(version: float) -> xr.Dataset:
    """A small dataset whose every value is ``version`` (so a read names its version)."""
    lam = np.linspace(1.0, 3.0, 7)
    return xr.Dataset(
        {"phi": ("stretch", np.full(7, float(version)),
                 {"units": "1", "long_name": "version marker"})},
        coords={"stretch": ("stretch", lam, {"units": "1", "long_name": "stretch"})})


def write(directory: Path, version: float, name: str = "example", **kw) -> Path:
    kw.setdefault("overwrite", True)
    return write_dataset(dataset(version), name, title="t", summary="s",
                         parameters={"version": version}, out_dir=directory,
                         command="pytest", **kw)


def version_of(directory: Path, name: str = "example") -> float:
    """The version a reader sees; raises if the file does not verify."""
    phi = read_dataset(name, data_dir=directory)["phi"].values
    assert np.all(phi == phi[0]), "a mixture of two versions"
    return float(phi[0])


def assert_listed_and_verified(directory: Path) -> None:
    """Every dataset verifies and is listed with the sha256 of the file on disk."""
    assert verify_directory(directory) == []
    files = read_manifest(directory)
    for path in directory.glob("*.nc"):
        if not datasets.is_temporary(path.name):
            assert files[path.name]["sha256"] == datasets.sha256(path), path.name


def temporaries(directory: Path) -> list[str]:
    return sorted(p.name for p in directory.iterdir() if datasets.is_temporary(p.name))


@pytest.fixture(autouse=True)
def _no_orphans():
    """Kill every writer a test started, whatever the test's outcome."""
    yield
    for proc in multiprocessing.active_children():
        proc.kill()
        proc.join()


def run(target, *args) -> multiprocessing.Process:
    proc = FORK.Process(target=target, args=args, daemon=True)
    proc.start()
    return proc


def join(proc: multiprocessing.Process) -> int:
    proc.join(JOIN_TIMEOUT_S)
    if proc.is_alive():  # pragma: no cover - a hang is a failure, not a wait
        proc.kill()
        proc.join()
        pytest.fail("a writer process hung")
    return proc.exitcode


# --------------------------------------------------------------------------- kill -9
def _die() -> None:
    os.kill(os.getpid(), signal.SIGKILL)


def _write_and_die_at(directory: Path, step: str) -> None:
    """Child: write version 2 and SIGKILL itself at ``step`` of the write protocol."""
    real_replace = os.replace
    calls = {"n": 0}
    when, _, index = step.partition("_replace_")

    def replace(src, dst):
        calls["n"] += 1
        if when == "before" and calls["n"] == int(index):
            _die()
        real_replace(src, dst)
        if when == "after" and calls["n"] == int(index):
            _die()

    real_to_netcdf = xr.Dataset.to_netcdf

    def to_netcdf(self, path, *args, **kwargs):
        real_to_netcdf(self, path, *args, **kwargs)
        with open(path, "r+b") as fh:  # and then half of it again: a torn temporary
            fh.truncate(os.path.getsize(path) // 2)
        _die()

    os.replace = replace
    if step == "in_netcdf":
        xr.Dataset.to_netcdf = to_netcdf
    write(directory, 2.0)
    os._exit(0)  # pragma: no cover - every step kills first


#: The moments of a write (os.replace calls: 1 intent, 2 install, 3 commit) and the
#: version a reader must see after a kill there.
KILL_STEPS = {
    "in_netcdf": 1.0,          # the temporary file is half written
    "before_replace_1": 1.0,   # the manifest's new copy is written, not renamed
    "after_replace_1": 1.0,    # intent recorded, old file still in place
    "after_replace_2": 2.0,    # new file installed, manifest not yet committed
    "before_replace_3": 2.0,   # the same, with the committing manifest written
}


@pytest.mark.parametrize("step", list(KILL_STEPS))
@pytest.mark.parametrize("existing", [True, False], ids=["replace", "create"])
def test_kill_at_each_step_of_a_write_leaves_one_listed_version(tmp_path, step, existing):
    """SIGKILL at each step of the protocol: the file is the old or the new version,
    verifies and is listed; the next writer cleans up and writes normally."""
    if existing:
        write(tmp_path, 1.0)
    else:
        write(tmp_path, 0.0, name="other")  # the directory has a manifest already
    assert join(run(_write_and_die_at, tmp_path, step)) == KILLED
    expected = KILL_STEPS[step] if existing or KILL_STEPS[step] == 2.0 else None
    if expected is None:
        with pytest.raises(DatasetError, match="no such dataset"):
            version_of(tmp_path)
    else:
        assert version_of(tmp_path) == expected
    assert_listed_and_verified(tmp_path)
    write(tmp_path, 3.0)
    assert version_of(tmp_path) == 3.0
    assert temporaries(tmp_path) == []
    assert_listed_and_verified(tmp_path)


def _write_forever(directory: Path, started) -> None:
    version = 10.0
    while True:
        write(directory, version)
        started.set()
        version += 1.0


@pytest.mark.parametrize("n_kills", [
    N_RANDOM_KILLS, pytest.param(N_RANDOM_KILLS_FULL, marks=pytest.mark.slow)])
def test_kill_9_at_random_moments_never_loses_a_version(tmp_path, n_kills):
    """A writer rewriting one dataset in a loop is killed after a random delay, many
    times (fixed seed): each time the file verifies, is listed, and holds a version that
    was written (never a mixture, never nothing)."""
    rng = random.Random(KILL_SEED)
    write(tmp_path, 1.0)
    for trial in range(n_kills):
        started = FORK.Event()
        proc = run(_write_forever, tmp_path, started)
        assert started.wait(JOIN_TIMEOUT_S)
        time.sleep(rng.uniform(0.0, MAX_KILL_DELAY_S))
        proc.kill()
        assert join(proc) == KILLED
        seen = version_of(tmp_path)
        assert seen == 1.0 or (seen >= 10.0 and seen.is_integer()), (trial, seen)
        assert_listed_and_verified(tmp_path)
    datasets.recover(tmp_path)
    assert temporaries(tmp_path) == []


# --------------------------------------------------------------------------- concurrency
def _write_many(directory: Path, writer: int, per_writer: int, go) -> None:
    go.wait()
    for j in range(per_writer):
        write(directory, 100.0 * writer + j, name=f"w{writer}_{j:02d}")


@pytest.mark.parametrize("per_writer", [
    N_PER_WRITER, pytest.param(N_PER_WRITER_FULL, marks=pytest.mark.slow)])
def test_concurrent_writers_of_different_datasets_lose_no_entry(tmp_path, per_writer):
    """8 processes write their datasets into one directory at the same time: every
    entry is listed and verifies, each with the values its writer wrote."""
    go = FORK.Event()
    procs = [run(_write_many, tmp_path, w, per_writer, go) for w in range(N_WRITERS)]
    go.set()
    assert [join(p) for p in procs] == [0] * N_WRITERS
    files = read_manifest(tmp_path)
    assert len(files) == N_WRITERS * per_writer
    assert_listed_and_verified(tmp_path)
    for w in range(N_WRITERS):
        for j in range(per_writer):
            assert version_of(tmp_path, f"w{w}_{j:02d}") == 100.0 * w + j
    assert temporaries(tmp_path) == []


def _write_same(directory: Path, version: float, go, overwrite: bool) -> None:
    go.wait()
    try:
        for _ in range(5 if overwrite else 1):
            write(directory, version, overwrite=overwrite)
    except FileExistsError:
        os._exit(3)
    os._exit(0)


def test_two_writers_of_one_dataset_both_succeed_and_the_result_verifies(tmp_path):
    """Two processes rewrite the same dataset 5 times each at once: both succeed, the
    file verifies and is one writer's version."""
    go = FORK.Event()
    procs = [run(_write_same, tmp_path, v, go, True) for v in (1.0, 2.0)]
    go.set()
    assert [join(p) for p in procs] == [0, 0]
    assert version_of(tmp_path) in (1.0, 2.0)
    assert_listed_and_verified(tmp_path)
    assert temporaries(tmp_path) == []


def test_two_creators_of_one_new_dataset_one_wins_one_fails_cleanly(tmp_path):
    """Without ``overwrite`` exactly one of two simultaneous creators succeeds; the other
    gets FileExistsError and leaves nothing behind."""
    go = FORK.Event()
    procs = [run(_write_same, tmp_path, v, go, False) for v in (1.0, 2.0)]
    go.set()
    codes = [join(p) for p in procs]
    assert sorted(codes) == [0, 3]
    assert version_of(tmp_path) == (1.0, 2.0)[codes.index(0)]
    assert_listed_and_verified(tmp_path)
    assert temporaries(tmp_path) == []


def _read_while_written(directory: Path, stop) -> None:
    version = 10.0
    while not stop.is_set():
        write(directory, version)
        version += 1.0
    os._exit(0)


def test_readers_never_fail_while_a_writer_rewrites(tmp_path):
    """A reader in a loop while another process rewrites the dataset: every read
    verifies (a reader that sees the manifest and the file disagree re-reads)."""
    write(tmp_path, 1.0)
    stop = FORK.Event()
    proc = run(_read_while_written, tmp_path, stop)
    seen = set()
    deadline = time.monotonic() + 1.5
    try:
        while time.monotonic() < deadline:
            seen.add(version_of(tmp_path))
    finally:
        stop.set()
    assert join(proc) == 0
    assert len(seen) > 1, "the reader never saw a new version: the test tested nothing"


# --------------------------------------------------------------------------- disk full
def _enospc(self, path, *args, **kwargs):
    with open(path, "wb") as fh:
        fh.write(b"\x89HDF\r\n half")
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))


def test_full_disk_keeps_the_old_version_and_says_so(tmp_path, monkeypatch):
    path = write(tmp_path, 1.0)
    before = path.read_bytes()
    monkeypatch.setattr(xr.Dataset, "to_netcdf", _enospc)
    with pytest.raises(DatasetWriteError, match="No space left.*previous version is intact"
                       ) as info:
        write(tmp_path, 2.0)
    assert info.value.errno == errno.ENOSPC
    monkeypatch.undo()
    assert path.read_bytes() == before
    assert temporaries(tmp_path) == []
    assert_listed_and_verified(tmp_path)


def test_full_disk_when_committing_the_manifest_keeps_a_listed_version(tmp_path,
                                                                        monkeypatch):
    """The disk fills after the new file is installed: every later manifest write fails
    too, yet the file on disk verifies (through the recorded intent) and the error says
    the new version is in place; the next writer completes the manifest."""
    write(tmp_path, 1.0)
    real = manifest.write_manifest
    calls = {"n": 0}

    def fill_after_intent(*args, **kwargs):
        calls["n"] += 1
        if calls["n"] > 1:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        real(*args, **kwargs)

    monkeypatch.setattr(manifest, "write_manifest", fill_after_intent)
    with pytest.raises(DatasetWriteError, match="new version was installed"):
        write(tmp_path, 2.0)
    assert version_of(tmp_path) == 2.0  # accepted through the pending record
    monkeypatch.undo()
    datasets.recover(tmp_path)
    assert_listed_and_verified(tmp_path)
    assert "pending" not in json.loads((tmp_path / datasets.MANIFEST_NAME).read_text())


# --------------------------------------------------------------------------- read-only
def test_read_only_directory_refuses_the_write_and_keeps_the_data(tmp_path):
    path = write(tmp_path, 1.0)
    before = path.read_bytes()
    tmp_path.chmod(stat.S_IRUSR | stat.S_IXUSR)
    try:
        if os.access(tmp_path, os.W_OK):
            pytest.skip("chmod does not stop this user (root); see the os.replace test")
        with pytest.raises(DatasetWriteError, match=str(tmp_path)):
            write(tmp_path, 2.0)
        assert version_of(tmp_path) == 1.0  # a read-only directory still reads
    finally:
        tmp_path.chmod(stat.S_IRWXU)
    assert path.read_bytes() == before
    assert_listed_and_verified(tmp_path)


def test_refused_rename_rolls_back_the_recorded_intent(tmp_path, monkeypatch):
    """Installing the new file is refused (a read-only target, simulated because root
    ignores chmod): the old version stays listed, the intent and temporaries go."""
    path = write(tmp_path, 1.0)
    before = path.read_bytes()
    real_replace = os.replace

    def refuse_data(src, dst):
        if Path(dst) == path:
            raise PermissionError(errno.EACCES, os.strerror(errno.EACCES), str(dst))
        real_replace(src, dst)

    monkeypatch.setattr(os, "replace", refuse_data)
    with pytest.raises(DatasetWriteError, match="Permission denied.*previous version"):
        write(tmp_path, 2.0)
    monkeypatch.undo()
    assert path.read_bytes() == before
    assert temporaries(tmp_path) == []
    assert "pending" not in json.loads((tmp_path / datasets.MANIFEST_NAME).read_text())
    assert_listed_and_verified(tmp_path)


# --------------------------------------------------------------------------- directory
STALE = (".example.tmp.nc", ".example.4242.0badcafe.tmp.nc", "MANIFEST.json.tmp",
         "MANIFEST.json.4242.0badcafe.tmp")


def test_stale_temporaries_are_not_data_and_are_cleaned(tmp_path):
    write(tmp_path, 1.0)
    for name in STALE:
        (tmp_path / name).write_bytes(b"left by a killed writer")
    assert verify_directory(tmp_path) == []
    actions = datasets.recover(tmp_path)
    assert sorted(a.split(":")[0] for a in actions) == sorted(STALE)
    assert temporaries(tmp_path) == []
    for name in STALE:  # and a writer cleans them too
        (tmp_path / name).write_bytes(b"left by a killed writer")
    write(tmp_path, 2.0)
    assert temporaries(tmp_path) == []


def test_manifest_entry_without_checksum_is_an_error_naming_the_file(tmp_path):
    write(tmp_path, 1.0)
    manifest = tmp_path / datasets.MANIFEST_NAME
    body = json.loads(manifest.read_text())
    del body["files"]["example.nc"]["sha256"]
    manifest.write_text(json.dumps(body))
    with pytest.raises(DatasetError, match="example.nc has no sha256"):
        read_dataset("example", data_dir=tmp_path)
    [problem] = verify_directory(tmp_path)
    assert problem.kind == "data" and "example.nc has no sha256" in problem.reason


@pytest.mark.parametrize("state", ["missing", "empty", "empty_manifest"])
def test_missing_or_empty_data_directory_is_a_data_problem(tmp_path, state):
    directory = tmp_path / "data"
    if state != "missing":
        directory.mkdir()
    if state == "empty_manifest":
        manifest.write_manifest(directory, {})
    [problem] = verify_directory(directory)
    assert problem.file == str(directory)
    assert "debench reproduce --write-data" in problem.reason


def test_tampered_and_unlisted_files_are_records_naming_the_file(tmp_path):
    path = write(tmp_path, 1.0)
    with open(path, "r+b") as fh:
        fh.seek(-8, os.SEEK_END)
        fh.write(b"tampered")
    write(tmp_path, 1.0, name="stray").rename(tmp_path / "stray_copy.nc")
    problems = {p.file: p for p in verify_directory(tmp_path)}
    assert "does not match manifest" in problems["example.nc"].reason
    assert "not listed" in problems["stray_copy.nc"].reason
    assert problems["example.nc"].as_json() == {
        "kind": "data", "id": "data:example.nc", "file": "example.nc",
        "reason": problems["example.nc"].reason}


# --------------------------------------------------------------------------- command line
@pytest.fixture
def no_catalogue(monkeypatch):
    """The command line without the catalogue evaluation, the value guards (their
    producers take ~30 s and are tested elsewhere) and the report's consensus of peer
    submissions (it reads the reference datasets, which these tests' data directories do
    not hold): the data handling of the commands is what is tested here."""
    from debench.reference import catalogue, cli_reproduction, report

    monkeypatch.setattr(catalogue, "evaluate_all", lambda progress=None: [])
    monkeypatch.setattr(cli_reproduction, "value_deviations", lambda *a, **k: [])
    monkeypatch.setattr(report, "consensus_section", lambda: [])


def test_reproduce_into_the_curated_directory_needs_write_data(tmp_path, monkeypatch, capsys):
    from debench.reference.cli import main

    monkeypatch.setenv(datasets.DATA_DIR_ENV, str(tmp_path / "curated"))
    (tmp_path / "curated").mkdir()
    for out in (tmp_path / "curated", tmp_path / "curated" / ".." / "curated"):
        code = main(["reproduce", "catalogue", "--out", str(out)])
        [error] = [line for line in capsys.readouterr().err.splitlines()
                   if line.startswith("debench: error:")]
        assert code == 2 and "curated data directory" in error and "--write-data" in error
    assert list((tmp_path / "curated").iterdir()) == []


def test_verify_json_names_the_tampered_file(tmp_path, monkeypatch, capsys, no_catalogue):
    from debench.reference.cli import main

    path = write(tmp_path, 1.0)
    path.write_bytes(path.read_bytes()[:-8] + b"tampered")
    monkeypatch.setenv(datasets.DATA_DIR_ENV, str(tmp_path))
    code = main(["verify", "--json", "--no-regenerate"])
    captured = capsys.readouterr()
    rows = json.loads(captured.out)
    data = [r for r in rows if r["kind"] == "data"]
    assert code == 1
    assert {"kind": "data", "id": "data:example.nc", "file": "example.nc"}.items() \
        <= data[0].items()
    assert "does not match manifest" in data[0]["reason"]
    assert "example.nc" in captured.err


def test_report_with_partial_figures_warns_listing_the_missing(tmp_path, monkeypatch,
                                                               capsys, no_catalogue):
    from debench.reference.cli import main

    curated = tmp_path / "curated"
    (curated / "figures").mkdir(parents=True)
    for name in ("fig3_2_a.png", "fig3_4_b.png", "fig4_3_c.png"):
        (curated / "figures" / name).write_bytes(b"png")
    monkeypatch.setenv(datasets.DATA_DIR_ENV, str(curated))
    out = tmp_path / "results"
    (out / "figures").mkdir(parents=True)
    (out / "figures" / "fig3_2_a.png").write_bytes(b"png")
    assert main(["report", "--out", str(out)]) == 0
    err = capsys.readouterr().err
    assert "lacks 2 of the 3 expected figures" in err
    assert "fig3_4_b.png, fig4_3_c.png" in err
    (out / "figures" / "fig3_4_b.png").write_bytes(b"png")
    (out / "figures" / "fig4_3_c.png").write_bytes(b"png")
    assert main(["report", "--out", str(out)]) == 0
    assert "warning" not in capsys.readouterr().err
