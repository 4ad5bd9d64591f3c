"""``debench reproduce --jobs N``: chapters built at once in a process pool.

Checked here (the builders are stubs unless marked slow: this tests the command, not the
physics; the stubs reach the pool processes because the pool forks, on Linux):

* ``--jobs 2`` builds two chapters in two processes at the same time (a barrier both
  must reach) and writes the same files, with the same content, and the same report
  summary as ``--jobs 1``;
* ``--write-data`` with two chapters writing at the same moment keeps the manifest
  complete (both entries);
* a chapter that raises stops the command with its message and exit code 3, as the serial
  path does, and the chapter still running is ended (its file never written);
* ``--jobs 0`` and negative counts are usage errors naming the argument;
* the catalogue is evaluated once per command and the Chapter 5 model guard takes the
  coarsest critical voltages of a ``ch5`` dataset built in the same command instead of
  solving them again, and only when its parameters are those of the curated dataset;
* (slow) the real ``ch2_appendix`` and ``ch3`` builders: the same files and report summary
  with ``--jobs 2`` and ``--jobs 1``.
"""

from __future__ import annotations

import multiprocessing
import os
import sys
import time
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import xarray as xr
from debench.reference import builds, catalogue, cli, regeneration, report, report_tables
from debench.reference.datasets import read_dataset

pytestmark = pytest.mark.skipif(
    not sys.platform.startswith("linux"),
    reason="the stub builders reach the pool processes by fork (Linux)")

#: seconds a stub waits at the barrier for the other chapter (it is reached within
#: milliseconds when both run at once; a serial build would never reach it)
BARRIER_TIMEOUT_S = 60.0


def _stub_module(chapter: str, barrier=None, fail: bool = False, pid_dir: Path | None = None):
    """A builder writing one small dataset of its own (values fixed by the chapter name)
    and a text file; ``barrier``: wait there first (both chapters must run at once);
    ``fail``: raise instead."""
    from debench.reference.datasets import write_dataset

    def build(out, full=False):
        if pid_dir is not None:
            (pid_dir / chapter).write_text(str(os.getpid()))
        if barrier is not None:
            barrier.wait(BARRIER_TIMEOUT_S)
        if fail:
            raise RuntimeError(f"stub failure in {chapter}")
        print(f"{chapter}: stub line", file=sys.stderr)
        x = np.linspace(0.0, 1.0, 5) * (1 + len(chapter))
        ds = xr.Dataset({"y": ("x", x**2, {"long_name": "y", "units": "1"})},
                        coords={"x": ("x", x, {"long_name": "x", "units": "1"})})
        nc = write_dataset(ds, f"stub_{chapter}", out_dir=Path(out), overwrite=True,
                           title=f"stub {chapter}", summary="stub dataset",
                           parameters={"chapter": chapter})
        txt = Path(out) / f"stub_{chapter}.txt"
        txt.write_text(chapter)
        return [nc, txt]

    return _module(build=build)


def _module(**attrs):
    """A stub builder module: its attributes and the properties every builder declares."""
    return SimpleNamespace(BUILD_CPU_S=1.0, REGENERATED_BY_VERIFY=False, GUARDS={}, **attrs)


def _stub_catalogue(monkeypatch, results=()):
    calls = []

    def evaluate_all(entries=None, progress=None):
        calls.append(1)
        return list(results)

    monkeypatch.setattr(catalogue, "evaluate_all", evaluate_all)
    return calls


def _run(args, capsys) -> tuple[int, str, str]:
    code = cli.main(args)
    captured = capsys.readouterr()
    return code, captured.out, captured.err


@pytest.fixture
def few_results():
    """Real results of three cheap catalogue entries (for the report)."""
    entries = [e for e in catalogue.load() if e.kind == "assumption"][:3]
    return [catalogue.evaluate(e) for e in entries]


