"""Citations of a catalogue entry, dataset or reference problem (``debench cite ID``).

Each citation names the debench version and git commit, the sha256 of the datasets the
value comes from (from ``MANIFEST.json``), the thesis section, equation, figure, table
and page, and the references: the thesis and, for Chapter 3, the source paper; a problem
beyond the thesis (chapter 0, e.g. ``lit_balloon``) and its dataset cite the sources the
problem names instead, never the thesis. URLs come from one
place, ``[project.urls]`` of ``pyproject.toml``: the repository's (none while the project
has no public address) and the thesis'. Output as BibTeX and CSL-JSON (the item list
citeproc processors read).
"""

from __future__ import annotations

import datetime
import json
import re
from typing import Any

from debench.reference import catalogue, problems, provenance
from debench.reference.datasets import data_dir, read_manifest
from debench.reference.provenance import git_commit

from debench import __version__

THESIS = {
    "id": "zeng_2020", "type": "thesis", "genre": "PhD dissertation",
    "title": "Deformation and stability of dielectric elastomer films used in actuators",
    "author": [{"family": "Zeng", "given": "Chuan"}],
    "publisher": "The University of Akron", "issued": {"date-parts": [[2020]]},
}
#: items whose ``URL`` is the ``[project.urls]`` entry of this label (pyproject.toml, the
#: one place the project states addresses: ``debench.reference.provenance.project_urls``)
URL_LABELS = {"zeng_2020": "Thesis"}
ZENG_GAO_2019 = {
    "id": "zeng_gao_2019", "type": "article-journal",
    "title": "Effect of the deformation dependent permittivity on the actuation of a "
             "pre-stretched circular dielectric actuator",
    "author": [{"family": "Zeng", "given": "Chuan"}, {"family": "Gao", "given": "Xiaosheng"}],
    "container-title": "Mechanics Research Communications", "issued": {"date-parts": [[2019]]},
    "DOI": "10.1016/j.mechrescom.2019.103420",
}
ZHAO_SUO_2007 = {
    "id": "zhao_suo_2007", "type": "article-journal",
    "title": "Method to analyze electromechanical stability of dielectric elastomers",
    "author": [{"family": "Zhao", "given": "Xuanhe"}, {"family": "Suo", "given": "Zhigang"}],
    "container-title": "Applied Physics Letters", "volume": "91", "page": "061921",
    "issued": {"date-parts": [[2007]]}, "DOI": "10.1063/1.2768641",
}
ROACHE_1994 = {
    "id": "roache_1994", "type": "article-journal",
    "title": "Perspective: a method for uniform reporting of grid refinement studies",
    "author": [{"family": "Roache", "given": "P. J."}],
    "container-title": "Journal of Fluids Engineering", "volume": "116", "page": "405-413",
    "issued": {"date-parts": [[1994]]},
}
HUANG_1964 = {
    "id": "huang_1964", "type": "article-journal",
    "title": "Unsymmetrical buckling of thin shallow spherical shells",
    "author": [{"family": "Huang", "given": "N. C."}],
    "container-title": "Journal of Applied Mechanics", "volume": "31", "page": "447-457",
    "issued": {"date-parts": [[1964]]},
}
ZHU_CAI_SUO_2010 = {
    "id": "zhu_cai_suo_2010", "type": "article-journal",
    "title": "Nonlinear oscillation of a dielectric elastomer balloon",
    "author": [{"family": "Zhu", "given": "J."}, {"family": "Cai", "given": "S."},
               {"family": "Suo", "given": "Z."}],
    "container-title": "Polymer International", "volume": "59", "page": "378-383",
    "issued": {"date-parts": [[2010]]}, "DOI": "10.1002/pi.2767",
}
TIMOSHENKO_1925 = {
    "id": "timoshenko_1925", "type": "article-journal",
    "title": "Analysis of bi-metal thermostats",
    "author": [{"family": "Timoshenko", "given": "S."}],
    "container-title": "Journal of the Optical Society of America", "volume": "11",
    "issue": "3", "page": "233-255", "issued": {"date-parts": [[1925]]},
    "DOI": "10.1364/JOSA.11.000233",
}
LAND_2015 = {
    "id": "land_2015", "type": "article-journal",
    "title": "Verification of cardiac mechanics software: benchmark problems and solutions "
             "for testing active and passive material behaviour",
    "author": [{"family": "Land", "given": "S."}, {"literal": "et al."}],
    "container-title": "Proceedings of the Royal Society A", "volume": "471",
    "page": "20150641", "issued": {"date-parts": [[2015]]}, "DOI": "10.1098/rspa.2015.0641",
}
REFERENCES = {r["id"]: r for r in (THESIS, ZENG_GAO_2019, ZHAO_SUO_2007, ROACHE_1994,
                                   HUANG_1964, ZHU_CAI_SUO_2010, TIMOSHENKO_1925,
                                   LAND_2015)}


