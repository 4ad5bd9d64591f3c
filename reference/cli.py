"""``debench`` command line: list, reproduce, verify, report.

Errors are one clear line (``debench: error: ...``) unless ``--debug`` is given (before or
after the subcommand). Exit codes: 0 ok; 1 a check or verification failed; 2 usage error
(bad arguments, unknown chapter, problem or file); 3 runtime error (a computation failed).
Progress bars are drawn only when stderr is a terminal (never in logs).

Examples
--------
    debench list claims
    debench reproduce              # fast default: every chapter, coarse FE meshes, the
                                   # chapters built at once on all cores (--jobs)
    debench reproduce ch5 --full   # converged finite-element meshes (long)
    debench verify --json          # one JSON object per catalogue entry
    debench report --readme        # regenerate the README results table
    debench problems ch3_free_membrane_nh --json
    debench check ch3_free_membrane_nh results.csv
    debench check ch5_pullin pullin.csv   # columns case, v_pullin, w_pullin: each checked
    debench check --submission submissions/ch5_critical_voltage/dolfinx-axisym
    debench cite ch3.pullin.voltage_lamP_1p25
"""

from __future__ import annotations

import argparse
import importlib
import inspect
import json
import os
import pkgutil
import sys
from pathlib import Path

import numpy as np
from debench.reference.results_files import UsageError, read_results


def _discover_chapters() -> tuple[str, ...]:
    """Builder modules in ``debench.reference.builders``; the catalogue last (it reflects all)."""
    import debench.reference.builders as pkg

    names = sorted(m.name for m in pkgutil.iter_modules(pkg.__path__)
                   if not m.name.startswith("_"))
    return tuple([n for n in names if n != "catalogue"] + ["catalogue"])


CHAPTERS = _discover_chapters()
#: The Chapter 5 finite-element chapters and the thin-solid thickness study (minutes of CPU
#: each) are checked by their model guards (coarse recomputations:
#: :func:`debench.reference.producers.ch5.coarse_guards`,
#: :func:`debench.reference.producers.ch3_fe.thickness_guards`) and the catalogue builder's
#: values by the value check; none is rebuilt by verify.
NOT_REGENERATED_BY_VERIFY = ("ch3_fe_thickness", "ch5", "ch5_axisym", "ch5_axisym_methods",
                             "ch5_axisym_path",
                             "ch5_imperfection",
                             "ch5_thickness", "ch5_wrinkling", "ch5_methods", "catalogue")
REGENERATED_BY_VERIFY = tuple(c for c in CHAPTERS if c not in NOT_REGENERATED_BY_VERIFY)
DEFAULT_OUT = Path("results")


#: exit codes (module docstring)
EXIT_OK, EXIT_FAILED, EXIT_USAGE, EXIT_RUNTIME = 0, 1, 2, 3


def resolve_chapter(name: str) -> str:
    """The builder name of a chapter given as ``ch3``, ``3`` or its full builder name
    (``ch2`` and ``2`` name ``ch2_appendix``)."""
    if name in CHAPTERS:
        return name
    key = f"ch{name}" if name.isdigit() else name
    hits = [c for c in CHAPTERS if c == key or c.startswith(f"{key}_")]
    if len(hits) != 1:
        raise UsageError(f"unknown chapter {name!r}; choose from {', '.join(CHAPTERS)} "
                         "(aliases: ch2 .. ch5 or 2 .. 5)")
    return hits[0]


def _progress(iterable, desc: str, **kw):
    from tqdm.auto import tqdm

    return tqdm(iterable, desc=desc, file=sys.stderr, leave=False,
                disable=not sys.stderr.isatty(), **kw)


# --------------------------------------------------------------------------- list
def cmd_list(args) -> int:
    what = args.what
    if what in ("models", "all"):
        from debench import models

        print("models:")
        for mod in pkgutil.iter_modules(models.__path__):
            if not mod.name.startswith("_"):
                print(f"  debench.models.{mod.name}")
    if what in ("datasets", "all"):
        from debench.reference.datasets import data_dir, read_manifest

        files = read_manifest(data_dir())
        print(f"datasets in {data_dir()}:")
        for name, meta in files.items():
            print(f"  {name:40s} {meta['sha256'][:12]}  {meta.get('title', '')}")
        if not files:
            print("  (none: run `debench reproduce --write-data`)")
    if what in ("claims", "all"):
        from debench.reference import catalogue

        entries = catalogue.load()
        print(f"catalogue ({len(entries)} entries):")
        for e in entries:
            print(f"  {e.kind:11s} {e.id:55s} {e.printed or e.value!s:>10} {e.unit}")
    return 0


# --------------------------------------------------------------------------- reproduce
def _builder(chapter: str):
    try:
        return importlib.import_module(f"debench.reference.builders.{chapter}")
    except ModuleNotFoundError as exc:
        if exc.name == f"debench.reference.builders.{chapter}":
            return None
        raise


#: Default agreement of a regenerated numeric variable with its curated counterpart, for
#: variables that state no accuracy of their own: the builders' solvers stop at relative
#: tolerances <= 1e-10 and a recomputation on another CPU/BLAS moves their values by
#: < 1e-8 relative (measured across OpenBLAS kernels), so 1e-6 keeps a 100x margin; the
#: absolute floor 1e-12 covers values that vanish (differences of equal quantities)
REGEN_RTOL = 1e-6
REGEN_ATOL = 1e-12


