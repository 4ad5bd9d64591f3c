"""Our values, stored once with the tolerance their method supports, and their guard.

Every value the catalogue producers compute - the main value of an entry and every
numeric or boolean item of its ``details`` - is a *guarded value*: a key, the value, and
the absolute tolerance its method supports (the producer module's
:class:`~debench.reference.catalogue.Accuracy`). Chapters may add guarded values that are
not catalogue entries (the model guards each builder declares in ``GUARDS``,
:func:`~debench.reference.builds.properties`: e.g. the Chapter 5 finite-element model
recomputed on its coarsest mesh).

The store is one committed dataset, ``our_values.nc`` in the data directory, written by
``debench reproduce --write-data`` (builder ``catalogue``). :func:`check` compares a
recomputation with it and returns one :class:`Deviation` per value that left its
tolerance, appeared, disappeared or changed status; ``debench verify`` prints them as a
table and exits non-zero.

Keys: the entry id for the main value, ``<id>#<path>`` for an item of ``details``
(``path`` joins nested keys and list indices with ``.``), ``<chapter>.guard.<name>`` for
the extra guards.
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
from debench.reference import builds
from debench.reference.catalogue import Accuracy, Result
from debench.reference.datasets import read_dataset

STORE_NAME = "our_values"

@dataclass(frozen=True)
class Guarded:
    """One value and how far a recomputation may move it."""

    key: str
    value: float | str
    tolerance: float        # absolute; 0 for text (compared exactly)
    reason: str
    status: str = ""        # the entry's status (main values only)

    @property
    def numeric(self) -> bool:
        return not isinstance(self.value, str)


@dataclass(frozen=True)
class Deviation:
    """A guarded value that left its tolerance (or appeared, disappeared, changed status)."""

    key: str
    stored: Any
    recomputed: Any
    tolerance: float | None
    what: str               # "value", "status", "missing", "new"

    def line(self) -> str:
        def fmt(x):
            if isinstance(x, float):
                return f"{x:.10g}"
            return "-" if x is None else str(x)

        diff = ""
        if self.what == "value" and isinstance(self.stored, float) and isinstance(
                self.recomputed, float):
            diff = f"{self.recomputed - self.stored:+.3g}"
        tol = "-" if self.tolerance is None else f"{self.tolerance:.2g}"
        return (f"| `{self.key}` | {self.what} | {fmt(self.stored)} | {fmt(self.recomputed)} "
                f"| {diff} | {tol} |")


TABLE_HEADER = ("| value | what | stored | recomputed | difference | tolerance |\n"
                "|---|---|---|---|---|---|")


# --------------------------------------------------------------------------- flattening
def flatten(prefix: str, obj: Any) -> Iterable[tuple[str, Any]]:
    """The leaves of nested mappings, sequences and arrays as ``(path, leaf)`` pairs:
    ``path`` the dotted keys and indices below ``prefix`` (mapping keys in sorted order,
    an array as its nested list), ``leaf`` any other object."""
    if isinstance(obj, Mapping):
        for k in sorted(obj, key=str):
            yield from flatten(f"{prefix}.{k}" if prefix else str(k), obj[k])
    elif isinstance(obj, list | tuple):
        for i, x in enumerate(obj):
            yield from flatten(f"{prefix}.{i}" if prefix else str(i), x)
    elif isinstance(obj, np.ndarray):
        yield from flatten(prefix, obj.tolist())
    else:
        yield prefix, obj


def _scalar(x: Any) -> float | str | None:
    """A guardable scalar: float (finite), text for bool/str, ``None`` otherwise."""
    if isinstance(x, bool | np.bool_):
        return str(bool(x))
    if isinstance(x, int | float | np.integer | np.floating):
        x = float(x)
        return x if math.isfinite(x) else "non-finite"
    if isinstance(x, str):
        return x
    return None


def guarded_from_results(results: Iterable[Result]) -> list[Guarded]:
    """Guarded values of catalogue results (main values and ``details`` items).

    Text in ``details`` is descriptive and not guarded; booleans are. A numeric value
    without an accuracy (an entry without producer: assumptions stated in the
    catalogue) is guarded exactly.
    """
    out: list[Guarded] = []
    for r in results:
        acc: Accuracy | None = r.accuracy
        main = _scalar(r.value)
        if main is None:
            main = "None"
        out.append(_guard(r.entry.id, main, acc, r.status))
        for path, x in flatten("", r.details):
            v = _scalar(x)
            if v is None or (isinstance(v, str) and v not in ("True", "False")):
                continue
            out.append(_guard(f"{r.entry.id}#{path}", v, acc, ""))
    return out


def _guard(key: str, value: float | str, acc: Accuracy | None, status: str) -> Guarded:
    if isinstance(value, str) or acc is None:
        return Guarded(key, value, 0.0, "exact" if acc is None else acc.reason, status)
    return Guarded(key, value, acc.tolerance(value), acc.reason, status)


def model_guard_names() -> tuple[str, ...]:
    """The model guards every builder declares (``GUARDS``), in the chapters' order."""
    return tuple(builds.model_guards(builds.chapters()))


