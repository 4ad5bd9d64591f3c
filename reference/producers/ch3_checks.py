"""The qualitative Chapter 3 claims (Secs 3.5.1-3.5.6, Figs 3.2-3.9): one check per kind
of claim, named by the entry's ``parameters.check`` (:data:`CHECKS`), dispatched by
:func:`debench.reference.producers.ch3.qualitative`.

A check is ``check(entry, eps_r, equilibrium) -> (holds, detail)``: whether the claim holds
for that relative permittivity and annulus equilibrium variant, and what was found.
"""

from __future__ import annotations

import numpy as np
from debench.models.circular import circle_a
from debench.reference.catalogue import Entry
from debench.reference.producers.ch3_model import branch, curves, failure_modes, profiles
from debench.reference.studies import ch3 as study

#: c grid for the Fig. 3.9 sweeps (the thesis' Table 3.1 range 0 .. -0.1): the study's
C_SWEEP = tuple(float(c) for c in study.c_grid(False))


def parameter(entry: Entry, key: str, default=None):
    """The entry's parameter ``key`` (``default`` when the catalogue does not state it)."""
    return entry.parameters.get(key, default)


def _check_failure_modes(entry, eps_r, eq):
    lamP = parameter(entry, "lamP")
    cs = parameter(entry, "c_values")
    want = parameter(entry, "modes")
    fails = failure_modes(lamP, cs, eps_r, eq)
    got = [f.kind if f else None for f in fails]
    ok = got == want
    lams = [f.lam for f in fails if f]
    if parameter(entry, "same_stretch", False):
        ok = ok and max(lams) - min(lams) < 1e-9
    return ok, f"lamP={lamP}, c={cs}: modes {got} at stretches {[round(x, 4) for x in lams]}"


def _check_annulus_profile(entry, eps_r, eq):
    br = branch(parameter(entry, "lamP"), eq)
    ok = True
    msgs = []
    profs = profiles(parameter(entry, "lamP"), parameter(entry, "c"),
                     parameter(entry, "phibar"), eq)
    for c, (p1, p2) in zip((0.0, parameter(entry, "c")), profs, strict=True):
        mono = bool(np.all(np.diff(p1) > 0) and np.all(np.diff(p2) < 0))
        near = abs(p1[-1] - br.annulus.lamP) / br.annulus.lamP
        ok &= mono and near < parameter(entry, "rel_gap_at_RB")
        msgs.append(f"c={c}: l1 up/l2 down {mono}, |l1(RB)-lamP|/lamP={near:.3g}")
    return ok, "; ".join(msgs)


def _check_difference_decays(entry, eps_r, eq):
    prof = profiles(parameter(entry, "lamP"), parameter(entry, "c"), parameter(entry, "phibar"), eq)
    d1 = np.abs(prof[1][0] - prof[0][0])
    d3 = np.abs(1 / (prof[1][0] * prof[1][1]) - 1 / (prof[0][0] * prof[0][1]))
    ok = bool(np.all(np.diff(d1) < 0) and d1[-1] < 0.05 * d1[0] and d3[-1] < 0.05 * d3[0])
    return ok, f"|d lambda1| from {d1[0]:.3g} at R_A to {d1[-1]:.3g} at R_B"


def _check_pullin_vs_prestretch(entry, eps_r, eq):
    res = {}
    for lamP in parameter(entry, "with_pullin") + parameter(entry, "without_pullin"):
        cv = curves(lamP, (0.0,), eps_r, eq)[0]
        res[lamP] = not cv.pullin_suppressed
    ok = all(res[x] for x in parameter(entry, "with_pullin")) and not any(
        res[x] for x in parameter(entry, "without_pullin"))
    return ok, f"pull-in before loss of tension: {res}"


def _check_pullin_delayed_by_c(entry, eps_r, eq):
    cs = parameter(entry, "c_values")
    cvs = curves(parameter(entry, "lamP"), tuple(cs), eps_r, eq)
    pts = [(cv.events["pullin"].lam, cv.events["pullin"].phibar) for cv in cvs]
    ok = all(b[0] > a[0] and b[1] > a[1] for a, b in zip(pts, pts[1:], strict=False))
    return ok, f"pull-in (lam, Phibar) for c={cs}: {[(round(a, 4), round(b, 4)) for a, b in pts]}"