def regeneration_tolerance(attrs) -> tuple[float, float]:
    """(rtol, atol) to which a regenerated variable must match its curated counterpart.

    A variable that states its own accuracy (attributes ``accuracy_rtol`` and/or
    ``accuracy_atol``, the producer's :class:`~debench.reference.catalogue.Accuracy` of
    its values) is judged by it, tighter or looser than the default; any other numeric
    variable by :data:`REGEN_RTOL` and :data:`REGEN_ATOL`.
    """
    if "accuracy_rtol" not in attrs and "accuracy_atol" not in attrs:
        return REGEN_RTOL, REGEN_ATOL
    rtol, atol = (float(attrs.get(k, 0.0)) for k in ("accuracy_rtol", "accuracy_atol"))
    if not (np.isfinite(rtol) and np.isfinite(atol) and rtol >= 0 and atol >= 0
            and rtol + atol > 0):
        raise ValueError(f"accuracy_rtol and accuracy_atol must be finite, >= 0 and not both "
                         f"0, got {rtol}, {atol}")
    return rtol, atol


#: per dataset, the variables compared element by element within the absolute tolerance
#: stored beside them: the store of our values (:mod:`debench.reference.values`), each value
#: with the tolerance its method supports (the thesis values beside their printed-digit
#: tolerances are literals: compared by the default, i.e. equal)
TOLERANCE_VARIABLES = {"our_values": {"value": "tolerance"}}
#: a residual (backward error, Newton residual) of a converged solve is round-off: it
#: reproduces in size, not in digits (measured: eigen-residuals of ~3e-12 regenerate
#: within a factor 2). It matches when it stays below RESIDUAL_GROWTH x its curated value
#: (or REGEN_ATOL): a solve that got worse by an order of magnitude still shows.
RESIDUAL_GROWTH = 10.0


def is_residual(name: str, attrs) -> bool:
    """Whether a variable is a residual of a solve: quality information
    (``coverage_content_type``) named a residual."""
    return (attrs.get("coverage_content_type") == "qualityInformation"
            and "residual" in name)


def _numeric_match(name: str, var: str, new, old) -> bool:
    a, b = np.asarray(old[var].values, float), np.asarray(new[var].values, float)
    same_nan = np.array_equal(np.isnan(a), np.isnan(b))
    ok = ~np.isnan(a)
    tol_var = TOLERANCE_VARIABLES.get(name, {}).get(var)
    if tol_var is not None and tol_var in old and old[tol_var].shape == old[var].shape:
        tol = np.asarray(old[tol_var].values, float)
        return same_nan and bool(np.all(np.abs(b[ok] - a[ok]) <= tol[ok]))
    if is_residual(var, old[var].attrs):
        return same_nan and bool(np.all(np.abs(b[ok]) <= np.maximum(
            RESIDUAL_GROWTH * np.abs(a[ok]), REGEN_ATOL)))
    rtol, atol = regeneration_tolerance(old[var].attrs)
    return bool(np.allclose(b, a, rtol=rtol, atol=atol, equal_nan=True))


def compare_with_curated(path: Path, curated_dir: Path) -> str:
    """One line saying whether a regenerated dataset matches the curated one.

    Numeric variables must agree within the accuracy they state: a variable with a
    per-element absolute tolerance beside it (the store of our values: ``value`` within
    ``tolerance``, :data:`TOLERANCE_VARIABLES`) within that tolerance; a residual
    (:func:`is_residual`) by its size; any other within :func:`regeneration_tolerance`
    of the curated variable (``|new - old| <= atol + rtol |old|``); NaN where the curated
    value is NaN. Text variables exactly.
    """
    from debench.reference.datasets import DatasetError, read_dataset

    curated = curated_dir / path.name
    if not curated.exists():
        return f"{path.name}: no curated counterpart in {curated_dir}"
    try:
        new, old = read_dataset(path), read_dataset(curated)
    except DatasetError as exc:
        return f"{path.name}: cannot compare ({exc})"
    if new.attrs.get("parameters") != old.attrs.get("parameters"):
        return f"{path.name}: not comparable (different parameters, e.g. mesh resolution)"
    bad = []
    for var in old.data_vars:
        if var not in new:
            bad.append(f"{var} missing")
        elif np.issubdtype(old[var].dtype, np.number):
            if old[var].shape != new[var].shape or not _numeric_match(
                    path.stem, var, new, old):
                bad.append(var)
        elif not np.array_equal(new[var].values, old[var].values):
            bad.append(var)
    return f"{path.name}: {'matches curated' if not bad else 'DIFFERS in ' + ', '.join(bad)}"


def _same_directory(a: Path, b: Path) -> bool:
    """Whether two paths name one directory (symlinks, ``..`` and bind mounts included)."""
    try:
        return a.samefile(b)
    except OSError:  # one of them does not exist yet
        return a.resolve() == b.resolve()


