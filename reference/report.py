"""Markdown report: each thesis claim beside our value and its status, with figures.

The README's status counts are generated here too (between the markers
``<!-- results:start -->`` and ``<!-- results:end -->``), and so is its verdict in brief
(between ``<!-- verdict:start -->`` and ``<!-- verdict:end -->``): the plain-language
verdict of ``verdict.md`` filled from the computed records (:func:`verdict_markdown`),
which the report and the documentation site's verdict page open with. A test checks both
are current.
"""

from __future__ import annotations

import datetime as _dt
import os
import re
import sys
from collections import Counter
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from debench.reference.catalogue import Result
from debench.reference.provenance import git_commit

START, END = "<!-- results:start -->", "<!-- results:end -->"
VERDICT_START, VERDICT_END = "<!-- verdict:start -->", "<!-- verdict:end -->"
#: the plain-language verdict with placeholders (its header comment says which)
VERDICT_TEMPLATE = Path(__file__).with_name("verdict.md")
STATUS_MARK = {
    "reproduced": "✅ reproduced", "not_reproduced": "❌ not reproduced",
    "not_reproducible": "⚠️ not reproducible", "pending": "⏳ pending",
    "confirmed": "📝 erratum confirmed", "refuted": "erratum refuted",
    "editorial": "✏️ editorial erratum",
    "explained": "🔎 explained", "unexplained": "🔎 unexplained",
    "assumed": "assumed", "input": "input (stated parameter)",
    "not_comparable": "↔️ not comparable (our setting)", "error": "💥 error",
}
CHAPTER_TITLES = {
    "ch2": "Chapter 2 and Appendix A: invariants and constitutive equations",
    "app": "Appendix A", "ch3": "Chapter 3: pre-stretched circular actuator",
    "ch4": "Chapter 4: bifurcation of the anisotropic plate",
    "ch5": "Chapter 5: buckling membrane actuator (finite elements)",
    "lit": "Literature reference values",
}


def format_value(value, unit: str = "") -> str:
    """A value as the report's tables print it: None as a dash, a bool as holds / does not
    hold, a float to 5 significant digits, a mapping as ``key = value`` pairs, a sequence
    comma-separated; whitespace collapsed, ``unit`` appended unless it is 1, empty or
    already ends the text, and ``|`` escaped for a markdown table."""
    if value is None:
        return "—"
    if isinstance(value, bool):
        return "holds" if value else "does not hold"
    if isinstance(value, float):
        text = f"{value:.5g}"
    elif isinstance(value, dict):  # never a raw Python dict: "key = value" pairs
        text = "; ".join(f"{k} = {format_value(v)}" for k, v in value.items())
    elif isinstance(value, list | tuple):
        text = ", ".join(format_value(v) for v in value)
    else:
        text = str(value)
    text = " ".join(text.split())
    unit = "" if unit in ("1", "") or text.endswith(unit) else f" {unit}"
    return (text + unit).replace("|", "\\|")


def _cell(text: str, width: int | None = 90) -> str:
    """A table cell on one line; ``width=None`` never shortens (errata, diagnoses)."""
    text = " ".join(str(text).split()).replace("|", "\\|")
    return text if width is None or len(text) <= width else text[: width - 1] + "…"


def status_counts(results: Iterable[Result]) -> Counter:
    return Counter(r.status for r in results)


#: The order statuses are counted in, everywhere.
STATUS_ORDER = ("reproduced", "not_reproduced", "not_reproducible", "pending", "confirmed",
                "refuted", "editorial", "explained", "unexplained", "assumed", "input",
                "not_comparable", "error")
#: The catalogue kinds the report counts apart, each beside its own table: a status means
#: something different in each (a thesis claim not reproduced is a finding about the
#: thesis; an own check not reproduced is a disagreement between our own models; a refuted
#: erratum is a printed form found right, not an erratum).
GROUPS = {
    "claims": ("claim", "literature"),
    "own checks": ("derived",),
    "errata": ("erratum",),
    "diagnoses": ("diagnosis",),
    "assumptions": ("assumption",),
}
#: How the counts sentences and the README tables name each group.
GROUP_LABELS = {
    "claims": "thesis claims and literature values",
    "own checks": "own checks of our models and derived values (not thesis claims)",
    "errata": "errata checked",
    "diagnoses": "diagnoses",
    "assumptions": "assumptions",
}


def in_group(results: Iterable[Result], group: str) -> list[Result]:
    """The results whose entry kind belongs to ``group`` (a key of :data:`GROUPS`)."""
    return [r for r in results if r.entry.kind in GROUPS[group]]


