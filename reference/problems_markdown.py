"""The page of a reference problem: everything needed to implement it and check results
against it, from its spec alone (:func:`render_markdown`, what ``debench problems ID
--markdown`` prints and the documentation's problem pages show)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from debench.reference import confirmations
from debench.reference.problems import BEYOND_THESIS, Problem, Quantity, provenance
from debench.reference.problems_reference import COORD_MATCH_RTOL
from debench.reference.results_files import expected_header


def _md_value(v: Any) -> str:
    if isinstance(v, list):
        return ", ".join(_md_value(x) for x in v)
    return repr(v) if isinstance(v, float) else str(v)   # every digit the spec states


def _md_units(u: str) -> str:
    return "text" if u == "" else f"`{u}`"


def _md_parameters(pars: Mapping[str, Mapping[str, Any]]) -> list[str]:
    out = ["| parameter | value | units | meaning |", "|---|---|---|---|"]
    for name, par in pars.items():
        out.append(f"| `{name}` | {_md_value(par.get('value'))} | "
                   f"{_md_units(par.get('units', ''))} | {par.get('description', '')} |")
    return out


def _md_model(p: Problem) -> list[str]:
    """The page's title, geometry, model, boundary conditions and loading."""
    where = "Beyond the thesis." if p.chapter == BEYOND_THESIS else f"Chapter {p.chapter}."
    out = [f"# {p.id}: {p.title}", "", f"{where} {p.summary}", ""]
    if p.variant:
        out += [f"**Variant of `{p.variant['of']}`.** {p.variant['why']}", ""]
    out += ["## Geometry", "", p.geometry, "", "## Model", ""]
    m = p.model
    for key, label in (("energy", "Energy"), ("compressibility", "Compressibility"),
                       ("extension_off_J1", "Extension off J = 1"),
                       ("equations", "Equations")):
        if m.get(key):
            out += [f"**{label}.** {m[key]}", ""]
    for mat in m.get("material", ()):
        out += [f"### Material `{mat['name']}`", "", f"- energy: {mat['energy']}",
                f"- compressibility: {mat['compressibility']}"]
        if mat.get("extension_off_J1"):
            out.append(f"- extension off J = 1: {mat['extension_off_J1']}")
        out += ["", *_md_parameters(mat["parameters"]), ""]
    out += ["## Boundary conditions", ""]
    if isinstance(p.boundary_conditions, str):
        out += [p.boundary_conditions, ""]
    else:
        out += ["| boundary | kinematic | electric |", "|---|---|---|"]
        out += [f"| {b['boundary']} | {b['kinematic']} | {b['electric']} |"
                for b in p.boundary_conditions]
        out.append("")
    out += ["## Loading", ""]
    if isinstance(p.loading, str):
        out += [p.loading, ""]
    else:
        out += [f"**Path.** {p.loading['path']}", "",
                f"**Controlled.** {p.loading['controlled']}", ""]
    return out


def _md_quantity(p: Problem, q: Quantity) -> list[str]:
    """The page's section of one quantity: its definition, coordinates, domain,
    accuracy, reference values and how to check it."""
    out: list[str] = []
    acc = q.accuracy
    out += [f"## Quantity `{q.name}` [{_md_units(q.units)}]", "", q.long_name, ""]
    for key in ("formula", "criterion", "tangent", "branch", "root_numbering",
                "normalisation"):
        if q.definition.get(key):
            out.append(f"- **{key.replace('_', ' ')}**: {q.definition[key]}")
    out += ["", "**Coordinates** (columns of your results file, with units):", ""]
    for c in q.coordinates:
        role = ("abscissa, interpolated" + (" in log" if q.along_scale == "log" else "")
                if c == q.along else "selector, matched to the grid")
        dflt = f"; default {q.defaults[c]}" if c in q.defaults else ""
        unit = q.units_of(c) if (c in q.coordinate_units or c == q.along) else "?"
        out.append(f"- `{c}` [{_md_units(unit)}]: {role}{dflt}")
    out += ["", f"**Domain.** {q.domain.get('window', '')}", ""]
    if q.domain.get("excluded"):
        out += ["| excluded | why |", "|---|---|"]
        out += [f"| {e['what']} | {e['why']} |" for e in q.domain["excluded"]]
        out.append("")
    out += [f"**Accuracy.** |error| <= atol + rtol |ref| + discretisation "
            f"(+ the interpolation error estimate off the grid): atol = {acc.atol:g}, "
            f"rtol = {acc.rtol:g} ({acc.reason}); discretisation "
            + (f"{float(acc.discretisation):g}" if np.ndim(acc.discretisation) == 0
               else "per value") + f": {acc.discretisation_reason}", ""]
    src = (f"dataset `{q.dataset}.nc`, variable `{q.variable}`" if q.source == "dataset"
           else f"closed form on the grid of {int(q.grid['num'])} equally spaced values of "
                f"`{q.along}` from {_md_value(q.grid['start'])} to "
                f"{_md_value(q.grid['stop'])} (both included)")
    if q.fixed:
        src += " at " + ", ".join(f"{k} = {_md_value(v)}" for k, v in q.fixed.items())
    out += [f"**Reference values.** {src}; `debench problems {p.id} --json` prints "
            "them with their coordinates.", "",
            f"**Check.** `debench check {p.id} results.csv` with the header "
            f"`{expected_header([q])}` (CSV separated by commas, semicolons or tabs, "
            "UTF-8 or UTF-16 text; or netCDF with these variables and their `units`; an "
            "empty cell, `nan` or `NaN` is no value, which matches only where the "
            "reference has none). Coverage: every stored "
            + ("curve" if q.along else "value") + " of every value of a selector "
            "without a default, and of the values your file gives of one with a "
            "default" + (", each at least as densely as the stored grid over its "
                         "whole range (any points; one within a relative "
                         f"{COORD_MATCH_RTOL:g} of a stored point is that point)"
                         if q.along else "") + "; or pass `--partial` and the report "
            "says what was covered.", ""]
    out += _md_confirmation(p, q)
    return out


