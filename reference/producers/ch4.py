"""Producers for the Chapter 4 catalogue (``reference/catalogue/ch4.toml``).

Qualitative claims of Sec. 4.4-4.5 are evaluated with the variant of the coefficients
given in the entry's ``parameters.variant`` (default ``"printed"``: the thesis' printed
coefficients (4.54)-(4.60) in a consistent formulation with beta = 0.5, the closest
model to what the thesis computed). The outcome for the energy-consistent
``"derived"`` coefficients (and the ``"literal"`` equations) is reported in ``details``.
Unstable-region areas use the window of ``ch4.assumption.area_window``. Everything is
cached so the whole chapter evaluates in a few seconds.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from debench.models.plate import PlateParams, ellipticity_limit_stretch
from debench.models.plate.analysis import (
    biot_equibiaxial_closed_form,
    half_space_limit,
    region,
)
from debench.models.plate.ansatz import critical_stretches
from debench.models.plate.coefficients import coefficients
from debench.models.plate.voltage import critical_stretches_at_voltage, dhat_at_voltage
from debench.reference.catalogue import Accuracy, Entry, Outcome, readable
from debench.reference.producers import ch4_errata
from debench.reference.studies.ch4 import (
    FIG42_D,
    FIG45_XI,
    KH_MAX,
    XI_TI,
    area,
    critical_D,
    kH_grid,
    lam_grid,
    thin,
)

EV = "verification/test_ch4_claims.py"
EV_ERR = "verification/test_ch4_derivation.py"
#: Accuracy of every Chapter 4 value: roots of the ansatz determinant are refined by
#: brentq to 1e-13 and areas are sums over fixed grids, so a recomputation on another
#: CPU/BLAS moves a value by round-off in the determinant (measured < 1e-9 relative
#: between two OpenBLAS kernels); rtol 1e-7 keeps a 100x margin.
ACCURACY = Accuracy(rtol=1e-7, atol=1e-9, reason="ch4 determinant roots to 1e-13 on fixed "
                    "grids; cross-CPU spread < 1e-9 relative, 100x margin")


def _variant(entry: Entry) -> str:
    return entry.parameters.get("variant", "printed")


def _others(fn, entry: Entry):
    out = {}
    for v in ("derived", "printed", "literal"):
        try:
            out[v] = fn(v)
        except Exception as exc:  # noqa: BLE001 - reported, the entry's variant decides
            out[v] = f"{type(exc).__name__}: {exc}"
    return out


# ------------------------------------------------------------------ literature limits
def biot_limit(entry: Entry) -> Outcome:
    """kH -> inf, Dhat = 0, xi = 0: the half-space determinant root (method 1 rows)."""
    p = PlateParams(xi=0.0, Dhat=0.0, variant="derived")
    ours = half_space_limit(p)
    big = critical_stretches(200.0, p).lam
    return Outcome(ours, evidence="verification/test_ch4_limits.py::"
                   "test_thick_limit_is_biot_surface_instability",
                   details={"closed_form": biot_equibiaxial_closed_form(),
                            "roots_at_kH_200": big.tolist()})


def euler_limit(entry: Entry) -> Outcome:
    """kH -> 0, Dhat = 0, xi = 0: method-1 root at kH = 1e-3."""
    p = PlateParams(xi=0.0, Dhat=0.0, variant="derived")
    r = critical_stretches(1e-3, p).lam
    return Outcome(float(r.max()), evidence="verification/test_ch4_limits.py::"
                   "test_thin_limit_is_euler_buckling_with_plate_theory_slope")


# ------------------------------------------------------------------ qualitative claims
def ti_region_larger(entry: Entry) -> Outcome:
    """Sec. 4.4: 'the unstable region of the TI material was larger than that of the
    isotropic material under the same Dhat' (all nine Fig. 4.2 cases)."""
    def f(v):
        return {D: (area(XI_TI, D, v), area(0.0, D, v)) for D in FIG42_D}

    res = f(_variant(entry))
    ok = all(a > b for a, b in res.values())
    return Outcome(ok, diagnosis=f"areas (TI, iso): {readable(res)}", evidence=EV,
                   details={"areas_TI_iso": {str(k): v for k, v in res.items()}})


def destabilising_a_to_c(entry: Entry) -> Outcome:
    """Figs 4.2(a)-(c): the unstable region grows with Dhat = 0, 1, 2 (both materials)."""
    v = _variant(entry)
    res = {xi: [area(xi, D, v) for D in (0.0, 1.0, 2.0)] for xi in (0.0, XI_TI)}
    ok = all(np.all(np.diff(a) > 0) for a in res.values())
    return Outcome(ok, diagnosis=f"areas at Dhat=0,1,2: {readable(res)}", evidence=EV,
                   details={"areas": {str(k): a for k, a in res.items()}})