def count_text(results: Iterable[Result]) -> str:
    """The status counts of ``results``: ``"24 reproduced, 5 not reproduced"`` (in
    :data:`STATUS_ORDER`, only those that occur; ``"none"`` when there is none)."""
    counts = status_counts(results)
    return ", ".join(f"{counts[s]} {s.replace('_', ' ')}" for s in STATUS_ORDER
                     if counts[s]) or "none"


def count_sentence(group: str, results: Iterable[Result], capital: bool = True) -> str:
    """``"Thesis claims and literature values: 46 entries: 24 reproduced, ..."`` for the
    results of ``group`` among ``results`` (no final full stop)."""
    chosen = in_group(results, group)
    label = GROUP_LABELS[group]
    label = label[0].upper() + label[1:] if capital else label
    noun = "entry" if len(chosen) == 1 else "entries"
    return f"{label}: {len(chosen)} {noun}: {count_text(chosen)}"


def results_table(results: Iterable[Result], kinds=("claim", "literature")) -> str:
    """Markdown table: thesis claim, thesis value, our value, status."""
    rows = ["| id | thesis claim | thesis value | our value | status |",
            "|---|---|---|---|---|"]
    for r in results:
        e = r.entry
        if e.kind not in kinds:
            continue
        thesis = format_value(e.printed or e.value, e.unit)
        rows.append(f"| `{e.id}` | {_cell(e.quantity, 70)} | {thesis} | "
                    f"{format_value(r.value, e.unit)} | {STATUS_MARK.get(r.status, r.status)} |")
    return "\n".join(rows)


def own_checks_table(results: Iterable[Result]) -> str:
    """Markdown table of our own checks (kind ``derived``): what is compared, the value
    the entry states, our value and the status. Not thesis claims: a row not reproduced
    is a disagreement between our own models."""
    rows = ["| id | check | stated value | our value | status |", "|---|---|---|---|---|"]
    for r in in_group(results, "own checks"):
        e = r.entry
        rows.append(f"| `{e.id}` | {_cell(e.quantity, 70)} | "
                    f"{format_value(e.printed or e.value, e.unit)} | "
                    f"{format_value(r.value, e.unit)} | {STATUS_MARK.get(r.status, r.status)} |")
    return "\n".join(rows)


def _by_root_cause(results: list[Result]) -> list[tuple[str, list[Result]]]:
    """Errata grouped by their root error (catalogue field ``root_cause``), roots in
    catalogue order; within a group the root first."""
    groups: dict[str, list[Result]] = {}
    for r in results:
        if r.entry.kind == "erratum":
            groups.setdefault(r.entry.root_cause or r.entry.id, []).append(r)
    return [(root, sorted(rs, key=lambda r: r.entry.id != root))
            for root, rs in groups.items()]


def errata_table(results: Iterable[Result]) -> str:
    """Markdown table of the errata, grouped by root cause (the root error first)."""
    rows = ["| root cause | id | equation | as printed | corrected | status | evidence |",
            "|---|---|---|---|---|---|---|"]
    for root, group in _by_root_cause(list(results)):
        for r in group:
            e = r.entry
            cause = "root" if e.id == root else f"`{root}`"
            rows.append(f"| {cause} | `{e.id}` | {_cell(e.source.get('equation', ''), 20)} | "
                        f"{_cell(e.as_printed, None)} | {_cell(e.corrected, None)} | "
                        f"{STATUS_MARK.get(r.status, r.status)} | "
                        f"`{_cell(r.evidence or e.evidence, None)}` |")
    return "\n".join(rows)


def root_cause_table(results: Iterable[Result]) -> str:
    """Markdown table: each root error, the errata and the other entries that follow from
    it (entries naming it as ``root_cause``)."""
    results = list(results)
    rows = ["| root error | status | errata it causes | other entries it causes |",
            "|---|---|---|---|"]
    for root, group in _by_root_cause(results):
        head = next((r for r in results if r.entry.id == root), group[0])
        errata = [f"`{r.entry.id}`" for r in group if r.entry.id != root]
        others = [f"`{r.entry.id}` ({STATUS_MARK.get(r.status, r.status)})" for r in results
                  if r.entry.kind != "erratum" and r.entry.root_cause == root]
        rows.append(f"| `{root}` | {STATUS_MARK.get(head.status, head.status)} | "
                    f"{', '.join(errata) or '—'} | {', '.join(others) or '—'} |")
    return "\n".join(rows)


#: words of an entry's ``quantity`` that name what kind of quantity it is, in the order
#: they are looked for; the earliest one in the text decides (:func:`quantity_kind`)
QUANTITY_WORDS = (("share", "share"), ("voltage", "voltage"), ("phibar", "voltage"),
                  ("field", "field"), ("displacement", "displacement"),
                  ("deflection", "displacement"), ("dhat", "Dhat"), ("area", "area"),
                  ("stretch", "stretch"))


