"""Pages of the debench site generated from the repository at build time.

Connected to ``builder-inited`` (before Sphinx looks for source files), this writes
``docs/generated/``:

* ``verdict.md`` -- the report ``debench report`` writes
  (:func:`debench.reference.report.write_report`: the verdict in brief that the README
  shares (:func:`debench.reference.report.verdict_markdown`), the verdict per chapter, the
  cross-check matrix, every table, the figures of ``data/figures``);
* ``problems/`` -- one page per reference problem: the page ``debench problems ID
  --markdown`` prints (:func:`debench.reference.problems_markdown.render_markdown`), its
  reference figures (the thesis figures and tables its spec names, as curated in
  ``data/figures``) and its variants; its reference values as downloads (the JSON
  ``debench problems ID --json`` prints, a CSV per quantity in the results-file format of
  ``debench check``) and, where curated submissions exist, a plot of the reference beside
  the other codes and their spread (:mod:`debench.reference.consensus`);
* ``datasets/`` -- one page per curated dataset, from the netCDF attributes of the file
  itself (read verified by :func:`debench.reference.datasets.read_dataset`);
* ``errata.md`` -- the errata of the catalogue and their root causes;
* ``api/`` -- one autodoc page per public module of ``debench.models`` (discovered, so a
  new module gets a page), plus the user-facing ``debench.testing``, the pytest fixture
  and the reference-problem and dataset readers; the modules of these pages are imported
  by autodoc alone (the pytest plugin with pytest mocked: the docs extra has no pytest);
* ``cli.md`` -- every subcommand's ``--help``, from the parser the ``debench`` command uses;
* ``peers.md`` -- peer submissions: ``peers/README.md`` and the consensus table of
  ``debench.reference.consensus`` where they exist.

A file is rewritten only when its text changed, so incremental builds stay incremental.
Nothing here catches an error of the code it calls: a page that cannot be generated
fails the build.
"""

from __future__ import annotations

import importlib
import importlib.util
import json
import pkgutil
import re
import shutil
import time
from pathlib import Path

DOCS = Path(__file__).resolve().parent.parent
ROOT = DOCS.parent
OUT = DOCS / "generated"

#: names, in this order, under which the docs look for the consensus table of peer
#: submissions in ``debench.reference.consensus``: a callable taking no argument (all
#: problems) and returning markdown
CONSENSUS_FUNCTIONS = ("consensus_markdown", "markdown", "render_markdown")


