"""Try bad input on every public callable of ``debench.models`` (except Chapter 5).

Every value listed for every argument in ``verification/fuzz_registry.py`` (NaN, +-inf,
0, negatives, 1e300, wrong shapes and types, det F <= 0, stretches out of range,
non-finite tolerances, zero iteration counts) is tried once, with the other arguments
valid. Prints the counts of outcomes:

* clear    -- ValueError / TypeError / ConvergenceError raised by debench code;
* unclear  -- a foreign exception, or one raised from inside numpy/scipy;
* silent   -- NaN/inf returned, or a result returned for an invalid input;
* ok       -- an extreme but admissible input gave a finite result;
* slow     -- runs over ``--timeout`` seconds (60 by default; interrupted).

Usage: ``python tools/fuzz_report.py [--list silent,unclear] [--skip MODULE] [--only S]``.
"""

from __future__ import annotations

import argparse
import collections
import os
import signal
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from verification import fuzz_registry as reg  # noqa: E402


class _Timeout(Exception):
    pass


def _alarm(signum, frame):
    raise _Timeout


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--timeout", type=float, default=60.0)
    ap.add_argument("--list", default="silent,unclear",
                    help="comma-separated outcomes to list one per line")
    ap.add_argument("--skip", action="append", default=[],
                    help="skip cases whose name starts with this prefix")
    ap.add_argument("--only", default="", help="only cases whose name contains this")
    args = ap.parse_args(argv)
    signal.signal(signal.SIGALRM, _alarm)
    counts = collections.Counter()
    invalid_counts = collections.Counter()
    listing = []
    cases = [c for c in reg.cases() if args.only in c.name
             and not any(c.name.startswith(s) for s in args.skip)]
    t0 = time.perf_counter()
    for case in cases:
        for arg, value, invalid in [(None, None, False), *case.inputs()]:
            t = time.perf_counter()
            signal.setitimer(signal.ITIMER_REAL, args.timeout)
            try:
                outcome, detail = reg.classify(case, arg, value, invalid)
            except _Timeout:
                outcome, detail = "slow", f"> {args.timeout:g} s"
            finally:
                signal.setitimer(signal.ITIMER_REAL, 0)
            if outcome == "foreign":
                outcome = "unclear"
            if arg is None:  # the valid call itself
                outcome = "valid_" + outcome
            dt = time.perf_counter() - t
            counts[outcome] += 1
            if invalid:
                invalid_counts[outcome] += 1
            shown = repr(value) if not hasattr(value, "shape") else (
                f"array{value.shape}")
            if outcome.removeprefix("valid_") in args.list.split(",") or (
                    outcome.startswith("valid_") and outcome != "valid_ok"):
                listing.append(f"{outcome:8s} {case.name}({arg}={shown[:40]}) "
                               f"[{dt:.1f}s] {detail}")
    for line in listing:
        print(line)
    tried = sum(v for k, v in counts.items() if not k.startswith("valid_"))
    n_inv = sum(invalid_counts.values())
    print(f"\ncallables: {len(cases)}   inputs tried: {tried} "
          f"({n_inv} invalid, {tried - n_inv} extreme)   time {time.perf_counter() - t0:.0f} s")
    for k in ("clear", "unclear", "silent", "ok", "slow"):
        share = 100 * counts[k] / tried if tried else 0.0
        print(f"  {k:8s} {counts[k]:5d}  ({share:5.1f} %)   of invalid: {invalid_counts[k]}")
    bad_valid = {k: v for k, v in counts.items() if k.startswith("valid_") and k != "valid_ok"}
    print(f"  valid calls that failed: {sum(bad_valid.values())} {dict(bad_valid) or ''}")
    return 0 if counts["unclear"] + counts["silent"] + counts["slow"] == 0 else 1


if __name__ == "__main__":
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    sys.exit(main())
