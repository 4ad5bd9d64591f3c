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
import hashlib
import importlib
import os
import pkgutil
import sys
from pathlib import Path

from debench.reference import builds, catalogue, provenance
from debench.reference.mms_check import FINEST_LEVELS
from debench.reference.results_files import (  # noqa: F401 - the exit codes, for callers
    EXIT_FAILED,
    EXIT_OK,
    EXIT_RUNTIME,
    EXIT_USAGE,
    UsageError,
)

from debench import __version__, models
from debench.threads import limit_threads

CHAPTERS = builds.chapters()
DEFAULT_OUT = Path("results")
#: the function that runs each subcommand, ``"module:function"`` taking the parsed
#: arguments and returning the exit code; its module is imported when the subcommand runs
#: (:func:`command`), so that ``debench --help`` and each subcommand load only what they use
COMMANDS = {
    "list": "debench.reference.cli:cmd_list",
    "reproduce": "debench.reference.cli_reproduction:cmd_reproduce",
    "verify": "debench.reference.cli_reproduction:cmd_verify",
    "report": "debench.reference.cli_reproduction:cmd_report",
    "problems": "debench.reference.cli_users:cmd_problems",
    "check": "debench.reference.cli_users:cmd_check",
    "orders": "debench.reference.mms_check:cmd_orders",
    "cite": "debench.reference.cli_cite:cmd_cite_naming_others",
}


def command(name: str):
    """The function that runs the subcommand ``name`` (:data:`COMMANDS`), its module
    imported."""
    module, _, function = COMMANDS[name].partition(":")
    return getattr(importlib.import_module(module), function)


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
        entries = catalogue.load()
        print(f"catalogue ({len(entries)} entries):")
        for e in entries:
            print(f"  {e.kind:11s} {e.id:55s} {e.printed or e.value!s:>10} {e.unit}")
    return 0


# --------------------------------------------------------------------------- main
def version_string() -> str:
    """``debench X (commit C; data manifest sha256 D)``: what ``--version`` prints."""
    from debench.reference.datasets import MANIFEST_NAME, data_dir

    manifest = data_dir() / MANIFEST_NAME
    digest = (hashlib.sha256(manifest.read_bytes()).hexdigest()[:16]
              if manifest.is_file() else f"none ({manifest} missing)")
    return (f"debench {__version__} (commit {provenance.git_commit()}; "
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


def _add_report(sub) -> None:
    """The ``debench report`` subcommand."""
    s = sub.add_parser("report", help="write the markdown report (and README table)")
    s.add_argument("--out", default=str(DEFAULT_OUT), help="directory of REPORT.md")
    s.add_argument("--readme", action="store_true", help="also regenerate the README table")
    s.add_argument("--datacard", action="store_true", help="also regenerate data/README.md")


def _add_problems(sub) -> None:
    """The ``debench problems`` subcommand."""
    s = sub.add_parser("problems", help="list reference problems or print one (spec, "
                       "reference values, accuracy)")
    s.add_argument("id", nargs="?", help="problem id (default: list all)")
    s.add_argument("--json", action="store_true", help="JSON: the spec and, per quantity, "
                   "reference coordinates, values, units and accuracy")
    s.add_argument("--markdown", action="store_true", help="the problem page (markdown): "
                   "everything needed to implement the problem and check it")


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
    s.set_defaults(check_parser=s)


def _add_cite(sub) -> None:
    """The ``debench cite`` subcommand."""
    s = sub.add_parser("cite", help="BibTeX and CSL-JSON for a catalogue entry, dataset "
                       "or reference problem")
    s.add_argument("id", help="catalogue id, dataset name or problem id; a name that is "
                   "both a problem and a dataset cites the problem (and says so on stderr), "
                   "NAME.nc cites the dataset")
    s.add_argument("--format", choices=["both", "bibtex", "csl"], default="both")


def _add_orders(sub) -> None:
    """The ``debench orders`` subcommand (problem ``mms_electroelastic``)."""
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
        limit_threads(args.threads)
        if not sys.stderr.isatty():  # progress bars only on a terminal (never in logs)
            os.environ.setdefault("TQDM_DISABLE", "1")
        return int(command(args.command)(args) or 0)
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
