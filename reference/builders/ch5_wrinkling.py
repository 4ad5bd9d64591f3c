"""Chapter 5 wrinkling search at radius/thickness 20 (§5.3.1, Fig. 5.5, Table 5.3).

The thesis reports that the 0.5 mm Ogden film wrinkles (a non-axisymmetric instability)
at a centre deflection of 3.64 mm, before pull-in, while the 1 mm film fails by pull-in.
At the stated radius/thickness 10 both thicknesses are the same normalised problem (scale
invariance), and the ramps of :mod:`debench.reference.builders.ch5` find no
non-axisymmetric instability before pull-in. The hypothesis of the
``ch5.hypothesis.radius_kept`` entries is that the 0.5 mm model kept R = 10 mm, i.e.
R/t0 = 20.

``build(out_dir, full=True)`` follows the imperfect Ogden film (Table 5.1, t0 = 0.5 mm) at
R/t0 = 20 to and past pull-in (:func:`debench.models.buckling.solver.voltage_ramp`; one
layer of quadratic prisms as the radius/thickness 10 ramps) with the eigen-analysis of the
condensed tangent every :data:`EIG_EVERY` steps (the three algebraically smallest
eigenvalues, their axisymmetric fraction and dominant angular wavenumber on the mid-plane
circle r = R/2, :func:`debench.models.buckling.modes.mode_harmonics`), on five
circumferential resolutions (the default build writes nothing: :data:`LEVELS`). It
writes ``ch5_wrinkling.nc``: the path, the eigen-records (each from a random start block:
a warm start can hide a newly unstable mode), the path's voltage maximum, the first
instability along the path (:func:`path_instability`: the kind of the mode that becomes
unstable first, axisymmetric = pull-in or non-axisymmetric = wrinkling, its voltage,
deflection and wavenumber) and the smallest non-axisymmetric eigenvalue before it, per
mesh. Where the path turns at a wrinkling bifurcation, its voltage maximum is that
bifurcation, not the axisymmetric limit point: the first instability is read from the
eigen-records, never from the maximum. A path whose deflection-controlled phase cannot
continue before a voltage maximum is kept (``stop_on_stall``) and says so
(``path_end``), with the eigen-analysis of its last state.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import xarray as xr
from debench.models.buckling.ramp_result import RampResult
from debench.reference.builders.ch5 import draw_from_curated, not_recomputed_line
from debench.reference.datasets import variable_attrs, write_dataset
from debench.reference.figures import footnote, pyplot, save
from debench.reference.studies.ch5 import (
    CASES,
    ORDER,  # noqa: F401 - the setting of the paths
    axisymmetric,
    first_instability,
    lowest_nonaxisymmetric,
    wrinkling_task,
)
from debench.reference.studies.ch5 import WRINKLING_ASPECT as ASPECT
from debench.reference.studies.ch5 import WRINKLING_CASE as CASE
from debench.reference.studies.ch5 import WRINKLING_DV_MAX as DV_MAX  # noqa: F401
from debench.reference.studies.ch5 import WRINKLING_EIG_EVERY as EIG_EVERY
from debench.reference.studies.ch5 import WRINKLING_LAYERS as LAYERS
from debench.reference.tasks import resolve_scheduler, run_tasks

#: CPU seconds of the default build (one thread, measured in one `debench reproduce` with
#: two pool processes on the quiet 2-core machine): the pool starts the longest first.
BUILD_CPU_S = 1.2
#: ``debench verify`` does not rebuild this chapter (minutes of CPU, or the catalogue itself):
#: its model guards and the value check stand for it.
REGENERATED_BY_VERIFY = False
#: Model guards ``debench verify`` runs for this chapter (none).
GUARDS = {}

NAME = "ch5_wrinkling"
LEVELS = {False: (), True: (4.0, 3.0, 2.5, 2.0, 1.5)}
"""In-plane mesh sizes / t0: about 2 pi R/h = 31, 42, 50, 63 and 84 quadratic elements
around the rim (angular wavenumbers up to n ~ 8, 10, 12, 15 and 21 resolved by at least two
quadratic elements per half-wave). The search is converged-only: one R/t0 = 20 Ogden ramp
with eigen-analyses costs ~10-25 CPU minutes, beyond the default reproduce's budget, so the
default build recomputes nothing and draws the figure from the curated dataset
(:func:`debench.reference.builders.ch5.draw_from_curated`)."""
COST = "one radius/thickness 20 ramp with eigen-analyses costs 10-25 CPU minutes, 5 meshes"
"""Why the default run does not recompute the search."""


def not_recomputed(full: bool) -> str | None:
    """The line ``debench reproduce`` reports for ``ch5_wrinkling.nc`` when this plan does
    not recompute it (the default run), else None."""
    return None if LEVELS[full] else not_recomputed_line(NAME, COST)

def path_instability(r) -> dict:
    """The first instability recorded along one path
    (:func:`debench.reference.studies.ch5.first_instability`: its kind, voltage,
    deflection / t0 and wavenumber) and the smallest eigenvalue of a non-axisymmetric mode
    recorded up to it (the whole path when nothing became unstable) with its wavenumber."""
    lam, ax = np.asarray(r.eig_lam, float), np.asarray(r.eig_axisym, float)
    w, n = np.asarray(r.eig_w, float), np.asarray(r.eig_wavenumber, float)
    out = first_instability(w, r.eig_v, lam, ax, n)
    upto = w <= (out["w"] if np.isfinite(out["w"]) else np.inf)
    non = np.where(axisymmetric(n), np.nan, lam)[upto]
    out["min_lambda"] = out["min_lambda_n"] = math.nan
    if np.any(np.isfinite(non)):
        i, j = np.unravel_index(np.nanargmin(non), non.shape)
        out["min_lambda"], out["min_lambda_n"] = float(non[i, j]), float(n[upto][i, j])
    return out


def _pad(rows, width, fill=np.nan):
    out = np.full((len(rows), width) + np.shape(rows[0])[1:], fill, dtype=float)
    for i, r in enumerate(rows):
        out[i, : len(r)] = r
    return out


def compute(full: bool = False, progress: bool = True, scheduler=None) -> xr.Dataset:
    levels = LEVELS[full]
    tasks = [(wrinkling_task, h, EIG_EVERY) for h in levels]
    ramps = [RampResult(**d) for d in run_tasks(tasks, scheduler=scheduler, progress=progress)]
    found = [path_instability(r) for r in ramps]
    nstep = max(len(r.v) for r in ramps)
    neig = max(len(r.eig_v) for r in ramps)

    a = variable_attrs

    def per_level(values):
        return np.array([np.nan if x is None else x for x in values], float)

    pullin_acc = ("of this mesh: vertex of the parabola through three path points around the "
                  "voltage maximum (interpolation error < 1e-3 relative); NaN: no maximum")
    data = {
        "v": (("level", "step"), _pad([r.v for r in ramps], nstep), a(
            "normalised voltage Phi/t0 sqrt(eps/mu_ref) along the path")),
        "w": (("level", "step"), _pad([r.w for r in ramps], nstep), a(
            "centre deflection of the top surface / t0 along the path")),
        "eig_v": (("level", "eig_record"), _pad([r.eig_v for r in ramps], neig), a(
            "normalised voltage of the eigen-record")),
        "eig_w": (("level", "eig_record"), _pad([r.eig_w for r in ramps], neig), a(
            "centre deflection / t0 of the eigen-record")),
        "eig_lam": (("level", "eig_record", "mode"), _pad([r.eig_lam for r in ramps], neig), a(
            "three algebraically smallest eigenvalues of the condensed tangent (L2 mass)")),
        "eig_axisym": (("level", "eig_record", "mode"),
                       _pad([r.eig_axisym for r in ramps], neig), a(
                           "fraction of the mode in the angular harmonic n = 0")),
        "eig_wavenumber": (("level", "eig_record", "mode"),
                           _pad([r.eig_wavenumber for r in ramps], neig), a(
                               "dominant angular wavenumber n of the mode on r = R/2")),
        "v_pullin": (("level",), per_level([r.v_pullin for r in ramps]), a(
            "voltage maximum of the path (pull-in at the axisymmetric limit point; where the "
            "path turns at a bifurcation, the bifurcation)", accuracy=pullin_acc)),
        "w_pullin": (("level",), per_level([r.w_pullin for r in ramps]), a(
            "centre deflection / t0 at the voltage maximum", accuracy=pullin_acc)),
        "path_end": (("level",), np.array([r.end for r in ramps], dtype=str), a(
            "why the path stopped (RampResult.end)")),
        "first_kind": (("level",), np.array([f["kind"] for f in found], dtype=str), a(
            "the first instability along the path: the kind of the mode whose eigenvalue at "
            "fixed voltage reaches zero first (axisymmetric: pull-in; non-axisymmetric: "
            "wrinkling; none)")),
        "v_first": (("level",), per_level([f["v"] for f in found]), a(
            "normalised voltage at the first instability (NaN: none recorded)",
            accuracy=("linear interpolation to the zero of the lowest eigenvalue of that kind "
                      f"between eigen-records (every {EIG_EVERY} path points)"))),
        "w_first": (("level",), per_level([f["w"] for f in found]), a(
            "centre deflection / t0 at the first instability (NaN: none recorded)")),
        "n_first": (("level",), per_level([f["n"] for f in found]), a(
            "dominant angular wavenumber of the mode that becomes unstable first")),
        "min_nonaxisymmetric_lambda": (("level",), per_level([f["min_lambda"] for f in found]),
                                       a("smallest eigenvalue of a non-axisymmetric mode "
                                         "recorded up to the first instability")),
        "min_nonaxisymmetric_n": (("level",), per_level([f["min_lambda_n"] for f in found]), a(
            "wavenumber of that mode")),
        "ndof": (("level",), np.array([r.ndof for r in ramps], np.int64), a(
            "degrees of freedom")),
        "rim_elements": (("level",), np.array([2 * math.pi * ASPECT / h for h in levels]), a(
            "nominal number of elements around the rim, 2 pi R / h")),
        "wall_seconds_assembly": (("level",), np.array(
            [r.stats.get("assemble_s", np.nan) for r in ramps]), a(
                "time spent assembling (one thread)", "s")),
    }
    return xr.Dataset(data, coords={
        "level": ("level", np.arange(len(levels)), a("mesh level")),
        "h_rel": ("level", np.array(levels), a("in-plane mesh size / t0")),
        "step": ("step", np.arange(nstep), a("converged path point")),
        "eig_record": ("eig_record", np.arange(neig), a("eigen-analysis record")),
        "mode": ("mode", np.arange(3), a("mode index (ascending eigenvalue)"))})


def figure(ds: xr.Dataset, fig_dir: Path, note: str | None = None) -> list[Path]:
    """Fig. 5.5 counterpart at radius/thickness 20: the lowest non-axisymmetric eigenvalue
    along the path per mesh (wrinkling where it crosses zero first; dotted: the first
    instability of each mesh); ``note`` below the axes (where the data come from)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(5.8, 4.2))
    for lev, style in zip(ds.level.values, ("-o", "--s", ":^", "-.v", "-D"), strict=False):
        r = ds.sel(level=lev)
        lam_min = lowest_nonaxisymmetric(r.eig_lam.values, r.eig_wavenumber.values)
        ok = np.isfinite(r.eig_w.values) & np.isfinite(lam_min)
        ax.plot(r.eig_w.values[ok], lam_min[ok], style, ms=3,
                label=f"h = {float(r.h_rel):g} t0 ({float(r.rim_elements):.0f} rim elements)")
        if np.isfinite(float(r.w_first)):
            ax.axvline(float(r.w_first), color="0.5", lw=0.8, ls=":")
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_xlabel(r"centre deflection $w/t_0$ (dotted: first instability)")
    ax.set_ylabel(r"lowest non-axisymmetric eigenvalue $\lambda$")
    ax.set_title("Fig 5.5 counterpart, Ogden, radius/thickness 20")
    ax.legend()
    footnote(fig, note)
    return save(fig, fig_dir / "fig5_5_nonaxisymmetric_modes_r20")


