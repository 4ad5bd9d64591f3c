"""Spectra per angular wavenumber of the axisymmetric model (Ch. 5).

The perturbation side of the model: the mode spaces of wavenumber n with their axis
regularity conditions, the bilinear forms at the current state for the three stability
operators of ``TANGENTS``, and the shift-invert Lanczos eigen-solve certified by
inertia counts. The formulation (the cos and sin groups of the perturbation, the axis
regularity per n, the condensed tangent and Haynsworth's inertia additivity) is written
once, in :mod:`debench.models.buckling.axisym`.

:class:`ModeAnalysis` is the part of
:class:`~debench.models.buckling.axisym.model.AxisymModel` that analyses perturbations: it
reads the state the model holds (``gf``, ``mesh``, ``plate``, ``material``, ``disc``,
``mu_ref``, the radius ``R``, the lift slope ``w0p``, the inverse lift ``_ginv()`` and the
enthalpy ``_enthalpy(F, E)``), caches its forms in ``_forms`` and adds its times to
``stats``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp
from debench.models import validation as val
from debench.models.buckling.axisym.kinematics import (
    perturbation_fields,
    perturbation_gradients,
    referential_field,
    section_gradient,
)
from debench.models.buckling.axisym.linalg import Factor, csr_of, embed_block
from debench.models.buckling.eigen import negative_pivots, negative_pivots_of
from debench.models.errors import ConvergenceError, require
from debench.models.materials import ngsolve_forms as ngf
from scipy.sparse.linalg import LinearOperator, eigsh

EIG_RTOL = 1e-10
"""Backward error ``||S x - lam M x|| / (||K_uu||_inf ||x|| + |lam| ||M x||)`` every returned
eigenpair must reach (its round-off floor is ~1e-16; ARPACK's shift-invert iteration gives
1e-15 .. 1e-13 here)."""
EIG_COUNT_MARGIN = 1e-6
"""Relative margin (to the largest computed |lambda|; at least two are computed, so the scale
is a separated eigenvalue even when the lowest is at zero) below the lowest computed
eigenvalue at which the inertia count certifies it: far above the eigenvalue error (1e-13 of
the scale) and far below the gaps between the modes (1e-1 of the scale)."""
SHIFT_BENDING = 0.1
"""Default eigen-shift, in units of the bending scale (t0/a)^2 of the pencil, below zero."""
EIG_ARPACK_TOL = 1e-13
"""ARPACK's convergence tolerance of the Ritz values (relative)."""
EIG_MAXIT = 3000
EIG_NCV = 12
"""Lanczos basis size of ARPACK (its default 2k+1 restarts often: 80 operator applications
for one eigenvalue against ~25 with 12, measured)."""
TANGENTS = ("coupled", "frozen_potential", "initial_stress")
"""The stability operators :meth:`ModeAnalysis.spectrum` offers."""
RQ_ORDER_FACTOR = 2
"""The Rayleigh quotients are integrated with the rule of order RQ_ORDER_FACTOR p, that of
NGSolve's assembly of the order-p forms (checked: on a coarse mesh the quotient at an
eigenvector equals its eigenvalue to round-off, test_ch5_axisym)."""


@dataclass(frozen=True)
class ModeSpectrum:
    """Lowest eigenvalues of the condensed tangent of wavenumber ``n`` at one state.

    ``lam`` ascending: the Rayleigh quotients of the eigenvectors integrated at the
    quadrature points (:meth:`ModeAnalysis.rayleigh_quotients`), the eigenvalues free of
    the round-off of the assembled matrices; ``lam_matrix``: the eigenvalues of the
    assembled pencil they refine (equal to ~1e-9 of the bending scale on graded meshes);
    ``residual``: the largest relative eigen-residual of the pencil; ``below``: the
    inertia count of eigenvalues below ``lam[0] - margin`` (zero: certified lowest);
    ``ndof``: unknowns of the perturbation problem; ``modes``: eigenvectors (free
    displacement DOFs, columns)."""

    n: int
    lam: np.ndarray
    residual: float
    below: int
    margin: float
    ndof: int
    modes: np.ndarray = field(repr=False, default_factory=lambda: np.zeros((0, 0)))
    lam_matrix: np.ndarray = field(repr=False, default_factory=lambda: np.zeros(0))


