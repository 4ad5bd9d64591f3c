"""Reference problems: benchmark specs that users check their own codes against.

A reference problem (one TOML file in ``reference/problems/``, in the spirit of the
cardiac-mechanics benchmark of Land et al. 2015; its completeness is checked against
``verification/schemas/problem-spec.schema.json``) states

* the **spec**: the model (energy with every parameter and its units, compressibility,
  the extension off J = 1 where stresses depend on it, the equations), every boundary
  with its kinematic and electric condition, the load path and what is controlled, the
  thesis section / equations / figure (a problem beyond the thesis has ``chapter = 0``
  and names its sources in ``references`` instead); a named **variant** says which
  default problem it varies and why (the thesis "as printed");
* per **quantity of interest**: its exact definition (formula, criterion, tangent,
  branch, root numbering, normalisation), its domain (window, and what is excluded and
  why), its coordinates with units (``select``: matched exactly; ``along``: the abscissa
  of a curve, interpolated; ``fixed``: dataset coordinates held at one value), and where
  the reference values come from: a curated dataset (``source = "dataset"``, read verified
  by :func:`debench.reference.datasets.read_dataset`) or a closed form
  (``source = "function"``, refused outside its grid's range);
* the **accuracy** of the reference values: the solver tolerance (the ``ACCURACY`` of the
  producer module that guards the values, ``from = "module:ACCURACY"``, or an explicit
  ``rtol``/``atol``) plus the discretisation error, measured (``discretisation_atol``) or
  read from the dataset (``discretisation_from``), each with its reason.

The reference values at a user's points (interpolation, tolerances) are in
:mod:`debench.reference.problems_reference`, whether results cover them in
:mod:`debench.reference.problems_coverage`, and the page ``debench problems ID
--markdown`` prints in :mod:`debench.reference.problems_markdown`.

Examples
--------
>>> from debench.reference import problems
>>> [p.id for p in problems.load_all()][:2]
['ch2_kernel_states', 'ch3_failure_points']
>>> problems.get("ch3_free_membrane_nh").quantity("phibar").units
'1'
"""

from __future__ import annotations

import copy
import importlib
import math
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
from debench.reference.datasets import data_dir, read_dataset, read_manifest

PROBLEMS_DIR = Path(__file__).resolve().parent / "problems"
#: the ``chapter`` of a problem beyond the thesis (the literature's problems other DE codes
#: validate on): it names its sources in ``references`` and has no ``thesis`` location
BEYOND_THESIS = 0


class ProblemError(ValueError):
    """A malformed problem spec or an unknown problem / quantity."""


@dataclass(frozen=True)
class ReferenceAccuracy:
    """Accuracy of a reference value: ``atol + rtol |ref| + discretisation``.

    ``discretisation`` is a number (measured, stated in the spec) or, for datasets that
    carry it implicitly, an array read from the dataset per reference value.
    """

    rtol: float
    atol: float
    reason: str
    discretisation: Any = 0.0
    discretisation_reason: str = ""

    def tolerance(self, reference: np.ndarray, discretisation=None) -> np.ndarray:
        d = self.discretisation if discretisation is None else discretisation
        return self.atol + self.rtol * np.abs(reference) + np.asarray(d, dtype=float)

    def as_json(self) -> dict[str, Any]:
        d = self.discretisation
        return {"rtol": self.rtol, "atol": self.atol, "solver_reason": self.reason,
                "discretisation_atol": (float(d) if np.ndim(d) == 0 else "per value"),
                "discretisation_reason": self.discretisation_reason}


