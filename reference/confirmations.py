"""What the confirmations of the reference problems measured (``reference/confirmations.json``).

Every quantity of a reference problem states in its spec how its reference values are
confirmed (``[[quantity.confirmation]]``, :attr:`debench.reference.problems.Quantity.confirmation`):
a second computation that shares no code with the reference, the test asserting their
agreement at the stated accuracy and the command reproducing it, or ``status = "missing"``
with the reason. ``python tools/confirm.py [--full]`` runs each confirmation's computation
and writes what it measured here: per problem and quantity the largest |difference| between
the reference and the independent values, its largest ratio to the stated accuracy, the CPU
seconds, the git commit, the date, the sha256 of the datasets compared with and the command.
Nothing in this file is typed by hand (``verification/test_confirmations.py`` checks it
against the specs and recomputes the cheap ones).
"""

from __future__ import annotations

import json
from functools import cache
from pathlib import Path
from typing import Any

PATH = Path(__file__).resolve().parent / "confirmations.json"
#: fields of a spec record that the JSON repeats (what was run)
SPEC_FIELDS = ("status", "method", "implementation", "test", "tier", "command", "covers",
               "gap", "reason")


@cache
def load(path: Path = PATH) -> dict[str, Any]:
    """The measured confirmations: ``{"problems": {id: {quantity: [record, ...]}}, ...}``
    (an empty ``problems`` mapping when the file does not exist)."""
    if not Path(path).exists():
        return {"problems": {}}
    return json.loads(Path(path).read_text(encoding="utf-8"))


def measured(problem_id: str, quantity: str, test: str) -> dict[str, Any] | None:
    """The JSON record of ``test`` for one quantity (None: not measured)."""
    recs = load()["problems"].get(problem_id, {}).get(quantity, [])
    return next((r for r in recs if r.get("test") == test and "ratio" in r), None)


def records(problem_id: str, quantity) -> list[dict[str, Any]]:
    """The confirmations of a quantity as users see them: each spec record with, for a
    confirmed one, what its last run measured (``measured``: None when never run)."""
    out = []
    for spec in quantity.confirmation:
        rec = dict(spec)
        if spec["status"] == "confirmed":
            m = measured(problem_id, quantity.name, spec["test"])
            rec["measured"] = None if m is None else {
                k: m[k] for k in ("points", "max_abs_difference", "ratio", "worst_at",
                                  "cpu_seconds", "shared_with", "commit", "date",
                                  "datasets") if k in m}
        out.append(rec)
    return out


def _g(x: float) -> str:
    return f"{x:.2g}"


def summary(rec: dict[str, Any]) -> str:
    """One line: ``confirmed by ...: max |difference| 3.4e-14 = 0.0021 of the stated
    accuracy, 1.2 s CPU`` or ``missing: reason``."""
    if rec["status"] == "missing":
        return f"missing: {rec['reason']}"
    m = rec.get("measured")
    if m is None:
        return f"confirmed by {rec['implementation']} (not measured yet: python tools/confirm.py)"
    return (f"{rec['implementation']}: max |difference| {_g(m['max_abs_difference'])}, "
            f"{_g(m['ratio'])} of the stated accuracy, {m['cpu_seconds']:.3g} s CPU "
            f"({m['points']} values; commit {m['commit'][:10]}, {m['date']})")
