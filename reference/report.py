"""Markdown report: each thesis claim beside our value and its status, with figures.

The README's status counts are generated here too (between the markers
``<!-- results:start -->`` and ``<!-- results:end -->``); a test checks they are current.
"""

from __future__ import annotations

import datetime as _dt
import os
import sys
from collections import Counter
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from debench.reference.catalogue import Result
from debench.reference.provenance import git_commit

START, END = "<!-- results:start -->", "<!-- results:end -->"
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
        head = group[0]
        errata = [f"`{r.entry.id}`" for r in group[1:]]
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
    counts = status_counts(results)
    order = ["reproduced", "not_reproduced", "not_reproducible", "pending", "confirmed",
             "refuted", "editorial", "explained", "unexplained", "assumed", "input",
             "not_comparable", "error"]
    return ", ".join(f"{counts[s]} {s.replace('_', ' ')}" for s in order if counts[s])


def chapter_summary(results: list[Result]) -> str:
    """Markdown table of status counts per chapter."""
    cols = ["reproduced", "not_reproduced", "not_reproducible", "pending", "confirmed",
            "refuted", "editorial", "explained", "unexplained", "assumed", "input",
             "not_comparable", "error"]
    present = [c for c in cols if any(r.status == c for r in results)]
    names = {"confirmed": "errata confirmed", "refuted": "errata refuted",
             "editorial": "editorial errata"}
    head = "| chapter | " + " | ".join(names.get(c, c.replace("_", " "))
                                       for c in present) + " |"
    rows = [head, "|---|" + "---|" * len(present)]
    prefixes = sorted({r.entry.id.split(".")[0] for r in results},
                      key=lambda p: list(CHAPTER_TITLES).index(p) if p in CHAPTER_TITLES else 99)
    for prefix in prefixes:
        counts = status_counts(r for r in results if r.entry.id.split(".")[0] == prefix)
        rows.append(f"| {CHAPTER_TITLES.get(prefix, prefix)} | "
                    + " | ".join(str(counts[c]) for c in present) + " |")
    return "\n".join(rows)


def _headline(r: Result) -> bool:
    """Numeric thesis claims and literature values (not stated inputs)."""
    v = r.entry.value
    return (r.entry.kind in ("claim", "literature")
            and r.status not in ("input", "not_comparable")
            and isinstance(v, int | float) and not isinstance(v, bool))


def readme_block(results: list[Result]) -> str:
    """The generated README section: the status counts, in all and per chapter. Every
    claim, erratum and diagnosis is in the report (:func:`write_report`), which the
    documentation site shows as its verdict page."""
    return "\n".join([
        START,
        f"_Generated by `debench report --readme` from the catalogue: {summary_line(results)}._",
        "",
        chapter_summary(results),
        "",
        "Every claim beside our value, the errata with their evidence, the diagnoses and the "
        "cross-check matrix: `debench report` (`results/REPORT.md`), the verdict page of the "
        "documentation site.",
        END,
    ])


def update_readme(readme: Path, results: list[Result]) -> bool:
    """Rewrite the results block of ``readme``; return True if it changed."""
    text = readme.read_text()
    if START not in text or END not in text:
        raise ValueError(f"{readme} lacks the markers {START} … {END}")
    head, rest = text.split(START, 1)
    _, tail = rest.split(END, 1)
    new = head + readme_block(results) + tail
    if new == text:
        return False
    readme.write_text(new)
    return True


def _chapter_of(name: str) -> str | None:
    """The chapter prefix of a figure file (``fig3_4_*``, ``table5_1_*``, ``ch4_*``)."""
    import re

    m = re.match(r"^(?:fig|table|ch)(\d)[_.]", name)
    return f"ch{m[1]}" if m else None


