"""Property-based fuzzing of the public API of ``debench.models`` (Chapter 5 excluded).

Claim (DESIGN.md, "Numerical honesty"): every public callable, given any argument from
the registry's invalid or extreme lists (NaN, +-inf, 0, negatives, 1e300, wrong shapes
and types, det F <= 0, stretches out of range, non-finite tolerances, zero counts) or a
random valid-looking input, either returns finite values that pass the model's own
checks, or raises ``ValueError`` / ``TypeError`` / ``ConvergenceError`` from debench
code -- never NaN, inf or a foreign exception.

The registry (``verification/fuzz_registry.py``) is explicit; a meta-test fails when a
public callable is missing from it. Default run: few examples per callable
(``FEW``/``SOME`` below) under the deterministic profile ``debench``; run longer with
``--hypothesis-profile=explore``.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from verification import fuzz_registry as reg

#: examples per callable in the default run (the whole file stays well under 60 s);
#: the ``explore`` profile's max_examples applies when it is loaded instead
FEW = 6
SOME = 40

CASES = {c.name: c for c in reg.cases()}


def _examples(n: int) -> int:
    return n if settings.default.max_examples <= 50 else settings.default.max_examples


def _assert_outcome(case, arg, value, invalid):
    outcome, detail = reg.classify(case, arg, value, invalid)
    assert outcome in ("clear", "ok"), f"{case.name}({arg}={value!r:.60}): {outcome}: {detail}"


def test_every_public_callable_is_registered():
    """Meta-test: a new public function, class, method or property of debench.models
    (outside the excluded modules) must be added to the fuzz registry."""
    missing = reg.public_names() - set(CASES)
    assert not missing, f"not in verification/fuzz_registry.py: {sorted(missing)}"


@pytest.mark.parametrize("name", sorted(CASES))
def test_valid_call_returns_finite_values(name):
    """The registered valid call succeeds and passes its checks (a fuzz case that cannot
    succeed would prove nothing)."""
    _assert_outcome(CASES[name], None, None, False)


@pytest.mark.parametrize("name", sorted(CASES))
def test_bad_input_raises_a_project_error(name):
    """Every listed invalid value raises a clear error; every extreme one raises or
    returns finite values (sampled by Hypothesis from the registry lists)."""
    case = CASES[name]
    inputs = list(case.inputs())
    if not inputs:
        pytest.skip("no arguments")

    @settings(max_examples=_examples(FEW), deadline=None,
              suppress_health_check=[HealthCheck.too_slow])
    @given(st.sampled_from(inputs))
    def run(item):
        arg, value, invalid = item
        _assert_outcome(case, arg, value, invalid)

    run()


# ----------------------------------------------------------- valid-looking inputs
_MATERIAL_RESPONSES = sorted(n for n in CASES if n.endswith((".response", ".energy"))
                             and ".library." in n)


@pytest.mark.parametrize("name", _MATERIAL_RESPONSES)
@settings(max_examples=_examples(SOME), deadline=None)
@given(F=st.lists(st.floats(-3.0, 3.0), min_size=9, max_size=9),
       D=st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3))
def test_material_response_of_random_states_is_finite_or_refused(name, F, D):
    """Random finite F (any det) and D_L: the energy and response are finite or the state
    is refused (det F <= 0, past the Gent lock) with ValueError."""
    case = CASES[name]
    scale = 1e-3 if "IdealDielectric" in name and "Dorfmann" not in name else 1.0
    _assert_outcome(case, "F", np.array(F).reshape(3, 3), False)
    _assert_outcome(case, "D_L", np.array(D) * scale, False)


@settings(max_examples=_examples(SOME), deadline=None)
@given(lam=st.floats(0.0, 20.0), T1B=st.floats(-5.0, 5.0), c=st.floats(-0.5, 0.1),
       Jm=st.floats(1.0, 500.0))
def test_phibar_squared_of_random_states_is_finite_or_refused(lam, T1B, c, Jm):
    """(3.30): finite, or ValueError (lam <= 0, past the lock, K <= 0)."""
    case = CASES["debench.models.circular.circle_a.phibar_squared"]
    from debench.models.circular import circle_a
    from debench.models.errors import ConvergenceError
    try:
        out = circle_a.phibar_squared(lam, T1B, c, 1 / Jm)
    except (ValueError, ConvergenceError):
        return
    reg.all_finite(out)
    assert case is not None


@settings(max_examples=_examples(SOME), deadline=None)
@given(lam=st.floats(0.05, 10.0), kH=st.floats(1e-3, 50.0), xi=st.floats(0.0, 10.0),
       Dhat=st.floats(0.0, 5.0), parity=st.sampled_from(["E", "O"]))
def test_plate_determinant_of_random_states_is_finite_or_refused(lam, kH, xi, Dhat, parity):
    """Method-1 determinant: finite, or ValueError outside the strongly elliptic range."""
    from debench.models.plate import PlateParams
    from debench.models.plate.ansatz import determinant
    from debench.models.plate.coefficients import strongly_elliptic
    p = PlateParams(xi=xi, Dhat=Dhat)
    try:
        out = determinant(lam, kH, p, parity)
    except ValueError:
        assert not strongly_elliptic(lam, p)
        return
    reg.all_finite(out)
