"""Whether a regenerated dataset matches its curated counterpart, each numeric variable
within the accuracy it states (``debench reproduce`` and ``debench verify``)."""

from __future__ import annotations

from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr
from debench.reference import builds
from debench.reference.datasets import DatasetError, data_dir, read_dataset
from debench.reference.figures import not_written
from debench.reference.values import extra_guards

#: Default agreement of a regenerated numeric variable with its curated counterpart, for
#: variables that state no accuracy of their own: the builders' solvers stop at relative
#: tolerances <= 1e-10 and a recomputation on another CPU/BLAS moves their values by
#: < 1e-8 relative (measured across OpenBLAS kernels), so 1e-6 keeps a 100x margin; the
#: absolute floor 1e-12 covers values that vanish (differences of equal quantities)
REGEN_RTOL = 1e-6
REGEN_ATOL = 1e-12


def regeneration_tolerance(attrs) -> tuple[float, float]:
    """(rtol, atol) to which a regenerated variable must match its curated counterpart.

    A variable that states its own accuracy (attributes ``accuracy_rtol`` and/or
    ``accuracy_atol``, the producer's :class:`~debench.reference.catalogue.Accuracy` of
    its values) is judged by it, tighter or looser than the default; any other numeric
    variable by :data:`REGEN_RTOL` and :data:`REGEN_ATOL`.
    """
    if "accuracy_rtol" not in attrs and "accuracy_atol" not in attrs:
        return REGEN_RTOL, REGEN_ATOL
    rtol, atol = (float(attrs.get(k, 0.0)) for k in ("accuracy_rtol", "accuracy_atol"))
    if not (np.isfinite(rtol) and np.isfinite(atol) and rtol >= 0 and atol >= 0
            and rtol + atol > 0):
        raise ValueError(f"accuracy_rtol and accuracy_atol must be finite, >= 0 and not both "
                         f"0, got {rtol}, {atol}")
    return rtol, atol


#: per dataset, the variables compared element by element within the absolute tolerance
#: stored beside them: the store of our values (:mod:`debench.reference.values`), each value
#: with the tolerance its method supports (the thesis values beside their printed-digit
#: tolerances are literals: compared by the default, i.e. equal)
TOLERANCE_VARIABLES = {"our_values": {"value": "tolerance"}}
#: a residual (backward error, Newton residual) of a converged solve is round-off: it
#: reproduces in size, not in digits (measured: eigen-residuals of ~3e-12 regenerate
#: within a factor 2). It matches when it stays below RESIDUAL_GROWTH x its curated value
#: (or REGEN_ATOL): a solve that got worse by an order of magnitude still shows.
RESIDUAL_GROWTH = 10.0


def is_residual(name: str, attrs) -> bool:
    """Whether a variable is a residual of a solve: quality information
    (``coverage_content_type``) named a residual."""
    return (attrs.get("coverage_content_type") == "qualityInformation"
            and "residual" in name)


def _numeric_match(name: str, var: str, new, old) -> bool:
    a, b = np.asarray(old[var].values, float), np.asarray(new[var].values, float)
    same_nan = np.array_equal(np.isnan(a), np.isnan(b))
    ok = ~np.isnan(a)
    tol_var = TOLERANCE_VARIABLES.get(name, {}).get(var)
    if tol_var is not None and tol_var in old and old[tol_var].shape == old[var].shape:
        tol = np.asarray(old[tol_var].values, float)
        return same_nan and bool(np.all(np.abs(b[ok] - a[ok]) <= tol[ok]))
    if is_residual(var, old[var].attrs):
        return same_nan and bool(np.all(np.abs(b[ok]) <= np.maximum(
            RESIDUAL_GROWTH * np.abs(a[ok]), REGEN_ATOL)))
    rtol, atol = regeneration_tolerance(old[var].attrs)
    return bool(np.allclose(b, a, rtol=rtol, atol=atol, equal_nan=True))


@dataclass(frozen=True)
class PlanCheck:
    """What of a dataset whose default plan is cheaper than its curated (``--full``) plan
    is checked against the curated dataset, and why that much.

    ``converged``: variables that estimate the limit of the discretisation, independent of
    the plan, each with the variable holding its error estimate; a default value agrees
    when it lies within the sum of the two plans' error estimates of the curated value
    (each bounds its own value's distance from the limit). ``same_mesh``: variables given
    per discretisation, with the coordinate naming it and the relative accuracy the values
    state; on the discretisations both plans compute they must agree within it.
    ``note``: what is not compared and why.
    """

    converged: dict[str, str] = field(default_factory=dict)
    same_mesh: dict[str, tuple[str, float]] = field(default_factory=dict)
    note: str = ""


#: The pull-in voltage and deflection of one ramp mesh are the vertex of the parabola
#: through three path points (:func:`debench.models.buckling.solver.voltage_ramp`: < 1e-3
#: relative), which path step control may place differently
PULLIN_VERTEX_RTOL = 1e-3
_AXISYM_PATH_CONVERGED = ("v_max", "w_max", "thickness_max", "lam_at_max", "w_cross",
                          "v_cross")

