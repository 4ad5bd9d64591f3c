"""Run the confirmation of every reference quantity and write what it measured to
``reference/confirmations.json`` (``debench.reference.confirmations``).

Each ``[[quantity.confirmation]]`` of a problem spec with ``status = "confirmed"`` names the
test that asserts an independent computation (a clean room of ``verification/cleanroom/``)
against the reference at the stated accuracy. This tool runs the same computation (the
clean-room functions the test calls, at the test's points), compares it with the
reference by :func:`debench.reference.comparison.compare` (what ``debench check`` and the
tests apply: the stated accuracy, full coverage) and records per quantity: the number of values, the
largest |difference|, the largest |difference| / stated accuracy (the ratio; the test
passes when it is <= 1) and where, the CPU seconds of the computation, the git commit,
the date, the sha256 of the datasets compared with and the command that reproduces it.

    python tools/confirm.py            # the default-tier confirmations
    python tools/confirm.py --full     # and the slow ones
    python tools/confirm.py --problem lit_balloon --full
    python tools/confirm.py --problem ch2_kernel_states --merge a.json --merge b.json

A confirmation not run keeps its last record (if its spec is unchanged), from the output
file or from the ``--merge`` files (outputs of runs of single problems in parallel). Run from a
clone (it imports ``verification.cleanroom``); commit the specs first, so the records name
a clean commit.
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

TC = "verification/test_cleanroom.py"
TB = "verification/test_cleanroom_balloon.py"
TP = "verification/test_cleanroom_pullin.py"
TM = "verification/test_mms.py"
TW = "verification/test_cleanroom_wrinkling.py"
TL = "verification/test_cleanroom_bilayer.py"

#: a computation: problem id -> {quantity: (values, coords)} at the test's points
Computation = Callable[[str], dict]


def _ref(problem_id: str, quantity: str) -> dict:
    from debench.reference import problems, problems_reference

    return problems_reference.reference_json(problems.get(problem_id))["reference"][quantity]


# ------------------------------------------------------------------ the computations
def free_membrane(Jm: float, top: float) -> Computation:
    """test_cleanroom_free_membrane_passes_check: the grid's 401 stretches."""
    def run(problem_id):
        from verification.cleanroom import free_membrane as cr

        lam = np.linspace(1.0, top, 401)
        return {"phibar": (cr.phibar(lam, Jm, top), {"lam": lam})}
    return run


def kernel(problem_id):
    """test_cleanroom_kernel_passes_check: W and sigma of six materials at five states."""
    from verification.cleanroom import kernel as cr

    w, s = [], []
    for m in cr.MATERIALS:
        for st in cr.STATES:
            w.append((m, st, cr.energy(m, st)))
            sig = cr.stress(m, st)
            s += [(m, st, i, a, sig[i][a]) for i in range(3) for a in range(3)]
    mw, sw, vw = zip(*w, strict=True)
    ms, ss, i, a, vs = zip(*s, strict=True)
    return {"W": (np.array(vw, float), {"material": np.array(mw), "state": np.array(sw)}),
            "sigma": (np.array(vs, float), {"material": np.array(ms), "state": np.array(ss),
                                            "i": np.array(i), "alpha": np.array(a)})}


def voltage_stretch(problem_id):
    """test_cleanroom_voltage_stretch_passes_check_everywhere: every lamP and c at the
    published stretches."""
    from verification.cleanroom import voltage_stretch as cr

    ref = _ref(problem_id, "phibar")
    lamP_grid, c_grid = ref["coords"]["lamP"], ref["coords"]["c"]
    cols = ([], [], [], [])
    for lamP in lamP_grid:
        lam = np.array(ref["along"]["values"][lamP_grid.index(lamP)], dtype=float)
        tb = cr.interface(lam, lamP, problem_id.endswith("as_printed"))
        for c in c_grid:
            ph = cr.phibar_from_interface(lam, tb, c)
            ok = np.isfinite(ph)
            for col, v in zip(cols, ([lamP] * ok.sum(), [c] * ok.sum(), lam[ok], ph[ok]),
                              strict=True):
                col.extend(v)
    lamP, c, lam, ph = (np.array(x, dtype=float) for x in cols)
    return {"phibar": (ph, {"lamP": lamP, "c": c, "lambda_a": lam})}


