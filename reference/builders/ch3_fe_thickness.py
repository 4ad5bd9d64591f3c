# ruff: noqa: E501  -- CF attribute dicts and dataset descriptions read best on one line
"""Builder of ``ch3_fe_thickness``: the thin axisymmetric solid of the Chapter 3 actuator
(models/circular/fe_solid.py) on film sequences H -> 0: Phibar at a fixed centre stretch
(lamP = 3, c = 0 and -0.053; lamP = 2, 4 at centre stretch lamP + 1), Phibar at pull-in
(lamP = 1.25), the loss-of-tension stretch (lamP = 3), each beside the membrane FE and both
analytic variants, with the limit H -> 0 (the ``ch3.fe.thickness_*`` entries read it).

A chapter of its own because it costs minutes of CPU (the loss-of-tension sequence most):
``debench verify`` does not rebuild it; its model guard
(:func:`debench.reference.producers.ch3_fe.thickness_guards`) recomputes the thickest film
of one sequence and compares it with the stored value. The films are independent solves:
they run as tasks (:func:`film_task`) on the Chapter 5 task runner
(:func:`debench.reference.tasks.run_tasks`: serial, a Dask LocalCluster or an
existing scheduler), thinnest first (the longest); the sequences' membrane references and
analytic variants are computed here.
"""

from __future__ import annotations

import hashlib
import sys
import time
from pathlib import Path

import debench.models.circular as circular
import debench.reference.studies.ch3_fe as study_module
import numpy as np
import xarray as xr
from debench.reference.datasets import write_dataset
from debench.reference.studies import ch3_fe as study
from debench.reference.tasks import limit_threads, resolve_scheduler, run_tasks

#: CPU seconds of the default build (one thread, measured in one `debench reproduce` with
#: two pool processes on the quiet 2-core machine): the pool starts the longest first.
BUILD_CPU_S = 46.0
#: ``debench verify`` does not rebuild this chapter (minutes of CPU, or the catalogue itself):
#: its model guards and the value check stand for it.
REGENERATED_BY_VERIFY = False
#: The model guards ``debench verify`` runs for this chapter instead of rebuilding it
#: (``module:function`` returning guarded values -> measured CPU seconds, one thread).
GUARDS = {"debench.reference.producers.ch3_fe:thickness_guards": 2.3}

NAME = "ch3_fe_thickness"
TITLE = "Chapter 3 film thickness: the thin axisymmetric solid on film sequences H -> 0"
SUMMARY = ("Film sequences of the thin solid FE (Phibar at a fixed centre stretch for lamP = 3 and c = 0, -0.053, and for lamP = 2, 4 at centre stretch lamP + 1; Phibar at pull-in for lamP = 1.25; the loss-of-tension centre stretch for lamP = 3) per film thickness H, the extrapolation to H -> 0, the membrane FE with the in-plane mesh error and both analytic variants.")


def film_sources() -> str:
    """sha256 of the source a film runs beyond what the task runner's cache key holds
    (:func:`debench.reference.tasks.models_digest` covers the materials and the
    top-level model modules): the Chapter 3 models and the study module."""
    h = hashlib.sha256()
    for f in [*sorted(Path(circular.__file__).parent.glob("*.py")), Path(study_module.__file__)]:
        h.update(f.name.encode())
        h.update(f.read_bytes())
    return h.hexdigest()


def film_task(H: float, quantity: str, lamP: float, c: float, lam_centre: float,
              nz: int, sources: str = "") -> float:
    """One film of a sequence as a task (H first: the task runner submits the thinnest,
    the longest, first): the solid's value on SOLID_MESH_COARSE with ``nz`` rows; a film
    that cannot be solved raises ConvergenceError naming it (the runner then fails the
    build naming the task: no NaN reaches the dataset). One thread for BLAS and NGSolve. ``sources``
    (:func:`film_sources`) is not used here: it is part of the task, so that a result
    kept by the runner's cache (``DEBENCH_FE_CACHE``) is never served for other code."""
    limit_threads()
    return study.film_value(quantity, lamP, c, H, lam_centre, dict(study.SOLID_MESH_COARSE, nz=nz))


