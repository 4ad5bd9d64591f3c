"""The consensus table: every curated submission checked against its problem.

In the manner of Land et al. (2015, Proc. R. Soc. A 471:20150641: one problem, many codes,
the spread published), per problem and quantity each code's value, its difference from the
reference, whether that is within the reference's stated accuracy (``debench check``
without ``--rtol``) and within the submitter's own stated accuracy (``[check]`` of the
metadata), and the spread across codes. A quantity with one value per selection (a
critical voltage per material) is shown value by value; a curve by its worst point (the
largest |error|/tolerance at the reference's stated accuracy).

The curated submissions live in the repository's ``submissions/`` folder
(:func:`debench.reference.submissions.curated_root`); a submission that fails validation
is reported as refused, never left out silently.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

import numpy as np
from debench.reference.problems_markdown import render_markdown

from . import problems
from . import submissions as subs


@dataclass(frozen=True)
class Row:
    """One code on one selection (``selection``: e.g. ``case=nh_t1``; ``"curve"``: the
    worst point of a curve quantity, ``where`` its coordinates)."""

    code: str
    folder: str
    selection: str
    value: float
    reference: float
    error: float
    tolerance_stated: float
    within_stated: bool
    within_declared: bool | None
    tolerance_declared: float | None
    points: int
    where: str = ""
    claim_holds: bool | None = None


@dataclass(frozen=True)
class Table:
    """The consensus of one problem's quantity."""

    problem: str
    quantity: str
    units: str
    curve: bool
    rows: list[Row] = field(default_factory=list)
    refused: list[str] = field(default_factory=list)

    def spread(self) -> dict[str, float]:
        """Per selection: the spread across codes, max - min of the values of every code
        and of the reference (debench's own model counts as a code; a scalar quantity),
        or the largest |error| from the reference over every point of every code (a
        curve: all codes lie within +- that of the reference)."""
        out = {}
        for sel in dict.fromkeys(r.selection for r in self.rows):
            rs = [r for r in self.rows if r.selection == sel]
            if self.curve:
                out[sel] = max(abs(r.error) for r in rs)
            else:
                vals = [r.value for r in rs] + [rs[0].reference]
                out[sel] = max(vals) - min(vals)
        return out


def _rows(outcome: subs.Outcome, curve: bool, along: str | None) -> list[Row]:
    sub, st, dec = outcome.submission, outcome.stated, outcome.declared
    code = sub.label
    names = [k for k in st.coords if k != along]
    if curve:
        i = int(np.argmax(st.ratio))
        where = ", ".join(f"{k}={_fmt(st.coords[k][i])}" for k in st.coords)
        return [Row(code=code, folder=str(sub.folder), selection="curve",
                    value=float(st.values[i]), reference=float(st.reference[i]),
                    error=float(st.error[i]), tolerance_stated=float(st.tolerance[i]),
                    within_stated=st.passed,
                    within_declared=None if dec is None else dec.passed,
                    tolerance_declared=None if dec is None else float(dec.tolerance[i]),
                    points=int(st.values.size), where=where,
                    claim_holds=outcome.claim_holds)]
    rows = []
    for i in range(st.values.size):
        sel = ", ".join(f"{k}={_fmt(st.coords[k][i])}" for k in names) or "value"
        rows.append(Row(code=code, folder=str(sub.folder), selection=sel,
                        value=float(st.values[i]), reference=float(st.reference[i]),
                        error=float(st.error[i]), tolerance_stated=float(st.tolerance[i]),
                        within_stated=bool(not st.failed[i]),
                        within_declared=None if dec is None else bool(not dec.failed[i]),
                        tolerance_declared=None if dec is None else float(dec.tolerance[i]),
                        points=1, claim_holds=outcome.claim_holds))
    return rows


def _fmt(x) -> str:
    if isinstance(x, float | np.floating):
        return f"{float(x):.6g}"
    return str(x)