class ModeAnalysis:
    """Perturbations of wavenumber n about the current state of the axisymmetric film: the
    mode forms, their matrices and the lowest eigenvalues (module docstring)."""

    def _mode_space(self, n: int):
        p = self.disc.order
        if n == 0:
            dirs = ("axis|rim", "axis|rim", "rim", "top|bottom")        # U, V, W, Q
        elif n == 1:
            dirs = ("axis|rim", "rim", "axis|rim", "axis|top|bottom")   # S, D, W, Q
        else:
            dirs = ("axis|rim", "axis|rim", "axis|rim", "axis|top|bottom")
        spaces = [ngs.H1(self.mesh, order=p, dirichlet=d) for d in dirs]
        Y = spaces[0] * spaces[1] * spaces[2] * spaces[3]
        return Y, [s.ndof for s in spaces]

    def _mode_forms(self, n: int, tangent: str = "coupled"):
        """Bilinear forms (Hessian at the state, mass) of wavenumber n: of the enthalpy
        (``"coupled"``, ``"frozen_potential"``), or the initial-stress form (:meth:`spectrum`)."""
        if (n, tangent) in self._forms:
            return self._forms[(n, tangent)]
        Y, sizes = self._mode_space(n)
        (a1, a2, W, Q), (b1, b2, bw, _) = Y.TnT()
        energy = self._perturbation_energy(n, tangent, a1, a2, W, Q)
        k = ngs.BilinearForm(Y, symmetric=False)
        k += ngs.Variation((energy * self.R).Compile() * ngs.dx)
        Ut, Vt = _displacements(n, b1, b2)
        U, V = _displacements(n, a1, a2)
        m = ngs.BilinearForm(Y, symmetric=False)
        m += (U * Ut + V * Vt + W * bw) / self.plate.thickness**2 * self.R * ngs.dx
        m.Assemble()
        free = np.array(Y.FreeDofs(), dtype=bool)
        is_u = np.zeros(Y.ndof, dtype=bool)
        is_u[: sum(sizes[:3])] = True
        out = (Y, k, csr_of(m.mat, Y.ndof), free, is_u)
        self._forms[(n, tangent)] = out
        return out

    def _perturbation_energy(self, n: int, tangent: str, a1, a2, W, Q, t=1.0):
        """The energy of the wavenumber-n perturbation with amplitudes ``a1, a2, W, Q``
        (trial functions or grid functions; for n = 1 ``a1, a2`` = S, D) scaled by ``t``,
        about the current state: its Hessian in the amplitudes at zero is the stability
        operator ``tangent``."""
        g = ngs.grad
        U, V = _displacements(n, a1, a2)
        gU, gV = _displacements(n, g(a1), g(a2))
        R = self.R
        ur, uz, pp = self.gf.components
        Gx0 = section_gradient(ur, uz, R, self.w0p)
        gi = self._ginv()
        E0 = referential_field(gi, pp)
        dGc, dGs = perturbation_gradients(n, U, V, gU, gV, W, R)
        dEc, dEs = perturbation_fields(n, gi, Q, R)
        dGc, dGs, dEc, dEs = t * dGc, t * dGs, t * dEc, t * dEs
        if tangent == "initial_stress":
            energy = self._initial_stress_energy(Gx0 * gi, E0, dGc * gi, dGs * gi)
            return energy + 0 * Q * Q         # the potential block is unused
        # the sin group leaves the axisymmetric states (it couples theta): the energy to
        # second order about the state, exact in the Hessian
        F0 = Gx0 * gi
        return (self._enthalpy((Gx0 + dGc) * gi, E0 + dEc, F0)
                + self._enthalpy((Gx0 + dGs) * gi, E0 + dEs, F0))

    def _second_variation(self, n: int, tangent: str):
        """(grid function of the perturbation, the form of its second variation, the
        integrand of its mass ``(U^2 + V^2 + W^2)/t0^2 R``), built once per (n, tangent);
        they read the state through its grid function.

        The second variation ``int d^2/dt^2 energy(t x)|_0 R`` is the 1 x 1 Hessian, in
        the one unknown t of a :class:`ngsolve.NumberSpace`, of the energy of the
        perturbation ``t x``, assembled by NGSolve's automatic differentiation of the energy
        at the quadrature points (order RQ_ORDER_FACTOR p): the integrand is the pointwise
        quadratic form of the perturbation's gradients, never the product of assembled
        matrices with the DOF vector."""
        key = ("rq", n, tangent)
        if key not in self._forms:
            Y, *_ = self._mode_forms(n, tangent)
            x = ngs.GridFunction(Y)
            a1, a2, W, Q = x.components
            scale = ngs.NumberSpace(self.mesh)
            t = scale.TrialFunction()
            energy = self._perturbation_energy(n, tangent, a1, a2, W, Q, t)
            q = ngs.BilinearForm(scale, symmetric=True)
            q += ngs.Variation((energy * self.R).Compile()
                               * ngs.dx(bonus_intorder=RQ_ORDER_FACTOR * self.disc.order))
            U, V = _displacements(n, a1, a2)
            mass = (U * U + V * V + W * W) / self.plate.thickness**2 * self.R
            self._forms[key] = (x, q, ngs.GridFunction(scale), mass)
        return self._forms[key]

    def rayleigh_quotients(self, n: int, modes: np.ndarray, potentials: np.ndarray,
                           tangent: str = "coupled") -> np.ndarray:
        """Rayleigh quotients ``Q(x)/M(x)`` of the wavenumber-n perturbations ``x`` =
        (``modes``: free displacement DOFs, columns; ``potentials``: free potential DOFs,
        columns), with the second variation ``Q`` and the mass ``M`` integrated at the
        quadrature points (the order of the assembled forms, ``RQ_ORDER_FACTOR`` p).

        At an eigenvector of :meth:`spectrum`'s pencil (with its condensed potential) this
        is its eigenvalue, to second order in the eigenvector's error, but free of the
        cancellation of the assembled product ``x^T K x``: on the graded meshes the entries
        of K reach ~1/h_min times the bending scale of a near-zero eigenvalue, and the
        eigenvalues from the matrices scatter by ~1e-9 (measured, order 4 with 8 layers,
        between start vectors) where these agree to ~1e-16."""
        Y, _, _, free, is_u = self._mode_forms(n, tangent)
        x, q, at_zero, mass = self._second_variation(n, tangent)
        idx = np.flatnonzero(free)
        iu = idx[is_u[free]]
        ip = idx[~is_u[free]]
        order = RQ_ORDER_FACTOR * self.disc.order
        out = np.empty(modes.shape[1])
        vec = x.vec.FV().NumPy()
        for j in range(modes.shape[1]):
            vec[:] = 0.0
            vec[iu] = modes[:, j]
            vec[ip] = potentials[:, j]
            q.AssembleLinearization(at_zero.vec)
            out[j] = (csr_of(q.mat, 1)[0, 0]
                      / ngs.Integrate(mass, self.mesh, order=order))
        return out

    def _initial_stress_energy(self, F0, E0, dFc, dFs):
        """The energy whose Hessian at zero is the initial-stress operator: the material
        stiffness of the unloaded film plus the stress stiffness of the total second
        Piola-Kirchhoff stress ``S = F^-1 dOmega/dF`` of the state (``F0``, ``E0``), for the
        cos and sin groups ``dFc``, ``dFs`` of the perturbation."""
        F0 = F0.MakeVariable()
        S0 = ngs.Inv(F0) * self._enthalpy(F0, E0).Diff(F0)
        energy = 0
        for dF in (dFc, dFs):
            energy = energy + (self._mechanical_energy(ngs.Id(3) + dF, ngs.Id(3))
                               + 0.5 * ngs.InnerProduct(S0, dF.trans * dF))
        return energy

    def _mechanical_energy(self, F, about=None):
        """The material's strain energy at ``F`` in units of ``mu_ref``, exact at an
        axisymmetric ``F`` (``about`` None) or to second order in ``F - about`` about the
        axisymmetric state ``about``
        (:func:`~debench.models.materials.ngsolve_forms.axisymmetric_mechanical_energy`)."""
        return ngf.axisymmetric_mechanical_energy(self.material, F, about) / self.mu_ref

    def mode_blocks(self, n: int) -> np.ndarray:
        """Block index (0: U or S, 1: V or D, 2: W, 3: Q) of each free DOF of the
        wavenumber-n perturbation problem, in the order of :meth:`mode_matrices`."""
        Y, _, _, free, _ = self._mode_forms(val.integer_at_least("n", n, 0))
        sizes = [Y.components[k].ndof for k in range(4)]
        return np.repeat(np.arange(4), sizes)[free]

    def axis_fixed_blocks(self, n: int) -> set[int]:
        """The blocks of the wavenumber-n perturbation whose every DOF on the axis is fixed
        (the axis regularity conditions, module docstring)."""
        Y, _, _, free, _ = self._mode_forms(val.integer_at_least("n", n, 0))
        out, start = set(), 0
        for k in range(4):
            sp_k = Y.components[k]
            on_axis = np.array(sp_k.GetDofs(self.mesh.Boundaries("axis")), dtype=bool)
            if not np.any(free[start:start + sp_k.ndof][on_axis]):
                out.add(k)
            start += sp_k.ndof
        return out

    def mode_matrices(self, n: int, tangent: str = "coupled"):
        """(K, M, iu, ip): the saddle-point tangent of wavenumber ``n`` at the current state
        on its free DOFs, the mass on the displacement DOFs, and the masks of the
        displacement and potential DOFs among the free ones (``tangent``: see
        :meth:`spectrum`)."""
        n = val.integer_at_least("n", n, 0)
        val.choice("tangent", tangent, TANGENTS)
        Y, k, M, free, is_u = self._mode_forms(n, tangent)
        t = time.perf_counter()
        zero = ngs.GridFunction(Y)
        k.AssembleLinearization(zero.vec)
        K = csr_of(k.mat, Y.ndof)
        self.stats["assemble_s"] += time.perf_counter() - t
        K, M = K[free][:, free].tocsc(), M[free][:, free].tocsc()
        iu = is_u[free]
        return K, M, iu, ~iu

    def spectrum(self, n: int, nev: int = 3, *, sigma: float | None = None,
                 tangent: str = "coupled") -> ModeSpectrum:
        """Lowest ``nev`` eigenvalues of ``S_n x = lam M_n x`` at the current state.

        ``tangent``: ``"coupled"`` -- the condensed tangent at fixed electrode voltage
        ``S = K_uu - K_up K_pp^-1 K_pu``; ``"frozen_potential"`` -- ``K_uu``, the tangent at
        fixed potential (the field does not redistribute with the mode); ``"initial_stress"``
        -- the classical linear buckling operator: the material stiffness of the unloaded
        film plus the stress stiffness ``int S : (dF^T dF)`` of the state's total second
        Piola-Kirchhoff stress (mechanical + Maxwell).

        Shift-invert Lanczos (ARPACK) about ``sigma`` (default: a shift below the spectrum
        found by inertia counts, so the returned eigenvalues are the algebraically lowest);
        each solve ``(S - sigma M)^-1`` is one solve with the shifted saddle-point tangent.
        Certified by an inertia count: no eigenvalue lies below ``lam[0] - margin``
        (ConvergenceError otherwise, and when an eigen-residual exceeds EIG_RTOL)."""
        nev = val.integer_at_least("nev", nev, 1)
        t = time.perf_counter()
        K, M, iu, ip = self.mode_matrices(n, tangent)
        nu = int(iu.sum())
        require(nev < nu - 1, f"nev = {nev} must be < {nu - 1} (displacement DOFs)")
        pencil = _Pencil(K, M, iu, ip, tangent)
        rng = np.random.default_rng(0)
        user = sigma is not None
        # default shift: below zero by a tenth of the bending scale (t0/a)^2 of the
        # normalised pencil (the lowest bending eigenvalues of the unloaded film are
        # ~0.3 (t0/a)^2), so that the shifted tangent stays regular at a critical state
        sigma = (-SHIFT_BENDING * (self.plate.thickness / self.plate.radius) ** 2
                 if sigma is None else float(val.finite("sigma", sigma)))
        w, V = pencil.solve_about(sigma, nev, rng)
        margin = _count_margin(w)
        below = pencil.count_below(float(w[0]) - margin)
        if below and not user:
            # eigenvalues below the ones nearest zero: shift below the whole spectrum (found
            # by inertia counts) and take the lowest from there
            w, V = pencil.solve_about(pencil.shift_below(w, margin), nev, rng)
            margin = _count_margin(w)
            below = pencil.count_below(float(w[0]) - margin)
        res = pencil.residuals(w, V)
        if not np.all(res < EIG_RTOL):
            raise ConvergenceError(f"AxisymModel.spectrum(n={n}): eigen-residuals {res}")
        if below:
            raise ConvergenceError(f"AxisymModel.spectrum(n={n}): {below} eigenvalue(s) below "
                                   f"the lowest computed {w[0]:.6g}")
        w, V, res = w[:nev], V[:, :nev], res[:nev]
        lam = self.rayleigh_quotients(n, V, pencil.potentials(V), tangent)
        order = np.argsort(lam, kind="stable")
        self.stats["eig_s"] += time.perf_counter() - t
        self.stats["eigen_analyses"] += 1
        return ModeSpectrum(n=n, lam=lam[order], residual=float(np.max(res)), below=below,
                            margin=margin, ndof=pencil.K.shape[0], modes=V[:, order],
                            lam_matrix=w[order])