def failure_points(problem_id):
    """test_cleanroom_failure_points_pass_check_everywhere: every lamP and c, the events
    the clean room finds."""
    from verification.cleanroom import voltage_stretch as cr

    ref = _ref(problem_id, "pullin_lambda")
    rows: dict[str, list] = {}
    for lamP in ref["coords"]["lamP"]:
        cs = [c for c in ref["coords"]["c"] if 1 + c * (2.5 * lamP - 2) > 0]
        for (c, kind), (lam, ph) in cr.events(lamP, cs).items():
            rows.setdefault(f"{kind}_lambda", []).append((lamP, c, lam))
            rows.setdefault(f"{kind}_phibar", []).append((lamP, c, ph))
    out = {}
    for name, r in rows.items():
        lamP, c, v = (np.array(x, dtype=float) for x in zip(*r, strict=True))
        out[name] = (v, {"lamP": lamP, "c": c})
    return out


#: worker processes of the plate computations (``--jobs``; 1: in this process)
JOBS = 1


def _plate_curve(args):
    """The roots of one curve (variant, xi, D) at every kH (a worker's task: every root,
    or root 0 only) and the worker's CPU seconds."""
    from verification.cleanroom import plate as cr

    variant, xi, D, kH, voltage, every_root = args
    t0 = time.process_time()
    rows = []
    for k in kH:
        r = cr.roots(k, xi, D, voltage=voltage, variant=variant)
        for j, x in enumerate(r if every_root else r[:1]):
            rows.append((variant, xi, D, j, k, float(x)))
    return rows, time.process_time() - t0


def plate(voltage: bool, every_root: bool = True) -> Computation:
    """test_cleanroom_plate_voltage_control_passes_check_on_every_curve: every root of
    every curve of both stored variants at every published kH;
    test_cleanroom_plate_every_root_of_every_variant: every root of every curve of the
    three stored variants at every published kH;
    test_cleanroom_plate_passes_check_on_every_curve (``every_root`` False): root 0 of
    every curve of the variant 'derived' at every published kH (curves in JOBS processes:
    the CPU seconds are the workers' sum, in ``run.worker_cpu``)."""
    def run(problem_id):
        ref = _ref(problem_id, "lam_cr")
        field = "Vhat" if voltage else "Dhat"
        kH = [float(k) for k in ref["coords"]["kH"]]
        variants = ref["coords"]["variant"] if every_root else ["derived"]
        tasks = [(str(v), float(xi), float(D), kH, voltage, every_root) for v in variants
                 for xi in ref["coords"]["xi"] for D in ref["coords"][field]]
        if JOBS > 1:
            from concurrent.futures import ProcessPoolExecutor

            with ProcessPoolExecutor(JOBS) as pool:
                done = list(pool.map(_plate_curve, tasks))
            run.worker_cpu = sum(c for _, c in done)
        else:
            done = [_plate_curve(t) for t in tasks]
        rows = [r for part, _ in done for r in part]
        variant, xi, D, root, k, lam = zip(*rows, strict=True)
        coords = {"xi": np.array(xi, dtype=float), field: np.array(D, dtype=float),
                  "kH": np.array(k, dtype=float)}
        if every_root:
            coords.update(variant=np.array(variant), root=np.array(root, dtype=int))
        return {"lam_cr": (np.array(lam, dtype=float), coords)}
    return run


def balloon(which: str) -> Computation:
    """test_cleanroom_balloon: the clean room at every stored point of the curves
    (``pbar``), the pressure extrema or the voltage limit points."""
    def run(problem_id):
        from debench.reference.datasets import read_dataset

        from verification.cleanroom import balloon as cr

        ds = read_dataset(problem_id)

        def jm_of(jm):
            return None if math.isinf(jm) else float(jm)

        if which == "pbar":
            cols = ([], [], [], [])
            for jm in ds.Jm.values:
                lam = ds.lam.sel(Jm=jm).values
                for vb in ds.vbar.values:
                    y = [float(cr.pressure(x, vb, jm_of(jm))) for x in lam]
                    for col, v in zip(cols, ([jm] * lam.size, [vb] * lam.size, lam, y),
                                      strict=True):
                        col.extend(v)
            jm, vb, lam, y = (np.array(x, dtype=float) for x in cols)
            return {"pbar": (y, {"Jm": jm, "vbar": vb, "lam": lam})}
        if which == "extrema":
            keys = {"lam_pmax": ("max", 0), "pbar_max": ("max", 1),
                    "lam_pmin": ("min", 0), "pbar_min": ("min", 1)}
            vals = {k: [] for k in keys}
            jms, vbs = [], []
            for jm in ds.Jm.values:
                for vb in ds.vbar.values:
                    found = cr.pressure_extrema(vb, jm_of(jm))
                    jms.append(jm)
                    vbs.append(vb)
                    for name, (kind, i) in keys.items():   # NaN: no extremum found
                        vals[name].append(math.nan if found[kind] is None
                                          else float(found[kind][i]))
            coords = {"Jm": np.array(jms, float), "vbar": np.array(vbs, float)}
            return {k: (np.array(v, float), coords) for k, v in vals.items()}
        jms, pfs, lam, v = [], [], [], []
        for jm in ds.Jm.values:
            for pf in ds.pbar_fixed.values:
                found = cr.voltage_limit(pf, jm_of(jm))
                jms.append(jm)
                pfs.append(pf)
                lam.append(math.nan if found is None else float(found[0]))
                v.append(math.nan if found is None else float(found[1]))
        coords = {"Jm": np.array(jms, float), "pbar_fixed": np.array(pfs, float)}
        return {"lam_vmax": (np.array(lam), coords), "vbar_max": (np.array(v), coords)}
    return run