def upper_curve_higher_ti(entry: Entry) -> Outcome:
    """Sec. 4.4: 'the upper curve started at a higher value from kH close to 0 for the
    TI material' (Figs 4.2(a)-(c), Fig. 4.4)."""
    def f(v):
        return {D: (thin(XI_TI, D, v), thin(0.0, D, v)) for D in (0.0, 1.0, 2.0)}

    res = f(_variant(entry))
    ok = all(a > b + 1e-9 for a, b in res.values())
    other = _others(lambda v: {str(k): x for k, x in f(v).items()}, entry)
    return Outcome(ok, diagnosis=f"lam_cr(kH->0) (TI, iso): {readable(res)}", evidence=EV,
                   details={"by_variant": other})


def upper_discrepancy_decreases(entry: Entry) -> Outcome:
    """Sec. 4.4: 'the discrepancy between the upper curves for the two materials
    decreased as Dhat increased' (a)-(c), and 'decreased further' (d)-(i)."""
    Ds = entry.parameters.get("Dhat", [0.0, 1.0, 2.0])
    v = _variant(entry)
    gap = [thin(XI_TI, D, v) - thin(0.0, D, v) for D in Ds]
    ok = bool(np.all(np.diff(gap) < 0))
    return Outcome(ok, diagnosis=f"upper-curve gap at kH->0 for Dhat={readable(Ds)}: "
                   f"{readable(gap)}", evidence=EV, details={"gap": gap})


def thick_more_stable(entry: Entry) -> Outcome:
    """Figs 4.2(a)-(c): 'as kH increased, the unstable range of lam_cr reduced for both
    materials'. The lam-extent of the thesis region at kH = 0.1, 1, 5, 10 decreases."""
    v = _variant(entry)
    lam = lam_grid()
    kHs = np.array([0.1, 1.0, 5.0, 10.0])
    res = {}
    for xi in (0.0, XI_TI):
        for D in (0.0, 1.0, 2.0):
            r = region(PlateParams(xi=xi, Dhat=D, variant=v), kHs, lam)
            res[(xi, D)] = np.trapezoid(r.thesis.astype(float), lam, axis=1).tolist()
    ok = all(np.all(np.diff(x) <= 1e-12) and x[-1] < x[0] for x in res.values())
    return Outcome(ok, diagnosis=f"lam-extent at kH={readable(kHs)}: {readable(res)}", evidence=EV,
                   details={str(k): x for k, x in res.items()})


def iso_stabilising_d_to_i(entry: Entry) -> Outcome:
    """Figs 4.2(d)-(i): for the isotropic material the unstable region became smaller
    as Dhat increased (Dhat = 2.2 ... 5)."""
    v = _variant(entry)
    a = [area(0.0, D, v) for D in FIG42_D[3:]]
    ok = bool(np.all(np.diff(a) < 0))
    return Outcome(ok, diagnosis=f"iso areas at Dhat={readable(FIG42_D[3:])}: {readable(a)}",
                   evidence=EV, details={"areas": a})


def ti_change_at_f(entry: Entry) -> Outcome:
    """Sec. 4.4: 'for the TI material, the change occurred at a higher Dhat, which can be
    seen in case (f)' (Dhat = 2.6): the TI area is largest at Dhat = 2.6 among the nine
    cases while the isotropic one peaks earlier."""
    v = _variant(entry)
    ti = [area(XI_TI, D, v) for D in FIG42_D]
    iso = [area(0.0, D, v) for D in FIG42_D]
    d_ti, d_iso = FIG42_D[int(np.argmax(ti))], FIG42_D[int(np.argmax(iso))]
    ok = d_ti == 2.6 and d_iso < d_ti
    return Outcome(ok, diagnosis=f"TI area peaks at Dhat={d_ti:g}, isotropic at {d_iso:g}",
                   evidence=EV, details={"ti": ti, "iso": iso})


def field_destabilises_then_stabilises(entry: Entry) -> Outcome:
    """Sec. 4.5: increasing from zero, the field first destabilises then stabilises, for
    both materials: the area over the nine Dhat has an interior maximum."""
    v = _variant(entry)
    ok, where = True, {}
    for xi in (0.0, XI_TI):
        a = [area(xi, D, v) for D in FIG42_D]
        i = int(np.argmax(a))
        where[xi] = FIG42_D[i]
        ok &= 0 < i < len(a) - 1
    return Outcome(bool(ok), diagnosis=f"area maxima at {readable(where)}", evidence=EV,
                   details={"argmax": {str(k): x for k, x in where.items()}})


