"""How ``debench reproduce`` builds chapters: each chapter's builder module, built serially
in the command's process or concurrently in a pool of processes (longest first, each
chapter's output printed together), and the catalogue builder last, from the command's one
catalogue evaluation."""

from __future__ import annotations

import importlib
import inspect
import multiprocessing
import os
import pickle
import pkgutil
import resource
import sys
import tempfile
import time
import traceback
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path

import debench.reference.builders as pkg
from debench.reference.results_files import UsageError

from debench.threads import limit_threads


def builder(chapter: str):
    """The builder module of ``chapter`` (``debench.reference.builders.<chapter>``), or None
    when the chapter has none."""
    try:
        return importlib.import_module(f"debench.reference.builders.{chapter}")
    except ModuleNotFoundError as exc:
        if exc.name == f"debench.reference.builders.{chapter}":
            return None
        raise


def chapters() -> tuple[str, ...]:
    """The builder modules in ``debench.reference.builders`` (the chapters of ``debench
    reproduce``), sorted, the catalogue last (it reflects all)."""
    names = sorted(m.name for m in pkgutil.iter_modules(pkg.__path__)
                   if not m.name.startswith("_"))
    return tuple([n for n in names if n != "catalogue"] + ["catalogue"])


@dataclass(frozen=True)
class BuildProperties:
    """What a builder module declares about itself: ``BUILD_CPU_S``, the CPU seconds of its
    default build (one thread; ``debench reproduce`` starts the longest first),
    ``REGENERATED_BY_VERIFY``, whether ``debench verify`` rebuilds its default plan, and
    ``GUARDS``, the model guards verify runs for it (``module:function`` returning
    :class:`~debench.reference.values.Guarded` values -> their CPU seconds)."""

    cpu_s: float
    regenerated_by_verify: bool
    guards: dict[str, float]


def properties(chapter: str) -> BuildProperties:
    """The :class:`BuildProperties` declared by ``chapter``'s builder module. Raises
    ValueError naming the chapter and the attribute when one is missing or of the wrong
    kind (a builder added without them is refused, never scheduled or verified by guess)."""
    mod = builder(chapter)
    if mod is None:
        raise ValueError(f"chapter {chapter!r} has no builder module")
    cpu = getattr(mod, "BUILD_CPU_S", None)
    regen = getattr(mod, "REGENERATED_BY_VERIFY", None)
    guards = getattr(mod, "GUARDS", None)
    if isinstance(cpu, bool) or not isinstance(cpu, (int, float)) or not cpu >= 0 \
            or cpu == float("inf"):
        raise ValueError(f"builder {chapter!r}: BUILD_CPU_S = {cpu!r} must be a finite "
                         "number >= 0 (CPU seconds of its default build)")
    if not isinstance(regen, bool):
        raise ValueError(f"builder {chapter!r}: REGENERATED_BY_VERIFY = {regen!r} must be "
                         "True or False")
    if not isinstance(guards, dict) or not all(
            isinstance(k, str) and ":" in k and isinstance(v, (int, float))
            and not isinstance(v, bool) and v >= 0 for k, v in guards.items()):
        raise ValueError(f"builder {chapter!r}: GUARDS = {guards!r} must map "
                         "'module:function' to CPU seconds >= 0")
    return BuildProperties(float(cpu), regen, dict(guards))


def build_cpu_s(chapters) -> dict[str, float]:
    """The declared CPU seconds of each of ``chapters``' default builds."""
    return {c: properties(c).cpu_s for c in chapters}


def regenerated_by_verify(chapters) -> tuple[str, ...]:
    """Those of ``chapters`` whose default plan ``debench verify`` rebuilds."""
    return tuple(c for c in chapters if properties(c).regenerated_by_verify)


def model_guards(chapters) -> dict[str, float]:
    """The model guards of ``chapters`` (``module:function`` -> CPU seconds), in their order."""
    out: dict[str, float] = {}
    for c in chapters:
        out.update(properties(c).guards)
    return out


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
    own = resource.getrusage(resource.RUSAGE_SELF)
    return own.ru_utime + own.ru_stime


def init_pool_process() -> None:
    """A pool process: BLAS/OpenMP and NGSolve threads as configured for the command
    (:func:`debench.threads.limit_threads` reads ``DEBENCH_THREADS``, which the command
    set), no progress bars."""
    limit_threads()
    os.environ["TQDM_DISABLE"] = "1"


def _build_captured(chapter: str, out: str, full: bool, scheduler: str | None) -> _Built:
    """Build one chapter in a pool process with its output captured (file descriptors 1 and
    2 and ``sys.stdout``/``sys.stderr``), so that the command prints each chapter's lines
    together; an exception is returned, not raised (with its traceback text)."""
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
            mod = builder(chapter)
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


def pool_context():
    """``fork`` where the platform has it (Linux: no re-import of the package in every pool
    process), else ``spawn``."""
    methods = multiprocessing.get_all_start_methods()
    return multiprocessing.get_context("fork" if sys.platform.startswith("linux")
                                       and "fork" in methods else "spawn")


def _announce(chapter: str, full: bool, out: Path) -> None:
    print(f"{chapter}: building{' (full)' if full else ''} into {out} ...", file=sys.stderr)


