"""The thesis catalogue: every number the thesis states, with provenance, and its status.

The catalogue lives in human-editable TOML files in ``reference/catalogue/`` (one per
chapter plus ``literature.toml``). Each ``[[entry]]`` has

========================  ==============================================================
``id``                    stable identifier, ``ch3.pullin.voltage_lamP_1p25``; users script
                          against it, never rename
``kind``                  ``claim`` | ``erratum`` | ``assumption`` | ``literature``
``quantity``              the quantity in words
``value``                 the thesis' (or the source's) value: number, string or bool
``printed``               the value exactly as printed (its digits set the tolerance)
``unit``                  UDUNITS string; ``"1"`` dimensionless, ``"%"`` percent
``source``                table: ``chapter``, ``section``, ``equation``, ``figure``,
                          ``table``, ``page`` (thesis page number as printed)
``parameters``            table of the model parameters that produce the value
``producer``              ``"module:function"`` computing our value (absent: pending)
``expected_status``       the status the code is known to produce; ``debench verify``
                          fails when the computed status differs (a regression)
``tolerance``             optional explicit absolute tolerance, *only* with
                          ``tolerance_reason`` (e.g. value read off a figure)
``diagnosis``             why a value does not reproduce (errata, missing parameter ...)
``evidence``              test node id that shows the status (errata: required)
``as_printed``            errata: the printed form;  ``corrected``: the consistent form
``reference``             literature: the citation (derived: the closed form used)
``replaces``              an earlier id of the same entry (still resolved by ``by_id``)
``root_cause``            errata (required with a status): the id of the erratum that is
                          the root error (its own id for a root); any other entry whose
                          status follows from an erratum names that root too
========================  ==============================================================

A producer is a function ``f(entry) -> Outcome``. It must be quick (seconds) so that
``debench verify`` can run every producer; producers of finite-element claims read the
stored datasets instead of recomputing.

Every producer module states the accuracy of the values its methods compute
(``ACCURACY``, an :class:`Accuracy`; an :class:`Outcome` may carry a narrower one). Our
values are stored once with that tolerance (``data/our_values.nc``,
:mod:`debench.reference.values`), and ``debench verify`` fails when a recomputed value
leaves it, whatever its status.
"""

from __future__ import annotations

import hashlib
import importlib
import math
import re
import tomllib
from collections.abc import Iterable
from dataclasses import dataclass, field, replace
from decimal import Decimal, InvalidOperation
from pathlib import Path
from typing import Any

CATALOGUE_DIR = Path(__file__).resolve().parent / "catalogue"
#: claim: a number or statement printed in the thesis; erratum: a printed equation or text
#: that is wrong (or checked and right); assumption: a value the thesis does not state;
#: literature: a number printed in a cited source (``lit.*``, only in literature.toml);
#: derived: a value implied by stated inputs or closed forms but printed nowhere (checked,
#: never presented as a thesis or literature number); diagnosis: a hypothesis about why
#: a thesis number does not reproduce, tested against that number (ids
#: ``<chapter>.hypothesis.<name>.<quantity>``; parameter ``target`` names the claim).
KINDS = ("claim", "erratum", "assumption", "literature", "derived", "diagnosis")
STATUSES = (
    "reproduced",        # our value agrees within the tolerance the printed digits imply
    "not_reproduced",    # our value differs; diagnosis says why
    "not_reproducible",  # the thesis lacks information needed to compute it (named)
    "pending",           # no model yet
    "confirmed",         # erratum: the printed form is wrong, evidence shows it
    "refuted",           # erratum: on checking, the printed form is right after all
    "editorial",         # erratum: a wrong cross-reference or label, no effect on results
    "explained",         # diagnosis: the hypothesis gives the thesis number to its digits
    "unexplained",       # diagnosis: it does not
    "assumed",           # assumption: the value we use where the thesis is silent
    "input",             # a stated parameter; the models use exactly it (transcription
                         # checked), so there is nothing to reproduce
    "not_comparable",    # a setting of ours (discretisation, element type) that the thesis
                         # states differently for its own method: neither a result nor a
                         # failure to reproduce one (the diagnosis gives the reason)
    "error",             # the producer raised: always a regression
)
_ID = re.compile(r"^(ch[2-5]|app|lit)\.[a-z0-9_]+(\.[a-zA-Z0-9_]+)*$")


