"""Chapter 5 datasets and figures: the clamped dielectric buckling membrane (NGSolve).

``build(out_dir, full=False)`` writes

* ``ch5_critical_voltage.nc`` -- critical normalised voltage of the perfect film by the
  linearised eigen-analysis on a sequence of meshes (case x level), the fitted
  convergence rate and Richardson limit, plate-theory estimates (Kirchhoff, Mindlin) and
  the Southwell estimate from the ramp of the imperfect film;
* ``ch5_ramps.nc`` -- centre deflection, thickness and true field versus normalised
  voltage of the imperfect film (case x step), pull-in (bracketed limit point), the
  eigenvalues of the condensed tangent along the path and their modes' axisymmetric
  fraction (wrinkling detection);
* figures mirroring Figs 5.4 and 5.6 and the mesh-convergence of the critical voltage.

``full=False``: coarse meshes (in-plane size 3, 2, 1.4 t0; ramps at 3 t0), about a minute
on one core.  ``full=True``: refined meshes (down to 0.5 t0; ramps at 1 t0), hours, run as
independent tasks on Dask ``distributed`` (:func:`run_tasks`).  The 0.5 mm Ogden case is
the 1 mm case by scale invariance (:data:`SCALE_COPIES`).  :func:`coarse_values` recomputes
the coarsest level of every case (``debench verify``).
"""

from __future__ import annotations

import hashlib
import math
import os
import pickle
import sys
from pathlib import Path

import numpy as np
import xarray as xr
from debench.models.errors import ConvergenceError
from debench.models.materials.constants import OGDEN_DELTA
from debench.reference.builders._ch5_tasks import (  # noqa: F401 - re-exported
    CASES,
    EIG_EVERY,
    ORDER,
    RAMP_DV_MAX,
    _limit_threads,
    _material,
    critical_task,
    ramp_task,
)
from debench.reference.datasets import write_dataset
from scipy.optimize import brentq

SCALE_COPIES = {"ogden_t0p5": "ogden_t1"}
"""Cases identical in normalised variables by scale invariance (radius/thickness fixed: no
intrinsic length; ``verification/test_ch5_fem.py::test_normalised_results_are_scale_invariant``
checks it on the coarse mesh): computed once, from the case they copy."""
LEVELS = {False: (3.0, 2.0, 1.4), True: (3.0, 2.0, 1.4, 1.0, 0.7, 0.45)}
"""In-plane mesh sizes / t0 of the critical-voltage sequence (the finest full level, 0.45 t0
with two layers, has about 150,000 DOFs)."""
LAYERS = {False: 1, True: 2}
"""Layers of quadratic prisms through the thickness of the mesh sequences."""
LAYER_STUDY = {False: (3.0, (1, 2)), True: (2.0, (1, 2, 3, 4))}
"""(in-plane size, layer counts) of the through-thickness convergence study."""
RAMP_LEVELS = {False: (3.0,), True: (3.0, 2.5, 2.0)}
"""In-plane mesh sizes of the ramps (pull-in); the finest is the ramp stored step by step."""
RAMP_LAYERS = 1
"""Layers of the ramps: one. With two layers the Ogden ramp at h = 2 t0 met a singular
tangent at v = 0.449, just below its pull-in (direct solve residual NaN in the
eigen-analysis along the path), and the converged run stopped; the layer effect on the
critical voltage is measured by the through-thickness study (``v_cr_layers``)."""
GUARD_DV_MAX = 0.04  # coarse_values(): only the pull-in is needed (step-independent to
                     # the parabola's accuracy)
COARSE_H = 3.0      # the coarsest level: what coarse_values() and `debench verify` recompute


def expected_order(case: str) -> float:
    """Asymptotic convergence order of the critical voltage of ``case`` on quadratic prisms:
    2 s(nu), s the Williams exponent of the clamped-free edge at the material's small-strain
    Poisson ratio (:mod:`debench.models.buckling.singularity`)."""
    from debench.models.buckling.singularity import expected_eigenvalue_order, poisson_ratio
    mat = _material(CASES[case][0])
    mu0 = getattr(mat, "mu", None) or float(sum(mat.mus))   # initial shear modulus
    return expected_eigenvalue_order(poisson_ratio(mu0, mat.k), order=ORDER)


def richardson(h, v):
    """Fit v = v_inf + C h^p through the last three levels; returns (v_inf, p)."""
    h1, h2, h3 = h[-3:]
    v1, v2, v3 = v[-3:]
    ratio = (v1 - v2) / (v2 - v3)

    def f(p):
        return (h1**p - h2**p) / (h2**p - h3**p) - ratio

    if not (math.isfinite(ratio) and ratio > 0 and f(0.05) * f(8.0) < 0):
        raise ConvergenceError(f"richardson: levels {list(v[-3:])} at h = {list(h[-3:])} do "
                               "not converge monotonically at a rate in [0.05, 8]")
    p = brentq(f, 0.05, 8.0)
    c = (v2 - v3) / (h2**p - h3**p)
    return v3 - c * h3**p, p


#: On synthetic sequences v_inf + C h^1.7 + D h^3 with the h^3 term 1-4 % of the leading
#: one at the coarsest level (5 levels, h = 3 ... 0.7), the true error of the fitted limit
#: was up to 2x the larger of (drop-a-level change, fit residual); 3x covers it.
FIT_SAFETY = 3.0


def propagated_accuracy(f, x, dx) -> np.ndarray:
    """Bound on the change of ``f(x)`` (an array function of an array) when each input
    ``x[i]`` moves by up to ``dx[i]``: the sum over inputs of the change each causes alone
    (first order, one input at a time), elementwise. Regenerated derived values (ratios,
    extrapolations, error estimates) may differ from the curated ones by this much when
    their inputs are iterates converged only to ``dx``."""
    x = np.asarray(x, float)
    dx = np.broadcast_to(np.asarray(dx, float), x.shape)
    base = np.asarray(f(x), float)
    out = np.zeros_like(base)
    for i in np.ndindex(x.shape):
        xi = x.copy()
        xi[i] += dx[i]
        out += np.abs(np.asarray(f(xi), float) - base)
    return out