def quantity_kind(entry) -> str:
    """What kind of quantity an entry's value is: ``parameters.quantity`` when the entry
    states it, otherwise the earliest word of :data:`QUANTITY_WORDS` in its ``quantity``
    text ("" when none occurs)."""
    stated = entry.parameters.get("quantity")
    if isinstance(stated, str) and stated:
        return stated
    text = entry.quantity.lower()
    hits = [(text.find(w), kind) for w, kind in QUANTITY_WORDS if w in text]
    return min(hits)[1] if hits else ""


def value_kind(value) -> str:
    """``number``, ``bool``, ``text`` or ``none``: what a table cell compares."""
    if value is None:
        return "none"
    if isinstance(value, bool):
        return "bool"
    if isinstance(value, int | float):
        return "number"
    return "text"


@dataclass(frozen=True)
class Comparison:
    """One diagnosis row: the value the hypothesis predicts and the value it is compared
    with, each with its unit and kind of quantity. ``against`` says where the compared
    value comes from: the target entry's printed value, or the value the producer states
    it compared with (``details["compared_with"]``, in the entry's unit and kind)."""

    predicted: object
    predicted_unit: str
    predicted_kind: str
    compared: object
    compared_unit: str
    compared_kind: str
    against: str


def diagnosis_comparison(r: Result, ids: dict) -> Comparison:
    """The comparison a diagnosis row shows (:class:`Comparison`)."""
    e = r.entry
    kind = quantity_kind(e)
    if "compared_with" in r.details:
        return Comparison(r.value, e.unit, kind, r.details["compared_with"], e.unit, kind,
                          "stated by the producer")
    t = ids.get(e.parameters.get("target", ""))
    if t is None:
        return Comparison(r.value, e.unit, kind, None, "", "", "missing target")
    return Comparison(r.value, e.unit, kind, t.value, t.unit, quantity_kind(t), "target")


def row_problems(results: Iterable[Result]) -> list[str]:
    """Rows of the report's tables that do not compare like with like: a claim or
    literature row whose value and ours are of different kinds (number, bool, text; a
    missing value on either side is shown as such), a diagnosis row whose predicted and
    compared values differ in unit or kind of quantity, or whose kind is unknown."""
    from debench.reference.catalogue import by_id

    results = list(results)
    ids = by_id([r.entry for r in results])
    out = []
    for r in results:
        e = r.entry
        if e.kind in ("claim", "literature"):
            a, b = value_kind(e.value), value_kind(r.value)
            if "none" not in (a, b) and a != b:
                out.append(f"{e.id}: thesis value is {a}, ours is {b}")
        elif e.kind == "diagnosis":
            c = diagnosis_comparison(r, ids)
            if not c.predicted_kind:
                out.append(f"{e.id}: kind of the predicted quantity unknown")
            if (c.predicted_unit, c.predicted_kind) != (c.compared_unit, c.compared_kind):
                out.append(f"{e.id}: predicts {c.predicted_kind} [{c.predicted_unit}], "
                           f"compared with {c.compared_kind} [{c.compared_unit}] "
                           f"({c.against})")
            if value_kind(c.predicted) not in ("number", "none") or \
                    value_kind(c.compared) != "number":
                out.append(f"{e.id}: predicted {value_kind(c.predicted)}, compared with "
                           f"{value_kind(c.compared)}")
    return out


def diagnosis_table(results: Iterable[Result]) -> str:
    """Markdown table of the diagnoses: hypothesis, the entry it targets, the value it is
    compared with (the target's printed value, or the criterion its producer states) and
    what the hypothesis predicts, each with unit and kind, and whether they agree."""
    from debench.reference.catalogue import by_id

    results = list(results)
    ids = by_id([r.entry for r in results])
    rows = ["| hypothesis | target | compared with | predicted | kind | status |",
            "|---|---|---|---|---|---|"]
    for r in results:
        e = r.entry
        if e.kind != "diagnosis":
            continue
        c = diagnosis_comparison(r, ids)
        t = ids.get(e.parameters.get("target", ""))
        shown = (format_value(t.printed or t.value, t.unit) if c.against == "target" and t
                 else format_value(c.compared, c.compared_unit))
        if c.against != "target":
            shown += f" ({r.details.get('compared_as', 'criterion')})"
        rows.append(f"| `{e.id}` | `{e.parameters.get('target', '')}` | {shown} | "
                    f"{format_value(c.predicted, c.predicted_unit)} | {c.predicted_kind} | "
                    f"{STATUS_MARK.get(r.status, r.status)} |")
    return "\n".join(rows)