def anisotropy_raises_curves(entry: Entry) -> Outcome:
    """Fig. 4.5 (Dhat = 2): as xi = 0, 3, 5, 10 increases the upper curve (kH -> 0) is
    higher and the unstable region larger."""
    v = _variant(entry)
    up = [thin(xi, 2.0, v) for xi in FIG45_XI]
    ar = [area(xi, 2.0, v) for xi in FIG45_XI]
    ok = bool(np.all(np.diff(up) > 0) and np.all(np.diff(ar) > 0))
    return Outcome(ok, diagnosis=f"upper lam_cr(kH->0)={readable(up)}, areas={readable(ar)}",
                   evidence=EV, details={"upper": up, "areas": ar})


def upper_gap(xi: float, D: float, kH: float, variant: str = "printed") -> float:
    """TI minus isotropic upper critical stretch (largest root) at one kH, NaN without a
    root for either material."""
    ti = critical_stretches(kH, PlateParams(xi, D, variant=variant)).lam
    iso = critical_stretches(kH, PlateParams(0.0, D, variant=variant)).lam
    return float(ti.max() - iso.max()) if ti.size and iso.size else float("nan")


#: the thin and the thick plate of the comparison (the ends of the Figs 4.2/4.5 kH axis)
KH_THIN, KH_THICK = 0.1, 10.0


def thin_plates_more_affected(entry: Entry) -> Outcome:
    """Sec. 4.4 on Fig. 4.5 ("anisotropy increased the risk of bifurcation instability,
    especially for thin plates. Similar conclusions can be drawn under larger electric
    field"), summed up in Sec. 4.5: for each xi of Fig. 4.5 at its Dhat, the TI - isotropic
    gap of the upper critical stretch is larger in magnitude for the thin plate
    (kH = KH_THIN) than for the thick one (KH_THICK). The same comparison at the larger
    fields of Fig. 4.2 (``larger_Dhat``, xi = 5) is reported in details."""
    v = _variant(entry)
    D = float(entry.parameters["Dhat"])
    out = {f"xi{xi:g}": (upper_gap(float(xi), D, KH_THIN, v), upper_gap(float(xi), D, KH_THICK, v))
           for xi in entry.parameters["xi"]}
    holds = {k: abs(a) > abs(b) for k, (a, b) in out.items()}
    larger = {f"D{d:g}": (upper_gap(XI_TI, float(d), KH_THIN, v),
                          upper_gap(XI_TI, float(d), KH_THICK, v))
              for d in entry.parameters["larger_Dhat"]}
    larger_holds = {k: abs(a) > abs(b) for k, (a, b) in larger.items()}
    return Outcome(all(holds.values()), diagnosis=entry.diagnosis, evidence=EV,
                   details={"gaps": out, "holds": holds, "larger_field_gaps_xi5": larger,
                            "larger_field_holds": larger_holds,
                            "failing": [k for k, h in holds.items() if not h]})


def critical_D_increases(entry: Entry) -> Outcome:
    """Fig. 4.6: the critical Dhat (field turns from destabilising to stabilising)
    increases with xi = 0, 3, 5, 10, for both candidate definitions."""
    v = _variant(entry)
    res = {c: [critical_D(xi, c, v) for xi in FIG45_XI]
           for c in ("max_area", "thin_extensional")}
    ok = all(bool(np.all(np.diff(x) > 0)) for x in res.values())
    return Outcome(ok, diagnosis=f"critical Dhat at xi={readable(FIG45_XI)}: {readable(res)}",
                   evidence=EV, details=res)


def critical_D_value(entry: Entry) -> Outcome:
    """Fig. 4.6 point: the value is only in the figure image (not transcribable); ours is
    reported for both candidate definitions."""
    xi = float(entry.parameters["xi"])
    v = _variant(entry)
    ours = {c: critical_D(xi, c, v) for c in ("max_area", "thin_extensional")}
    return Outcome(ours["max_area"],
                   diagnosis="value only in the image of Fig. 4.6 (not in the text); "
                   f"ours: {readable(ours)}", details=ours)


