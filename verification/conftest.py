"""Shared pytest configuration for the verification suite.

* ``--full`` opts in to tests marked ``slow`` (converged finite-element meshes, full
  sweeps). Without it they are skipped, and a fast but real version of every check runs.
* ``--docs`` opts in to tests marked ``docs``: the documentation site is built and opened
  in headless Chromium (a missing Sphinx or Chromium then fails, with how to install it).
* ``--commands`` opts in to tests marked ``commands``: every command block of the README
  and the site's pages runs in a fresh copy of the repository with a fresh venv
  (``test_documented_commands.py``; a failed install or command fails the test).
* ``--peers`` opts in to tests marked ``peers``: they build the peer libraries'
  environments from their pinned requirements (``peers/run.py``) and rerun every curated
  submission's adapter. Opted in, nothing is skipped: a missing Python or a failed install
  fails the test.
* Thread counts (BLAS/OpenMP, NGSolve) are set once here by
  :func:`debench.threads.limit_threads` (``DEBENCH_THREADS``, default 1).
* Hypothesis is deterministic by default (profile ``debench``: derandomized, no example
  database, no deadline) so that CI is reproducible; ``--hypothesis-profile=explore``
  searches with fresh randomness. Counterexamples found while exploring are frozen as
  named regular tests.
"""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, settings

from debench.threads import limit_threads

# One thread per process for BLAS/OpenMP and NGSolve unless DEBENCH_THREADS says otherwise:
# default thread counts oversubscribe small machines (and must not change any result).
limit_threads()

settings.register_profile(
    "debench",
    derandomize=True,
    database=None,
    deadline=None,
    max_examples=50,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile("explore", deadline=None, max_examples=1000)
settings.load_profile("debench")


def pytest_report_header(config: pytest.Config) -> list[str]:
    """The BLAS kernels and thread counts in use (results must not depend on them)."""
    from debench.threads import thread_report

    return [f"debench threads: {p['internal_api']} {p['version']} "
            f"({p.get('architecture') or p.get('user_api')}), {p['num_threads']} thread(s)"
            for p in thread_report()]


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption(
        "--full", action="store_true", default=False,
        help="run tests marked slow (converged FE meshes, full sweeps)",
    )
    parser.addoption(
        "--install", action="store_true", default=False,
        help="run tests marked install (wheel built and installed in a fresh venv)",
    )
    parser.addoption(
        "--docs", action="store_true", default=False,
        help="run tests marked docs (build the documentation site, check it in Chromium)",
    )
    parser.addoption(
        "--commands", action="store_true", default=False,
        help="run tests marked commands (every documented command block in a fresh clone "
             "and venv)",
    )
    parser.addoption(
        "--peers", action="store_true", default=False,
        help="run tests marked peers (build the peer codes' venvs, rerun their adapters "
             "and compare with the curated submissions)",
    )


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    skip_slow = pytest.mark.skip(reason="slow: opt in with --full")
    skip_install = pytest.mark.skip(reason="install: opt in with --install")
    skip_docs = pytest.mark.skip(reason="docs: opt in with --docs")
    skip_peers = pytest.mark.skip(reason="peers: opt in with --peers")
    skip_commands = pytest.mark.skip(reason="commands: opt in with --commands")
    for item in items:
        if "slow" in item.keywords and not config.getoption("--full"):
            item.add_marker(skip_slow)
        if "install" in item.keywords and not config.getoption("--install"):
            item.add_marker(skip_install)
        if "docs" in item.keywords and not config.getoption("--docs"):
            item.add_marker(skip_docs)
        if "peers" in item.keywords and not config.getoption("--peers"):
            item.add_marker(skip_peers)
        if "commands" in item.keywords and not config.getoption("--commands"):
            item.add_marker(skip_commands)
