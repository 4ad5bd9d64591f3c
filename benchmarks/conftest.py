"""Benchmarks run with fixed thread counts (BLAS/OpenMP and NGSolve), set in one place.

``DEBENCH_THREADS`` (default 1) is applied by :func:`debench.threads.limit_threads`
before any benchmark module is imported; group names state the count.
"""

from debench.threads import limit_threads

THREADS = limit_threads()