@dataclass(frozen=True)
class Quantity:
    """One quantity of interest of a problem (a ``[[quantity]]`` table)."""

    name: str
    long_name: str
    units: str
    source: str
    accuracy: ReferenceAccuracy
    select: tuple[str, ...] = ()
    defaults: dict[str, Any] = field(default_factory=dict)
    along: str | None = None
    along_long_name: str = ""
    along_units: str = "1"
    along_scale: str = "linear"
    interpolate_power: float = 1.0
    #: ``{function = "module:name", selectors = [...], args = {...}}``: a weight w(x) such
    #: that y^p w is smooth where y^p has poles (interpolated instead of y^p)
    interpolate_weight: dict[str, Any] = field(default_factory=dict)
    dataset: str | None = None
    variable: str | None = None
    function: str | None = None
    function_args: dict[str, Any] = field(default_factory=dict)
    grid: dict[str, Any] = field(default_factory=dict)
    discretisation_from: dict[str, Any] = field(default_factory=dict)
    #: dataset coordinates held at one value for this problem (e.g. the equilibrium
    #: variant of a dataset that stores several), selected before anything else
    fixed: dict[str, Any] = field(default_factory=dict)
    #: units of each coordinate ("" for a text coordinate such as a material name)
    coordinate_units: dict[str, str] = field(default_factory=dict)
    #: exact definition: formula, criterion, tangent, branch, root_numbering, normalisation
    definition: dict[str, str] = field(default_factory=dict)
    #: where the reference is defined: window, and what is excluded and why
    domain: dict[str, Any] = field(default_factory=dict)
    #: how the reference is confirmed (``[[quantity.confirmation]]``): per record its
    #: ``status`` ("confirmed": a second computation sharing no code with the reference,
    #: its ``method``, ``implementation``, the ``test`` asserting agreement at the stated
    #: accuracy, its ``tier``, the ``command`` reproducing it and what it ``covers``;
    #: "missing": the ``reason``). What it measured is in ``reference/confirmations.json``
    #: (``debench.reference.confirmations``).
    confirmation: tuple[dict[str, Any], ...] = ()

    @property
    def coordinates(self) -> tuple[str, ...]:
        """Coordinate names a user supplies (selectors, then the abscissa)."""
        return self.select + ((self.along,) if self.along else ())

    def units_of(self, name: str) -> str:
        """Units of the quantity or of one of its coordinates ("" for text)."""
        if name == self.name:
            return self.units
        if name == self.along:
            return self.along_units
        if name in self.coordinate_units:
            return self.coordinate_units[name]
        if name in self.select and self.source == "dataset":
            # a spec that does not state them: the units the dataset's coordinate carries
            # (CF: numeric coordinates have units; text ones none)
            return str(quantity_dataset(self)[name].attrs.get("units", ""))
        raise ProblemError(f"quantity {self.name} has no coordinate {name!r}; "
                           f"coordinates {list(self.coordinates)}")