class CatalogueError(ValueError):
    """The catalogue files are malformed (bad id, kind, duplicate, missing field)."""


@dataclass(frozen=True)
class Accuracy:
    """How far a recomputed value may move: ``|new - stored| <= atol + rtol |stored|``.

    ``reason`` names what sets it (solver tolerance, mesh error, round-off floor), so that
    the guard is never tighter than the method supports nor looser than it needs to be.
    """

    rtol: float
    atol: float
    reason: str

    def __post_init__(self):
        for name in ("rtol", "atol"):
            x = getattr(self, name)
            if not (isinstance(x, int | float) and math.isfinite(x) and x >= 0):
                raise ValueError(f"Accuracy.{name} = {x!r} must be finite and >= 0")
        if self.rtol == 0 and self.atol == 0:
            raise ValueError("Accuracy needs rtol > 0 or atol > 0")
        if not self.reason:
            raise ValueError("Accuracy needs a reason")

    def tolerance(self, value: float) -> float:
        """Absolute tolerance at ``value``."""
        return self.atol + self.rtol * abs(float(value))


@dataclass(frozen=True)
class Outcome:
    """What a producer returns.

    ``value`` is our number (or bool for a qualitative claim: does the statement hold?).
    ``status`` may be set explicitly (``not_reproducible``, ``confirmed``, ...); otherwise
    it is computed from ``value`` against the entry's tolerance.
    """

    value: float | bool | str | None
    status: str | None = None
    diagnosis: str = ""
    evidence: str = ""
    details: dict[str, Any] = field(default_factory=dict)
    accuracy: Accuracy | None = None


@dataclass(frozen=True)
class Entry:
    id: str
    kind: str
    quantity: str
    value: Any = None
    printed: str = ""
    unit: str = "1"
    source: dict[str, Any] = field(default_factory=dict)
    parameters: dict[str, Any] = field(default_factory=dict)
    producer: str = ""
    expected_status: str = "pending"
    tolerance: float | None = None
    tolerance_reason: str = ""
    diagnosis: str = ""
    evidence: str = ""
    as_printed: str = ""
    corrected: str = ""
    reference: str = ""
    replaces: str = ""
    root_cause: str = ""
    notes: str = ""
    file: str = ""

    @property
    def thesis_value(self) -> Any:
        """The printed value (for an erratum: the printed equation number)."""
        if self.kind == "erratum":
            return self.source.get("equation", "")
        return self.value

    def implied_tolerance(self) -> float | None:
        """Absolute tolerance: explicit, or half a unit in the last printed digit."""
        if self.tolerance is not None:
            return float(self.tolerance)
        return printed_half_ulp(self.printed or self.value)

    def load_producer(self):
        module, _, func = self.producer.partition(":")
        if not module or not func:
            raise CatalogueError(f"{self.id}: producer {self.producer!r} is not 'module:function'")
        return getattr(importlib.import_module(module), func)

    def producer_accuracy(self) -> Accuracy | None:
        """The ``ACCURACY`` of the producer's module (``None`` without a producer)."""
        if not self.producer:
            return None
        mod = importlib.import_module(self.producer.partition(":")[0])
        acc = getattr(mod, "ACCURACY", None)
        if not isinstance(acc, Accuracy):
            raise CatalogueError(f"{self.id}: producer module {mod.__name__} lacks ACCURACY")
        return acc


def printed_half_ulp(printed: Any) -> float | None:
    """Half a unit in the last printed decimal place: ``"0.518"`` -> ``5e-4``.

    Returns ``None`` for non-numeric values.
    """
    if isinstance(printed, bool) or printed is None:
        return None
    text = str(printed).strip().replace("−", "-").rstrip("%").strip()
    try:
        dec = Decimal(text)
    except InvalidOperation:
        return None
    exponent = dec.as_tuple().exponent
    if not isinstance(exponent, int):
        return None
    return 0.5 * 10.0**exponent


# --------------------------------------------------------------------------- loading
_ENTRY_FIELDS = set(Entry.__dataclass_fields__) - {"file"}


