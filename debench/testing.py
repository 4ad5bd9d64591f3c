"""Check your own results against a debench reference problem.

:func:`assert_matches` loads the verified reference of a problem (see
:mod:`debench.reference.problems`; ``debench problems`` lists them), interpolates it to
your coordinates where the quantity is a curve, and applies the accuracy the reference
states (solver tolerance + discretisation error + interpolation error estimate) or your
tolerance, whichever is larger: a reference cannot be checked tighter than it is known.
Several quantities of one problem at the same points are checked at once by passing their
values as a mapping (quantity name -> values): each against its own reference and
accuracy, with the same coverage and duplicate checks, reported together
(:class:`~debench.reference.comparison.Comparisons`).

Examples
--------
>>> import numpy as np
>>> from debench.testing import assert_matches
>>> lam = np.linspace(1.0, 5.0, 401)             # the reference range, as densely
>>> phibar = np.sqrt(lam**-2 - lam**-8)        # your free-membrane solver here
>>> assert_matches("ch3_free_membrane_nh", "phibar", phibar, {"lam": lam}).passed
True

Two quantities of one problem at once (here the reference values themselves):

>>> from debench.reference import problems
>>> from debench.reference.problems_reference import reference_at
>>> prob = problems.get("ch5_pullin")
>>> films = {"case": ["nh_r10", "ogden_r10"]}     # every film: full coverage
>>> mine = {q.name: reference_at(prob, q, films).value for q in prob.quantities}
>>> assert_matches("ch5_pullin", None, mine, films).quantities
('v_pullin', 'w_pullin')
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from debench.reference.comparison import Comparison, Comparisons, compare

__all__ = ["Comparison", "Comparisons", "assert_matches", "compare"]


def assert_matches(problem: str, quantity: str | None, values, coords: Mapping[str, Any],
                   rtol: float | Mapping[str, float] | None = None, *,
                   atol: float | Mapping[str, float] | None = None,
                   coverage: str = "full") -> Comparison | Comparisons:
    """Raise ``AssertionError`` (with a table of the worst points) unless ``values`` match
    the reference of ``problem``; see :func:`~debench.reference.comparison.compare` for
    the arguments (``values`` a mapping quantity name -> values: every quantity must
    match, the message names those that do not).

    Returns the :class:`~debench.reference.comparison.Comparison`
    (:class:`~debench.reference.comparison.Comparisons`) when they match.
    """
    result = compare(problem, quantity, values, coords, rtol=rtol, atol=atol,
                     coverage=coverage)
    if not result.passed:
        raise AssertionError(f"{result.summary()}\n{result.table()}")
    return result