def convergence_fit(h, v, expected_order: float | None = None) -> dict[str, float]:
    """Mesh limit of ``v(h) = v_inf + C h^p`` with an error estimate.

    Three levels: the exact three-point fit (:func:`richardson`); its error estimate is
    the distance of the limit from the finest level (no redundancy to do better). Four or
    more levels (more levels than unknowns): least squares over all levels (log-spaced
    start from the three-point fit); the error estimate is :data:`FIT_SAFETY` times the
    larger of the change of the limit when the coarsest level is dropped and the largest
    fit residual.

    ``expected_order``: the asymptotic rate the discretisation theory predicts (for the
    critical voltage, twice the edge-singularity exponent,
    :func:`debench.models.buckling.singularity.expected_eigenvalue_order`). A sequence that
    is not yet in the asymptotic range fits a faster, pre-asymptotic rate, and the fit's own
    redundancy cannot see that its limit is then too close to the finest level. With it the
    error estimate also covers the limit extrapolated from the two finest levels at the
    expected rate, ``v_exp``: the error is the larger of the estimate above and
    :data:`FIT_SAFETY` times ``|v_inf - v_exp|``. Returns ``v_inf``, ``p``, ``error``,
    ``residual`` (largest |fit - v|, 0 for three levels) and, with ``expected_order``,
    ``v_inf_expected_order``.
    """
    from scipy.optimize import least_squares

    h, v = np.asarray(h, float), np.asarray(v, float)
    if h.size < 3:
        raise ValueError(f"convergence_fit needs >= 3 levels, got {h.size}")
    if expected_order is not None and not (math.isfinite(expected_order)
                                           and 0 < expected_order <= 8.0):
        raise ValueError(f"expected_order = {expected_order!r} must lie in (0, 8]")

    def with_expected(out):
        if expected_order is None:
            return out
        v_exp = v[-1] + (v[-1] - v[-2]) / ((h[-2] / h[-1]) ** expected_order - 1.0)
        out["v_inf_expected_order"] = float(v_exp)
        out["error"] = max(out["error"], FIT_SAFETY * abs(out["v_inf"] - float(v_exp)))
        return out

    if h.size == 3:
        v3, p3 = richardson(h, v)
        return with_expected({"v_inf": float(v3), "p": float(p3),
                              "error": float(abs(v3 - v[-1])), "residual": 0.0})
    try:
        v3, p3 = richardson(h, v)
    except ConvergenceError:  # the finest three are not monotone: start from the data
        v3, p3 = float(v[-1]), 1.0
    scale = abs(v[-1] - v[-2]) or 1.0

    def fit(hh, vv, start):
        c0 = (vv[-1] - start[0]) / hh[-1] ** start[1]
        res = least_squares(lambda x: (x[0] + x[1] * hh**x[2] - vv) / scale,
                            [start[0], c0, start[1]], bounds=([-np.inf, -np.inf, 0.05],
                                                              [np.inf, np.inf, 8.0]))
        if not res.success:
            raise ConvergenceError(f"convergence_fit: least squares failed ({res.message})")
        return res.x, float(np.max(np.abs(res.fun))) * scale

    (vi, _, p), resid = fit(h, v, (v3, p3))
    if not 0.05 + 1e-6 < p < 8.0 - 1e-6:
        raise ConvergenceError(f"convergence_fit: the fitted rate {p:.4g} is at a bound of "
                               f"[0.05, 8]: levels {v.tolist()} at h = {h.tolist()} are not "
                               "in the asymptotic range")
    dropped = fit(h[1:], v[1:], (v3, p3))[0][0] if h.size >= 4 else vi
    return with_expected({"v_inf": float(vi), "p": float(p), "residual": float(resid),
                          "error": FIT_SAFETY * float(max(abs(vi - dropped), resid))})


#: levels of the asymptotic fit: the finest three (two unknowns at the known order, one
#: level of redundancy for the residual)
ASYMPTOTIC_LEVELS = 3


def asymptotic_fit(h, v, order: float) -> dict[str, float]:
    """Mesh limit at the known asymptotic order: ``v(h) = v_inf + C h^order`` by least
    squares over the finest :data:`ASYMPTOTIC_LEVELS` levels.

    For the critical voltage the order is twice the edge-singularity exponent
    (:func:`expected_order`); the finest levels are the asymptotic range (their observed
    order, ``p``, is the three-point rate of :func:`richardson`, asserted against the
    expected one by the converged-data tests). The error estimate is :data:`FIT_SAFETY`
    times the largest of: the fit residual; the distance from the three-point limit with a
    free rate (a sequence not yet at the expected order: the coarse default); and, when a
    coarser level exists, the change of the limit when it is added to the fit (what is
    left of pre-asymptotic terms). Returns ``v_inf``, ``p``, ``error``, ``residual`` and
    the three ``error_*`` terms.
    """
    h, v = np.asarray(h, float), np.asarray(v, float)
    if h.size < ASYMPTOTIC_LEVELS:
        raise ValueError(f"asymptotic_fit needs >= {ASYMPTOTIC_LEVELS} levels, got {h.size}")
    if not (math.isfinite(order) and 0 < order <= 8.0):
        raise ValueError(f"order = {order!r} must lie in (0, 8]")

    def fixed(n):
        a = np.column_stack([np.ones(n), h[-n:] ** order])
        x = np.linalg.lstsq(a, v[-n:], rcond=None)[0]
        return float(x[0]), float(np.max(np.abs(a @ x - v[-n:])))

    n = ASYMPTOTIC_LEVELS
    v_inf, resid = fixed(n)
    try:
        v_free, p_obs = richardson(h[-n:], v[-n:])
        free = abs(v_free - v_inf)
    except ConvergenceError:   # not monotone: no rate; the spread of the levels bounds it
        p_obs, free = float("nan"), float(np.max(np.abs(v[-n:] - v[-1])))
    added = abs(fixed(n + 1)[0] - v_inf) if h.size > n else 0.0
    return {"v_inf": v_inf, "p": float(p_obs), "residual": resid,
            "error": FIT_SAFETY * max(resid, free, added), "error_residual": resid,
            "error_free_order": free, "error_added_level": added}


#: the observed order of the finest three levels agrees with the expected order when within
#: this distance: the three-point rate of a sequence v_inf + C h^q + D h^(2q) with the
#: second term below ~20 % of the first at the coarsest of the three stays within 0.25 of
#: q; the secant tolerance 1e-6 is 0.1 % of the level differences (~1e-3) and moves it by
#: far less
ORDER_TOL = 0.25


def reference_fit(h, v, order: float) -> dict[str, float]:
    """The mesh limit a dataset reports: :func:`asymptotic_fit` at the expected ``order``
    when the finest three levels show that order (observed within :data:`ORDER_TOL`: the
    asymptotic range), else -- a pre-asymptotic sequence such as the coarse default --
    :func:`convergence_fit` with a free rate over all levels and the expected-order bound
    on its error. ``kind`` says which; ``p`` is the observed order of the finest three."""
    fit = asymptotic_fit(h, v, order)
    if abs(fit["p"] - order) <= ORDER_TOL:
        return fit | {"kind": "expected order, three finest levels"}
    free = convergence_fit(h, v, expected_order=order)
    return free | {"p": fit["p"], "kind": "free rate, all levels (pre-asymptotic)"}


# ------------------------------------------------------------------ tasks (plain data out)
def _cost(task: tuple) -> float:
    """Rough relative cost of a task (DOFs ~ layers / h^2 x aspect^2; Ogden assembles ~3x
    slower; a ramp is ~8 critical voltages): the longest tasks are submitted first.  Tasks
    whose first argument is the in-plane mesh size (the radius/thickness 20 paths, all of
    one kind within a build) cost ~ 1 / h^2."""
    if task[0] not in (critical_task, ramp_task):
        h = task[1] if len(task) > 1 else None
        return 1.0 / h**2 if isinstance(h, float) and h > 0 else 1.0
    fn, case, h, *rest = task
    layers = rest[2] if fn is ramp_task and len(rest) > 2 else (rest[0] if rest else 1)
    aspect = (rest[3] if fn is ramp_task and len(rest) > 3
              else rest[1] if fn is critical_task and len(rest) > 1 else 10.0)
    c = (2 * layers + 1) / h**2 * (aspect / 10.0) ** 2
    return c * (3.0 if CASES[case][0] == "ogden" else 1.0) * (8.0 if fn is ramp_task else 1.0)


