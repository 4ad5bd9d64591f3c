"""Reference problems: benchmark specs that users check their own codes against.

A reference problem (one TOML file in ``reference/problems/``, in the spirit of the
cardiac-mechanics benchmark of Land et al. 2015; its completeness is checked against
``verification/schemas/problem-spec.schema.json``) states

* the **spec**: the model (energy with every parameter and its units, compressibility,
  the extension off J = 1 where stresses depend on it, the equations), every boundary
  with its kinematic and electric condition, the load path and what is controlled, the
  thesis section / equations / figure; a named **variant** says which default problem it
  varies and why (the thesis "as printed");
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

Curves are interpolated with a cubic spline in the abscissa (in its logarithm for
``along_scale = "log"``), piece by piece between gaps (NaN: no root, inadmissible state)
and jumps (a root number shifting as a root enters the stretch window); points in a gap,
on a jump or outside the curve are rejected with ``ValueError`` naming the curve. The
interpolation error at a point is estimated as the distance between that spline and the
spline through every other grid point (for a resolved smooth curve the O(h^4) error of the
coarse spline is about 16 times that of the full one, so the estimate is conservative)
and added to the tolerance; a stored grid point carries none. A curve with a square-root
end is splined in its square (``interpolate_power = 2``), one with poles in its product
with a weight that removes them (``interpolate_weight``).

:func:`coverage` says whether results cover every reference curve or value they address;
:func:`render_markdown` is the page ``debench problems ID --markdown`` prints.

Examples
--------
>>> from debench.reference import problems
>>> [p.id for p in problems.load_all()][:2]
['ch2_kernel_states', 'ch3_failure_points']
>>> problems.get("ch3_free_membrane_nh").quantity("phibar").units
'1'
"""

from __future__ import annotations

import importlib
import math
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np

PROBLEMS_DIR = Path(__file__).resolve().parent / "problems"
#: relative tolerance for matching a user's selector coordinate (lamP = 1.25) with the
#: stored grid value: grid values are printed decimals, so anything beyond round-off of a
#: decimal-to-binary conversion (1e-16) is a different grid point; 1e-9 is far above it
#: and far below any grid spacing (>= 1e-3)
COORD_MATCH_RTOL = 1e-9
#: an abscissa within this relative distance of a stored grid point takes the stored value
#: (no interpolation error): a few ulp, so only the grid printed by ``--json`` (17
#: significant digits, which round-trip exactly) and its round-off qualify
NODE_MATCH_RTOL = 1e-15


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
            return str(_dataset(self)[name].attrs.get("units", ""))
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
                "accuracy": q.accuracy.as_json()} for q in self.quantities],
        }


# --------------------------------------------------------------------------- loading
def _discretisation_error(ds, var, f: Mapping[str, Any]):
    """The discretisation error a dataset states for ``var``: ``{error = NAME}`` names a
    variable holding the error estimate; ``{variable, dim, index}`` bounds it by the
    distance of ``var`` from that level of ``variable`` (e.g. the finest mesh)."""
    if "error" in f:
        return np.abs(ds[f["error"]])
    fine = ds[f["variable"]].isel({f["dim"]: int(f["index"])})
    return np.abs(var - fine)


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
    return Quantity(accuracy=_accuracy(acc, where), discretisation_from=dfrom, **raw)


def load_file(path: Path) -> Problem:
    """One problem spec from a TOML file."""
    import copy

    raw = tomllib.loads(Path(path).read_text(encoding="utf-8"))
    parsed = copy.deepcopy(raw)
    where = Path(path).name
    try:
        quantities = tuple(_quantity(q, where) for q in raw.pop("quantity"))
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
    from debench.reference.datasets import data_dir, read_manifest

    manifest = read_manifest(data_dir())
    out = {}
    for name in problem.datasets:
        meta = manifest.get(f"{name}.nc", {})
        out[name] = {"file": f"{name}.nc", "sha256": meta.get("sha256", "missing"),
                     "commit": meta.get("commit", "")}
    return {"datasets": out, "thesis": problem.thesis}