def critical_voltage(wavenumber: int) -> Computation:
    """test_cleanroom_buckling(_n1)_converged_confirms_reference_at_stated_accuracy: the
    buckling clean room's converged critical voltage of every case (P4, N x N/4 for
    N = 16, 24, 32, 40, 15 corner refinements, Richardson-extrapolated) in wavenumber 0
    (v_cr) or 1 (v_cr_n1)."""
    def run(problem_id):
        from verification.cleanroom import buckling as cr
        from verification.cleanroom import buckling_n1 as cr1

        conv = cr.converged_critical_voltage if wavenumber == 0 else \
            cr1.converged_critical_voltage
        name = "v_cr" if wavenumber == 0 else "v_cr_n1"
        values = np.array([conv(case).value for case in cr.CASES])
        return {name: (values, {"case": np.array(cr.CASES)})}
    return run


def pullin_refined(problem_id):
    """test_cleanroom_pullin_passes_check_refined[p4_40x8]: the pull-in clean room's voltage
    maximum (v and w) of both films on its refined discretisation (P4, 40 x 8, 6 corner
    refinements)."""
    from verification.cleanroom import pullin as cr
    from verification.test_cleanroom_pullin import PULLIN_REFINED

    res = {c: cr.pullin(c, **PULLIN_REFINED["p4_40x8"]) for c in cr.CASES}
    coords = {"case": np.array(cr.CASES)}
    return {"v_pullin": (np.array([res[c].v_pullin for c in cr.CASES]), coords),
            "w_pullin": (np.array([res[c].w_pullin for c in cr.CASES]), coords)}


def mms_orders(problem_id):
    """test_cleanroom_scikit_fem_orders_on_the_spec_levels: the clean room's four orders
    fitted over the finest three of h = 1/8 .. 1/64 at every degree of the reference grid
    (p = 1, 2, 3) for both materials. The reference depends on the degree alone, so each
    degree gives one value per quantity: that of the material whose order lies farther
    from the reference (both are within the stated accuracy exactly when it is)."""
    from verification.test_mms import MATERIALS, cleanroom_spec_fits

    columns = ("u_L2", "u_H1", "phi_L2", "phi_H1")
    refs = {c: _ref(problem_id, f"{c}_order") for c in columns}
    degrees = [int(d) for d in refs["u_L2"]["coords"]["degree"]]
    fits = {(m, p): cleanroom_spec_fits(m, p) for m in MATERIALS for p in degrees}
    out = {}
    for c in columns:
        ref = refs[c]
        expected = dict(zip((int(d) for d in ref["coords"]["degree"]), ref["values"],
                            strict=True))
        worst = [max((fits[m, p][c].order for m in MATERIALS),
                     key=lambda x, p=p: abs(x - expected[p])) for p in expected]
        out[f"{c}_order"] = (np.array(worst), {"degree": np.array(list(expected), float)})
    return out


def wrinkling_refined(disc: str) -> Computation:
    """test_cleanroom_wrinkling_passes_check_refined[disc]: the wrinkling clean room's first
    zero (w and v) of every wavenumber with a reference value on that refined
    discretisation."""
    def run(problem_id):
        from verification.cleanroom import wrinkling as cr
        from verification.test_cleanroom_wrinkling import CROSSING_N, WRINKLING_REFINED

        res = cr.crossings(**WRINKLING_REFINED[disc], wavenumbers=CROSSING_N)
        coords = {"case": np.array(["ogden_r20"] * len(res.wavenumbers)),
                  "n": np.array(res.wavenumbers)}
        return {"w_cross": (np.asarray(res.w_cross, float), coords),
                "v_cross": (np.asarray(res.v_cross, float), coords)}
    return run