def run_tasks(tasks: list[tuple], scheduler=None, progress: bool = True) -> list:
    """Run ``(function, *args)`` tasks serially (``scheduler=None``) or on Dask
    ``distributed``: ``"local"`` starts a LocalCluster sized to the machine (one process per
    core, one thread each; ``DEBENCH_WORKERS`` overrides the number), any other string is
    the address of an existing scheduler (e.g. one started by dask-jobqueue on SLURM/PBS or
    by dask-kubernetes).  Results come back in task order.  With ``DEBENCH_FE_CACHE`` set
    to a directory, each finished task's result is kept there as it finishes (keyed on the
    task and the source of the code that computes it) so that a long sweep resumes after
    an interruption (:class:`_TaskCache`)."""
    cache = _TaskCache.from_env()
    out = [cache.get(t) if cache is not None else None for t in tasks]
    todo = [i for i, r in enumerate(out) if r is None]
    failed: list[tuple[int, BaseException]] = []
    log = progress and not sys.stderr.isatty()     # a line per task in logs (no bar)

    def finished(i, result, error=None):
        if error is not None:
            failed.append((i, error))
        else:
            out[i] = result
            if cache is not None:
                cache.put(tasks[i], result)
        if log:
            fn, *args = tasks[i]
            print(f"ch5 FE: {fn.__name__}{tuple(args)} "
                  f"{'FAILED: ' + repr(error) if error is not None else 'done'} "
                  f"[{len(todo) - sum(r is None for r in out) + len(failed)}/{len(todo)}]",
                  file=sys.stderr, flush=True)

    if not todo:
        return out
    if scheduler is None:
        try:
            from tqdm import tqdm
        except ImportError:  # pragma: no cover
            tqdm = None
        it = tqdm(todo, desc="ch5 FE", disable=(not progress) or None) if tqdm else todo
        for i in it:
            fn, *args = tasks[i]
            try:
                result = fn(*args)
            except Exception as exc:  # noqa: BLE001 - the others still run (and are cached)
                finished(i, None, exc)
            else:
                finished(i, result)
    else:
        _run_distributed(scheduler, tasks, todo, finished, progress)
    if failed:
        i, exc = failed[0]
        names = ", ".join(f"{tasks[j][0].__name__}{tuple(tasks[j][1:])}" for j, _ in failed)
        msg = f"{len(failed)} of {len(todo)} FE tasks failed ({names}); the first: {exc}"
        raise (ConvergenceError(msg) if isinstance(exc, ConvergenceError)
               else RuntimeError(msg)) from exc
    return out


WORKER_CONFIG = {"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None}
"""Dask configuration of the LocalCluster's worker processes.  Dask's default sets
``MALLOC_TRIM_THRESHOLD_=65536`` in every worker, which turns off glibc's adaptive mmap
threshold: NGSolve's large assembly and factorisation buffers are then mapped and unmapped
at every Newton step, and the page faults made an Ogden critical voltage at h = 2 t0 take
84 s in a worker against 13 s in a plain process (65 s of it system time).  Unset, the
worker is as fast as the plain process.  An existing cluster (``--scheduler ADDRESS``)
wants the same setting in its Dask configuration."""


def _run_distributed(scheduler, tasks, todo, finished, progress) -> None:
    """Run ``todo`` on Dask (see :func:`run_tasks`)."""
    import dask
    from distributed import Client, LocalCluster
    if scheduler == "local":
        n = int(os.environ.get("DEBENCH_WORKERS", os.cpu_count() or 1))
        # the dashboard on a free port: None still starts it on 8787 and warns when a
        # second sweep runs
        with dask.config.set(WORKER_CONFIG), \
                LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                             dashboard_address=":0") as cluster, Client(cluster) as client:
            _gather(client, tasks, todo, finished, progress)
    else:
        with Client(scheduler) as client:
            _gather(client, tasks, todo, finished, progress)


class _TaskCache:
    """Finished FE task results on disk, so that an interrupted sweep resumes.

    A result is keyed on the task (function, arguments, the source of the whole module that
    defines the function, so that its module-level settings count too) and on the source
    of the modules of :mod:`debench.models` that it runs (:func:`models_digest`): a change of
    the code that computes a result is a miss, never a stale hit.  Written atomically
    (temporary file + rename)."""

    def __init__(self, root: Path, code_digest: str):
        self.root, self.code_digest = Path(root), code_digest
        self.root.mkdir(parents=True, exist_ok=True)

    @classmethod
    def from_env(cls):
        root = os.environ.get("DEBENCH_FE_CACHE")
        return cls(Path(root), models_digest()) if root else None

    def _path(self, task: tuple) -> Path:
        fn, *args = task
        key = repr((fn.__module__, fn.__qualname__, tuple(args), task_source(fn.__module__),
                    self.code_digest)).encode()
        return self.root / f"{hashlib.sha256(key).hexdigest()[:32]}.pkl"

    def get(self, task: tuple):
        p = self._path(task)
        if not p.exists():
            return None
        with p.open("rb") as fh:
            return pickle.load(fh)

    def put(self, task: tuple, result) -> None:
        p = self._path(task)
        tmp = p.with_suffix(f".tmp{os.getpid()}")
        with tmp.open("wb") as fh:
            pickle.dump(result, fh)
        os.replace(tmp, p)


def task_source(module: str) -> str:
    """The source a task defined in ``module`` depends on outside :mod:`debench.models`:
    the module's own source, followed by that of every module of the same package it
    imports (at any depth of the file, recursively; e.g. a task module that takes its cases
    and material choice from another), in import order. A module that imports no sibling
    contributes its own source alone."""
    import ast
    import importlib
    import inspect
    package = module.rpartition(".")[0]
    sources: dict[str, str] = {}
    todo = [module]
    while todo:
        name = todo.pop(0)
        if name in sources:
            continue
        src = sources[name] = inspect.getsource(importlib.import_module(name))
        for node in ast.walk(ast.parse(src)):
            if not isinstance(node, ast.ImportFrom) or not node.module:
                continue
            target = (node.module if node.level == 0
                      else f"{package}.{node.module}" if node.level == 1 else None)
            if target is not None and package and target.rpartition(".")[0] == package:
                todo.append(target)
    return "\n".join(sources.values())


#: the parts of :mod:`debench.models` the FE tasks run: the buckling model, the
#: constitutive library and the package's top-level modules (validation, errors)
FE_SOURCES = ("buckling/**/*.py", "materials/**/*.py", "*.py")


def models_digest() -> str:
    """sha256 of the source (path and content) of the modules of :mod:`debench.models` that
    the FE tasks run (:data:`FE_SOURCES`)."""
    import debench.models as models
    root = Path(models.__file__).parent
    h = hashlib.sha256()
    for f in sorted({f for pattern in FE_SOURCES for f in root.glob(pattern)}):
        h.update(str(f.relative_to(root)).encode())
        h.update(f.read_bytes())
    return h.hexdigest()


def _gather(client, tasks: list[tuple], todo: list[int], finished, progress: bool) -> None:
    """Submit the tasks ``todo`` longest first (:func:`_cost`), hand each result to
    ``finished(index, result, error)`` as it arrives; a failed task does not stop the
    others (their results are kept; :func:`run_tasks` raises after all have finished)."""
    from distributed import as_completed
    order = sorted(todo, key=lambda i: -_cost(tasks[i]))
    futures = {client.submit(tasks[i][0], *tasks[i][1:], pure=False): i for i in order}
    try:
        from tqdm import tqdm
        bar = tqdm(total=len(todo), desc="ch5 FE (dask)", disable=(not progress) or None)
    except ImportError:  # pragma: no cover
        bar = None
    for fut in as_completed(futures):
        try:
            result = fut.result()
        except Exception as exc:  # noqa: BLE001 - reported by run_tasks after the others
            finished(futures[fut], None, exc)
        else:
            finished(futures[fut], result)
        if bar is not None:
            bar.update()
    if bar is not None:
        bar.close()