def report_figures(figures: Path) -> Path:
    """The figures directory for a report, warning (stderr) about expected figures it lacks.

    Expected are the figures of the curated set (``data_dir()/figures``); a partial
    directory is used as it is, but never silently.
    """
    from debench.reference.datasets import data_dir

    curated = data_dir() / "figures"
    expected = {p.name for p in curated.glob("*.png")}
    present = {p.name for p in figures.glob("*.png")}
    missing = sorted(expected - present)
    if missing:
        print(f"debench: warning: {figures} lacks {len(missing)} of the {len(expected)} "
              f"expected figures, which the report omits: {', '.join(missing)}. To include "
              "them, run `debench reproduce` for the chapters that make them (figures of "
              "converged-only studies, such as the radius/thickness 20 ones, need `--full`: "
              "hours of FE), or `debench report --out DIR` with a DIR that has no figures/ "
              "to use the curated figures", file=sys.stderr)
    elif not present:
        print(f"debench: warning: no figures in {figures}; the report has none "
              "(`debench reproduce` makes them)", file=sys.stderr)
    return figures


#: CPU seconds of each builder's default build, one thread, FE tasks serial in the
#: chapter's process (measured in one `debench reproduce --jobs 2` on the 2-core
#: development machine, heavily loaded, so upper bounds): `debench reproduce` starts the
#: longest first, so that no long chapter starts last. Only the order depends on these
#: numbers; a chapter not listed counts as :data:`UNLISTED_BUILD_CPU_S`.
BUILD_CPU_S = {
    "ch3_fe_thickness": 96.3, "ch5_axisym": 118.5, "ch5_axisym_path": 71.0, "ch5": 70.7,
    "ch5_axisym_methods": 12.0,
    "ch4_fe": 32.8, "ch4": 28.3,
    "ch5_thickness": 26.7, "ch5_methods": 23.3, "ch4_inplane": 16.9, "ch3": 9.0,
    "ch3_fe": 7.2, "ch2_appendix": 0.7, "ch5_imperfection": 0.0, "ch5_wrinkling": 0.0,
}
UNLISTED_BUILD_CPU_S = 60.0


def parse_jobs(value: int | None) -> int:
    """The ``--jobs`` of ``debench reproduce``: how many chapters are built at once (pool
    processes), an integer >= 1; None means the number of cores. Anything else is a
    :class:`UsageError` naming the argument."""
    if value is None:
        return os.cpu_count() or 1
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise UsageError(f"--jobs {value!r}: must be an integer >= 1 (processes building "
                         "chapters at once)")
    return value


def _scheduler_option(mod, scheduler: str | None) -> dict:
    """The ``scheduler`` keyword for a builder that runs its own FE tasks (none for others)."""
    if scheduler is None or "scheduler" not in inspect.signature(mod.build).parameters:
        return {}
    return {"scheduler": scheduler}


class _Built:
    """What a chapter's build in a pool process sends back: the files written, the
    chapter's own output (stdout, stderr), its CPU and wall seconds, and on failure the
    exception and its traceback text."""

    def __init__(self, chapter: str):
        self.chapter = chapter
        self.paths: list[Path] | None = []
        self.stdout = self.stderr = ""
        self.cpu = self.wall = 0.0
        self.error: BaseException | None = None
        self.traceback = ""


class ChapterTraceback(Exception):
    """The traceback of a chapter that failed in a pool process (the ``__cause__`` of the
    exception re-raised in the command's own process)."""


def _process_cpu() -> float:
    import resource

    own = resource.getrusage(resource.RUSAGE_SELF)
    return own.ru_utime + own.ru_stime


def _init_pool_process() -> None:
    """A pool process: BLAS/OpenMP and NGSolve threads as configured for the command
    (:func:`debench.threads.limit_threads` reads ``DEBENCH_THREADS``, which the command
    set), no progress bars."""
    from debench.threads import limit_threads

    limit_threads()
    os.environ["TQDM_DISABLE"] = "1"


def _build_captured(chapter: str, out: str, full: bool, scheduler: str | None) -> _Built:
    """Build one chapter in a pool process with its output captured (file descriptors 1 and
    2 and ``sys.stdout``/``sys.stderr``), so that the command prints each chapter's lines
    together; an exception is returned, not raised (with its traceback text)."""
    import pickle
    import tempfile
    import time
    import traceback

    built = _Built(chapter)
    cpu0, wall0 = _process_cpu(), time.monotonic()
    with tempfile.TemporaryFile() as fout, tempfile.TemporaryFile() as ferr:
        sys.stdout.flush()
        sys.stderr.flush()
        saved_fds, saved_streams = (os.dup(1), os.dup(2)), (sys.stdout, sys.stderr)
        os.dup2(fout.fileno(), 1)
        os.dup2(ferr.fileno(), 2)
        sys.stdout = open(1, "w", encoding="utf-8", errors="replace", closefd=False)  # noqa: SIM115
        sys.stderr = open(2, "w", encoding="utf-8", errors="replace", closefd=False)  # noqa: SIM115
        try:
            mod = _builder(chapter)
            if mod is None:
                built.paths = None
            else:
                built.paths = list(mod.build(Path(out), full=full,
                                             **_scheduler_option(mod, scheduler)))
        except Exception as exc:  # noqa: BLE001 - sent back and re-raised by the command
            built.traceback = traceback.format_exc()
            try:
                pickle.loads(pickle.dumps(exc))
                built.error = exc
            except Exception:  # noqa: BLE001 - an exception that cannot cross processes
                built.error = RuntimeError(f"{type(exc).__name__}: {exc}")
        finally:
            sys.stdout.flush()
            sys.stderr.flush()
            sys.stdout.close()
            sys.stderr.close()
            sys.stdout, sys.stderr = saved_streams
            for fd, saved in zip((1, 2), saved_fds, strict=True):
                os.dup2(saved, fd)
                os.close(saved)
        for f, attr in ((fout, "stdout"), (ferr, "stderr")):
            f.seek(0)
            setattr(built, attr, f.read().decode("utf-8", errors="replace"))
    built.cpu, built.wall = _process_cpu() - cpu0, time.monotonic() - wall0
    return built


