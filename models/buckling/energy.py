"""The energy of the Chapter 5 finite-element model (:mod:`debench.models.buckling.fem`):
the electric enthalpy as an NGSolve CoefficientFunction and its compilation.

The energies come from the constitutive library's NGSolve path
(:mod:`debench.models.materials.ngsolve_forms`): the strain energy of any library elastomer
with the ideal dielectric (:class:`~debench.models.materials.protocol.IdealDielectricElastomer`:
neo-Hookean (5.15), Ogden (5.26) by the averaged spectral perturbation, error O(delta^2),
``Discretisation.ogden_delta``, Mooney-Rivlin, ...), and the enthalpy of the ideal
dielectric. Both Chapter 5 models (this 3D one and the axisymmetric one) build their
enthalpy with :func:`enthalpy_cf`.  The energy is compiled to C++
(``Compile(realcompile=True)``) when the problem is large enough to repay the compile time
(seconds), with a fall-back to the interpreted compiled tree.
"""

from __future__ import annotations

import os
import shutil
import sys
from pathlib import Path

import ngsolve as ngs
import numpy as np
from debench.models.buckling.parameters import MU_REF
from debench.models.errors import require
from debench.models.materials import ngsolve_forms as ngf
from debench.models.materials.constants import OGDEN_DELTA
from debench.models.materials.protocol import IdealDielectricElastomer
from netgen.meshing import Element3D, MeshPoint, Pnt
from netgen.meshing import Mesh as NGMesh

REALCOMPILE_MIN_DOFS = 20000
"""``compile="auto"`` compiles the energy to C++ above this size: compiling takes 15-20 s
(measured), assembly is 1.2-2.3x faster with identical matrices, so it pays only for
problems assembled hundreds of times at >= 20k DOFs."""


def enthalpy_cf(F, EL_hat, mat: IdealDielectricElastomer, *, mu_ref: float = MU_REF,
                ogden_delta: float = OGDEN_DELTA, xp=None):
    """Electric enthalpy Omega/mu_ref with the scaled referential field
    ``EL_hat = E_L sqrt(eps/mu_ref)``: ``W_mech/mu_ref - 1/2 J C^-1:(EL x EL)``
    (library energies, :mod:`debench.models.materials.ngsolve_forms`).

    ``W_mech`` is the material's ``mechanical_energy`` in the NGSolve namespace ``xp``
    (default: :func:`~debench.models.materials.ngsolve_forms.regularised` with
    ``ogden_delta``, which only spectral energies use; the axisymmetric model passes its
    exact namespaces)."""
    xp = ngf.regularised(ogden_delta) if xp is None else xp
    return (mat.mechanical_energy(F, xp=xp) / mu_ref
            + ngf.ideal_dielectric_enthalpy(F, EL_hat, eps=1.0))


def compile_energy(cf, mode: str, ndof: int):
    """Compile an energy CF: C++ (``realcompile``) when asked or, with ``"auto"``, when
    the problem is large; falls back to the interpreted compiled tree when no compiler
    works.  Returns (cf, how)."""
    if (mode is True or (mode == "auto" and ndof >= REALCOMPILE_MIN_DOFS)) and compiler_available():
        try:
            return cf.Compile(realcompile=True, wait=True), "realcompile"
        except Exception:  # noqa: BLE001 - a failed build: fall back
            pass
    return cf.Compile(), "compiled-tree"


def compiler_available() -> bool:
    """Whether NGSolve's compiler wrapper ``ngscxx`` (which ``realcompile`` runs through
    the shell) can be found. The wheel installs it beside the Python interpreter; when the
    environment is used without being activated that directory is not on ``PATH``, so it
    is put first there (as activation would). False when it is nowhere: compile as a tree
    without a failed shell call."""
    if shutil.which("ngscxx"):
        return True
    here = Path(sys.executable).parent
    if (here / "ngscxx").exists():
        os.environ["PATH"] = f"{here}{os.pathsep}{os.environ.get('PATH', '')}"
        return True
    return False


def energies_at(F: np.ndarray, E_hat: np.ndarray, mat: IdealDielectricElastomer,
                mu_ref: float = MU_REF) -> tuple[float, float]:
    """Evaluate the CoefficientFunction energies at a constant ``F`` and scaled field.

    Returns ``(W_mech [Pa], Omega/mu_ref)`` exactly as assembled by
    :class:`~debench.models.buckling.fem.MembraneModel`
    (used to check the NGSolve energies against :mod:`debench.models.materials`).
    """
    F = np.asarray(F, dtype=float)
    require(F.shape == (3, 3), f"F must be 3x3, got {F.shape}")
    require(np.linalg.det(F) > 0, f"det F must be > 0, got {np.linalg.det(F)}")
    mesh = _unit_mesh()
    mip = mesh(0.25, 0.25, 0.25)
    Fcf = ngs.CF(tuple(F.ravel()), dims=(3, 3))
    Ecf = ngs.CF(tuple(float(e) for e in E_hat))
    return (float(ngf.mechanical_energy_cf(mat, Fcf)(mip)),
            float(enthalpy_cf(Fcf, Ecf, mat, mu_ref=mu_ref)(mip)))


def _unit_mesh():
    ngm = NGMesh(dim=3)
    pts = [ngm.Add(MeshPoint(Pnt(*p))) for p in ((0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1))]
    ngm.Add(Element3D(1, pts))
    return ngs.Mesh(ngm)