def coarse_values(*, cases=tuple(CASES)) -> dict[str, float]:
    """The coarsest level of every case, recomputed now (what ``debench verify`` guards).

    Keys (stable): ``"<case>.v_cr"`` -- critical voltage on the coarsest mesh (h = 3 t0,
    one layer of quadratic prisms), for every case; ``"<case>.v_pullin"`` and
    ``"<case>.w_pullin"`` -- pull-in voltage and centre deflection / t0 of the ramp on the
    same mesh (no eigen-analysis along the path), for the cases that are not scale copies
    (``nh_t1``, ``ogden_t1``).  Accuracy: v_cr to the secant's |dv| < 1e-6; pull-in to the
    parabola through the maximum (< 1e-3 relative, see ``voltage_ramp``).
    """
    out = {}
    for case in cases:
        out[f"{case}.v_cr"] = float(critical_task(case, COARSE_H)["v"])
    for case in cases:
        if case in SCALE_COPIES:
            continue
        r = ramp_task(case, COARSE_H, eig_every=0, dv_max=GUARD_DV_MAX)
        out[f"{case}.v_pullin"] = float(r["v_pullin"])
        out[f"{case}.w_pullin"] = float(r["w_pullin"])
    return out


def _at_pullin(r, arr) -> float:
    """A path quantity interpolated (in the centre deflection) at the pull-in deflection."""
    k = int(np.argmax(r.v))
    return float(np.interp(r.w_pullin, r.w[: k + 2], arr[: k + 2]))


def _level_fit(h, values) -> dict[str, float]:
    """:func:`convergence_fit` with three or more levels (levels that do not converge
    monotonically: the finest value, no rate, the largest distance of a level from it as the
    error); with fewer, the finest value and (two levels) its change from the previous one
    as the error (NaN with one level)."""
    h, values = np.asarray(h, float), np.asarray(values, float)
    if h.size >= 3:
        try:
            return convergence_fit(h, values)
        except ConvergenceError:  # not monotone: no rate; the spread bounds the error
            return {"v_inf": float(values[-1]), "p": float("nan"),
                    "error": float(np.max(np.abs(values - values[-1]))), "residual": 0.0}
    err = float(abs(values[-1] - values[-2])) if h.size == 2 else float("nan")
    return {"v_inf": float(values[-1]), "p": float("nan"), "error": err, "residual": 0.0}


def plan(full: bool = False) -> dict[str, list[tuple]]:
    """The independent FE tasks of a build, by role: ``critical`` (case x level),
    ``layers`` (case x layer count of the through-thickness study, at its in-plane size),
    ``ramp_mesh`` (the critical voltage on the finest ramp mesh, for Southwell), ``ramps``
    (case x ramp level).  Scale copies are not computed.  (The radius/thickness 20
    wrinkling ramps are :mod:`debench.reference.builders.ch5_wrinkling`.)"""
    computed = [c for c in CASES if c not in SCALE_COPIES]
    lay = LAYERS[full]
    h_ls, layer_counts = LAYER_STUDY[full]
    return {
        "critical": [(critical_task, c, h, lay) for c in computed for h in LEVELS[full]],
        "layers": [(critical_task, c, h_ls, n) for c in computed for n in layer_counts],
        "ramp_mesh": [(critical_task, c, RAMP_LEVELS[full][-1], RAMP_LAYERS) for c in computed],
        "ramps": [(ramp_task, c, h, EIG_EVERY, RAMP_DV_MAX, RAMP_LAYERS)
                  for c in computed for h in RAMP_LEVELS[full]],
    }