def load(directory: Path = CATALOGUE_DIR) -> list[Entry]:
    """All catalogue entries, validated, in file then file order.

    The files are parsed once per process and content: the parsed entries are memoised
    on the directory and the bytes of its ``*.toml`` files (a sha256 of each), so an edit
    of a file is seen by the next call while repeated calls (producers resolving a target
    id, the report, the CLI) cost one read of the files. Every call returns a new list of
    the same (frozen) entries: their tables (``parameters``, ``source``) are shared and
    must not be mutated.
    """
    directory = Path(directory).resolve()
    files = tuple((path.name, path.read_bytes())
                  for path in sorted(directory.glob("*.toml")))
    key = (str(directory), tuple((name, hashlib.sha256(text).hexdigest())
                                 for name, text in files))
    cached = _LOADED.get(key)
    if cached is None:
        cached = parse_files(files)
        _LOADED.clear()   # one content per directory and process is all that is reused
        _LOADED[key] = cached
    return list(cached)


#: parsed entries by (directory, file names and content digests): see :func:`load`
_LOADED: dict[tuple, tuple[Entry, ...]] = {}


def parse_files(files: tuple[tuple[str, bytes], ...]) -> tuple[Entry, ...]:
    """Entries of the catalogue files given as (name, bytes), validated; parsed on every
    call (:func:`load` memoises it on the files' content)."""
    entries: list[Entry] = []
    seen: dict[str, str] = {}
    for name, text in files:
        try:
            doc = tomllib.loads(text.decode("utf-8"))
        except tomllib.TOMLDecodeError as exc:
            raise CatalogueError(f"{name}: {exc}") from exc
        for raw in doc.get("entry", []):
            unknown = set(raw) - _ENTRY_FIELDS
            if unknown:
                raise CatalogueError(
                    f"{name}: {raw.get('id')}: unknown fields {sorted(unknown)}")
            if raw.get("kind") == "assumption" and "expected_status" not in raw:
                raw = {**raw, "expected_status": "assumed"}
            try:
                entry = Entry(**raw, file=name)
            except TypeError as exc:
                raise CatalogueError(f"{name}: {raw.get('id')}: {exc}") from exc
            _validate(entry)
            if entry.id in seen:
                raise CatalogueError(
                    f"duplicate id {entry.id!r} in {name} and {seen[entry.id]}")
            seen[entry.id] = name
            entries.append(entry)
    _validate_root_causes(entries)
    return tuple(entries)


def _validate_root_causes(entries: list[Entry]) -> None:
    """Every erratum with a status names its root error; a root names itself; every
    ``root_cause`` is the id of an erratum that is its own root (no chains)."""
    errata = {e.id: e for e in entries if e.kind == "erratum"}
    for e in entries:
        where = f"{e.file}: {e.id}"
        if e.kind == "erratum" and e.expected_status != "pending" and not e.root_cause:
            raise CatalogueError(f"{where}: an erratum with a status needs a root_cause "
                                 "(its own id when it is the root error)")
        if not e.root_cause:
            continue
        root = errata.get(e.root_cause)
        if root is None:
            raise CatalogueError(f"{where}: root_cause {e.root_cause!r} is not an erratum")
        if root.root_cause != root.id:
            raise CatalogueError(f"{where}: root_cause {e.root_cause!r} is not a root "
                                 f"(it names {root.root_cause!r})")


def _validate(e: Entry) -> None:
    where = f"{e.file}: {e.id}"
    if not _ID.match(e.id):
        raise CatalogueError(f"{where}: id must match {_ID.pattern}")
    if e.kind not in KINDS:
        raise CatalogueError(f"{where}: kind {e.kind!r} not in {KINDS}")
    if not e.quantity:
        raise CatalogueError(f"{where}: 'quantity' (in words) is required")
    if e.expected_status not in STATUSES:
        raise CatalogueError(f"{where}: expected_status {e.expected_status!r} not in {STATUSES}")
    if e.tolerance is not None and not e.tolerance_reason:
        raise CatalogueError(f"{where}: an explicit tolerance needs a tolerance_reason")
    if e.kind in ("claim", "erratum") and not e.source:
        raise CatalogueError(f"{where}: thesis entries need a source (section/equation/page)")
    if e.kind == "erratum" and not (e.as_printed and e.corrected):
        raise CatalogueError(f"{where}: an erratum needs as_printed and corrected")
    if e.kind == "erratum" and not e.evidence and e.expected_status != "pending":
        raise CatalogueError(f"{where}: an erratum with a status needs evidence (a test)")
    if e.kind == "literature" and not e.reference:
        raise CatalogueError(f"{where}: a literature value needs a reference")
    if (e.kind == "literature") != e.id.startswith("lit."):
        raise CatalogueError(f"{where}: ids lit.* are exactly the literature entries")
    if e.kind == "literature" and e.file != "literature.toml":
        raise CatalogueError(f"{where}: literature entries live in literature.toml")
    if e.kind == "diagnosis" and not e.parameters.get("target"):
        raise CatalogueError(f"{where}: a diagnosis names its target claim (parameters.target)")
    if e.kind == "derived" and not (e.reference or e.source):
        raise CatalogueError(f"{where}: a derived value needs its reference or source")
    if e.kind == "assumption" and not e.diagnosis and not e.notes:
        raise CatalogueError(f"{where}: an assumption must say why (diagnosis or notes)")