#: The datasets whose default plan differs from the curated plan (coarser meshes, fewer
#: cases or orders): what ``debench reproduce`` checks of them (:class:`PlanCheck`).
PLAN_CHECKS = {
    "ch5_critical_voltage": PlanCheck(
        converged={"v_cr_reference": "v_cr_reference_error"},
        note=("per-mesh values, the in-plane limit at the plan's layer count and the "
              "through-thickness study are at other meshes or layer counts in the two "
              "plans")),
    "ch5_ramps": PlanCheck(
        same_mesh={"v_pullin_levels": ("ramp_level", PULLIN_VERTEX_RTOL),
                   "w_pullin_levels": ("ramp_level", PULLIN_VERTEX_RTOL)},
        note=("the default plan ramps one mesh, so it has no error estimate of the mesh "
              "limit: its pull-in is checked on the mesh both plans ramp; the paths have "
              "other steps")),
    "ch5_axisym": PlanCheck(
        converged={"v_cr_converged": "v_cr_error"},
        note="per-discretisation values are on other orders and gradings in the two plans"),
    "ch5_axisym_methods": PlanCheck(
        converged={"v_cr_converged": "v_cr_error"},
        note="per-discretisation values are on other orders and gradings in the two plans"),
    "ch5_axisym_path": PlanCheck(
        converged={f"{q}_converged": f"{q}_error" for q in _AXISYM_PATH_CONVERGED},
        note=("per-discretisation paths and the 3D-like study are on other discretisations "
              "in the two plans; the default plan has the neo-Hookean film and "
              "wavenumbers 1-4 only")),
    "lit_bilayer": PlanCheck(
        converged={"tip_deflection": "tip_deflection_error",
                   "tip_rotation": "tip_rotation_error"},
        note="the per-order values are on other orders and gradings in the two plans"),
}


def _on_shared(new, old, var: str, key: str | None = None):
    """``var`` of both datasets on the coordinates they share (inner join; along the
    dimension that ``key`` labels, by ``key``): (new values, old values, the datasets
    aligned), or None when the variable is missing or the two cannot be aligned."""
    if var not in new or var not in old:
        return None
    a, b = new, old
    if key is not None and new[key].dims[0] != key:
        dim = new[key].dims[0]
        a, b = a.swap_dims({dim: key}), b.swap_dims({dim: key})
    try:
        a, b = xr.align(a, b, join="inner", exclude=set(a.dims) - set(a[var].dims))
    except ValueError:
        return None
    if a[var].shape != b[var].shape or a[var].size == 0:
        return None
    return np.asarray(a[var].values, float), np.asarray(b[var].values, float), a, b


def compare_plans(name: str, new, old) -> str:
    """One line: the default plan's values of dataset ``name`` checked against the curated
    ones as :data:`PLAN_CHECKS` declares (converged values within the sum of the two error
    estimates, shared-discretisation values within their stated accuracy), each variable
    with its largest |difference| relative to its bound; ``DIFFERS`` when one leaves it."""
    check = PLAN_CHECKS[name]
    parts, bad = [], []
    for var, err in check.converged.items():
        got = _on_shared(new, old, var)
        if got is None:
            bad.append(f"{var} (not on shared coordinates)")
            continue
        a, b, na, ob = got
        bound = np.asarray(na[err].values, float) + np.asarray(ob[err].values, float)
        both = np.isfinite(a) & np.isfinite(b)
        if not np.array_equal(np.isfinite(a), np.isfinite(b)) or np.any(~np.isfinite(
                bound[both])):
            bad.append(f"{var} (a value or its error estimate missing on one side)")
            continue
        ratio = float(np.max(np.abs(a[both] - b[both]) / bound[both], initial=0.0))
        parts.append(f"{var} {ratio:.2g}")
        if ratio > 1.0:
            bad.append(f"{var} (|difference| = {ratio:.3g} x the error estimates)")
    for var, (key, rtol) in check.same_mesh.items():
        got = _on_shared(new, old, var, key)
        if got is None:
            bad.append(f"{var} (no {key} in both plans)")
            continue
        a, b, na, _ = got
        both = np.isfinite(a) & np.isfinite(b)
        ratio = float(np.max(np.abs(a[both] - b[both]) / (rtol * np.abs(b[both])),
                             initial=0.0))
        shared = ", ".join(f"{x:g}" for x in np.atleast_1d(na[key].values))
        parts.append(f"{var} at {key} {shared} {ratio:.2g}")
        if ratio > 1.0 or not np.array_equal(np.isfinite(a), np.isfinite(b)):
            bad.append(f"{var} (|difference| = {ratio:.3g} x the stated {rtol:g} relative)")
    what = []
    if check.converged:
        what.append("converged values within the sum of both error estimates")
    if check.same_mesh:
        what.append("values on the discretisations both plans compute within their stated "
                    "accuracy")
    head = (f"{name}.nc: default plan, cheaper than the curated --full plan: checked "
            f"{' and '.join(what)} (largest |difference| / bound: {'; '.join(parts)})")
    verdict = "agrees with curated" if not bad else "DIFFERS in " + ", ".join(bad)
    return f"{head}: {verdict}; not compared: {check.note}"