def compute(full: bool = False, progress: bool = True, scheduler=None):
    """Run the FE computations; returns (critical dataset, ramps dataset, parameters).

    Every task of :func:`plan` is independent (run serially, or on Dask with
    ``scheduler``); a task that appears twice (a layer-study mesh that is also a level of
    the sequence) runs once; scale copies (:data:`SCALE_COPIES`) are filled from the case
    they copy.
    """
    from debench.models.buckling import analytic
    from debench.models.buckling.parameters import MU_REF
    from debench.models.buckling.solver import RampResult, southwell
    levels, ramp_levels = LEVELS[full], RAMP_LEVELS[full]
    h_ls, layer_counts = LAYER_STUDY[full]
    roles = plan(full)
    unique = list(dict.fromkeys(t for ts in roles.values() for t in ts))
    done = dict(zip(unique, run_tasks(unique, scheduler=scheduler, progress=progress),
                    strict=True))

    def ramp(task):
        fields = dict(done[task])
        return RampResult(**fields)

    names = list(CASES)

    def source(case):
        return SCALE_COPIES.get(case, case)

    lay = LAYERS[full]
    crit_res = {(c, h): done[(critical_task, source(c), h, lay)] for c in names for h in levels}
    layer_res = {(c, n): done[(critical_task, source(c), h_ls, n)]
                 for c in names for n in layer_counts}
    ramps = {(c, h): ramp((ramp_task, source(c), h, EIG_EVERY, RAMP_DV_MAX, RAMP_LAYERS))
             for c in names for h in ramp_levels}
    vcr = np.array([[crit_res[(c, h)]["v"] for h in levels] for c in names])
    ndof = np.array([[crit_res[(c, h)]["ndof"] for h in levels] for c in names], dtype=np.int64)
    nel = np.array([[crit_res[(c, h)]["nelements"] for h in levels] for c in names],
                   dtype=np.int64)
    secs = np.array([[crit_res[(c, h)]["seconds"] for h in levels] for c in names])
    eig_res = np.array([[crit_res[(c, h)]["eig_residual"] for h in levels] for c in names])
    v_layers = np.array([[layer_res[(c, n)]["v"] for n in layer_counts] for c in names])
    ndof_layers = np.array([[layer_res[(c, n)]["ndof"] for n in layer_counts] for c in names],
                           dtype=np.int64)

    v_inf, rate, err, resid, v_k, v_m, v_sw, v_cr_ramp_mesh = ([] for _ in range(8))
    v_free, p_free, p_exp, fit_kind = [], [], [], []
    lay_lim, lay_err, lay_corr = [], [], []
    finest_ramp = ramp_levels[-1]
    for i, case in enumerate(names):
        p_exp.append(expected_order(source(case)))
        fitted = reference_fit(np.array(levels), vcr[i], p_exp[-1])
        fit_kind.append(fitted["kind"])
        v_inf.append(fitted["v_inf"])
        rate.append(fitted["p"])
        err.append(fitted["error"])
        resid.append(fitted["residual"])
        try:
            free_fit = convergence_fit(np.array(levels), vcr[i])
        except ConvergenceError:   # a free rate at its bound: no free-rate limit
            free_fit = {"v_inf": float("nan"), "p": float("nan")}
        v_free.append(free_fit["v_inf"])
        p_free.append(free_fit["p"])
        # through-thickness: v(n layers) ~ v_n_inf + C n^-q, i.e. a fit in 1/n
        lf = _level_fit(1.0 / np.array(layer_counts, float), v_layers[i])
        lay_lim.append(lf["v_inf"])
        lay_err.append(lf["error"])
        lay_corr.append(lf["v_inf"] - v_layers[i][list(layer_counts).index(lay)])
        mat = _material(CASES[case][0])
        v_k.append(analytic.critical_voltage_plate(mat, 10.0, mindlin=False))
        v_m.append(analytic.critical_voltage_plate(mat, 10.0, mindlin=True))
        r = ramps[(case, finest_ramp)]
        v_rm = done[(critical_task, source(case), finest_ramp, RAMP_LAYERS)]["v"]
        v_cr_ramp_mesh.append(v_rm)
        v_sw.append(southwell(r.v, r.w_mid, v_guess=v_rm))
    v_ref = np.array(v_inf) + np.array(lay_corr)
    v_ref_err = np.array(err) + np.abs(np.array(lay_err))

    def attrs1(ln, u="1", accuracy=None):
        out = {"long_name": ln, "units": u}
        if accuracy:
            out["accuracy"] = accuracy
        return out

    this_mesh = ("of this mesh: secant on the lowest eigenvalue to |dv| < 1e-6; the "
                 "discretisation error is what the sequence measures")
    crit = xr.Dataset(
        {
            "v_cr": (("case", "level"), vcr, attrs1(
                "normalised critical voltage Phi/t0 sqrt(eps/mu_ref) of the perfect film "
                "(linearised eigen-analysis)", accuracy=this_mesh)),
            "ndof": (("case", "level"), ndof, attrs1("degrees of freedom")),
            "nelements": (("case", "level"), nel, attrs1("prism elements")),
            "eig_residual": (("case", "level"), eig_res, attrs1(
                "relative eigen-residual ||S x - lambda M x||/||M x|| at v_cr")),
            "wall_seconds": (("case", "level"), secs, attrs1(
                "wall time of the critical-voltage computation (one thread)", "s")),
            "v_cr_extrapolated": (("case",), np.array(v_inf), attrs1(
                "in-plane mesh limit of v_cr at the sequence's layer count (fit_kind: "
                "v_inf + C h^q at the expected order q over the three finest levels when "
                "they show it, else a free-rate fit over all levels)",
                accuracy="+- v_cr_error")),
            "v_cr_error": (("case",), np.array(err), attrs1(
                "error estimate of the in-plane mesh limit (expected order: 3 x the largest "
                "of the fit residual, the distance from the three-point limit with a free "
                "rate and the change when the next coarser level is added; free rate: 3 x "
                "the largest of the drop-a-level change, the residual and the distance "
                "from the limit at the expected order)")),
            "fit_kind": (("case",), np.array(fit_kind, dtype=str), attrs1(
                "which fit gives v_cr_extrapolated")),
            "expected_order": (("case",), np.array(p_exp), attrs1(
                "asymptotic convergence order q of v_cr: 2 s(nu), s the Williams exponent "
                "of the clamped-free edge for the material's small-strain Poisson ratio")),
            "v_cr_fit_residual": (("case",), np.array(resid), attrs1(
                "largest |fit - v_cr| over the three finest levels")),
            "convergence_rate": (("case",), np.array(rate), attrs1(
                "observed convergence order of v_cr on the three finest levels")),
            "v_cr_free_fit": (("case",), np.array(v_free), attrs1(
                "mesh limit of a least-squares fit v_inf + C h^p with a free rate over all "
                "levels (a diagnostic: the coarse levels are pre-asymptotic)")),
            "free_fit_rate": (("case",), np.array(p_free), attrs1(
                "rate p of the free-rate fit over all levels")),
            "v_cr_layers": (("case", "layer_count"), v_layers, attrs1(
                "v_cr at the layer-study in-plane size versus layers through the thickness",
                accuracy=this_mesh)),
            "ndof_layers": (("case", "layer_count"), ndof_layers,
                            attrs1("degrees of freedom of the layer study")),
            "v_cr_layer_limit": (("case",), np.array(lay_lim), attrs1(
                "through-thickness limit of v_cr at the layer-study in-plane size (fit in "
                "1/layers; with two counts: the finer)", accuracy="+- v_cr_layer_error")),
            "v_cr_layer_error": (("case",), np.abs(np.array(lay_err)), attrs1(
                "error estimate of the through-thickness limit")),
            "layer_correction": (("case",), np.array(lay_corr), attrs1(
                "v_cr_layer_limit minus v_cr with the sequence's layer count, same mesh")),
            "v_cr_reference": (("case",), v_ref, attrs1(
                "reference critical voltage: in-plane limit plus through-thickness "
                "correction (errors assumed additive)", accuracy="+- v_cr_reference_error")),
            "v_cr_reference_error": (("case",), v_ref_err, attrs1(
                "error estimate of v_cr_reference: v_cr_error + v_cr_layer_error")),
            "v_cr_kirchhoff": (("case",), np.array(v_k), attrs1(
                "Kirchhoff clamped-plate estimate (14.68 D/a^2, compressible flat film)")),
            "v_cr_mindlin": (("case",), np.array(v_m), attrs1(
                "Mindlin (thick-plate) corrected clamped-plate estimate")),
            "v_cr_southwell": (("case",), np.array(v_sw), attrs1(
                "Southwell estimate from the ramp of the imperfect film (finest ramp mesh)")),
            "v_cr_ramp_mesh": (("case",), np.array(v_cr_ramp_mesh), attrs1(
                "eigen-analysis critical voltage on the finest ramp mesh")),
            "thickness_m": (("case",), np.array([CASES[c][1] for c in names]),
                            attrs1("initial thickness t0", "m")),
        },
        coords={"case": ("case", names, {"long_name": "material and thickness case"}),
                "level": ("level", np.arange(len(levels)), attrs1("mesh level")),
                "h_rel": ("level", np.array(levels), attrs1("in-plane mesh size / t0")),
                "layer_count": ("layer_count", np.array(layer_counts, dtype=np.int64),
                                attrs1("layers of quadratic prisms through the thickness"))},
    )
    rfin = {c: ramps[(c, finest_ramp)] for c in names}
    nstep = max(len(r.v) for r in rfin.values())
    neig = max(len(r.eig_v) for r in rfin.values())

    def pad(a, n, extra=()):
        out = np.full((n,) + extra, np.nan)
        out[: len(a)] = a
        return out

    data = {}
    for key, ln, unit in (("v", "normalised voltage Phi/t0 sqrt(eps/mu_ref)", "1"),
                          ("w", "vertical displacement of the top-surface centre / t0", "1"),
                          ("w_mid", "mean vertical displacement of top and bottom centre / t0",
                           "1"),
                          ("thickness", "current centre thickness / t0", "1"),
                          ("e_centre", "normalised true field at the centre E sqrt(eps/mu_ref)",
                           "1"),
                          ("e_max", "largest sampled normalised true field (mid-plane radius)",
                           "1")):
        data[key] = (("case", "step"),
                     np.array([pad(getattr(rfin[c], key), nstep) for c in names]),
                     attrs1(ln, unit))
    data["eig_v"] = (("case", "eig_record"), np.array([pad(rfin[c].eig_v, neig) for c in names]),
                     attrs1("normalised voltage of the eigen-analysis record"))
    data["eig_w"] = (("case", "eig_record"), np.array([pad(rfin[c].eig_w, neig) for c in names]),
                     attrs1("centre deflection / t0 of the eigen-analysis record"))
    data["eig_lambda"] = (("case", "eig_record", "mode"),
                          np.array([pad(rfin[c].eig_lam, neig, (3,)) for c in names]),
                          attrs1("lowest eigenvalues of the condensed tangent "
                                 "S u = lambda M u (M: L2 mass / t0^2)"))
    data["eig_axisymmetry"] = (("case", "eig_record", "mode"),
                               np.array([pad(rfin[c].eig_axisym, neig, (3,)) for c in names]),
                               attrs1("fraction of the mode in the angular harmonic n = 0"))
    data["eig_wavenumber"] = (("case", "eig_record", "mode"),
                              np.array([pad(rfin[c].eig_wavenumber, neig, (3,)) for c in names]),
                              attrs1("dominant angular harmonic of the mode (0: axisymmetric)"))

    rl = [rfin[c] for c in names]
    pullin_acc = "parabola through the voltage maximum of this mesh (< 1e-3 relative)"
    data["v_pullin"] = (("case",), np.array([r.v_pullin for r in rl]), attrs1(
        "pull-in on the finest ramp mesh: voltage limit point (vertex of the parabola v(w) "
        "through the maximum)", accuracy=pullin_acc))
    data["v_max_computed"] = (("case",), np.array([np.max(r.v) for r in rl]), attrs1(
        "largest normalised voltage among the computed path points"))
    data["w_pullin"] = (("case",), np.array([r.w_pullin for r in rl]), attrs1(
        "centre deflection / t0 at pull-in (finest ramp mesh)", accuracy=pullin_acc))
    data["thickness_pullin"] = (("case",), np.array([_at_pullin(r, r.thickness) for r in rl]),
                                attrs1("centre thickness / t0 at pull-in"))
    data["e_centre_pullin"] = (("case",), np.array([_at_pullin(r, r.e_centre) for r in rl]),
                               attrs1("normalised true centre field at pull-in"))
    data["e_max_pullin"] = (("case",), np.array([_at_pullin(r, r.e_max) for r in rl]),
                            attrs1("largest sampled normalised true field at pull-in"))

    def wrinkling(r) -> dict:
        f = first_instability(r.eig_w, r.eig_v, r.eig_lam, r.eig_axisym, r.eig_wavenumber)
        return f if f["kind"] == "non-axisymmetric" else {**f, "v": np.nan, "w": np.nan}

    first = [wrinkling(r) for r in rl]
    data["first_kind"] = (("case",), np.array([f["kind"] for f in first], dtype=str), {
        "long_name": "kind of the first instability along the finest ramp (first eigen-record "
        "with an eigenvalue <= 0): axisymmetric (pull-in), non-axisymmetric (wrinkling) or "
        "none"})
    data["v_wrinkling"] = (("case",), np.array([f["v"] for f in first]), attrs1(
        "normalised voltage at the onset of a non-axisymmetric mode when it is the first "
        "instability (NaN: pull-in or nothing comes first)"))
    data["w_wrinkling"] = (("case",), np.array([f["w"] for f in first]), attrs1(
        "centre deflection / t0 at the onset of a non-axisymmetric mode when it is the first "
        "instability (NaN: none)"))
    data["ndof"] = (("case",), np.array([r.ndof for r in rl]), attrs1("degrees of freedom"))
    # pull-in on every ramp level and its mesh limit
    by_level = {key: np.array([[getattr(ramps[(c, h)], key) for h in ramp_levels]
                               for c in names], float) for key in ("v_pullin", "w_pullin")}
    data["v_pullin_levels"] = (("case", "ramp_level"), by_level["v_pullin"], attrs1(
        "pull-in voltage per ramp mesh", accuracy=pullin_acc))
    data["w_pullin_levels"] = (("case", "ramp_level"), by_level["w_pullin"], attrs1(
        "centre deflection / t0 at pull-in per ramp mesh", accuracy=pullin_acc))
    data["v_wrinkling_levels"] = (("case", "ramp_level"), np.array(
        [[wrinkling(ramps[(c, h)])["v"] for h in ramp_levels] for c in names]), attrs1(
        "onset voltage of a non-axisymmetric mode as the first instability per ramp mesh "
        "(NaN: none)"))
    data["ndof_ramp_levels"] = (("case", "ramp_level"), np.array(
        [[ramps[(c, h)].ndof for h in ramp_levels] for c in names], dtype=np.int64),
        attrs1("degrees of freedom of the ramp meshes"))
    for key, ln in (("v_pullin", "pull-in voltage"), ("w_pullin", "pull-in deflection / t0")):
        fits = [_level_fit(ramp_levels, by_level[key][i]) for i in range(len(names))]
        data[f"{key}_extrapolated"] = (("case",), np.array([f["v_inf"] for f in fits]), attrs1(
            f"mesh limit of the {ln} (fit v_inf + C h^p with three or more ramp levels; "
            "else the finest level)", accuracy=f"+- {key}_error"))
        data[f"{key}_error"] = (("case",), np.array([f["error"] for f in fits]), attrs1(
            f"error estimate of the mesh limit of the {ln} (NaN: one ramp level)"))
        data[f"{key}_rate"] = (("case",), np.array([f["p"] for f in fits]), attrs1(
            f"fitted convergence rate of the {ln} (NaN: fewer than three levels)"))
    data["thickness_m"] = (("case",), np.array([CASES[c][1] for c in names]),
                           attrs1("initial thickness t0", "m"))
    coords = {
        "case": ("case", names, {"long_name": "material and thickness case"}),
        "step": ("step", np.arange(nstep), attrs1("converged load step")),
        "eig_record": ("eig_record", np.arange(neig), attrs1("eigen-analysis record")),
        "mode": ("mode", np.arange(3), attrs1("mode index (ascending eigenvalue)")),
        "ramp_level": ("ramp_level", np.array(ramp_levels), attrs1(
            "in-plane mesh size / t0 of the ramp"))}
    data["min_nonaxisymmetric_lambda"] = (("case",), np.array([_min_nonaxisym(r) for r in rl]),
                                          attrs1("smallest eigenvalue of a non-axisymmetric "
                                                 "mode recorded before pull-in"))
    ramp_ds = xr.Dataset(data, coords=coords)
    nh, og = _material("nh"), _material("ogden")
    params = {"mu_ref_Pa": MU_REF, "nh_mu_Pa": nh.mu, "k_Pa": nh.k,
              "ogden_alphas": list(og.alphas), "ogden_mus_Pa": list(og.mus),
              "ogden_delta": OGDEN_DELTA, "aspect": 10.0, "imperfection_rel": 1e-3,
              "imperfection_shape": "t0*1e-3*(1-r^2/a^2)^2", "eps_r": 4.7, "layers": lay,
              "order": ORDER, "levels_h_rel": list(levels), "ramp_h_rel": list(ramp_levels),
              "ramp_layers": RAMP_LAYERS,
              "layer_study_h_rel": h_ls, "layer_counts": list(layer_counts),
              "full": full, "ramp_dc_over_t0": 0.2, "ramp_dv_max": RAMP_DV_MAX,
              "eig_every": EIG_EVERY, "fit_safety": FIT_SAFETY,
              "scale_copies": ", ".join(f"{a} = {b}" for a, b in SCALE_COPIES.items())}
    return crit, ramp_ds, params