@cache
def _tables(root: str) -> tuple[Table, ...]:
    found: dict[tuple[str, str], Table] = {}
    for folder in subs.discover(root):
        try:
            sub = subs.load(folder)
        except subs.SubmissionError as exc:
            key = (folder.parent.name, "?")
            found.setdefault(key, Table(key[0], "?", "", False)).refused.append(str(exc))
            continue
        prob = problems.get(sub.problem)
        q = prob.quantity(sub.quantity)
        key = (prob.id, q.name)
        table = found.setdefault(key, Table(prob.id, q.name, q.units, bool(q.along)))
        try:
            outcome = subs.check(sub)
        except subs.SubmissionError as exc:
            table.refused.append(str(exc))
            continue
        table.rows.extend(_rows(outcome, bool(q.along), q.along))
    return tuple(found[k] for k in sorted(found))


def tables(root=None) -> list[Table]:
    """The consensus tables of every problem and quantity with curated submissions
    (``root``: a submissions folder; default the repository's ``submissions/``)."""
    root = Path(root) if root is not None else subs.curated_root()
    if not root.is_dir():
        return []
    return list(_tables(str(root.resolve())))


def _yes(b: bool | None) -> str:
    return "n/a" if b is None else ("yes" if b else "**no**")


def markdown(table: Table) -> str:
    """The table as markdown: one row per code and selection, then the spread."""
    head = ("| code | selection | value | reference | difference | within stated "
            "accuracy (tol) | within submitter's accuracy (tol) |" + (" worst point |"
                                                                      if table.curve else ""))
    sep = "|---" * (8 if table.curve else 7) + "|"
    lines = [head, sep]
    for r in table.rows:
        dec = (f"{_yes(r.within_declared)} ({r.tolerance_declared:.2g})"
               if r.within_declared is not None else "n/a (none stated)")
        sel = r.selection if not table.curve else f"{r.points} points"
        lines.append(f"| {r.code} | {sel} | {r.value:.8g} | {r.reference:.8g} | "
                     f"{r.error:+.3g} | {_yes(r.within_stated)} ({r.tolerance_stated:.2g})"
                     f" | {dec} |" + (f" {r.where} |" if table.curve else ""))
    spread = table.spread()
    if spread:
        what = ("largest |difference| from the reference over every point of every code"
                if table.curve else "spread across codes and the reference (max - min)")
        n = len({r.code for r in table.rows})
        lines += ["", f"{what.capitalize()}, {n} code(s): " + "; ".join(
            f"{k}: {v:.3g}" for k, v in spread.items())]
    for msg in table.refused:
        lines += ["", f"Refused: {msg}"]
    return "\n".join(lines)


def problem_page(problem) -> str:
    """The page of a reference problem
    (:func:`debench.reference.problems_markdown.render_markdown`) with its consensus of
    codes (:func:`problem_section`), as ``debench problems ID --markdown`` prints it."""
    return render_markdown(problem, extra=problem_section(problem.id))


def problem_section(problem_id: str, root=None) -> list[str]:
    """The consensus lines of one problem's page (empty when no submission exists)."""
    found = [t for t in tables(root) if t.problem == problem_id]
    if not found:
        return []
    out = ["## Other codes (curated submissions)", "",
           "Each curated submission (`submissions/`) checked against this problem "
           "(`debench check --submission DIR`); *stated accuracy*: the reference's, as "
           "`debench check` applies it; *submitter's accuracy*: the tolerance the "
           "submission states for its own values (e.g. from a mesh refinement).", ""]
    for t in found:
        out += [f"Quantity `{t.quantity}` [{t.units}]:", "", markdown(t), ""]
    return out


def report_section(root=None) -> list[str]:
    """The consensus section of the report."""
    found = tables(root)
    out = ["## Consensus of codes: curated submissions from other codes", ""]
    if not found:
        return out + ["No curated submissions found (the repository's `submissions/` "
                      "folder; a source checkout has it).", ""]
    codes = {r.code.split(" (")[0] for t in found for r in t.rows}
    out += [f"{sum(len({r.folder for r in t.rows}) for t in found)} submission(s) from "
            f"{len(codes)} code version(s) on {len({t.problem for t in found})} "
            "problem(s); each checked against its problem as `debench check --submission` "
            "does.", ""]
    for t in found:
        out += [f"### {t.problem}: `{t.quantity}`", "", markdown(t), ""]
    return out


def consensus_markdown() -> str:
    """The consensus of codes of every problem as one markdown section (the documentation
    site's peers page; :func:`report_section` joined)."""
    return "\n".join(report_section())