def by_id(entries: Iterable[Entry] | None = None) -> dict[str, Entry]:
    """Entries by id; an entry's earlier id (``replaces``) resolves to it too."""
    entries = list(entries if entries is not None else load())
    out = {e.replaces: e for e in entries if e.replaces}
    out.update({e.id: e for e in entries})
    return out


# --------------------------------------------------------------------------- status
@dataclass(frozen=True)
class Result:
    """An entry beside our value: one row of ``debench verify``."""

    entry: Entry
    value: Any
    status: str
    diagnosis: str
    evidence: str = ""
    details: dict[str, Any] = field(default_factory=dict)
    accuracy: Accuracy | None = None

    @property
    def regressed(self) -> bool:
        return self.status == "error" or self.status != self.entry.expected_status

    def as_json(self) -> dict[str, Any]:
        e = self.entry
        return {
            "kind": e.kind, "id": e.id, "quantity": e.quantity,
            "thesis_value": _jsonable(e.thesis_value), "value": _jsonable(self.value),
            "unit": e.unit, "status": self.status, "expected_status": e.expected_status,
            "diagnosis": self.diagnosis, "tolerance": e.implied_tolerance(),
            "evidence": self.evidence or e.evidence, "source": e.source,
            "parameters": e.parameters, "root_cause": e.root_cause,
        }


def _jsonable(v: Any) -> Any:
    if isinstance(v, float) and not math.isfinite(v):
        return None
    if hasattr(v, "item"):
        return v.item()
    return v


def readable(value: Any, digits: int = 6) -> str:
    """A value as prose quotes it: numbers (numpy scalars too) to ``digits`` significant
    digits, a mapping as ``key = value`` pairs, a sequence or array comma-separated (in
    parentheses when nested), never a Python repr (``np.float64(...)``, ``{'...': ...}``).

    Parameters
    ----------
    value : Any
        A number, bool, string, mapping, sequence or numpy array (nested freely).
    digits : int, optional
        Significant digits of every float.

    Returns
    -------
    str
        E.g. ``readable({"derived": 1.0, "literal": 0.9999999994444345}, 11)`` is
        ``"derived = 1, literal = 0.99999999944"``.
    """
    def one(v: Any, nested: bool) -> str:
        if hasattr(v, "tolist") and not isinstance(v, list | tuple | str):
            v = v.tolist()  # a numpy array or scalar: nested lists or a Python number
        if isinstance(v, bool | str) or v is None:
            return str(v)
        if isinstance(v, int):
            return str(v)
        if isinstance(v, float):
            return f"{v:.{digits}g}"
        if isinstance(v, dict):
            text = ", ".join(f"{one(k, True)} = {one(x, True)}" for k, x in v.items())
        elif isinstance(v, list | tuple):
            text = ", ".join(one(x, True) for x in v)
        else:
            return str(v)
        return f"({text})" if nested else text

    return one(value, False)


def render(text: str, value: Any, details: dict[str, Any]) -> str:
    """Fill a catalogue diagnosis with our computed numbers.

    Diagnoses quote our values only through placeholders - ``{value:.4g}`` or
    ``{details[membrane]:.4f}`` - so that prose never holds a number that nothing checks.
    """
    if "{" not in text:
        return text
    try:
        return text.format(value=value, details=details)
    except (KeyError, IndexError, ValueError, TypeError) as exc:
        raise CatalogueError(
            f"diagnosis placeholder cannot be filled ({exc!r}): {text!r}") from exc