def _write(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_text() != text:
        path.write_text(text)


def _log(msg: str) -> None:
    from sphinx.util import logging

    logging.getLogger(__name__).info(f"[debench_pages] {msg}")


# --------------------------------------------------------------------------- figures
def _copy_figures() -> list[Path]:
    """The curated figures (PNG and SVG) copied next to the generated pages."""
    from debench.reference.datasets import data_dir

    src = data_dir() / "figures"
    dst = OUT / "figures"
    dst.mkdir(parents=True, exist_ok=True)
    copied = []
    for f in sorted(src.iterdir()):
        if f.suffix in (".png", ".svg"):
            target = dst / f.name
            if not target.exists() or target.read_bytes() != f.read_bytes():
                shutil.copyfile(f, target)
            copied.append(target)
    return [f for f in copied if f.suffix == ".png"]


def _numbers(spec: str) -> list[tuple[int, int]]:
    """Thesis figure or table numbers of a spec field: ``"3.4-3.8"``, ``"5.1, 5.2"``."""
    out: list[tuple[int, int]] = []
    for part in str(spec).split(","):
        part = part.strip()
        m = re.fullmatch(r"(\d+)\.(\d+)(?:\s*-\s*(\d+)\.(\d+))?", part)
        if not m:
            raise ValueError(f"thesis figure/table {part!r} is not N.M or N.M-N.M")
        a, b = int(m[1]), int(m[2])
        if m[3] is None:
            out.append((a, b))
        else:
            if int(m[3]) != a:
                raise ValueError(f"thesis range {part!r} spans chapters")
            out += [(a, k) for k in range(b, int(m[4]) + 1)]
    return out


def problem_figures(problem, figures: list[Path]) -> list[tuple[Path, str]]:
    """Curated figures of a problem: those of the thesis figures and tables its spec
    names (``fig3_4_*`` for Fig. 3.4, ``table5_1_*`` for Table 5.1), and those named after
    one of its datasets (``ch4_beyond_voltage_control`` for ``ch4_voltage_control``)."""
    chosen: dict[Path, str] = {}
    for key, stem in (("figure", "fig"), ("table", "table")):
        if key in problem.thesis:
            for a, b in _numbers(problem.thesis[key]):
                for f in figures:
                    if f.name.startswith(f"{stem}{a}_{b}_"):
                        chosen.setdefault(f, f"thesis {key} {a}.{b}")
    for ds in problem.datasets:
        tail = ds.split("_", 1)[1]
        for f in figures:
            if f.stem.startswith(f"ch{problem.chapter}_") and f.stem.endswith(tail):
                chosen.setdefault(f, f"dataset {ds}")
    return list(chosen.items())


# --------------------------------------------------------------------------- verdict
def verdict_page(results) -> None:
    from debench.reference import report

    # figures linked relative to the page: the report is written beside them
    path = report.write_report(OUT, results, figures_dir=OUT / "figures")
    text = path.read_text()
    path.unlink()
    head = ("The report `debench report` writes (here generated from the catalogue when "
            "the site was built; `debench reproduce` writes the same page to "
            "`results/REPORT.md` next to freshly built figures); the verdict in brief above "
            "is also the README's.\n\n")
    title, rest = text.split("\n", 1)
    title = title.replace("# debench report:", "# The verdict:")  # the report's own title
    # the page opens with the verdict in brief (report.verdict_markdown), then this note
    brief, counts = rest.split("## The counts\n", 1)
    _write(OUT / "verdict.md", title + "\n" + brief + head + "## The counts\n" + counts)


# --------------------------------------------------------------------------- errata
def errata_page(results) -> None:
    from debench.reference import report, report_tables

    errata = [r for r in results if r.entry.kind == "erratum"]
    lines = [
        "# Errata", "",
        "The printed equations and statements checked as possible errata, from the "
        "catalogue (`reference/catalogue/*.toml`, entries of kind `erratum`). Each is "
        "*confirmed* (an erratum) or *refuted* (the printed form is right after all) by the "
        "test named as its evidence, or *editorial* (a wrong cross-reference); each names "
        "its root error (`root_cause`). The status is computed when the site is built. "
        "Claims that do not reproduce, and the hypotheses tested against them, are on the "
        "[verdict](verdict.md) page.", "",
        report.errata_sentence(results), "",
        report_tables.errata_table(results), "",
        "## Root causes", "",
        "Each root error and what follows from it.", "",
        report_tables.root_cause_table(results), "",
        "## Details", "",
    ]
    for r in errata:
        e = r.entry
        where = ", ".join(f"{k} {v}" for k, v in e.source.items()) or "—"
        lines += [f"### `{e.id}`", "", _md(e.quantity), "",
                  f"- **status**: {report_tables.STATUS_MARK.get(r.status, r.status)}",
                  f"- **where**: {_md(where)}",
                  f"- **as printed**: {_md(e.as_printed)}",
                  f"- **corrected**: {_md(e.corrected)}",
                  f"- **root cause**: `{e.root_cause}`",
                  f"- **evidence**: `{r.evidence or e.evidence}`"]
        for label, text in (("diagnosis", r.diagnosis or e.diagnosis), ("notes", e.notes)):
            if text:
                lines.append(f"- **{label}**: {_md(text)}")
        lines.append("")
    _write(OUT / "errata.md", "\n".join(lines))


# --------------------------------------------------------------------------- problem data
def _csv_cell(v) -> str:
    """A value as the downloads write it: a float to round trip (``repr``), no value as
    ``nan`` (the no-event NaN ``debench check`` accepts), text as it is."""
    if v is None:
        return "nan"
    if isinstance(v, float):
        return repr(v)
    return str(v)


def reference_csv(problem, quantity, item: dict) -> str:
    """One quantity's reference values (``item``: its entry of
    :func:`debench.reference.problems_reference.reference_json`) as CSV: one row per
    reference point, a column per coordinate a user supplies (selectors, then the
    abscissa) and the quantity, each headed ``name [units]`` as the results files
    ``debench check`` reads; padding points of ragged curves (no abscissa) are left out."""
    import csv
    import io

    import numpy as np

    dims, coords, along = item["dims"], item["coords"], item.get("along")
    shape = tuple(len(coords[d]) for d in dims)
    values = np.empty(shape, dtype=object)
    values[...] = _nested(item["values"], shape)
    kept = [d for d in dims if d in quantity.coordinates]
    if along and along["name"] in kept:
        along = None  # the abscissa is a dimension itself: already a column
    names = kept + ([along["name"]] if along else []) + [quantity.name]
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow([f"{n} [{quantity.units_of(n) or ''}]" if quantity.units_of(n) else n
                     for n in names])
    along_values = None
    if along:
        along_values = np.empty(tuple(len(coords[d]) for d in along["dims"]), dtype=object)
        along_values[...] = _nested(along["values"], along_values.shape)
    for index in np.ndindex(*shape):
        at = dict(zip(dims, index, strict=True))
        row = [coords[d][at[d]] for d in kept]
        if along:
            x = along_values[tuple(at[d] for d in along["dims"])]
            if x is None:
                continue  # padding of a shorter curve
            row.append(x)
        row.append(values[index])
        writer.writerow([_csv_cell(v) for v in row])
    return out.getvalue()


def _nested(values, shape):
    """A nested list as an object array of ``shape`` (None kept)."""
    import numpy as np

    arr = np.empty(shape, dtype=object)
    for index in np.ndindex(*shape):
        v = values
        for i in index:
            v = v[i]
        arr[index] = v
    return arr


def problem_downloads(problem) -> list[str]:
    """Write ``problems/data/ID.json`` (what ``debench problems ID --json`` prints) and a
    CSV per quantity; return the page's section offering them."""
    from debench.reference.problems_reference import reference_json

    data = reference_json(problem)
    folder = OUT / "problems" / "data"
    _write(folder / f"{problem.id}.json", json.dumps(data, ensure_ascii=False) + "\n")
    lines = ["## Reference values: downloads", "",
             "Generated when this site was built from the same data `debench problems "
             f"{problem.id} --json` prints:", "",
             f"- {{download}}`{problem.id}.json <data/{problem.id}.json>`: the spec and, per "
             "quantity, the coordinates, values, units and accuracy (JSON, exactly what "
             f"`debench problems {problem.id} --json` prints)."]
    for q in problem.quantities:
        name = f"{problem.id}.{q.name}.csv"
        _write(folder / name, reference_csv(problem, q, data["reference"][q.name]))
        lines.append(f"- {{download}}`{name} <data/{name}>`: quantity `{q.name}` "
                     f"[{q.units}], one row per reference point, columns named and with "
                     "units as the results files `debench check` reads.")
    return lines + [""]


def _outcomes(problem_id: str, quantity: str) -> list:
    """The curated submissions of a problem's quantity, each checked (as the consensus
    table does)."""
    from debench.reference import submissions as subs

    out = []
    for folder in subs.discover(subs.curated_root()):
        sub = subs.load(folder)
        if (sub.problem, sub.quantity) == (problem_id, quantity):
            out.append(subs.check(sub))
    return out


def consensus_plot(problem) -> list[str]:
    """Per quantity with curated submissions: a figure of the reference with every code's
    values (upper panel) and their differences from the reference beside the reference's
    stated accuracy (lower panel: the spread), written to ``problems/figures/``; return the
    page's section (empty when no submission exists)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from debench.reference import consensus

    found = [t for t in consensus.tables() if t.problem == problem.id and t.rows]
    if not found:
        return []
    lines = ["## Reference and other codes (plot)", "",
             "The reference beside the curated submissions of other codes (the consensus "
             "table above, `submissions/`): upper panel the values, lower panel each code's "
             "difference from the reference, with the reference's stated accuracy shaded "
             "(`debench check` without `--rtol`) and, as error bars, the accuracy each "
             "submitter states.", ""]
    for t in found:
        q = problem.quantity(t.quantity)
        outcomes = _outcomes(problem.id, t.quantity)
        fig, (top, low) = plt.subplots(2, 1, figsize=(7.5, 6.0), sharex=t.curve,
                                       height_ratios=(3, 2), layout="constrained")
        markers = "osD^v<>"
        if t.curve:
            for k, o in enumerate(outcomes):
                st = o.stated
                x = np.asarray(st.coords[q.along], dtype=float)
                groups = {}
                for i in range(x.size):
                    key = tuple(str(st.coords[c][i]) for c in q.select)
                    groups.setdefault(key, []).append(i)
                for j, idx in enumerate(groups.values()):
                    idx = np.asarray(idx)[np.argsort(x[idx])]
                    if k == 0:
                        top.plot(x[idx], st.reference[idx], color="0.3", lw=0.8,
                                 label="reference" if j == 0 else None)
                    step = max(1, idx.size // 12)
                    top.plot(x[idx][::step], st.values[idx][::step], markers[k % 7],
                             ms=4 - k, mfc="none", color=f"C{k}", alpha=0.8,
                             label=o.submission.label if j == 0 else None)
                order = np.argsort(x)
                low.plot(x[order], st.error[order], markers[k % 7], ms=max(1, 3 - k),
                         color=f"C{k}", alpha=0.7, label=o.submission.label)
                if k == 0:
                    low.fill_between(x[order], -st.tolerance[order], st.tolerance[order],
                                     color="0.85", label="stated accuracy", step="mid")
            top.set_ylabel(f"{q.name} [{q.units}]")
            low.set_xlabel(f"{q.along} [{q.along_units}]")
        else:
            sels = list(dict.fromkeys(r.selection for r in t.rows))
            pos = {s: i for i, s in enumerate(sels)}
            ref = {r.selection: (r.reference, r.tolerance_stated) for r in t.rows}
            xs = np.arange(len(sels))
            top.errorbar(xs, [ref[s][0] for s in sels], yerr=[ref[s][1] for s in sels],
                         fmt="_", ms=24, color="0.2", label="reference")
            low.bar(xs, [2 * ref[s][1] for s in sels], bottom=[-ref[s][1] for s in sels],
                    width=0.6, color="0.85", label="stated accuracy")
            codes = list(dict.fromkeys(r.code for r in t.rows))
            width = 0.4 / max(1, len(codes))
            for k, code in enumerate(codes):
                rows = [r for r in t.rows if r.code == code]
                x = np.array([pos[r.selection] for r in rows]) + (k - (len(codes) - 1) / 2) * width
                top.plot(x, [r.value for r in rows], markers[k % 7], color=f"C{k}", label=code)
                low.errorbar(x, [r.error for r in rows],
                             yerr=[r.tolerance_declared or 0.0 for r in rows],
                             fmt=markers[k % 7], color=f"C{k}", capsize=3, label=code)
            for ax in (top, low):
                ax.set_xticks(xs, sels)
            top.set_ylabel(f"{q.name} [{q.units}]")
        low.axhline(0.0, color="0.3", lw=0.6)
        low.set_ylabel(f"code - reference [{q.units}]")
        top.legend(fontsize=7)
        low.legend(fontsize=7)
        top.set_title(f"{problem.id}: {q.name}", fontsize=10)
        name = f"{problem.id}.{q.name}.consensus.png"
        path = OUT / "problems" / "figures" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path, dpi=110, metadata={"Software": None})
        plt.close(fig)
        spread = "; ".join(f"{k}: {v:.3g}" for k, v in t.spread().items())
        stated = max(r.tolerance_stated for r in t.rows)
        what = ("largest |difference| from the reference over every point of every code"
                if t.curve else "spread across the codes and the reference (max - min)")
        lines += [f"```{{figure}} figures/{name}", f":alt: {problem.id} {q.name}: reference "
                  "and other codes", "",
                  f"Quantity `{q.name}` [{q.units}]: {len({r.code for r in t.rows})} code(s); "
                  f"{what}: {spread}; the reference's stated accuracy is at most "
                  f"{stated:.2g}.", "```", ""]
    return lines


# --------------------------------------------------------------------------- problems
def problem_pages(figures: list[Path]) -> list[str]:
    from debench.reference import consensus, problems

    items = problems.load_all()
    variants_of: dict[str, list] = {}
    for p in items:
        if p.variant:
            variants_of.setdefault(p.variant["of"], []).append(p)
    index = ["# Reference problems", "",
             "The benchmark problems users check their own codes against, one page each, "
             "generated from its spec (`reference/problems/*.toml`): the page is what "
             "`debench problems ID --markdown` prints, followed by its reference values as "
             "JSON and CSV downloads, a plot of the reference beside other codes where "
             "they submitted, the reference figures and the variants. Check results with "
             "`debench check ID FILE` or "
             "{func}`debench.testing.assert_matches` "
             "([getting started](../../getting-started.md)).",
             "", "| problem | chapter | title | quantities |", "|---|---|---|---|"]
    names = []
    for p in items:
        qs = ", ".join(f"`{q.name}`" for q in p.quantities)
        chapter = p.chapter or "beyond the thesis"
        index.append(f"| [`{p.id}`]({p.id}.md) | {chapter} | {p.title} | {qs} |")
        names.append(p.id)
        page = consensus.problem_page(p).rstrip("\n").split("\n")
        extra = ["", *problem_downloads(p), *consensus_plot(p), "## Reference figures", ""]
        figs = problem_figures(p, figures)
        if figs:
            extra += ["The curated figures (`data/figures/`) of the thesis figures and tables "
                      "this problem's spec names, as `debench reproduce` redraws them. A "
                      "redrawn thesis figure uses the form of the equations the thesis used "
                      "unless its name or title says another (`..._derived`), so it may show "
                      "a named variant of this problem rather than its default (see "
                      "[Variants](#variants)).", ""]
            for f, why in figs:
                svg = f.with_suffix(".svg")
                link = f" ([SVG](../figures/{svg.name}))" if svg.exists() else ""
                extra += [f"```{{figure}} ../figures/{f.name}", f":alt: {f.stem}", "",
                          f"`{f.stem}` ({why}).", "```", ""]
                if link:
                    extra += [f"Vector version{link}.", ""]
        else:
            extra += ["No curated figure belongs to this problem (its spec names no thesis "
                      "figure or table that `data/figures/` holds).", ""]
        extra += ["## Variants", ""]
        listed = False
        if p.variant:
            extra += [f"- This problem is the named variant of [`{p.variant['of']}`]"
                      f"({p.variant['of']}.md).", ""]
            listed = True
        for v in variants_of.get(p.id, ()):
            extra += [f"- Named variant [`{v.id}`]({v.id}.md): {v.title}.", ""]
            listed = True
        for q in p.quantities:
            if "variant" in q.select:
                par = p.parameters.get("variant", {})
                vals = ", ".join(f"`{v}`" for v in par.get("value", ()))
                dflt = q.defaults.get("variant")
                extra += [f"- Quantity `{q.name}` has the selector `variant` ({vals}; "
                          f"default `{dflt}`): {par.get('description', '')}", ""]
                listed = True
        if not listed:
            extra += ["None: this problem has no named variant and no variant selector.", ""]
        _write(OUT / "problems" / f"{p.id}.md", "\n".join(page + extra))
    index += ["", "```{toctree}", ":hidden:", "", *names, "```", ""]
    _write(OUT / "problems" / "index.md", "\n".join(index))
    return names


# --------------------------------------------------------------------------- datasets
def _md(text) -> str:
    return " ".join(str(text).split()).replace("|", "\\|")


def _md_number(value, digits: int = 12) -> str:
    """A number, or a JSON list or mapping of them (attribute text such as ``param_*``),
    as a reader reads it (:func:`debench.reference.catalogue.readable`); any other text as
    the file stores it."""
    from debench.reference.catalogue import readable

    if isinstance(value, str):
        try:
            parsed = json.loads(value) if value.lstrip()[:1] in ("[", "{") else None
        except ValueError:
            parsed = None
        return _md(value if parsed is None else readable(parsed, digits))
    return _md(readable(value, digits))


def dataset_pages() -> list[str]:
    from debench.reference.datasets import data_dir, read_dataset, read_manifest

    directory = data_dir()
    files = read_manifest(directory)
    index = ["# Datasets", "",
             "The curated reference datasets in `data/` (netCDF-4, CF-1.10, ACDD-1.3), one "
             "page each with every variable, its units and its meaning, generated from the "
             "attributes of the file itself (read verified against its sha256). Below the "
             "list: the data card `data/README.md`, as shipped with the package.", "",
             "| dataset | title | dimensions |", "|---|---|---|"]
    names = []
    for fname, meta in files.items():
        stem = Path(fname).stem
        ds = read_dataset(directory / fname)
        dims = ", ".join(f"{k} = {v}" for k, v in ds.sizes.items()) or "none"
        index.append(f"| [`{fname}`]({stem}.md) | {_md(ds.attrs.get('title', ''))} | {dims} |")
        names.append(stem)
        a = ds.attrs
        page = [f"# `{fname}`", "", f"**{_md(a.get('title', ''))}.** {_md(a.get('summary', ''))}",
                "", "```python", "from debench.reference.datasets import read_dataset",
                f'ds = read_dataset("{stem}")   # xarray.Dataset, checksum verified', "```", "",
                f"- **dimensions**: {dims}",
                f"- **sha256**: `{meta['sha256']}`",
                f"- **made by**: `{_md(a.get('command', ''))}` at commit "
                f"`{str(a.get('git_commit', ''))[:12]}`",
                f"- **conventions**: {_md(a.get('Conventions', ''))}",
                f"- **licence**: {_md(a.get('license', ''))}", "",
                "## Variables", "",
                "| variable | units | meaning | dims | role | accuracy |",
                "|---|---|---|---|---|---|"]
        for name, var in {**ds.coords, **ds.data_vars}.items():
            va = var.attrs
            acc = "; ".join(f"{k.removeprefix('accuracy_')} {_md_number(va[k], 6)}" for k in
                            ("accuracy_rtol", "accuracy_atol") if k in va) or "—"
            units = va.get("units", "")
            page.append(f"| `{name}` | {'`' + _md(units) + '`' if units else '—'} | "
                        f"{_md(va.get('long_name', ''))} | "
                        f"({', '.join(var.dims) or 'scalar'}) | "
                        f"{_md(va.get('coverage_content_type', ''))} | {_md(acc)} |")
        notes = [(n, v.attrs.get("comment") or v.attrs.get("description"))
                 for n, v in {**ds.coords, **ds.data_vars}.items()]
        notes = [(n, c) for n, c in notes if c]
        if notes:
            page += ["", "## Notes on the variables", ""]
            page += [f"- `{n}`: {_md(c)}" for n, c in notes]
        params = json.loads(a.get("parameters", "{}"))
        if params:
            page += ["", "## Parameters", "", "| parameter | value |", "|---|---|"]
            page += [f"| `{k}` | {_md_number(v)} |" for k, v in sorted(params.items())]
        page += ["", "## Global attributes", "", "| attribute | value |", "|---|---|"]
        page += [f"| `{k}` | {_md_number(v)[:300]} |" for k, v in sorted(a.items())
                 if k not in ("parameters",)]
        _write(OUT / "datasets" / f"{stem}.md", "\n".join(page) + "\n")
    index += ["", "```{toctree}", ":hidden:", "", *names, "```", "",
              "## The data card", "",
              "```{include} ../../../data/README.md", ":heading-offset: 1", "```", ""]
    _write(OUT / "datasets" / "index.md", "\n".join(index))
    return names


# --------------------------------------------------------------------------- API
#: user-facing modules outside debench.models, with what the page shows of them
USER_MODULES = {
    "debench.testing": None,
    "debench.pytest_plugin": None,
    "debench.reference.problems": ("Problem", "Quantity", "ReferenceAccuracy",
                                   "ProblemError", "load_all", "get"),
    "debench.reference.problems_reference": ("Reference", "reference_at", "reference_json"),
    "debench.reference.problems_coverage": ("Coverage", "CoverageError", "coverage"),
    "debench.reference.comparison": ("Comparison", "Comparisons", "compare"),
    "debench.reference.problems_markdown": ("render_markdown",),
    "debench.reference.datasets": ("read_dataset", "data_dir", "read_manifest"),
    "debench.reference.cite": ("citation", "render"),
    "debench.reference.standards": ("acdd_attributes",),
    "debench.reference.datacard": ("render", "write"),
}


def _public_modules(package: str) -> list[str]:
    pkg = importlib.import_module(package)
    out = [package]
    for m in pkgutil.walk_packages(pkg.__path__, prefix=package + "."):
        if not any(part.startswith("_") for part in m.name.split(".")):
            out.append(m.name)
    return sorted(out)


def _where(package: str, name: str) -> str:
    """A link to where a re-exported name of ``package`` is documented."""
    obj = getattr(importlib.import_module(package), name)
    mod, qual = getattr(obj, "__module__", None), getattr(obj, "__qualname__", None)
    if mod and qual and isinstance(obj, type):
        return f":class:`~{mod}.{qual}`"
    if mod and qual and callable(obj):
        return f":func:`~{mod}.{qual}`"
    # data: the submodule whose source assigns it
    for sub in _public_modules(package):
        m = importlib.import_module(sub)
        if sub != package and getattr(m, name, None) is obj and \
                f"\n{name}" in Path(m.__file__).read_text():
            return f":data:`~{sub}.{name}`"
    return f":data:`~{package}.{name}`"


def api_pages() -> list[str]:
    modules = _public_modules("debench.models")
    names = []
    for mod in modules + list(USER_MODULES):
        # found, not imported: autodoc imports the module, with conf.autodoc_mock_imports
        # mocked (the pytest plugin needs pytest, which the docs extra does not install)
        is_pkg = importlib.util.find_spec(mod).submodule_search_locations is not None
        title = f"``{mod}``"
        body = [title, "=" * len(title), "", f".. automodule:: {mod}"]
        members = USER_MODULES.get(mod)
        if is_pkg:
            # what the package itself defines; its re-exports are documented where defined
            body += ["   :members:", "   :ignore-module-all:"]
            subs = [m for m in modules if m.rsplit(".", 1)[0] == mod]
            if subs:
                body += ["", "Modules:", ""] + [f"- :mod:`{m}`" for m in subs]
        elif members:
            body.append(f"   :members: {', '.join(members)}")
        else:
            body += ["   :members:", "   :ignore-module-all:"]
        if is_pkg and getattr(importlib.import_module(mod), "__all__", None):
            body += ["", "Public names (``from " + mod + " import ...``):", ""]
            body += [f"- {_where(mod, n)}" for n in importlib.import_module(mod).__all__]
        _write(OUT / "api" / f"{mod}.rst", "\n".join(body) + "\n")
        names.append(mod)
    index = ["# API reference", "",
             "The physics (`debench.models`: pure functions, a frozen parameter dataclass in, "
             "a result object out) and the functions a user checks results with. One page "
             "per public module, generated from the docstrings (equation numbers refer to "
             "Zeng 2020).", "",
             "## `debench.models`", "",
             *[f"- [`{m}`]({m}.rst)" for m in modules], "",
             "## Checking results and reading the references", "",
             *[f"- [`{m}`]({m}.rst)" for m in USER_MODULES], "",
             "The command line is on the [CLI](../cli.md) page.", "",
             "```{toctree}", ":hidden:", "", *names, "```", ""]
    _write(OUT / "api" / "index.md", "\n".join(index))
    return names


# --------------------------------------------------------------------------- CLI
def cli_page() -> None:
    from debench.reference import cli

    parser = cli.build_parser()
    lines = ["# Command line", "",
             "`debench` is installed with the package (`pip install -e .`). Exit codes of "
             "every command: 0 ok, 1 a check or verification failed, 2 usage error, 3 "
             "runtime error; `--debug` (anywhere) shows tracebacks. Generated from the "
             "parser the command uses ({func}`debench.reference.cli.build_parser`).", "",
             "## `debench`", "", "```text", parser.format_help().rstrip(), "```", ""]
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    for name, sp in sub.choices.items():
        lines += [f"## `debench {name}`", "", "```text", sp.format_help().rstrip(), "```", ""]
    lines += ["## Entry points", "", "```{eval-rst}",
              ".. autofunction:: debench.reference.cli.main",
              ".. autofunction:: debench.reference.cli.build_parser", "```", ""]
    _write(OUT / "cli.md", "\n".join(lines))


# --------------------------------------------------------------------------- peers
def peers_page() -> None:
    """Peer submissions: ``peers/README.md`` if the repository has one, and the
    consensus table if ``debench.reference.consensus`` exists. Absent is said on the page;
    any other failure (an import error inside the module, a table that cannot be made)
    fails the build."""
    lines = ["# Peer codes and consensus", "",
             "Other codes join the benchmark through submissions (metadata and results) "
             "checked against the reference problems; this page shows how to submit and "
             "the consensus across the codes that did.", ""]
    readme = ROOT / "peers" / "README.md"
    if readme.exists():
        lines += ["## How to submit", "", "```{include} ../../peers/README.md",
                  ":heading-offset: 2", ":relative-docs: ../", ":relative-images:", "```", ""]
    else:
        lines += ["## How to submit", "",
                  "_This build has no `peers/README.md` (the submission guide is not part "
                  "of this checkout)._", ""]
    lines += ["## Consensus", ""]
    try:
        consensus = importlib.import_module("debench.reference.consensus")
    except ModuleNotFoundError as exc:
        if exc.name != "debench.reference.consensus":
            raise  # the module exists but something it imports is missing
        lines += ["_This build has no consensus table (`debench.reference.consensus` is "
                  "not part of this checkout)._", ""]
    else:
        fn = next((getattr(consensus, n) for n in CONSENSUS_FUNCTIONS
                   if callable(getattr(consensus, n, None))), None)
        if fn is None:
            raise RuntimeError("debench.reference.consensus exists but has none of "
                               f"{CONSENSUS_FUNCTIONS}; the docs page peers.md needs one "
                               "(no argument, returns markdown): see "
                               "docs/_ext/debench_pages.py")
        lines += [str(fn()).rstrip(), ""]
    _write(OUT / "peers.md", "\n".join(lines))


# --------------------------------------------------------------------------- cite
def cite_example(item_id: str = "ch3_free_membrane_nh") -> None:
    from debench.reference import cite

    _write(OUT / "cite_example.md", "```text\n$ debench cite " + item_id + "\n"
           + cite.render(item_id).rstrip() + "\n```\n")


# --------------------------------------------------------------------------- sphinx
def generate(app=None) -> None:
    import locale

    from debench.reference import catalogue

    # Sphinx sets the user's locale (LC_ALL = ""): with C.UTF-8, locale.getlocale() reports
    # ("en_US", "UTF-8"), which cf_units (the units of the consensus checks) cannot restore
    # after its own switch to "C"; numbers are formatted in the C locale anyway
    locale.setlocale(locale.LC_NUMERIC, "C")
    t0 = time.perf_counter()
    OUT.mkdir(parents=True, exist_ok=True)
    figures = _copy_figures()
    results = catalogue.evaluate_all()
    _log(f"catalogue evaluated in {time.perf_counter() - t0:.1f} s")
    verdict_page(results)
    errata_page(results)
    problem_pages(figures)
    dataset_pages()
    api_pages()
    cli_page()
    peers_page()
    cite_example()
    _log(f"pages generated in {time.perf_counter() - t0:.1f} s")


def setup(app):
    app.connect("builder-inited", generate)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