# --------------------------------------------------------------------------- reference
def _function(q: Quantity):
    module, _, name = q.function.partition(":")
    fn = getattr(importlib.import_module(module), name)
    return lambda x: np.asarray(fn(np.asarray(x, dtype=float), **q.function_args), float)


def _dataset(q: Quantity):
    from debench.reference.datasets import read_dataset

    ds = read_dataset(q.dataset)
    return ds.sel(q.fixed) if q.fixed else ds


def _match(values: np.ndarray, wanted: Any, name: str) -> int:
    """Index of ``wanted`` in a coordinate (exact for text, COORD_MATCH_RTOL for numbers)."""
    wanted = wanted.item() if isinstance(wanted, np.generic) else wanted
    if values.dtype.kind in "fiu":
        try:
            w = float(wanted)
        except (TypeError, ValueError):
            raise ValueError(f"coordinate {name} must be numeric, got {wanted!r}") from None
        hit = np.nonzero(np.isclose(values, w, rtol=COORD_MATCH_RTOL, atol=0.0))[0]
    else:
        hit = np.nonzero(values.astype(str) == str(wanted))[0]
    if hit.size != 1:
        raise ValueError(f"coordinate {name} = {wanted!r} is not on the reference grid; "
                         f"choose from {values.tolist()}")
    return int(hit[0])


@dataclass(frozen=True)
class Reference:
    """Reference values and tolerances at the user's points."""

    value: np.ndarray
    tolerance: np.ndarray
    interpolation: np.ndarray


def _weight(q: Quantity, sel_values: Mapping[str, Any]):
    """The interpolation weight w(x) of ``q`` at the selected curve (None: no weight)."""
    if not q.interpolate_weight:
        return None
    module, _, name = q.interpolate_weight["function"].partition(":")
    fn = getattr(importlib.import_module(module), name)
    kw = {**q.interpolate_weight.get("args", {}),
          **{k: float(sel_values[k]) for k in q.interpolate_weight.get("selectors", ())}}
    return lambda x: np.asarray(fn(np.asarray(x, dtype=float), **kw), dtype=float)


#: an interval of a stored curve whose change exceeds this many times the larger change of
#: its two neighbours is a jump, not a resolved part of the curve: on these grids the
#: changes of neighbouring intervals of a smooth curve differ by a factor <= 3 (square-root
#: ends and turning points included); a root number that shifts because a root enters or
#: leaves the stretch window changes by 10-1000 times more
JUMP_FACTOR = 20.0
#: ... and exceeds this fraction of the curve's magnitude (round-off on flat parts is no jump)
JUMP_FLOOR = 1e-6


def _transformed(x, y, power: float = 1.0, weight=None):
    """The values a curve is splined in: ``y**power * weight(x)``."""
    v = y**power
    if weight is not None:
        v = v * weight(x)
    return v