def extra_guards(names: Iterable[str] | None = None) -> list[Guarded]:
    """Run the chapters' model guards (model recomputations that are not entries): those
    named (``module:function``), by default every builder's (:func:`model_guard_names`)."""
    out: list[Guarded] = []
    for name in model_guard_names() if names is None else names:
        module, _, func = name.partition(":")
        fn: Callable[[], list[Guarded]] = getattr(importlib.import_module(module), func)
        out += fn()
    return out


# --------------------------------------------------------------------------- store
def store_dataset(guards: list[Guarded]) -> xr.Dataset:
    """The guarded values as a dataset (dimension ``key``), without global attributes."""
    keys = [g.key for g in guards]
    if len(set(keys)) != len(keys):
        dup = sorted({k for k in keys if keys.count(k) > 1})
        raise ValueError(f"duplicate guarded keys: {dup[:5]}")

    def text(values, long_name):
        return ("key", np.array(values, dtype=object), {"long_name": long_name})

    return xr.Dataset(
        {
            "value": ("key", np.array([g.value if g.numeric else np.nan for g in guards],
                                      dtype=float),
                      {"long_name": "our computed value (NaN when the value is text)",
                       "units": "1", "comment": "unit of the catalogue entry"}),
            "value_text": text([g.value if not g.numeric else "" for g in guards],
                               "our value as text (qualitative results; compared exactly)"),
            "tolerance": ("key", np.array([g.tolerance for g in guards], dtype=float),
                          {"long_name": "absolute tolerance of the value supported by its "
                                        "method", "units": "1",
                           "comment": "unit of the catalogue entry"}),
            "reason": text([g.reason for g in guards], "what sets the tolerance"),
            "status": text([g.status for g in guards],
                           "computed status of the catalogue entry (main values only)"),
        },
        coords={"key": ("key", np.array(keys, dtype=object),
                        {"long_name": "catalogue id, id#detail path, or chapter guard"})},
    )


def read_store(data_dir: Path | None = None) -> dict[str, Guarded]:
    """The committed guarded values (verified read of ``our_values.nc``)."""
    ds = read_dataset(STORE_NAME, data_dir=data_dir)
    out = {}
    for i, key in enumerate(ds.key.values.tolist()):
        text = str(ds.value_text.values[i])
        value: float | str = text if text else float(ds.value.values[i])
        out[key] = Guarded(key, value, float(ds.tolerance.values[i]),
                           str(ds.reason.values[i]), str(ds.status.values[i]))
    return out


# --------------------------------------------------------------------------- check
def check(recomputed: Iterable[Guarded], stored: Mapping[str, Guarded], *,
          complete: bool = True) -> list[Deviation]:
    """Deviations of a recomputation from the store.

    ``complete=False`` checks only the recomputed keys (a partial recomputation, e.g.
    one chapter); otherwise stored keys that were not recomputed are deviations too.
    """
    out: list[Deviation] = []
    seen = set()
    for g in recomputed:
        seen.add(g.key)
        s = stored.get(g.key)
        if s is None:
            out.append(Deviation(g.key, None, g.value, None, "new"))
            continue
        if g.status != s.status:
            out.append(Deviation(g.key, s.status, g.status, None, "status"))
        if s.numeric and g.numeric:
            if not abs(float(g.value) - float(s.value)) <= s.tolerance:
                out.append(Deviation(g.key, float(s.value), float(g.value), s.tolerance,
                                     "value"))
        elif g.value != s.value:
            out.append(Deviation(g.key, s.value, g.value, None, "value"))
    if complete:
        out += [Deviation(k, s.value, None, None, "missing")
                for k, s in stored.items() if k not in seen]
    return out


def table(deviations: list[Deviation], limit: int = 50) -> str:
    """A markdown table of deviations (at most ``limit`` rows, then a count)."""
    rows = [TABLE_HEADER] + [d.line() for d in deviations[:limit]]
    if len(deviations) > limit:
        rows.append(f"... and {len(deviations) - limit} more")
    return "\n".join(rows)