def _pool_context():
    """``fork`` where the platform has it (Linux: no re-import of the package in every pool
    process), else ``spawn``."""
    import multiprocessing

    methods = multiprocessing.get_all_start_methods()
    return multiprocessing.get_context("fork" if sys.platform.startswith("linux")
                                       and "fork" in methods else "spawn")


def _announce(chapter: str, full: bool, out: Path) -> None:
    print(f"{chapter}: building{' (full)' if full else ''} into {out} ...", file=sys.stderr)


def _build_serially(chapters: list[str], out: Path, full: bool,
                    scheduler: str | None) -> dict[str, list[Path]]:
    """Build ``chapters`` one after the other in this process (``--jobs 1``)."""
    written: dict[str, list[Path]] = {}
    for chapter in chapters:
        mod = _builder(chapter)
        if mod is None:
            print(f"{chapter}: no builder yet (pending)", file=sys.stderr)
            continue
        _announce(chapter, full, out)
        written[chapter] = list(mod.build(out, full=full, **_scheduler_option(mod, scheduler)))
        for p in written[chapter]:
            print(f"  wrote {p}", file=sys.stderr)
    return written


def _stop_pool(executor) -> None:
    """Cancel the chapters not started and end the pool processes building the others."""
    import multiprocessing

    executor.shutdown(wait=False, cancel_futures=True)
    for proc in multiprocessing.active_children():
        proc.terminate()
    for proc in multiprocessing.active_children():
        proc.join(timeout=10)


def _build_concurrently(chapters: list[str], out: Path, full: bool, scheduler: str | None,
                        jobs: int) -> dict[str, list[Path]]:
    """Build ``chapters`` in a pool of ``jobs`` processes, longest first (:data:`BUILD_CPU_S`).

    Each chapter's output is printed together when it finishes (a progress line per chapter
    on a terminal). Builders that run their own FE tasks run them serially in their pool
    process unless ``scheduler`` names one (no cluster inside a pool). A chapter that
    raises stops the command: the chapters not started are cancelled, those running are
    ended, and its exception is raised here (its traceback as the cause).
    """
    import time
    from concurrent.futures import ProcessPoolExecutor, as_completed

    order = sorted(chapters, key=lambda c: -BUILD_CPU_S.get(c, UNLISTED_BUILD_CPU_S))
    started = time.monotonic()
    written: dict[str, list[Path]] = {}
    tty = sys.stderr.isatty()
    executor = ProcessPoolExecutor(max_workers=min(jobs, len(order)), mp_context=_pool_context(),
                                   initializer=_init_pool_process)
    try:
        futures = {executor.submit(_build_captured, c, str(out), full, scheduler or "serial"): c
                   for c in order}
        for k, fut in enumerate(as_completed(futures), 1):
            built = fut.result()
            if built.paths is None:
                print(f"{built.chapter}: no builder yet (pending)", file=sys.stderr)
                continue
            _announce(built.chapter, full, out)
            sys.stdout.write(built.stdout)
            sys.stderr.write(built.stderr)
            if built.error is not None:
                raise built.error from ChapterTraceback(
                    f"{built.chapter} failed in a pool process:\n{built.traceback}")
            written[built.chapter] = built.paths
            for p in built.paths:
                print(f"  wrote {p}", file=sys.stderr)
            if tty:
                print(f"[{k}/{len(order)}] {built.chapter} done: {built.cpu:.0f} s CPU, "
                      f"{built.wall:.0f} s; {time.monotonic() - started:.0f} s since the start",
                      file=sys.stderr)
            sys.stderr.flush()
    except BaseException:      # a chapter failed, or an interrupt: nothing else runs on
        sys.stderr.flush()
        _stop_pool(executor)
        raise
    executor.shutdown(wait=True)
    return {c: written[c] for c in chapters if c in written}


