"""NGSolve finite-element model of the clamped dielectric buckling membrane (Ch. 5).

Formulation (re-derived; the thesis uses Abaqus UEL with D_L-based energy (5.1)-(5.9)):

* Unknowns: displacement ``u`` (VectorH1) and the *scaled* potential
  ``p = phi * sqrt(eps/mu_ref)`` (H1), both of polynomial ``order``.  The electric
  energy enters through the partial Legendre transform of the ideal dielectric (5.9),
  ``W_ele = I5 / (2 eps J) = D_L.C D_L / (2 eps J)``:  with ``E_L = dW/dD_L = C D_L/(eps J)``
  one gets ``D_L = eps J C^-1 E_L`` and the electric enthalpy

      Omega(F, E_L) = min over ... = W_mech(F) + W_ele - E_L.D_L
                    = W_mech(F) - eps/2 J C^-1 : (E_L x E_L),     E_L = -Grad phi,

  (tested in ``verification/test_ch5_constitutive.py``).  Equilibrium is the saddle point
  of ``int Omega dV``: minimum in ``u``, maximum in ``phi``.  Dividing by ``mu_ref`` and
  scaling the potential makes the discrete problem depend on eps only through the
  normalised voltage ``v = Phi/t0 sqrt(eps/mu_ref)``.
* Mechanical parts: neo-Hookean (5.15) ``mu/2 (J^-2/3 I1 - 3) + k/2 (J-1)^2`` and Ogden
  (5.26) ``sum 2 mu_p/alpha_p^2 (sum_i lamb_i^alpha_p - 3) + k/2 (J-1)^2``.
* Ogden at equal principal stretches (the flat pre-buckled state has lam1 = lam2
  everywhere, §5.2.2.2): the eigenvalues of ``Cbar`` are computed in closed form
  (trigonometric solution of the characteristic cubic), whose derivative is singular
  (0 * inf) exactly at repeated eigenvalues.  We evaluate the energy at
  ``Cbar + delta P`` and ``Cbar - delta P`` with a fixed traceless ``P = diag(1,0,-1)``
  in a frame rotated away from the model axes and average: the odd term cancels, so the
  energy is that of (5.26) up to O(delta^2) (delta = 1e-3: relative error ~1e-6, checked
  against the closed-form Kirchhoff stress (5.27) at equal stretches), while every
  evaluated matrix has distinct eigenvalues and automatic differentiation gives finite,
  accurate stresses and tangents (no case distinction (5.37)-(5.50) is needed).
* Mesh: a netgen triangulation of the disk extruded into ``layers`` prism layers
  (the thesis: 8-node bricks, 5 layers).  Edge (lateral face) clamped: u = 0.
  Electrodes: p = 0 on the bottom face, p = v t0 on the top face.  Imperfection:
  the reference geometry is lifted by ``w0(r) = imperfection t0 (1 - r^2/a^2)^2``
  (the clamped-plate polynomial close to the first buckling mode).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import ngsolve as ngs
import numpy as np
from debench.models.buckling.parameters import MU_REF, Discretisation, NeoHookean, Ogden, Plate
from debench.models.errors import ConvergenceError, require
from netgen.geom2d import SplineGeometry
from netgen.meshing import Element2D, Element3D, FaceDescriptor, MeshPoint, Pnt
from netgen.meshing import Mesh as NGMesh

NEWTON_TOL = 1e-9    # Newton: max |correction| / t0
NEWTON_MAXIT = 30
EIG_ATOL = 1e-13     # absolute floor for Ritz-value convergence (lambda is dimensionless,
                     # ~1e-2 for the unloaded aspect-10 plate; near lambda = 0 only this counts)
RESIDUAL_ATOL = 1e-12  # accept a stalled correction once |residual| < this * t0^2


# --------------------------------------------------------------------------- mesh
def disk_prism_mesh(plate: Plate, disc: Discretisation, *, with_imperfection: bool = True
                    ) -> ngs.Mesh:
    """Extruded prism mesh of the disk of radius ``plate.radius`` and thickness t0.

    Boundaries: ``bottom`` (z = 0), ``top`` (z = t0), ``edge`` (r = a).  The
    imperfection ``w0(r)`` lifts every node vertically (same for all layers).
    """
    a, t0 = plate.radius, plate.thickness
    geo = SplineGeometry()
    geo.AddCircle((0.0, 0.0), a, bc="edge")
    m2 = geo.GenerateMesh(maxh=disc.h_rel * t0)
    pts2 = np.array([[p[0], p[1]] for p in m2.Points()])
    tris = np.array([[v.nr - 1 for v in el.vertices] for el in m2.Elements2D()])
    segs = np.array([[v.nr - 1 for v in el.vertices] for el in m2.Elements1D()])
    npt = len(pts2)
    amp = plate.imperfection * t0 if with_imperfection else 0.0
    r2 = np.sum(pts2**2, axis=1) / a**2
    w0 = amp * np.clip(1.0 - r2, 0.0, None) ** 2

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


# --------------------------------------------------------------------------- energies
def _sym_eigs(M):
    """Closed-form eigenvalues of a symmetric 3x3 CF matrix with distinct eigenvalues."""
    m = ngs.Trace(M) / 3
    dev = M - m * ngs.Id(3)
    p = ngs.sqrt(ngs.InnerProduct(dev, dev) / 6)
    r = ngs.Det(dev) / (2 * p**3)
    r = ngs.IfPos(r - 1, 1, ngs.IfPos(-1 - r, -1, r))
    phi = ngs.acos(r) / 3
    return [m + 2 * p * ngs.cos(phi + 2 * math.pi * j / 3) for j in range(3)]


def _perturbation():
    """Fixed traceless symmetric direction, diag(1,0,-1) in a generic rotated frame."""
    ang = (0.3, 0.7, 1.1)
    cz, sz = math.cos(ang[0]), math.sin(ang[0])
    cy, sy = math.cos(ang[1]), math.sin(ang[1])
    cx, sx = math.cos(ang[2]), math.sin(ang[2])
    Rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    Ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    Rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    R = Rz @ Ry @ Rx
    return R @ np.diag([1.0, 0.0, -1.0]) @ R.T


def mechanical_energy_cf(F, mat: NeoHookean | Ogden):
    """Mechanical energy density W_mech(F) [Pa], Eq. (5.15) or (5.26) + k/2 (J-1)^2."""
    C = F.trans * F
    J = ngs.Det(F)
    vol = mat.k / 2 * (J - 1) ** 2
    if isinstance(mat, NeoHookean):
        return mat.mu / 2 * (J ** (-2 / 3) * ngs.Trace(C) - 3) + vol
    Cb = J ** (-2 / 3) * C
    P = ngs.CF(tuple(_perturbation().ravel()), dims=(3, 3))
    w = 0
    for sign in (1.0, -1.0):
        eigs = _sym_eigs(Cb + sign * mat.delta * P)
        for a, mu in zip(mat.alphas, mat.mus, strict=True):
            w = w + 0.5 * 2 * mu / a**2 * (sum(e ** (a / 2) for e in eigs) - 3)
    return w + vol


def enthalpy_cf(F, EL_hat, mat, mu_ref: float = MU_REF):
    """Electric enthalpy Omega/mu_ref with the scaled referential field
    ``EL_hat = E_L sqrt(eps/mu_ref)``: W_mech/mu_ref - 1/2 J C^-1:(EL x EL)."""
    C = F.trans * F
    J = ngs.Det(F)
    return mechanical_energy_cf(F, mat) / mu_ref - 0.5 * J * ngs.InnerProduct(
        ngs.Inv(C) * EL_hat, EL_hat)


# --------------------------------------------------------------------------- problem
@dataclass
class MembraneModel:
    """The discrete saddle-point problem of one plate, material and mesh."""

    plate: Plate
    material: NeoHookean | Ogden
    disc: Discretisation = field(default_factory=Discretisation)
    with_imperfection: bool = True
    inverse: str = "umfpack"

    def __post_init__(self):
        require(self.inverse in ngs.la.GetAvailableSolvers() or self.inverse == "sparsecholesky",
                f"inverse must be one of {ngs.la.GetAvailableSolvers()}, got {self.inverse}")
        self.mesh = disk_prism_mesh(self.plate, self.disc, with_imperfection=self.with_imperfection)
        order = self.disc.order
        V = ngs.VectorH1(self.mesh, order=order, dirichlet="edge")
        Q = ngs.H1(self.mesh, order=order, dirichlet="top|bottom")
        self.X = V * Q
        (u, p), (du, dp) = self.X.TnT()
        F = ngs.Id(3) + ngs.Grad(u)
        self.a = ngs.BilinearForm(self.X, symmetric=False)
        self.a += ngs.Variation(enthalpy_cf(F, -ngs.Grad(p), self.material).Compile() * ngs.dx)
        self.m = ngs.BilinearForm(self.X, symmetric=False)
        self.m += ngs.InnerProduct(u, du) / self.plate.thickness**2 * ngs.dx
        self.m.Assemble()
        self.gf = ngs.GridFunction(self.X)
        self.v = 0.0
        self.res = self.gf.vec.CreateVector()
        self.stats = {"assemble_s": 0.0, "factor_s": 0.0, "newton_steps": 0}

    # ----------------------------------------------------------------- basics
    @property
    def ndof(self) -> int:
        return self.X.ndof

    @property
    def nelements(self) -> int:
        return self.mesh.ne

    def set_voltage(self, v: float) -> None:
        """Impose the normalised voltage ``v`` on the top electrode (bottom grounded)."""
        self.v = float(v)
        if not hasattr(self, "_dir_pattern"):
            tmp = ngs.GridFunction(self.X)
            tmp.components[1].Set(self.plate.thickness, definedon=self.mesh.Boundaries("top"))
            fixed = ~np.array(self.X.FreeDofs(), dtype=bool)
            self._dir_fixed = fixed
            self._dir_pattern = np.array(tmp.vec.FV(), copy=True)[fixed]
        # only the Dirichlet (non-free) dofs are touched: all electrode dofs are fixed
        self.gf.vec.FV().NumPy()[self._dir_fixed] = self.v * self._dir_pattern

    def state(self) -> np.ndarray:
        return np.array(self.gf.vec.FV(), copy=True)

    def set_state(self, x: np.ndarray) -> None:
        self.gf.vec.FV().NumPy()[:] = x

    def _factor(self):
        t = time.perf_counter()
        self.a.AssembleLinearization(self.gf.vec)
        t1 = time.perf_counter()
        try:
            inv = self.a.mat.Inverse(self.X.FreeDofs(), inverse=self.inverse)
        except Exception as exc:  # NgException: singular tangent (exactly at a bifurcation)
            raise ConvergenceError(f"factorisation of the tangent failed at v={self.v:.6g}: "
                                   f"{exc}") from exc
        t2 = time.perf_counter()
        self.stats["assemble_s"] += t1 - t
        self.stats["factor_s"] += t2 - t1
        return inv

    def newton(self, *, tol: float = NEWTON_TOL, maxit: int = NEWTON_MAXIT) -> int:
        """Newton for the saddle point at the current voltage; raises ConvergenceError."""
        t0 = self.plate.thickness
        free = np.array(self.X.FreeDofs(), dtype=bool)
        for it in range(1, maxit + 1):
            self.a.Apply(self.gf.vec, self.res)
            rn = float(np.linalg.norm(self.res.FV().NumPy()[free]))
            if it > 1 and rn <= RESIDUAL_ATOL * t0**2:
                # near a bifurcation the tangent is almost singular and round-off in the
                # correction stalls above tol; the residual (scale t0^2 for unit strain in
                # the mu_ref-scaled energy) has reached round-off level
                return it - 1
            inv = self._factor()
            du = (inv * self.res).Evaluate()
            dmax = float(np.max(np.abs(du.FV().NumPy())))
            if not np.isfinite(dmax):
                raise ConvergenceError(f"Newton: non-finite correction at v={self.v:.6g}")
            self.gf.vec.data -= du
            self.stats["newton_steps"] += 1
            if dmax < tol * t0:
                return it
            if dmax > 0.5 * t0 * self.plate.aspect:
                raise ConvergenceError(
                    f"Newton: correction {dmax / t0:.3g} t0 too large at v={self.v:.6g}")
        raise ConvergenceError(f"Newton: no convergence in {maxit} steps at v={self.v:.6g}, "
                               f"last |du|/t0={dmax / t0:.3g}")

    # ----------------------------------------------------------------- outputs
    def _point(self, x, y, z):
        try:
            return self.mesh(x, y, z)
        except Exception as exc:  # NgException
            raise ValueError(
                f"point ({x:.3g}, {y:.3g}, {z:.3g}) is outside the faceted mesh: the "
                f"imperfection {self.plate.imperfection} t0 is too curved for h_rel = "
                f"{self.disc.h_rel} (works for imperfection <= 1e-3)") from exc

    def centre_deflection(self) -> float:
        """Vertical displacement of the centre point of the top surface / t0."""
        t0 = self.plate.thickness
        z = t0 + (self.plate.imperfection * t0 if self.with_imperfection else 0.0)
        return float(self.gf.components[0](self._point(0.0, 0.0, z - 1e-12 * t0))[2]) / t0

    def centre_midplane_deflection(self) -> float:
        """Mean vertical displacement of the top and bottom centre points / t0 (free of the
        symmetric thinning of the flat film)."""
        t0 = self.plate.thickness
        w = self.plate.imperfection * t0 if self.with_imperfection else 0.0
        ut = self.gf.components[0](self._point(0.0, 0.0, t0 + w - 1e-12 * t0))[2]
        ub = self.gf.components[0](self._point(0.0, 0.0, w + 1e-12 * t0))[2]
        return 0.5 * (ut + ub) / t0

    def centre_thickness(self) -> float:
        """Current thickness at the centre / t0 (top minus bottom vertical position)."""
        t0 = self.plate.thickness
        w = self.plate.imperfection * t0 if self.with_imperfection else 0.0
        ut = self.gf.components[0](self._point(0.0, 0.0, t0 + w - 1e-12 * t0))[2]
        ub = self.gf.components[0](self._point(0.0, 0.0, w + 1e-12 * t0))[2]
        return (t0 + ut - ub) / t0

    def centre_stress(self) -> np.ndarray:
        """Total Cauchy stress / mu_ref at the mid-plane centre (3x3)."""
        u, p = self.gf.components
        F = ngs.Id(3) + ngs.Grad(u)
        J = ngs.Det(F)
        E = -(ngs.Inv(F).trans * ngs.Grad(p))   # true field, scaled, Eq. (5.14)
        # mechanical Cauchy stress from the energy derivative: sigma = J^-1 dW/dF F^T
        Fv = ngs.Parameter(0)  # placeholder to keep numpy path below
        del Fv
        t0 = self.plate.thickness
        w = self.plate.imperfection * t0 if self.with_imperfection else 0.0
        mip = self.mesh(0.0, 0.0, 0.5 * t0 + w)
        Fn = np.array(F(mip)).reshape(3, 3)
        En = np.array(E(mip))
        from debench.models.buckling.analytic import cauchy_mech_numpy
        sig = cauchy_mech_numpy(Fn, self.material) / MU_REF
        sig += np.outer(En, En) - 0.5 * En @ En * np.eye(3)
        del J
        return sig

    def max_true_field(self, npts: int = 40) -> float:
        """Largest scaled true field |E| sqrt(eps/mu_ref) sampled along a radius (mid-plane)."""
        u, p = self.gf.components
        F = ngs.Id(3) + ngs.Grad(u)
        E = ngs.Norm(ngs.Inv(F).trans * ngs.Grad(p))
        a, t0 = self.plate.radius, self.plate.thickness
        best = 0.0
        for r in np.linspace(0, 0.95 * a, npts):
            amp = self.plate.imperfection * t0 if self.with_imperfection else 0.0
            w = amp * (1 - (r / a) ** 2) ** 2
            best = max(best, float(E(self.mesh(r, 0.0, 0.5 * t0 + w))))
        return best

    # ----------------------------------------------------------------- stability
    def lowest_eigenvalues(self, *, nev: int = 3, iters: int = 300, rtol: float = 1e-9,
                           seed: int = 0, shift: float = 0.0):
        """Eigenvalues of smallest magnitude of the condensed tangent S u = lambda M u.

        S = K_uu + K_up K_pp^-1 K_pu is the stiffness at fixed electrode voltage.  Block
        inverse (subspace) iteration with Rayleigh-Ritz, using the factorised saddle-point
        tangent: the potential rows of the right-hand side are zero, so the displacement
        part of each solve is S^-1 M x.  M is the L2 mass of u / t0^2.
        With ``shift > 0`` the iteration runs on S + shift M, so it returns the eigenvalues
        of S closest to -shift: the algebraically smallest ones whenever they exceed
        -shift (used to detect negative eigenvalues, i.e. instability, along the path).
        Returns (eigenvalues sorted ascending, modes as columns).  Raises
        ConvergenceError if the Ritz values do not settle to ``rtol``.
        """
        if shift:
            self.a.AssembleLinearization(self.gf.vec)
            self.a.mat.AsVector().data += shift * self.m.mat.AsVector()
            inv = self.a.mat.Inverse(self.X.FreeDofs(), inverse=self.inverse)
        else:
            inv = self._factor()
        free = np.array(self.X.FreeDofs(), dtype=bool)
        nu = ngs.VectorH1(self.mesh, order=self.disc.order).ndof
        mask = free.copy()
        mask[nu:] = False
        rng = np.random.default_rng(seed)
        nb = nev + 2
        Xb = rng.standard_normal((len(free), nb)) * mask[:, None]
        vin, vout = self.gf.vec.CreateVector(), self.gf.vec.CreateVector()

        def apply(mat_or_inv, x):
            vin.FV().NumPy()[:] = x
            vout.data = mat_or_inv * vin
            return np.array(vout.FV(), copy=True)

        Mmat = self.m.mat
        old = None
        for _ in range(iters):
            MX = np.column_stack([apply(Mmat, Xb[:, j]) for j in range(nb)])
            Y = np.column_stack([apply(inv, MX[:, j]) for j in range(nb)]) * mask[:, None]
            scale = np.max(np.abs(Y), axis=0)
            if not np.all(np.isfinite(scale)) or np.any(scale == 0):
                raise ConvergenceError("subspace iteration: singular tangent (exact bifurcation)")
            Y = Y / scale
            MX = MX / scale       # keeps S Y = M X
            MY = np.column_stack([apply(Mmat, Y[:, j]) for j in range(nb)])
            A = Y.T @ MX          # Y^T S Y  (S Y = M X)
            B = Y.T @ MY
            A = 0.5 * (A + A.T)
            B = 0.5 * (B + B.T)
            # Rayleigh-Ritz in an M-orthonormal basis of span(Y) (columns may differ by
            # many orders of magnitude when an eigenvalue is almost zero)
            bw, bv = np.linalg.eigh(B)
            keep = bw > 1e-13 * bw.max()
            T = bv[:, keep] / np.sqrt(bw[keep])
            w, Q = np.linalg.eigh(T.T @ A @ T)
            Q = T @ Q
            if len(w) < nb:
                Q = np.column_stack([Q, rng.standard_normal((nb, nb - len(w)))])
                w = np.concatenate([w, np.full(nb - len(w), np.inf)])
            order = np.argsort(np.abs(w))
            w, Q = w[order], Q[:, order]
            Xb = Y @ Q
            wscale = np.max(np.abs(w[np.isfinite(w)]))   # block scale: absolute floor
            if old is not None and np.all(np.abs(w[:nev] - old) <= rtol * wscale + EIG_ATOL):
                idx = np.argsort(w[:nev])
                return w[:nev][idx] - shift, Xb[:, :nev][:, idx]
            old = w[:nev]
        raise ConvergenceError(f"subspace iteration: no convergence in {iters} steps ({w[:nev]})")


def energies_at(F: np.ndarray, E_hat: np.ndarray, mat: NeoHookean | Ogden,
                mu_ref: float = MU_REF) -> tuple[float, float]:
    """Evaluate the CoefficientFunction energies at a constant ``F`` and scaled field.

    Returns ``(W_mech [Pa], Omega/mu_ref)`` exactly as assembled by :class:`MembraneModel`
    (used to check the NGSolve energies against :mod:`debench.models.materials`).
    """
    F = np.asarray(F, dtype=float)
    require(F.shape == (3, 3), f"F must be 3x3, got {F.shape}")
    require(np.linalg.det(F) > 0, f"det F must be > 0, got {np.linalg.det(F)}")
    mesh = _unit_mesh()
    mip = mesh(0.25, 0.25, 0.25)
    Fcf = ngs.CF(tuple(F.ravel()), dims=(3, 3))
    Ecf = ngs.CF(tuple(float(e) for e in E_hat))
    return (float(mechanical_energy_cf(Fcf, mat)(mip)),
            float(enthalpy_cf(Fcf, Ecf, mat, mu_ref)(mip)))


def _unit_mesh():
    ngm = NGMesh(dim=3)
    pts = [ngm.Add(MeshPoint(Pnt(*p))) for p in ((0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1))]
    ngm.Add(Element3D(1, pts))
    return ngs.Mesh(ngm)


def mode_axisymmetry(model: MembraneModel, mode: np.ndarray, n_theta: int = 24) -> float:
    """Fraction of a mode's displacement in the angular harmonic n = 0.

    The mode's cylindrical components (u_r, u_theta, u_z) are sampled on the mid-plane
    circle r = a/2; returns sum_c |mean_theta u_c|^2 / mean_theta sum_c |u_c|^2, which is
    1 for an axisymmetric mode and 0 for a pure n >= 1 (wrinkling) mode.
    """
    gf = ngs.GridFunction(model.X)
    gf.vec.FV().NumPy()[:] = mode
    gu = gf.components[0]
    a, t0 = model.plate.radius, model.plate.thickness
    r = 0.5 * a
    w = (model.plate.imperfection * t0 if model.with_imperfection else 0.0) * (1 - 0.25) ** 2
    comps = []
    for th in np.linspace(0, 2 * np.pi, n_theta, endpoint=False):
        ux, uy, uz = gu(model.mesh(r * np.cos(th), r * np.sin(th), 0.5 * t0 + w))
        comps.append((ux * np.cos(th) + uy * np.sin(th), -ux * np.sin(th) + uy * np.cos(th), uz))
    comps = np.array(comps)
    total = float(np.mean(np.sum(comps**2, axis=1)))
    if total == 0:
        raise ValueError("mode is zero on the sampling circle")
    return float(np.sum(np.mean(comps, axis=0) ** 2) / total)


def _control_dofs(model: MembraneModel) -> tuple[int, int]:
    """z-displacement dofs of the top and bottom vertices nearest to the centre axis."""
    t0 = model.plate.thickness
    w0 = model.plate.imperfection * t0 if model.with_imperfection else 0.0
    best = {}
    for v in model.mesh.vertices:
        x, y, z = v.point
        for key, zt in (("top", t0 + w0), ("bottom", w0)):
            d = x * x + y * y + (z - zt) ** 2
            if key not in best or d < best[key][0]:
                best[key] = (d, v.nr)
    dofs = []
    for key in ("top", "bottom"):
        nrs = model.X.GetDofNrs(ngs.NodeId(ngs.VERTEX, best[key][1]))
        dofs.append(int(nrs[2]))          # (u_x, u_y, u_z, phi) of the compound space
    return dofs[0], dofs[1]


def control_deflection(model: MembraneModel) -> float:
    """Control variable of the deflection-controlled continuation: mean z-displacement of
    the top and bottom vertices nearest to the centre, / t0."""
    it, ib = model._ctrl if hasattr(model, "_ctrl") else _control_dofs(model)
    model._ctrl = (it, ib)
    x = model.gf.vec.FV().NumPy()
    return 0.5 * (x[it] + x[ib]) / model.plate.thickness


def newton_deflection(model: MembraneModel, c: float, *, tol: float = NEWTON_TOL,
                      maxit: int = NEWTON_MAXIT) -> int:
    """Bordered Newton with the voltage as unknown and the centre deflection prescribed.

    Solves R(x, v) = 0, g(x) = c (g: :func:`control_deflection`) by
    ``dx = -a - dv b``, ``K a = R``, ``K b = dR/dv``, ``dv = (g(x) - c - g(a)) / g(b)``;
    dR/dv by a central difference, exact because R is quadratic in the potential.
    Passes voltage limit points (pull-in).  Raises ConvergenceError.
    """
    t0 = model.plate.thickness
    g = control_deflection  # noqa: F841 (sets model._ctrl)
    control_deflection(model)
    it_, ib_ = model._ctrl
    res_p, res_m = model.res.CreateVector(), model.res.CreateVector()
    for k in range(1, maxit + 1):
        v = model.v
        h = 1e-3 * max(abs(v), 0.1)
        model.set_voltage(v + h)
        model.a.Apply(model.gf.vec, res_p)
        model.set_voltage(v - h)
        model.a.Apply(model.gf.vec, res_m)
        model.set_voltage(v)
        model.a.Apply(model.gf.vec, model.res)
        rv = ((1 / (2 * h)) * (res_p - res_m)).Evaluate()
        inv = model._factor()
        a = (inv * model.res).Evaluate().FV().NumPy().copy()
        b = (inv * rv).Evaluate().FV().NumPy().copy()
        x = model.gf.vec.FV().NumPy()
        gx = 0.5 * (x[it_] + x[ib_]) / t0
        ga = 0.5 * (a[it_] + a[ib_]) / t0
        gb = 0.5 * (b[it_] + b[ib_]) / t0
        if gb == 0 or not np.isfinite(gb):
            raise ConvergenceError(f"bordered Newton: singular border at c={c}")
        dv = (gx - c - ga) / gb
        dx = -a - dv * b
        dmax = float(np.max(np.abs(dx)))
        if not np.isfinite(dmax) or abs(dv) > 0.5:
            raise ConvergenceError(f"bordered Newton: diverged at c={c} (dv={dv:.3g})")
        x += dx
        model.set_voltage(v + dv)
        model.stats["newton_steps"] += 1
        if dmax < tol * t0 and abs(dv) < 1e-9:
            return k
    raise ConvergenceError(f"bordered Newton: no convergence in {maxit} steps at c={c}")