def summary_line(results: list[Result]) -> str:
    """The status counts of every group (:data:`GROUPS`), each group apart."""
    return "; ".join(count_sentence(g, results, capital=False) for g in GROUPS
                     if in_group(results, g))


def _prefixes(results: Iterable[Result]) -> list[str]:
    return sorted({r.entry.id.split(".")[0] for r in results},
                  key=lambda p: list(CHAPTER_TITLES).index(p) if p in CHAPTER_TITLES else 99)


def chapter_summary(results: list[Result], groups: Iterable[str] = ("claims",)) -> str:
    """Markdown table of the status counts per chapter of the entries of ``groups``:
    a column per status that occurs (headed ``group: status`` when there are several
    groups) and the number of entries."""
    results = list(results)
    groups = list(groups)
    cols = [(g, s) for g in groups for s in STATUS_ORDER
            if any(r.status == s for r in in_group(results, g))]

    def head(g: str, s: str) -> str:
        return s.replace("_", " ") if len(groups) == 1 else f"{g}: {s.replace('_', ' ')}"

    rows = ["| chapter | entries | " + " | ".join(head(g, s) for g, s in cols) + " |",
            "|---|---|" + "---|" * len(cols)]
    for prefix in _prefixes(results):
        chunk = [r for r in results if r.entry.id.split(".")[0] == prefix]
        chosen = [r for g in groups for r in in_group(chunk, g)]
        if not chosen:
            continue
        counts = {g: status_counts(in_group(chunk, g)) for g in groups}
        rows.append(f"| {CHAPTER_TITLES.get(prefix, prefix)} | {len(chosen)} | "
                    + " | ".join(str(counts[g][s]) for g, s in cols) + " |")
    return "\n".join(rows)


#: the README's two tables: the thesis' claims, and everything else, apart
README_TABLES = (("claims",), ("own checks", "errata", "diagnoses", "assumptions"))


def readme_block(results: list[Result]) -> str:
    """The generated README section: the status counts, in all and per chapter, thesis
    claims apart from our own checks, errata, diagnoses and assumptions; each table below
    the sentence that counts its entries. Every claim, erratum and diagnosis is in the
    report (:func:`write_report`), which the documentation site shows as its verdict
    page."""
    lines = [START, "_Generated by `debench report --readme` from the catalogue._", ""]
    for groups in README_TABLES:
        lines += [" ".join(count_sentence(g, results) + "." for g in groups
                           if in_group(results, g)), "",
                  chapter_summary(results, groups), ""]
    lines += ["Every claim beside our value, the errata with their evidence, the diagnoses "
              "and the cross-check matrix: `debench report` (`results/REPORT.md`), the "
              "verdict page of the documentation site.", END]
    return "\n".join(lines)


# --------------------------------------------------------------------------- verdict
#: a placeholder of the verdict template: ``{{ ... }}``
PLACEHOLDER = re.compile(r"\{\{(.*?)\}\}", re.S)
#: what a placeholder whose record was not computed renders as (visible, never a number)
NOT_COMPUTED = "**[not computed: {}]**"


class VerdictError(ValueError):
    """A placeholder of the verdict template that names no entry or is malformed."""


def _verdict_text(value, spec: str = "", unit: str = "") -> str:
    """A value of a record as the verdict prints it: numbers with ``spec`` (default four
    significant digits), a sequence comma-separated, a bool as holds / does not hold, the
    unit appended unless it is 1 or empty."""
    from debench.reference.catalogue import readable

    if hasattr(value, "tolist") and not isinstance(value, str):
        value = value.tolist()  # a numpy scalar or array
    if isinstance(value, bool):
        text = "holds" if value else "does not hold"
    elif isinstance(value, int | float):
        text = format(value, spec or ".4g")
    elif isinstance(value, list | tuple):
        text = ", ".join(_verdict_text(v, spec) for v in value)
    elif isinstance(value, dict):
        text = readable(value, 4)
    else:
        text = " ".join(str(value).split())
    return text + ("" if unit in ("", "1") or text.endswith(unit) else f" {unit}")


def _split_id(path: str, ids: dict[str, Result]) -> tuple[Result, list[str]]:
    """The result an ``ID.field.key`` path starts with (the longest id), and the rest."""
    parts = path.split(".")
    for k in range(len(parts), 0, -1):
        head = ".".join(parts[:k])
        if head in ids:
            return ids[head], parts[k:]
    raise VerdictError(f"verdict placeholder {path!r} names no catalogue entry")