def _pieces(t: np.ndarray, v: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) indices of the runs of finite ``v`` (sorted abscissa ``t``) that hold
    no jump (:data:`JUMP_FACTOR`): the pieces a spline may cover."""
    ok = np.isfinite(v) & np.isfinite(t)
    d = np.abs(np.diff(v))
    nb = np.full(d.shape, np.nan)
    if d.size > 1:
        nb[1:] = d[:-1]
        nb[:-1] = np.fmax(nb[:-1], d[1:])
    scale = np.nanmax(np.abs(v[ok])) if ok.any() else 0.0
    with np.errstate(invalid="ignore"):
        jump = (d > JUMP_FACTOR * np.nan_to_num(nb, nan=np.inf)) & (d > JUMP_FLOOR * scale)
    out, start = [], None
    for k in range(v.size):
        if not ok[k]:
            if start is not None:
                out.append((start, k - 1))
            start = None
            continue
        if start is None:
            start = k
        if k < v.size - 1 and jump[k]:
            out.append((start, k))
            start = None
    if start is not None:
        out.append((start, v.size - 1))
    return out


def _curve_at(x: np.ndarray, y: np.ndarray, xq: np.ndarray, name: str, log: bool,
              power: float = 1.0, weight=None):
    """Cubic-spline value and its error estimate (distance to the half-grid spline).

    ``power`` p: interpolate ``y**p`` (a curve with a square-root end, such as Phibar near
    Phibar = 0, is smooth in Phibar^2), then return ``(.)**(1/p)``. ``weight`` w(x):
    interpolate ``y**p w`` (smooth where y^p has poles), then divide by w(xq). Each piece
    of the curve (:func:`_pieces`: between gaps and jumps) has its own spline; a point in
    a gap, on a jump or outside the finite range is refused.
    """
    from scipy.interpolate import CubicSpline

    order = np.argsort(x)
    x, y = x[order], y[order]
    finite = np.isfinite(x)
    x, y = x[finite], y[finite]
    ok = np.isfinite(y)
    if ok.sum() < 2:
        raise ValueError(f"the reference curve has fewer than 2 points along {name}")
    lo, hi = x[ok].min(), x[ok].max()
    outside = (xq < lo) | (xq > hi) | ~np.isfinite(xq)
    if outside.any():
        raise ValueError(f"{name} must lie in the reference range [{lo:.6g}, {hi:.6g}]; "
                         f"got {xq[outside][:3].tolist()}")
    t = np.log(x) if log else x
    tq = np.log(xq) if log else xq
    v = _transformed(x, y, power, weight)
    pieces = _pieces(t, v)
    k = np.clip(np.searchsorted(x, xq), 0, x.size - 1)
    node = np.isclose(x[k], xq, rtol=NODE_MATCH_RTOL, atol=0.0) & ok[k]
    value, error = np.full(xq.size, np.nan), np.zeros(xq.size)
    value[node] = y[k[node]]
    todo = ~node
    for a, b in pieces:
        inside = todo & (xq >= x[a]) & (xq <= x[b])
        if not inside.any():
            continue
        if b - a + 1 < 4:
            raise ValueError(f"{name} = {xq[inside][:3].tolist()} lies on a piece of the "
                             f"reference curve too short to interpolate with an error "
                             f"estimate ({b - a + 1} points)")
        tt, vv = t[a:b + 1], v[a:b + 1]
        half = np.unique(np.r_[np.arange(0, tt.size, 2), tt.size - 1])
        cubic = CubicSpline(tt, vv)(tq[inside])
        coarse = CubicSpline(tt[half], vv[half])(tq[inside])
        if weight is not None:
            wq = weight(xq[inside])
            cubic, coarse = cubic / wq, coarse / wq
        if power != 1.0:
            cubic, coarse = (np.maximum(cubic, 0.0) ** (1 / power),
                             np.maximum(coarse, 0.0) ** (1 / power))
        value[inside], error[inside] = cubic, np.abs(cubic - coarse)
        todo &= ~inside
    if todo.any():
        raise ValueError(f"{name} = {xq[todo][:3].tolist()} falls in a gap of the reference "
                         "curve (no reference value there: no root or inadmissible state) "
                         "or on a jump of it (a root enters or leaves the stretch window "
                         "and the root numbers shift)")
    return value, error


def _describe(chosen: Mapping[str, Any]) -> str:
    """``xi = 5, Dhat = 5, root = 0``: the curve a message is about."""
    def show(v):
        v = v.item() if isinstance(v, np.generic) else v
        return f"{v:g}" if isinstance(v, float) else str(v)
    return ", ".join(f"{k} = {show(v)}" for k, v in chosen.items()) or "the curve"


def reference_at(problem: Problem, quantity: Quantity,
                 coords: Mapping[str, Any]) -> Reference:
    """Reference values, tolerances (stated accuracy) and interpolation error estimates at
    the user's points; ``coords`` maps coordinate names to scalars or arrays (broadcast)."""
    names = quantity.coordinates
    given = {**quantity.defaults, **dict(coords)}
    missing = [n for n in names if n not in given]
    if missing:
        raise ValueError(f"coords lack {missing} (problem {problem.id}, quantity "
                         f"{quantity.name} needs {list(names)})")
    extra = sorted(set(coords) - set(names))
    if extra:
        raise ValueError(f"coords has unknown names {extra}; {quantity.name} takes {list(names)}")
    arrays = np.broadcast_arrays(*[np.asarray(given[n]) for n in names])
    arrays = [a.ravel() for a in arrays]
    n = arrays[0].size if arrays else 1
    if quantity.source == "function":
        xq = np.asarray(arrays[-1], dtype=float)
        lo, hi = float(quantity.grid["start"]), float(quantity.grid["stop"])
        outside = ~((xq >= lo) & (xq <= hi))
        if outside.any():
            raise ValueError(f"{quantity.along} must lie in the reference range [{lo:g}, "
                             f"{hi:g}] (problem {problem.id}); got "
                             f"{xq[outside][:3].tolist()}")
        ref = _function(quantity)(xq)
        zeros = np.zeros(n)
        return Reference(ref, quantity.accuracy.tolerance(ref), zeros)
    ds = _dataset(quantity)
    var = ds[quantity.variable]
    disc_var = None
    if quantity.discretisation_from:
        disc_var = _discretisation_error(ds, var, quantity.discretisation_from)
    value, interp, disc = np.empty(n), np.zeros(n), np.zeros(n)
    keys = list(zip(*arrays[:len(quantity.select)], strict=True)) if quantity.select else [()] * n
    groups: dict[tuple, list[int]] = {}
    for i, k in enumerate(keys):
        groups.setdefault(tuple(str(v) for v in k), []).append(i)
    for _, idx in groups.items():
        first = idx[0]
        sel = {s: _match(ds[s].values, arrays[j][first], s)
               for j, s in enumerate(quantity.select)}
        y = var.isel(sel)
        d = disc_var.isel(sel) if disc_var is not None else None
        if quantity.along is None:
            if y.ndim:
                raise ProblemError(f"{problem.id}:{quantity.name}: selectors leave dims "
                                   f"{y.dims}; the spec must select all of them")
            value[idx] = float(y)
            if d is not None:
                disc[idx] = float(d)
        else:
            x = ds[quantity.along]
            x = x.isel({k: v for k, v in sel.items() if k in x.dims})
            if x.ndim != 1 or y.ndim != 1:
                raise ProblemError(f"{problem.id}:{quantity.name}: curve is not 1-D after "
                                   f"selection ({y.dims})")
            xq = np.asarray(arrays[-1][idx], dtype=float)
            chosen = {s: ds[s].values[i] for s, i in sel.items()}
            try:
                value[idx], interp[idx] = _curve_at(
                    np.asarray(x.values, float), np.asarray(y.values, float), xq,
                    quantity.along, quantity.along_scale == "log",
                    quantity.interpolate_power, _weight(quantity, chosen))
            except ValueError as exc:
                raise ValueError(f"{_describe(chosen)}: {exc}") from None
    tol = quantity.accuracy.tolerance(value, quantity.accuracy.discretisation + disc)
    return Reference(value, tol + interp, interp)


