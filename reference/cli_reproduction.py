"""The reproduction subcommands of ``debench`` (:mod:`debench.reference.cli`): ``reproduce``
(regenerate datasets, figures and the report), ``verify`` (stored data and computed claims
against the catalogue) and ``report`` (the markdown report and README table)."""

from __future__ import annotations

import contextlib
import json
import sys
import tempfile
import time
from pathlib import Path

from debench.reference import (
    builds,
    catalogue,
    datacard,
    datasets,
    provenance,
    regeneration,
    report,
    report_tables,
    values,
)
from debench.reference.builders import catalogue as catalogue_builder
from debench.reference.cli import CHAPTERS, progress_bar, resolve_chapter
from debench.reference.producers import ch5 as ch5_producer
from debench.reference.results_files import UsageError


# --------------------------------------------------------------------------- reproduce
def _same_directory(a: Path, b: Path) -> bool:
    """Whether two paths name one directory (symlinks, ``..`` and bind mounts included)."""
    try:
        return a.samefile(b)
    except OSError:  # one of them does not exist yet
        return a.resolve() == b.resolve()


def _evaluate_with_guards(by_chapter, jobs: int, out: Path):
    """The catalogue evaluation and, beside it (:class:`~debench.reference.regeneration.
    Recomputations`), the model guards: ``(results, guards)``. The Chapter 5 guard takes
    the coarsest critical voltages from the ``ch5`` dataset this command built, when it
    built one with the curated dataset's parameters
    (:func:`debench.reference.producers.ch5.recomputed_in_this_command`)."""
    fresh = [p for p in by_chapter.get("ch5", []) if p.name == "ch5_critical_voltage.nc"]
    with contextlib.ExitStack() as stack:
        if fresh:
            stack.enter_context(ch5_producer.recomputed_in_this_command(fresh[0]))
        work = stack.enter_context(regeneration.Recomputations(
            (), builds.model_guards(CHAPTERS), jobs=jobs, out=out))
        results = catalogue.evaluate_all(progress=lambda xs: progress_bar(xs, "verifying claims"))
        return results, work.guarded()


def cmd_reproduce(args) -> int:
    started = time.monotonic()
    chapters = [resolve_chapter(c) for c in args.chapters] or list(CHAPTERS)
    jobs = builds.parse_jobs(getattr(args, "jobs", None))
    if not args.write_data and _same_directory(Path(args.out), datasets.data_dir()):
        raise UsageError(f"--out {args.out} is the curated data directory "
                         f"{datasets.data_dir()}; replacing the curated datasets needs "
                         "--write-data")
    out = datasets.data_dir() if args.write_data else Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if args.write_data:
        print(f"--write-data: replacing curated datasets in {out}", file=sys.stderr)
    scheduler = getattr(args, "scheduler", None)
    # the catalogue builder reflects the data of all others: built last, in this process,
    # from the one catalogue evaluation of the command
    builders = [c for c in chapters if c != "catalogue"]
    if jobs > 1 and len(builders) > 1:
        by_chapter, cpu = builds.build_concurrently(builders, out, args.full, scheduler, jobs)
    else:
        by_chapter, cpu = builds.build_serially(builders, out, args.full, scheduler)
    if "catalogue" in chapters:
        # the model guards beside the catalogue evaluation (in a pool unless this process
        # built a chapter itself: no fork after FE work in it)
        guard_jobs = jobs if len(builders) != 1 else 1
        results, guards = _evaluate_with_guards(by_chapter, guard_jobs, out)
        by_chapter["catalogue"] = builds.build_catalogue(out, args.full, results, guards)
    else:
        results = catalogue.evaluate_all(progress=lambda xs: progress_bar(xs, "verifying claims"))
    written = [p for c in chapters for p in by_chapter.get(c, [])]
    compared = []
    if args.write_data:
        print(f"  data card: {datacard.write(out)}", file=sys.stderr)
    else:
        compared = [regeneration.compare_with_curated(p, datasets.data_dir())
                    for p in written if p.suffix == ".nc"]
        compared += builds.not_recomputed(builders, args.full)
        for line in compared:
            print(f"  {line}", file=sys.stderr)
    path = report.write_report(Path(args.out), results, regeneration=compared,
                               figures_dir=report.report_figures(out / "figures"))
    if not args.full:
        for line in builds.stale_declarations(cpu):
            print(f"  {line}", file=sys.stderr)
    print(f"report: {path}  ({report_tables.summary_line(results)})")
    print(f"reproduce: {', '.join(chapters)}: wrote {len(written)} file(s) "
          f"({sum(p.suffix == '.nc' for p in written)} datasets) to {out.resolve()}, report "
          f"{Path(path).resolve()}, in {time.monotonic() - started:.1f} s")
    return 0