def thin_limit_value(entry: Entry) -> Outcome:
    """Fig. 4.4 bar: lam_cr(kH -> 0); the printed bars are only in the figure image."""
    xi, D = float(entry.parameters["xi"]), float(entry.parameters["Dhat"])
    ours = _others(lambda v: thin(xi, D, v), entry)
    return Outcome(ours[_variant(entry)],
                   diagnosis="value only in the image of Fig. 4.4; ours by variant: "
                   f"{readable(ours, 11)}",
                   details=ours)


def area_values(entry: Entry) -> Outcome:
    """Fig. 4.3: AutoCAD areas, only in the figure image; ours in data/ch4_areas.nc."""
    v = _variant(entry)
    ours = {f"xi{xi:g}_D{D:g}": area(xi, D, v) for xi in (0.0, XI_TI) for D in FIG42_D}
    return Outcome(None, diagnosis="areas only in the image of Fig. 4.3 and the thesis window is "
                   "not stated; ours (thesis definition, window ch4.assumption.area_window)"
                   f": {readable(ours)}", details=ours)


def bicubic_independent_of_D(entry: Entry) -> Outcome:
    """(4.63) does not contain Dhat: with alpha = 0 the roots s of det M(s) = 0 are the
    same for every Dhat (checked numerically on the full 2x2 symbol)."""
    def roots(D):
        a, b2, c, d, e, f, g = (float(x) for x in coefficients(
            np.array(1.3), PlateParams(xi=5.0, Dhat=D, variant="derived")))
        # det [[a - b2 s^2 + c s^4, s(e - d - d s^2)], [.., f s^2 - g]] as poly in s
        P11 = np.array([c, 0, -b2, 0, a])
        P12 = np.array([-d, 0, e - d, 0])
        P22 = np.array([f, 0, -g])
        det = np.polysub(np.polymul(P11, P22), np.polymul(P12, P12))
        return np.sort_complex(np.roots(det))

    r0, r3 = roots(0.0), roots(3.0)
    ok = bool(np.allclose(r0, r3, rtol=1e-9))
    return Outcome(ok, evidence=EV_ERR, details={"roots_D0": r0.tolist()})


def ellipticity_of_ti_curves(entry: Entry) -> Outcome:
    """Implicit in Figs 4.2/4.5: the TI bifurcation curves are well posed, i.e. lie where
    the energy (4.22) is strongly elliptic. Ours: the energy (4.22) with xi = 5 loses
    strong ellipticity at lam_E = (2 xi/(2 xi - 1))^(1/4); the TI upper curves of the
    thesis (printed coefficients) start above it."""
    lamE = ellipticity_limit_stretch(PlateParams(xi=XI_TI, variant="derived"))
    ups = [thin(XI_TI, D, "printed") for D in (0.0, 1.0, 2.0)]
    ok = all(u < lamE for u in ups)
    return Outcome(ok, diagnosis=f"(4.22) with xi=5 is not strongly elliptic for lam > "
                   f"{lamE:.6f}; the printed-coefficient TI upper curves start at "
                   f"{readable(ups)}",
                   evidence="verification/test_ch4_limits.py::"
                   "test_derived_model_loses_ellipticity_at_closed_form_stretch",
                   details={"lam_E": lamE, "upper": ups})


def parameters_used(entry: Entry) -> Outcome:
    """The model's default parameters are the thesis' alpha = 0, beta = 0.5 (Sec. 4.4):
    status "input" (checked against the stated value, not a reproduction)."""
    d = PlateParams()
    return Outcome(f"alpha = {d.alpha:g}, beta = {d.beta:g}", status="input",
                   diagnosis="debench.models.plate.PlateParams defaults")


def erratum(entry: Entry) -> Outcome:
    """Run the erratum's check (:mod:`.ch4_errata`, the same function as its evidence test):
    ``confirmed`` when the printed form fails and the corrected one holds, ``refuted``
    when the printed form holds; a correction that fails too is an error."""
    key = entry.id.removeprefix("ch4.erratum.")
    chk = ch4_errata.CHECKS[key]()
    if chk.printed_wrong and not chk.corrected_right:
        raise RuntimeError(f"{entry.id}: the corrected form fails its check too: {chk.details}")
    return Outcome(chk.printed_wrong, status="confirmed" if chk.confirmed else "refuted",
                   evidence=entry.evidence, details=chk.details)