def build(out_dir: Path, *, full: bool = False, scheduler: str | None = None) -> list[Path]:
    """Compute and write ``ch5_wrinkling.nc`` and its figure into ``out_dir``
    (``scheduler``: as :func:`debench.reference.builders.ch5.build`); the default build
    (no level in its plan) draws the figure from the curated dataset and writes no
    dataset."""
    out_dir = Path(out_dir)
    if not LEVELS[full]:
        return draw_from_curated(NAME, COST, figure, out_dir)
    ds = compute(full, scheduler=resolve_scheduler(scheduler))
    return [write_dataset(
        ds, NAME, out_dir=out_dir, overwrite=True,
        title="Chapter 5 wrinkling search: the Ogden film at radius/thickness 20",
        summary=("Voltage ramp of the imperfect clamped Ogden film (Table 5.1, t0 = 0.5 mm) "
                 "at radius/thickness 20 to and past pull-in with the eigen-analysis along "
                 "the path: the first instability along it (pull-in or wrinkling; voltage, "
                 "deflection, wavenumber), on several circumferential "
                 "resolutions: the data behind the hypothesis that the thesis' 0.5 mm model "
                 "kept R = 10 mm (§5.3.1, Fig. 5.5)."),
        parameters={"full": full, "levels_h_rel": list(LEVELS[full]), "layers": LAYERS,
                    "order": ORDER, "aspect": ASPECT, "eig_every": EIG_EVERY,
                    "dv_max": DV_MAX, "case": CASE,
                    "mode_kind": "dominant angular harmonic (0: axisymmetric)",
                    "thickness_m": CASES[CASE][1]},
    )] + figure(ds, out_dir / "figures")
