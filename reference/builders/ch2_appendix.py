"""Kernel reference data: energy, stresses, field and moduli of every library material at
canonical states (for people checking their own constitutive code), and a figure of the
Table 5.1 / Ch. 3 models in incompressible uniaxial tension.

``build(out_dir, full=False)`` writes

* ``ch2_kernel_reference_states.nc`` - for each thesis material of the library
  (:data:`debench.models.materials.THESIS_MATERIALS`; the non-dimensional ones in SI units, see
  :data:`TI_SI`, :data:`DO_SI`) and each state of :data:`STATES` (isochoric F, D_L in units of
  ``sqrt(eps mu)``): W, dW/dF, dW/dD_L, Cauchy stress (p = 0), the traction-free p
  (variable ``pressure``) on the face with current normal e3 (incompressible materials;
  NaN otherwise), E, and the moduli AA, AAA, A of eqs (2.65)-(2.67);
* ``figures/table5_1_uniaxial_stress_difference.png`` - sigma11 - sigma22 in incompressible
  uniaxial tension for Gent (Ch. 3), neo-Hookean and Ogden (Table 5.1).

Seconds; ``full`` changes nothing (kept for the common builder signature).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import xarray as xr
from debench.models.materials import (
    THESIS_MATERIALS,
    DorfmannOgdenElectric,
    TransverselyIsotropicNeoHookean,
    cauchy_stress,
    electric_field,
    material,
    pressure_from_traction_free_face,
)
from debench.models.materials.constants import (
    EPS_R_ASSUMED,
    VACUUM_PERMITTIVITY,
    VHB_SHEAR_MODULUS,
)
from debench.reference.datasets import write_dataset
from debench.reference.figures import LABELS, pyplot, save

#: CPU seconds of the default build (one thread, measured in one `debench reproduce` with
#: two pool processes on the quiet 2-core machine): the pool starts the longest first.
BUILD_CPU_S = 0.4
#: ``debench verify`` rebuilds this chapter's default plan and compares it with data/.
REGENERATED_BY_VERIFY = True
#: Model guards ``debench verify`` runs for this chapter (none).
GUARDS = {}

STATES = {
    # name: (principal stretches l1, l2 (l3 = 1/(l1 l2)), shear gamma, normalised D_L)
    "reference": ((1.0, 1.0), 0.0, (0.0, 0.0, 0.0)),
    "uniaxial_1p5": ((1.5, 1.5**-0.5), 0.0, (0.0, 0.0, 0.0)),
    "equibiaxial_2_poled": ((2.0, 2.0), 0.0, (0.0, 0.0, 0.5)),
    "simple_shear_0p5_poled": ((1.0, 1.0), 0.5, (0.0, 0.3, 0.4)),
    "general": ((1.3, 0.9), 0.2, (0.2, -0.1, 0.6)),
}
TI_SI = dict(mu=VHB_SHEAR_MODULUS, xi=5.0, alpha=0.0, beta=0.5,
             eps=EPS_R_ASSUMED * VACUUM_PERMITTIVITY)
"""SI instance of (4.22) for the dataset (the registry one is non-dimensional)."""
DO_SI = dict(alpha=0.3, beta=0.5, eps=EPS_R_ASSUMED * VACUUM_PERMITTIVITY)
"""SI instance of (4.20) for the dataset."""


def _materials():
    mats = {name: material(name) for name in THESIS_MATERIALS}
    mats["ti_neo_hookean_dielectric"] = TransverselyIsotropicNeoHookean(**TI_SI)
    mats["dorfmann_ogden_electric"] = DorfmannOgdenElectric(**DO_SI)
    return mats


def _state(name, mat):
    (l1, l2), gamma, d = STATES[name]
    F = np.diag([l1, l2, 1 / (l1 * l2)])
    F[0, 1] = gamma * F[1, 1]
    mu = mat.shear_modulus or 1e5
    return F, np.asarray(d, dtype=float) * math.sqrt(mat.eps * mu)


#: what the stored derivatives regenerate to: double-precision evaluations of closed forms
#: (the forward derivatives of each energy expression) agree to a few ulp of each
#: variable's largest entry, so a structurally zero modulus comes out as ~1e-16 of that
#: scale rather than 0 (``accuracy_atol`` = this times the variable's largest entry)
ROUNDOFF_RTOL = 1e-12


def compute() -> xr.Dataset:
    """The reference-state dataset (pure computation, no I/O)."""
    mats = _materials()
    names, states = list(mats), list(STATES)
    shape = (len(names), len(states))
    out = {k: np.full(shape + s, np.nan) for k, s in (
        ("W", ()), ("F", (3, 3)), ("D_L", (3,)), ("P", (3, 3)), ("E_L", (3,)),
        ("sigma", (3, 3)), ("pressure", ()), ("E", (3,)), ("AA", (3, 3, 3, 3)), ("AAA", (3, 3, 3)),
        ("A", (3, 3)))}
    for a, mname in enumerate(names):
        mat = mats[mname]
        for b, sname in enumerate(states):
            F, D = _state(sname, mat)
            r = mat.response(F, D)
            out["W"][a, b] = r.W
            out["F"][a, b], out["D_L"][a, b] = F, D
            out["P"][a, b], out["E_L"][a, b] = r.P, r.E_L
            out["AA"][a, b], out["AAA"][a, b], out["A"][a, b] = r.AA, r.AAA, r.A
            out["sigma"][a, b] = cauchy_stress(mat, F, D)
            out["E"][a, b] = electric_field(mat, F, D)
            if mat.incompressible:
                n = np.linalg.inv(F).T @ np.array([0.0, 0.0, 1.0])
                out["pressure"][a, b] = pressure_from_traction_free_face(mat, F, D,
                                                                  n / np.linalg.norm(n))
    dims = {0: (), 1: ("i",), 2: ("i", "alpha"), 3: ("i", "alpha", "beta"),
            4: ("i", "alpha", "j", "beta")}
    meta = {
        "W": ("J m-3", "energy density W(F, D_L)"),
        "F": ("1", "deformation gradient F[i, alpha]"),
        "D_L": ("C m-2", "Lagrangian electric displacement"),
        "P": ("Pa", "dW/dF (first Piola stress without pressure; nominal stress T = P^T)"),
        "E_L": ("V m-1", "Lagrangian electric field dW/dD_L, eq. (2.28)"),
        "sigma": ("Pa", "Cauchy stress J^-1 dW/dF F^T at p = 0, eq. (2.31)/(2.33)"),
        "pressure": ("Pa", "Lagrange multiplier p making the face with current normal F^-T e3 "
                    "traction free (incompressible materials; NaN otherwise)"),
        "E": ("V m-1", "Eulerian electric field F^-T E_L, eq. (2.32)"),
        "AA": ("Pa", "moduli d2W/dF_ia dF_jb, eq. (2.65)"),
        "AAA": ("V m-1", "moduli d2W/dF_ia dD_Lb, eq. (2.66)"),
        "A": ("m F-1", "moduli d2W/dD_La dD_Lb, eq. (2.67)"),
    }
    data_vars = {}
    for k, (units, long_name) in meta.items():
        extra = out[k].ndim - 2
        d = dims[extra] if k not in ("D_L", "E_L", "E") else ("alpha",)
        if k == "A":
            d = ("alpha", "beta")
        attrs = {"units": units, "long_name": long_name}
        if k not in ("F", "D_L"):
            attrs.update(accuracy_rtol=ROUNDOFF_RTOL,
                         accuracy_atol=ROUNDOFF_RTOL * float(np.nanmax(np.abs(out[k]))))
        data_vars[k] = (("material", "state") + d, out[k], attrs)
    coords = {
        "material": ("material", names,
                     {"long_name": "library material (debench.models.materials)"}),
        "state": ("state", states, {"long_name": "canonical isochoric state"}),
        "i": ("i", np.arange(3), {"long_name": "spatial index", "units": "1"}),
        "j": ("j", np.arange(3), {"long_name": "spatial index", "units": "1"}),
        "alpha": ("alpha", np.arange(3), {"long_name": "material index", "units": "1"}),
        "beta": ("beta", np.arange(3), {"long_name": "material index", "units": "1"}),
    }
    return xr.Dataset(data_vars, coords=coords)


def _parameters():
    mats = _materials()
    params = {}
    for name, mat in mats.items():
        for field in mat.__dataclass_fields__:
            params[f"{name}__{field}"] = getattr(mat, field)
    params["states"] = {k: list(map(list, [v[0]])) + [v[1], list(v[2])] for k, v in
                        STATES.items()}
    return params


def figure(path: Path) -> list[Path]:
    """sigma11 - sigma22 in incompressible uniaxial tension (Gent, Table 5.1 NH and Ogden);
    ``path`` without suffix, written as PNG and SVG."""
    plt = pyplot()
    lam = np.linspace(1.0, 4.0, 61)
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for name, label in (("gent_ideal_dielectric", r"Gent, $\mu$ = 51 kPa, $J_m$ = 120 (Ch. 3)"),
                        ("neo_hookean_ideal_dielectric",
                         r"neo-Hookean, $\mu$ = 156 kPa (Tab. 5.1)"),
                        ("ogden_ideal_dielectric", r"Ogden, $\sum\mu_p$ = 69.6 kPa (Tab. 5.1)")):
        mat = material(name)
        s = [np.diff(np.diag(cauchy_stress(mat, np.diag([x, x**-0.5, x**-0.5]),
                                            np.zeros(3)))[[1, 0]])[0] for x in lam]
        ax.plot(lam, np.array(s) / 1e3, label=label)
    ax.set_xlabel(LABELS["lambda_uniaxial"] + " (incompressible)")
    ax.set_ylabel(LABELS["stress_difference_kPa"])
    ax.legend()
    return save(fig, path)


def build(out_dir: Path, *, full: bool = False) -> list[Path]:
    """Write the kernel dataset and figure into ``out_dir``; returns the paths."""
    out_dir = Path(out_dir)
    ds = compute()
    nc = write_dataset(
        ds, "ch2_kernel_reference_states",
        title="debench constitutive kernel: energies, stresses and moduli at canonical states",
        summary=("W, dW/dF, dW/dD_L, Cauchy stress, electric field and electroelastic moduli "
                 "(eqs 2.27-2.34, 2.65-2.67 of Zeng 2020) of the library materials (Gent 3.23, "
                 "neo-Hookean 5.15, Ogden 5.26, ideal dielectric 5.9, transversely isotropic "
                 "4.22) at five isochoric states. Verified by Taylor tests, sympy and NGSolve "
                 "symbolic differentiation (verification/test_materials_*.py)."),
        parameters=_parameters(), out_dir=out_dir, overwrite=True)
    return [nc, *figure(out_dir / "figures" / "table5_1_uniaxial_stress_difference")]