def _check_lot_independent_of_c(entry, eps_r, eq):
    cs = parameter(entry, "c_values")
    cvs = curves(parameter(entry, "lamP"), tuple(cs), eps_r, eq)
    lams = [cv.events["loss_of_tension"].lam for cv in cvs]
    return max(lams) - min(lams) < 1e-12, f"spread {max(lams) - min(lams):.2g}"


def _check_discrepancy_grows(entry, eps_r, eq):
    c = parameter(entry, "c")
    ok = True
    msgs = []
    prev = None
    for lamP in parameter(entry, "lamPs"):
        br = branch(lamP, eq)
        lam = br.lam[br.lam < min(f.lam for f in failure_modes(lamP, (0.0, c), eps_r, eq))]
        kap = br.annulus.kappa
        T1 = br.T1[: lam.size]
        with np.errstate(invalid="ignore", divide="ignore"):  # 0/0 at lam = lamP
            r = np.sqrt(circle_a.phibar_squared(lam, T1, c, kap) /
                        circle_a.phibar_squared(lam, T1, 0.0, kap))
        ok &= bool(np.all(np.diff(r[1:]) > 0))  # grows with the stretch
        # at a common actuated stretch lam/lamP
        ra = float(np.interp(parameter(entry, "actuated_stretch") * lamP, lam, r))
        if prev is not None:
            ok &= ra > prev
        prev = ra
        msgs.append(f"lamP={lamP}: ratio at lam/lamP={parameter(entry, 'actuated_stretch')} "
                    f"{ra:.4f}")
    return ok, "; ".join(msgs)


def failure_sweep(lamP, eps_r, eq):
    """First failures along :data:`C_SWEEP`: (kinds, stretches, Phibar values)."""
    fails = failure_modes(lamP, C_SWEEP, eps_r, eq)
    return [f.kind for f in fails], np.array([f.lam for f in fails]), np.array(
        [f.phibar for f in fails])


def _runs(kinds):
    """``kinds`` with consecutive repeats merged (the sequence of failure modes)."""
    out = []
    for k in kinds:
        if not out or out[-1] != k:
            out.append(k)
    return out


def _check_fig39(entry, eps_r, eq):
    """Fig. 3.9: sequence of failure modes as c decreases, and the trends within each."""
    lamP = parameter(entry, "lamP")
    kinds, lam, phi = failure_sweep(lamP, eps_r, eq)
    seq = _runs(kinds)
    ok = seq == parameter(entry, "mode_sequence")
    trend = parameter(entry, "lam_trend")  # per mode: "up", "flat", "down" as c decreases
    for mode, want in zip(parameter(entry, "mode_sequence"), trend, strict=False):
        sel = np.array([k == mode for k in kinds])
        if sel.sum() < 2:
            continue
        d = np.diff(lam[sel])
        ok &= {"up": bool(np.all(d > 0)), "down": bool(np.all(d < 0)),
               "flat": bool(np.all(np.abs(d) < 1e-9))}[want]
    if parameter(entry, "phibar_increases", False):
        ok &= bool(np.all(np.diff(phi) > 0))
    return ok, (f"lamP={lamP}: modes along c=0..-0.1 {seq}, failure stretch from "
                f"{lam[0]:.4f} to {lam[-1]:.4f}")


CHECKS = {
    "failure_modes": _check_failure_modes,
    "annulus_profile": _check_annulus_profile,
    "difference_decays": _check_difference_decays,
    "pullin_vs_prestretch": _check_pullin_vs_prestretch,
    "pullin_delayed_by_c": _check_pullin_delayed_by_c,
    "lot_independent_of_c": _check_lot_independent_of_c,
    "discrepancy_grows": _check_discrepancy_grows,
    "fig39": _check_fig39,
}
