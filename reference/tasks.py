"""The task runner of the finite-element sweeps: independent ``(function, *args)`` tasks
run serially or on Dask ``distributed``, with a resumable on-disk cache of finished
results.

* :func:`run_tasks` -- run tasks (serial, a LocalCluster, or an existing scheduler);
* :func:`resolve_scheduler` -- a builder's ``scheduler`` option as :func:`run_tasks` takes it;
* :class:`TaskCache` -- finished results on disk (``DEBENCH_FE_CACHE``), keyed on the task
  and on what computes it (:func:`task_inputs`, :func:`models_digest`);
* :func:`limit_threads` -- one thread for BLAS and NGSolve in a task's process.
"""

from __future__ import annotations

import dis
import functools
import hashlib
import importlib
import inspect
import os
import pickle
import sys
from collections.abc import Callable
from pathlib import Path

import debench.models as models
from debench.models.errors import ConvergenceError
from tqdm import tqdm

from debench.threads import limit_threads as limit

WORKER_CONFIG = {"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None}
"""Dask configuration of the LocalCluster's worker processes.  Dask's default sets
``MALLOC_TRIM_THRESHOLD_=65536`` in every worker, which turns off glibc's adaptive mmap
threshold: NGSolve's large assembly and factorisation buffers are then mapped and unmapped
at every Newton step, and the page faults made an Ogden critical voltage at h = 2 t0 take
84 s in a worker against 13 s in a plain process (65 s of it system time).  Unset, the
worker is as fast as the plain process.  An existing cluster (``--scheduler ADDRESS``)
wants the same setting in its Dask configuration."""

#: the parts of :mod:`debench.models` the FE tasks run: the buckling model, the
#: constitutive library, the shared numerics and the package's top-level modules
#: (validation, errors)
FE_SOURCES = ("buckling/**/*.py", "materials/**/*.py", "numerics/**/*.py", "*.py")


def limit_threads() -> None:
    """One thread for BLAS and NGSolve's TaskManager in this process (a Dask worker runs
    one task per process; nothing oversubscribes): :func:`debench.threads.limit_threads`."""
    import ngsolve  # noqa: F401 - loaded first so that its TaskManager is limited too


    limit(1)


def default_cost(task: tuple) -> float:
    """Rough relative cost of a task whose first argument is a mesh size ``h`` (~ 1/h^2;
    1 for any other task): the longest tasks are submitted first."""
    h = task[1] if len(task) > 1 else None
    return 1.0 / h**2 if isinstance(h, float) and h > 0 else 1.0


def resolve_scheduler(scheduler: str | None):
    """The ``scheduler`` of :func:`run_tasks` for a builder's ``scheduler`` option: None
    means ``"local"`` on a machine with more than one core, else serial; ``"serial"``
    means None (this process)."""
    if scheduler is None:
        scheduler = "local" if (os.cpu_count() or 1) > 1 else "serial"
    return None if scheduler == "serial" else scheduler


def run_tasks(tasks: list[tuple], scheduler=None, progress: bool = True, *,
              cost: Callable[[tuple], float] = default_cost, label: str = "ch5 FE") -> list:
    """Run ``(function, *args)`` tasks serially (``scheduler=None``) or on Dask
    ``distributed``: ``"local"`` starts a LocalCluster sized to the machine (one process per
    core, one thread each; ``DEBENCH_WORKERS`` overrides the number), any other string is
    the address of an existing scheduler (e.g. one started by dask-jobqueue on SLURM/PBS or
    by dask-kubernetes).  Results come back in task order; on Dask the tasks are submitted
    in decreasing ``cost``.  With ``DEBENCH_FE_CACHE`` set to a directory, each finished
    task's result is kept there as it finishes (keyed on the task and the source of the code
    that computes it) so that a long sweep resumes after an interruption
    (:class:`TaskCache`).  A failed task does not stop the others; after all have run, the
    first failure is raised (ConvergenceError when it was one, else RuntimeError) naming
    every failed task.  ``label`` names the sweep in the progress bar and log lines."""
    cache = TaskCache.from_env()
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
            print(f"{label}: {fn.__name__}{tuple(args)} "
                  f"{'FAILED: ' + repr(error) if error is not None else 'done'} "
                  f"[{len(todo) - sum(r is None for r in out) + len(failed)}/{len(todo)}]",
                  file=sys.stderr, flush=True)

    if not todo:
        return out
    if scheduler is None:
        for i in tqdm(todo, desc=label, disable=(not progress) or None):
            fn, *args = tasks[i]
            try:
                result = fn(*args)
            except Exception as exc:  # noqa: BLE001 - the others still run (and are cached)
                finished(i, None, exc)
            else:
                finished(i, result)
    else:
        _run_distributed(scheduler, tasks, todo, finished, progress, cost, label)
    if failed:
        i, exc = failed[0]
        names = ", ".join(f"{tasks[j][0].__name__}{tuple(tasks[j][1:])}" for j, _ in failed)
        msg = f"{len(failed)} of {len(todo)} FE tasks failed ({names}); the first: {exc}"
        raise (ConvergenceError(msg) if isinstance(exc, ConvergenceError)
               else RuntimeError(msg)) from exc
    return out


def _run_distributed(scheduler, tasks, todo, finished, progress, cost, label) -> None:
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
            _gather(client, tasks, todo, finished, progress, cost, label)
    else:
        with Client(scheduler) as client:
            _gather(client, tasks, todo, finished, progress, cost, label)


def _gather(client, tasks, todo, finished, progress, cost, label) -> None:
    """Submit the tasks ``todo`` longest first (``cost``), hand each result to
    ``finished(index, result, error)`` as it arrives; a failed task does not stop the
    others (their results are kept; :func:`run_tasks` raises after all have finished)."""
    from distributed import as_completed
    order = sorted(todo, key=lambda i: -cost(tasks[i]))
    futures = {client.submit(tasks[i][0], *tasks[i][1:], pure=False): i for i in order}
    bar = tqdm(total=len(todo), desc=f"{label} (dask)", disable=(not progress) or None)
    for fut in as_completed(futures):
        try:
            result = fut.result()
        except Exception as exc:  # noqa: BLE001 - reported by run_tasks after the others
            finished(futures[fut], None, exc)
        else:
            finished(futures[fut], result)
        bar.update()
    bar.close()


class TaskCache:
    """Finished FE task results on disk, so that an interrupted sweep resumes.

    A result is keyed on the task (function, arguments, and what the function reads outside
    :mod:`debench.models`: its source, the helpers it calls and the settings it reads,
    :func:`task_inputs`) and on the source of the modules of :mod:`debench.models` that it
    runs (:func:`models_digest`): a change of the code or a setting that computes a result
    is a miss, never a stale hit.  Written atomically
    (temporary file + rename)."""

    def __init__(self, root: Path, code_digest: str):
        self.root, self.code_digest = Path(root), code_digest
        self.root.mkdir(parents=True, exist_ok=True)

    @classmethod
    def from_env(cls):
        """The cache in ``DEBENCH_FE_CACHE`` (None when unset)."""
        root = os.environ.get("DEBENCH_FE_CACHE")
        return cls(Path(root), models_digest()) if root else None

    def _path(self, task: tuple) -> Path:
        fn, *args = task
        key = repr((fn.__module__, fn.__qualname__, tuple(args), task_inputs(fn),
                    self.code_digest)).encode()
        return self.root / f"{hashlib.sha256(key).hexdigest()[:32]}.pkl"

    def get(self, task: tuple):
        """The stored result of ``task`` (None when absent)."""
        p = self._path(task)
        if not p.exists():
            return None
        with p.open("rb") as fh:
            return pickle.load(fh)

    def put(self, task: tuple, result) -> None:
        """Store the result of ``task`` (atomically)."""
        p = self._path(task)
        tmp = p.with_suffix(f".tmp{os.getpid()}")
        with tmp.open("wb") as fh:
            pickle.dump(result, fh)
        os.replace(tmp, p)


@functools.cache
def task_inputs(fn: Callable) -> str:
    """What the result of the task function ``fn`` depends on outside :mod:`debench.models`
    (whose source :func:`models_digest` covers), as text for the cache key.

    The source of ``fn``, then for every name its code reads (its own and that of the
    functions nested in it) that resolves to a global of its module, or that it imports
    inside its body from a module of its package (the studies: the task modules and the
    settings they share): a function or class of that package contributes its source and,
    recursively, what it reads; a module of it, the values of the names read from it; any
    other value its ``repr``. Code outside the package (the models, whose source
    :func:`models_digest` covers; the runner; third-party libraries) is not followed.
    Settings of the task's module that it never reads (a study's plan table beside a task)
    are not inputs: editing them leaves finished results valid, while an edit of anything
    the task reads is a miss. Read once per function and process (a global the task
    mutates as it runs, such as a record of its calls, does not change its key).
    """
    package = fn.__module__.rpartition(".")[0]
    seen = {id(fn)}
    parts = [inspect.getsource(fn)]

    def own(name: str) -> bool:
        return name == fn.__module__ or bool(package) and name.startswith(package + ".")

    def value(name: str, obj, names: set[str]) -> None:
        code = inspect.isfunction(obj) or inspect.isclass(obj) or inspect.ismodule(obj)
        if code and id(obj) in seen:
            return
        seen.add(id(obj))
        if inspect.isfunction(obj) or inspect.isclass(obj):
            if own(getattr(obj, "__module__", "") or ""):
                parts.append(inspect.getsource(obj))
                if inspect.isfunction(obj):
                    walk(obj)
        elif inspect.ismodule(obj):
            if own(obj.__name__):
                for attr in sorted(names & set(vars(obj))):
                    value(f"{obj.__name__}.{attr}", getattr(obj, attr), names)
        else:
            text = repr(obj)
            # an object without a value repr (its address) is no setting: its type stands
            parts.append(f"{name}: {type(obj).__qualname__}" if " at 0x" in text
                         else f"{name} = {text}")

    def walk(f) -> None:
        names = _names_read(f.__code__)
        for name in sorted(names & set(f.__globals__)):
            value(name, f.__globals__[name], names)
        for module, name in _imported(f.__code__):
            if own(module):
                value(f"{module}.{name}", getattr(importlib.import_module(module), name),
                      names)

    walk(fn)
    return "\n".join(parts)


def _names_read(code) -> set[str]:
    """The global and attribute names a code object and the code nested in it read."""
    out = set(code.co_names)
    for const in code.co_consts:
        if inspect.iscode(const):
            out |= _names_read(const)
    return out


def _imported(code) -> list[tuple[str, str]]:
    """``(module, name)`` of every ``from module import name`` in a code object and the
    code nested in it."""
    out, module = [], None
    for ins in dis.get_instructions(code):
        if ins.opname == "IMPORT_NAME":
            module = ins.argval
        elif ins.opname == "IMPORT_FROM" and module:
            out.append((module, ins.argval))
    for const in code.co_consts:
        if inspect.iscode(const):
            out += _imported(const)
    return out


def models_digest() -> str:
    """sha256 of the source (path and content) of the modules of :mod:`debench.models` that
    the FE tasks run (:data:`FE_SOURCES`)."""
    root = Path(models.__file__).parent
    h = hashlib.sha256()
    for f in sorted({f for pattern in FE_SOURCES for f in root.glob(pattern)}):
        h.update(str(f.relative_to(root)).encode())
        h.update(f.read_bytes())
    return h.hexdigest()
