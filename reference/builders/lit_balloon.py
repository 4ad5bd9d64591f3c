"""The dielectric-elastomer balloon (beyond the thesis; Zhu, Cai & Suo 2010): the reference
dataset of the problem ``lit_balloon``.

``build(out_dir, full=False)`` writes ``lit_balloon.nc``: for each Gent locking parameter
of :data:`JM` (inf: neo-Hookean)

* the normalised pressure pbar = p R/(mu H) on :data:`N_LAM` stretches at each normalised
  voltage of :data:`VBAR` (:func:`debench.models.balloon.pressure`, Eq. (4));
* the local maximum and minimum of pbar(lam) at each voltage, stretch and value
  (:func:`debench.models.balloon.pressure_extrema`, Eq. (5); NaN where absent);
* the voltage limit point (first local maximum of vbar(lam)) at each normalised pressure
  of :data:`PBAR_FIXED` (:func:`debench.models.balloon.voltage_limit`, Eq. (6)).

Closed forms and roots of closed forms: well under a second; ``full`` changes nothing.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import xarray as xr
from debench.models import balloon
from debench.reference.datasets import write_dataset

#: CPU seconds of the default build (one thread, measured in one `debench reproduce` with
#: two pool processes on the quiet 2-core machine): the pool starts the longest first.
BUILD_CPU_S = 1.0
#: ``debench verify`` rebuilds this chapter's default plan and compares it with data/.
REGENERATED_BY_VERIFY = True
#: Model guards ``debench verify`` runs for this chapter (none).
GUARDS = {}

NAME = "lit_balloon"
#: Gent locking parameters: neo-Hookean, and two Gent elastomers (97.2 a common fit of
#: VHB 4910 in the DE-balloon literature; 50 a stiffer-locking one)
JM = (math.inf, 97.2, 50.0)
#: normalised voltages vbar = (Phi/H) sqrt(eps/mu) of the pressure curves and extrema
VBAR = (0.0, 0.1, 0.2, 0.3, 0.4, 0.5)
#: normalised pressures pbar = p R/(mu H) of the voltage limit points (all below the
#: neo-Hookean snap-through pressure 1.2395 at vbar = 0, so each has one)
PBAR_FIXED = (0.0, 0.25, 0.5, 0.75, 1.0, 1.2)
#: stretches per pressure curve, uniform on [1, top]
N_LAM = 401
#: top of the neo-Hookean curves
NH_TOP = 8.0
#: top of a Gent curve: this fraction of the way from 1 to the locking stretch (pbar
#: diverges at the lock)
GENT_TOP_FRACTION = 0.98

REFERENCES = ("Zhu J, Cai S, Suo Z (2010) Nonlinear oscillation of a dielectric elastomer "
              "balloon. Polymer International 59:378-383, doi:10.1002/pi.2767")


def lam_top(Jm: float) -> float:
    """The largest stored stretch of the curves at ``Jm``."""
    if math.isinf(Jm):
        return NH_TOP
    return 1 + GENT_TOP_FRACTION * (balloon.locking_stretch(Jm) - 1)


def compute() -> xr.Dataset:
    """The balloon dataset (pure computation, no I/O)."""
    nj, nv, npf = len(JM), len(VBAR), len(PBAR_FIXED)
    lam = np.empty((nj, N_LAM))
    pbar = np.empty((nj, nv, N_LAM))
    ext = {k: np.full((nj, nv), np.nan) for k in ("lam_pmax", "pbar_max", "lam_pmin",
                                                    "pbar_min")}
    lim = {k: np.full((nj, npf), np.nan) for k in ("lam_vmax", "vbar_max")}
    for a, jm in enumerate(JM):
        lam[a] = np.linspace(1.0, lam_top(jm), N_LAM)
        for b, vb in enumerate(VBAR):
            pbar[a, b] = balloon.pressure(lam[a], vb, jm)
            e = balloon.pressure_extrema(vb, jm)
            if e.maximum is not None:
                ext["lam_pmax"][a, b], ext["pbar_max"][a, b] = e.maximum.lam, e.maximum.value
            if e.minimum is not None:
                ext["lam_pmin"][a, b], ext["pbar_min"][a, b] = e.minimum.lam, e.minimum.value
        for b, pf in enumerate(PBAR_FIXED):
            e = balloon.voltage_limit(pf, jm)
            if e is not None:
                lim["lam_vmax"][a, b], lim["vbar_max"][a, b] = e.lam, e.value
    sel_v, sel_p = ("Jm", "vbar"), ("Jm", "pbar_fixed")
    data_vars = {
        "lam": (("Jm", "point"), lam,
                {"units": "1", "long_name": "equibiaxial stretch lam = r/R of the balloon"}),
        "pbar": (("Jm", "vbar", "point"), pbar,
                 {"units": "1", "long_name": "normalised pressure p R/(mu H) in equilibrium "
                  "at stretch lam and voltage vbar, Eq. (4)"}),
        "lam_pmax": (sel_v, ext["lam_pmax"],
                     {"units": "1", "long_name": "stretch at the local maximum of pbar(lam) "
                      "at fixed vbar"}),
        "pbar_max": (sel_v, ext["pbar_max"],
                     {"units": "1", "long_name": "local maximum of pbar(lam) at fixed vbar"}),
        "lam_pmin": (sel_v, ext["lam_pmin"],
                     {"units": "1", "long_name": "stretch at the local minimum of pbar(lam) "
                      "at fixed vbar (NaN: none)"}),
        "pbar_min": (sel_v, ext["pbar_min"],
                     {"units": "1", "long_name": "local minimum of pbar(lam) at fixed vbar "
                      "(NaN: none)"}),
        "lam_vmax": (sel_p, lim["lam_vmax"],
                     {"units": "1", "long_name": "stretch at the voltage limit point (first "
                      "local maximum of vbar(lam)) at fixed pbar"}),
        "vbar_max": (sel_p, lim["vbar_max"],
                     {"units": "1", "long_name": "voltage at the limit point: first local "
                      "maximum of vbar(lam) at fixed pbar"}),
    }
    coords = {
        "Jm": ("Jm", np.array(JM), {"units": "1", "long_name": "Gent locking parameter "
                                    "(inf: neo-Hookean)"}),
        "vbar": ("vbar", np.array(VBAR), {"units": "1", "long_name": "normalised voltage "
                                          "(Phi/H) sqrt(eps/mu), reference thickness H"}),
        "pbar_fixed": ("pbar_fixed", np.array(PBAR_FIXED),
                       {"units": "1", "long_name": "normalised pressure p R/(mu H) held "
                        "fixed"}),
        "point": ("point", np.arange(N_LAM), {"units": "1", "long_name": "index of the "
                                              "stretch along a curve"}),
    }
    return xr.Dataset(data_vars, coords=coords)


def build(out_dir: Path, *, full: bool = False) -> list[Path]:
    """Write ``lit_balloon.nc`` into ``out_dir``; returns its path."""
    nc = write_dataset(
        compute(), NAME,
        title="debench: the dielectric-elastomer balloon (thin sphere, pressure and voltage)",
        summary=("Thin spherical incompressible neo-Hookean / Gent ideal-dielectric membrane "
                 "under internal pressure and a voltage through its thickness (Zhu, Cai & "
                 "Suo 2010): normalised pressure pR/(mu H) against stretch at fixed voltage, "
                 "its local maximum and minimum, and the voltage limit point at fixed "
                 "pressure (closed forms, debench.models.balloon). Confirmed by a 30-digit "
                 "clean room (verification/cleanroom/balloon.py)."),
        references=REFERENCES,
        parameters={"Jm": [("inf" if math.isinf(j) else j) for j in JM],
                    "vbar": list(VBAR), "pbar_fixed": list(PBAR_FIXED),
                    "n_lam": N_LAM, "nh_top": NH_TOP,
                    "gent_top_fraction": GENT_TOP_FRACTION, "xtol": balloon.XTOL,
                    "n_scan": balloon.N_SCAN},
        out_dir=Path(out_dir), overwrite=True)
    return [nc]