def bilayer_q8(problem_id):
    """test_cleanroom_bilayer_passes_check_at_the_stated_accuracy[q8_12x2]: the
    quadrilateral bilayer clean room's tip deflection and rotation at the six stored
    voltages (Q8, 12 x 2 per layer, 2 geometric layers of ratio 0.15)."""
    from verification.cleanroom import bilayer_quad as cr
    from verification.test_cleanroom_bilayer import DISCRETISATIONS

    r = cr.solve(cr.VOLTAGES, **DISCRETISATIONS["q8_12x2"])
    coords = {"v": np.asarray(r.voltages, float)}
    return {"tip_deflection": (np.asarray(r.tip_deflection), coords),
            "tip_rotation": (np.asarray(r.tip_rotation), coords)}


#: the test each computation reproduces -> the computation
COMPUTATIONS: dict[str, Computation] = {
    f"{TC}::test_cleanroom_free_membrane_passes_check[ch3_free_membrane_nh-inf-5.0]":
        free_membrane(np.inf, 5.0),
    f"{TC}::test_cleanroom_free_membrane_passes_check[ch3_free_membrane_gent-120.0-7.8]":
        free_membrane(120.0, 7.8),
    f"{TC}::test_cleanroom_kernel_passes_check": kernel,
    f"{TC}::test_cleanroom_voltage_stretch_passes_check_everywhere[ch3_voltage_stretch]":
        voltage_stretch,
    f"{TC}::test_cleanroom_voltage_stretch_passes_check_everywhere"
    "[ch3_voltage_stretch_as_printed]": voltage_stretch,
    f"{TC}::test_cleanroom_failure_points_pass_check_everywhere": failure_points,
    f"{TC}::test_cleanroom_plate_passes_check_on_every_curve": plate(voltage=False,
                                                                    every_root=False),
    f"{TC}::test_cleanroom_plate_every_root_of_every_variant": plate(voltage=False),
    f"{TC}::test_cleanroom_plate_voltage_control_passes_check_on_every_curve":
        plate(voltage=True),
    f"{TC}::test_cleanroom_buckling_converged_confirms_reference_at_stated_accuracy":
        critical_voltage(0),
    f"{TC}::test_cleanroom_buckling_n1_converged_confirms_reference_at_stated_accuracy":
        critical_voltage(1),
    f"{TP}::test_cleanroom_pullin_passes_check_refined[p4_40x8]": pullin_refined,
    f"{TW}::test_cleanroom_wrinkling_passes_check_refined[p4_40x4]":
        wrinkling_refined("p4_40x4"),
    f"{TB}::test_pressure_curves_match_the_clean_room_at_the_stated_accuracy":
        balloon("pbar"),
    f"{TB}::test_pressure_extrema_match_the_clean_room_at_the_stated_accuracy":
        balloon("extrema"),
    f"{TB}::test_voltage_limit_points_match_the_clean_room_at_the_stated_accuracy":
        balloon("limit"),
    f"{TM}::test_cleanroom_scikit_fem_orders_on_the_spec_levels": mms_orders,
    f"{TL}::test_cleanroom_bilayer_passes_check_at_the_stated_accuracy[q8_12x2]": bilayer_q8,
}


# ------------------------------------------------------------------ measuring
def _plain(x):
    if isinstance(x, np.generic):
        return x.item()
    return x


def measure(problem_id: str, test: str) -> dict[str, dict]:
    """Run the computation of ``test`` once and compare each quantity it gives with the
    reference at the stated accuracy (full coverage): {quantity: measurement}."""
    from debench.reference.comparison import compare

    computation = COMPUTATIONS[test]
    t0 = time.process_time()
    results = computation(problem_id)
    cpu = time.process_time() - t0 + getattr(computation, "worker_cpu", 0.0)
    if hasattr(computation, "worker_cpu"):
        del computation.worker_cpu
    out = {}
    for name, (values, coords) in results.items():
        cmp = compare(problem_id, name, values, coords, coverage="full")
        err = np.abs(cmp.error)
        ratio = cmp.ratio
        i = int(np.argmax(ratio))
        out[name] = {
            "points": int(cmp.values.size),
            "max_abs_difference": float(np.nanmax(err)) if np.isfinite(err).any() else 0.0,
            "ratio": float(ratio.max()),
            "worst_at": {k: _plain(v[i]) for k, v in cmp.coords.items()},
            "cpu_seconds": round(cpu, 3),
            "shared_with": sorted(set(results) - {name}),
        }
    return out


