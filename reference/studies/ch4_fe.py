"""The Chapter 4 finite-element study (the ``ch4.fe.*`` entries, whose producers are
:mod:`debench.reference.producers.ch4_fe`): the plane-strain strip FE model (method 3,
:mod:`debench.models.plate.strip_fe`) against the exponential-ansatz determinant
(method 1, :mod:`debench.models.plate.ansatz`) and the Biot and Euler limits.

The strip model uses the energy (4.22) of the constitutive library, so it is compared with
the determinant of the energy-consistent ``"derived"`` coefficients. The check functions
here are called by the producers (on the coarse mesh, level 0) and by the evidence tests
``verification/test_ch4_fe.py`` (coarse in the default run, finer behind ``--full``).
Every FE root is searched in a narrow bracket around the determinant root of the same
parity, by secant steps started at that root (certified by a sign change across less than
the root tolerance; the whole bracket is searched when they fail); its value is fixed by
the FE eigenvalue alone.

The producers read the FE roots from curated datasets (the finite-element producers read
curated data): the agreement producers from ``ch4_fe_agreement.nc``, each FE root beside
the determinant root recomputed live (:func:`curated_comparisons`); the Biot and Euler
producers from ``ch4_fe_limits.nc`` (:func:`curated_limit`), whose determinant root is
recomputed live too and must be the one the FE root was searched next to. ``debench
verify`` regenerates both datasets with the FE model and compares them with the curated
ones, and the evidence tests recompute the FE roots.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from debench.models.plate import PlateParams, strip_fe
from debench.models.plate.ansatz import critical_stretches
from debench.models.plate.voltage import critical_stretches_at_voltage
from debench.reference.catalogue import Accuracy
from debench.reference.datasets import read_dataset

#: half-width of the FE search bracket around a determinant root (relative); the coarse
#: FE error is < 1e-4 (measured), and same-parity neighbours closer than twice this are
#: bracketed at their mid-point instead
BRACKET = 5e-3
#: Representative subset of Figs 4.2 and 4.5 (xi, Dhat, kH) for the default run and the
#: producers: Fig. 4.2(a) TI, (c) thin isotropic, (i) isotropic, Fig. 4.5 xi = 10 thick.
CASES_FAST = ((5.0, 0.0, 2.0), (0.0, 2.0, 0.3), (0.0, 5.0, 2.0), (10.0, 2.0, 10.0))
#: every case of Figs 4.2 (nine Dhat, xi = 0 and 5) and 4.5 (xi = 3, 10 at Dhat = 2)
FIG42_D = (0.0, 1.0, 2.0, 2.2, 2.4, 2.6, 3.0, 4.0, 5.0)
CASES_FULL = tuple((xi, D, kH) for D in FIG42_D for xi in (0.0, 5.0)
                   for kH in (0.3, 2.0, 10.0)) + tuple(
    (xi, 2.0, kH) for xi in (3.0, 10.0) for kH in (0.3, 2.0, 10.0))
#: voltage control (beyond the thesis): isotropic and TI at Vhat = 0.5
VOLTAGE_CASES = ((0.0, 0.5, 2.0), (5.0, 0.5, 10.0))
#: the two controls of the plate: fixed Dhat (charge) or fixed Vhat (voltage)
CONTROLS = ("charge", "voltage")
#: kH of the thick (Biot) and thin (Euler) limits
KH_BIOT = 20.0
KH_EULER = 0.05
#: coarse-mesh (level 0) agreement FE vs determinant, by kH class; each is ~3x the largest
#: error measured on the coarse mesh in the convergence study (every root of Figs 4.2/4.5
#: at kH = 0.3, 2, 10: <= 1e-6, 3e-5, 3.2e-4; the root error falls like h_e^6), and
#: > 1e5 x the round-off of a root (~1e-12)
TOL_COARSE = {0.3: 3e-6, 2.0: 1e-4, 10.0: 1e-3}


def tolerance(kH: float, table=None) -> float:
    """The coarse tolerance of the kH class nearest (in log kH) to ``kH``."""
    table = TOL_COARSE if table is None else table
    return table[min(table, key=lambda k: abs(math.log(k / kH)))]
#: Biot's surface-instability stretch of the equibiaxially pre-stretched neo-Hookean
#: half-space (literature entry lit.plate.biot_thick_limit)
BIOT = 0.66614
#: Accuracy of a recomputed FE value on the same mesh: brentq to XTOL = 1e-11 in lam on
#: an eigenvalue with relative backward error < 1e-12; a different BLAS moves the root by
#: ~1e-12 (eigenvalue round-off / slope); 1e-9 keeps > 100x margin.
ACCURACY = Accuracy(rtol=1e-9, atol=1e-9, reason="strip FE roots: brentq xtol 1e-11 on an "
                    "eigenvalue with backward error < 1e-12; 100x margin over the "
                    "cross-BLAS spread")


@dataclass(frozen=True)
class Comparison:
    """One FE root beside the determinant root it was searched next to."""

    xi: float
    load: float        # Dhat (charge control) or Vhat (voltage control)
    kH: float
    parity: str
    control: str
    lam_det: float
    lam_fe: float
    ndof: int
    level: int

    @property
    def diff(self) -> float:
        return self.lam_fe - self.lam_det


def _brackets(lams, parities):
    """(lo, hi) around each root: +-BRACKET, cut at mid-points to same-parity neighbours."""
    out = []
    for i, (x, p) in enumerate(zip(lams, parities, strict=True)):
        lo, hi = x * (1 - BRACKET), x * (1 + BRACKET)
        for j, (y, q) in enumerate(zip(lams, parities, strict=True)):
            if j != i and q == p:
                if y < x:
                    lo = max(lo, 0.5 * (x + y))
                else:
                    hi = min(hi, 0.5 * (x + y))
        out.append((lo, hi))
    return out


@lru_cache(maxsize=256)
def compare(xi: float, load: float, kH: float, *, level: int = 0,
            control: str = "charge", parity: str | None = None) -> tuple[Comparison, ...]:
    """Every determinant root at (xi, load, kH) beside its strip-FE root on mesh ``level``
    (only the roots of ``parity``, ``"E"`` or ``"O"``, when it is given; the brackets are
    those of the full set)."""
    if parity is not None and parity not in strip_fe.PARITIES:
        raise ValueError(f"parity must be one of {strip_fe.PARITIES} or None, got {parity!r}")
    lams, pars = determinant_roots(xi, load, kH, control)
    mat = strip_fe.material_for(xi)
    mesh = strip_fe.default_mesh(kH, level=level)
    strip = strip_fe._Strip(mesh)  # assembled once for the roots of this case
    out = []
    for lam, par, br in zip(lams, pars, _brackets(lams, pars), strict=True):
        if parity is not None and par != parity:
            continue
        kw = {"Dhat": load} if control == "charge" else {"Vhat": load}
        fe = strip_fe.critical_stretch(kH, br, par, mat, mesh=mesh, guess=float(lam),
                                       _strip=strip, **kw)
        out.append(Comparison(xi, load, kH, par, control, float(lam), fe.lam, fe.ndof, level))
    return tuple(out)


def max_disagreement(cases, *, level: int = 0, control: str = "charge"):
    """(max |lam_fe - lam_det|, all comparisons) over ``cases`` of (xi, load, kH)."""
    rows = [c for case in cases for c in compare(*case, level=level, control=control)]
    return max(abs(c.diff) for c in rows), rows


#: a curated FE root belongs to a live determinant root when their determinant roots
#: agree to this: both come from the same refinement to xtol 1e-13 (round-off of the
#: root ~1e-12), while distinct roots of a case are >= 1e-3 apart (closest pair measured:
#: 3.5328 and 3.5338 at xi = 0, Dhat = 5, kH = 2)
SAME_DET_ROOT = 1e-9


@lru_cache(maxsize=4)
def _agreement_data():
    return read_dataset("ch4_fe_agreement")


def determinant_roots(xi: float, load: float, kH: float, control: str):
    """(lam, parity) of the ``"derived"`` determinant (method 1) at (xi, load, kH): the
    roots, sorted, every FE root of this study is searched next to.

    ``control`` one of :data:`CONTROLS`: ``"charge"`` (``load`` is Dhat,
    :func:`~debench.models.plate.ansatz.critical_stretches`) or ``"voltage"`` (``load`` is
    Vhat, :func:`~debench.models.plate.voltage.critical_stretches_at_voltage`), both on
    their default window and scan.
    """
    if control not in CONTROLS:
        raise ValueError(f"control must be one of {CONTROLS}, got {control!r}")
    params = PlateParams(xi=xi, Dhat=load if control == "charge" else 0.0, variant="derived")
    if control == "charge":
        r = critical_stretches(kH, params)
        return r.lam, r.parity
    return critical_stretches_at_voltage(kH, load, params)


def curated_comparisons(cases, control: str = "charge") -> list[Comparison]:
    """The FE roots of the curated ``ch4_fe_agreement.nc`` beside the determinant roots
    recomputed now, over ``cases`` of (xi, load, kH).

    Raises ``LookupError`` when the dataset lacks an FE root beside a determinant root
    (same case, control and parity, determinant root within :data:`SAME_DET_ROOT`): the
    determinant moved or the dataset is stale.
    """
    ds = _agreement_data()
    col = {k: ds[k].values for k in ("xi", "load", "kH", "parity", "control", "lam_det",
                                     "lam_fe", "ndof", "level")}
    out = []
    for xi, load, kH in cases:
        lams, pars = determinant_roots(xi, load, kH, control)
        for lam, par in zip(lams, pars, strict=True):
            hit = np.nonzero((col["xi"] == xi) & (col["load"] == load) & (col["kH"] == kH)
                             & (col["control"] == control) & (col["parity"] == par)
                             & (np.abs(col["lam_det"] - lam) <= SAME_DET_ROOT))[0]
            if hit.size != 1:
                raise LookupError(
                    f"ch4_fe_agreement.nc holds {hit.size} FE roots beside the determinant "
                    f"root lam = {lam:.12g} ({par}, xi = {xi}, load = {load}, kH = {kH}, "
                    f"{control}); regenerate it (debench reproduce ch4_fe --write-data)")
            i = int(hit[0])
            out.append(Comparison(xi, load, kH, par, control, float(lam),
                                  float(col["lam_fe"][i]), int(col["ndof"][i]),
                                  int(col["level"][i])))
    return out


def _biot_det_roots():
    """The determinant roots at kH = KH_BIOT, xi = Dhat = 0 (both parities: they coincide
    to ~exp(-kH), and the FE root of :func:`biot_root` is searched around both)."""
    return critical_stretches(KH_BIOT, PlateParams(xi=0.0, Dhat=0.0, variant="derived"))


def _biot_det_root(roots=None) -> float:
    """The flexural determinant root at kH = KH_BIOT, xi = Dhat = 0."""
    r = _biot_det_roots() if roots is None else roots
    return float(next(x for x, p in zip(r.lam, r.parity, strict=True) if p == "E"))


@lru_cache(maxsize=8)
def biot_comparison(level: int = 0) -> Comparison:
    """FE critical stretch at kH = KH_BIOT, xi = Dhat = 0 (flexural mode; the extensional
    one coincides to ~exp(-kH)) beside the flexural determinant root."""
    roots = _biot_det_roots()
    br = (min(roots.lam) * (1 - BRACKET), max(roots.lam) * (1 + BRACKET))
    det = _biot_det_root(roots)
    fe = strip_fe.critical_stretch(KH_BIOT, br, "E", strip_fe.material_for(0.0), Dhat=0.0,
                                   mesh=strip_fe.default_mesh(KH_BIOT, level=level), guess=det)
    return Comparison(0.0, 0.0, KH_BIOT, "E", "charge", det, fe.lam, fe.ndof, level)


def biot_root(level: int = 0) -> float:
    """FE critical stretch at kH = KH_BIOT, xi = Dhat = 0 (flexural mode)."""
    return biot_comparison(level).lam_fe


def euler_comparison(level: int = 0) -> Comparison:
    """The flexural FE root at kH = KH_EULER, xi = Dhat = 0 beside the determinant root."""
    return next(c for c in compare(0.0, 0.0, KH_EULER, level=level) if c.parity == "E")


def euler_slope(level: int = 0) -> tuple[float, float]:
    """(1 - lam_cr)/kH^2 at kH = KH_EULER, xi = Dhat = 0: FE and determinant.

    Plate theory (Euler buckling at vanishing membrane stress, literature entry
    lit.plate.euler_thin_limit) gives 1/18 as kH -> 0.
    """
    return euler_slopes_of(euler_comparison(level))


def euler_slopes_of(c: Comparison) -> tuple[float, float]:
    """(1 - lam_cr)/kH^2 of a comparison at kH = KH_EULER: FE and determinant."""
    return (1 - c.lam_fe) / KH_EULER**2, (1 - c.lam_det) / KH_EULER**2


#: the limits the producers read from ``ch4_fe_limits.nc`` (:func:`curated_limit`), on the
#: mesh level the producers' values are stated for (coarse, as the evidence tests)
LIMITS = ("biot", "euler")
LIMITS_LEVEL = 0


def limit_comparison(name: str, level: int = LIMITS_LEVEL) -> Comparison:
    """The FE root of limit ``name`` (one of :data:`LIMITS`) computed now."""
    if name not in LIMITS:
        raise ValueError(f"limit must be one of {LIMITS}, got {name!r}")
    return biot_comparison(level) if name == "biot" else euler_comparison(level)


@lru_cache(maxsize=4)
def _limits_data():
    return read_dataset("ch4_fe_limits")


def curated_limit(name: str, *, data=None) -> Comparison:
    """The FE root of limit ``name`` from the curated ``ch4_fe_limits.nc`` beside the
    flexural determinant root recomputed now.

    ``data``: the limits dataset to read instead (a regenerated or edited copy of
    ``ch4_fe_limits.nc``); by default the curated file, read once per process. Raises
    ``LookupError`` when the dataset lacks the limit or its determinant root is not the
    live one within :data:`SAME_DET_ROOT` (the determinant moved or the dataset is stale).
    """
    ds = _limits_data() if data is None else data
    names = [str(x) for x in ds["limit"].values]
    if name not in names:
        raise LookupError(f"ch4_fe_limits.nc lacks the {name} limit; regenerate it "
                          "(debench reproduce ch4_fe --write-data)")
    row = ds.isel(limit=names.index(name))
    kH = KH_BIOT if name == "biot" else KH_EULER
    lam = (_biot_det_root() if name == "biot" else
           next(x for x, p in zip(*determinant_roots(0.0, 0.0, kH, "charge"), strict=True)
                if p == "E"))
    if (float(row["kH"]) != kH or int(row["level"]) != LIMITS_LEVEL
            or not abs(float(row["lam_det"]) - lam) <= SAME_DET_ROOT):
        raise LookupError(
            f"ch4_fe_limits.nc: the {name} row (kH = {float(row['kH'])}, level "
            f"{int(row['level'])}, lam_det = {float(row['lam_det']):.12g}) is not beside the "
            f"live determinant root {lam:.12g} at kH = {kH}, level {LIMITS_LEVEL}; regenerate "
            "it (debench reproduce ch4_fe --write-data)")
    return Comparison(0.0, 0.0, kH, "E", "charge", float(lam), float(row["lam_fe"]),
                      int(row["ndof"]), int(row["level"]))


# ------------------------------------------------------------------ producers


