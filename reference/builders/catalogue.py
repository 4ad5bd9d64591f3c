"""Builder of ``thesis_values.nc`` (the thesis catalogue as a citable dataset) and of
``our_values.nc`` (our computed values with the tolerance their methods support).

One row (dimension ``entry``) per catalogue entry: its id, kind, the value as printed,
the numeric value (NaN when not numeric), unit, implied tolerance and where it stands in
the thesis. Statuses are *not* stored: they are computed by ``debench verify`` from the
code and change as the models improve; this file holds what the thesis (or the cited
literature) states.

``our_values.nc`` (:mod:`debench.reference.values`) holds every value our producers and
model guards compute, its tolerance and the status it gave; ``debench verify`` recomputes
them and fails when one leaves its tolerance.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import xarray as xr
from debench.reference import catalogue, values
from debench.reference.datasets import DatasetError, read_dataset, write_dataset

#: CPU seconds of the default build: the catalogue is built last, from the command's one
#: catalogue evaluation, so its cost orders nothing.
BUILD_CPU_S = 0.0
#: ``debench verify`` does not rebuild this chapter (minutes of CPU, or the catalogue itself):
#: its model guards and the value check stand for it.
REGENERATED_BY_VERIFY = False
#: Model guards ``debench verify`` runs for this chapter (none).
GUARDS = {}

NAME = "thesis_values"


def _num(value) -> float:
    if isinstance(value, bool):
        return float(value)
    if isinstance(value, int | float):
        return float(value)
    return np.nan


def catalogue_dataset(entries: list[catalogue.Entry] | None = None) -> xr.Dataset:
    """The catalogue as an :class:`xarray.Dataset` (no global provenance attributes)."""
    entries = entries if entries is not None else catalogue.load()

    def text(name: str, values: list[str], long_name: str) -> tuple:
        return ("entry", np.array(values, dtype=object), {"long_name": long_name})

    src = [e.source for e in entries]
    tol = [e.implied_tolerance() for e in entries]
    data = {
        "kind": text("kind", [e.kind for e in entries],
                     "kind of entry: claim, erratum, assumption or literature"),
        "quantity": text("quantity", [e.quantity for e in entries], "the quantity in words"),
        "value": ("entry", np.array([_num(e.value) for e in entries]),
                  {"long_name": "numeric value as stated (NaN when not numeric)",
                   "units": "1",
                   "comment": "units differ per entry: see variable 'unit'"}),
        "value_text": text("value_text", [str(e.value) for e in entries],
                           "value as stated, as text (qualitative claims, errata)"),
        "printed": text("printed", [e.printed or "" for e in entries],
                        "value exactly as printed in the thesis"),
        "unit": text("unit", [e.unit for e in entries], "UDUNITS unit of the value"),
        "tolerance": ("entry", np.array([np.nan if t is None else t for t in tol]),
                      {"long_name": "absolute tolerance implied by the printed digits "
                                    "(or explicit, with reason)", "units": "1",
                       "comment": "in the unit of each entry"}),
        "section": text("section", [str(s.get("section", "")) for s in src], "thesis section"),
        "equation": text("equation", [str(s.get("equation", "")) for s in src],
                         "thesis equation number(s)"),
        "figure": text("figure", [str(s.get("figure", "")) for s in src], "thesis figure"),
        "table": text("table", [str(s.get("table", "")) for s in src], "thesis table"),
        "page": text("page", [str(s.get("page", "")) for s in src],
                     "thesis page number as printed"),
        "parameters": text("parameters",
                           [json.dumps(e.parameters, sort_keys=True) for e in entries],
                           "model parameters producing the value (JSON)"),
        "reference": text("reference", [e.reference for e in entries],
                          "literature reference (kind literature)"),
        "as_printed": text("as_printed", [e.as_printed for e in entries],
                           "erratum: the printed form"),
        "corrected": text("corrected", [e.corrected for e in entries],
                          "erratum: the corrected form"),
        "root_cause": text("root_cause", [e.root_cause for e in entries],
                           "the erratum that is the root error of this entry (an erratum "
                           "names itself when it is the root; empty: none)"),
    }
    coords = {"entry": ("entry", np.array([e.id for e in entries], dtype=object),
                        {"long_name": "stable catalogue identifier"})}
    return xr.Dataset(data, coords=coords)


def thesis_values_problems(data_dir: Path | None = None) -> list[str]:
    """Differences between the curated ``thesis_values.nc`` and the catalogue files."""
    try:
        curated = read_dataset(NAME, data_dir=data_dir)
    except DatasetError as exc:
        return [str(exc)]
    fresh = catalogue_dataset()
    if curated.sizes != fresh.sizes or list(curated.entry.values) != list(fresh.entry.values):
        return [f"{NAME}.nc: entries differ from the catalogue files "
                "(run `debench reproduce catalogue --write-data`)"]
    bad = [v for v in fresh.data_vars
           if not np.array_equal(np.asarray(curated[v].values, dtype=fresh[v].dtype),
                                 fresh[v].values, equal_nan=fresh[v].dtype.kind == "f")]
    return [f"{NAME}.nc: {', '.join(bad)} differ from the catalogue files (run "
            "`debench reproduce catalogue --write-data`)"] if bad else []


def build(out_dir: Path, *, full: bool = False, results=None, guards=None) -> list[Path]:
    """Write ``thesis_values.nc`` and ``our_values.nc`` into ``out_dir`` (``full`` has no
    effect); ``results``: ``catalogue.evaluate_all()`` and ``guards``: the values of
    :func:`debench.reference.values.extra_guards`, when the caller has them (computed here
    otherwise)."""
    entries = catalogue.load()
    ds = catalogue_dataset(entries)
    path = write_dataset(
        ds, NAME, out_dir=out_dir, overwrite=True,
        title="Values stated in Zeng (2020), with provenance",
        summary=("Every number and checkable statement of the dissertation 'Deformation and "
                 "stability of dielectric elastomer films used in actuators' (Chapters 2-5, "
                 "Appendix A), the errata found, the assumptions debench makes where the "
                 "thesis is silent, and independent literature reference values, each with "
                 "section, equation, figure, table and page."),
        parameters={"n_entries": len(entries),
                    "catalogue_files": ",".join(sorted({e.file for e in entries}))},
    )
    results = catalogue.evaluate_all(entries) if results is None else results
    errors = [r.entry.id for r in results if r.status == "error"]
    if errors:
        raise RuntimeError(f"producers raised for {errors}: fix them before storing values")
    guards = values.guarded_from_results(results) + (values.extra_guards() if guards is None
                                                      else list(guards))
    ours = write_dataset(
        values.store_dataset(guards), values.STORE_NAME, out_dir=out_dir, overwrite=True,
        title="debench's computed values with the tolerances their methods support",
        summary=("Every value the debench producers compute for the catalogue of Zeng (2020) "
                 "(main values and numeric details), the Chapter 5 finite-element model "
                 "recomputed on its coarsest mesh, the absolute tolerance each method "
                 "supports and what sets it, and the status each entry received. "
                 "`debench verify` recomputes them and fails when one leaves its tolerance."),
        parameters={"n_values": len(guards), "n_entries": len(entries),
                    "extra_guards": ",".join(values.model_guard_names())},
    )
    return [path, ours]