def build_serially(chapters: list[str], out: Path, full: bool,
                   scheduler: str | None) -> tuple[dict[str, list[Path]], dict[str, float]]:
    """Build ``chapters`` one after the other in this process (``--jobs 1``): the files
    each wrote and the CPU seconds of each build."""
    written: dict[str, list[Path]] = {}
    cpu: dict[str, float] = {}
    for chapter in chapters:
        mod = builder(chapter)
        if mod is None:
            print(f"{chapter}: no builder yet (pending)", file=sys.stderr)
            continue
        _announce(chapter, full, out)
        cpu0 = _process_cpu()
        written[chapter] = list(mod.build(out, full=full, **_scheduler_option(mod, scheduler)))
        cpu[chapter] = _process_cpu() - cpu0
        for p in written[chapter]:
            print(f"  wrote {p}", file=sys.stderr)
    return written, cpu


STALE_RATIO = 2.0
"""A default build whose measured CPU seconds differ from its declared ``BUILD_CPU_S`` by
more than this factor (either way) is reported: the pool's longest-first order and the
guards' budget read the declarations. Two, because one build's CPU varies with the machine
and its load (two pool processes on two hyperthreads of one core take ~1.7x the CPU of one,
measured)."""
STALE_MIN_S = 5.0
"""Builds below this many CPU seconds, declared and measured, are not reported (their
order in the pool does not matter)."""


def stale_declarations(cpu: dict[str, float]) -> list[str]:
    """One line per default build of ``cpu`` (chapter -> measured CPU seconds) whose
    declared ``BUILD_CPU_S`` is stale (:data:`STALE_RATIO`, :data:`STALE_MIN_S`)."""
    lines = []
    for chapter, measured in cpu.items():
        declared = properties(chapter).cpu_s
        if max(measured, declared) < STALE_MIN_S:
            continue
        if not declared / STALE_RATIO <= measured <= declared * STALE_RATIO:
            lines.append(f"{chapter}: the default build took {measured:.0f} s CPU, its "
                         f"BUILD_CPU_S declares {declared:g} s: update the declaration")
    return lines


def stop_pool(executor) -> None:
    """Cancel the chapters not started and end the pool processes building the others."""
    executor.shutdown(wait=False, cancel_futures=True)
    for proc in multiprocessing.active_children():
        proc.terminate()
    for proc in multiprocessing.active_children():
        proc.join(timeout=10)


def build_concurrently(chapters: list[str], out: Path, full: bool, scheduler: str | None,
                        jobs: int) -> tuple[dict[str, list[Path]], dict[str, float]]:
    """Build ``chapters`` in a pool of ``jobs`` processes, longest first (each builder's
    declared ``BUILD_CPU_S``, :func:`properties`): the files each wrote and the CPU seconds
    of each build (its pool process's).

    Each chapter's output is printed together when it finishes, with a line of its CPU and
    wall seconds. Builders that run their own FE tasks run them serially in their pool
    process unless ``scheduler`` names one (no cluster inside a pool). A chapter that
    raises stops the command: the chapters not started are cancelled, those running are
    ended, and its exception is raised here (its traceback as the cause).
    """
    cost = build_cpu_s(chapters)
    order = sorted(chapters, key=lambda c: -cost[c])
    started = time.monotonic()
    written: dict[str, list[Path]] = {}
    cpu: dict[str, float] = {}
    executor = ProcessPoolExecutor(max_workers=min(jobs, len(order)), mp_context=pool_context(),
                                   initializer=init_pool_process)
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
            cpu[built.chapter] = built.cpu
            for p in built.paths:
                print(f"  wrote {p}", file=sys.stderr)
            print(f"[{k}/{len(order)}] {built.chapter} done: {built.cpu:.0f} s CPU, "
                  f"{built.wall:.0f} s; {time.monotonic() - started:.0f} s since the start",
                  file=sys.stderr)
            sys.stderr.flush()
    except BaseException:      # a chapter failed, or an interrupt: nothing else runs on
        sys.stderr.flush()
        stop_pool(executor)
        raise
    executor.shutdown(wait=True)
    return {c: written[c] for c in chapters if c in written}, cpu


def not_recomputed(chapters, full: bool) -> list[str]:
    """One line per dataset of ``chapters`` that this plan does not recompute (the
    converged-only studies in the default run: their builders' ``not_recomputed(full)``),
    saying why and what their figures are drawn from."""
    lines = []
    for chapter in chapters:
        mod = builder(chapter)
        line = mod.not_recomputed(full) if hasattr(mod, "not_recomputed") else None
        if line:
            lines.append(line)
    return lines


def build_catalogue(out: Path, full: bool, results, guards) -> list[Path]:
    """The catalogue builder with the command's catalogue evaluation ``results`` and model
    guards ``guards`` (:func:`debench.reference.values.extra_guards`)."""
    mod = builder("catalogue")
    _announce("catalogue", full, out)
    paths = list(mod.build(out, full=full, results=results, guards=guards))
    for p in paths:
        print(f"  wrote {p}", file=sys.stderr)
    return paths