def axisymmetric(eig_n) -> np.ndarray:
    """Which recorded modes are axisymmetric: those whose dominant angular harmonic (the
    harmonic with the largest share of the mode, ``eig_wavenumber`` of the records; see
    :func:`debench.models.buckling.fem.mode_harmonics`) is n = 0. The dominant harmonic
    rather than a threshold on the n = 0 share: on the unstructured meshes the pull-in mode
    can carry half of its amplitude in n >= 1 harmonics spread over several wavenumbers
    (measured: 47 % in n = 0 at the first record past pull-in of one R/t0 = 10 mesh),
    while a wrinkling mode's share is concentrated in one n >= 1. NaN padding is not
    axisymmetric."""
    n = np.asarray(eig_n, float)
    return np.isfinite(n) & (n == 0)


def lowest_nonaxisymmetric(eig_lam, eig_n) -> np.ndarray:
    """Per eigen-record, the lowest eigenvalue of a non-axisymmetric mode (dominant
    harmonic n >= 1, :func:`axisymmetric`); inf where a record has none or is NaN padding
    (the Fig. 5.5 counterparts plot it against the deflection)."""
    lam = np.where(axisymmetric(eig_n), np.nan, np.asarray(eig_lam, float))
    return np.nanmin(np.where(np.isfinite(lam), lam, np.inf), axis=1)


