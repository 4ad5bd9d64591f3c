"""The shared numerics (:mod:`debench.models.numerics`) on synthetic problems with known
answers, each collection run through every method (SciPy's ``test_zeros`` runs one list of
functions with known roots through every root finder the same way)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from debench.models.errors import ConvergenceError
from debench.models.numerics import (
    Memo,
    asymptotic_fit,
    bisect_boundary,
    bordered_solve,
    bracketed_root,
    convergence_fit,
    damped_newton,
    gci,
    grid_brackets,
    level_fit,
    newton,
    p_grading_estimate,
    p_grading_safety,
    reference_fit,
    regula_falsi_many,
    residual_converged,
    richardson,
    roots,
    round_off_floor,
    scan_brackets,
    scan_roots,
    secant,
    secant_until,
    secants,
    two_term_limits,
    zero_near,
)
from debench.models.numerics.continuation import StepControl
from debench.models.numerics.convergence import (
    GCI_SAFETY_OBSERVED,
    GCI_SAFETY_THEORETICAL,
    SECOND_EXPONENTS,
    loglog_order,
)
from debench.models.numerics.roots import SCAN_METHODS

EPS = np.finfo(float).eps
#: the absolute tolerance every root method is asked for
XTOL = 1e-12

#: (name, f, bracket, root): smooth, steep, flat (triple root) and rational functions; the
#: roots are closed forms (or, for x^3 - 2x - 5, Wallis's cubic, its 17-digit value)
ROOT_PROBLEMS = [
    ("x^2 - 2", lambda x: x * x - 2.0, (0.0, 2.0), math.sqrt(2.0)),
    ("x^3 - 2x - 5", lambda x: x**3 - 2.0 * x - 5.0, (2.0, 3.0), 2.0945514815423265),
    ("exp(x) - 2", lambda x: np.exp(x) - 2.0, (0.0, 1.0), math.log(2.0)),
    ("sin(x) - 1/2", lambda x: np.sin(x) - 0.5, (0.0, 1.5), math.pi / 6),
    ("1/x - 1/2", lambda x: 1.0 / x - 0.5, (1.0, 3.0), 2.0),
    ("atan(20 (x - 0.3))", lambda x: np.arctan(20.0 * (x - 0.3)), (-1.0, 4.0), 0.3),
    ("x exp(-x) - 0.1", lambda x: x * np.exp(-x) - 0.1, (0.0, 1.0), 0.11183255915896297),
]

#: the secant's starting points: 1 % and 0.5 % of the bracket above the root (the secant
#: needs no bracket but a start in the root's basin; atan(20 (x - 0.3)) diverges, to a
#: flat secant, from starts 5 % and 2.5 % of its bracket away)
SECANT_STARTS = (1e-2, 5e-3)
#: scan points of scan_roots over a problem's bracket (each problem has one root there)
SCAN_POINTS = 7


def _bracketed(f, a, b, root, **kw):
    return bracketed_root(f, a, b, xtol=XTOL, what="synthetic", **kw)


def _secant(f, a, b, root, **kw):
    x0, x1 = (root + s * (b - a) for s in SECANT_STARTS)
    return secant(f, x0, x1, xtol=XTOL, what="synthetic", **kw)


def _secant_until(finish):
    def run(f, a, b, root, **kw):
        x0, x1 = (root + s * (b - a) for s in SECANT_STARTS)
        return secant_until(f, x0, x1, converged=lambda x, x_next: abs(x_next - x) < XTOL,
                            finish=finish, what="synthetic", **kw)
    return run


def _zero_near_bracket(f, a, b, root, **kw):
    return zero_near(f, None, a, b, XTOL, "synthetic", **kw)


def _zero_near_guess(f, a, b, root, **kw):
    # an estimate 1e-4 relative off, as a cheaper method supplies it
    return zero_near(f, root * (1 + 1e-4), a, b, XTOL, "synthetic", **kw)


def _regula_falsi(f, a, b, root, **kw):
    return regula_falsi_many(lambda x, active: f(x), [a], [b], [f(a)], [f(b)], XTOL, **kw)


def _scan(method):
    def run(f, a, b, root, **kw):
        found = scan_roots(f, np.linspace(a, b, SCAN_POINTS),
                           np.array([f(x) for x in np.linspace(a, b, SCAN_POINTS)]),
                           xtol=XTOL, method=method, what="synthetic", **kw)
        if found.root.size != 1:
            raise ConvergenceError(f"scan found {found.root.size} roots")
        return found.refined
    return run


ROOT_METHODS = {"bracketed_root": _bracketed, "secant": _secant,
                "secant_until (evaluated)": _secant_until("evaluated"),
                "secant_until (inverse quadratic)": _secant_until("inverse_quadratic"),
                "zero_near (bracket)": _zero_near_bracket, "zero_near (guess)": _zero_near_guess,
                "regula_falsi_many": _regula_falsi,
                "scan_roots (regula falsi)": _scan("regula_falsi"),
                "scan_roots (brentq)": _scan("brentq")}


def _root(res):
    return float(np.asarray(res.root).ravel()[0])


@pytest.mark.parametrize("method", ROOT_METHODS)
@pytest.mark.parametrize(("name", "f", "bracket", "root"), ROOT_PROBLEMS,
                         ids=[p[0] for p in ROOT_PROBLEMS])
def test_every_root_method_finds_every_known_root(method, name, f, bracket, root):
    """Each method returns a point within its contract of the known root: a sign change
    across an interval of width <= xtol + 4 eps |x| (brentq's stopping rule), so the
    returned end lies within twice that of the root; the secant's last step is below
    xtol and it converges superlinearly, so its root is as close. The result states it:
    converged, a bracket around the known root no wider than its ``error``."""
    res = ROOT_METHODS[method](f, *bracket, root)
    x = _root(res)
    assert abs(x - root) <= 2 * (XTOL + 4 * EPS * abs(root)), (method, name, x, root)
    # (a zero at a scan point needs no evaluation beyond the scan)
    assert res.converged and res.function_calls >= 0 and res.iterations >= 0
    if res.bracket is not None:
        a, b = (float(np.asarray(e).ravel()[0]) for e in res.bracket)
        # round-off of f beside the root may put the sign change a few ulps off it
        assert min(a, b) - 4 * EPS * abs(root) <= root <= max(a, b) + 4 * EPS * abs(root)
        assert float(np.asarray(res.error).ravel()[0]) == pytest.approx(abs(b - a))
    if not method.startswith("secant"):
        assert float(np.asarray(res.error).ravel()[0]) <= XTOL + 4 * EPS * abs(root)


@pytest.mark.parametrize("method", ROOT_METHODS)
def test_every_root_method_finds_a_triple_root_or_raises(method):
    """(x - 1)^3 on [0, 3]: flat at its root, brentq's 100 iterations do not suffice
    there. A method returns a point within its contract or raises ConvergenceError; it
    never returns a number outside it."""
    def f(x):
        return (x - 1.0) ** 3

    try:
        res = ROOT_METHODS[method](f, 0.0, 3.0, 1.0)
    except ConvergenceError:
        return
    # the secant converges only linearly on a triple root: its last step, below xtol,
    # is ~1/3 of its error
    slack = 4 if method.startswith("secant") else 2
    assert abs(_root(res) - 1.0) <= slack * (XTOL + 4 * EPS), (method, res)


#: (name, f, bracket, root, what every method must do): the failures of SciPy's
#: test_zeros collection that a root finder must not hide. "raises": ConvergenceError;
#: the scans report "no root" (an empty result) where no sign change is sampled
FAILURES = [
    ("no sign change (x^2 + 1)", lambda x: x * x + 1.0, (0.0, 1.0), 0.5),
    ("NaN inside the bracket", lambda x: np.nan if 0.29 < x < 0.31 else x - 0.3, (0.0, 1.0),
     0.3),
]


@pytest.mark.parametrize("method", ROOT_METHODS)
@pytest.mark.parametrize(("name", "f", "bracket", "root"), FAILURES,
                         ids=[p[0] for p in FAILURES])
def test_every_root_method_refuses_what_it_cannot_solve(method, name, f, bracket, root):
    """No sign change (no real root) and a function that is NaN where the iteration goes:
    every method raises ConvergenceError, none returns a number. (A scan that samples no
    sign change finds no root: its grid here is chosen to sample the NaN-free sign
    change, whose refinement meets the NaN.)"""
    if not method.startswith("scan_roots"):
        with pytest.raises(ConvergenceError):
            ROOT_METHODS[method](f, *bracket, root)
        return
    # grid 0, 0.2, ..., 1: the NaN is not sampled, the sign change [0.2, 0.4] is, and its
    # refinement evaluates the NaN
    grid = np.linspace(0.0, 1.0, 6)
    kw = {"xtol": XTOL, "method": "brentq" if "brentq" in method else "regula_falsi"}
    if name.startswith("NaN"):
        with pytest.raises(ConvergenceError):
            scan_roots(f, grid, np.array([f(x) for x in grid]), **kw)
    else:
        found = scan_roots(f, grid, np.array([f(x) for x in grid]), **kw)
        assert found.root.size == 0 and found.refined is None


@pytest.mark.parametrize("method", [m for m in ROOT_METHODS if m != "zero_near (guess)"])
def test_every_root_method_raises_when_maxiter_does_not_suffice(method):
    """exp(x) - 2 on [0, 1] needs several iterations of every method: with maxiter = 1
    each raises ConvergenceError instead of returning its last iterate. (zero_near from a
    close estimate is left out: its secant steps, with their own fixed budget, leave a
    bracket already below xtol, on which brentq converges in its first iteration.)"""
    name, f, bracket, root = ROOT_PROBLEMS[2]
    with pytest.raises(ConvergenceError):
        ROOT_METHODS[method](f, *bracket, root, maxiter=1)


def test_results_count_what_was_evaluated():
    """function_calls of brentq and of the secant are the calls of f (brentq's f is
    called as brentq calls it, no memo; the secant's through a Memo, once per point)."""
    calls = []

    def f(x):
        calls.append(x)
        return math.exp(x) - 2.0

    res = bracketed_root(f, 0.0, 1.0, xtol=XTOL)
    assert res.function_calls == len(calls) and res.method == "brentq"
    calls.clear()
    res = secant(f, 0.8, 0.75, xtol=XTOL)
    assert res.function_calls == len(calls) == len(set(calls)) and res.method == "secant"


def test_secant_until_stops_before_the_small_step_without_evaluating_it():
    """exp(x) - 2 from 0.5, 0.6 (no bracket: both below ln 2), stopped before a step below
    1e-6: the step is never evaluated; "evaluated" answers the last evaluated point, whose
    error is below that step (superlinear convergence), "inverse_quadratic" a point closer
    to the root than it (the interpolation error is of the order of the product of the last
    three distances, here below 1e-12, set by the 1e-6 stop: the last two are < 1e-3 and
    < 1e-6 away)."""
    for finish in ("evaluated", "inverse_quadratic"):
        calls = []

        def f(x, calls=calls):
            calls.append(x)
            return math.exp(x) - 2.0

        res = secant_until(f, 0.5, 0.6, converged=lambda x, x_next: abs(x_next - x) < 1e-6,
                           finish=finish, what="synthetic")
        assert res.next_iterate not in calls and res.function_calls == len(calls) >= 3
        assert abs(res.next_iterate - calls[-1]) < 1e-6
        if finish == "evaluated":
            assert res.root == calls[-1] and abs(res.root - math.log(2.0)) < 1e-6
        else:
            assert abs(res.root - math.log(2.0)) < 1e-12 < abs(calls[-1] - math.log(2.0))
    with pytest.raises(ValueError, match="finish"):
        secant_until(f, 0.5, 0.6, converged=lambda x, x_next: True, finish="brent")


def test_regula_falsi_refines_every_bracket_at_once():
    """All the problems refined in one call (the vectorised use of the Chapter 4 scans):
    the same roots as one at a time, with ``f`` called only on the active brackets."""
    fs = [p[1] for p in ROOT_PROBLEMS]
    a = np.array([p[2][0] for p in ROOT_PROBLEMS])
    b = np.array([p[2][1] for p in ROOT_PROBLEMS])
    calls = []

    def f(x, active):
        idx = np.flatnonzero(active)
        calls.append(idx.size)
        return np.array([fs[i](xi) for i, xi in zip(idx, x, strict=True)])

    fa = np.array([g(x) for g, x in zip(fs, a, strict=True)])
    fb = np.array([g(x) for g, x in zip(fs, b, strict=True)])
    res = regula_falsi_many(f, a, b, fa, fb, XTOL)
    roots = np.array([p[3] for p in ROOT_PROBLEMS])
    assert np.all(np.abs(res.root - roots) <= 2 * (XTOL + 4 * EPS * np.abs(roots)))
    assert calls[-1] < len(fs)            # converged brackets are no longer evaluated
    assert res.function_calls == len(calls)


def test_regula_falsi_refuses_a_function_not_finite_in_its_bracket():
    with pytest.raises(ConvergenceError, match="not finite"):
        regula_falsi_many(lambda x, active: np.full_like(x, np.nan), [0.0], [1.0], [-1.0],
                          [1.0], XTOL)


def test_bracketed_root_names_the_search_in_its_failures():
    """A bracket without a sign change raises ConvergenceError naming the search and the
    bracket; a bad tolerance is a ValueError naming it."""
    assert bracketed_root(lambda x: x - 0.25, 0.0, 1.0, xtol=XTOL, what="w").root == (
        pytest.approx(0.25))
    with pytest.raises(ConvergenceError, match=r"w: brentq failed on \[0.0, 1.0\]"):
        bracketed_root(lambda x: x + 1.0, 0.0, 1.0, xtol=XTOL, what="w")
    with pytest.raises(ValueError, match="xtol"):
        bracketed_root(lambda x: x, -1.0, 1.0, xtol=0.0)
    with pytest.raises(ValueError, match="rtol"):
        bracketed_root(lambda x: x, -1.0, 1.0, xtol=XTOL, rtol=1e-17)


def test_zero_near_from_a_close_estimate_brackets_the_zero_within_xtol():
    """Secant steps from a close estimate leave two evaluated points closer than xtol with
    opposite signs around the zero, and brentq then returns one of them (in few
    evaluations: each may be an eigen-solve); where the steps find no sign change (a zero
    outside the bracket, a flat function) the whole bracket is searched, and a bracket
    without a sign change raises."""
    root, xtol = 0.7310585786300049, 1e-11
    fm = Memo(lambda x: np.tanh(3 * (x - root)))
    res = zero_near(fm, 0.73, 0.7, 0.8, xtol)
    a, b = res.bracket
    assert 0 < b - a < xtol and a <= root <= b and len(fm.values) <= 6
    assert abs(res.root - root) <= xtol and res.root in fm.values
    assert abs(zero_near(lambda x: x - 0.79, 0.701, 0.7, 0.8, xtol).root - 0.79) <= xtol
    with pytest.raises(ConvergenceError, match="does not change sign"):
        zero_near(lambda x: x - 0.95, 0.75, 0.7, 0.8, xtol)
    with pytest.raises(ConvergenceError, match="does not change sign"):
        zero_near(lambda x: 1.0, 0.75, 0.7, 0.8, xtol)


# ------------------------------------------------------------------ grid scans
def test_scan_roots_finds_every_zero_on_its_grid_once():
    """sin(x) on [0.5, 10]: pi, 2 pi, 3 pi, in scan order; a zero at a grid point
    (x - 2 on a grid through 2) is returned once, unrefined; ``select`` keeps the first
    or last zero; a descending grid gives the zeros in its own order; the brackets are
    passed with their lower end first (the same roots as an ascending grid)."""
    grid = np.linspace(0.5, 10.0, 40)
    want = np.pi * np.arange(1, 4)
    for method in SCAN_METHODS:
        found = scan_roots(np.sin, grid, xtol=XTOL, method=method)
        np.testing.assert_allclose(found.root, want, rtol=0, atol=2 * (XTOL + 4 * EPS * 10))
        assert list(found.row) == [0, 0, 0]
        assert np.all((grid[found.interval] < found.root)
                      & (found.root < grid[found.interval + 1]))
        first = scan_roots(np.sin, grid, xtol=XTOL, method=method, select="first")
        last = scan_roots(np.sin, grid, xtol=XTOL, method=method, select="last")
        assert (first.root.tolist(), last.root.tolist()) == ([found.root[0]],
                                                              [found.root[-1]])
        down = scan_roots(np.sin, grid[::-1], xtol=XTOL, method=method)
        np.testing.assert_array_equal(down.root, found.root[::-1])
        on = scan_roots(lambda x: x - 2.0, np.linspace(0.0, 4.0, 5), xtol=XTOL,
                        method=method)
        assert on.root.tolist() == [2.0]


def test_scan_roots_of_several_rows_on_one_grid():
    """Rows of one grid (the Chapter 4 curves: one row per kH) refined together: each
    row's zeros, tagged with their row; ``f(points, rows)`` sees each bracket's row."""
    grid = np.linspace(0.0, 1.0, 11)
    shifts = np.array([0.33, 0.71, 0.05])

    def f(x, rows):
        return np.asarray(x) - shifts[rows]

    vals = grid[None, :] - shifts[:, None]
    for method in SCAN_METHODS:
        found = scan_roots(f, grid, vals, xtol=XTOL, method=method)
        assert found.row.tolist() == [0, 1, 2]
        np.testing.assert_allclose(found.root, shifts, rtol=0, atol=2 * XTOL)


def test_scan_roots_refuses_bad_arguments_naming_them():
    with pytest.raises(ValueError, match="method"):
        scan_roots(np.sin, np.linspace(1, 4, 5), xtol=XTOL, method="newton")
    with pytest.raises(ValueError, match="select"):
        scan_roots(np.sin, np.linspace(1, 4, 5), xtol=XTOL, select="middle")
    with pytest.raises(ValueError, match="values"):
        scan_roots(np.sin, np.linspace(1, 4, 5), np.ones(4), xtol=XTOL)


def test_bisect_boundary_halves_to_xtol_or_a_fixed_count():
    """The boundary of {x >= sqrt(2)} from [1, 2]: to xtol, the end where the predicate
    holds lies within xtol above it; with a fixed count of halvings the bracket is the
    first interval halved that many times (its width exactly 2^-n here, dyadic ends), and
    the predicate is called once per halving."""
    calls = []

    def inside(x):
        calls.append(x)
        return x * x >= 2.0

    res = bisect_boundary(inside, 1.0, 2.0, xtol=XTOL)
    a, b = res.bracket
    assert a < math.sqrt(2.0) <= b and b - a <= XTOL and res.root == b
    assert res.function_calls == res.iterations == len(calls)
    res = bisect_boundary(inside, 1.0, 2.0, halvings=20)
    a, b = res.bracket
    assert b - a == 2.0**-20 and a < math.sqrt(2.0) <= b and res.iterations == 20


def test_bisect_boundary_refuses_what_it_cannot_do():
    """An xtol below the spacing of doubles stalls: ConvergenceError, not a loop; both or
    neither stopping rule, or equal ends: ValueError naming them."""
    with pytest.raises(ConvergenceError, match="stalled"):
        bisect_boundary(lambda x: x >= 1.5, 1.0, 2.0, xtol=0.0)
    with pytest.raises(ValueError, match="exactly one of xtol and halvings"):
        bisect_boundary(lambda x: True, 1.0, 2.0, xtol=1e-3, halvings=3)
    with pytest.raises(ValueError, match="exactly one of xtol and halvings"):
        bisect_boundary(lambda x: True, 1.0, 2.0)
    with pytest.raises(ValueError, match="distinct"):
        bisect_boundary(lambda x: True, 1.0, 1.0, xtol=1e-3)


# ------------------------------------------------- adaptive scans: hidden sign changes
#: a zero refined by brentq to 1e-15 on an O(1) synthetic function: 1e-12 is > 100x its
#: round-off
TOL_SYNTH = 1e-12
#: the refinement width of the scans: that of the in-plane determinant scans
#: (debench.models.plate.inplane.W_SCAN), whose cases these functions reproduce
WIDTH = 1e-8
#: the synthetic scans: a geometric grid of ~1.3 % intervals, as the builder's (40 points)
GRID = np.geomspace(0.5, 0.9, 40)


def _brackets_of(f, m=None, grid=GRID):
    """scan_brackets of f with the measure m (default |f|) at the determinant's width."""
    m = m or (lambda x: np.abs(f(x)))
    return scan_brackets(lambda x: (f(x), m(x)), grid, width=WIDTH)


def _zeros(f, brackets):
    return sorted(a if fa == 0 else b if fb == 0 else bracketed_root(f, a, b, xtol=1e-15).root
                  for a, b, fa, fb in brackets)


def test_refined_scan_separates_a_root_pair_inside_one_grid_interval():
    """Two simple zeros 1.2e-3 apart in one grid interval: the grid sees no sign change,
    the refinement beside the minimum of |f| brackets each."""
    def f(x):
        return (x - 0.6001) * (x - 0.6013) * np.exp(x)

    assert not np.any(np.diff(np.sign(f(GRID))))
    brackets, *_ = _brackets_of(f)
    np.testing.assert_allclose(_zeros(f, brackets), [0.6001, 0.6013], rtol=0, atol=TOL_SYNTH)


def test_refined_scan_finds_a_root_beside_a_zero_the_measure_does_not_see():
    """The determinant's case: a root (where the measure, like the singularity ratio,
    vanishes) beside a spurious zero of f (a weight factor, which the measure does not
    see) in one grid interval; both sign changes are bracketed."""
    def f(x):
        return (x - 0.7002) * (x - 0.7049)

    assert not np.any(np.diff(np.sign(f(GRID))))
    brackets, *_ = _brackets_of(f, lambda x: np.abs(x - 0.7002))
    np.testing.assert_allclose(_zeros(f, brackets), [0.7002, 0.7049], rtol=0, atol=TOL_SYNTH)


def test_refined_scan_locates_a_double_root_but_brackets_none():
    """A tangency f = (x - 0.7)^2 (x + 1): the refinement samples it to the width
    W_SCAN (|f| never resolves there) but f does not change sign: no bracket, no root."""
    def f(x):
        return (x - 0.7) ** 2 * (x + 1)

    brackets, x, _, _ = _brackets_of(f)
    assert brackets == []
    assert np.min(np.abs(x - 0.7)) <= WIDTH * 0.7


def test_refined_scan_brackets_a_root_at_a_grid_point():
    """f vanishes exactly at a grid point: both intervals beside it are brackets whose
    end is that point, and the zero is the grid point itself."""
    x0 = GRID[17]

    def f(x):
        return (x - x0) * (2.0 - x)

    brackets, *_ = _brackets_of(f)
    assert brackets and all(x0 in (a, b) for a, b, *_ in brackets)
    assert set(_zeros(f, brackets)) == {x0}


def test_refined_scan_adds_no_root_at_a_minimum_away_from_zero():
    """|f| has a sharp minimum 1e-8 above zero (a near miss): the refinement resolves
    it (neighbours within RESOLVED of it) after a few halvings, with no bracket."""
    def f(x):
        return (x - 0.7) ** 2 + 1e-8

    brackets, x, *_ = _brackets_of(f)
    assert brackets == [] and x.size > GRID.size
    # resolved once the spacing is ~sqrt(RESOLVED 1e-8) = 5e-5: far above W_SCAN
    assert np.min(np.abs(np.diff(x))) > 1e3 * WIDTH


#: rows of one grid for grid_brackets: (f, its zeros on the GRID window)
GRID_ROWS = (
    (lambda x: (x - 0.6001) * (x - 0.6013) * np.exp(x), [0.6001, 0.6013]),   # a pair
    (lambda x: (x - 0.55) * (x - 0.6001) * (x - 0.6013), [0.55, 0.6001, 0.6013]),
    (lambda x: x - 0.71, [0.71]),                                             # simple
    (lambda x: (x - GRID[17]) * (2.0 - x), [GRID[17]]),                       # at a point
    (lambda x: (x - 0.7) ** 2 + 1e-8, []),                                    # near miss
    (lambda x: (x - 0.7) ** 2 * (x + 1), []),                                 # tangency
    (lambda x: np.cos(40 * x) + 2.0, []),                                     # no minimum
)


def test_grid_brackets_finds_every_zero_of_every_row_and_refines_only_where_needed():
    """Many functions on one grid: every zero bracketed once (a pair inside one interval
    separated), and only the rows with a minimum of |f| between samples of one sign
    evaluated again (the pair rows, the near miss, the tangency, not the simple zeros)."""
    fs = [f for f, _ in GRID_ROWS]
    called = set()

    def evaluate(rows, x):
        called.update(int(r) for r in rows)
        return np.array([fs[r](p) for r, p in zip(rows, x, strict=True)])

    vals = np.array([f(GRID) for f in fs])
    scan, a, b, fa, fb = grid_brackets(evaluate, GRID, vals, width=WIDTH)
    for r, (f, zeros) in enumerate(GRID_ROWS):
        sel = scan == r
        got = _zeros(f, list(zip(a[sel], b[sel], fa[sel], fb[sel], strict=True)))
        got = sorted(set(got))
        np.testing.assert_allclose(got, zeros, rtol=0, atol=TOL_SYNTH)
    assert called == {0, 1, 4, 5}
    assert np.all(np.diff(scan) >= 0)


def test_grid_brackets_refuses_bad_arguments_naming_them():
    with pytest.raises(ValueError, match="f must have shape"):
        grid_brackets(lambda r, x: x, GRID, np.zeros(GRID.size), width=WIDTH)
    with pytest.raises(ValueError, match="usable"):
        grid_brackets(lambda r, x: x, GRID, np.zeros((2, GRID.size)), width=WIDTH,
                      usable=np.ones((2, 3), bool))
    with pytest.raises(TypeError, match="evaluate"):
        grid_brackets(None, GRID, np.zeros((2, GRID.size)), width=WIDTH)


# ------------------------------------------------------------------ convergence fits
H5 = np.array([3.0, 2.0, 1.4, 1.0, 0.7])
#: (name, levels, values, limit, order): exact power laws at several rates and signs, and
#: sequences with a higher-order term (1-4 % of the leading one at the coarsest level)
FIT_PROBLEMS = [
    ("h^2", H5, 1.0 + 0.1 * H5**2, 1.0, 2.0),
    ("h^1.2 decreasing", H5, 0.22 - 0.004 * H5**1.2, 0.22, 1.2),
    ("h^1.7 + 1 % h^3", H5, 0.5 + 0.2 * H5**1.7 + 0.002 * H5**3, 0.5, 1.7),
    ("h^1.7 + 4 % h^3", H5, 0.5 + 0.2 * H5**1.7 + 0.008 * H5**3, 0.5, 1.7),
    ("h^4", H5, -3.0 + 1e-3 * H5**4, -3.0, 4.0),
]


def _fit_richardson(h, v, order):
    v_inf, _ = richardson(h, v)
    return v_inf, abs(v_inf - v[-1])          # the three-point fit: no redundancy


def _fit(fn):
    def run(h, v, order):
        out = fn(h, v, order)
        return out.v_inf, out.error
    return run


def _fit_gci(h, v, order):
    out = gci(h, v, order)
    return out.v_inf, out.gci


FIT_METHODS = {
    "richardson": _fit_richardson,
    "convergence_fit": _fit(lambda h, v, q: convergence_fit(h, v)),
    "convergence_fit (expected order)": _fit(lambda h, v, q: convergence_fit(h, v, q)),
    "asymptotic_fit": _fit(asymptotic_fit),
    "reference_fit": _fit(reference_fit),
    "level_fit": _fit(lambda h, v, q: level_fit(h, v)),
    "gci": _fit_gci,
}


@pytest.mark.parametrize("method", FIT_METHODS)
@pytest.mark.parametrize(("name", "h", "v", "limit", "order"), FIT_PROBLEMS,
                         ids=[p[0] for p in FIT_PROBLEMS])
def test_every_fit_bounds_the_error_of_its_limit(method, name, h, v, limit, order):
    """Each fit's limit lies within its own error estimate of the known limit (the GCI:
    within its band of the finest value's error), and on exact power laws the limit is
    recovered to well below the level differences (1e-6 of them)."""
    v_inf, err = FIT_METHODS[method](h, v, order)
    if method == "gci":
        assert abs(v[-1] - limit) <= err, (name, v_inf, err)
    else:
        assert abs(v_inf - limit) <= err + 1e-12, (name, v_inf, err)
    if "%" not in name:
        assert abs(v_inf - limit) <= 1e-6 * abs(v[-2] - v[-1]), (name, v_inf)


def test_richardson_recovers_the_rate_of_non_uniform_levels():
    h = np.array([3.0, 1.9, 1.1])
    v_inf, p = richardson(h, 2.0 + 0.3 * h**1.45)
    assert v_inf == pytest.approx(2.0, abs=1e-10) and p == pytest.approx(1.45, rel=1e-8)


@pytest.mark.parametrize("fit", [richardson, convergence_fit])
def test_free_rate_fits_refuse_a_non_monotone_sequence(fit):
    with pytest.raises(ConvergenceError):
        fit(np.array([3.0, 2.0, 1.4]), np.array([1.0, 1.2, 1.1]))


def test_level_fit_falls_back_to_the_finest_level_and_its_last_change():
    """Fewer than three levels: the finest value, its change from the previous level as
    the error (two levels) or NaN (one level); a non-monotone triple: the spread, or the
    fit's error when asked to raise."""
    two = level_fit([2.0, 1.0], [1.3, 1.1])
    assert (two.v_inf, two.error) == (1.1, pytest.approx(0.2)) and math.isnan(two.p)
    one = level_fit([1.0], [1.1])
    assert one.v_inf == 1.1 and math.isnan(one.error)
    bumpy = level_fit([3.0, 2.0, 1.4], [1.0, 1.2, 1.1])
    assert bumpy.v_inf == 1.1 and bumpy.error == pytest.approx(0.1)
    with pytest.raises(ConvergenceError):
        level_fit([3.0, 2.0, 1.4], [1.0, 1.2, 1.1], spread_if_not_monotone=False)


def test_gci_takes_the_observed_order_with_safety_1_25_when_it_matches_the_theory():
    """Roache: three levels whose observed order is the theoretical one (or no theory
    given): Fs = 1.25 with the observed order; GCI = Fs |v1 - v2| / (r^p - 1)."""
    h = np.array([4.0, 2.0, 1.0])
    v = 1.0 + 0.1 * h**2
    for theory in (None, 2.0, 2.2):
        out = gci(h, v, theory)
        assert out.safety == GCI_SAFETY_OBSERVED == 1.25
        assert out.p == pytest.approx(2.0) and out.p_observed == pytest.approx(2.0)
        assert out.gci == pytest.approx(1.25 * 0.3 / 3.0)
        assert out.v_inf == pytest.approx(1.0) and out.gci_relative == pytest.approx(
            out.gci / 1.1)


def test_gci_uses_the_theoretical_order_with_safety_3_otherwise():
    """An observed order off the theoretical one, a non-monotone triple and two levels:
    Fs = 3 with the theoretical order; without a theoretical order no GCI (raises)."""
    h = np.array([4.0, 2.0, 1.0])
    off = gci(h, 1.0 + 0.1 * h**2, 1.0)
    assert off.safety == GCI_SAFETY_THEORETICAL == 3.0 and off.p == 1.0
    assert off.gci == pytest.approx(3.0 * 0.3 / 1.0) and "off" in off.reason
    bumpy = gci(h, np.array([1.0, 1.2, 1.1]), 2.0)
    assert bumpy.safety == 3.0 and math.isnan(bumpy.p_observed)
    two = gci(h[1:], np.array([1.4, 1.1]), 2.0)
    assert two.safety == 3.0 and two.gci == pytest.approx(3.0 * 0.3 / 3.0)
    with pytest.raises(ConvergenceError, match="no order"):
        gci(h[1:], np.array([1.4, 1.1]))
    with pytest.raises(ValueError, match="decreasing"):
        gci(h[::-1], np.array([1.0, 1.1, 1.2]), 2.0)


#: levels of the 3D model's in-plane sequence (h / t0), on which the two-term fits run
TWO_TERM_H = np.array([3.0, 2.0, 1.4, 1.0, 0.7, 0.45])


@pytest.mark.parametrize("q", SECOND_EXPONENTS)
def test_two_term_limits_recover_a_two_term_sequence_at_its_own_exponent(q):
    """A sequence v + C1 h^1.2 + C2 h^q: the fit with that second exponent q returns v
    (plus the correction) to round-off, every other exponent misses it by far more."""
    v = 0.22 + 0.01 * TWO_TERM_H**1.2 - 0.002 * TWO_TERM_H**q
    fits = two_term_limits(TWO_TERM_H, v, 1.2, -1e-4)
    assert list(fits) == list(SECOND_EXPONENTS)
    # lstsq round-off: condition number of the 4 x 3 design matrix (< 100 here) x eps x |v|
    assert fits[q] == pytest.approx(0.22 - 1e-4, abs=100 * EPS)
    assert all(abs(fits[p] - (0.22 - 1e-4)) > 1e-6 for p in SECOND_EXPONENTS if p != q)


def test_two_term_limits_refuse_too_few_or_mismatched_levels():
    with pytest.raises(ValueError, match="at least 4 levels"):
        two_term_limits(TWO_TERM_H[:3], TWO_TERM_H[:3], 1.2)
    with pytest.raises(ValueError, match="one length"):
        two_term_limits(TWO_TERM_H, TWO_TERM_H[:5], 1.2)


# ---------------------------------------------------------- p- and grading-sequences
#: a plan of three orders at the finest grading and a coarser grading at the top order
PG_PLAN = ((2, 6), (3, 6), (4, 6), (4, 4))


@pytest.mark.parametrize("h", [[0.4, 0.2, 0.1, 0.05], [3.0, 1.7, 1.1]])
@pytest.mark.parametrize("order", [-2.0, 1.0, 2.5])
def test_loglog_order_recovers_the_order_of_a_power_law(h, order):
    """On exact power laws ``e = C h^p`` (either sign of C) the slope and intercept are
    exact to round-off."""
    h = np.asarray(h)
    for c in (3.0, -0.02):
        fit = loglog_order(h, c * h**order)
        # 1e-12: the least-squares slope of exact data, round-off of logs of O(1) numbers
        assert fit.order == pytest.approx(order, abs=1e-12)
        assert fit.intercept == pytest.approx(math.log(abs(c)), abs=1e-12)


@pytest.mark.parametrize(("h", "e", "named"), [
    ([0.1], [1e-3], "h and e"), ([0.1, 0.2], [1e-3], "h and e"),
    ([0.1, -0.2], [1e-3, 2e-3], "h must"), ([0.1, 0.1], [1e-3, 2e-3], "distinct"),
    ([0.1, 0.2], [0.0, 2e-3], "e must"), ([0.1, 0.2], [np.nan, 2e-3], "e must"),
    ([0.1, np.inf], [1e-3, 2e-3], "h must")])
def test_loglog_order_refuses_what_it_cannot_fit(h, e, named):
    with pytest.raises(ValueError, match=named):
        loglog_order(h, e)


def test_p_grading_estimate_takes_the_top_discretisation_and_both_changes():
    """Exponential p-convergence 1e-3 * 10^-p plus a grading term: the value is the top
    (order 4, 6 layers) entry, the changes are exactly the two differences, and the safety
    factor is 1.25 (three orders at 6 layers)."""
    vals = {(2, 6): 1.0 + 1e-5, (3, 6): 1.0 + 1e-6, (4, 6): 1.0 + 1e-7, (4, 4): 1.0 + 3e-7}
    x = np.array([vals[d] for d in PG_PLAN])
    got = p_grading_estimate(x, PG_PLAN)
    assert got.value == x[PG_PLAN.index((4, 6))]
    # the differences of numbers near 1: exact to a few ulps of 1
    assert got.p_change == pytest.approx(9e-7, abs=1e-15)
    assert got.grading_change == pytest.approx(2e-7, abs=1e-15)
    assert p_grading_safety(PG_PLAN) == got.safety_factor == 1.25
    assert got.error == pytest.approx(1.25 * 9e-7, abs=1e-15)


def test_p_grading_estimate_with_two_orders_uses_the_larger_safety_factor():
    discs = ((2, 3), (3, 3), (3, 2))
    assert p_grading_safety(discs) == 3.0
    got = p_grading_estimate(np.array([2.0, 1.0, 1.5]), discs)
    assert got.value == 1.0 and got.error == 3.0 * 1.0


def test_p_grading_estimate_is_nan_where_a_discretisation_has_no_value():
    """A crossing found on some discretisations only has no error estimate."""
    x = np.array([[1.0, 1.1, 1.2, 1.3], [np.nan, 1.0, 1.0, 1.0]])
    got = p_grading_estimate(x, PG_PLAN)
    assert np.isfinite(got.error[0])
    assert np.isfinite(got.error[1])      # the NaN is at order 2, not used
    x[1, 1] = np.nan
    assert np.isnan(p_grading_estimate(x, PG_PLAN).error[1])


def test_p_grading_estimate_has_its_floor_and_refuses_what_it_cannot_judge():
    """A sequence that does not change has the floor as its error estimate; a plan without
    a lower order at the top grading, values that do not match the plan and a negative
    floor raise ValueError."""
    flat = p_grading_estimate(np.full(4, 0.5), PG_PLAN, floor=2e-7)
    assert flat.error == 2e-7 and flat.p_change == 0.0 and flat.grading_change == 0.0
    with pytest.raises(ValueError, match="no lower order"):
        p_grading_estimate(np.ones(2), ((3, 4), (3, 6)))
    with pytest.raises(ValueError, match="last axis"):
        p_grading_estimate(np.ones(3), PG_PLAN)
    with pytest.raises(ValueError, match="floor"):
        p_grading_estimate(np.ones(4), PG_PLAN, floor=-1.0)


SCIPY_ROOT_FINDERS = {"brentq", "brenth", "ridder", "bisect", "toms748", "root_scalar"}


def test_scipy_scalar_root_finders_are_called_only_in_numerics():
    """One home for root finding: outside ``debench.models.numerics`` no module of the
    package imports or calls SciPy's scalar root finders (they are reached through
    :mod:`debench.models.numerics.roots`, whose results and failures are uniform)."""
    import ast
    import pathlib

    import debench.models
    import debench.models.numerics
    import debench.reference

    import debench

    packages = {pathlib.Path(m.__file__).parent
                for m in (debench, debench.models, debench.reference)}
    numerics = pathlib.Path(debench.models.numerics.__file__).parent
    found = []
    for path in sorted({p for pkg in packages for p in pkg.rglob("*.py")}):
        if numerics in path.parents:
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            names = ([a.name for a in node.names] if isinstance(node, ast.ImportFrom)
                     and node.module and node.module.startswith("scipy.optimize") else
                     [node.attr] if isinstance(node, ast.Attribute) else [])
            found += [f"{path.name}:{node.lineno} {n}" for n in names
                      if n in SCIPY_ROOT_FINDERS]
    assert not found, found


# ------------------------------------------------------------------ continuation steps
def _steep_solution(w):
    """The solution y*(w) = 10 tanh(5 (w - 1)) of the synthetic path: flat, then a slope of
    50 around w = 1 where only short steps keep the predictor in Newton's basin."""
    return 10.0 * math.tanh(5.0 * (w - 1.0))


def _newton_on_arctan(y, w):
    """Newton on arctan(y - y*(w)) = 0 from ``y``: (root, iterations); it converges from
    |y - y*| < 1.39 (Newton's basin for arctan) and diverges from further."""
    for its in range(31):
        e = y - _steep_solution(w)
        if abs(e) < 1e-12:
            return y, its
        y -= (1.0 + e * e) * math.atan(e)
        if not abs(y) < 1e6:
            break
    raise ConvergenceError(f"Newton diverged at w = {w}")


def _follow(control, w_end=2.0):
    """A path from w = 0 to ``w_end`` (the last solution the predictor of the next step):
    (steps taken, steps failed, largest step taken)."""
    w, y, fails, taken = 0.0, _steep_solution(0.0), 0, []
    while w < w_end:
        target = min(w + control.size, w_end)
        try:
            y_new, its = _newton_on_arctan(y, target)
        except ConvergenceError:
            fails += 1
            if not control.failed():
                raise
            continue
        taken.append(target - w)
        w, y = target, y_new
        control.converged(its)
    return len(taken), fails, max(taken)


@pytest.mark.parametrize("regrow_after", [None, 4])
def test_step_control_follows_a_steep_path_within_its_bounds(regrow_after):
    """Both policies reach the end of a path whose slope jumps to 50, never step above
    ``max_size``, and the cautious regrowth fails fewer steps near the steep part than
    plain doubling (measured: 4 and 7 failed steps of 35 and 32 solves)."""
    control = StepControl(0.05, 0.5, min_size=1e-6, regrow_after=regrow_after)
    steps, fails, largest = _follow(control)
    assert largest <= 0.5
    assert 0 < fails <= steps
    if regrow_after is not None:
        assert fails < _follow(StepControl(0.05, 0.5, min_size=1e-6))[1]


def test_step_control_grows_easy_steps_to_the_cap_and_halves_failed_ones_exactly():
    """The exact sequence: easy steps grow by ``grow`` to ``max_size``, hard ones keep
    the size, a failure halves it (exactly), and the cap stays at ``max_size``."""
    c = StepControl(0.1, 0.5, grow=2.0, easy_iterations=4)
    seen = [c.size]
    for its in (2, 3, 9, 1, 1):
        c.converged(its)
        seen.append(c.size)
    assert seen == [0.1, 0.2, 0.4, 0.4, 0.5, 0.5]
    assert c.failed() and c.size == 0.25 and c.cap == 0.5
    c = StepControl(0.3, 0.3, grow=1.5, easy_iterations=None)
    c.failed()
    c.converged(100)       # every converged step is easy
    assert c.size == min(0.15 * 1.5, 0.3)


def test_cautious_regrowth_keeps_a_failed_size_until_enough_easy_steps():
    """After a failure the cap is the halved step; it doubles only after ``regrow_after``
    easy steps in a row (a hard step restarts the count)."""
    c = StepControl(0.4, 1.6, grow=2.0, regrow_after=3)
    c.failed()
    assert (c.size, c.cap) == (0.2, 0.2)
    sizes = []
    for its in (1, 1, 9, 1, 1, 1, 1):
        c.converged(its)
        sizes.append((c.size, c.cap))
    # the third easy step in a row doubles the cap, and the size with it; the next one
    # cannot pass the cap
    assert sizes == [(0.2, 0.2)] * 5 + [(0.4, 0.4), (0.4, 0.4)]


def test_step_control_refuses_to_halve_below_its_minimum():
    """``failed`` says False once the halved step lies below the minimum (its own or the
    one given for this failure)."""
    c = StepControl(1.0, 1.0, min_size=0.3)
    assert c.failed() and c.size == 0.5
    assert not c.failed() and c.size == 0.25
    c = StepControl(1.0, 1.0)
    assert c.failed(min_size=0.5) and not c.failed(min_size=0.5)


@pytest.mark.parametrize(("kwargs", "named"), [
    ({"size": 0.0, "max_size": 1.0}, "size"),
    ({"size": math.nan, "max_size": 1.0}, "size"),
    ({"size": 2.0, "max_size": 1.0}, "max_size"),
    ({"size": 0.1, "max_size": 1.0, "grow": 1.0}, "grow"),
    ({"size": 0.1, "max_size": 1.0, "easy_iterations": 0}, "easy_iterations"),
    ({"size": 0.1, "max_size": 1.0, "min_size": -1.0}, "min_size"),
    ({"size": 0.1, "max_size": 1.0, "regrow_after": 0}, "regrow_after"),
])
def test_step_control_refuses_bad_arguments_naming_them(kwargs, named):
    with pytest.raises(ValueError, match=named):
        StepControl(**kwargs)


# ------------------------------------------------------------------ Newton


def _quadratic_system(a=0.5):
    """R(x) = (x0^2 + x1 - 1 - a, x0 - x1^3 + ... ) with the known root x = (1, a): a
    small nonlinear system whose state the driver's callbacks own."""
    root = np.array([1.0, a])
    state = {"x": np.array([3.0, -2.0])}

    def R(x):
        return np.array([x[0] ** 2 + x[1] - 1.0 - a, x[0] * x[1] - a + (x[1] - a) ** 3])

    def J(x):
        return np.array([[2 * x[0], 1.0], [x[1], x[0] + 3 * (x[1] - a) ** 2]])

    def residual():
        return float(np.linalg.norm(R(state["x"])))

    def correction():
        return np.linalg.solve(J(state["x"]), R(state["x"]))

    def move(du, s):
        state["x"] = state["x"] - s * du

    return state, root, residual, correction, move


def test_damped_newton_converges_to_the_policy_and_reports_it():
    """From a far start the backtracking driver reaches the known root; it stops at the
    policy's relative residual RTOL (the history decreasing) and says so."""
    state, root, residual, correction, move = _quadratic_system()
    res = damped_newton(residual, correction, move, what="test system")
    assert res.reason == "relative residual"
    assert res.residual == res.history[-1] <= newton.RTOL * res.reference
    assert all(b < a for a, b in zip(res.history, res.history[1:], strict=False))
    # the root to the conditioning of the system (J ~ O(1)) times the residual reached
    np.testing.assert_allclose(state["x"], root, rtol=0, atol=1e-10)


def test_damped_newton_raises_naming_the_problem_when_it_cannot_converge():
    """A residual without a root (x^2 + 1) makes no progress: ConvergenceError naming the
    problem, never a silent return; maxit = 1 on a solvable system raises too."""
    x = {"v": np.array([0.3])}
    with pytest.raises(ConvergenceError, match="no root here"):
        damped_newton(lambda: float(abs(x["v"][0] ** 2 + 1.0)),
                      lambda: np.array([(x["v"][0] ** 2 + 1.0) / (2 * x["v"][0])]),
                      lambda du, s: x.__setitem__("v", x["v"] - s * du),
                      what="no root here")
    state, root, residual, correction, move = _quadratic_system()
    with pytest.raises(ConvergenceError, match="did not reach"):
        damped_newton(residual, correction, move, maxit=1)
    for kwargs, name in (({"rtol": math.inf}, "rtol"), ({"maxit": 0}, "maxit"),
                         ({"atol": -1.0}, "atol"), ({"halvings": -1}, "halvings")):
        with pytest.raises(ValueError, match=name):
            damped_newton(residual, correction, move, **kwargs)


def test_bordered_solve_equals_the_dense_bordered_system_and_survives_a_singular_block():
    """Block elimination gives the solution of the whole bordered matrix (random
    well-conditioned K to 1e-12); with K singular along the border's direction (the
    voltage maximum) and refinement it still does (the bordered matrix is regular); a
    border that misses the singular direction raises ConvergenceError."""
    rng = np.random.default_rng(7)
    n = 12
    A = rng.standard_normal((n, n))
    K = A @ A.T + n * np.eye(n)
    col, row, rhs = rng.standard_normal(n), rng.standard_normal(n), rng.standard_normal(n)
    B = np.block([[K, col[:, None]], [row[None, :], np.zeros((1, 1))]])
    want = np.linalg.solve(B, np.append(rhs, 0.7))
    dx, dl = bordered_solve(lambda b: np.linalg.solve(K, b), col, row, rhs, 0.7)
    np.testing.assert_allclose(np.append(dx, dl), want, rtol=1e-12, atol=1e-12)
    # nearly singular K (one eigenvalue 1e-10 along q), border along q: regular B
    q = np.linalg.qr(rng.standard_normal((n, n)))[0]
    ev = np.linspace(1.0, 5.0, n)
    ev[0] = 1e-10
    Ks = (q * ev) @ q.T
    B = np.block([[Ks, q[:, :1]], [q[:, 0][None, :], np.zeros((1, 1))]])
    want = np.linalg.solve(B, np.append(rhs, 0.3))
    dx, dl = bordered_solve(lambda b: np.linalg.solve(Ks, b), q[:, 0], q[:, 0], rhs, 0.3,
                            apply=Ks.__matmul__, refinements=4, rtol=1e-14)
    # 1e-8: the elimination works through K^-1 of condition 5e10, which refinement
    # brings back to the bordered matrix's own conditioning (O(10)) times eps
    np.testing.assert_allclose(np.append(dx, dl), want, rtol=0, atol=1e-8)
    with pytest.raises(ConvergenceError, match="singular border"):
        bordered_solve(lambda b: np.zeros_like(b), col, row, rhs, 0.0, what="the test")
    with pytest.raises(ValueError, match="apply"):
        bordered_solve(lambda b: b, col, row, rhs, 0.0, refinements=1)


def test_round_off_floor_and_residual_test_follow_the_policy():
    """The floor is FLOOR_FACTOR eps || |K| |x| || over the given rows; the residual test
    names why it accepts, and refuses above both bounds."""
    K = np.array([[2.0, -1.0], [-1.0, 4.0]])
    x = np.array([1.0, -3.0])
    want = newton.FLOOR_FACTOR * np.finfo(float).eps * np.linalg.norm(np.abs(K) @ np.abs(x))
    assert round_off_floor(np.abs(K), np.abs(x)) == pytest.approx(want, rel=1e-15)
    assert round_off_floor(np.abs(K), np.abs(x), np.array([False, True])) == pytest.approx(
        newton.FLOOR_FACTOR * np.finfo(float).eps * 13.0, rel=1e-15)
    assert residual_converged(1e-12, 1.0) == "relative residual"
    assert residual_converged(1e-9, 1.0, floor=1e-8) == "floor"
    assert residual_converged(1e-9, 1.0, floor=1e-10) is None


def test_newton_tolerances_are_defined_only_in_numerics():
    """One Newton policy: no module of the package outside ``debench.models.numerics``
    assigns a name NEWTON_RTOL, NEWTON_FLOOR_FACTOR or *_RTOL used as Newton's relative
    residual tolerance; the models import :data:`debench.models.numerics.newton.RTOL`."""
    import ast
    import pathlib

    import debench.models
    import debench.models.numerics

    root = pathlib.Path(debench.models.__file__).parent
    numerics = pathlib.Path(debench.models.numerics.__file__).parent
    found = []
    for path in sorted(root.rglob("*.py")):
        if numerics in path.parents:
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Assign):
                found += [f"{path.name}:{node.lineno} {t.id}" for t in node.targets
                          if isinstance(t, ast.Name)
                          and t.id in {"NEWTON_RTOL", "NEWTON_FLOOR_FACTOR"}]
    assert not found, found


def test_secant_step_and_inverse_quadratic_root_are_exact_where_they_should_be():
    """The secant step is exact for a linear f, the inverse quadratic root for an x(f)
    quadratic; a flat secant, a step leaving its bounds and repeated values raise
    ConvergenceError naming the caller."""
    assert roots.secant_step(1.0, -2.0, 3.0, 2.0) == 2.0
    with pytest.raises(ConvergenceError, match="my secant: flat"):
        roots.secant_step(1.0, 0.5, 2.0, 0.5, what="my secant")
    with pytest.raises(ConvergenceError, match="leaves"):
        roots.secant_step(1.0, 1.0, 2.0, 0.5, bounds=(0.0, 2.5))

    def x_of(f):
        return 1.25 - 0.5 * f + 0.75 * f**2

    fs = [-0.4, 0.1, 0.9]
    xs = [x_of(f) for f in fs]
    assert roots.inverse_quadratic_root(xs, fs) == pytest.approx(1.25, rel=4e-16, abs=0)
    with pytest.raises(ConvergenceError, match="repeated"):
        roots.inverse_quadratic_root([0.0, 1.0, 2.0], [1.0, 1.0, 2.0])


def test_secant_zero_answers_with_an_evaluated_point_of_every_function_in_the_collection():
    """secant_zero from two points about each root of the synthetic collection (bracketed:
    Illinois) and from two points on one side (the secant): the answer is an evaluated
    point within its stated tolerance of the root (a last step below xtol, or a bracket
    narrower than stall_width), every evaluation appended."""
    for f, root in ((lambda x: x**3 - 2.0, 2.0 ** (1 / 3)),
                    (lambda x: math.exp(x) - 3.0, math.log(3.0)),
                    (lambda x: math.atan(x - 0.4), 0.4)):
        for x0, x1 in ((root - 0.3, root + 0.2), (root + 0.05, root + 0.1)):
            xs, fs = [x0, x1], [f(x0), f(x1)]
            k, tol = secants.secant_zero(f, xs, fs, xtol=1e-10, stall_width=1e-8)
            assert fs[k] == f(xs[k]) and len(xs) == len(fs) > 2
            # the stated tolerance: the bracket's width, or the last step (10 x: a step
            # bounds the error of a superlinear iteration to a small factor)
            assert tol < 1e-8 and abs(xs[k] - root) <= 10 * tol
