"""The tables and counts of the report and the README: status marks, groups, the claims,
own checks, errata, root causes and diagnoses as Markdown tables, and the sentences that
count them (:mod:`debench.reference.report` assembles them with the verdict and figures).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable
from dataclasses import dataclass

from debench.reference.catalogue import Result, by_id

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


def cell(text: str, width: int | None = 90) -> str:
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
        rows.append(f"| `{e.id}` | {cell(e.quantity, 70)} | {thesis} | "
                    f"{format_value(r.value, e.unit)} | {STATUS_MARK.get(r.status, r.status)} |")
    return "\n".join(rows)


def own_checks_table(results: Iterable[Result]) -> str:
    """Markdown table of our own checks (kind ``derived``): what is compared, the value
    the entry states, our value and the status. Not thesis claims: a row not reproduced
    is a disagreement between our own models."""
    rows = ["| id | check | stated value | our value | status |", "|---|---|---|---|---|"]
    for r in in_group(results, "own checks"):
        e = r.entry
        rows.append(f"| `{e.id}` | {cell(e.quantity, 70)} | "
                    f"{format_value(e.printed or e.value, e.unit)} | "
                    f"{format_value(r.value, e.unit)} | {STATUS_MARK.get(r.status, r.status)} |")
    return "\n".join(rows)


def by_root_cause(results: list[Result]) -> list[tuple[str, list[Result]]]:
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
    for root, group in by_root_cause(list(results)):
        for r in group:
            e = r.entry
            cause = "root" if e.id == root else f"`{root}`"
            rows.append(f"| {cause} | `{e.id}` | {cell(e.source.get('equation', ''), 20)} | "
                        f"{cell(e.as_printed, None)} | {cell(e.corrected, None)} | "
                        f"{STATUS_MARK.get(r.status, r.status)} | "
                        f"`{cell(r.evidence or e.evidence, None)}` |")
    return "\n".join(rows)


def root_cause_table(results: Iterable[Result]) -> str:
    """Markdown table: each root error, the errata and the other entries that follow from
    it (entries naming it as ``root_cause``)."""
    results = list(results)
    rows = ["| root error | status | errata it causes | other entries it causes |",
            "|---|---|---|---|"]
    for root, group in by_root_cause(results):
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


def chapter_prefixes(results: Iterable[Result]) -> list[str]:
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
    for prefix in chapter_prefixes(results):
        chunk = [r for r in results if r.entry.id.split(".")[0] == prefix]
        chosen = [r for g in groups for r in in_group(chunk, g)]
        if not chosen:
            continue
        counts = {g: status_counts(in_group(chunk, g)) for g in groups}
        rows.append(f"| {CHAPTER_TITLES.get(prefix, prefix)} | {len(chosen)} | "
                    + " | ".join(str(counts[g][s]) for g, s in cols) + " |")
    return "\n".join(rows)


#: the README's two tables: the thesis' claims, and everything else, apart