def _datasets(problem) -> dict[str, str]:
    from debench.reference.datasets import data_dir, read_manifest

    manifest = read_manifest(data_dir())
    return {d: manifest.get(f"{d}.nc", {}).get("sha256", "missing") for d in problem.datasets}


def run(full: bool, only: list[str] | None, path: Path, quiet: bool = False,
        earlier: tuple[Path, ...] = ()) -> dict:
    """Measure the confirmations (default tier; ``full``: also the slow ones) of the
    problems ``only`` (None: all) and return the JSON, keeping the last record of those
    not run: from ``path``, else from the ``earlier`` outputs of this tool (runs of single
    problems in parallel, merged), when the spec record is unchanged."""
    from debench.reference import confirmations, problems
    from debench.reference.provenance import git_commit

    sources = [json.loads(f.read_text(encoding="utf-8")) for f in (path, *earlier)
               if f.exists()]
    commit = git_commit(ROOT)
    today = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%dT%H:%M:%SZ")
    doc = {"about": "written by tools/confirm.py: what each confirmation of "
                    "reference/problems/*.toml measured (debench.reference.confirmations)",
           "problems": {}}
    cache: dict[tuple[str, str], dict] = {}
    for p in problems.load_all():
        sums = _datasets(p)
        for q in p.quantities:
            recs = []
            for spec in q.confirmation:
                rec = {k: spec[k] for k in confirmations.SPEC_FIELDS if k in spec}
                prev = next((r for doc in sources
                             for r in doc["problems"].get(p.id, {}).get(q.name, [])
                             if {k: r.get(k) for k in rec} == rec and "ratio" in r), None)
                if spec["status"] == "confirmed":
                    wanted = (only is None or p.id in only) and (full or spec["tier"] == "default")
                    if wanted:
                        key = (p.id, spec["test"])
                        if key not in cache:
                            if not quiet:
                                print(f"{p.id}: {spec['test']} ...", flush=True)
                            cache[key] = measure(p.id, spec["test"])
                        if q.name not in cache[key]:
                            raise RuntimeError(f"{spec['test']} gives no {q.name}")
                        rec.update(cache[key][q.name], commit=commit, date=today,
                                   datasets=sums)
                        if not quiet:
                            m = cache[key][q.name]
                            print(f"  {q.name}: max |diff| {m['max_abs_difference']:.3g}, "
                                  f"ratio {m['ratio']:.3g}, {m['cpu_seconds']:.3g} s",
                                  flush=True)
                    elif prev is not None:
                        rec = prev
                recs.append(rec)
            doc["problems"].setdefault(p.id, {})[q.name] = recs
    return doc


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--full", action="store_true", help="also the slow-tier confirmations")
    ap.add_argument("--problem", action="append", help="only this problem (repeatable)")
    ap.add_argument("--output", type=Path, default=None,
                    help="where to write (default reference/confirmations.json)")
    ap.add_argument("--merge", type=Path, action="append", default=[],
                    help="an earlier output of this tool whose records (of unchanged specs) "
                         "are kept where this run measures none (repeatable)")
    ap.add_argument("--jobs", type=int, default=1,
                    help="worker processes of the plate computations (CPU seconds summed)")
    args = ap.parse_args(argv)
    from debench.reference import confirmations

    global JOBS
    JOBS = max(1, args.jobs)

    path = args.output or ROOT / "reference" / confirmations.PATH.name
    doc = run(args.full, args.problem, path, earlier=tuple(args.merge))
    path.write_text(json.dumps(doc, indent=1, ensure_ascii=False) + "\n", encoding="utf-8")
    bad = [(pid, q, r["test"]) for pid, qs in doc["problems"].items() for q, rs in qs.items()
           for r in rs if r.get("ratio", 0.0) > 1]
    unmeasured = [(pid, q) for pid, qs in doc["problems"].items() for q, rs in qs.items()
                  for r in rs if r["status"] == "confirmed" and "ratio" not in r]
    print(f"wrote {path}")
    if unmeasured:
        print(f"not measured (slow: --full): {unmeasured}")
    if bad:
        print(f"ABOVE the stated accuracy: {bad}")
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