def cmd_reproduce(args) -> int:
    import time

    from debench.reference import catalogue, report
    from debench.reference.datasets import data_dir

    started = time.monotonic()
    chapters = [resolve_chapter(c) for c in args.chapters] or list(CHAPTERS)
    jobs = parse_jobs(getattr(args, "jobs", None))
    if not args.write_data and _same_directory(Path(args.out), data_dir()):
        raise UsageError(f"--out {args.out} is the curated data directory {data_dir()}; "
                         "replacing the curated datasets needs --write-data")
    out = data_dir() if args.write_data else Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if args.write_data:
        print(f"--write-data: replacing curated datasets in {out}", file=sys.stderr)
    scheduler = getattr(args, "scheduler", None)
    # the catalogue builder reflects the data of all others: built last, in this process,
    # from the one catalogue evaluation of the command
    builders = [c for c in chapters if c != "catalogue"]
    if jobs > 1 and len(builders) > 1:
        by_chapter = _build_concurrently(builders, out, args.full, scheduler, jobs)
    else:
        by_chapter = _build_serially(builders, out, args.full, scheduler)
    results = catalogue.evaluate_all(progress=lambda xs: _progress(xs, "verifying claims"))
    if "catalogue" in chapters:
        by_chapter["catalogue"] = _build_catalogue(out, args.full, results, by_chapter)
    written = [p for c in chapters for p in by_chapter.get(c, [])]
    regeneration = []
    if args.write_data:
        from debench.reference import datacard

        print(f"  data card: {datacard.write(out)}", file=sys.stderr)
    else:
        regeneration = [compare_with_curated(p, data_dir())
                        for p in written if p.suffix == ".nc"]
        for line in regeneration:
            print(f"  {line}", file=sys.stderr)
    path = report.write_report(Path(args.out), results, regeneration=regeneration,
                               figures_dir=report_figures(out / "figures"))
    print(f"report: {path}  ({report.summary_line(results)})")
    print(f"reproduce: {', '.join(chapters)}: wrote {len(written)} file(s) "
          f"({sum(p.suffix == '.nc' for p in written)} datasets) to {out.resolve()}, report "
          f"{Path(path).resolve()}, in {time.monotonic() - started:.1f} s")
    return 0


def _build_catalogue(out: Path, full: bool, results, by_chapter) -> list[Path]:
    """The catalogue builder with the command's catalogue evaluation ``results``; its Chapter
    5 model guard takes the coarsest critical voltages from the ``ch5`` dataset this command
    built, when it built one with the curated dataset's parameters
    (:func:`debench.reference.producers.ch5.recomputed_in_this_command`)."""
    import contextlib

    mod = _builder("catalogue")
    _announce("catalogue", full, out)
    fresh = [p for p in by_chapter.get("ch5", []) if p.name == "ch5_critical_voltage.nc"]
    with contextlib.ExitStack() as stack:
        if fresh:
            from debench.reference.producers.ch5 import recomputed_in_this_command

            stack.enter_context(recomputed_in_this_command(fresh[0]))
        paths = list(mod.build(out, full=full, results=results))
    for p in paths:
        print(f"  wrote {p}", file=sys.stderr)
    return paths


# --------------------------------------------------------------------------- verify
def regenerate_and_compare(chapters, *, quiet: bool = False) -> list:
    """Rebuild cheap chapters in a temporary directory; problems (``DataProblem``
    records) where data/ differs."""
    import tempfile

    from debench.reference.datasets import DataProblem, data_dir
    from debench.reference.figures import not_written

    problems = []
    with tempfile.TemporaryDirectory(prefix="debench-verify-") as tmp, not_written():
        for chapter in chapters:
            mod = _builder(chapter)
            if mod is None:
                continue
            for path in mod.build(Path(tmp) / chapter, full=False):
                if path.suffix != ".nc":
                    continue
                line = compare_with_curated(path, data_dir())
                if not quiet:
                    print(f"regenerated {line}", file=sys.stderr)
                if "DIFFERS" in line or "cannot compare" in line:
                    problems.append(DataProblem.coerce(line))
    return problems


def value_deviations(results, *, models: bool = True, quiet: bool = False):
    """Recomputed values against the store ``our_values.nc`` (see :mod:`.values`).

    ``models=False`` skips the extra model guards (the Chapter 5 FE recomputation) and
    checks only the values that were recomputed.
    """
    from debench.reference import values

    guards = values.guarded_from_results(results)
    if models:
        if not quiet:
            print("recomputing the model guards (ch5 FE on the coarsest mesh) ...",
                  file=sys.stderr)
        guards += values.extra_guards()
    return values.check(guards, values.read_store(), complete=models)


def cmd_verify(args) -> int:
    from debench.reference import catalogue, values
    from debench.reference.datasets import verify_directory

    results = catalogue.evaluate_all(progress=None if args.json else
                                     (lambda xs: _progress(xs, "verifying claims")))
    problems = [] if args.no_data else verify_directory()
    if not args.no_data and not args.no_regenerate:
        problems += regenerate_and_compare(REGENERATED_BY_VERIFY, quiet=args.json)
    if not args.no_data:
        from debench.reference.builders.catalogue import thesis_values_problems

        problems += thesis_values_problems()
    deviations = [] if args.no_data else value_deviations(
        results, models=not args.no_regenerate, quiet=args.json)
    regressed = [r for r in results if r.regressed]
    if args.json:
        from debench.reference.datasets import DataProblem

        # Data problems are appended to the array as records {"kind": "data", "id",
        # "file", "reason"}; consumers of catalogue entries select them by kind.
        records = [DataProblem.coerce(p) for p in problems]
        for p in records:
            print(f"DATA {p}", file=sys.stderr)
        rows = [r.as_json() for r in results] + [p.as_json() for p in records]
        rows += [{"kind": "value", "id": d.key, "what": d.what, "stored": d.stored,
                  "recomputed": d.recomputed, "tolerance": d.tolerance} for d in deviations]
        print(json.dumps(rows, indent=1, ensure_ascii=False, default=str))
    else:
        from debench.reference.report import summary_line

        for r in results:
            if r.status in ("not_reproduced", "not_reproducible", "error") or r.regressed:
                flag = "REGRESSION " if r.regressed else ""
                print(f"{flag}{r.status:17s} {r.entry.id}: {r.diagnosis}")
        print(f"{len(results)} entries: {summary_line(results)}")
        for p in problems:
            print(f"DATA {p}")
        if regressed:
            print(f"{len(regressed)} regression(s): computed status differs from "
                  "expected_status in the catalogue")
        if deviations:
            print(f"\n{len(deviations)} value(s) left their stored tolerance "
                  f"({values.STORE_NAME}.nc):")
            print(values.table(deviations))
    return 1 if (regressed or problems or deviations) else 0