def first_instability(eig_w, eig_v, eig_lam, eig_axisym, eig_n) -> dict:
    """The first instability recorded along a path: the first eigen-record where an
    eigenvalue of the condensed tangent at fixed voltage is <= 0, classified by the mode
    that is lowest there (:func:`axisymmetric`): ``axisymmetric`` is the pull-in limit
    point of the axisymmetric film, ``non-axisymmetric`` a wrinkling bifurcation. Its
    deflection / t0 (``w``) and voltage (``v``) are interpolated linearly
    to the zero of the lowest eigenvalue of that kind between the previous record and this
    one; ``n`` is the mode's dominant wavenumber; ``lam_ratio`` the three recorded
    eigenvalues there over the largest lowest eigenvalue of the path (how far the next
    modes are from zero); ``axisym`` their n = 0 fractions, ``wavenumbers`` their dominant
    wavenumbers. Kind ``"none"`` (NaN values)
    when nothing became unstable. The voltage maximum of the deflection-controlled path is
    not used: where the path turns at a bifurcation, its maximum is the bifurcation, not
    the axisymmetric limit point."""
    lam, ax = np.asarray(eig_lam, float), np.asarray(eig_axisym, float)
    w, v = np.asarray(eig_w, float), np.asarray(eig_v, float)
    ok = np.isfinite(w)
    lam, ax, w, v, n = lam[ok], ax[ok], w[ok], v[ok], np.asarray(eig_n)[ok]
    out = {"kind": "none", "w": math.nan, "v": math.nan, "n": math.nan,
           "lam_ratio": [math.nan] * 3, "axisym": [math.nan] * 3,
           "wavenumbers": [math.nan] * 3}
    bad = np.flatnonzero(np.min(lam, axis=1) <= 0.0)
    if not bad.size:
        return out
    i = int(bad[0])
    j = int(np.argmin(lam[i]))
    sym = axisymmetric(n)
    axisym = bool(sym[i, j])
    same = sym if axisym else ~sym
    lowest = np.min(np.where(same, lam, np.inf), axis=1)
    wi, vi = w[i], v[i]
    if i > 0 and np.isfinite(lowest[i - 1]) and lowest[i - 1] > 0:
        f = lowest[i - 1] / (lowest[i - 1] - lowest[i])
        wi, vi = w[i - 1] + f * (w[i] - w[i - 1]), v[i - 1] + f * (v[i] - v[i - 1])
    scale = float(np.max(np.min(lam, axis=1)))
    out.update(kind="axisymmetric" if axisym else "non-axisymmetric", w=float(wi),
               v=float(vi), n=float(n[i, j]), lam_ratio=[float(x) / scale for x in lam[i]],
               axisym=[float(x) for x in ax[i]], wavenumbers=[float(x) for x in n[i]])
    return out


def stable_records_past_voltage_maximum(w, v, eig_w, eig_v, eig_lam) -> np.ndarray:
    """The eigen-records of one deflection-controlled path that lie past its voltage
    maximum and show no negative eigenvalue; an empty array when there are none.

    Past a voltage maximum the path descends in voltage: at the maximum the derivative of
    the equilibrium voltage along the path changes sign, and with it the determinant of the
    tangent at fixed voltage (the path's tangent solves K du/dw = -dR/dv dv/dw), so an odd
    number of its eigenvalues has crossed zero and at least one is negative until the path
    turns again. A record there whose eigenvalues are all positive is therefore not the
    lowest part of the spectrum: an eigen-solver that missed the unstable mode. The maximum
    is the largest computed path point (``w``, ``v``, the path; NaN padding ignored); the
    records checked are those after it in deflection and below it in voltage (``eig_w``,
    ``eig_v``, ``eig_lam``: the records, rows of eigenvalues). A path whose largest voltage
    is its last point has none. Returns the indices (into the records) of the offending
    ones."""
    w, v = np.asarray(w, float), np.asarray(v, float)
    ew, ev = np.asarray(eig_w, float), np.asarray(eig_v, float)
    lam = np.asarray(eig_lam, float)
    if w.shape != v.shape or ew.shape != ev.shape or lam.shape[:1] != ew.shape:
        raise ValueError(f"path shapes w {w.shape}, v {v.shape} and record shapes eig_w "
                         f"{ew.shape}, eig_v {ev.shape}, eig_lam {lam.shape} do not match")
    ok = np.flatnonzero(np.isfinite(v) & np.isfinite(w))
    if not ok.size:
        return np.array([], int)
    k = ok[int(np.argmax(v[ok]))]
    if k == ok[-1]:
        return np.array([], int)
    with np.errstate(invalid="ignore"):
        past = np.isfinite(ew) & (ew > w[k]) & (ev < v[k])
        stable = np.all(lam > 0.0, axis=1)
    return np.flatnonzero(past & stable)


def _min_nonaxisym(r) -> float:
    """Smallest eigenvalue of a non-axisymmetric mode (:func:`axisymmetric`) among the
    records up to the pull-in deflection (NaN: none recorded)."""
    if len(r.eig_v) == 0:
        return float("nan")
    upto = np.asarray(r.eig_w) <= (r.w_pullin if r.w_pullin is not None else np.inf)
    lam = lowest_nonaxisymmetric(r.eig_lam, r.eig_wavenumber)[upto]
    return float(np.min(lam)) if np.any(np.isfinite(lam)) else float("nan")