@dataclass(frozen=True)
class Problem:
    """A reference problem: spec, quantities, provenance."""

    id: str
    title: str
    chapter: int
    summary: str
    geometry: str
    boundary_conditions: Any
    loading: Any
    thesis: dict[str, Any]
    parameters: dict[str, dict[str, Any]]
    quantities: tuple[Quantity, ...]
    catalogue: tuple[str, ...] = ()
    references: tuple[str, ...] = ()
    file: str = ""
    #: energy, compressibility, extension off J = 1, equations, materials
    model: dict[str, Any] = field(default_factory=dict)
    #: for a named variant: the default problem it varies and why it exists
    variant: dict[str, str] | None = None
    #: the spec as parsed from TOML (what the schema validates)
    raw: dict[str, Any] = field(default_factory=dict, repr=False, compare=False)

    def quantity(self, name: str | None = None) -> Quantity:
        """The quantity ``name`` (default: the only one)."""
        names = [q.name for q in self.quantities]
        if name is None:
            if len(self.quantities) != 1:
                raise ProblemError(f"problem {self.id} has quantities {names}: name one")
            return self.quantities[0]
        for q in self.quantities:
            if q.name == name:
                return q
        raise ProblemError(f"problem {self.id} has no quantity {name!r}; choose from {names}")

    @property
    def chapter_label(self) -> str:
        """``ch3`` (the thesis chapter), or ``beyond`` for a problem beyond the thesis."""
        return "beyond" if self.chapter == BEYOND_THESIS else f"ch{self.chapter}"

    @property
    def where(self) -> str:
        """``Chapter 3`` or ``beyond the thesis`` (what a page or listing says)."""
        return ("beyond the thesis" if self.chapter == BEYOND_THESIS
                else f"Chapter {self.chapter}")

    @property
    def datasets(self) -> tuple[str, ...]:
        return tuple(dict.fromkeys(q.dataset for q in self.quantities if q.dataset))

    def spec(self) -> dict[str, Any]:
        """The spec as plain data (what ``debench problems ID --json`` prints first)."""
        return {
            "id": self.id, "title": self.title, "chapter": self.chapter,
            "summary": self.summary, "geometry": self.geometry,
            "boundary_conditions": self.boundary_conditions, "loading": self.loading,
            "model": self.model, "variant": self.variant,
            "thesis": self.thesis, "parameters": self.parameters,
            "catalogue": list(self.catalogue), "references": list(self.references),
            "provenance": provenance(self),
            "quantities": [{
                "name": q.name, "long_name": q.long_name, "units": q.units,
                "coordinates": list(q.coordinates), "select": list(q.select),
                "coordinate_units": {c: q.units_of(c) for c in q.coordinates
                                     if c in q.coordinate_units or c == q.along},
                "definition": q.definition, "domain": q.domain,
                "defaults": q.defaults, "along": q.along, "along_units": q.along_units,
                "source": (f"dataset {q.dataset}:{q.variable}" if q.source == "dataset"
                           else f"closed form {q.function}({q.function_args})"),
                "accuracy": q.accuracy.as_json(),
                "confirmation": [dict(c) for c in q.confirmation]} for q in self.quantities],
        }


# --------------------------------------------------------------------------- loading
def _accuracy(raw: Mapping[str, Any], where: str) -> ReferenceAccuracy:
    raw = dict(raw)
    if "from" in raw:
        module, _, attr = raw["from"].partition(":")
        acc = getattr(importlib.import_module(module), attr or "ACCURACY")
        rtol, atol, reason = acc.rtol, acc.atol, f"{acc.reason} ({raw['from']})"
    else:
        try:
            rtol, atol, reason = float(raw["rtol"]), float(raw["atol"]), str(raw["reason"])
        except KeyError as exc:
            raise ProblemError(f"{where}: accuracy needs 'from' or rtol, atol and reason "
                               f"(missing {exc})") from None
    disc = float(raw.get("discretisation_atol", 0.0))
    if not raw.get("discretisation"):
        raise ProblemError(f"{where}: accuracy.discretisation must state the discretisation "
                           "error or why there is none")
    for name, x in (("rtol", rtol), ("atol", atol), ("discretisation_atol", disc)):
        if not (math.isfinite(x) and x >= 0):
            raise ProblemError(f"{where}: accuracy.{name} must be finite and >= 0, got {x}")
    return ReferenceAccuracy(rtol=rtol, atol=atol, reason=reason, discretisation=disc,
                    discretisation_reason=str(raw["discretisation"]))


#: fields a ``[[quantity.confirmation]]`` record needs, by status
CONFIRMATION_FIELDS = {
    "confirmed": ("method", "implementation", "test", "tier", "command", "covers"),
    "missing": ("reason",),
}


def _confirmation(raw: Mapping[str, Any], where: str) -> dict[str, Any]:
    raw = dict(raw)
    status = raw.get("status")
    if status not in CONFIRMATION_FIELDS:
        raise ProblemError(f"{where}: confirmation status must be one of "
                           f"{sorted(CONFIRMATION_FIELDS)}, got {status!r}")
    lacking = [k for k in CONFIRMATION_FIELDS[status] if not raw.get(k)]
    if lacking:
        raise ProblemError(f"{where}: a {status} confirmation needs {lacking}")
    if status == "confirmed" and raw["tier"] not in ("default", "slow"):
        raise ProblemError(f"{where}: confirmation tier must be 'default' or 'slow', got "
                           f"{raw['tier']!r}")
    return raw


