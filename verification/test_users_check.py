"""Checking one's own results: the Python API, the pytest fixture and the README example
(run as written, and a perturbed copy that must fail)."""

from __future__ import annotations

import runpy
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from debench.reference import cli

from debench.testing import assert_matches, compare

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "free_membrane_nh.py"
#: at its own grid points the reference is returned through Phibar -> Phibar^2 -> Phibar
#: (interpolation in the square), exact to round-off: |error| / tolerance below 1e-3
#: (measured 6e-10)
SELF_RATIO = 1e-3
#: a 1e-4 relative perturbation of a reference curve: far above every stated accuracy of
#: the dataset-backed problems (<= 2e-6 absolute away from interpolation-limited points)
PERTURBATION = 1e-4


def _stored_curve(problem, quantity, **sel):
    """Reference values at the stored grid points (the reference itself)."""
    from debench.reference import problems
    from debench.reference.datasets import read_dataset

    q = problems.get(problem).quantity(quantity)
    ds = read_dataset(q.dataset)
    y = ds[q.variable].sel(sel)
    x = ds[q.along].sel({k: v for k, v in sel.items() if k in ds[q.along].dims})
    ok = np.isfinite(x.values) & np.isfinite(y.values)
    return x.values[ok], y.values[ok]


def test_reference_reproduces_itself_and_a_perturbation_fails():
    """At its own grid points the reference matches exactly; scaled by 1 + 1e-4 it fails
    with a table naming the worst points."""
    lam, phibar = _stored_curve("ch3_voltage_stretch", "phibar", lamP=2.0, c=-0.053)
    coords = {"lamP": 2.0, "c": -0.053, "lambda_a": lam}
    assert compare("ch3_voltage_stretch", "phibar", phibar, coords,
                   coverage="partial").ratio.max() < SELF_RATIO
    with pytest.raises(AssertionError, match=r"DOES NOT MATCH(.|\n)*lambda_a(.|\n)*\|err\|/tol"):
        assert_matches("ch3_voltage_stretch", "phibar", phibar * (1 + PERTURBATION), coords,
                       coverage="partial")


@pytest.mark.parametrize("problem, equilibrium", [("ch3_voltage_stretch", "membrane"),
                                                  ("ch3_voltage_stretch_as_printed",
                                                   "printed")])
def test_curve_interpolated_between_grid_points_matches_an_independent_solve(problem,
                                                                             equilibrium):
    """Phibar of the annulus-coupled actuator solved afresh (1600 RK4 steps) between the
    stored points matches the interpolated reference within its stated accuracy, for the
    consistent membrane balance (default) and the printed (3.33) (variant); each fails
    the other problem."""
    from debench.models.circular import circle_a, params
    from debench.models.circular.actuator import branch
    from debench.models.circular.params import Annulus

    lam = np.linspace(2.01, 4.0, 23)
    br = branch(Annulus(2.0, 15.0, equilibrium=equilibrium), lam=lam, steps=1600)
    phibar = np.sqrt(circle_a.phibar_squared(br.lam, br.T1, -0.053, 1.0 / params.JM_VHB))
    coords = {"lamP": 2.0, "c": -0.053, "lambda_a": lam}
    assert_matches(problem, "phibar", phibar, coords, coverage="partial")
    with pytest.raises(AssertionError):
        assert_matches(problem, "phibar", phibar * (1 + PERTURBATION), coords,
                       coverage="partial")
    other = ({"ch3_voltage_stretch", "ch3_voltage_stretch_as_printed"} - {problem}).pop()
    assert not compare(other, "phibar", phibar, coords, coverage="partial").passed


def test_scalar_quantity_uses_discretisation_error_from_the_dataset():
    """ch5: the tolerance is the reference's error estimate stated in the dataset
    (``v_cr_error`` of ch5_axisym: the GCI of its p- and grading-sequences)."""
    from debench.reference.datasets import read_dataset

    ds = read_dataset("ch5_axisym").sel(n=0)
    ref = ds.v_cr_converged.values
    gap = ds.v_cr_error.values
    coords = {"case": ds.case.values}
    ok = compare("ch5_critical_voltage", "v_cr", ref + 0.5 * gap, coords)
    assert ok.passed
    bad = compare("ch5_critical_voltage", "v_cr", ref + 1.5 * gap, coords)
    assert bad.failed.all()


def test_user_rtol_loosens_but_never_tightens_the_stated_accuracy():
    lam, phibar = _stored_curve("ch4_plate_critical_stretch", "lam_cr", variant="derived",
                                xi=5.0, Dhat=2.0, root=0)
    coords = {"xi": 5.0, "Dhat": 2.0, "kH": lam}
    off = phibar * (1 + PERTURBATION)
    part = {"coverage": "partial"}
    assert not compare("ch4_plate_critical_stretch", None, off, coords, **part).passed
    assert compare("ch4_plate_critical_stretch", None, off, coords, rtol=1e-3, **part).passed
    tight = compare("ch4_plate_critical_stretch", None, phibar, coords, rtol=0.0, **part)
    assert tight.passed and np.all(tight.tolerance > 0)
    with pytest.raises(ValueError, match="rtol must be finite and >= 0"):
        compare("ch4_plate_critical_stretch", None, phibar, coords, rtol=-1.0, **part)


