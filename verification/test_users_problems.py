"""Reference problems as data: specs load, state their accuracy, and the stated accuracy
holds (re-measured here, fast; the full measurement is slow)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from debench.reference import problems, problems_reference
from debench.reference.datasets import data_dir, read_manifest

#: the discretisation error of ch3_voltage_stretch is measured against this many RK4
#: steps (8x the dataset's 200; the error is O(h^4), so the 1600-step error is ~4000x
#: smaller and the difference is the 200-step error to 0.03 %)
CH3_FINE_STEPS = 1600
#: digits of the independent evaluation of the free-membrane closed form
MPMATH_DIGITS = 40


def test_every_chapter_with_data_has_a_problem():
    """One problem per chapter with curated data (2, 3, 4, 5), each from a listed dataset
    or a closed form."""
    loaded = problems.load_all()
    assert {p.chapter for p in loaded} >= {2, 3, 4, 5}
    manifest = read_manifest(data_dir())
    for p in loaded:
        for name in p.datasets:
            assert f"{name}.nc" in manifest, (p.id, name)


@pytest.mark.parametrize("problem", problems.load_all(), ids=lambda p: p.id)
def test_problem_states_spec_and_accuracy(problem):
    """Parameters carry units; every quantity states solver accuracy and discretisation
    error with reasons, and its reference values load (verified read)."""
    assert problem.geometry and problem.boundary_conditions and problem.loading
    for name, par in problem.parameters.items():
        assert "value" in par and "units" in par and par.get("description"), name
    blob = problems_reference.reference_json(problem)
    json.dumps(blob)  # plain data, NaN as null
    for q in problem.quantities:
        acc = q.accuracy
        assert acc.reason and acc.discretisation_reason
        assert acc.rtol > 0 or acc.atol > 0
        ref = blob["reference"][q.name]
        assert ref["units"] == q.units
        values = np.array(ref["values"], dtype=float)
        assert np.isfinite(values).any()


def test_malformed_spec_is_rejected(tmp_path):
    """A quantity without a stated discretisation error is refused."""
    src = (problems.PROBLEMS_DIR / "ch5_critical_voltage.toml").read_text()
    bad = tmp_path / "ch5_critical_voltage.toml"
    bad.write_text(src.replace("discretisation = ", "not_a_field_discretisation = "))
    with pytest.raises(problems.ProblemError, match="discretisation"):
        problems.load_file(bad)


def test_off_grid_selector_and_out_of_range_abscissa_are_rejected():
    p = problems.get("ch3_voltage_stretch")
    q = p.quantity("phibar")
    with pytest.raises(ValueError, match="lamP = 1.3 is not on the reference grid"):
        problems_reference.reference_at(p, q, {"lamP": 1.3, "c": 0.0, "lambda_a": [2.0]})
    with pytest.raises(ValueError, match="lamP = 2, c = 0: lambda_a must lie in the "
                                         "reference range"):
        problems_reference.reference_at(p, q, {"lamP": 2.0, "c": 0.0, "lambda_a": [1.5]})


def test_free_membrane_closed_form_meets_stated_accuracy():
    """The closed form Phibar = sqrt(lam^-2 - lam^-8) (Eq. 3.30, T1B = 0, Zhao & Suo
    2007) against a 40-digit evaluation: inside the stated accuracy, by >= 10x."""
    mpmath = pytest.importorskip("mpmath")
    p = problems.get("ch3_free_membrane_nh")
    q = p.quantity()
    lam = np.linspace(1.0, 5.0, 401)[1:]
    ref = problems_reference.reference_at(p, q, {"lam": lam})
    mpmath.mp.dps = MPMATH_DIGITS
    exact = np.array([float(mpmath.sqrt(mpmath.mpf(x) ** -2 - mpmath.mpf(x) ** -8))
                      for x in lam])
    assert np.all(np.abs(ref.value - exact) <= 0.1 * ref.tolerance)


#: annulus equilibrium of each Chapter 3 voltage-stretch problem
CH3_EQUILIBRIUM = {"ch3_voltage_stretch": "membrane", "ch3_voltage_stretch_as_printed": "printed"}


def _ch3_fine_errors(problem_id, lamPs, cs):
    from debench.models.circular import circle_a, params
    from debench.models.circular.actuator import branch
    from debench.models.circular.params import Annulus
    from debench.reference.datasets import read_dataset

    prob = problems.get(problem_id)
    ds = read_dataset(prob.quantity().dataset)
    radius = prob.parameters["radius_ratio"]["value"]
    worst = 0.0
    for lamP in lamPs:
        lam = ds.lambda_a.sel(lamP=lamP).values
        lam = lam[np.isfinite(lam)][:-1]  # the last point sits on the admissible end
        br = branch(Annulus(float(lamP), radius, equilibrium=CH3_EQUILIBRIUM[problem_id]),
                    lam=lam, steps=CH3_FINE_STEPS)
        for c in cs:
            stored = ds.phibar.sel(lamP=lamP, c=c).values[:lam.size]
            p2 = circle_a.phibar_squared_where_defined(br.lam, br.T1, float(c),
                                                       1.0 / params.JM_VHB)
            fine = np.sqrt(np.where(p2 >= 0, p2, np.nan))
            worst = max(worst, float(np.nanmax(np.abs(fine - stored))))
    return worst


#: the pre-stretch of the largest measured RK4 error of each problem (all lamP and c)
CH3_WORST_LAMP = {"ch3_voltage_stretch": 4.0, "ch3_voltage_stretch_as_printed": 3.0}


@pytest.mark.parametrize("problem_id", sorted(CH3_EQUILIBRIUM))
def test_ch3_discretisation_error_is_within_stated_bound_fast(problem_id):
    """Stored Phibar (200 RK4 steps) against 1600 steps at the measured worst pre-stretch,
    three values of c: within the stated discretisation error."""
    stated = problems.get(problem_id).quantity().accuracy.discretisation
    worst = _ch3_fine_errors(problem_id, [CH3_WORST_LAMP[problem_id]], [0.0, -0.053, -0.06])
    assert 0 < worst <= stated


@pytest.mark.slow
@pytest.mark.parametrize("problem_id", sorted(CH3_EQUILIBRIUM))
def test_ch3_discretisation_error_is_within_stated_bound_everywhere(problem_id):
    """Every stored pre-stretch and c (the measurement the spec quotes)."""
    from debench.reference.datasets import read_dataset

    ds = read_dataset(problems.get(problem_id).quantity().dataset)
    stated = problems.get(problem_id).quantity().accuracy.discretisation
    assert _ch3_fine_errors(problem_id, ds.lamP.values, ds.c.values) <= stated
