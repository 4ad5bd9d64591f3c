"""The Chapter 4 study: the cases of Figs 4.2-4.5 (pre-stretch fields, anisotropy levels),
the (kH, lam) window of the stable-region areas and the memoised regions, areas, thin
limits and critical fields on it, which the builder's datasets and figures and the
producers' catalogue values share."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from debench.models.plate import PlateParams
from debench.models.plate.analysis import (
    _max_area_D,
    critical_D_thin_extensional,
    region,
    thin_limit,
)

#: thesis Fig. 4.2 cases and Fig. 4.5 anisotropy levels (Sec. 4.4)
FIG42_D = (0.0, 1.0, 2.0, 2.2, 2.4, 2.6, 3.0, 4.0, 5.0)
FIG45_XI = (0.0, 3.0, 5.0, 10.0)
XI_TI = 5.0
#: area window (assumption ch4.assumption.area_window): kH linear in [0.01, 10],
#: lam in [0.4, 8]; the sensitivity study uses kH_max = 5 and 20
KH_MAX = 10.0
AREA_KH_N = 81
AREA_LAM = (0.4, 8.0, 241)


def kH_grid(kH_max=KH_MAX):
    """The kH grid of the area window (linear in [0.01, kH_max])."""
    return np.linspace(0.01, kH_max, AREA_KH_N)


def lam_grid(lam_min=AREA_LAM[0]):
    """The lam grid of the area window (geometric in [lam_min, 8])."""
    return np.geomspace(lam_min, AREA_LAM[1], AREA_LAM[2])


@lru_cache(maxsize=512)
def area(xi: float, D: float, variant: str = "printed", which: str = "thesis",
         kH_max: float = KH_MAX, lam_min: float = AREA_LAM[0]) -> float:
    """Area of the stable region of the (kH, lam) window (memoised; Figs 4.2-4.5)."""
    return region_of(xi, D, variant, kH_max, lam_min).area(which)


@lru_cache(maxsize=256)
def region_of(xi: float, D: float, variant: str, kH_max: float, lam_min: float):
    """The unstable region on the area window (shared by both area definitions)."""
    return region(PlateParams(xi=xi, Dhat=D, variant=variant), kH_grid(kH_max), lam_grid(lam_min))


@lru_cache(maxsize=256)
def thin(xi: float, D: float, variant: str = "printed") -> float:
    """Largest kH -> 0 critical stretch of the flexural mode (upper curve start)."""
    r = thin_limit(PlateParams(xi=xi, Dhat=D, variant=variant))
    return float(r.max()) if r.size else float("nan")


@lru_cache(maxsize=16)
def critical_D(xi: float, candidate: str, variant: str = "printed") -> float:
    p = PlateParams(xi=xi, variant=variant)
    if candidate == "max_area":
        # critical_D_max_area(p, Ds, kH_grid(), lam_grid()) on the memoised areas (the Fig. 4.2
        # producers use the same regions)
        Ds = np.round(np.arange(1.0, 4.01, 0.2), 6)
        return _max_area_D(Ds, [area(float(xi), float(D), variant) for D in Ds])
    return critical_D_thin_extensional(p)