def _catalogued(path: str) -> bool:
    """Whether ``path`` starts with the id of an entry of the catalogue (evaluated or not)."""
    from debench.reference.catalogue import load

    known = {e.id for e in load()}
    parts = path.split(".")
    return any(".".join(parts[:k]) in known for k in range(len(parts), 0, -1))


def _record_field(path: str, spec: str, ids: dict[str, Result]) -> str:
    try:
        r, rest = _split_id(path, ids)
    except VerdictError:
        if _catalogued(path):       # an entry of the catalogue this evaluation left out
            return NOT_COMPUTED.format(path)
        raise
    e = r.entry
    what, keys = (rest[0], rest[1:]) if rest else ("value", [])
    if what == "value" and not keys:
        if r.value is None or r.status == "error":
            return NOT_COMPUTED.format(path)
        return _verdict_text(r.value, spec, e.unit)
    if what == "printed" and not keys:
        return _verdict_text(e.printed or e.value, spec, e.unit)
    if what == "status" and not keys:
        return r.status.replace("_", " ")
    if what not in ("details", "parameters") or not keys:
        raise VerdictError(f"verdict placeholder {path!r}: after the id comes value, "
                           "printed, status, details.KEY or parameters.KEY")
    obj = r.details if what == "details" else e.parameters
    for key in keys:
        if not isinstance(obj, dict) or key not in obj:
            return NOT_COMPUTED.format(path)
        obj = obj[key]
    return _verdict_text(obj, spec)


def _count(args: list[str], results: list[Result]) -> str:
    group, opts = args[0].replace("_", " "), dict(a.split("=", 1) for a in args[1:])
    if group not in GROUPS or set(opts) - {"prefix", "status"}:
        raise VerdictError(f"verdict placeholder 'count {' '.join(args)}': count GROUP "
                           f"[prefix=P,Q] [status=S], GROUP one of {list(GROUPS)}")
    chosen = in_group(results, group)
    if "prefix" in opts:
        chosen = [r for r in chosen if r.entry.id.startswith(tuple(opts["prefix"].split(",")))]
    if "status" in opts:
        chosen = [r for r in chosen if r.status == opts["status"]]
    return str(len(chosen))


def _errata(prefixes: list[str], results: list[Result]) -> str:
    """The equations (or tables) of the confirmed errata whose id starts with a prefix."""
    out = []
    for r in results:
        e = r.entry
        if e.kind == "erratum" and r.status == "confirmed" and e.id.startswith(tuple(prefixes)):
            if "equation" in e.source:
                out.append(f"({str(e.source['equation']).replace('-', '–')})")
            elif "table" in e.source:
                out.append(f"Table {e.source['table']}")
    if not out:
        return NOT_COMPUTED.format("errata " + " ".join(prefixes))
    return ", ".join(out[:-1]) + (" and " if len(out) > 1 else "") + out[-1]


def consensus_sentence(problem: str, quantity: str) -> str:
    """What the curated submissions of other codes on ``problem``'s ``quantity`` show, in
    one sentence from the consensus records (:mod:`debench.reference.consensus`): how many
    of their values lie within the reference's stated accuracy and within the accuracy
    their submitters state, and the spread. It says "within" only of the values that are."""
    from debench.reference import consensus
    from debench.reference.manifest import DatasetError

    try:
        tables = consensus.tables()
    except DatasetError:        # a data directory without the references (a partial one)
        return NOT_COMPUTED.format(f"consensus {problem} {quantity}")
    found = [t for t in tables if (t.problem, t.quantity) == (problem, quantity)]
    if not found or not found[0].rows:
        return f"no curated submission from another code on `{problem}`."
    t = found[0]
    codes = list(dict.fromkeys(r.code.split(" (")[0] for r in t.rows))
    n = len(t.rows)
    stated = sum(r.within_stated for r in t.rows)
    declared = [r for r in t.rows if r.within_declared is not None]
    noun = "curve" if t.curve else "value"
    text = (f"{len(codes)} code{'s' if len(codes) > 1 else ''} ({', '.join(codes)}) "
            f"submitted {n} {noun}{'s' if n > 1 else ''}; {stated} of {n} lie within the "
            "reference's stated accuracy")
    if declared:
        text += (f" and {sum(r.within_declared for r in declared)} of {len(declared)} within "
                 "the accuracy their submitters state")
    spread = t.spread()
    if t.curve:
        text += (f"; the largest difference from the reference at any point is "
                 f"{max(spread.values()):.2g}")
    else:
        ref = {r.selection: abs(r.reference) for r in t.rows}
        rel = max(v / ref[k] for k, v in spread.items() if ref[k])
        text += (f"; the spread across the codes and the reference is at most "
                 f"{max(spread.values()):.2g} ({rel:.1g} relative)")
    if t.refused:
        text += f"; {len(t.refused)} submission(s) refused"
    return text + "."