def reference_json(problem: Problem) -> dict[str, Any]:
    """Spec plus, per quantity, the reference coordinates, values, units and accuracy."""

    def clean(a):
        a = np.asarray(a)
        if a.dtype.kind == "f":
            return np.where(np.isfinite(a), a, None).tolist()
        return a.astype(str).tolist() if a.dtype.kind in "US" else a.tolist()

    out = {"spec": problem.spec(), "reference": {}}
    for q in problem.quantities:
        item: dict[str, Any] = {"units": q.units, "long_name": q.long_name,
                                "accuracy": q.accuracy.as_json()}
        if q.source == "function":
            x = np.linspace(q.grid["start"], q.grid["stop"], int(q.grid["num"]))
            item.update(dims=[q.along], coords={q.along: clean(x)},
                        values=clean(_function(q)(x)))
        else:
            ds = _dataset(q)
            var = ds[q.variable]
            item.update(dims=list(var.dims),
                        coords={d: clean(ds[d].values) for d in var.dims},
                        values=clean(var.values))
            if q.along:
                a = ds[q.along]
                item["along"] = {"name": q.along, "units": q.along_units,
                                 "dims": list(a.dims), "values": clean(a.values)}
            if q.discretisation_from:
                item["discretisation_error"] = clean(
                    _discretisation_error(ds, var, q.discretisation_from).values)
        out["reference"][q.name] = item
    return out