def figures(crit, ramps, fig_dir: Path) -> list[Path]:
    """Figs 5.4 and 5.6 (deflection versus voltage, pull-in marked), the Fig 5.5
    counterpart (the lowest non-axisymmetric eigenvalue along the path: wrinkling where it
    crosses zero before pull-in), and the mesh convergence of the critical voltage, the
    pull-in and the through-thickness study.  The thesis' printed values are overlaid in
    the overlays of :mod:`debench.reference.builders.ch5_methods`."""
    from debench.models.buckling.parameters import Plate
    from debench.reference.figures import LABELS, pyplot, save
    plt = pyplot()
    fig_dir.mkdir(parents=True, exist_ok=True)
    out = []
    # Fig 5.4: thickness study (Ogden), deflection in mm vs voltage in kV (eps_r 4.7)
    fig, axs = plt.subplots(1, 2, figsize=(10, 4))
    for case, style in (("ogden_t1", "-"), ("ogden_t0p5", "--")):
        r = ramps.sel(case=case)
        t0 = float(r.thickness_m)
        ok = np.isfinite(r.v.values)
        pl = Plate(thickness=t0)
        lab = rf"$t_0$ = {t0 * 1e3:g} mm"
        axs[0].plot(r.v.values[ok], r.w.values[ok] * t0 * 1e3, style, label=lab)
        axs[1].plot([pl.volts(x) / 1e3 for x in r.v.values[ok]], r.w.values[ok] * t0 * 1e3,
                    style, label=lab)
        axs[0].plot(float(r.v_pullin), float(r.w_pullin) * t0 * 1e3, "ko")
    axs[0].set_xlabel(LABELS["phibar_ch5"] + r", $\mu$ = 156 kPa")
    axs[1].set_xlabel(r"voltage $\Phi$ [kV], $\varepsilon_r$ = 4.7")
    for ax in axs:
        ax.set_ylabel(LABELS["deflection_mm"])
        ax.legend()
    fig.suptitle("Fig 5.4 (debench): Ogden films, radius/thickness 10; dot = pull-in")
    out += save(fig, fig_dir / "fig5_4_deflection_voltage_thickness")
    # Fig 5.6: material study at 1 mm
    fig, ax = plt.subplots(figsize=(5.8, 4.2))
    for case, style, lab in (("nh_t1", "-", "neo-Hookean"), ("ogden_t1", "--", "Ogden")):
        r = ramps.sel(case=case)
        ok = np.isfinite(r.v.values)
        ax.plot(r.v.values[ok], r.w.values[ok], style, label=lab)
        ax.plot(float(r.v_pullin), float(r.w_pullin), "ko")
    ax.set_xlabel(LABELS["phibar_ch5"] + r", $\mu$ = 156 kPa")
    ax.set_ylabel(r"centre deflection $w/t_0$")
    ax.legend()
    ax.set_title(r"Fig 5.6 (debench): $t_0$ = 1 mm; dot = pull-in")
    out += save(fig, fig_dir / "fig5_6_deflection_voltage_material")
    # Fig 5.5 counterpart: the lowest non-axisymmetric eigenvalue along the path
    fig, ax = plt.subplots(figsize=(5.8, 4.2))
    for case, style in (("nh_t1", "-o"), ("ogden_t1", "--s")):
        r = ramps.sel(case=case)
        lam_min = lowest_nonaxisymmetric(r.eig_lambda.values, r.eig_wavenumber.values)
        ok = np.isfinite(r.eig_w.values) & np.isfinite(lam_min)
        ax.plot(r.eig_w.values[ok], lam_min[ok], style, ms=3,
                label=f"{case}, radius/thickness 10")
        ax.axvline(float(r.w_pullin), color="0.5", lw=0.8, ls=":")
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_xlabel(r"centre deflection $w/t_0$ (dotted: pull-in)")
    ax.set_ylabel(r"lowest non-axisymmetric eigenvalue $\lambda$")
    ax.set_title("Fig 5.5 counterpart: wrinkling where a non-axisymmetric mode crosses 0")
    ax.legend()
    out += save(fig, fig_dir / "fig5_5_nonaxisymmetric_modes")
    # convergence: critical voltage (in-plane), pull-in (ramps), through-thickness
    fig, axs = plt.subplots(1, 3, figsize=(14, 4.2))
    for case in crit.case.values:
        c = crit.sel(case=case)
        err = np.abs(c.v_cr.values - float(c.v_cr_extrapolated))
        axs[0].loglog(crit.h_rel.values, err, "o-",
                      label=f"{case} (p = {float(c.convergence_rate):.2f})")
        axs[2].plot(c.layer_count.values, c.v_cr_layers.values, "o-", label=str(case))
    axs[0].set_xlabel(LABELS["h_over_t0"])
    axs[0].set_ylabel(r"$|v_{cr}(h) - v_{cr}(h \to 0)|$")
    axs[0].set_title("critical voltage, in-plane sequence")
    for case in ("nh_t1", "ogden_t1"):
        r = ramps.sel(case=case)
        axs[1].plot(r.ramp_level.values, r.v_pullin_levels.values, "o-", label=case)
    axs[1].set_xlabel(LABELS["h_over_t0"])
    axs[1].set_ylabel(r"pull-in voltage $v_{pi}(h)$")
    axs[1].set_title("pull-in per ramp mesh")
    axs[2].set_xlabel("layers through the thickness")
    axs[2].set_ylabel(r"$v_{cr}$ at the layer-study mesh")
    axs[2].set_title("through-thickness convergence")
    for ax in axs:
        ax.legend()
    out += save(fig, fig_dir / "fig5_x_critical_voltage_convergence")
    return out


def converged_only(name: str, levels) -> bool:
    """Whether the build of a converged-only chapter has nothing to compute (no mesh
    ``levels`` in this mode, the default build): then it says so on stderr."""
    if len(levels):
        return False
    print(f"{name}: converged-only (run with --full); nothing written", file=sys.stderr)
    return True


def resolve_scheduler(scheduler: str | None):
    """The ``scheduler`` of :func:`run_tasks` for a builder's ``scheduler`` option: None
    means ``"local"`` on a machine with more than one core, else serial; ``"serial"``
    means None (this process)."""
    if scheduler is None:
        scheduler = "local" if (os.cpu_count() or 1) > 1 else "serial"
    return None if scheduler == "serial" else scheduler


def build(out_dir: Path, *, full: bool = False, scheduler: str | None = None) -> list[Path]:
    """Compute and write the Chapter 5 datasets and figures into ``out_dir``.

    ``scheduler``: ``"serial"`` runs the FE tasks one after the other in this process;
    ``"local"`` on a Dask LocalCluster sized to the machine (``DEBENCH_WORKERS`` overrides
    the number of worker processes; one thread each); an address on an existing Dask
    scheduler.  None: ``"local"`` on a machine with more than one core, else serial.
    """
    out_dir = Path(out_dir)
    crit, ramps, params = compute(full=full, scheduler=resolve_scheduler(scheduler))
    size = "converged (full)" if full else "coarse"
    paths = [
        write_dataset(crit, "ch5_critical_voltage", out_dir=out_dir, overwrite=True,
                      title="Ch. 5 buckling membrane: critical voltage of the clamped DE film",
                      summary=("Normalised critical voltage of the perfect clamped dielectric "
                               f"film (radius/thickness 10) by FE eigen-analysis on {size} "
                               "meshes, Richardson limit, plate-theory and Southwell estimates "
                               "(thesis Tables 5.2, 5.4)."),
                      parameters=params),
        write_dataset(ramps, "ch5_ramps", out_dir=out_dir, overwrite=True,
                      title="Ch. 5 buckling membrane: voltage ramps to pull-in",
                      summary=("Centre deflection, thickness and true field versus normalised "
                               f"voltage of the imperfect clamped film ({size} mesh), pull-in, "
                               "eigenvalues along the path (thesis Figs 5.4, 5.6, Tables 5.3, "
                               "5.5)."),
                      parameters=params),
    ]
    return paths + figures(crit, ramps, out_dir / "figures")