def test_jobs_2_builds_at_once_and_writes_what_jobs_1_writes(tmp_path, monkeypatch, capsys,
                                                             few_results):
    from debench.reference.datasets import read_manifest

    calls = _stub_catalogue(monkeypatch, few_results)
    ctx = multiprocessing.get_context("fork")
    barrier = ctx.Barrier(2)
    pid_dir = tmp_path / "pids"
    pid_dir.mkdir()
    stubs = {"serial": lambda c: _stub_module(c),
             "pool": lambda c: _stub_module(c, barrier=barrier, pid_dir=pid_dir)}
    outs = {}
    for mode, jobs in (("serial", "1"), ("pool", "2")):
        monkeypatch.setattr(builds, "builder", stubs[mode])
        out = tmp_path / mode
        code, stdout, stderr = _run(["reproduce", "ch2", "ch3", "--jobs", jobs, "--out",
                                     str(out)], capsys)
        assert code == 0, stderr
        outs[mode] = (out, stdout, stderr)
    pids = {p.read_text() for p in pid_dir.iterdir()}
    assert len(pids) == 2 and str(os.getpid()) not in pids   # two pool processes
    assert len(calls) == 2                                   # one evaluation per command
    (a, out_a, _), (b, out_b, err_b) = outs["serial"], outs["pool"]
    files = sorted(p.name for p in a.iterdir() if p.suffix in (".nc", ".txt"))
    assert files == sorted(p.name for p in b.iterdir() if p.suffix in (".nc", ".txt"))
    assert set(read_manifest(a)) == set(read_manifest(b)) == {
        "stub_ch2_appendix.nc", "stub_ch3.nc"}
    for name in files:
        if name.endswith(".nc"):
            assert regeneration.compare_with_curated(b / name, a).endswith("matches curated")
        else:
            assert (a / name).read_text() == (b / name).read_text()
    summary = [ln for ln in out_a.splitlines() if ln.startswith("report:")]
    assert [s.split("(", 1)[1] for s in summary] == [
        ln.split("(", 1)[1] for ln in out_b.splitlines() if ln.startswith("report:")]
    assert report_tables.summary_line(few_results) in summary[0]
    # each chapter's lines together: its announcement, its own output, its files
    for chapter in ("ch2_appendix", "ch3"):
        lines = err_b.splitlines()
        i = lines.index(f"{chapter}: building into {b} ...")
        assert lines[i + 1] == f"{chapter}: stub line"
        assert lines[i + 2].startswith("  wrote ") and chapter in lines[i + 2]


def test_write_data_from_two_chapters_at_once_keeps_the_manifest_complete(
        tmp_path, monkeypatch, capsys):
    from debench.reference import datacard
    from debench.reference.datasets import read_dataset, read_manifest

    data = tmp_path / "data"
    data.mkdir()
    monkeypatch.setenv("DEBENCH_DATA_DIR", str(data))
    _stub_catalogue(monkeypatch)
    monkeypatch.setattr(datacard, "write", lambda out=None: Path(out) / "README.md")
    monkeypatch.setattr(report, "write_report", lambda out, results, **kw: Path(out) / "R.md")
    barrier = multiprocessing.get_context("fork").Barrier(2)
    monkeypatch.setattr(builds, "builder", lambda c: _stub_module(c, barrier=barrier))
    code, _, stderr = _run(["reproduce", "ch2", "ch3", "--jobs", "2", "--write-data",
                            "--out", str(tmp_path / "report")], capsys)
    assert code == 0, stderr
    assert set(read_manifest(data)) == {"stub_ch2_appendix.nc", "stub_ch3.nc"}
    for name in ("stub_ch2_appendix", "stub_ch3"):
        assert read_dataset(name, data_dir=data).sizes["x"] == 5   # checksums verified


def test_a_failing_chapter_stops_the_command_with_its_message(tmp_path, monkeypatch, capsys):
    _stub_catalogue(monkeypatch)
    done = tmp_path / "slow_done"

    def builder(chapter):
        if chapter == "ch3":
            return _stub_module(chapter, fail=True)

        def slow(out, full=False):       # still running when ch3 fails: ended, not waited for
            time.sleep(BARRIER_TIMEOUT_S)
            done.write_text("finished")
            return []

        return _module(build=slow)

    monkeypatch.setattr(builds, "builder", builder)
    started = time.monotonic()
    code, _, stderr = _run(["reproduce", "ch2", "ch3", "--jobs", "2", "--out",
                            str(tmp_path / "out")], capsys)
    assert code == cli.EXIT_RUNTIME
    assert "debench: error: RuntimeError: stub failure in ch3" in stderr
    assert time.monotonic() - started < BARRIER_TIMEOUT_S / 2 and not done.exists()
    # the serial path fails with the same line
    monkeypatch.setattr(builds, "builder", lambda c: _stub_module(c, fail=c == "ch3"))
    code1, _, stderr1 = _run(["reproduce", "ch2", "ch3", "--jobs", "1", "--out",
                              str(tmp_path / "out1")], capsys)
    assert code1 == code
    assert stderr1.splitlines()[-1] == stderr.splitlines()[-1]


def test_a_failing_chapter_raises_its_exception_with_the_pool_traceback(tmp_path, monkeypatch):
    """With ``--debug`` the exception itself is raised; its cause carries the traceback of
    the pool process (where the builder raised)."""
    monkeypatch.setattr(builds, "builder", lambda c: _stub_module(c, fail=c == "ch3"))
    with pytest.raises(RuntimeError, match="stub failure in ch3") as info:
        cli.main(["--debug", "reproduce", "ch2", "ch3", "--jobs", "2", "--out",
                  str(tmp_path)])
    cause = info.value.__cause__
    assert isinstance(cause, builds.ChapterTraceback)
    assert "ch3 failed in a pool process" in str(cause) and "in build" in str(cause)