def test_nan_values_fail():
    lam = np.linspace(1.1, 2.0, 5)
    vals = np.sqrt(lam**-2 - lam**-8)
    vals[2] = np.nan
    assert compare("ch3_free_membrane_nh", "phibar", vals, {"lam": lam},
                   coverage="partial").failed.sum() == 1


def test_pytest_fixture_is_registered_and_checks(debench_reference):
    """The ``pytest11`` entry point provides ``debench_reference``."""
    lam = np.linspace(1.0, 5.0, 401)
    phibar = np.sqrt(lam**-2 - lam**-8)
    debench_reference.assert_matches("ch3_free_membrane_nh", "phibar", phibar, {"lam": lam})
    with pytest.raises(AssertionError):
        debench_reference.assert_matches("ch3_free_membrane_nh", "phibar", 1.01 * phibar,
                                         {"lam": lam})


def test_readme_example_runs_as_written(tmp_path):
    """examples/free_membrane_nh.py: the user's solver matches; it writes the CSV that
    ``debench check`` accepts (exit 0)."""
    out = tmp_path / "out.csv"
    run = subprocess.run([sys.executable, str(EXAMPLE), str(out)], capture_output=True,
                         text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert "MATCHES" in run.stdout
    assert cli.main(["check", "ch3_free_membrane_nh", str(out)]) == 0


def test_readme_example_perturbed_fails(tmp_path):
    """The same script with the electrical stress 1 % too large must fail all three ways:
    the script's own check, the CLI (exit 1) and the API."""
    src = EXAMPLE.read_text()
    assert "phibar**2 * lam**4" in src
    bad = tmp_path / "perturbed.py"
    bad.write_text(src.replace("phibar**2 * lam**4", "1.01 * phibar**2 * lam**4"))
    run = subprocess.run([sys.executable, str(bad)], capture_output=True, text=True,
                         timeout=120)
    assert run.returncode != 0 and "DOES NOT MATCH" in run.stderr
    mod = runpy.run_path(str(bad), run_name="perturbed")
    with pytest.raises(AssertionError):
        assert_matches("ch3_free_membrane_nh", "phibar", mod["phibar"], {"lam": mod["lam"]})
    csv = tmp_path / "bad.csv"
    np.savetxt(csv, np.column_stack([mod["lam"], mod["phibar"]]), delimiter=",",
               header="lam [1],phibar [1]", comments="")
    assert cli.main(["check", "ch3_free_membrane_nh", str(csv)]) == 1


def test_readme_shows_the_example_as_it_runs():
    """The README's example block is the code of examples/free_membrane_nh.py (in order)."""
    readme = (ROOT / "README.md").read_text()
    marker = "<!-- example: examples/free_membrane_nh.py -->\n```python\n"
    assert marker in readme
    block = readme.split(marker, 1)[1].split("```", 1)[0]
    source = EXAMPLE.read_text()
    pos = 0
    for line in filter(None, block.splitlines()):
        pos = source.index(line, pos) + len(line)


def test_several_quantities_are_checked_each_against_its_own_reference():
    """A mapping quantity -> values checks each quantity of ch5_pullin against its own
    reference and stated accuracy; the failure message names the quantity that failed;
    a tolerance may be given per quantity; a mapping with a quantity named, or naming
    quantities that do not share their coordinates, is refused."""
    from debench.reference import problems, problems_reference

    p = problems.get("ch5_pullin")
    films = {"case": ["nh_r10", "ogden_r10"]}      # both films: full coverage
    ref = {q.name: problems_reference.reference_at(p, q, films) for q in p.quantities}
    half = {n: r.value + 0.5 * r.tolerance for n, r in ref.items()}
    ok = assert_matches("ch5_pullin", None, half, films)
    assert ok.quantities == ("v_pullin", "w_pullin") and ok.passed
    assert ok["w_pullin"].ratio.max() == pytest.approx(0.5)
    off = {**half, "w_pullin": ref["w_pullin"].value + 2.0 * ref["w_pullin"].tolerance}
    with pytest.raises(AssertionError, match=r"1 of 2 quantities failed \(w_pullin\)"):
        assert_matches("ch5_pullin", None, off, films)
    res = compare("ch5_pullin", None, off, films, rtol={"w_pullin": 1e-3})
    assert res.passed and res["v_pullin"].tolerance_source.startswith("stated")
    with pytest.raises(ValueError, match="quantity must be None"):
        compare("ch5_pullin", "v_pullin", half, films)
    with pytest.raises(ValueError, match="rtol names quantities"):
        compare("ch5_pullin", None, half, films, rtol={"v_cr": 1e-3})
    with pytest.raises(ValueError, match="do not share their coordinates"):
        compare("ch2_kernel_states", None, {"W": 1.0, "sigma": 1.0},
                {"material": "x", "state": "y"})


def test_several_quantities_error_names_the_quantity():
    """An off-grid selector with several quantities: the error names problem and quantity."""
    with pytest.raises(ValueError, match=r"ch5_pullin:v_pullin: coordinate case"):
        compare("ch5_pullin", None, {"v_pullin": 0.68, "w_pullin": 5.56},
                {"case": "ogden_r20"})
