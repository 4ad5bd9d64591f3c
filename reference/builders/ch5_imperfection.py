"""Chapter 5 imperfection sensitivity of the wrinkling bifurcation at radius/thickness 20
(§5.3.1, Fig. 5.4, Fig. 5.5).

Along the path of the perfect (axisymmetrically imperfect) Ogden film at radius/thickness
20, an angular wavenumber-1 eigenvalue of the tangent at fixed voltage reaches zero at a
centre deflection of 7.6-7.95 t0 on the finest meshes (``ch5_wrinkling.nc``): a
non-axisymmetric bifurcation. Whether the film *fails* there (the thesis: the 0.5 mm film
"encountered wrinkling instability" at 3.64 mm, before pull-in) depends on the bifurcated
branch: if it falls in voltage (unstable), a film with any small wavenumber-1 imperfection
reaches a voltage maximum near the bifurcation, below its voltage, and snaps there under
voltage control (Koiter: the drop grows like the amplitude to the power 2/3 for a
symmetric unstable bifurcation); if it rises (stable), the imperfect film passes the
bifurcation with a growing wavenumber-1 deflection and fails later, at a limit point of
the wrinkled film.

``build(out_dir, full=True)`` follows the film with seeds of peak amplitude
:data:`AMPLITUDES` (fractions of t0, the wavenumber-1 term of
:meth:`~debench.models.buckling.parameters.Plate.imperfection_lift`) on the meshes
:data:`LEVELS` (:mod:`debench.reference.studies.ch5_imperfection`) and writes
``ch5_imperfection.nc``: the paths (voltage, centre deflection, amplitude of the
non-axisymmetric deflection), the eigen-records, and per path its voltage maximum (vertex
of the parabola through three path points) and where it lies. The default build recomputes
nothing (each path costs 5-15 CPU minutes) and draws the figure from the curated dataset
(:func:`debench.reference.builders.ch5.draw_from_curated`).

The reading is fixed before the data (:func:`wrinkling_governs`): the wavenumber-1
bifurcation governs the failure if on every mesh the voltage maximum of every seeded path
lies before :data:`W_SPLIT` and falls as the seed grows; the film passes the bifurcation if
on every mesh the smallest seed's maximum lies beyond :data:`W_SPLIT`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr
from debench.models.buckling.parameters import Plate
from debench.models.buckling.ramp_result import RampResult
from debench.reference.builders.ch5 import draw_from_curated, not_recomputed_line
from debench.reference.builders.ch5_wrinkling import _pad
from debench.reference.datasets import DatasetError, read_dataset, variable_attrs, write_dataset
from debench.reference.figures import footnote, pyplot, save
from debench.reference.studies import ch5_imperfection as study
from debench.reference.studies.ch5 import CASES
from debench.reference.studies.ch5_imperfection import (
    AMPLITUDES,
    LEVELS,
    W_SPLIT,
)
from debench.reference.tasks import resolve_scheduler, run_tasks

#: CPU seconds of the default build (one thread, measured in one `debench reproduce` with
#: two pool processes on the quiet 2-core machine): the pool starts the longest first.
BUILD_CPU_S = 1.2
#: ``debench verify`` does not rebuild this chapter (minutes of CPU, or the catalogue itself):
#: its model guards and the value check stand for it.
REGENERATED_BY_VERIFY = False
#: Model guards ``debench verify`` runs for this chapter (none).
GUARDS = {}

NAME = "ch5_imperfection"
W_ZOOM = 0.6
"""The voltage panel of the figure starts at W_ZOOM x W_SPLIT: the paths agree before."""
COST = "one seeded radius/thickness 20 path costs 5-15 CPU minutes, 6 paths"
"""Why the default run does not recompute the study."""


def not_recomputed(full: bool) -> str | None:
    """The line ``debench reproduce`` reports for ``ch5_imperfection.nc`` when this plan
    does not recompute it (the default run), else None."""
    return None if LEVELS[full] else not_recomputed_line(NAME, COST)


def compute(full: bool = False, progress: bool = True, scheduler=None) -> xr.Dataset:
    levels = LEVELS[full]
    todo = [(study.imperfect_path_task, h, amp) for h in levels for amp in AMPLITUDES]
    ramps = [RampResult(**d) for d in run_tasks(todo, scheduler=scheduler, progress=progress)]
    nl, na = len(levels), len(AMPLITUDES)
    nstep = max(len(r.v) for r in ramps)
    neig = max(len(r.eig_v) for r in ramps)

    def grid(rows, width):
        return _pad(rows, width).reshape((nl, na, width) + np.shape(rows[0])[1:])

    def scalar(values):
        return np.array([np.nan if x is None else x for x in values], float).reshape(nl, na)

    a = variable_attrs

    asym_at_max = []
    for r in ramps:
        if r.w_pullin is None:
            asym_at_max.append(np.nan)
            continue
        k = int(np.argmax(r.v))
        asym_at_max.append(float(r.w_asym[k]))
    acc = ("of this mesh: vertex of the parabola through the three path points around the "
           "voltage maximum (interpolation error < 1e-3 relative); NaN: no maximum")
    dims3 = ("level", "amplitude", "step")
    dimse = ("level", "amplitude", "eig_record")
    data = {
        "v": (dims3, grid([r.v for r in ramps], nstep), a(
            "normalised voltage Phi/t0 sqrt(eps/mu_ref) along the path")),
        "w": (dims3, grid([r.w for r in ramps], nstep), a(
            "centre deflection of the top surface / t0 along the path")),
        "w_asym": (dims3, grid([r.w_asym for r in ramps], nstep), a(
            "amplitude / t0 of the largest non-axisymmetric harmonic of the deflection on "
            "the mid-plane circle r = R/2")),
        "n_asym": (dims3, grid([r.n_asym for r in ramps], nstep), a(
            "angular wavenumber of that harmonic")),
        "eig_v": (dimse, grid([r.eig_v for r in ramps], neig), a(
            "normalised voltage of the eigen-record")),
        "eig_w": (dimse, grid([r.eig_w for r in ramps], neig), a(
            "centre deflection / t0 of the eigen-record")),
        "eig_lam": (dimse + ("mode",), grid([r.eig_lam for r in ramps], neig), a(
            "three algebraically smallest eigenvalues of the condensed tangent (L2 mass)")),
        "eig_axisym": (dimse + ("mode",), grid([r.eig_axisym for r in ramps], neig), a(
            "fraction of the mode in the angular harmonic n = 0")),
        "eig_wavenumber": (dimse + ("mode",), grid([r.eig_wavenumber for r in ramps], neig),
                           a("dominant angular wavenumber n of the mode on r = R/2")),
        "v_max": (("level", "amplitude"), scalar([r.v_pullin for r in ramps]), a(
            "voltage maximum of the path (the film snaps there under voltage control)",
            accuracy=acc)),
        "w_at_v_max": (("level", "amplitude"), scalar([r.w_pullin for r in ramps]), a(
            "centre deflection / t0 at the voltage maximum", accuracy=acc)),
        "w_asym_at_v_max": (("level", "amplitude"), scalar(asym_at_max), a(
            "non-axisymmetric deflection amplitude / t0 at the largest computed voltage")),
        "path_end": (("level", "amplitude"),
                     np.array([r.end for r in ramps], dtype=str).reshape(nl, na), a(
                         "why the path stopped (RampResult.end)")),
        "ndof": (("level",), np.array([r.ndof for r in ramps[::na]], np.int64), a(
            "degrees of freedom")),
        "cpu_seconds_assembly": (("level", "amplitude"), scalar(
            [r.stats.get("assemble_s", np.nan) for r in ramps]), a(
                "time spent assembling (one thread)", "s")),
    }
    return xr.Dataset(data, coords={
        "level": ("level", np.arange(nl), a("mesh level")),
        "h_rel": ("level", np.array(levels), a("in-plane mesh size / t0")),
        "amplitude": ("amplitude", np.array(AMPLITUDES), a(
            "peak of the wavenumber-1 seed of the imperfection / t0")),
        "step": ("step", np.arange(nstep), a("converged path point")),
        "eig_record": ("eig_record", np.arange(neig), a("eigen-analysis record")),
        "mode": ("mode", np.arange(3), a("mode index (ascending eigenvalue)"))})


def figure(ds: xr.Dataset, fig_dir: Path, perfect: xr.Dataset | None = None,
           note: str | None = None) -> list[Path]:
    """Fig. 5.4 counterpart at radius/thickness 20: voltage against centre deflection of the
    seeded films (and the perfect film of ``ch5_wrinkling.nc`` when given), and the growth
    of the wavenumber-1 deflection; ``note`` below the axes (where the data come from)."""
    plt = pyplot()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4.2))
    colours = ("C0", "C1", "C2", "C3")
    for lev, ls in zip(ds.level.values, ("--", "-"), strict=False):
        h = float(ds.h_rel[lev])
        same = [] if perfect is None else np.flatnonzero(perfect.h_rel.values == h)
        if len(same):
            p = perfect.isel(level=int(same[0]))
            ax1.plot(p.w, p.v, ls, color="k", lw=1, label=f"no seed, h = {h:g} t0")
        for j, amp in enumerate(ds.amplitude.values):
            r = ds.isel(level=lev, amplitude=j)
            lab = f"seed {amp:g} t0, h = {h:g} t0"
            ax1.plot(r.w, r.v, ls, color=colours[j], lw=1, label=lab)
            ax2.plot(r.w, r.w_asym, ls, color=colours[j], lw=1, label=lab)
            if np.isfinite(float(r.v_max)):
                ax1.plot(float(r.w_at_v_max), float(r.v_max), "o", color=colours[j], ms=4)
    for ax in (ax1, ax2):
        ax.axvline(W_SPLIT, color="0.6", lw=0.8, ls=":")
        ax.set_xlabel(rf"centre deflection $w/t_0$ (dotted: {W_SPLIT:g})")
    w_lo = W_ZOOM * W_SPLIT
    near = np.concatenate([ds.v.values[ds.w.values >= w_lo].ravel(),
                           ds.v_max.values.ravel()])
    near = near[np.isfinite(near)]
    ax1.set_xlim(w_lo, study.C_MAX)
    if near.size:
        pad = 0.1 * (near.max() - near.min()) + 1e-4
        ax1.set_ylim(near.min() - pad, near.max() + pad)
    ax1.set_ylabel(r"normalised voltage $v$ (dots: voltage maxima)")
    ax2.set_ylabel(r"non-axisymmetric deflection on $r = R/2$ / $t_0$")
    ax2.set_yscale("log")
    fig.suptitle("Ogden, radius/thickness 20: films with a wavenumber-1 seed "
                 "(dashed h = 2.5 t0, solid h = 2 t0)")
    ax1.legend(fontsize=7)
    footnote(fig, note)
    return save(fig, fig_dir / "fig5_4_imperfection_sensitivity_r20")


def _perfect_film():
    """The perfect film's paths of the curated ``ch5_wrinkling.nc``, or None without it."""
    try:
        return read_dataset("ch5_wrinkling")
    except (DatasetError, FileNotFoundError):
        return None      # the figure then shows the seeded paths only


