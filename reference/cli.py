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
    debench check mms_electroelastic errors.csv   # errors per mesh level of an MMS study
                                                  # (degree, h, u_L2, ...): orders fitted
                                                  # and judged like any reference problem
    debench orders errors.csv --write orders.csv  # the fitted orders alone
"""

from __future__ import annotations

import argparse
import json
import os
import pkgutil
import sys
from pathlib import Path

from debench.reference import builds, regeneration
from debench.reference.cli_users import cmd_check, cmd_cite, cmd_problems
from debench.reference.results_files import (  # noqa: F401 - the exit codes, for callers
    EXIT_FAILED,
    EXIT_OK,
    EXIT_RUNTIME,
    EXIT_USAGE,
    UsageError,
)

CHAPTERS = builds.chapters()
DEFAULT_OUT = Path("results")




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


def progress_bar(iterable, desc: str, **kw):
    """``iterable`` wrapped in a tqdm bar labelled ``desc`` on stderr, drawn only when
    stderr is a terminal (never in logs); ``kw`` goes to tqdm."""
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
    import contextlib

    from debench.reference import catalogue

    fresh = [p for p in by_chapter.get("ch5", []) if p.name == "ch5_critical_voltage.nc"]
    with contextlib.ExitStack() as stack:
        if fresh:
            from debench.reference.producers.ch5 import recomputed_in_this_command

            stack.enter_context(recomputed_in_this_command(fresh[0]))
        work = stack.enter_context(regeneration.Recomputations(
            (), builds.model_guards(CHAPTERS), jobs=jobs, out=out))
        results = catalogue.evaluate_all(progress=lambda xs: progress_bar(xs, "verifying claims"))
        return results, work.guarded()


def cmd_reproduce(args) -> int:
    import time

    from debench.reference import catalogue, report, report_tables
    from debench.reference.datasets import data_dir

    started = time.monotonic()
    chapters = [resolve_chapter(c) for c in args.chapters] or list(CHAPTERS)
    jobs = builds.parse_jobs(getattr(args, "jobs", None))
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
        by_chapter = builds.build_concurrently(builders, out, args.full, scheduler, jobs)
    else:
        by_chapter = builds.build_serially(builders, out, args.full, scheduler)
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
        from debench.reference import datacard

        print(f"  data card: {datacard.write(out)}", file=sys.stderr)
    else:
        compared = [regeneration.compare_with_curated(p, data_dir())
                    for p in written if p.suffix == ".nc"]
        compared += builds.not_recomputed(builders, args.full)
        for line in compared:
            print(f"  {line}", file=sys.stderr)
    path = report.write_report(Path(args.out), results, regeneration=compared,
                               figures_dir=report.report_figures(out / "figures"))
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
    from debench.reference import values

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
    import tempfile

    from debench.reference import catalogue, values
    from debench.reference.datasets import DataProblem, verify_directory

    regenerate = not args.no_data and not args.no_regenerate
    with tempfile.TemporaryDirectory(prefix="debench-verify-") as tmp, verify_recomputations(
            regenerate=regenerate, jobs=builds.parse_jobs(args.jobs), out=Path(tmp)) as work:
        results = catalogue.evaluate_all(progress=None if args.json else
                                         (lambda xs: progress_bar(xs, "verifying claims")))
        problems = [] if args.no_data else verify_directory()
        if regenerate:
            if not args.json:
                print("regenerating the cheap chapters and recomputing the model guards ...",
                      file=sys.stderr)
            for line in work.lines():
                if not args.json:
                    print(f"regenerated {line}", file=sys.stderr)
                if "DIFFERS" in line or "cannot compare" in line:
                    problems.append(DataProblem.coerce(line))
        extra = work.guarded() if regenerate else None
    if not args.no_data:
        from debench.reference.builders.catalogue import thesis_values_problems

        problems += thesis_values_problems()
    deviations = [] if args.no_data else value_deviations(results, extra)
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
        from debench.reference.report_tables import summary_line

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
    from debench.reference import catalogue, report, report_tables

    results = catalogue.evaluate_all(progress=lambda xs: progress_bar(xs, "verifying claims"))
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
    path = report.write_report(out, results, figures_dir=report.report_figures(figures))
    print(f"report: {path}  ({report_tables.summary_line(results)})")
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


def _add_list(sub) -> None:
    """The ``debench list`` subcommand."""
    s = sub.add_parser("list", help="list models, datasets and catalogue entries")
    s.add_argument("what", nargs="?", default="all",
                   choices=["all", "models", "datasets", "claims"])
    s.set_defaults(func=cmd_list)


def _add_reproduce(sub) -> None:
    """The ``debench reproduce`` subcommand."""
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


def _add_verify(sub) -> None:
    """The ``debench verify`` subcommand."""
    s = sub.add_parser("verify", help="check stored data and computed claims against the catalogue")
    s.add_argument("--json", action="store_true", help="JSON array, one object per entry")
    s.add_argument("--no-data", action="store_true",
                   help="skip the checks of data/ (checksums and regeneration)")
    s.add_argument("--no-regenerate", action="store_true",
                   help="do not regenerate the cheap chapters to compare with data/")
    s.add_argument("--jobs", type=int, default=None, metavar="N",
                   help="chapters regenerated at once, one process each (default: the "
                        "number of cores; 1: one after the other in this process)")
    s.set_defaults(func=cmd_verify)


def _add_report(sub) -> None:
    """The ``debench report`` subcommand."""
    s = sub.add_parser("report", help="write the markdown report (and README table)")
    s.add_argument("--out", default=str(DEFAULT_OUT), help="directory of REPORT.md")
    s.add_argument("--readme", action="store_true", help="also regenerate the README table")
    s.add_argument("--datacard", action="store_true", help="also regenerate data/README.md")
    s.set_defaults(func=cmd_report)


def _add_problems(sub) -> None:
    """The ``debench problems`` subcommand."""
    s = sub.add_parser("problems", help="list reference problems or print one (spec, "
                       "reference values, accuracy)")
    s.add_argument("id", nargs="?", help="problem id (default: list all)")
    s.add_argument("--json", action="store_true", help="JSON: the spec and, per quantity, "
                   "reference coordinates, values, units and accuracy")
    s.add_argument("--markdown", action="store_true", help="the problem page (markdown): "
                   "everything needed to implement the problem and check it")
    s.set_defaults(func=cmd_problems)


def _add_check(sub) -> None:
    """The ``debench check`` subcommand."""
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


def cmd_cite_naming_others(args) -> int:
    """``debench cite``: the citation on stdout and, when the id names more than one thing
    (a problem and a dataset of the same name), which one was cited and how to cite the
    other on stderr (:func:`debench.reference.cite.ambiguity`)."""
    from debench.reference import cite

    code = cmd_cite(args)
    note = cite.ambiguity(args.id)
    if note:
        print(f"debench: note: {note}", file=sys.stderr)
    return code


def _add_cite(sub) -> None:
    """The ``debench cite`` subcommand."""
    s = sub.add_parser("cite", help="BibTeX and CSL-JSON for a catalogue entry, dataset "
                       "or reference problem")
    s.add_argument("id", help="catalogue id, dataset name or problem id; a name that is "
                   "both a problem and a dataset cites the problem (and says so on stderr), "
                   "NAME.nc cites the dataset")
    s.add_argument("--format", choices=["both", "bibtex", "csl"], default="both")
    s.set_defaults(func=cmd_cite_naming_others)


def _add_orders(sub) -> None:
    """The ``debench orders`` subcommand (problem ``mms_electroelastic``)."""
    from debench.reference.mms_check import FINEST_LEVELS, cmd_orders

    s = sub.add_parser("orders", help="fit the orders of convergence of a manufactured-"
                       "solution study (CSV: h or ndof, [degree], u_L2, u_H1, phi_L2, "
                       "phi_H1) and judge them (problem mms_electroelastic)")
    s.add_argument("table", help="CSV, one row per mesh level")
    s.add_argument("--degree", type=int, help="polynomial degree (or a degree column)")
    s.add_argument("--dim", type=int, help="space dimension when the table gives ndof")
    s.add_argument("--finest", type=int, default=FINEST_LEVELS,
                   help="finest levels fitted (default %(default)s)")
    s.add_argument("--write", metavar="CSV", help="write the fitted orders as a table "
                   "`debench check mms_electroelastic` reads")
    s.set_defaults(func=cmd_orders)


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
    for add in (_add_list, _add_reproduce, _add_verify, _add_report, _add_problems,
                _add_check, _add_orders, _add_cite):
        add(sub)
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
