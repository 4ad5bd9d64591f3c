"""Beyond the thesis: critical stretch of the plate with the fibre in its plane.

Dataset ``ch4_inplane_lam_cr.nc`` (in ``out_dir``): lam_cr(kH, theta, xi) at Dhat = 0
(and Dhat = 2 with ``full``) by both methods of :mod:`debench.models.plate.inplane`
(exponential-ansatz determinant and through-thickness FE), with the strong-ellipticity
limit lam_E(theta, xi). lam_cr is the largest bifurcation stretch in
[max(lam_E, LAM_LO), 0.999] (equibiaxial compression); NaN where there is none (the
material loses ellipticity first).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr
from debench.models.plate import PlateParams
from debench.models.plate import inplane as ip
from debench.reference.datasets import write_dataset

THETA_FAST = (0.0, 30.0, 45.0, 60.0, 90.0)
THETA_FULL = tuple(float(t) for t in range(0, 91, 10)) + (45.0,)
KH_FAST = (0.5, 2.0, 5.0)
KH_FULL = (0.25, 0.5, 1.0, 2.0, 3.0, 5.0, 8.0)
XI_FAST = (5.0,)
XI_FULL = (1.0, 5.0)
D_FAST = (0.0,)
D_FULL = (0.0, 2.0)
#: lower end of the scanned window, above the slender-plate Euler roots of interest
LAM_LO = 0.6
#: grid points of the scan (each method)
N_SCAN = 40
COMMON = {"alpha": 0.0, "beta": 0.5, "mu": 1.0, "eps": 1.0, "control": "charge",
          "fibre": "A = (cos theta, 0, sin theta), in the plane of the plate",
          "units": "mu = eps = 1, Dhat = D2/sqrt(mu eps)", "n_elements": ip.N_ELEMENTS}


def _attrs(long_name, units="1"):
    return {"long_name": long_name, "units": units}


def lam_cr_dataset(full: bool) -> xr.Dataset:
    thetas = sorted(set(THETA_FULL)) if full else THETA_FAST
    khs = KH_FULL if full else KH_FAST
    xis = XI_FULL if full else XI_FAST
    ds_ = D_FULL if full else D_FAST
    shape = (len(xis), len(ds_), len(thetas), len(khs))
    det, fe = np.full(shape, np.nan), np.full(shape, np.nan)
    lam_e = np.full(shape[:3], np.nan)
    for a, xi in enumerate(xis):
        for b, D in enumerate(ds_):
            p = PlateParams(xi=xi, Dhat=D)
            for c, th in enumerate(thetas):
                lam_e[a, b, c] = ip.ellipticity_limit(th, p, window=(0.45, 0.999))
                lo = max(LAM_LO, lam_e[a, b, c] * (1 + 1e-9))
                for d, kh in enumerate(khs):
                    r1 = ip.critical_stretches_det(kh, th, p, window=(lo, 0.999),
                                                   n_scan=N_SCAN)
                    r2 = ip.critical_stretches_fe(kh, th, p, window=(lo, 0.999),
                                                  n_scan=N_SCAN)
                    det[a, b, c, d] = max(r1, default=np.nan)
                    fe[a, b, c, d] = max(r2, default=np.nan)
    dims = ("xi", "Dhat", "theta", "kH")
    return xr.Dataset(
        {"lam_cr_det": (dims, det, _attrs(
            "critical stretch, exponential-ansatz determinant (method 1)")),
         "lam_cr_fe": (dims, fe, _attrs(
             "critical stretch, through-thickness FE (method 2)")),
         "lam_E": (dims[:3], lam_e, _attrs(
             "largest compressive stretch without plane strong ellipticity"))},
        coords={"xi": ("xi", np.array(xis), _attrs("anisotropy parameter")),
                "Dhat": ("Dhat", np.array(ds_), _attrs("Eulerian D2/sqrt(mu eps)")),
                "theta": ("theta", np.array(thetas), _attrs(
                    "fibre angle to the wave vector", "degree")),
                "kH": ("kH", np.array(khs), _attrs("wavenumber times reference thickness"))})


def build(out_dir: Path, *, full: bool = False, progress: bool = True) -> list[Path]:
    out_dir = Path(out_dir)
    return [write_dataset(
        lam_cr_dataset(full), "ch4_inplane_lam_cr", out_dir=out_dir, overwrite=True,
        title="Plate bifurcation with the fibre in the plane (beyond the thesis)",
        summary="Critical stretch lam_cr(kH) of the equibiaxially compressed transversely "
                "isotropic dielectric plate (energy 4.22) with the fibre in its plane at "
                "the angle theta to the wave vector, by the exponential-ansatz determinant "
                "and by through-thickness finite elements, with the strong-ellipticity "
                "limit. Our results, not thesis values.",
        parameters={**COMMON, "full": full, "lam_lo": LAM_LO, "n_scan": N_SCAN})]
