"""The cross-check matrix: which implementation checked which, and how closely they agree.

Each :class:`CrossCheck` names a quantity computed by two implementations, the dataset
where both values are stored, the tolerance (a named constant of a producer or a test,
read from its source so it is never typed twice) and the test that asserts it. The
agreement is measured from the curated datasets when the matrix is built
(:func:`matrix`), never typed in. The report renders it (:func:`table`);
``verification/test_report.py`` checks that every referenced test exists and every
agreement is within its tolerance.
"""

from __future__ import annotations

import ast
import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from debench.reference.datasets import read_dataset

_ROOT = Path(__file__).resolve().parent.parent


@dataclass(frozen=True)
class CrossCheck:
    """One pair of implementations of one quantity.

    Attributes
    ----------
    chapter, quantity
        Where and what.
    a, b
        The two implementations.
    dataset
        The curated dataset that stores both values.
    measure
        ``f(dataset) -> float``: the measured absolute difference (``max |a - b|``).
    tolerance
        ``"<repository path>::<CONSTANT>"`` (a float, or a dict entry ``CONSTANT[key]``);
        ``None`` for a pair expected to differ (a diagnosis, not an agreement).
    test
        ``"<repository path>::<test function>"`` that asserts the agreement.
    """

    chapter: str
    quantity: str
    a: str
    b: str
    dataset: str
    measure: Callable
    tolerance: str | None
    test: str

    def measured(self, data_dir: Path | None = None) -> float:
        return float(self.measure(read_dataset(self.dataset, data_dir=data_dir)))

    def tolerance_value(self) -> float | None:
        return None if self.tolerance is None else constant(self.tolerance)


def constant(ref: str) -> float:
    """The value of a module-level constant ``path::NAME`` or ``path::NAME[key]`` (read
    from the source with ``ast``, so test modules need not be imported)."""
    path, name = ref.split("::")
    key = None
    if "[" in name:
        name, key = name[:-1].split("[")
        key = ast.literal_eval(key)
    tree = ast.parse((_ROOT / path).read_text())
    for node in tree.body:
        targets = (node.targets if isinstance(node, ast.Assign) else
                   [node.target] if isinstance(node, ast.AnnAssign) else [])
        if any(isinstance(t, ast.Name) and t.id == name for t in targets):
            value = ast.literal_eval(node.value)
            return float(value[key] if key is not None else value)
    raise KeyError(f"{ref}: no module-level constant {name!r} in {path}")


def test_exists(ref: str) -> bool:
    """Whether ``path::test_name`` names a test function defined in that file."""
    path, name = ref.split("::")
    file = _ROOT / path
    if not file.exists():
        return False
    tree = ast.parse(file.read_text())
    return any(isinstance(n, ast.FunctionDef) and n.name == name for n in tree.body)


def _finest(ds, fe: str, analytic: str) -> float:
    return abs(float(ds[fe].isel(n_b=-1)) - float(ds[analytic]))


def _roots_at(ds, kH_class: float, classes) -> float:
    kH = ds.kH.values
    nearest = np.array([min(classes, key=lambda k: abs(math.log(k / x))) for x in kH])
    m = nearest == kH_class
    return float(np.max(np.abs(ds.lam_det.values[m] - ds.lam_fe.values[m])))


def _method_gap(ds, a: str, b: str, level: int = -1) -> float:
    def v(m):  # sel's own ``method`` keyword would shadow the dimension: pass a dict
        return float(ds.v_cr.sel({"method": m}).isel(level=level))

    return abs(v(a) - (float(ds[b]) if b in ds.data_vars else v(b)))


_CH3_FE = "reference/studies/ch3_fe.py"
_CH4_FE = "reference/studies/ch4_fe.py"
_CH4_FE_CLASSES = (0.3, 2.0, 10.0)

