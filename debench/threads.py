"""Thread counts of BLAS/OpenMP and NGSolve, set in one place.

On the small shared machines this project runs on, the default thread counts of the
numerical libraries oversubscribe the cores (measured up to 3x slower). Everything that
computes - the ``debench`` command, the test suite, the benchmarks and the Dask workers -
calls :func:`limit_threads` once before working.

The count is, in order: the argument, the environment variable ``DEBENCH_THREADS``, or 1.
One thread per process is the right default: the heavy work of this project is many small
or medium sparse factorisations and vectorised numpy, which gain little from threads, and
parallel sweeps run one process per core instead.

Examples
--------
>>> from debench.threads import limit_threads
>>> limit_threads(1)
1
"""

from __future__ import annotations

import os
import sys

from threadpoolctl import threadpool_info, threadpool_limits

#: Environment variable with the thread count to use (default 1).
THREADS_ENV = "DEBENCH_THREADS"
_ENV_VARS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
             "BLIS_NUM_THREADS", "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS")
_limiter = None


def configured_threads(n: int | None = None) -> int:
    """The thread count to use: ``n``, else ``$DEBENCH_THREADS``, else 1 (validated)."""
    if n is None:
        raw = os.environ.get(THREADS_ENV, "1")
        try:
            n = int(raw)
        except ValueError:
            raise ValueError(f"{THREADS_ENV} = {raw!r} must be a positive integer") from None
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise ValueError(f"threads = {n!r} must be an integer >= 1")
    return n


def limit_threads(n: int | None = None) -> int:
    """Set the BLAS/OpenMP and NGSolve thread counts of this process (and its children).

    Sets the usual environment variables (for libraries loaded later and for child
    processes), limits the thread pools already loaded (threadpoolctl) and, when NGSolve is
    imported, its TaskManager (``ngsolve.SetNumThreads``). Returns the count.
    """
    global _limiter
    n = configured_threads(n)
    for var in _ENV_VARS:
        os.environ[var] = str(n)
    os.environ[THREADS_ENV] = str(n)
    _limiter = threadpool_limits(limits=n)
    if "ngsolve" in sys.modules:
        sys.modules["ngsolve"].SetNumThreads(n)
    return n


def thread_report() -> list[dict]:
    """The thread pools of numpy's BLAS (loaded here if needed) and of every other loaded
    library, with their sizes and kernels (threadpoolctl), for logs and benchmarks."""
    import numpy  # noqa: F401 - loads the BLAS whose kernel is reported

    keys = ("user_api", "internal_api", "num_threads", "version", "architecture")
    return [{k: p.get(k) for k in keys} for p in threadpool_info()]
