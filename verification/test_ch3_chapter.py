"""The Chapter 3 chapter pass: one memoised computation, keyed on its parameters, whose
results equal those of the one-annulus public functions it batches, and which the dataset
builder and the catalogue producers share.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from debench.models.circular import analysis, integrator, lockstep, shooting
from debench.models.circular.actuator import branch, branches, branches_solver, curves
from debench.models.circular.chapter_pass import ChapterSpec, chapter, current_constants
from debench.models.circular.params import Annulus

#: batched and one-by-one solves stop on the same relative criteria (events 1e-14 in q,
#: Newton 1e-13 or 1e-15 in q): measured agreement 7e-12 relative (the c threshold before
#: loss of tension, whose grid ends at a located event); 1e-9 keeps a >100x margin and
#: still sees a wrong variant, pre-stretch or c (>= 1e-4)
BATCH_RTOL = 1e-9

SMALL = ChapterSpec(lamPs=(3.0,), cs=(0.0, -0.053), states=((3.0, 0.2, -0.053),),
                    stretches=((3.0, 4.5),), n=120)


@pytest.fixture(scope="module")
def small():
    return chapter(SMALL)


def test_chapter_pass_is_memoised_on_its_parameters(small):
    """An equal specification returns the same result object (computed once); another
    value of a model constant is another key (never a stale result)."""
    assert chapter(replace(SMALL)) is small
    other = replace(SMALL, constants=(121.0, *current_constants()[1:]))
    assert other != SMALL and hash(other) != hash(SMALL)
    with pytest.raises(TypeError, match="ChapterSpec"):
        chapter({"lamPs": (3.0,)})


def test_chapter_curves_equal_curves_on_the_branch(small):
    """Every event of the chapter's curves (both variants) equals that of
    :func:`curves` on the chapter's branch, and the branch equals :func:`branch`."""
    for eq in ("printed", "membrane"):
        br = small.branches[(3.0, eq)]
        ref_br = branch(Annulus(3.0, equilibrium=eq), n=120)
        np.testing.assert_array_equal(br.lam, ref_br.lam)
        refs = curves(ref_br, [0.0, -0.053])
        for c, ref in zip((0.0, -0.053), refs, strict=True):
            cv = small.curves[(3.0, c, SMALL.eps_r, eq)]
            assert cv.failure.kind == ref.failure.kind
            for kind, ev in ref.events.items():
                got = cv.events[kind]
                assert (got is None) == (ev is None), (eq, c, kind)
                if ev is not None:
                    assert got.lam == pytest.approx(ev.lam, rel=BATCH_RTOL)
                    assert got.phibar == pytest.approx(ev.phibar, rel=BATCH_RTOL)


def test_chapter_states_and_stretches_equal_the_public_functions(small):
    """States at Phibar = 0.2 (c = 0 and -0.053) and the interface state at stretch 4.5
    equal :func:`analysis.state_at_voltage` and :func:`shooting.q_for_stretch`."""
    for eq in ("printed", "membrane"):
        br = small.branches[(3.0, eq)]
        for c in (0.0, -0.053):
            ref = analysis.state_at_voltage(br, c, 0.2)
            got = small.states[(3.0, 0.2, c, eq)]
            for key in ("lam", "lam1B", "q"):
                assert got[key] == pytest.approx(ref[key], rel=BATCH_RTOL), (eq, c, key)
            p1, p2, rho = small.profiles[(3.0, 0.2, c, eq)]
            assert p2[0] == pytest.approx(ref["lam"], rel=BATCH_RTOL)
            assert rho[0] == pytest.approx(1.0) and rho[-1] == pytest.approx(15.0)
            assert p1[-1] == pytest.approx(ref["q"], rel=BATCH_RTOL)
        q = shooting.q_for_stretch(br.annulus, np.array([4.5]), np.interp(4.5, br.lam, br.q))
        st = shooting.interface_state(br.annulus, q)
        lam, T1 = small.stretch_states[(3.0, 4.5, eq)]
        assert lam == pytest.approx(4.5, rel=1e-12)
        assert T1 == pytest.approx(float(st.T1[0]), rel=BATCH_RTOL)