def _chapter(text: str) -> int | None:
    m = re.match(r"ch(\d)", text)
    return int(m.group(1)) if m else None


def _reference(text: str) -> dict[str, Any] | None:
    """The CSL item a problem spec's reference names: an id of :data:`REFERENCES`, or a
    free-text reference that contains the title of one; ``None`` for any other text."""
    if text in REFERENCES:
        return REFERENCES[text]
    folded = " ".join(text.split()).casefold()
    return next((r for r in REFERENCES.values() if r["title"].casefold() in folded), None)


def _candidates(item_id: str) -> list[dict[str, Any]]:
    """Everything ``item_id`` names, in the order :func:`citation` prefers: a reference
    problem, a dataset (``NAME`` or ``NAME.nc``; ``NAME.nc`` names only the dataset), a
    catalogue entry (its id or an id it replaces). Each is a dict: kind, title, chapter,
    thesis location, datasets, references (CSL items) and references given only as text."""
    out = []
    if not item_id.endswith(".nc"):
        try:
            p = problems.get(item_id)
        except problems.ProblemError:
            p = None
        if p is not None:
            refs = [(r, _reference(r)) for r in p.references]
            out.append({"kind": "reference problem", "title": p.title, "chapter": p.chapter,
                        "thesis": dict(p.thesis), "datasets": list(p.datasets),
                        "refs": [item for _, item in refs if item is not None],
                        "text_refs": [text for text, item in refs if item is None]})
    name = item_id.removesuffix(".nc")
    manifest = read_manifest(data_dir())
    if f"{name}.nc" in manifest:
        meta = manifest[f"{name}.nc"]
        # the dataset of a problem beyond the thesis cites that problem's sources
        beyond = [q for q in problems.load_all()
                  if q.chapter == problems.BEYOND_THESIS and name in q.datasets]
        refs = [(r, _reference(r)) for q in beyond for r in q.references]
        out.append({"kind": "dataset", "title": meta.get("title", name),
                    "chapter": problems.BEYOND_THESIS if beyond else _chapter(name),
                    "thesis": {}, "datasets": [name],
                    "refs": [item for _, item in refs if item is not None],
                    "text_refs": [text for text, item in refs if item is None]})
    entries = {e.id: e for e in catalogue.load()}
    entry = entries.get(item_id) or next(
        (e for e in entries.values() if e.replaces == item_id), None)
    if entry is not None:
        src = {k: v for k, v in entry.source.items() if v not in ("", None)}
        chapter = src.get("chapter") or _chapter(entry.id)
        out.append({"kind": f"catalogue entry ({entry.kind})",
                    "title": f"{entry.id}: {entry.quantity}",
                    "chapter": int(chapter) if str(chapter).isdigit() else None,
                    "thesis": src, "datasets": ["thesis_values"], "refs": [],
                    "text_refs": [], "entry_id": entry.id})
    return out


def _resolve(item_id: str) -> dict[str, Any]:
    """What ``item_id`` names (the first of :func:`_candidates`)."""
    found = _candidates(item_id)
    if not found:
        raise ValueError(f"ID {item_id!r} is neither a reference problem (debench problems), "
                         "a dataset (debench list datasets) nor a catalogue entry "
                         "(debench list claims)")
    return found[0]