def _md_cell(text: str) -> str:
    return " ".join(str(text).split()).replace("|", "\\|")


def _md_confirmation(p: Problem, q: Quantity) -> list[str]:
    """The quantity's confirmation: per record the independent computation, what it
    covers, the largest |difference| and its ratio to the stated accuracy, the CPU time
    and the command reproducing it (measured by ``tools/confirm.py``,
    ``reference/confirmations.json``); or why there is none."""
    out: list[str] = []
    for rec in confirmations.records(p.id, q):
        if rec["status"] == "missing":
            out += [f"**Confirmation: missing.** {rec['reason']}", ""]
            continue
        m = rec.get("measured")
        tier = "default run" if rec["tier"] == "default" else "slow (opt in with `--full`)"
        rows = [("independent computation", f"{rec['method']} (`{rec['implementation']}`)"),
                ("covers", rec["covers"])]
        if m is None:
            rows.append(("measured", "not yet: run `python tools/confirm.py"
                         + (" --full" if rec["tier"] == "slow" else "") + "`"))
        else:
            at = ", ".join(f"{k} = {v:g}" if isinstance(v, float) else f"{k} = {v}"
                           for k, v in m["worst_at"].items())
            rows += [("largest \\|reference - independent\\|",
                      f"{m['max_abs_difference']:.2g} over {m['points']} values"),
                     ("/ stated accuracy", f"{m['ratio']:.2g} (largest ratio, at {at}; the "
                      "test asserts <= 1)"),
                     ("CPU", f"{m['cpu_seconds']:.3g} s (commit `{m['commit'][:12]}`, "
                      f"{m['date']}" + ("; the same run gives "
                                        + ", ".join(f"`{x}`" for x in m["shared_with"])
                                        if m.get("shared_with") else "") + ")")]
        rows.append(("reproduce", f"`{rec['command']}` ({tier}; from a clone)"))
        if rec.get("gap"):
            rows.append(("not confirmed", rec["gap"]))
        out += ["**Confirmation.** The reference agrees with a second computation that "
                "shares no code with it, within the stated accuracy:", "",
                "| | |", "|---|---|"]
        out += [f"| {k} | {_md_cell(v)} |" for k, v in rows]
        out.append("")
    return out


def _md_shared_files(p: Problem) -> list[str]:
    """How quantities sharing their coordinates are checked from one file."""
    out: list[str] = []
    groups: dict[tuple, list[Quantity]] = {}
    for q in p.quantities:
        groups.setdefault(tuple(sorted(q.coordinates)), []).append(q)
    for qs in (g for g in groups.values() if len(g) > 1):
        header = expected_header(qs)
        out += ["**Several quantities in one file.** "
                + ", ".join(f"`{q.name}`" for q in qs) + " share their coordinates: one "
                f"file with the header `{header}` is checked per quantity (each against "
                "its own reference and accuracy, each needing its own coverage; the exit "
                "code is the worst); `--quantity NAME` checks a file of one quantity "
                "alone, `--rtol NAME=X` sets one quantity's tolerance.", ""]
    return out


def render_markdown(problem: Problem, extra=()) -> str:
    """The page ``debench problems ID --markdown`` prints: everything needed to implement
    the problem and check it, from the spec alone.

    ``extra``: markdown lines placed before the provenance section (the consensus of codes:
    ``debench.reference.consensus.problem_page``)."""
    p = problem
    out = _md_model(p)
    out += ["## Parameters", "", *_md_parameters(p.parameters), ""]
    for q in p.quantities:
        out += _md_quantity(p, q)
    out += _md_shared_files(p)
    out += list(extra)
    prov = provenance(p)
    if prov["datasets"]:
        out += ["## Provenance", ""]
        out += [f"- `{d['file']}` sha256 `{d['sha256']}`" for d in prov["datasets"].values()]
        out.append("")
    if p.thesis:
        out.append("Thesis: " + ", ".join(f"{k} {v}" for k, v in p.thesis.items()))
    if p.chapter == BEYOND_THESIS:
        out.append("References: " + ", ".join(p.references))
    return "\n".join(out) + "\n"