# --------------------------------------------------------------------------- verify
def value_deviations(results, extra=None):
    """Recomputed values against the store ``our_values.nc`` (see :mod:`.values`): the
    catalogue's ``results`` and, unless ``extra`` is None, the model guards' values
    ``extra`` (then every stored value must be recomputed)."""
    guards = values.guarded_from_results(results)
    if extra is not None:
        guards += list(extra)
    return values.check(guards, values.read_store(), complete=extra is not None)


def verify_recomputations(*, regenerate: bool, jobs: int, out: Path):
    """What ``debench verify`` recomputes beside its catalogue evaluation
    (:class:`~debench.reference.regeneration.Recomputations`): with ``regenerate`` the
    chapters whose builders declare ``REGENERATED_BY_VERIFY`` and every builder's model
    guards, else nothing (:func:`~debench.reference.builds.properties`)."""
    if not regenerate:
        return regeneration.Recomputations((), (), jobs=jobs, out=out)
    return regeneration.Recomputations(builds.regenerated_by_verify(CHAPTERS),
                                       builds.model_guards(CHAPTERS), jobs=jobs, out=out)


def cmd_verify(args) -> int:
    regenerate = not args.no_data and not args.no_regenerate
    with tempfile.TemporaryDirectory(prefix="debench-verify-") as tmp, verify_recomputations(
            regenerate=regenerate, jobs=builds.parse_jobs(args.jobs), out=Path(tmp)) as work:
        results = catalogue.evaluate_all(progress=None if args.json else
                                         (lambda xs: progress_bar(xs, "verifying claims")))
        problems = [] if args.no_data else datasets.verify_directory()
        if regenerate:
            if not args.json:
                print("regenerating the cheap chapters and recomputing the model guards ...",
                      file=sys.stderr)
            for line in work.lines():
                if not args.json:
                    print(f"regenerated {line}", file=sys.stderr)
                if "DIFFERS" in line or "cannot compare" in line:
                    problems.append(datasets.DataProblem.coerce(line))
        extra = work.guarded() if regenerate else None
    if not args.no_data:
        problems += catalogue_builder.thesis_values_problems()
    deviations = [] if args.no_data else value_deviations(results, extra)
    regressed = [r for r in results if r.regressed]
    if args.json:
        # Data problems are appended to the array as records {"kind": "data", "id",
        # "file", "reason"}; consumers of catalogue entries select them by kind.
        records = [datasets.DataProblem.coerce(p) for p in problems]
        for p in records:
            print(f"DATA {p}", file=sys.stderr)
        rows = [r.as_json() for r in results] + [p.as_json() for p in records]
        rows += [{"kind": "value", "id": d.key, "what": d.what, "stored": d.stored,
                  "recomputed": d.recomputed, "tolerance": d.tolerance} for d in deviations]
        print(json.dumps(rows, indent=1, ensure_ascii=False, default=str))
    else:
        for r in results:
            if r.status in ("not_reproduced", "not_reproducible", "error") or r.regressed:
                flag = "REGRESSION " if r.regressed else ""
                print(f"{flag}{r.status:17s} {r.entry.id}: {r.diagnosis}")
        print(f"{len(results)} entries: {report_tables.summary_line(results)}")
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
    results = catalogue.evaluate_all(progress=lambda xs: progress_bar(xs, "verifying claims"))
    if args.datacard:
        print(f"data card: {datacard.write()}")
    if args.readme:
        if provenance.REPO_ROOT is None:
            raise RuntimeError("--readme updates README.md of a source checkout; "
                               "this debench is installed without one")
        readme = provenance.REPO_ROOT / "README.md"
        changed = report.update_readme(readme, results)
        print(f"{readme}: {'updated' if changed else 'already current'}")
    out = Path(args.out)
    figures = out / "figures"
    if not figures.exists():
        figures = datasets.data_dir() / "figures"
    path = report.write_report(out, results, figures_dir=report.report_figures(figures))
    print(f"report: {path}  ({report_tables.summary_line(results)})")
    return 0