def _placeholder(inner: str, results: list[Result], ids: dict[str, Result]) -> str:
    body, _, spec = inner.partition("|")
    words = body.split()
    if not words:
        raise VerdictError("empty verdict placeholder {{ }}")
    if words[0] == "count":
        return _count(words[1:], results)
    if words[0] == "errata":
        return _errata(words[1:], results)
    if words[0] == "consensus" and len(words) == 3:
        return consensus_sentence(words[1], words[2])
    if len(words) != 1:
        raise VerdictError(f"verdict placeholder {{{{{inner}}}}} is not ID[.field], count, "
                           "errata or consensus")
    return _record_field(words[0], spec.strip(), ids)


def verdict_template(path: Path | None = None) -> str:
    """The verdict template (:data:`VERDICT_TEMPLATE`) without its header comment."""
    text = Path(path or VERDICT_TEMPLATE).read_text()
    return re.sub(r"\A\s*<!--.*?-->\s*", "", text, count=1, flags=re.S).strip()


def _one_line_paragraphs(text: str) -> str:
    """Each paragraph on one line (a filled placeholder leaves ragged lines; a line break
    inside ``$...$`` would end the formula on some renderers)."""
    return "\n\n".join(" ".join(p.split()) for p in re.split(r"\n\s*\n", text.strip()))


def verdict_markdown(results: list[Result], template: Path | None = None) -> str:
    """The verdict in brief, in plain language: :data:`VERDICT_TEMPLATE` with every
    placeholder filled from ``results`` (the computed catalogue) and the consensus records.
    The report, the README and the site's verdict page all show this text. A placeholder
    whose record was not computed shows :data:`NOT_COMPUTED`; one that names no entry
    raises :class:`VerdictError`."""
    results = list(results)
    ids = {r.entry.id: r for r in results}
    return _one_line_paragraphs(PLACEHOLDER.sub(
        lambda m: _placeholder(m[1], results, ids), verdict_template(template)))


def verdict_block(results: list[Result]) -> str:
    """The README's verdict block: :func:`verdict_markdown` between its markers."""
    return "\n".join([VERDICT_START, "_Generated by `debench report --readme` from "
                       "`reference/verdict.md` and the computed records._", "",
                       verdict_markdown(results), VERDICT_END])


def _headline(r: Result) -> bool:
    """Numeric thesis claims and literature values (not stated inputs)."""
    v = r.entry.value
    return (r.entry.kind in ("claim", "literature")
            and r.status not in ("input", "not_comparable")
            and isinstance(v, int | float) and not isinstance(v, bool))


def _replace_block(text: str, start: str, end: str, block: str, where: Path) -> str:
    if start not in text or end not in text:
        raise ValueError(f"{where} lacks the markers {start} … {end}")
    head, rest = text.split(start, 1)
    _, tail = rest.split(end, 1)
    return head + block + tail


def update_readme(readme: Path, results: list[Result]) -> bool:
    """Rewrite the verdict block and the results block of ``readme``; return True if it
    changed."""
    text = readme.read_text()
    new = _replace_block(text, VERDICT_START, VERDICT_END, verdict_block(results), readme)
    new = _replace_block(new, START, END, readme_block(results), readme)
    if new == text:
        return False
    readme.write_text(new)
    return True


def _chapter_of(name: str) -> str | None:
    """The chapter prefix of a figure file (``fig3_4_*``, ``table5_1_*``, ``ch4_*``)."""
    m = re.match(r"^(?:fig|table|ch)(\d)[_.]", name)
    return f"ch{m[1]}" if m else None


def _beside_ours(r: Result, word: str = "printed") -> str:
    return (f"`{r.entry.id}` {word} "
            f"{format_value(r.entry.printed or r.entry.value, r.entry.unit)}, "
            f"ours {format_value(r.value, r.entry.unit)}")


def roots_text(errata: list[Result]) -> str:
    """``"By root error (4): `a` (with `b`), `c`, ..."``: the root errors of ``errata``
    (the rows of :func:`root_cause_table`), each with the errata it causes."""
    groups = _by_root_cause(errata)

    def caused(root: str, rs: list[Result]) -> str:
        others = [f"`{r.entry.id}`" for r in rs if r.entry.id != root]
        return f"`{root}`" + (f" (with {', '.join(others)})" if others else "")

    return f"By root error ({len(groups)}): " + ", ".join(caused(*g) for g in groups)