def ambiguity(item_id: str) -> str | None:
    """What ``debench cite`` says when ``item_id`` names more than one thing: which one it
    cites and how to cite the others; ``None`` when it names one thing or nothing.

    Parameters
    ----------
    item_id : str
        A problem id, dataset name (with or without ``.nc``) or catalogue entry id.

    Returns
    -------
    str or None
        One sentence, e.g. that ``ch5_critical_voltage`` is cited as the reference
        problem and ``ch5_critical_voltage.nc`` cites the dataset of the same name.
    """
    found = _candidates(item_id)
    if len(found) < 2:
        return None
    others = []
    for c in found[1:]:
        if c["kind"] == "dataset":
            others.append(f"the dataset of the same name is cited as `debench cite "
                          f"{c['datasets'][0]}.nc`")
        else:
            others.append(f"the {c['kind']} {c.get('entry_id', item_id)} has the same name")
    return (f"{item_id} names {len(found)} things; this is the citation of the "
            f"{found[0]['kind']}; " + "; ".join(others))


def citation(item_id: str) -> list[dict[str, Any]]:
    """CSL-JSON items: debench (with the item cited) first, then its references."""

    info = _resolve(item_id)
    manifest = read_manifest(data_dir())
    sums = {d: manifest.get(f"{d}.nc", {}).get("sha256", "missing") for d in info["datasets"]}
    where = ", ".join(f"{k} {v}" for k, v in info["thesis"].items() if k != "note")
    commit = git_commit()
    today = datetime.date.today()
    note = "; ".join(filter(None, [
        f"{info['kind']} {item_id}", f"debench {__version__}, commit {commit}",
        *(f"{d}.nc sha256 {s}" for d, s in sums.items()),
        f"thesis {where}" if where else "",
        *(f"also cites: {' '.join(text.split())}" for text in info["text_refs"])]))
    # a problem beyond the thesis (chapter 0) cites its own sources, not the thesis
    refs = ([] if info["chapter"] == problems.BEYOND_THESIS else
            [THESIS] + ([ZENG_GAO_2019] if info["chapter"] == 3 else []))
    refs += [r for r in info["refs"] if r not in refs]
    main = {
        "id": f"debench_{re.sub(r'[^A-Za-z0-9]+', '_', item_id)}",
        "type": "dataset" if info["datasets"] else "software",
        "title": f"debench: {info['title']}",
        "author": [{"literal": "debench developers"}],
        "version": __version__, **({"URL": repo} if (repo := provenance.repository_url()) else {}),
        "note": note,
        "issued": {"date-parts": [[today.year]]},
        "accessed": {"date-parts": [[today.year, today.month, today.day]]},
        "references": "; ".join(r["id"] for r in refs),
    }
    urls = provenance.project_urls()
    refs = [{**r, "URL": urls[label]} if (label := URL_LABELS.get(r["id"])) in urls else r
            for r in refs]
    return [main, *refs]


def _bib_authors(item: dict[str, Any]) -> str:
    return " and ".join(a.get("literal") and f"{{{a['literal']}}}" or
                        f"{a['family']}, {a['given']}" for a in item["author"])


def bibtex(items: list[dict[str, Any]]) -> str:
    """BibTeX entries of CSL-JSON items from :func:`citation`."""
    out = []
    for it in items:
        kind = {"thesis": "phdthesis", "article-journal": "article"}.get(it["type"], "misc")
        fields = {"author": _bib_authors(it), "title": f"{{{it['title']}}}",
                  "year": str(it["issued"]["date-parts"][0][0])}
        if kind == "phdthesis":
            fields["school"] = it["publisher"]
        if kind == "article":
            fields["journal"] = it["container-title"]
            for k in ("volume", "page"):
                if k in it:
                    fields["pages" if k == "page" else k] = it[k]
        for key, bib in (("DOI", "doi"), ("URL", "url"), ("version", "version"),
                         ("note", "note")):
            if key in it:
                fields[bib] = it[key]
        body = ",\n".join(f"  {k} = {{{v}}}" for k, v in fields.items())
        out.append(f"@{kind}{{{it['id']},\n{body}\n}}")
    return "\n\n".join(out)


def render(item_id: str, fmt: str = "both") -> str:
    """What ``debench cite`` prints: ``bibtex``, ``csl`` (JSON) or ``both``."""
    if fmt not in ("bibtex", "csl", "both"):
        raise ValueError(f"fmt must be 'bibtex', 'csl' or 'both', got {fmt!r}")
    items = citation(item_id)
    parts = []
    if fmt in ("bibtex", "both"):
        parts.append(bibtex(items))
    if fmt in ("csl", "both"):
        parts.append(json.dumps(items, indent=1, ensure_ascii=False))
    return "\n\n".join(parts)
