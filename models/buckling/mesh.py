"""Extruded prism mesh of the Chapter 5 clamped disk (the 3D finite-element model,
:mod:`debench.models.buckling.fem`).

A netgen triangulation of the disk extruded into ``layers`` prism layers (the thesis:
8-node bricks, 5 layers).  Boundaries: ``bottom`` (z = 0, grounded electrode), ``top``
(z = t0, the electrode at the voltage) and ``edge`` (r = a, clamped).  Imperfection: the
reference geometry is lifted by ``w0(r) = imperfection t0 (1 - r^2/a^2)^2`` (the
clamped-plate polynomial close to the first buckling mode), optionally plus a
non-axisymmetric term of wavenumber n (:class:`~debench.models.buckling.parameters.Plate`).
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np
from debench.models.buckling.parameters import Discretisation, Plate
from netgen.geom2d import SplineGeometry
from netgen.meshing import Element2D, Element3D, FaceDescriptor, MeshPoint, Pnt
from netgen.meshing import Mesh as NGMesh


def disk_prism_mesh(plate: Plate, disc: Discretisation, *, with_imperfection: bool = True
                    ) -> ngs.Mesh:
    """Extruded prism mesh of the disk of radius ``plate.radius`` and thickness t0.

    Boundaries: ``bottom`` (z = 0), ``top`` (z = t0), ``edge`` (r = a).  The
    imperfection ``w0(x, y)`` (:meth:`Plate.imperfection_lift`) lifts every node vertically
    (same for all layers).
    """
    a, t0 = plate.radius, plate.thickness
    geo = SplineGeometry()
    geo.AddCircle((0.0, 0.0), a, bc="edge")
    m2 = geo.GenerateMesh(maxh=disc.h_rel * t0)
    pts2 = np.array([[p[0], p[1]] for p in m2.Points()])
    tris = np.array([[v.nr - 1 for v in el.vertices] for el in m2.Elements2D()])
    segs = np.array([[v.nr - 1 for v in el.vertices] for el in m2.Elements1D()])
    npt = len(pts2)
    w0 = (plate.imperfection_lift(pts2[:, 0], pts2[:, 1]) if with_imperfection
          else np.zeros(npt))

    ngm = NGMesh(dim=3)
    ids = []
    for k in range(disc.layers + 1):
        z = t0 * k / disc.layers
        ids.append([ngm.Add(MeshPoint(Pnt(x, y, z + w)))
                    for (x, y), w in zip(pts2, w0, strict=True)])
    fd_bot = ngm.Add(FaceDescriptor(surfnr=1, domin=1, domout=0, bc=1))
    fd_top = ngm.Add(FaceDescriptor(surfnr=2, domin=1, domout=0, bc=2))
    fd_edge = ngm.Add(FaceDescriptor(surfnr=3, domin=1, domout=0, bc=3))
    ngm.SetBCName(0, "bottom")
    ngm.SetBCName(1, "top")
    ngm.SetBCName(2, "edge")
    # orientation: triangles counter-clockwise seen from +z
    p = pts2[tris]
    cross = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - \
            (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0])
    tris = np.where((cross > 0)[:, None], tris, tris[:, [0, 2, 1]])
    for k in range(disc.layers):
        lo, hi = ids[k], ids[k + 1]
        for t in tris:
            ngm.Add(Element3D(1, [lo[t[0]], lo[t[2]], lo[t[1]], hi[t[0]], hi[t[2]], hi[t[1]]]))
        for s in segs:
            ngm.Add(Element2D(fd_edge, [lo[s[0]], lo[s[1]], hi[s[1]], hi[s[0]]]))
    for t in tris:
        ngm.Add(Element2D(fd_bot, [ids[0][t[0]], ids[0][t[2]], ids[0][t[1]]]))
        ngm.Add(Element2D(fd_top, [ids[-1][t[0]], ids[-1][t[1]], ids[-1][t[2]]]))
    del npt
    return ngs.Mesh(ngm)
