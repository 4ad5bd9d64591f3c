"""The meridian section of the axisymmetric model: its discretisation and its mesh.

The tensor-product quadrilateral mesh of ``0 <= R <= a``, ``0 <= Z <= t0``, geometrically
graded towards the rim and its two clamped corners (the formulation it carries:
:mod:`debench.models.buckling.axisym`).
"""

from __future__ import annotations

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np
from debench.models import validation as val
from debench.models.buckling.parameters import Plate
from debench.models.errors import require
from netgen.meshing import Element1D, Element2D, FaceDescriptor, MeshPoint, Pnt
from netgen.meshing import Mesh as NGMesh

MAX_ORDER = 12
MAX_LAYERS = 30
"""Largest order and largest number of graded layers a discretisation accepts."""


@dataclass(frozen=True)
class AxisymDiscretisation:
    """Tensor-product mesh of the meridian section and its polynomial order.

    In R: ``n_r`` equal elements on ``[0, a - edge_zone t0]`` and ``edge_layers`` geometric
    layers (ratio ``grading``) on the rim zone ``[a - edge_zone t0, a]``, the smallest next to
    the rim. Through the thickness: ``n_z`` elements, whose two outer ones are split into
    ``face_layers`` geometric layers (ratio ``grading``) towards each face, so that the
    elements next to the two clamped corners (R, Z) = (a, 0), (a, t0) shrink geometrically in
    both directions (the hp-refinement of corner singularities, Babuska & Guo 1986).
    ``axis_layers`` geometric layers (ratio ``grading``) towards the axis inside the first
    radial element, a check of the axis regularity conditions (the smooth fields they admit
    need no resolution there: every wavenumber's critical voltage is unchanged by them to
    1e-9, tools/probe_n1_axis_grading.py); 0 (default) keeps the uniform inner mesh.
    ``order``: polynomial order of every field (H1, quadrilaterals).
    """

    order: int = 6
    n_r: int = 10
    n_z: int = 2
    edge_zone: float = 1.0
    edge_layers: int = 6
    face_layers: int = 6
    grading: float = 0.25
    axis_layers: int = 0

    def __post_init__(self):
        val.integer_at_least("order", self.order, 1)
        require(self.order <= MAX_ORDER, f"order = {self.order} must be <= {MAX_ORDER}")
        val.integer_at_least("n_r", self.n_r, 1)
        val.integer_at_least("n_z", self.n_z, 1)
        val.in_range("edge_zone", self.edge_zone, 0.0, 100.0, lo_open=True)
        for name in ("edge_layers", "face_layers", "axis_layers"):
            v = getattr(self, name)
            val.integer_at_least(name, v, 0)
            require(v <= MAX_LAYERS, f"{name} = {v} must be <= {MAX_LAYERS}")
        val.in_range("grading", self.grading, 0.0, 1.0, lo_open=True, hi_open=True)


def _graded(length: float, layers: int, ratio: float) -> np.ndarray:
    """Offsets ``length * ratio^k`` (k = layers .. 0) and 0, ascending: geometric layers
    towards 0 (the last element [0, length ratio^layers])."""
    return np.concatenate([[0.0], length * ratio ** np.arange(layers, -1, -1)])


def section_nodes(plate: Plate, disc: AxisymDiscretisation) -> tuple[np.ndarray, np.ndarray]:
    """Node coordinates in R and Z of the tensor-product mesh (m)."""
    a, t0 = plate.radius, plate.thickness
    zone = min(disc.edge_zone * t0, 0.5 * a)
    r_in = np.linspace(0.0, a - zone, disc.n_r + 1)
    r_in = np.concatenate([r_in, r_in[1] * disc.grading ** np.arange(1, disc.axis_layers + 1)])
    r_edge = a - _graded(zone, disc.edge_layers, disc.grading)[::-1]
    r = np.unique(np.concatenate([r_in, r_edge]))
    hz = t0 / disc.n_z
    z_mid = np.linspace(hz, t0 - hz, max(disc.n_z - 1, 0)) if disc.n_z > 1 else np.zeros(0)
    if disc.n_z == 1:
        hz = 0.5 * t0
    z_bot = _graded(hz, disc.face_layers, disc.grading)
    z = np.unique(np.round(np.concatenate([z_bot, z_mid, t0 - z_bot]) / t0, 15) * t0)
    return r, z


def section_mesh(plate: Plate, disc: AxisymDiscretisation) -> ngs.Mesh:
    """NGSolve mesh of the meridian section, x = R, y = Z (flat: the imperfection enters
    through the map G0). Boundaries ``axis``, ``rim``, ``bottom``, ``top``."""
    r, z = section_nodes(plate, disc)
    m = NGMesh(dim=2)
    ids = np.empty((len(r), len(z)), dtype=object)
    for i, ri in enumerate(r):
        for j, zj in enumerate(z):
            ids[i, j] = m.Add(MeshPoint(Pnt(float(ri), float(zj), 0.0)))
    m.Add(FaceDescriptor(surfnr=1, domin=1, bc=1))
    m.SetMaterial(1, "film")
    for i in range(len(r) - 1):
        for j in range(len(z) - 1):
            m.Add(Element2D(1, [ids[i, j], ids[i + 1, j], ids[i + 1, j + 1], ids[i, j + 1]]))
    names = {1: "bottom", 2: "rim", 3: "top", 4: "axis"}
    for i in range(len(r) - 1):
        m.Add(Element1D([ids[i, 0], ids[i + 1, 0]], index=1))
        m.Add(Element1D([ids[i + 1, -1], ids[i, -1]], index=3))
    for j in range(len(z) - 1):
        m.Add(Element1D([ids[-1, j], ids[-1, j + 1]], index=2))
        m.Add(Element1D([ids[0, j + 1], ids[0, j]], index=4))
    for k, name in names.items():
        m.SetBCName(k - 1, name)
    return ngs.Mesh(m)