def build(out_dir: Path, *, full: bool = False, scheduler: str | None = None) -> list[Path]:
    """Compute and write ``ch5_imperfection.nc`` and its figure into ``out_dir``
    (``scheduler``: as :func:`debench.reference.builders.ch5.build`); the default build
    (no level in its plan) draws the figure from the curated dataset and writes no
    dataset."""
    out_dir = Path(out_dir)
    if not LEVELS[full]:
        return draw_from_curated(
            NAME, COST, lambda ds, fig_dir, note: figure(ds, fig_dir, _perfect_film(), note),
            out_dir)
    ds = compute(full, scheduler=resolve_scheduler(scheduler))
    perfect = _perfect_film()
    return [write_dataset(
        ds, NAME, out_dir=out_dir, overwrite=True,
        title="Chapter 5 imperfection sensitivity of the wrinkling bifurcation, R/t0 = 20",
        summary=("Paths of the clamped Ogden film (Table 5.1, t0 = 0.5 mm) at radius/thickness "
                 "20 with the thesis' axisymmetric imperfection plus a seed of the "
                 "wavenumber-1 mode of three amplitudes, to and past the voltage maximum, on "
                 "two meshes: whether the non-axisymmetric bifurcation found along the "
                 "perfect path is where the film fails (§5.3.1, Figs 5.4-5.5)."),
        parameters={"full": full, "levels_h_rel": list(LEVELS[full]),
                    "amplitudes": list(AMPLITUDES), "wavenumber": study.WAVENUMBER,
                    "layers": study.LAYERS, "order": study.ORDER, "aspect": study.ASPECT,
                    "eig_every": study.EIG_EVERY, "dv_max": study.DV_MAX,
                    "c_max": study.C_MAX, "w_split": W_SPLIT, "case": study.CASE,
                    "thickness_m": CASES[study.CASE][1],
                    "axisymmetric_imperfection": Plate().imperfection},
    )] + figure(ds, out_dir / "figures", perfect)