def _displacements(n: int, a1, a2):
    """(U, V) of the amplitudes (a1, a2): themselves, or for n = 1 (S, D) -> ((S + D)/2,
    (S - D)/2) (the axis regularity U + V = 0 imposed on S)."""
    if n == 1:
        return 0.5 * (a1 + a2), 0.5 * (a1 - a2)
    return a1, a2


def _count_margin(w: np.ndarray) -> float:
    """The certification margin of computed eigenvalues ``w`` (:data:`EIG_COUNT_MARGIN`)."""
    return EIG_COUNT_MARGIN * max(float(np.max(np.abs(w))), 1e-300)


class _Pencil:
    """The pencil ``S x = lam M x`` of one spectrum on the free displacement DOFs.

    ``S`` is applied as an operator (condensed for the coupled tangent); ``K`` is the matrix
    whose shifted factorisations ``K - s M`` apply ``(S - s M)^-1`` and whose inertia counts
    the eigenvalues below ``s``: the saddle-point tangent (its potential block's ``npp``
    negative pivots discounted) for the coupled tangent, else ``K_uu``; ``iu`` marks the
    displacement DOFs of ``K``, ``Mu`` is the mass on them."""

    def __init__(self, K, M, iu, ip, tangent: str):
        Mu = M[iu][:, iu]
        nu = int(iu.sum())
        Kuu = K[iu][:, iu]
        if tangent == "coupled":
            Kup, Kpp = K[iu][:, ip], K[ip][:, ip].tocsc()
            lu_pp = Factor(Kpp, "AxisymModel.spectrum (potential block)")
            npp = negative_pivots_of(lu_pp.lu)
            require(npp == Kpp.shape[0], "AxisymModel.spectrum: the potential block is not "
                                         "negative definite (no dielectric saddle point)")

            def S(x):
                x = np.asarray(x).reshape(nu, -1)
                return Kuu @ x - Kup @ np.column_stack(
                    [lu_pp.solve(c) for c in np.asarray(Kup.T @ x).T])
        else:
            K, npp = Kuu.tocsc(), 0
            iu = np.ones(nu, dtype=bool)

            def S(x):
                return Kuu @ np.asarray(x).reshape(nu, -1)

        self.S, self.K, self.Kuu, self.Mu, self.iu, self.nu, self.npp = S, K, Kuu, Mu, iu, nu, npp
        self.n_p = int(np.count_nonzero(ip))
        if tangent == "coupled":
            def potentials(V):
                V = np.asarray(V).reshape(nu, -1)
                return -np.column_stack([lu_pp.solve(c) for c in np.asarray(Kup.T @ V).T])
        else:
            def potentials(V):
                return np.zeros((self.n_p, np.asarray(V).reshape(nu, -1).shape[1]))
        self.potentials = potentials
        self.M_full = embed_block(Mu, iu)

    def count_below(self, s: float) -> int:
        """Eigenvalues of the pencil below ``s`` (inertia of ``K - s M`` less ``npp``)."""
        return negative_pivots((self.K - s * self.M_full).tocsc()) - self.npp

    def solve_about(self, s: float, nev: int, rng: np.random.Generator):
        """The ``max(nev, 2)`` eigenpairs nearest ``s`` (ascending), by ARPACK's
        shift-invert Lanczos with one factorisation of ``K - s M``; its start vector drawn
        from ``rng``."""
        lu = Factor(self.K - s * self.M_full, "AxisymModel.spectrum (shifted tangent)")
        idx_u, nf, nu = np.flatnonzero(self.iu), self.K.shape[0], self.nu

        def opinv(b):
            rhs = np.zeros(nf)
            rhs[idx_u] = np.asarray(b).ravel()
            return lu.solve(rhs)[idx_u]

        A = LinearOperator((nu, nu), matvec=lambda x: self.S(x).ravel(), dtype=float)
        OP = LinearOperator((nu, nu), matvec=opinv, dtype=float)
        w, V = eigsh(A, k=max(nev, 2), M=self.Mu, sigma=s, OPinv=OP, which="LM",
                     v0=rng.standard_normal(nu), tol=EIG_ARPACK_TOL, maxiter=EIG_MAXIT,
                     ncv=max(2 * nev + 1, EIG_NCV))
        order = np.argsort(w)
        return w[order], V[:, order]

    def shift_below(self, w: np.ndarray, margin: float) -> float:
        """A shift below the whole spectrum: down from the lowest computed eigenvalue in
        doubling steps until the inertia count finds no eigenvalue below it."""
        step = max(abs(float(w[0])), margin)
        sigma = float(w[0])
        for _ in range(80):
            sigma -= step
            if self.count_below(sigma) == 0:
                return sigma
            step *= 2.0
        raise ConvergenceError("AxisymModel.spectrum: no shift below the spectrum")

    def residuals(self, w: np.ndarray, V: np.ndarray) -> np.ndarray:
        """Backward errors of the eigenpairs (:data:`EIG_RTOL`)."""
        SV, MV = self.S(V), self.Mu @ V
        norm_s = float(sp.linalg.norm(self.Kuu, np.inf))
        return np.linalg.norm(SV - MV * w, axis=0) / (
            norm_s * np.linalg.norm(V, axis=0) + np.abs(w) * np.linalg.norm(MV, axis=0))
