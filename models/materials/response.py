"""Stress, electric field and moduli of a material at (F, D_L): the public functions.

Conventions (thesis Sec. 2.2.4-2.2.5)
--------------------------------------
* ``P = dW/dF`` with ``P[i, a] = dW/dF_{ia}``; the thesis' nominal stress is ``T = P^T``
  (2.27); for incompressible materials ``T = dW/dF - p F^{-1}`` (2.29), i.e.
  ``P - p F^{-T}``.
* Cauchy stress ``sigma = J^{-1} F T = J^{-1} P F^T`` (2.31); incompressible
  ``sigma = F dW/dF - p I`` (2.33).
* ``E_L = dW/dD_L`` (2.28, 2.30), ``E = F^{-T} E_L`` (2.32, 2.34), ``D = J^{-1} F D_L``.
* Moduli ``AA[i,a,j,b] = d2W/dF_ia dF_jb`` (2.65), ``AAA[i,a,b] = d2W/dF_ia dD_Lb`` (2.66),
  ``A[a,b] = d2W/dD_La dD_Lb`` (2.67); push-forward (2.72)-(2.73)::

      AA0[i,p,j,q] = J^-1 F_pa F_qb AA[i,a,j,b],   AAA0[i,p,q] = F_pa Finv_bq AAA[i,a,b],
      A0 = J F^-T A F^-1

  so that ``Tdot0_{pi} = AA0[i,p,j,q] L_jq + AAA0[i,p,q] DdotL0_q`` and
  ``EdotL0_q = AAA0[i,p,q] L_ip + A0_qr DdotL0_r`` with ``Tdot0 = J^-1 F Tdot``,
  ``DdotL0 = J^-1 F DdotL``, ``EdotL0 = F^-T EdotL`` (2.54)-(2.56).
"""

from __future__ import annotations

import numpy as np
from debench.models import validation as v


def _material(material):
    """A library material: anything with ``response(F, D_L, second=...)``."""
    if not callable(getattr(material, "response", None)):
        raise TypeError(f"material must be a library material (with a response method), "
                        f"got {type(material).__name__} {material!r:.60}")
    return material


@v.finite_result
def first_piola(material, F, D_L, p: float = 0.0) -> np.ndarray:
    """``P = dW/dF - p F^{-T}`` (transpose of the nominal stress (2.27)/(2.29)).

    ``p`` must be 0 for compressible materials.
    """
    _check_p(_material(material), p)
    P = material.response(F, D_L, second=False).P
    return P - p * np.linalg.inv(np.asarray(F, dtype=float)).T


@v.finite_result
def cauchy_stress(material, F, D_L, p: float = 0.0) -> np.ndarray:
    """Total Cauchy stress (2.31)/(2.33): ``J^{-1} (dW/dF) F^T - p I``."""
    _check_p(_material(material), p)
    F = np.asarray(F, dtype=float)
    P = material.response(F, D_L, second=False).P
    J = np.linalg.det(F)
    return P @ F.T / J - p * np.eye(3)


@v.finite_result
def electric_field(material, F, D_L) -> np.ndarray:
    """Eulerian electric field ``E = F^{-T} dW/dD_L`` (2.32)/(2.34)."""
    _material(material)
    F = np.asarray(v.deformation_gradient("F", F), dtype=float)
    return np.linalg.solve(F.T, material.response(F, D_L, second=False).E_L)


@v.finite_result
def eulerian_displacement(F, D_L) -> np.ndarray:
    """``D = J^{-1} F D_L``."""
    F = np.asarray(v.deformation_gradient("F", F), dtype=float)
    D_L = np.asarray(v.vector("D_L", D_L), dtype=float)
    D = F @ D_L / np.linalg.det(F)
    return v.finite("D (overflow)", D)


def moduli(material, F, D_L) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(AA, AAA, A)`` of (2.65)-(2.67) (index layout in the module docstring)."""
    r = _material(material).response(F, D_L, second=True)
    return r.AA, r.AAA, r.A


@v.finite_result
def push_forward(F, AA, AAA, A) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Push-forward moduli ``(AA0, AAA0, A0)`` of (2.72)-(2.73).

    ``F`` finite (3, 3) with ``det F > 0``; ``AA`` (3, 3, 3, 3), ``AAA`` (3, 3, 3) and
    ``A`` (3, 3) finite arrays.
    """
    F = np.asarray(v.deformation_gradient("F", F), dtype=float)
    AA = v.array("AA", AA, (3, 3, 3, 3))
    AAA = v.array("AAA", AAA, (3, 3, 3))
    A = v.array("A", A, (3, 3))
    J = np.linalg.det(F)
    Finv = np.linalg.inv(F)
    AA0 = np.einsum("pa,qb,iajb->ipjq", F, F, AA) / J
    AAA0 = np.einsum("pa,bq,iab->ipq", F, Finv, AAA)
    A0 = J * Finv.T @ A @ Finv
    return AA0, AAA0, A0


def pressure_from_traction_free_face(material, F, D_L, normal) -> float:
    """Lagrange multiplier p making the normal traction on a face vanish.

    ``n . sigma n = 0`` with ``sigma = F dW/dF^T - p I`` gives ``p = n . (F dW/dF^T) n``
    (``n`` the unit normal in the current configuration). Only for incompressible
    materials (2.33).
    """
    if not _material(material).incompressible:
        raise ValueError("p is only defined for incompressible materials")
    n = v.unit_vector("normal", normal)
    sig0 = cauchy_stress(material, F, D_L, 0.0)
    return float(n @ sig0 @ n)


def _check_p(material, p):
    v.finite("p", p)
    if p != 0.0 and not material.incompressible:
        raise ValueError(f"p must be 0 for the compressible material "
                         f"{type(material).__name__}, got {p}")