# --------------------------------------------------------------------------- report
def cmd_report(args) -> int:
    from debench.reference import catalogue, report

    results = catalogue.evaluate_all(progress=lambda xs: _progress(xs, "verifying claims"))
    if args.datacard:
        from debench.reference import datacard

        print(f"data card: {datacard.write()}")
    if args.readme:
        from debench.reference.provenance import REPO_ROOT

        if REPO_ROOT is None:
            raise RuntimeError("--readme updates README.md of a source checkout; "
                               "this debench is installed without one")
        readme = REPO_ROOT / "README.md"
        changed = report.update_readme(readme, results)
        print(f"{readme}: {'updated' if changed else 'already current'}")
    out = Path(args.out)
    figures = out / "figures"
    if not figures.exists():
        from debench.reference.datasets import data_dir

        figures = data_dir() / "figures"
    path = report.write_report(out, results, figures_dir=report_figures(figures))
    print(f"report: {path}  ({report.summary_line(results)})")
    return 0


# --------------------------------------------------------------------------- users
def cmd_problems(args) -> int:
    from debench.reference import problems

    if args.id is None:
        items = problems.load_all()
        if args.json:
            print(json.dumps([p.spec() for p in items], indent=1, ensure_ascii=False))
            return 0
        print(f"reference problems ({len(items)}):")
        for p in items:
            qs = ", ".join(q.name for q in p.quantities)
            print(f"  {p.id:28s} ch{p.chapter}  {p.title}  [{qs}]")
        return 0
    try:
        p = problems.get(args.id)
    except problems.ProblemError as exc:
        raise UsageError(str(exc)) from None
    if args.json:
        print(json.dumps(problems.reference_json(p), ensure_ascii=False))
        return 0
    if args.markdown:
        from debench.reference import consensus

        print(consensus.problem_page(p), end="")
        return 0
    spec = p.spec()
    print(f"{p.id}: {p.title} (Chapter {p.chapter})\n\n{p.summary}\n")
    print(f"geometry: {p.geometry}")
    if isinstance(p.boundary_conditions, str):
        print(f"boundary conditions: {p.boundary_conditions}")
    else:
        print("boundary conditions:")
        for b in p.boundary_conditions:
            print(f"  {b['boundary']}: kinematic {b['kinematic']}; electric {b['electric']}")
    if isinstance(p.loading, str):
        print(f"loading: {p.loading}")
    else:
        print(f"loading: {p.loading['path']}\ncontrolled: {p.loading['controlled']}")
    print(f"(the full page: debench problems {p.id} --markdown)")
    print("thesis: " + ", ".join(f"{k} {v}" for k, v in p.thesis.items()))
    print("parameters:")
    for name, par in p.parameters.items():
        print(f"  {name} = {par.get('value')} [{par.get('units', '')}]  "
              f"{par.get('description', '')}")
    for q in p.quantities:
        acc = q.accuracy
        print(f"quantity {q.name} [{q.units}]: {q.long_name}; coordinates "
              f"{', '.join(q.coordinates)}"
              + (f" (defaults {q.defaults})" if q.defaults else ""))
        print(f"  accuracy: atol {acc.atol:g} + rtol {acc.rtol:g} |ref| ({acc.reason})")
        print(f"  discretisation: {acc.discretisation_reason}")
    for meta in spec["provenance"]["datasets"].values():
        print(f"dataset {meta['file']} sha256 {meta['sha256']}")
    return 0


def cmd_check_submission(args) -> int:
    """``debench check --submission DIR``: the metadata against the schema (refused, each
    missing or invalid field named, exit 2), the results checksum, then the ordinary check
    at the submitter's stated tolerance (if any) and at the reference's stated accuracy;
    the exit code follows the former (0 match, 1 mismatch)."""
    from debench.reference import submissions

    if args.problem or args.file or args.rtol is not None or args.partial or args.quantity:
        raise UsageError("--submission DIR takes neither PROBLEM, FILE, --quantity, --rtol "
                         "nor --partial (the metadata states them)")
    try:
        sub = submissions.load(args.submission)
        out = submissions.check(sub)
    except submissions.SubmissionError as exc:
        raise UsageError(str(exc)) from None
    m = sub.meta
    print(f"submission {sub.folder}: {m['code']['name']} {m['code']['version']} "
          f"({m['code']['commit_or_release']}), run by {m['submitter']['name']} on "
          f"{m['submitter']['date']}; results {m['results']} sha256 verified")
    q = out.stated
    if out.declared is not None:
        print(f"at the submitter's stated tolerance ({sub.claims.get('reason')}):")
        print("  " + out.declared.summary())
    print("at the reference's stated accuracy alone:")
    print("  " + q.summary())
    prob_q = _problem_quantity(sub.problem, sub.quantity)
    if prob_q.along and len(prob_q.select):
        print(out.verdict.by_curve(prob_q.along))
    print(out.verdict.table())
    if out.claim_holds is False:
        print(f"note: the submission claims '{sub.claims['claimed']}', the check says "
              f"{'match' if out.passed else 'mismatch'}")
    return EXIT_OK if out.passed else EXIT_FAILED