def errata_sentence(results: Iterable[Result]) -> str:
    """The counts of the errata checked, whose refuted ones are printed forms found
    right (no errata of the thesis), and their root errors."""
    errata = in_group(results, "errata")
    counts = status_counts(errata)
    text = count_sentence("errata", errata) + "."
    if counts["refuted"]:
        text += (f" The {counts['refuted']} refuted are printed forms found right on "
                 "checking, not errata of the thesis.")
    return text + " " + roots_text(errata) + "."


def chapter_verdict(prefix: str, chunk: list[Result]) -> str:
    """A written verdict of one chapter, generated from its computed results: the counts
    by status of each group apart (:data:`GROUPS`; the same records as the chapter's
    tables), every thesis claim that does not reproduce (ours beside the printed one), our
    own checks that do not, the errata and the diagnoses."""
    title = CHAPTER_TITLES.get(prefix, prefix)
    parts = [f"**{title}.**"]
    claims = in_group(chunk, "claims")
    if claims:
        parts.append(count_sentence("claims", chunk) + ".")
        numeric = [r for r in claims if _headline(r)]
        if numeric:
            same = sum(r.status == "reproduced" for r in numeric)
            parts.append(f"Of its {len(numeric)} numeric claims (stated inputs aside), "
                         f"{same} reproduce{'s' if same == 1 else ''} to the printed digits.")
        misses = [r for r in claims if r.status == "not_reproduced"]
        if misses:
            numbers = [_beside_ours(r) for r in misses if _headline(r)]
            statements = [f"`{r.entry.id}`" for r in misses if not _headline(r)]
            parts.append("Not reproduced: " + "; ".join(
                ([f"numbers {'; '.join(numbers)}"] if numbers else [])
                + ([f"statements {', '.join(statements)}"] if statements else [])) + ".")
    own = in_group(chunk, "own checks")
    if own:
        parts.append(count_sentence("own checks", chunk) + ".")
        misses = [r for r in own if r.status == "not_reproduced"]
        if misses:
            parts.append("Own checks not reproduced (our implementations disagree): "
                         + "; ".join(_beside_ours(r, "stated") for r in misses) + ".")
    errata = in_group(chunk, "errata")
    if errata:
        parts.append(errata_sentence(errata))
    diag = in_group(chunk, "diagnoses")
    if diag:
        parts.append(count_sentence("diagnoses", chunk) + " (" + "; ".join(
            f"`{r.entry.id}` {STATUS_MARK.get(r.status, r.status)}, predicts "
            f"{format_value(r.value, r.entry.unit)}" for r in diag) + ").")
    if in_group(chunk, "assumptions"):
        parts.append(count_sentence("assumptions", chunk) + ".")
    errors = status_counts(chunk)["error"]
    if errors:
        parts.append(f"{errors} producer(s) failed: see the tables.")
    return " ".join(parts)


def crosscheck_section(data_dir: Path | None = None,
                       results: Iterable[Result] = ()) -> list[str]:
    """The cross-check matrix (``debench.reference.crosschecks``) as report lines, and the
    counts of the catalogue's own checks of our models (kind ``derived``) among
    ``results``, which the chapter sections list."""
    from debench.reference import crosschecks

    own = in_group(results, "own checks")
    misses = [r for r in own if r.status == "not_reproduced"]
    catalogue = [f"Beyond this matrix, in the catalogue: {count_sentence('own checks', own)}."
                 + (" Not reproduced: " + ", ".join(f"`{r.entry.id}`" for r in misses) + "."
                    if misses else "")
                 + " Each chapter's section lists them.", ""] if own else []
    try:
        rows = crosschecks.matrix(data_dir)
    except Exception as exc:  # noqa: BLE001 - a report still renders without its datasets
        return ["## Cross-check matrix", "", f"Not available: {exc}", "", *catalogue]
    agree = sum(r.within is True for r in rows)
    judged = sum(r.within is not None for r in rows)
    return ["## Cross-check matrix: which implementation checked which", "",
            f"{agree} of the {judged} pairs of this matrix that have a tolerance agree within "
            f"it; {len(rows) - judged} pairs are expected to differ and are diagnoses. "
            "Measured from the curated datasets; the tolerance is the named constant the "
            "asserting test uses.", "", crosschecks.table(rows), "", *catalogue]


def consensus_section() -> list[str]:
    """The consensus of codes (``debench.reference.consensus``) as report lines."""
    from debench.reference import consensus

    return consensus.report_section()


def _figure_lines(fig: Path, out_dir: Path) -> list[str]:
    """A figure (PNG, relative link) with a link to its SVG when there is one."""
    rel = os.path.relpath(fig.resolve(), Path(out_dir).resolve())
    svg = fig.with_suffix(".svg")
    extra = f" ([SVG]({os.path.relpath(svg.resolve(), Path(out_dir).resolve())}))" \
        if svg.exists() else ""
    return [f"![{fig.stem}]({rel}){extra}", ""]