# --------------------------------------------------------------------------- rendering
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
    out = [f"# {p.id}: {p.title}", "", f"Chapter {p.chapter}. {p.summary}", ""]
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
           else f"closed form on the grid {q.grid}")
    if q.fixed:
        src += " at " + ", ".join(f"{k} = {v}" for k, v in q.fixed.items())
    header = ",".join(f"{c} [{q.units_of(c)}]" if (c in q.coordinate_units and
                      q.units_of(c)) or c == q.along else c for c in q.coordinates)
    out += [f"**Reference values.** {src}; `debench problems {p.id} --json` prints "
            "them with their coordinates.", "",
            f"**Check.** `debench check {p.id} results.csv` with the header "
            f"`{header},{q.name} [{q.units}]`. Coverage: every stored "
            + ("curve" if q.along else "value") + " of every value of a selector "
            "without a default, and of the values your file gives of one with a "
            "default" + (", each at least as densely as the stored grid over its "
                         "whole range (any points; the stored ones are exact)"
                         if q.along else "") + "; or pass `--partial` and the report "
            "says what was covered.", ""]
    return out


def _md_shared_files(p: Problem) -> list[str]:
    """How quantities sharing their coordinates are checked from one file."""
    out: list[str] = []
    groups: dict[tuple, list[Quantity]] = {}
    for q in p.quantities:
        groups.setdefault(tuple(sorted(q.coordinates)), []).append(q)
    for qs in (g for g in groups.values() if len(g) > 1):
        q0 = qs[0]
        header = ",".join(f"{c} [{q0.units_of(c)}]" if (c in q0.coordinate_units and
                          q0.units_of(c)) or c == q0.along else c for c in q0.coordinates)
        header += "".join(f",{q.name} [{q.units}]" for q in qs)
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
    out.append("Thesis: " + ", ".join(f"{k} {v}" for k, v in p.thesis.items()))
    return "\n".join(out) + "\n"


# --------------------------------------------------------------------------- coverage
class CoverageError(ValueError):
    """Results that do not cover the reference points they address (and did not declare
    partial coverage)."""


@dataclass(frozen=True)
class Coverage:
    """How much of the addressed reference a set of results covers.

    ``required``: the reference curves (or values) the results address: every grid value
    of a selector without a default, the values given (or the default) of a selector with
    one; ``covered``: those fully covered (a curve: on each finite stretch of the stored
    curve, the points span it and no gap between them, nor to its ends, exceeds the widest
    stored spacing there, in log for a log abscissa; a value: present). ``missing``:
    descriptions of the others (the first few).
    """

    declared: str
    required: int
    covered: int
    missing: tuple[str, ...]

    @property
    def complete(self) -> bool:
        return self.covered == self.required

    def describe(self) -> str:
        what = f"{self.covered}/{self.required} addressed reference curves or values covered"
        if self.complete:
            return f"coverage complete ({what})"
        head = "; ".join(self.missing[:3]) + (" ..." if len(self.missing) > 3 else "")
        return f"PARTIAL coverage ({self.declared}): {what}; not covered: {head}"


#: slack on "no gap wider than the widest stored spacing": relative round-off of the
#: user's printed abscissae (17 digits) is far below it, a skipped grid point far above
COVERAGE_GAP_SLACK = 1e-9


def _curve_covered(x: np.ndarray, y: np.ndarray, xq: np.ndarray, log: bool) -> str | None:
    """None if the points ``xq`` cover every piece of the curve (x, y) (values splined
    as ``y``; :func:`_pieces`: between gaps and jumps), else why."""
    order = np.argsort(x)
    x, y = x[order], y[order]
    t = np.log(x) if log else x
    tq = np.sort(np.log(xq) if log else xq)
    for a, b in _pieces(t, y):
        if b - a < 1:
            continue   # an isolated stored value: nothing to interpolate, not required
        seg = t[a:b + 1]
        gap = float(np.max(np.diff(seg))) * (1 + COVERAGE_GAP_SLACK)
        inside = tq[(tq >= seg[0] - gap) & (tq <= seg[-1] + gap)]
        pts = np.concatenate([[seg[0]], np.clip(inside, seg[0], seg[-1]), [seg[-1]]])
        widest = float(np.max(np.diff(pts)))
        if widest > gap:
            lo, hi = (np.exp(seg[[0, -1]]) if log else seg[[0, -1]])
            return (f"range [{lo:.6g}, {hi:.6g}] has a gap of {widest:.3g}"
                    f"{' in log' if log else ''} between your points (the reference "
                    f"spacing there is <= {gap:.3g})")
    return None