def compare_with_curated(path: Path, curated_dir: Path) -> str:
    """One line saying whether a regenerated dataset matches the curated one.

    Numeric variables must agree within the accuracy they state: a variable with a
    per-element absolute tolerance beside it (the store of our values: ``value`` within
    ``tolerance``, :data:`TOLERANCE_VARIABLES`) within that tolerance; a residual
    (:func:`is_residual`) by its size; any other within :func:`regeneration_tolerance`
    of the curated variable (``|new - old| <= atol + rtol |old|``); NaN where the curated
    value is NaN. Text variables exactly. A dataset computed with other parameters than the
    curated one (the default plan of a study whose curated data are ``--full``) is checked
    as :data:`PLAN_CHECKS` declares (:func:`compare_plans`).
    """
    curated = curated_dir / path.name
    if not curated.exists():
        return f"{path.name}: no curated counterpart in {curated_dir}"
    try:
        new, old = read_dataset(path), read_dataset(curated)
    except DatasetError as exc:
        return f"{path.name}: cannot compare ({exc})"
    if new.attrs.get("parameters") != old.attrs.get("parameters"):
        if path.stem in PLAN_CHECKS:
            return compare_plans(path.stem, new, old)
        return (f"{path.name}: not comparable (different parameters, e.g. mesh resolution, "
                "and no declared check of such plans: PLAN_CHECKS)")
    bad = []
    for var in old.data_vars:
        if var not in new:
            bad.append(f"{var} missing")
        elif np.issubdtype(old[var].dtype, np.number):
            if old[var].shape != new[var].shape or not _numeric_match(
                    path.stem, var, new, old):
                bad.append(var)
        elif not np.array_equal(new[var].values, old[var].values):
            bad.append(var)
    return f"{path.name}: {'matches curated' if not bad else 'DIFFERS in ' + ', '.join(bad)}"


# --------------------------------------------------------------------------- verify's work
def _regenerate(chapter: str, out: str) -> list[str]:
    """Rebuild ``chapter`` (default plan, no figures) into ``out`` and compare each dataset
    with its curated counterpart: one line per dataset (:func:`compare_with_curated`)."""
    mod = builds.builder(chapter)
    if mod is None:
        return []
    with not_written():
        paths = list(mod.build(Path(out) / chapter, full=False))
    return [compare_with_curated(p, data_dir()) for p in paths if p.suffix == ".nc"]


class Recomputations:
    """The recomputations of ``debench verify``: the cheap chapters rebuilt and compared with
    data/ (``chapters``), and the model guards (``guards``: names of
    :func:`debench.reference.values.model_guard_names`).

    With ``jobs`` > 1 they start at once in a pool of ``jobs`` processes (longest first, by
    the CPU seconds each builder declares), so that they run beside the catalogue
    evaluation of the calling process; with ``jobs`` = 1 each runs in this process when its
    result is asked for. :meth:`lines` and :meth:`guarded` return the results in the order
    given; an exception of a job is raised there. Use as a context manager (the pool and
    the output directory ``out`` are the caller's; the pool is ended on exit)."""

    def __init__(self, chapters, guards, *, jobs: int, out: Path):
        self.chapters, self.guards, self.out = tuple(chapters), tuple(guards), str(out)
        self._executor, self._futures = None, {}
        work = [("chapter", c) for c in self.chapters] + [("guard", g) for g in self.guards]
        if jobs > 1 and len(work) > 1:
            self._executor = ProcessPoolExecutor(
                max_workers=min(jobs, len(work)), mp_context=builds.pool_context(),
                initializer=builds.init_pool_process)
            every = builds.chapters()
            cost = builds.build_cpu_s(every) | builds.model_guards(every)
            for kind, name in sorted(work, key=lambda w: -cost.get(w[1], 0.0)):
                self._futures[(kind, name)] = self._executor.submit(*self._job(kind, name))

    def _job(self, kind: str, name: str):
        """The function and arguments of one recomputation."""
        return (_regenerate, name, self.out) if kind == "chapter" else (extra_guards, [name])

    def _result(self, kind: str, name: str):
        fut = self._futures.get((kind, name))
        if fut is not None:
            return fut.result()
        fn, *args = self._job(kind, name)
        return fn(*args)

    def lines(self) -> list[str]:
        """The comparison line of every regenerated dataset, chapter by chapter."""
        return [line for c in self.chapters for line in self._result("chapter", c)]

    def guarded(self) -> list:
        """The :class:`~debench.reference.values.Guarded` values of every guard."""
        return [g for name in self.guards for g in self._result("guard", name)]

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self._executor is not None:
            if exc[0] is not None:
                builds.stop_pool(self._executor)
            else:
                self._executor.shutdown(wait=True)
        return False