def chapter_verdict(prefix: str, chunk: list[Result]) -> str:
    """A written verdict of one chapter, generated from its computed results: the counts
    by status, every number that does not reproduce (ours beside the printed one), the
    errata and the diagnoses."""
    counts = status_counts(chunk)
    title = CHAPTER_TITLES.get(prefix, prefix)
    parts = [f"**{title}.** {len(chunk)} entries: {summary_line(chunk)}."]
    numeric = [r for r in chunk if _headline(r)]
    if numeric:
        same = sum(r.status == "reproduced" for r in numeric)
        parts.append(f"Of its {len(numeric)} numeric claims, {same} reproduce to the printed "
                     "digits.")
    misses = [r for r in numeric if r.status == "not_reproduced"]
    if misses:
        parts.append("Not reproduced: " + "; ".join(
            f"`{r.entry.id}` printed "
            f"{format_value(r.entry.printed or r.entry.value, r.entry.unit)}, "
            f"ours {format_value(r.value, r.entry.unit)}" for r in misses) + ".")
    errata = [r for r in chunk if r.entry.kind == "erratum"]
    if errata:
        roots = {r.entry.root_cause or r.entry.id for r in errata}
        parts.append(f"Errata: {counts['confirmed']} confirmed, {counts['editorial']} "
                     f"editorial, {counts['refuted']} refuted of {len(errata)}, from "
                     f"{len(roots)} root causes (" +
                     ", ".join(f"`{r.entry.id}`" for r in errata) + ").")
    diag = [r for r in chunk if r.entry.kind == "diagnosis"]
    if diag:
        parts.append(f"Diagnoses: {counts['explained']} of {len(diag)} hypotheses explain the "
                     "printed number (" + "; ".join(
                         f"`{r.entry.id}` {STATUS_MARK.get(r.status, r.status)}, predicts "
                         f"{format_value(r.value, r.entry.unit)}" for r in diag) + ").")
    if counts["error"]:
        parts.append(f"{counts['error']} producer(s) failed: see the table.")
    return " ".join(parts)


def crosscheck_section(data_dir: Path | None = None) -> list[str]:
    """The cross-check matrix (``debench.reference.crosschecks``) as report lines."""
    from debench.reference import crosschecks

    try:
        rows = crosschecks.matrix(data_dir)
    except Exception as exc:  # noqa: BLE001 - a report still renders without its datasets
        return ["## Cross-check matrix", "", f"Not available: {exc}", ""]
    agree = sum(r.within is True for r in rows)
    judged = sum(r.within is not None for r in rows)
    return ["## Cross-check matrix: which implementation checked which", "",
            f"{agree} of {judged} pairs agree within their tolerance; "
            f"{len(rows) - judged} pairs are expected to differ and are diagnoses. Measured "
            "from the curated datasets; the tolerance is the named constant the asserting "
            "test uses.", "", crosschecks.table(rows), ""]


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
        f"Generated {now} from commit `{git_commit()}`. Summary: {summary_line(results)}.",
        "",
        "Status meanings: *reproduced* = within half a unit of the last printed digit; "
        "*not reproduced* = our value differs (diagnosis given); *not reproducible* = the "
        "thesis lacks information (named); *pending* = no model yet; errata are "
        "*confirmed*, *refuted* or *editorial* (a wrong cross-reference), grouped by their root "
        "error; *not comparable* = a setting of ours (mesh, element type) that the thesis "
        "states differently for its own method, neither a result nor a failure; a diagnosis "
        "(hypothesis) is *explained* when it gives the printed number to its digits.",
        "",
        "## Verdict per chapter",
        "",
    ]
    prefixes = sorted({r.entry.id.split(".")[0] for r in results},
                      key=lambda p: list(CHAPTER_TITLES).index(p) if p in CHAPTER_TITLES else 99)
    for prefix in prefixes:
        lines += [chapter_verdict(prefix, [r for r in results
                                           if r.entry.id.split(".")[0] == prefix]), ""]
    lines += crosscheck_section()
    lines += consensus_section()
    shown: set[Path] = set()
    for prefix in prefixes:
        chunk = [r for r in results if r.entry.id.split(".")[0] == prefix]
        lines += [f"## {CHAPTER_TITLES.get(prefix, prefix)}", "", results_table(chunk), ""]
        diag = [r for r in chunk if r.diagnosis and r.status in
                ("not_reproduced", "not_reproducible", "not_comparable", "error")]
        if diag:
            lines += ["Diagnoses:", ""]
            lines += [f"- `{r.entry.id}`: {r.diagnosis}" for r in diag]
            lines.append("")
        assumptions = [r for r in chunk if r.entry.kind == "assumption"]
        if assumptions:
            lines += ["Assumptions (the thesis does not state these):", ""]
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
    lines += ["## Errata", "", errata_table(results), ""]
    lines += ["### Root causes", "", root_cause_table(results), ""]
    lines += ["## Diagnoses", "", diagnosis_table(results), ""]
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
              "them, run `debench reproduce` for the chapters that make them (figures of "
              "converged-only studies, such as the radius/thickness 20 ones, need `--full`: "
              "hours of FE), or `debench report --out DIR` with a DIR that has no figures/ "
              "to use the curated figures", file=sys.stderr)
    elif not present:
        print(f"debench: warning: no figures in {figures}; the report has none "
              "(`debench reproduce` makes them)", file=sys.stderr)
    return figures