def area_window_sensitivity(entry: Entry) -> Outcome:
    """Assumption ch4.assumption.area_window: areas for kH_max = 5, 10, 20."""
    sens = {f"kHmax{k:g}": [area(xi, 2.0, "printed", "thesis", k) for xi in (0.0, XI_TI)]
            for k in (5.0, 10.0, 20.0)}
    sens.update({f"lam_min{m:g}": [area(xi, 2.0, "printed", "thesis", KH_MAX, m)
                                   for xi in (0.0, XI_TI)] for m in (0.3, 0.5)})
    return Outcome(KH_MAX, status="assumed",
                   diagnosis="thesis-definition areas at Dhat=2 (iso, TI) by window: "
                   f"{readable(sens)}",
                   details=sens)


def critical_D_candidates(entry: Entry) -> Outcome:
    res = {c: [critical_D(xi, c, "printed") for xi in FIG45_XI]
           for c in ("max_area", "thin_extensional")}
    spread = [abs(a - b) for a, b in zip(*res.values(), strict=True)]
    return Outcome("max_area", status="assumed",
                   diagnosis=f"candidates at xi={readable(FIG45_XI)}: {readable(res)}; "
                   f"|difference| {readable(spread)}",
                   details=res)


#: the cases of Fig. 4.2 whose areas the text ranks: the isotropic region grows over
#: (a)-(c) and shrinks over (d)-(i), so it is largest at (c); the TI one changes "at a
#: higher Dhat, which can be seen in case (f)"
FIG42_CASES = "abcdefghi"


def area_peaks(beta: float, kH_max: float = KH_MAX, variant: str = "printed") -> dict:
    """Dhat of the largest unstable-region area (thesis definition) among the nine
    Fig. 4.2 cases, isotropic and TI, computed with ``beta`` in the boundary rows."""
    out = {}
    for name, xi in (("iso", 0.0), ("ti", XI_TI)):
        a = [region(PlateParams(xi=xi, Dhat=D, variant=variant, beta=beta), kH_grid(kH_max),
                    lam_grid()).area("thesis") for D in FIG42_D]
        out[name] = FIG42_D[int(np.argmax(a))]
    return out


def hypothesis_beta_in_rows(entry: Entry) -> Outcome:
    """Did the thesis compute Figs 4.2/4.3 with beta in the boundary rows (so that the
    printed (4.75)-(4.80), which lack it, are not what was computed)? The area peaks under
    beta = 0.5 (Sec. 4.4) and under the rows as printed (beta = 1), against the cases the
    text names; ``explained`` when beta = 0.5 gives both and the printed rows do not.
    Value: the TI peak under beta = 0.5 (the text: case (f)); the window's kH_max varied in
    details."""
    p = entry.parameters
    text = {"iso": FIG42_D[FIG42_CASES.index(p["case_iso"])],
            "ti": FIG42_D[FIG42_CASES.index(p["case_ti"])]}
    by_beta = {f"beta{b:g}": area_peaks(float(b)) for b in p["betas"]}
    window = {f"beta{b:g}_kHmax{k:g}": area_peaks(float(b), k)
              for b in p["betas"] for k in (5.0, 20.0)}
    stated, printed_rows = (by_beta[f"beta{b:g}"] for b in p["betas"])
    explained = stated == text and printed_rows != text
    return Outcome(stated["ti"], status="explained" if explained else "unexplained",
                   diagnosis=entry.diagnosis, evidence=EV,
                   details={"text": text, "peaks": by_beta, "window": window,
                            "compared_with": text["ti"],
                            "compared_as": f"case ({p['case_ti']}) of the text"})


__all__ = [n for n in dir() if not n.startswith("_")] + ["replace"]


def voltage_control_bc(entry: Entry) -> Outcome:
    """Voltage control of the electroded plate: every root of the voltage-controlled
    determinant is a root of the charge-controlled one at Dhat = Vhat lam^2/beta, i.e.
    the incremental boundary conditions are the same (value False = they do not differ)."""
    v = _variant(entry)
    worst = 0.0
    for xi in entry.parameters["xi"]:
        p = PlateParams(float(xi), 0.0, variant=v)
        for V in entry.parameters["Vhat"]:
            for kH in (0.5, 3.0):
                lam, _ = critical_stretches_at_voltage(kH, float(V), p, n_scan=200)
                for lv in lam:
                    cc = critical_stretches(kH, PlateParams(float(xi), float(
                        dhat_at_voltage(lv, float(V), p)), variant=v)).lam
                    worst = max(worst, float(np.min(np.abs(cc - lv))))
    same = worst < 1e-9
    return Outcome(not same, diagnosis=f"{entry.diagnosis}; max distance of a "
                   f"voltage-control root to the charge-control curve of its Dhat: {worst:.2e}",
                   evidence="verification/test_ch4_methods.py::"
                   "test_voltage_control_roots_agree_between_methods")