def test_suppression_search_with_given_bracket_branches_equals_its_own_trace():
    """The suppression search reading the chapter's bracket-end branches finds the roots
    it finds when it traces them itself (same function of lamP, same iteration)."""
    eqs = ("printed", "membrane")
    ends = branches([Annulus(x, equilibrium=eq) for x in (2.0, 3.2) for eq in eqs], n=60)
    given = analysis.pullin_suppression_prestretches(0.0, eqs, n=60, xtol=1e-6,
                                                     bracket_branches=ends)
    own = analysis.pullin_suppression_prestretches(0.0, eqs, n=60, xtol=1e-6)
    assert given == own
    with pytest.raises(ValueError, match="bracket_branches"):
        analysis.pullin_suppression_prestretches(0.0, eqs, n=60, bracket_branches=ends[::-1])


def test_branches_with_one_grid_size_per_annulus_equal_separate_traces():
    """``branches`` with one n per annulus (an annulus listed twice is scanned once)
    gives the branches that separate calls give."""
    an = [Annulus(1.25), Annulus(1.25, equilibrium="membrane"), Annulus(1.25)]
    got = branches(an, n=[50, 50, 80])
    for g, a, n in zip(got, an, (50, 50, 80), strict=True):
        ref = branches([a], n=n)[0]
        assert g.annulus == a and g.lam.size == n
        for name in ("q", "lam", "T1", "dlam", "dT1"):
            np.testing.assert_array_equal(getattr(g, name), getattr(ref, name))
    with pytest.raises(ValueError, match="one per annulus"):
        branches(an, n=[50, 50])


@pytest.mark.parametrize("cplx", [False, True])
def test_integration_in_pieces_equals_one_piece(monkeypatch, cplx):
    """A batch integrated in pieces (below the allocation threshold) equals the batch in
    one piece, bit for bit, mixed variants and pre-stretches included."""
    q = np.linspace(3.0, 1.2, 100)
    lamP = np.where(np.arange(100) % 2, 3.0, 2.0)
    mem = np.arange(100) % 3 == 0
    q = q + 1e-30j if cplx else q
    an = Annulus(3.0)
    one = integrator.integrate(an, q, lamP=lamP, membrane=mem)
    # pieces of at most 40 (three of 33-34 trajectories, above the scalar batch size)
    monkeypatch.setattr(integrator, "CHUNK_BYTES", 2 * 40 * q.dtype.itemsize)
    pieces = integrator.integrate(an, q, lamP=lamP, membrane=mem)
    for a, b in zip(one, pieces, strict=True):
        np.testing.assert_array_equal(a, b)


def test_lockstep_solvers_equal_each_run_alone():
    """Solvers run side by side (one integration per round for all, real before complex,
    annuli of another R_B/R_A in their own integration) return what each returns alone,
    bit for bit (batches above the scalar size either way)."""
    q1 = np.linspace(3.0, 2.2, 30)
    q2 = np.linspace(2.0, 1.6, 20)
    printed, membrane = Annulus(3.0), Annulus(2.0, equilibrium="membrane")
    wide = Annulus(3.0, radius_ratio=10.0)

    def solvers():
        return [shooting.interface_state_solver(printed, q1),
                shooting.interface_state_solver(membrane, q2),
                shooting.interface_state_solver(wide, q1),
                branches_solver([printed, membrane], n=[40, 30], steps=shooting.DEFAULT_STEPS)]

    together = lockstep.lockstep(solvers())
    alone = [lockstep.run(s) for s in solvers()]
    for a, b in zip(together[:3], alone[:3], strict=True):
        for name in ("lam", "lam1", "T1", "dlam", "dT1"):
            np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    for a, b in zip(together[3], alone[3], strict=True):
        np.testing.assert_array_equal(a.lam, b.lam)
        np.testing.assert_array_equal(a.T1, b.T1)
    assert not np.allclose(together[0].T1, together[2].T1)   # R_B/R_A kept apart


def test_lockstep_propagates_a_solver_error():
    def failing():
        yield lockstep.Request.of(Annulus(3.0), np.linspace(3.0, 2.5, 20), 200)
        raise ValueError("solver failed")

    with pytest.raises(ValueError, match="solver failed"):
        lockstep.lockstep([shooting.interface_state_solver(Annulus(3.0), [3.0, 2.9]),
                           failing()])