def judge(entry: Entry, outcome: Outcome) -> Result:
    """Status of an entry given a producer's outcome (see :data:`STATUSES`)."""
    diagnosis = outcome.diagnosis or entry.diagnosis
    if entry.diagnosis and entry.diagnosis in diagnosis:  # the catalogue's template
        diagnosis = diagnosis.replace(
            entry.diagnosis, render(entry.diagnosis, outcome.value, outcome.details))
    if outcome.status == "input":
        # A model input: its value must equal the stated one, but agreement is not a
        # reproduction of anything.
        tol = entry.implied_tolerance() or 0.0
        same = (outcome.value == entry.value if not isinstance(entry.value, int | float)
                else abs(float(outcome.value) - float(entry.value)) <= tol * (1 + 1e-12))
        if not same:
            return Result(entry, outcome.value, "not_reproduced",
                          f"the models use {outcome.value!r}, the thesis states "
                          f"{entry.value!r}", outcome.evidence, outcome.details)
    if outcome.status == "not_comparable":
        # a setting of ours beside the thesis' setting: the same one is an input, a
        # different one describes another method (not a result to reproduce)
        tol = entry.implied_tolerance() or 0.0
        same = (outcome.value == entry.value if not isinstance(entry.value, int | float)
                else abs(float(outcome.value) - float(entry.value)) <= tol * (1 + 1e-12))
        return Result(entry, outcome.value, "input" if same else "not_comparable", diagnosis,
                      outcome.evidence, outcome.details)
    if outcome.status is not None:
        if outcome.status not in STATUSES:
            raise CatalogueError(f"{entry.id}: producer returned unknown status {outcome.status!r}")
        return Result(entry, outcome.value, outcome.status, diagnosis, outcome.evidence,
                      outcome.details)
    value = outcome.value
    if entry.value is None and (value is not None or outcome.details):
        # the thesis states no number here (e.g. only in a figure image): our value is
        # reported, and the status says that nothing printed can be compared with it
        return Result(entry, value, "not_reproducible", diagnosis, outcome.evidence,
                      outcome.details)
    if entry.kind == "erratum" and isinstance(value, bool):
        # an erratum's value: the printed form is wrong (and the correction holds)
        return Result(entry, value, "confirmed" if value else "refuted", diagnosis,
                      outcome.evidence, outcome.details)
    if isinstance(value, bool):
        status = "reproduced" if value else "not_reproduced"
        return Result(entry, value, status, "" if value else diagnosis, outcome.evidence,
                      outcome.details)
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return Result(entry, None, "pending", diagnosis, outcome.evidence, outcome.details)
    tol = entry.implied_tolerance()
    thesis = entry.value
    if tol is None or not isinstance(thesis, int | float):
        raise CatalogueError(f"{entry.id}: numeric outcome for a non-numeric thesis value")
    diff = float(value) - float(thesis)
    if abs(diff) <= tol * (1 + 1e-12):
        return Result(entry, float(value), "reproduced", "", outcome.evidence, outcome.details)
    auto = (f"ours {float(value):.6g} vs thesis {thesis} {entry.unit} "
            f"(diff {diff:+.3g}, tol {tol:.2g})")
    return Result(entry, float(value), "not_reproduced",
                  f"{auto}; {diagnosis}" if diagnosis else auto, outcome.evidence, outcome.details)


def evaluate(entry: Entry) -> Result:
    """Run the entry's producer (if any) and judge the outcome. Never raises."""
    if entry.kind == "assumption" and not entry.producer:
        return Result(entry, entry.value, "assumed", entry.diagnosis or entry.notes)
    if not entry.producer:
        return Result(entry, None, "pending", entry.diagnosis)
    try:
        outcome = entry.load_producer()(entry)
        if not isinstance(outcome, Outcome):
            raise TypeError(f"producer returned {type(outcome).__name__}, not Outcome")
        accuracy = outcome.accuracy or entry.producer_accuracy()
        return replace(judge(entry, outcome), accuracy=accuracy)
    except Exception as exc:  # noqa: BLE001 - reported as status "error", never hidden
        return Result(entry, None, "error", f"{type(exc).__name__}: {exc}")


def evaluate_all(entries: Iterable[Entry] | None = None, progress=None) -> list[Result]:
    entries = list(entries if entries is not None else load())
    it = progress(entries) if progress is not None else entries
    return [evaluate(e) for e in it]
