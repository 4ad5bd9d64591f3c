"""Chapter 4 catalogue: every entry of reference/catalogue/ch4.toml evaluates to its
expected status, and the qualitative claims do not hinge on the assumed area window.

Claims of Sec. 4.4-4.5 are statused with the "printed" variant (see ch4.toml header);
the consequences of the errata are asserted in test_ch4_derivation.py/test_ch4_limits.py.
"""

from __future__ import annotations

import numpy as np
import pytest
from debench.reference import catalogue
from debench.reference.producers import ch4 as prod

ENTRIES = [e for e in catalogue.load() if e.file == "ch4.toml"]
ALL_IDS = catalogue.by_id()
REQUIRED = ("lit.plate.biot_equibiaxial", "lit.plate.euler_thin_limit")  # in literature.toml


def test_required_literature_ids_present():
    """The Chapter 4 literature anchors exist (in literature.toml) with a reference."""
    assert set(REQUIRED) <= set(ALL_IDS)
    assert all(ALL_IDS[i].kind == "literature" and ALL_IDS[i].reference for i in REQUIRED)


@pytest.mark.parametrize("entry", ENTRIES, ids=[e.id for e in ENTRIES])
def test_catalogue_entry_has_expected_status(entry):
    """The computed status of each ch4 entry equals its catalogued expected_status."""
    r = catalogue.evaluate(entry)
    assert r.status != "error", r.diagnosis
    assert r.status == entry.expected_status, (r.value, r.diagnosis)


@pytest.mark.parametrize(("kH_max", "lam_min"), [(5.0, 0.4), (20.0, 0.4), (10.0, 0.3),
                                                 (10.0, 0.5)])
def test_claims_robust_to_area_window(kH_max, lam_min):
    """ch4.assumption.area_window: the area orderings behind ch4.fig4_2.* hold for
    kH_max = 5, 20 and lam_min = 0.3, 0.5 as well as (10, 0.4) (printed variant)."""
    def a(xi, D):
        return prod.area(xi, D, "printed", "thesis", kH_max, lam_min)

    Ds = prod.FIG42_D
    assert all(a(5.0, D) > a(0.0, D) for D in Ds)                       # TI larger
    assert all(np.diff([a(xi, D) for D in (0.0, 1.0, 2.0)]).min() > 0 for xi in (0.0, 5.0))
    assert np.all(np.diff([a(0.0, D) for D in Ds[3:]]) < 0)            # iso (d)-(i)
    assert Ds[int(np.argmax([a(5.0, D) for D in Ds]))] == 2.6          # TI peak at (f)
    assert np.all(np.diff([a(xi, 2.0) for xi in prod.FIG45_XI]) > 0)    # Fig 4.5


def test_thesis_region_differs_from_physical_instability():
    """The thesis' 'determinant < 0' region omits points where both parities are unstable
    (det_E det_O > 0 but the incremental energy has two negative eigenvalues): its area is
    smaller than the physical unstable area (isotropic, Dhat = 0)."""
    assert prod.area(0.0, 0.0, "printed", "thesis") < prod.area(0.0, 0.0, "printed", "physical")