CROSSCHECKS: tuple[CrossCheck, ...] = (
    CrossCheck("ch3", "loss-of-tension stretch, lamP = 3, c = 0",
               "axisymmetric membrane FE (finest stored mesh)",
               "membrane ODE (shooting), consistent balance", "ch3_fe_convergence",
               lambda ds: _finest(ds, "lam_loss_of_tension_fe", "lam_loss_of_tension_membrane"),
               f"{_CH3_FE}::TOL_COARSE['loss_of_tension']",
               "verification/test_ch3_fe.py::test_fe_loss_of_tension_supports_membrane_balance"),
    CrossCheck("ch3", "pull-in voltage Phibar, lamP = 1.25, c = 0",
               "axisymmetric membrane FE (finest stored mesh)",
               "membrane ODE (shooting), consistent balance", "ch3_fe_convergence",
               lambda ds: _finest(ds, "phibar_pullin_fe", "phibar_pullin_membrane"),
               f"{_CH3_FE}::TOL_COARSE['pullin_phibar']",
               "verification/test_ch3_fe.py::test_fe_pullin_supports_membrane_balance"),
    CrossCheck("ch3", "pull-in stretch, lamP = 1.25, c = 0",
               "axisymmetric membrane FE (finest stored mesh)",
               "membrane ODE (shooting), consistent balance", "ch3_fe_convergence",
               lambda ds: _finest(ds, "lam_pullin_fe", "lam_pullin_membrane"),
               f"{_CH3_FE}::TOL_COARSE['pullin_lam']",
               "verification/test_ch3_fe.py::test_fe_pullin_supports_membrane_balance"),
    CrossCheck("ch4", "critical stretch, every root of Figs 4.2/4.5 (kH = 0.3, 2, 10)",
               "exponential-ansatz determinant (method 1)",
               "through-thickness spectral/Hermite FE eigenvalues (method 2)",
               "ch4_method_agreement",
               lambda ds: float(np.nanmax(np.abs(ds.lam_det.values - ds.lam_fe.values))),
               "verification/test_ch4_methods.py::TOL_AGREE",
               "verification/test_ch4_methods.py::"
               "test_determinant_and_fe_agree_on_every_root_of_every_figure_case"),
    *(CrossCheck("ch4", f"critical stretch, roots near kH = {k:g}",
                 "exponential-ansatz determinant (method 1)",
                 "plane-strain periodic strip FE, 2-D elements (coarse mesh)",
                 "ch4_fe_agreement",
                 lambda ds, k=k: _roots_at(ds, k, _CH4_FE_CLASSES),
                 f"{_CH4_FE}::TOL_COARSE[{k!r}]",
                 "verification/test_ch4_fe.py::test_strip_fe_agrees_with_determinant_charge_control")
      for k in _CH4_FE_CLASSES),
    CrossCheck("ch5", "critical voltage of the perfect film (finest stored mesh)",
               "FE: initial-stress eigenproblem", "FE: field-coupled eigenproblem",
               "ch5_methods", lambda ds: _method_gap(ds, "initial_stress", "coupled"),
               None, "verification/test_ch5_methods.py::"
               "test_condensing_the_potential_stiffens_and_the_coupling_is_percent_level"),
    CrossCheck("ch5", "critical voltage of the perfect film (finest stored mesh)",
               "FE: initial-stress eigenproblem", "Mindlin clamped plate (kappa = 5/6)",
               "ch5_methods", lambda ds: _method_gap(ds, "initial_stress", "v_cr_mindlin"),
               None, "verification/test_ch5_methods.py::"
               "test_coupling_is_a_mesh_independent_share_of_the_gap_to_mindlin"),
    CrossCheck("ch5", "critical voltage of the perfect film (finest stored mesh)",
               "FE: initial-stress eigenproblem", "Kirchhoff clamped plate (14.68 D/a^2)",
               "ch5_methods", lambda ds: _method_gap(ds, "initial_stress", "v_cr_kirchhoff"),
               None, "verification/test_ch5_methods.py::"
               "test_coupling_is_a_mesh_independent_share_of_the_gap_to_mindlin"),
)


@dataclass(frozen=True)
class Row:
    check: CrossCheck
    measured: float
    tolerance: float | None

    @property
    def within(self) -> bool | None:
        return None if self.tolerance is None else self.measured <= self.tolerance


def matrix(data_dir: Path | None = None) -> list[Row]:
    """Every cross-check with its agreement measured from the curated datasets."""
    return [Row(c, c.measured(data_dir), c.tolerance_value()) for c in CROSSCHECKS]


def table(rows: list[Row]) -> str:
    """Markdown table of the matrix."""
    out = ["| chapter | quantity | implementation A | implementation B | measured max abs "
           "difference | tolerance | verdict | asserted by |", "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        c = r.check
        tol = "—" if r.tolerance is None else f"{r.tolerance:.1e}"
        verdict = ("expected to differ (diagnosis)" if r.within is None
                   else "agree" if r.within else "DISAGREE")
        out.append(f"| {c.chapter} | {c.quantity} | {c.a} | {c.b} | {r.measured:.2e} | {tol} | "
                   f"{verdict} | `{c.test.split('::')[-1]}` (`{c.test.split('::')[0]}`) |")
    return "\n".join(out)