def _quantity(raw: Mapping[str, Any], where: str) -> Quantity:
    raw = dict(raw)
    where = f"{where} quantity {raw.get('name')!r}"
    source = raw.get("source")
    if source not in ("dataset", "function"):
        raise ProblemError(f"{where}: source must be 'dataset' or 'function', got {source!r}")
    if source == "dataset" and not (raw.get("dataset") and raw.get("variable")):
        raise ProblemError(f"{where}: a dataset quantity needs 'dataset' and 'variable'")
    if source == "function" and not (raw.get("function") and raw.get("along")):
        raise ProblemError(f"{where}: a closed-form quantity needs 'function' and 'along'")
    acc = raw.pop("accuracy", None)
    if acc is None:
        raise ProblemError(f"{where}: every quantity states its accuracy")
    dfrom = dict(acc.get("discretisation_from", {}))
    known = set(Quantity.__dataclass_fields__) - {"accuracy", "discretisation_from"}
    unknown = set(raw) - known
    if unknown:
        raise ProblemError(f"{where}: unknown fields {sorted(unknown)}")
    raw["select"] = tuple(raw.get("select", ()))
    raw["confirmation"] = tuple(_confirmation(c, where) for c in raw.get("confirmation", ()))
    return Quantity(accuracy=_accuracy(acc, where), discretisation_from=dfrom, **raw)


def load_file(path: Path) -> Problem:
    """One problem spec from a TOML file."""
    raw = tomllib.loads(Path(path).read_text(encoding="utf-8"))
    parsed = copy.deepcopy(raw)
    where = Path(path).name
    try:
        quantities = tuple(_quantity(q, where) for q in raw.pop("quantity"))
        if raw.get("chapter") == BEYOND_THESIS and "thesis" not in raw:
            if not raw.get("references"):
                raise ProblemError(f"{where}: a problem beyond the thesis (chapter = 0) "
                                   "names its sources in 'references'")
            raw["thesis"] = {}
        problem = Problem(
            catalogue=tuple(raw.pop("catalogue", ())),
            references=tuple(raw.pop("references", ())),
            quantities=quantities, file=where, raw=parsed, **raw)
    except (KeyError, TypeError) as exc:
        raise ProblemError(f"{where}: malformed problem spec ({exc})") from None
    if problem.id != Path(path).stem:
        raise ProblemError(f"{where}: id {problem.id!r} must equal the file name")
    return problem


@cache
def load_all() -> tuple[Problem, ...]:
    """Every reference problem, sorted by id."""
    return tuple(sorted((load_file(p) for p in PROBLEMS_DIR.glob("*.toml")),
                        key=lambda p: p.id))


def get(problem_id: str) -> Problem:
    """The problem ``problem_id`` (``ProblemError`` naming the known ids otherwise)."""
    for p in load_all():
        if p.id == problem_id:
            return p
    raise ProblemError(f"unknown problem {problem_id!r}; known: "
                       f"{', '.join(p.id for p in load_all())}")


def provenance(problem: Problem) -> dict[str, Any]:
    """Datasets (with sha256 from the manifest) and the thesis location of a problem."""
    manifest = read_manifest(data_dir())
    out = {}
    for name in problem.datasets:
        meta = manifest.get(f"{name}.nc", {})
        out[name] = {"file": f"{name}.nc", "sha256": meta.get("sha256", "missing"),
                     "commit": meta.get("commit", "")}
    return {"datasets": out, "thesis": problem.thesis}


def quantity_dataset(q: Quantity):
    """The curated dataset a ``source = "dataset"`` quantity reads its reference from
    (read verified by :func:`debench.reference.datasets.read_dataset`), with the
    quantity's ``fixed`` coordinates selected."""
    ds = read_dataset(q.dataset)
    return ds.sel(q.fixed) if q.fixed else ds