@pytest.mark.parametrize("jobs", ["0", "-1"])
def test_jobs_below_one_is_a_usage_error_naming_the_argument(jobs, tmp_path, capsys):
    code, _, stderr = _run(["reproduce", "ch3", "--jobs", jobs, "--out", str(tmp_path)],
                           capsys)
    assert code == cli.EXIT_USAGE
    assert stderr.startswith(f"debench: error: --jobs {jobs}: must be an integer >= 1")
    with pytest.raises(ValueError, match="--jobs"):
        builds.parse_jobs(int(jobs))
    assert builds.parse_jobs(None) == (os.cpu_count() or 1) and builds.parse_jobs(3) == 3


def test_the_catalogue_builder_gets_the_commands_evaluation_and_ch5_dataset(
        tmp_path, monkeypatch, capsys, few_results):
    """The catalogue builder runs after the others, in this process, with the one
    evaluation of the command and the model guards, which ran with the ``ch5`` dataset
    built before them as the source of the Chapter 5 guard's coarsest critical voltages."""
    from debench.reference import values
    from debench.reference.producers import ch5 as p5

    calls = _stub_catalogue(monkeypatch, few_results)
    seen = {}

    def probe_guard():
        fresh = p5.recomputed_dataset()
        return [values.Guarded("probe.fresh_has_v_cr", str(fresh is not None and "v_cr" in fresh),
                               0.0, "test")]

    monkeypatch.setattr(values, "probe_guard", probe_guard, raising=False)
    monkeypatch.setattr(builds, "model_guards",
                        lambda chapters: {"debench.reference.values:probe_guard": 1.0})

    def catalogue_build(out, full=False, results=None, guards=None):
        seen["results"], seen["guards"] = results, guards
        return []

    def ch5_build(out, full=False):
        return [_curated_copy(Path(out))]

    modules = {"catalogue": _module(build=catalogue_build),
               "ch5": _module(build=ch5_build)}
    monkeypatch.setattr(builds, "builder", modules.get)
    code, _, stderr = _run(["reproduce", "ch5", "catalogue", "--out", str(tmp_path)], capsys)
    assert code == 0, stderr
    assert len(calls) == 1 and seen["results"] == few_results
    assert [(g.key, g.value) for g in seen["guards"]] == [("probe.fresh_has_v_cr", "True")]
    assert p5.recomputed_dataset() is None                      # only for the guards


def _curated_copy(tmp_path, layers_marker=None, **changed):
    """The curated ``ch5_critical_voltage`` written to ``tmp_path`` with parameters
    ``changed`` and, with ``layers_marker``, ``v_cr_layers`` (and ``ndof_layers``)
    replaced by marker values (case index + layer count / 100, 100 x that)."""
    from debench.reference.datasets import dataset_parameters, read_dataset, write_dataset

    ds = read_dataset("ch5_critical_voltage").copy(deep=True)
    if layers_marker:
        marks = (np.arange(ds.sizes["case"])[:, None]
                 + ds.layer_count.values[None, :] / 100.0)
        ds["v_cr_layers"].values[:] = marks
        ds["ndof_layers"].values[:] = np.round(100 * marks).astype(np.int64)
    params = dict(dataset_parameters(ds), **changed)
    return write_dataset(ds, "ch5_critical_voltage", out_dir=tmp_path, overwrite=True,
                         title=ds.attrs["title"], summary=ds.attrs["summary"],
                         parameters=params)


def test_coarse_guard_takes_the_commands_ch5_dataset_instead_of_solving(tmp_path, monkeypatch):
    from debench.models.buckling import solver
    from debench.reference.producers import ch5 as p5

    def no_solve(*a, **k):
        raise AssertionError("solved although the command's ch5 dataset has the level")

    monkeypatch.setattr(solver, "critical_voltage", no_solve)
    crit = read_dataset("ch5_critical_voltage")
    with p5.recomputed_in_this_command(_curated_copy(tmp_path)):
        guards = {g.key: g.value for g in p5.coarse_guards()}
    for case in ("nh_t1", "ogden_t1"):
        first = crit.sel(case=case).isel(level=0)
        assert guards[f"ch5.guard.{case}.v_cr_coarse"] == float(first.v_cr)
        assert guards[f"ch5.guard.{case}.ndof_coarse"] == float(first.ndof)
        assert guards[f"ch5.guard.{case}.v_cr_coarse_minus_curated"] == 0.0


