"""pytest plugin (entry point ``pytest11``): the ``debench_reference`` fixture.

Installed with debench; in your own test suite::

    def test_my_membrane(debench_reference):
        lam = np.linspace(1.0, 5.0, 401)   # the reference grid: full coverage
        debench_reference.assert_matches("ch3_free_membrane_nh", "phibar",
                                         my_solver(lam), {"lam": lam})

The fixture imports nothing heavy until it is used, so the plugin costs nothing in test
suites that do not request it.
"""

from __future__ import annotations

import pytest


class DebenchReference:
    """What the fixture provides: :func:`debench.testing.assert_matches` and friends."""

    @staticmethod
    def assert_matches(problem, quantity, values, coords, rtol=None, *, atol=None,
                       coverage="full"):
        from debench.testing import assert_matches

        __tracebackhide__ = True
        return assert_matches(problem, quantity, values, coords, rtol, atol=atol,
                              coverage=coverage)

    @staticmethod
    def compare(problem, quantity, values, coords, *, rtol=None, atol=None,
                coverage="full"):
        from debench.testing import compare

        return compare(problem, quantity, values, coords, rtol=rtol, atol=atol,
                       coverage=coverage)

    @staticmethod
    def problem(problem_id):
        """The :class:`debench.reference.problems.Problem` spec."""
        from debench.reference import problems

        return problems.get(problem_id)


@pytest.fixture
def debench_reference() -> DebenchReference:
    """Check results against debench reference problems (``debench problems``)."""
    return DebenchReference()