def write_report(out_dir: Path, results: list[Result], *, data_problems: list[str] = (),
                 regeneration: list[str] = (), figures_dir: Path | None = None) -> Path:
    """Write ``out_dir/REPORT.md`` with tables per chapter and the figures.

    Figures are the PNG files of ``figures_dir`` (default ``out_dir/figures``) whose names
    start with the thesis figure number (``fig3_4_...``).
    """
    out_dir = Path(out_dir)
    figures_dir = Path(figures_dir) if figures_dir is not None else out_dir / "figures"
    figures = sorted(figures_dir.glob("*.png")) if figures_dir.exists() else []
    now = _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat()
    lines = [
        "# debench report: does Zeng (2020) reproduce?",
        "",
        "## The verdict in brief",
        "",
        verdict_markdown(results),
        "",
        "## The counts",
        "",
        f"Generated {now} from commit `{git_commit()}`. Summary: {summary_line(results)}.",
        "",
        "Status meanings: *reproduced* = within half a unit of the last printed digit; "
        "*not reproduced* = our value differs (diagnosis given); *not reproducible* = the "
        "thesis lacks information (named); *pending* = no model yet; errata are "
        "*confirmed*, *refuted* or *editorial* (a wrong cross-reference), grouped by their root "
        "error; *not comparable* = a setting of ours (mesh, element type) that the thesis "
        "states differently for its own method, neither a result nor a failure; a diagnosis "
        "(hypothesis) is *explained* when it gives the printed number to its digits. Thesis "
        "claims, our own checks (catalogue kind `derived`: our implementations against each "
        "other or a closed form, never a thesis claim), errata, diagnoses and assumptions are "
        "counted apart.",
        "",
        "## Verdict per chapter",
        "",
    ]
    prefixes = _prefixes(results)
    for prefix in prefixes:
        lines += [chapter_verdict(prefix, [r for r in results
                                           if r.entry.id.split(".")[0] == prefix]), ""]
    lines += crosscheck_section(results=results)
    lines += consensus_section()
    shown: set[Path] = set()
    for prefix in prefixes:
        chunk = [r for r in results if r.entry.id.split(".")[0] == prefix]
        lines += [f"## {CHAPTER_TITLES.get(prefix, prefix)}", ""]
        if in_group(chunk, "claims"):
            lines += [count_sentence("claims", chunk) + ".", "", results_table(chunk), ""]
        if in_group(chunk, "own checks"):
            lines += [count_sentence("own checks", chunk) + ".", "", own_checks_table(chunk),
                      ""]
        diag = [r for r in chunk if r.diagnosis and r.status in
                ("not_reproduced", "not_reproducible", "not_comparable", "error")]
        if diag:
            lines += ["Why these differ or cannot be compared:", ""]
            lines += [f"- `{r.entry.id}`: {r.diagnosis}" for r in diag]
            lines.append("")
        assumptions = in_group(chunk, "assumptions")
        if assumptions:
            lines += [count_sentence("assumptions", chunk) + " (the thesis does not state "
                      "these).", ""]
            lines += [f"- `{r.entry.id}` = {format_value(r.entry.value, r.entry.unit)}: "
                      f"{_cell(r.entry.diagnosis or r.entry.notes, 300)}" for r in assumptions]
            lines.append("")
        figs = [f for f in figures if _chapter_of(f.name) == prefix]
        for fig in figs:
            lines += _figure_lines(fig, out_dir)
            shown.add(fig)
    rest = [f for f in figures if f not in shown]
    if rest:
        lines += ["## Other figures", ""]
        for fig in rest:
            lines += _figure_lines(fig, out_dir)
    lines += ["## Errata", "", errata_sentence(results), "", errata_table(results), ""]
    lines += ["### Root causes", "", root_cause_table(results), ""]
    lines += ["## Diagnoses", "", count_sentence("diagnoses", results) + ".", "",
              diagnosis_table(results), ""]
    if data_problems:
        lines += ["## Dataset problems", ""] + [f"- {p}" for p in data_problems] + [""]
    if regeneration:
        lines += ["## Regenerated vs curated datasets", ""] + [f"- {p}" for p in regeneration]
        lines.append("")
    path = out_dir / "REPORT.md"
    out_dir.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(lines))
    return path


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
              "them, run `debench reproduce` with the chapters that make them (every "
              "chapter by default), or `debench report --out DIR` with a DIR that has no "
              "figures/ to use the curated figures", file=sys.stderr)
    elif not present:
        print(f"debench: warning: no figures in {figures}; the report has none "
              "(`debench reproduce` makes them)", file=sys.stderr)
    return figures
