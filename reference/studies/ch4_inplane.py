"""The Chapter 4 in-plane-fibre study (the ``ch4.beyond.inplane.*`` entries, whose
producers are :mod:`debench.reference.producers.ch4_inplane`): the fibre in the plane of
the plate.

Beyond the thesis (our results, :mod:`debench.models.plate.inplane`): the fibre
A = (cos theta, 0, sin theta) at the angle theta to the wave vector, energy (4.22):
charge control in equibiaxial compression (lam < 1, above the loss of strong
ellipticity) and in tension with a field (lam > 1, with the membrane limit tau11 = 0),
and voltage control (Dhat = Vhat lam^2/beta along the path). Both methods
(exponential-ansatz determinant and through-thickness FE) are run on each window; the
evidence tests ``verification/test_ch4_inplane.py`` call the same functions.

Each window is a :class:`Case`; its roots are memoised on the values of its parameters
(:func:`det_roots`, :func:`fe_roots`), shared by the producers, the tests and the builder
:mod:`debench.reference.builders.ch4_inplane`. The check functions take the source of the
FE roots: ``"live"`` solves the FE now (the evidence tests), ``"curated"`` reads every FE
root of :func:`producer_cases` from the curated ``ch4_inplane_roots.nc``
(:func:`curated_fe_roots`; the finite-element producers read curated data) while the
determinant roots are recomputed live. ``debench verify`` regenerates that dataset with
the FE model and compares it with the curated one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from debench.models.numerics.roots import bracketed_root
from debench.models.plate import PlateParams
from debench.models.plate import inplane as ip
from debench.models.plate import inplane_fe as ipfe
from debench.reference.catalogue import Accuracy
from debench.reference.datasets import read_dataset

#: fibre angles of the claims (degrees)
THETAS = (0.0, 30.0, 45.0, 60.0, 90.0)
#: the representative case: strongly anisotropic, no field, kH = 2
XI, KH = 5.0, 2.0
#: compression window scanned (lam_E <= 0.95 < 1 for xi = 5 and all THETAS) and its grid
WINDOW, N_SCAN = (0.8, 0.999), 40
#: determinant vs FE (24 elements): the FE root error is <= 1.1e-6 measured over the
#: cases here (O(N^-4), see debench.models.plate.fem); 1e-5 keeps ~10x over that and
#: > 1e6 x the round-off of a root (~1e-12)
TOL_AGREE = 1e-5
#: theta = 90 degrees against the isotropic energy matrix of the thesis case: both are
#: polynomials in lam evaluated in double precision (entries O(10)); 1e-12 is > 100x
#: their round-off
TOL_MATRIX = 1e-12
ACCURACY = Accuracy(rtol=1e-7, atol=2 * ipfe.FE_ROOT_ROUNDOFF,
                    reason="in-plane fibre roots: brentq to 1e-14 on fixed grids; a "
                    "determinant root moves by round-off only (< 1e-10), an FE root by up to "
                    "eps ||K||_1 / |de/dlam| <= FE_ROOT_ROUNDOFF (1e-6) on another BLAS; 2x")

# ------------------------------------------------------------ voltage control, tension
#: voltage control: the representative voltage and its window (across lam = 1: thin
#: plates at fixed voltage wrinkle in tension); lower end above lam_E(theta) for xi = 5
VHAT, V_WINDOW = 0.5, (0.9, 1.5)
#: tension with a field (charge control): the field and the window above 1
D_TENSION, T_WINDOW = 2.0, (1.0005, 2.0)
#: thicknesses of the tension claim (the FE resolves kH >= 0.5 in this window)
KH_TENSION = (0.5, 2.0)
#: kH of the membrane-limit fit lam_cr = a + b (kH)^2 (3 points, 2 unknowns)
KH_THIN = (0.01, 0.02, 0.05)


@dataclass(frozen=True)
class Case:
    """One scanned window: every bifurcation stretch in [lo, hi] at fibre angle ``theta``
    (degrees), anisotropy ``xi``, thickness ``kH``; charge control at ``Dhat`` or voltage
    control at ``Vhat`` (then ``Dhat`` = 0 and Dhat = Vhat lam^2/beta along the path).
    The values are floats, so equal parameters are one case however they were passed."""

    control: str
    theta: float
    xi: float
    Dhat: float
    Vhat: float
    kH: float
    lo: float
    hi: float

    def __post_init__(self):
        if self.control not in ("charge", "voltage"):
            raise ValueError(f"control must be 'charge' or 'voltage', got {self.control!r}")
        for name in ("theta", "xi", "Dhat", "Vhat", "kH", "lo", "hi"):
            object.__setattr__(self, name, float(getattr(self, name)))
        if self.control == "charge" and self.Vhat != 0.0:
            raise ValueError(f"Vhat must be 0 under charge control, got {self.Vhat}")

    def _args(self):
        kw = {"window": (self.lo, self.hi), "n_scan": N_SCAN}
        if self.control == "voltage":
            kw["Vhat"] = self.Vhat
        return (self.kH, self.theta, PlateParams(xi=self.xi, Dhat=self.Dhat)), kw


def compression_case(theta: float, xi: float = XI, Dhat: float = 0.0,
                     kH: float = KH) -> Case:
    """Charge control on the compression window :data:`WINDOW`."""
    return Case("charge", theta, xi, Dhat, 0.0, kH, *WINDOW)


def voltage_case(theta: float, Vhat: float = VHAT, kH: float = KH, xi: float = XI) -> Case:
    """Voltage control on :data:`V_WINDOW`, its lower end a relative
    ``ip.LAM_E_MARGIN`` above the ellipticity limit where that is higher."""
    return Case("voltage", theta, xi, 0.0, Vhat, kH, _voltage_lo(float(theta), float(Vhat),
                                                                  float(xi)), V_WINDOW[1])


@lru_cache(maxsize=64)
def _voltage_lo(theta: float, Vhat: float, xi: float) -> float:
    lam_e = ip.ellipticity_limit(theta, PlateParams(xi=xi), window=(0.45, 0.999), Vhat=Vhat)
    return max(V_WINDOW[0], lam_e * (1 + ip.LAM_E_MARGIN))


def tension_case(theta: float, Dhat: float, kH: float, xi: float = XI) -> Case:
    """Charge control on the tension window :data:`T_WINDOW`."""
    return Case("charge", theta, xi, Dhat, 0.0, kH, *T_WINDOW)


#: determinant roots by case (method 1), filled by :func:`det_roots_many`
_DET_ROOTS: dict[Case, tuple[float, ...]] = {}


def det_roots(case: Case) -> tuple[float, ...]:
    """Every exponential-ansatz determinant root of ``case`` (method 1), memoised."""
    return det_roots_many((case,))[0]


def det_roots_many(cases) -> list[tuple[float, ...]]:
    """:func:`det_roots` of several cases, those not yet memoised solved together
    (:func:`~debench.models.plate.inplane.critical_stretches_det_many`); where the joint
    solve fails, each case is solved alone so that the failing one raises for itself."""
    todo = list(dict.fromkeys(c for c in cases if c not in _DET_ROOTS))
    if todo:
        scans = [(*args, kw) for args, kw in (c._args() for c in todo)]
        try:
            found = ip.critical_stretches_det_many(scans)
        except Exception:  # noqa: BLE001 - retried one by one below, which raises
            found = [ip.critical_stretches_det_many([sc])[0] for sc in scans]
        for c, r in zip(todo, found, strict=True):
            _DET_ROOTS[c] = tuple(float(x) for x in r)
    return [_DET_ROOTS[c] for c in cases]


@lru_cache(maxsize=4096)
def fe_roots(case: Case) -> tuple[float, ...]:
    """Every through-thickness FE root of ``case`` (method 2) solved now, memoised."""
    args, kw = case._args()
    return tuple(float(x) for x in ipfe.critical_stretches_fe(*args, **kw))


def producer_cases() -> tuple[Case, ...]:
    """Every case whose FE roots the producers compare (stored in ``ch4_inplane_roots.nc``
    by the builder)."""
    return (tuple(compression_case(th) for th in THETAS)
            + tuple(voltage_case(th) for th in THETAS)
            + tuple(tension_case(th, D_TENSION, kh) for kh in KH_TENSION for th in THETAS))


#: a curated case is the live one when its window ends agree to this: the compression and
#: tension windows are constants, the voltage window starts at an ellipticity limit
#: bisected to round-off (~1e-15); a changed definition moves them by > 1e-6
SAME_WINDOW = 1e-12


@lru_cache(maxsize=4)
def _roots_data():
    return read_dataset("ch4_inplane_roots")


def curated_fe_roots(case: Case, *, data=None) -> tuple[float, ...]:
    """The FE roots of ``case`` in the curated ``ch4_inplane_roots.nc``.

    ``data``: the roots dataset to read instead (a regenerated or edited copy of
    ``ch4_inplane_roots.nc``); by default the curated file, read once per process. Raises
    ``LookupError`` when the dataset lacks the case (same control and parameters, window
    within :data:`SAME_WINDOW`): the producers' cases changed or the dataset is stale.
    """
    ds = _roots_data() if data is None else data
    col = {k: ds[k].values for k in ("control", "theta", "xi", "Dhat", "Vhat", "kH",
                                     "lam_lo", "lam_hi")}
    hit = np.nonzero((col["control"] == case.control) & (col["theta"] == case.theta)
                     & (col["xi"] == case.xi) & (col["Dhat"] == case.Dhat)
                     & (col["Vhat"] == case.Vhat) & (col["kH"] == case.kH)
                     & (np.abs(col["lam_lo"] - case.lo) <= SAME_WINDOW)
                     & (np.abs(col["lam_hi"] - case.hi) <= SAME_WINDOW))[0]
    if hit.size != 1:
        raise LookupError(f"ch4_inplane_roots.nc holds {hit.size} rows for {case}; "
                          "regenerate it (debench reproduce ch4_inplane --write-data)")
    i = int(hit[0])
    n = int(ds["n_fe"].values[i])
    return tuple(float(x) for x in ds["lam_fe"].values[i, :n])


_FE_SOURCES = {"live": fe_roots, "curated": curated_fe_roots}


def _fe(source: str):
    if source not in _FE_SOURCES:
        raise ValueError(f"fe_source must be one of {tuple(_FE_SOURCES)}, got {source!r}")
    return _FE_SOURCES[source]


def roots(theta: float, xi: float = XI, Dhat: float = 0.0, kH: float = KH):
    """(determinant roots, FE roots, ellipticity limit) on :data:`WINDOW` (memoised on the
    values of the parameters, however they are passed)."""
    case = compression_case(theta, xi, Dhat, kH)
    return det_roots(case), fe_roots(case), ellipticity_stretch(case.theta, case.xi, case.Dhat)


@lru_cache(maxsize=64)
def ellipticity_stretch(theta: float, xi: float, Dhat: float) -> float:
    return ip.ellipticity_limit(theta, PlateParams(xi=xi, Dhat=Dhat), window=WINDOW)


def max_disagreement(thetas=THETAS, xi=XI, Dhat=0.0, kH=KH, *, fe_source: str = "live"):
    """(max |lam_FE - lam_det|, same number of roots everywhere, rows); the FE roots from
    ``fe_source`` (``"live"`` or ``"curated"``)."""
    fe_of = _fe(fe_source)
    err, same, rows = 0.0, True, []
    det_roots_many([compression_case(th, xi, Dhat, kH) for th in thetas])
    for th in thetas:
        case = compression_case(th, xi, Dhat, kH)
        det, fe = det_roots(case), fe_of(case)
        same &= len(det) == len(fe)
        for a, b in zip(det, fe, strict=False):
            err = max(err, abs(a - b))
            rows.append((th, a, b))
    return err, same, rows


def voltage_roots(theta: float, Vhat: float = VHAT, kH: float = KH, xi: float = XI):
    """(determinant roots, FE roots) at fixed voltage on :data:`V_WINDOW` (memoised on
    the values of the parameters)."""
    case = voltage_case(theta, Vhat, kH, xi)
    return det_roots(case), fe_roots(case)


def voltage_agreement(fe_source: str = "live"):
    """(max |lam_FE - lam_det|, same number of roots everywhere, rows) under voltage
    control at :data:`VHAT` for every theta of :data:`THETAS`; the FE roots from
    ``fe_source`` (``"live"`` or ``"curated"``)."""
    fe_of = _fe(fe_source)
    err, same, rows = 0.0, True, []
    det_roots_many([voltage_case(th) for th in THETAS])
    for th in THETAS:
        case = voltage_case(th)
        det, fe = det_roots(case), fe_of(case)
        same &= len(det) == len(fe)
        for a, b in zip(det, fe, strict=False):
            err = max(err, abs(a - b))
            rows.append((th, a, b))
    return err, same, rows


def tension_check(fe_source: str = "live"):
    """(ok, rows, none_without_field) of the tension claim: with Dhat = D_TENSION a root
    above 1 at every theta and kH of KH_TENSION (both methods, within TOL_AGREE, the FE
    roots from ``fe_source``), lam_cr increasing with theta, none at Dhat = 0."""
    fe_of = _fe(fe_source)
    rows, ok = [], True
    det_roots_many([tension_case(th, D, kh) for D in (D_TENSION, 0.0) for kh in KH_TENSION
                    for th in THETAS])
    for kh in KH_TENSION:
        lc = []
        for th in THETAS:
            case = tension_case(th, D_TENSION, kh)
            det, fe = det_roots(case), fe_of(case)
            ok &= bool(det) and len(det) == len(fe) and all(
                abs(a - b) <= TOL_AGREE for a, b in zip(det, fe, strict=True))
            lc.append(max(det, default=math.nan))
            rows.append((kh, th, lc[-1], max(fe, default=math.nan)))
        ok &= bool(np.all(np.isfinite(lc)) and np.all(np.diff(lc) > 0))
    none_without_field = all(not det_roots(tension_case(th, 0.0, kh))
                             for th in THETAS for kh in KH_TENSION)
    return bool(ok and none_without_field), rows, none_without_field


def membrane_limit_closed_form(theta: float, xi: float, Dhat: float) -> float:
    """Largest zero above 1 of tau11 = lam^2 - lam^-4 + 2 xi c^2 lam^2 (lam^2 - 1) - beta
    Dhat^2 (beta = 0.5), written out here independently of the generated base state."""
    c2 = math.cos(math.radians(theta)) ** 2

    def tau11(x):
        return x**2 - x**-4 + 2 * xi * c2 * x**2 * (x**2 - 1) - 0.5 * Dhat**2

    return bracketed_root(tau11, 1.0, 8.0, xtol=ip.MEMBRANE_XTOL,
                          what="membrane limit (closed form)").root