def thickness(full: bool, scheduler: str | None = None) -> xr.Dataset:
    """Every film sequence of the thin solid the ``ch3.fe.thickness_*`` entries read
    (:data:`~debench.reference.studies.ch3_fe.THICKNESS_SEQUENCES`; ``full`` adds films
    and the edge layer resolved twice as finely): per film H the solid value, with the
    membrane FE (reference mesh), the in-plane mesh error of the limit, both analytic
    variants and the H -> 0 extrapolation with its uncertainty and observed order.
    ``scheduler``: where the films run (:func:`debench.reference.builders.ch5.build`)."""
    seqs = study.thickness_sequences(full)
    code = film_sources()
    tasks = [(film_task, float(h), s.quantity, float(s.lamP), float(s.c),
              float(s.lam_centre), int(s.nz), code) for s in seqs for h in s.films]
    cpu = time.process_time()
    films = iter(run_tasks(tasks, scheduler=resolve_scheduler(scheduler),
                           progress=sys.stderr.isatty()))
    print(f"  ch3_fe_thickness: {len(tasks)} films in {time.process_time() - cpu:.1f} s CPU "
          "(this process)", file=sys.stderr, flush=True)
    nf = max(len(s.films) for s in seqs)
    shape = (len(seqs), nf)
    H, val, diff = np.full(shape, np.nan), np.full(shape, np.nan), np.full(shape, np.nan)
    per = {k: np.empty(len(seqs)) for k in ("membrane_fe", "mesh_error", "printed", "membrane",
                                            "extrapolated", "extrapolated_observed_order",
                                            "extrapolation_error", "order")}
    for i, s in enumerate(seqs):
        vals = [next(films) for _ in s.films]
        d = study.thickness_study(s.quantity, s.lamP, s.films, dict(study.SOLID_MESH_COARSE, nz=s.nz),
                              s.lam_centre, c=s.c, values=vals)
        n = len(s.films)
        H[i, :n], val[i, :n], diff[i, :n] = s.films, d["values"], d["diff_membrane_fe"]
        for k in per:
            per[k][i] = d[k]
    a = lambda what: {"long_name": what, "units": "1"}  # noqa: E731
    seq = ("sequence",)
    what = ("the quantity of the sequence: phibar (Phibar at centre stretch lam_centre), "
            "pullin_phibar (Phibar at pull-in), loss_of_tension (centre stretch where the "
            "thickness-averaged radial stress at the centre vanishes)")
    vars_ = {
        "quantity": (seq, np.array([s.quantity for s in seqs]), {"long_name": what}),
        "lamP": (seq, np.array([s.lamP for s in seqs]), a("equibiaxial pre-stretch")),
        "c": (seq, np.array([s.c for s in seqs]), a("Zhao-Suo electrostrictive factor (3.27)")),
        "lam_centre": (seq, np.array([s.lam_centre for s in seqs]), a("centre stretch of circle A at which Phibar is compared (NaN: an event)")),
        "nz": (seq, np.array([s.nz for s in seqs]), a("element rows through the half thickness (edge elements H/(2 nz) square)")),
        "H": (("sequence", "film"), H, a("undeformed film thickness H/R_A (NaN: no such film)")),
        "value_solid": (("sequence", "film"), val, a("the quantity by the thin axisymmetric solid FE (NaN: no such film)")),
        "diff_membrane_fe": (("sequence", "film"), diff, a("solid minus membrane FE (reference mesh)")),
        "membrane_fe": (seq, per["membrane_fe"], a("the quantity by the membrane FE on the reference mesh")),
        "mesh_error": (seq, per["mesh_error"], a("membrane FE on the solid's in-plane mesh minus the reference: the error the H -> 0 limit inherits")),
        "value_printed": (seq, per["printed"], a("the quantity by the analytic model, Eq. (3.33) as printed")),
        "value_membrane": (seq, per["membrane"], a("the quantity by the analytic model, thin-membrane balance")),
        "extrapolated": (seq, per["extrapolated"], a("solid extrapolated to H -> 0 (Richardson, order 1, two thinnest films)")),
        "extrapolated_observed_order": (seq, per["extrapolated_observed_order"], a("solid extrapolated to H -> 0 at the observed order")),
        "extrapolation_error": (seq, per["extrapolation_error"], a("uncertainty of the extrapolation: |order-1 minus observed-order extrapolation| (at least 1e-6) + |mesh_error|")),
        "order_observed": (seq, per["order"], a("observed order in H of the solid values (three thinnest films)")),
    }
    ds = xr.Dataset(vars_, coords={
        "sequence": ("sequence", np.array([s.name for s in seqs]), {"long_name": "film sequence: quantity, pre-stretch, c, centre stretch, nz"}),
        "film": ("film", np.arange(nf), a("index of the film in its sequence (thickest first)"))})
    ds.attrs = {"model": "thin axisymmetric solid FE (models/circular/fe_solid.py) beside the membrane FE (models/circular/fe.py)",
                "solid_n_a": study.SOLID_MESH_COARSE["n_a"], "solid_n_b": study.SOLID_MESH_COARSE["n_b"],
                "membrane_n_b": study.MEMBRANE_REFERENCE_MESH["n_b"], "rk4_steps": study.ANALYTIC_STEPS}
    return ds



def build(out_dir: Path, *, full: bool = False, scheduler: str | None = None) -> list[Path]:
    """Write ``ch3_fe_thickness.nc`` to ``out_dir`` (``full``: more films and the edge layer
    resolved twice as finely; ``scheduler`` as :func:`debench.reference.builders.ch5.build`:
    None runs the films on a LocalCluster on a machine with more than one core)."""
    ds = thickness(full, scheduler)
    prm = study.dataset_parameters(full, **ds.attrs)
    ds.attrs = {}
    return [write_dataset(ds, NAME, title=TITLE, summary=SUMMARY, parameters=prm,
                          out_dir=Path(out_dir), overwrite=True)]
