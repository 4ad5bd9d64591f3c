"""Chapter 3 batched solves equal the one-annulus solves they batch.

The producers compute the states at a voltage (Figs 3.2-3.3), the branches up to loss of
tension (the c threshold, Sec. 3.5.2) and the annulus profiles of both equilibrium
variants in one shooting integration per iteration, with per-trajectory pre-stretch and
balance. Each batched result must be the one the public one-annulus function gives, to
the tolerance of the iteration that produces it.
"""

from __future__ import annotations

import numpy as np
import pytest
from debench.models.circular import analysis, shooting
from debench.models.circular.actuator import branch, branches
from debench.models.circular.params import Annulus

#: both iterations stop on a relative Newton step in q (1e-15 for the states at a
#: voltage, 1e-13 for the branch points, whose Newton starts differ); measured: the
#: batched and one-by-one solutions agree to 3.5e-13 relative (T1 near loss of tension);
#: 1e-9 keeps a >1000x margin and still sees a wrong variant or pre-stretch (>= 1e-4)
BATCH_RTOL = 1e-9


@pytest.fixture(scope="module")
def pair():
    return branches([Annulus(3.0), Annulus(3.0, equilibrium="membrane")], n=200)


def test_batched_states_at_voltage_equal_one_branch_each(pair):
    """States at Phibar = 0.2 for c = 0 and -0.053 on both variants in one iteration
    equal :func:`analysis.state_at_voltage` on each branch."""
    brs = [pair[0], pair[0], pair[1], pair[1]]
    cs = [0.0, -0.053, 0.0, -0.053]
    got = analysis.states_at_voltage_many(brs, cs, [0.2] * 4)
    for br, c, st in zip(brs, cs, got, strict=True):
        ref = analysis.state_at_voltage(br, c, 0.2)
        for key in ("lam", "lam1B", "q"):
            assert st[key] == pytest.approx(ref[key], rel=BATCH_RTOL), (br.annulus, c, key)
    # the variants differ (the batch does not mix them up)
    assert abs(got[0]["lam"] - got[2]["lam"]) > 1e-4


def test_batched_branches_at_stretches_equal_branch(pair):
    """Branch points at given stretches of both variants in one Newton iteration equal
    :func:`branch` with ``lam=`` (its own scan and Newton start) for each annulus."""
    lams = [np.linspace(3.0, 6.0, 40), np.linspace(3.0, 5.5, 30)]
    got = analysis.branches_at(pair, lams)
    for br, lam, g in zip(pair, lams, got, strict=True):
        ref = branch(br.annulus, lam=lam)
        np.testing.assert_allclose(g.lam, lam, rtol=BATCH_RTOL)
        for name in ("q", "T1", "lam1", "dlam", "dT1"):
            np.testing.assert_allclose(getattr(g, name), getattr(ref, name), rtol=BATCH_RTOL,
                                       err_msg=f"{br.annulus}: {name}")


def test_branches_at_rejects_stretches_off_the_branch(pair):
    with pytest.raises(ValueError, match="stretches must lie"):
        analysis.branches_at(pair[:1], [np.array([2.9, 3.5])])


def test_producer_profiles_equal_one_integration_each():
    """The producers' annulus profiles (both variants, c = 0 and -0.053, one integration)
    equal :func:`shooting.integrate_inward` of each state alone."""
    from debench.reference.producers import ch3_model as model

    for eq in ("printed", "membrane"):
        profs = model.profiles(3.0, -0.053, 0.2, eq)
        for c, (p1, p2) in zip((0.0, -0.053), profs, strict=True):
            q = model.state(3.0, eq, c, 0.2)["q"]
            _, _, _, P1, P2 = shooting.integrate_inward(Annulus(3.0, equilibrium=eq),
                                                       np.array([q]), profile=True)
            np.testing.assert_allclose(p1, P1[::-1, 0], rtol=1e-13)
            np.testing.assert_allclose(p2, P2[::-1, 0], rtol=1e-13)