def _problem_quantity(problem: str, quantity: str):
    from debench.reference import problems

    return problems.get(problem).quantity(quantity)


def _rtol(given: list[str] | None, quantities: tuple[str, ...]):
    """``--rtol`` values: ``X`` (every quantity) or ``NAME=X`` (one quantity), repeatable:
    None, a float, or {quantity: float}."""
    if not given:
        return None
    plain, named = [], {}
    for item in given:
        name, eq, value = item.rpartition("=")
        try:
            x = float(value)
        except ValueError:
            raise UsageError(f"--rtol {item}: expected a number or NAME=number") from None
        if not eq:
            plain.append(x)
        elif name not in quantities:
            raise UsageError(f"--rtol {item}: {name!r} is not a quantity of the file "
                             f"{list(quantities)}")
        else:
            named[name] = x
    if plain and (named or len(plain) > 1):
        raise UsageError("--rtol: give one number for every quantity, or NAME=number per "
                         "quantity, not both")
    return plain[0] if plain else named


def cmd_check(args) -> int:
    from debench.reference import problems

    from debench.testing import compare

    if args.submission is not None:
        return cmd_check_submission(args)
    if not args.problem or not args.file:  # argparse's own usage error (exit 2)
        args.check_parser.error("the following arguments are required: problem, file "
                                "(or --submission DIR)")
    try:
        prob = problems.get(args.problem)
    except problems.ProblemError as exc:
        raise UsageError(str(exc)) from None
    found, cols = read_results(Path(args.file), args.quantity, prob)
    rtol = _rtol(args.rtol, found)
    qs = [prob.quantity(n) for n in found]
    coords = {c: cols[c] for c in qs[0].coordinates if c in cols}
    cov = "partial" if args.partial else "full"
    try:
        if len(qs) == 1:
            result = compare(prob.id, qs[0].name, cols[qs[0].name], coords,
                             rtol=rtol[qs[0].name] if isinstance(rtol, dict) else rtol,
                             coverage=cov)
            items = (result,)
        else:
            result = compare(prob.id, None, {q.name: cols[q.name] for q in qs}, coords,
                             rtol=rtol, coverage=cov)
            items = result.items
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    print(result.summary())
    if len(qs) > 1:
        print(result.worst())
    for q, item in zip(qs, items, strict=True):
        if q.along and len(q.select):
            print(item.by_curve(q.along))
        print(item.table())
    return EXIT_OK if result.passed else EXIT_FAILED


def cmd_cite(args) -> int:
    from debench.reference import cite

    try:
        print(cite.render(args.id, args.format))
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    return 0


# --------------------------------------------------------------------------- main
def version_string() -> str:
    """``debench X (commit C; data manifest sha256 D)``: what ``--version`` prints."""
    import hashlib

    from debench.reference.datasets import MANIFEST_NAME, data_dir
    from debench.reference.provenance import git_commit

    from debench import __version__

    manifest = data_dir() / MANIFEST_NAME
    digest = (hashlib.sha256(manifest.read_bytes()).hexdigest()[:16]
              if manifest.is_file() else f"none ({manifest} missing)")
    return (f"debench {__version__} (commit {git_commit()}; "
            f"data {data_dir()}, manifest sha256 {digest})")