def coverage(problem: Problem, quantity: Quantity, coords: Mapping[str, Any], *,
             declared: str = "none") -> Coverage:
    """The :class:`Coverage` of results at ``coords`` (names -> arrays, as
    :func:`reference_at`) of the reference of ``quantity``."""
    import itertools

    given = {**quantity.defaults, **dict(coords)}
    names = quantity.coordinates
    arrays = [np.ravel(a) for a in np.broadcast_arrays(*[np.asarray(given[n])
                                                         for n in names])]
    sel_arrays = dict(zip(quantity.select, arrays[:len(quantity.select)], strict=True))
    if quantity.source == "function":
        x = np.linspace(quantity.grid["start"], quantity.grid["stop"],
                        int(quantity.grid["num"]))
        why = _curve_covered(x, np.ones_like(x), np.asarray(arrays[-1], float),
                             quantity.along_scale == "log")
        return Coverage(declared, 1, int(why is None),
                        () if why is None else (f"{quantity.along}: {why}",))
    ds = _dataset(quantity)
    var = ds[quantity.variable]
    choices = []
    for s in quantity.select:
        grid = ds[s].values
        if s in quantity.defaults:
            wanted = list(dict.fromkeys(np.asarray(sel_arrays[s]).tolist()))
            choices.append([_match(grid, w, s) for w in wanted])
        else:
            choices.append(list(range(grid.size)))
    required = covered = 0
    missing: list[str] = []
    # the user's points by grid combination (selector values matched as reference_at does)
    by_combo: dict[tuple, list[int]] = {}
    groups: dict[tuple, list[int]] = {}
    for i, k in enumerate(zip(*[sel_arrays[s] for s in quantity.select], strict=True)
                          if quantity.select else [()] * arrays[0].size):
        groups.setdefault(tuple(str(v) for v in k), []).append(i)
    for idx in groups.values():
        combo = tuple(_match(ds[s].values, sel_arrays[s][idx[0]], s) for s in quantity.select)
        by_combo.setdefault(combo, []).extend(idx)
    for combo in itertools.product(*choices):
        sel = dict(zip(quantity.select, combo, strict=True))
        y = np.asarray(var.isel(sel).values, float)
        if not np.isfinite(y).any():
            continue   # no reference value at all (e.g. a root number that never occurs)
        required += 1
        chosen = {s: ds[s].values[i] for s, i in sel.items()}
        mine = by_combo.get(tuple(combo), [])
        if quantity.along is None:
            if mine:
                covered += 1
            else:
                missing.append(_describe(chosen))
            continue
        x = ds[quantity.along].isel({k: v for k, v in sel.items()
                                     if k in ds[quantity.along].dims})
        xv = np.asarray(x.values, float)
        why = ("no points" if not mine else
               _curve_covered(xv, _transformed(xv, y, quantity.interpolate_power,
                                               _weight(quantity, chosen)),
                              np.asarray(arrays[-1], float)[mine],
                              quantity.along_scale == "log"))
        if why is None:
            covered += 1
        else:
            missing.append(f"{_describe(chosen)}: {why}")
    return Coverage(declared, required, covered, tuple(missing))


def duplicates(quantity: Quantity, coords: Mapping[str, Any]) -> list[str]:
    """Coordinate tuples that occur more than once in ``coords`` (described)."""
    given = {**quantity.defaults, **dict(coords)}
    names = quantity.coordinates
    arrays = [np.ravel(a) for a in np.broadcast_arrays(*[np.asarray(given[n])
                                                         for n in names])]
    seen: dict[tuple, int] = {}
    for row in zip(*arrays, strict=True):
        k = tuple(str(v) for v in row)
        seen[k] = seen.get(k, 0) + 1
    return [", ".join(f"{n} = {v}" for n, v in zip(names, k, strict=True)) + f" ({c} times)"
            for k, c in seen.items() if c > 1]