def test_coarse_guard_solves_when_the_commands_dataset_has_other_parameters(tmp_path,
                                                                           monkeypatch):
    """A dataset of another discretisation (here: two layers) is not the guard's
    computation: the guard solves (the solver is stubbed to a sentinel)."""
    from debench.models.buckling import solver
    from debench.reference.producers import ch5 as p5

    solved = []

    def sentinel(plate, material, disc):
        solved.append(disc)
        return SimpleNamespace(v=0.5, ndof=7)

    monkeypatch.setattr(solver, "critical_voltage", sentinel)
    from debench.reference.datasets import dataset_parameters

    layers = int(dataset_parameters(read_dataset("ch5_critical_voltage"))["layers"])
    with p5.recomputed_in_this_command(_curated_copy(tmp_path, layers=layers + 1)):
        guards = {g.key: g.value for g in p5.coarse_guards(cases=["nh_t1"])}
    assert len(solved) == 1 and solved[0].layers == layers
    assert guards["ch5.guard.nh_t1.v_cr_coarse"] == 0.5
    assert guards["ch5.guard.nh_t1.ndof_coarse"] == 7.0


def test_coarse_guard_takes_the_layer_study_point_of_its_discretisation(tmp_path,
                                                                        monkeypatch):
    """The default ``ch5`` build holds the guard's discretisation (coarsest in-plane size,
    the curated layer count) as a point of its through-thickness study, not as a level of
    its one-layer sequence: that point is taken (marker values show which one)."""
    from debench.models.buckling import solver
    from debench.reference.datasets import dataset_parameters
    from debench.reference.producers import ch5 as p5

    def no_solve(*a, **k):
        raise AssertionError("solved although the layer study holds the discretisation")

    monkeypatch.setattr(solver, "critical_voltage", no_solve)
    crit = read_dataset("ch5_critical_voltage")
    layers, h0 = int(dataset_parameters(crit)["layers"]), float(crit.h_rel.values[0])
    fresh = _curated_copy(tmp_path, layers_marker=True, layers=layers - 1,
                          layer_study_h_rel=h0)
    with p5.recomputed_in_this_command(fresh):
        guards = {g.key: g.value for g in p5.coarse_guards()}
    cases = crit.case.values.tolist()
    for case in ("nh_t1", "ogden_t1"):
        mark = cases.index(case) + layers / 100.0
        assert guards[f"ch5.guard.{case}.v_cr_coarse"] == mark
        assert guards[f"ch5.guard.{case}.ndof_coarse"] == round(100 * mark)


@pytest.mark.slow
def test_real_chapters_jobs_2_match_jobs_1(tmp_path, capsys):
    """The real ``ch2_appendix`` and ``ch3`` builders (about 15 s CPU each run, plus the
    catalogue evaluation): the same files, datasets and report summary."""
    outs = {}
    for jobs in ("1", "2"):
        out = tmp_path / f"jobs{jobs}"
        code, stdout, stderr = _run(["reproduce", "ch2", "ch3", "--jobs", jobs, "--out",
                                     str(out)], capsys)
        assert code == 0, stderr
        outs[jobs] = (out, [ln.split("(", 1)[1] for ln in stdout.splitlines()
                            if ln.startswith("report:")])
    (a, sum_a), (b, sum_b) = outs["1"], outs["2"]
    names = sorted(p.relative_to(a).as_posix() for p in a.rglob("*")
                   if p.suffix in (".nc", ".png", ".svg"))
    assert names and names == sorted(p.relative_to(b).as_posix() for p in b.rglob("*")
                                     if p.suffix in (".nc", ".png", ".svg"))
    for name in names:
        if name.endswith(".nc"):
            assert regeneration.compare_with_curated(b / name, a).endswith("matches curated"), name
    assert sum_a == sum_b and sum_a


def test_guards_in_a_pool_see_the_commands_ch5_dataset(tmp_path, monkeypatch):
    """Model guards run in a pool of two processes beside the catalogue evaluation still
    take the Chapter 5 coarsest critical voltages from the dataset the command built."""
    from debench.reference import regeneration, values
    from debench.reference.datasets import data_dir
    from debench.reference.producers import ch5 as p5

    def probe_guard():
        return [values.Guarded("probe", str(p5.recomputed_dataset() is not None), 0.0, "test")]

    monkeypatch.setattr(values, "probe_guard", probe_guard, raising=False)
    names = ("debench.reference.values:probe_guard",) * 2
    with p5.recomputed_in_this_command(data_dir() / "ch5_critical_voltage.nc"), \
            regeneration.Recomputations((), names, jobs=2, out=tmp_path) as work:
        assert [g.value for g in work.guarded()] == ["True", "True"]