class _VersionAction(argparse.Action):
    def __init__(self, option_strings, dest, **kw):
        super().__init__(option_strings, dest, nargs=0, default=argparse.SUPPRESS, **kw)

    def __call__(self, parser, namespace, values, option_string=None):
        print(version_string())
        parser.exit()


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="debench",
        description="Verification and reproducibility benchmark for dielectric elastomer "
                    "actuators (Zeng 2020).")
    p.add_argument("--debug", action="store_true", help="show tracebacks")
    p.add_argument("--threads", type=int, default=None, metavar="N",
                   help="BLAS/OpenMP and NGSolve threads per process (default: "
                        "$DEBENCH_THREADS or 1)")
    p.add_argument("--version", action=_VersionAction,
                   help="print version, git commit and data manifest digest, then exit")
    sub = p.add_subparsers(dest="command", required=True)

    s = sub.add_parser("list", help="list models, datasets and catalogue entries")
    s.add_argument("what", nargs="?", default="all",
                   choices=["all", "models", "datasets", "claims"])
    s.set_defaults(func=cmd_list)

    s = sub.add_parser("reproduce", help="regenerate datasets, figures and the report")
    s.add_argument("chapters", nargs="*", help=f"subset of {', '.join(CHAPTERS)} or an alias "
                   "ch2 .. ch5 (default: all)")
    s.add_argument("--full", action="store_true",
                   help="converged finite-element meshes and full sweeps (slow)")
    s.add_argument("--jobs", type=int, default=None, metavar="N",
                   help="chapters built at once, one process each with --threads threads "
                        "(default: the number of cores; 1 builds them one after the other "
                        "in this process)")
    s.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="where the independent FE tasks of ch5, ch3_fe_thickness and ch4_fe "
                        "run: 'serial' (the chapter's process), 'local' (a Dask LocalCluster "
                        "sized to the machine, DEBENCH_WORKERS processes) or the address of an "
                        "existing cluster, e.g. tcp://host:8786 (dask-jobqueue on SLURM/PBS, "
                        "dask-kubernetes). Default: serial when chapters are built at once "
                        "(--jobs > 1), else the builder's own default")
    s.add_argument("--out", default=str(DEFAULT_OUT), help="output directory (default results/)")
    s.add_argument("--write-data", action="store_true",
                   help="overwrite the curated datasets in data/ (explicit by design)")
    s.set_defaults(func=cmd_reproduce)

    s = sub.add_parser("verify", help="check stored data and computed claims against the catalogue")
    s.add_argument("--json", action="store_true", help="JSON array, one object per entry")
    s.add_argument("--no-data", action="store_true",
                   help="skip the checks of data/ (checksums and regeneration)")
    s.add_argument("--no-regenerate", action="store_true",
                   help="do not regenerate the cheap chapters to compare with data/")
    s.set_defaults(func=cmd_verify)

    s = sub.add_parser("report", help="write the markdown report (and README table)")
    s.add_argument("--out", default=str(DEFAULT_OUT), help="directory of REPORT.md")
    s.add_argument("--readme", action="store_true", help="also regenerate the README table")
    s.add_argument("--datacard", action="store_true", help="also regenerate data/README.md")
    s.set_defaults(func=cmd_report)

    s = sub.add_parser("problems", help="list reference problems or print one (spec, "
                       "reference values, accuracy)")
    s.add_argument("id", nargs="?", help="problem id (default: list all)")
    s.add_argument("--json", action="store_true", help="JSON: the spec and, per quantity, "
                   "reference coordinates, values, units and accuracy")
    s.add_argument("--markdown", action="store_true", help="the problem page (markdown): "
                   "everything needed to implement the problem and check it")
    s.set_defaults(func=cmd_problems)

    s = sub.add_parser("check", help="check your results (CSV or netCDF) against a "
                       "reference problem; exit 0 match, 1 mismatch")
    s.add_argument("problem", nargs="?", help="problem id (debench problems)")
    s.add_argument("file", nargs="?",
                   help="CSV with header 'name [units]' per column, or netCDF")
    s.add_argument("--submission", metavar="DIR", help="check a submission folder instead: "
                   "submission.toml (validated: code, version, commit, URL, submitter, date, "
                   "method, mesh, tolerances, hardware, command) and the results file it "
                   "names (checksum verified); refused, naming each missing field, when "
                   "the metadata is incomplete")
    s.add_argument("--quantity", help="the one quantity to check (default: every quantity "
                   "column in FILE, each against its own reference; they must share their "
                   "coordinates)")
    s.add_argument("--rtol", action="append", metavar="[NAME=]X", help="your relative "
                   "tolerance, for every quantity (X) or one (NAME=X, repeatable) (default: "
                   "the stated accuracy of the reference, which is also the floor)")
    s.add_argument("--partial", action="store_true", help="declare partial coverage: "
                   "check the points given and report what they cover (default: every "
                   "reference curve or value the file addresses must be covered)")
    s.add_argument("--verbose", action="store_true", help="accepted for compatibility: "
                   "the table of the worst points is always printed")
    s.set_defaults(func=cmd_check, check_parser=s)

    s = sub.add_parser("cite", help="BibTeX and CSL-JSON for a catalogue entry, dataset "
                       "or reference problem")
    s.add_argument("id", help="catalogue id, dataset name or problem id")
    s.add_argument("--format", choices=["both", "bibtex", "csl"], default="both")
    s.set_defaults(func=cmd_cite)

    # --debug is accepted after the subcommand too (SUPPRESS keeps a top-level --debug)
    for sp in sub.choices.values():
        sp.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                        help="show tracebacks")
    return p


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        from debench.threads import limit_threads

        limit_threads(args.threads)
        if not sys.stderr.isatty():  # progress bars only on a terminal (never in logs)
            os.environ.setdefault("TQDM_DISABLE", "1")
        return int(args.func(args) or 0)
    except KeyboardInterrupt:
        print("debench: interrupted", file=sys.stderr)
        return 130
    except UsageError as exc:
        if args.debug:
            raise
        print(f"debench: error: {exc} (debench -h for usage)", file=sys.stderr)
        return EXIT_USAGE
    except Exception as exc:  # noqa: BLE001 - one clear line unless --debug
        if args.debug:
            raise
        print(f"debench: error: {type(exc).__name__}: {exc}", file=sys.stderr)
        return EXIT_RUNTIME


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
