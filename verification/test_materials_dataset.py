"""The curated kernel dataset ``data/ch2_kernel_reference_states.nc`` is reproduced by the
code (regeneration test) and is self-consistent with the library."""

from __future__ import annotations

import numpy as np
import pytest
from debench.reference.builders import ch2_appendix
from debench.reference.datasets import read_dataset

REGEN_RTOL = 1e-12
"""Same inputs, the same derivatives: only rounding may differ, relative to each variable's
largest entry (a structurally zero modulus comes out as a few ulp of the others)."""


@pytest.fixture(scope="module")
def curated():
    return read_dataset("ch2_kernel_reference_states")


def test_regenerating_the_kernel_dataset_reproduces_the_curated_numbers(curated):
    """compute() equals the stored values (every variable, NaN where no p is defined)."""
    fresh = ch2_appendix.compute()
    assert list(fresh.material.values) == list(curated.material.values)
    assert list(fresh.state.values) == list(curated.state.values)
    for name in fresh.data_vars:
        a, b = fresh[name].values, curated[name].values
        atol = REGEN_RTOL * np.nanmax(np.abs(b)) if np.any(np.isfinite(b)) else 0.0
        np.testing.assert_allclose(a, b, rtol=REGEN_RTOL, atol=atol, equal_nan=True,
                                   err_msg=name)


def test_curated_reference_state_is_stress_free_with_traction_free_pressure(curated):
    """At the reference state every stored sigma - p I vanishes (p = 0 if compressible)."""
    ref = curated.sel(state="reference")
    p = np.nan_to_num(ref.pressure.values)
    resid = ref.sigma.values - p[:, None, None] * np.eye(3)
    assert np.max(np.abs(resid)) <= 1e-9 * np.max(np.abs(curated.sigma.values))


def test_build_writes_dataset_and_figure(tmp_path):
    """The builder writes the dataset and the figure into the directory it is given."""
    paths = ch2_appendix.build(tmp_path)
    assert {p.name for p in paths} == {"ch2_kernel_reference_states.nc",
                                       "table5_1_uniaxial_stress_difference.png",
                                       "table5_1_uniaxial_stress_difference.svg"}
    assert all(p.exists() and p.stat().st_size > 0 for p in paths)
