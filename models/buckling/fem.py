"""NGSolve finite-element model of the clamped dielectric buckling membrane (Ch. 5).

Formulation (re-derived; the thesis uses Abaqus UEL with D_L-based energy (5.1)-(5.9)):

* Unknowns: displacement ``u`` (VectorH1) and the *scaled* potential
  ``p = phi * sqrt(eps/mu_ref)`` (H1), both of polynomial ``order``.  The electric
  energy enters through the partial Legendre transform of the ideal dielectric (5.9),
  ``W_ele = I5 / (2 eps J)``: with ``E_L = dW/dD_L = C D_L/(eps J)`` one gets
  ``D_L = eps J C^-1 E_L`` and the electric enthalpy

      Omega(F, E_L) = W_mech(F) - eps/2 J C^-1 : (E_L x E_L),     E_L = -Grad phi,

  (tested in ``verification/test_ch5_constitutive.py``).  Equilibrium is the saddle point
  of ``int Omega dV``: minimum in ``u``, maximum in ``phi``.  Dividing by ``mu_ref`` and
  scaling the potential makes the discrete problem depend on eps only through the
  normalised voltage ``v = Phi/t0 sqrt(eps/mu_ref)``.
* Energies: any library elastomer with the ideal dielectric (neo-Hookean (5.15), Ogden
  (5.26), ...) from the constitutive library's NGSolve path and the enthalpy of the ideal
  dielectric, compiled to C++ when the problem is large
  (:mod:`debench.models.buckling.energy`).
* Mesh: a netgen triangulation of the disk extruded into ``layers`` prism layers, lifted
  by the imperfection ``w0`` (:mod:`debench.models.buckling.mesh`).  Edge (lateral face)
  clamped: u = 0.  Electrodes: p = 0 on the bottom face, p = v t0 on the top face.

Linear algebra (chosen by measurement, ``benchmarks/test_bench_ch5.py``):

* one sparse direct factorisation object per model, created once (symbolic analysis) and
  refactorised with ``Update()`` at every Newton step; default ``sparsecholesky`` (LDL^T,
  factors the indefinite saddle-point tangent with a backward error like UMFPACK's, 2-4x
  faster); every solve checks its own relative residual and raises
  :class:`~debench.models.errors.ConvergenceError` when the factorisation broke down at a
  singular tangent (what UMFPACK reports as "WARNING: matrix is singular": the step landed
  on a bifurcation or a voltage limit point, where the tangent at fixed voltage has a zero
  eigenvalue) -- the continuation then steps back and retries with a smaller step;
* Newton stops (the package's policy, :mod:`debench.models.numerics.newton`) when the
  residual has dropped by :data:`~debench.models.numerics.newton.RTOL` relative to its
  reference (the larger of its first value and the load residual, the residual of the
  undeformed plate at the same voltage), or is at its round-off floor (``|K| |x|`` times
  machine epsilon, measured at the state), or the correction is below ``tol * t0``; a
  residual that stagnates above the floor raises;
* the stability eigen-analysis (condensed tangent ``S`` at fixed voltage, L2 mass ``M``)
  uses LOBPCG for the *algebraically* smallest eigenvalues -- negative ones included, at
  any distance below zero -- preconditioned with the factorised saddle-point tangent.

The module holds the discrete problem and its Newton solver (:class:`MembraneModel`); the
stability analysis of its states, a coherent whole of its own (the condensed operators,
LOBPCG, the inertia counts), is
:class:`~debench.models.buckling.fem_stability.MembraneStability`, of which the model class
is a subclass.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp
from debench.models import validation as val
from debench.models.buckling.energy import compile_energy, enthalpy_cf
from debench.models.buckling.fem_stability import MembraneStability
from debench.models.buckling.mesh import disk_prism_mesh
from debench.models.buckling.parameters import MU_REF, Discretisation, Plate
from debench.models.errors import ConvergenceError, require
from debench.models.materials import cauchy_stress
from debench.models.materials.protocol import IdealDielectricElastomer
from debench.models.numerics.newton import RTOL, NewtonResult, round_off_floor

NEWTON_TOL = 1e-9
"""Newton stops when max |correction| < NEWTON_TOL * t0 (1e-9 t0: the displacements are
O(t0), so 7 digits above double round-off)."""
NEWTON_STAGNATION = 0.5
"""A step that reduces the residual by less than this factor, twice in a row, is
stagnation: accepted only below NEWTON_STAGNATION_RTOL x the reference residual, otherwise
raised.  It happens next to a singular tangent (the critical voltage of the flat film),
where the correction wanders along the null mode while the residual sits at ~1e-9 of the
load (measured)."""
NEWTON_STAGNATION_RTOL = 1e-7
NEWTON_MAXIT = 30
LINEAR_REFINE_RTOL = 1e-10
"""A direct solve whose relative residual ||K x - b|| / ||b|| exceeds this is improved by
iterative refinement (at most LINEAR_REFINEMENTS steps): the factorisations give 1e-14 ..
1e-12 on these matrices, but sparsecholesky (LDL^T without pivoting) loses digits near a
singular tangent (measured 4e-6 next to the Ogden critical voltage)."""
LINEAR_REFINEMENTS = 3
LINEAR_RTOL = 1e-3
"""Relative residual above which a solve is reported as a breakdown (singular tangent): a
zero pivot gives O(1) or non-finite residuals that refinement does not reduce.  At the
critical voltage itself the tangent is singular by definition and the solves keep 1e-6 ..
1e-5 (measured, Ogden, coarse mesh): an inexact Newton correction that still converges
(the nonlinear residual decides), so the bound sits well above it."""
#: the sparse direct solvers of NGSolve a model may use (``inverse=``), in order of preference
INVERSES = ("sparsecholesky", "umfpack", "pardiso", "superlu")
CHORD_RATE = 0.25
"""Newton with a reused tangent (``chord=True``): a step with the factorised tangent of
an earlier state (of this solve or of the previous load) is kept while it reduces the
residual at least by this factor; a weaker step makes the next one reassemble and
refactorise (a step that increases the residual is undone first).  Assembly of the tangent
costs 8-13x a residual evaluation and 5-15x a factorisation here (measured), so a chord
step is cheap; 0.25 makes six digits of contraction cost ten chord steps at most."""

# --------------------------------------------------------------------------- problem
@dataclass
class MembraneModel(MembraneStability):
    """The discrete saddle-point problem of one plate, material and mesh.

    ``inverse``: sparse direct solver (:data:`INVERSES`); ``reuse``: keep one
    factorisation object and refactorise with ``Update()`` (False: a new ``Inverse``, i.e.
    a new symbolic analysis, at every step -- the engine before the measured choice, kept
    for the benchmarks); ``eigensolver``: ``"lobpcg"`` (algebraically smallest
    eigenvalues) or ``"subspace"`` (the former shift-free inverse subspace iteration,
    smallest |lambda|, kept for the benchmarks); ``compile``: ``"auto"``, True or False;
    ``chord``: Newton steps reuse the last factorised tangent while it contracts
    (:data:`CHORD_RATE`; False: a new tangent at every step, the former engine).
    """

    plate: Plate
    material: IdealDielectricElastomer
    disc: Discretisation = field(default_factory=Discretisation)
    with_imperfection: bool = True
    inverse: str = "sparsecholesky"
    reuse: bool = True
    eigensolver: str = "lobpcg"
    compile: str | bool = "auto"
    chord: bool = True

    def __post_init__(self):
        val.instance("plate", self.plate, Plate)
        val.instance("material", self.material, IdealDielectricElastomer)
        val.instance("disc", self.disc, Discretisation)
        avail = [s for s in INVERSES if s in ngs.la.GetAvailableSolvers()]
        val.choice("inverse", self.inverse, avail)
        val.choice("eigensolver", self.eigensolver, ("lobpcg", "subspace"))
        require(self.compile in ("auto", True, False),
                f"compile must be 'auto', True or False, got {self.compile!r}")
        require(self.chord in (True, False), f"chord must be True or False, got {self.chord!r}")
        self.mesh = disk_prism_mesh(self.plate, self.disc, with_imperfection=self.with_imperfection)
        order = self.disc.order
        V = ngs.VectorH1(self.mesh, order=order, dirichlet="edge")
        Q = ngs.H1(self.mesh, order=order, dirichlet="top|bottom")
        self.X = V * Q
        (u, p), (du, dp) = self.X.TnT()
        F = ngs.Id(3) + ngs.Grad(u)
        energy, how = compile_energy(
            enthalpy_cf(F, -ngs.Grad(p), self.material, ogden_delta=self.disc.ogden_delta),
            self.compile, self.X.ndof)
        self.a = ngs.BilinearForm(self.X, symmetric=False)
        self.a += ngs.Variation(energy * ngs.dx)
        self.m = ngs.BilinearForm(self.X, symmetric=False)
        self.m += ngs.InnerProduct(u, du) / self.plate.thickness**2 * ngs.dx
        self.m.Assemble()
        self.gf = ngs.GridFunction(self.X)
        self.v = 0.0
        self.res = self.gf.vec.CreateVector()
        self._free = np.array(self.X.FreeDofs(), dtype=bool)
        nu = V.ndof
        self._ufree = self._free.copy()
        self._ufree[nu:] = False
        self._pfree = self._free.copy()
        self._pfree[:nu] = False
        self._inv = None
        self._inv_state = None       # id of the assembled tangent the factor belongs to
        self._assembled = None
        self._fresh = False          # factor of the tangent at the current (converged) state
        self.stats = {"assemble_s": 0.0, "factor_s": 0.0, "solve_s": 0.0, "eig_s": 0.0,
                      "newton_steps": 0, "chord_steps": 0, "undone_steps": 0,
                      "factorisations": 0, "solves": 0, "refinements": 0,
                      "eigen_analyses": 0, "energy": how, "inverse": self.inverse,
                      "reuse": self.reuse}
        self.last_newton = NewtonResult(0, math.nan, math.nan, "not run",
                                        details={"floor": math.nan})
        self.last_eig = {"residual": float("nan"), "iterations": 0}

    # ----------------------------------------------------------------- basics
    @property
    def ndof(self) -> int:
        return self.X.ndof

    @property
    def nelements(self) -> int:
        return self.mesh.ne

    @property
    def h(self) -> float:
        """In-plane mesh size / t0 (the ``maxh`` of the triangulation)."""
        return self.disc.h_rel

    def set_voltage(self, v: float) -> None:
        """Impose the normalised voltage ``v`` on the top electrode (bottom grounded)."""
        self.v = float(val.finite("v", v))
        self._fresh = False
        if not hasattr(self, "_dir_pattern"):
            tmp = ngs.GridFunction(self.X)
            tmp.components[1].Set(self.plate.thickness, definedon=self.mesh.Boundaries("top"))
            fixed = ~self._free
            self._dir_fixed = fixed
            self._dir_pattern = np.array(tmp.vec.FV(), copy=True)[fixed]
        # only the Dirichlet (non-free) dofs are touched: all electrode dofs are fixed
        self.gf.vec.FV().NumPy()[self._dir_fixed] = self.v * self._dir_pattern

    def state(self) -> np.ndarray:
        return np.array(self.gf.vec.FV(), copy=True)

    def set_state(self, x: np.ndarray) -> None:
        self.gf.vec.FV().NumPy()[:] = x
        self._fresh = False

    # ----------------------------------------------------------------- linear algebra
    def residual_norm(self) -> float:
        """Euclidean norm of the residual on the free dofs at the current state."""
        self.a.Apply(self.gf.vec, self.res)
        return float(np.linalg.norm(self.res.FV().NumPy()[self._free]))

    def assemble(self) -> None:
        """Assemble the tangent at the current state."""
        t = time.perf_counter()
        self.a.AssembleLinearization(self.gf.vec)
        self.stats["assemble_s"] += time.perf_counter() - t
        self._assembled = object()

    def factor(self):
        """Factorise the assembled tangent (``Update()`` of one factorisation object when
        ``reuse``, else a new ``Inverse``).  Raises ConvergenceError on a breakdown."""
        t = time.perf_counter()
        try:
            if self.reuse and self._inv is not None:
                self._inv.Update()
            else:
                self._inv = self.a.mat.Inverse(self.X.FreeDofs(), inverse=self.inverse)
        except Exception as exc:  # NgException: singular tangent (exactly at a bifurcation)
            self._inv = None
            raise ConvergenceError(f"factorisation of the tangent failed at v={self.v:.6g}: "
                                   f"{exc}") from exc
        self.stats["factor_s"] += time.perf_counter() - t
        self.stats["factorisations"] += 1
        self._inv_state = self._assembled
        return self._inv

    def tangent(self):
        """Assemble and factorise the tangent at the current state."""
        self.assemble()
        return self.factor()

    def solve(self, rhs):
        """``K^-1 rhs`` with the current factorisation, its relative residual checked
        against :data:`LINEAR_RTOL` (a singular tangent raises ConvergenceError)."""
        t = time.perf_counter()
        x = (self._inv * rhs).Evaluate()
        bn = float(np.linalg.norm(rhs.FV().NumPy()[self._free]))
        for k in range(LINEAR_REFINEMENTS + 1):
            r = (rhs - self.a.mat * x).Evaluate()
            rn = float(np.linalg.norm(r.FV().NumPy()[self._free]))
            if not np.isfinite(rn) or rn <= LINEAR_REFINE_RTOL * bn or k == LINEAR_REFINEMENTS:
                break
            x.data += self._inv * r           # iterative refinement
            self.stats["refinements"] += 1
        self.stats["solve_s"] += time.perf_counter() - t
        self.stats["solves"] += 1
        if not (np.isfinite(rn) and rn <= LINEAR_RTOL * bn):
            raise ConvergenceError(
                f"singular tangent at v={self.v:.6g}: direct solve residual "
                f"{rn / max(bn, 1e-300):.3g} > {LINEAR_RTOL} (the state is at a bifurcation "
                "or a voltage limit point; step to a different load)")
        return x

    def load_residual(self) -> float:
        """Residual norm of the undeformed plate at the current voltage (the force scale of
        the electric load); the state is restored."""
        x = self.state()
        self.gf.vec.FV().NumPy()[self._ufree] = 0.0
        r = self.residual_norm()
        self.set_state(x)
        return r

    def residual_floor(self) -> float:
        """Round-off floor of the residual at the current state
        (:func:`~debench.models.numerics.newton.round_off_floor` over the free rows; K
        assembled)."""
        rows, cols, vals = self.a.mat.COO()
        K = sp.csr_matrix((np.abs(np.asarray(vals)), (np.asarray(rows), np.asarray(cols))),
                          shape=(self.ndof, self.ndof))
        return round_off_floor(K, np.abs(self.gf.vec.FV().NumPy()), self._free)

    def newton(self, *, tol: float = NEWTON_TOL, maxit: int = NEWTON_MAXIT) -> NewtonResult:
        """Newton for the saddle point at the current voltage; returns its NewtonResult.
        (``_newton``; after a failure no later step reuses this solve's tangent.)"""
        try:
            return self._newton(tol=tol, maxit=maxit)
        except ConvergenceError:
            self.forget_tangent()
            raise

    def forget_tangent(self) -> None:
        """Keep the factorisation object (its symbolic analysis) but no chord step may
        reuse its values: they may belong to a rejected iterate."""
        self._inv_state = None
        self._fresh = False

    def _newton(self, *, tol: float, maxit: int) -> NewtonResult:
        """Newton for the saddle point at the current voltage; returns its NewtonResult.

        With ``chord`` a step uses the last factorised tangent (:meth:`chord_usable`) while
        it contracts the residual by :data:`CHORD_RATE` (:meth:`_chord_verdict`), else the
        tangent is reassembled at the current iterate.  Stops when the state's error is
        below ``tol t0`` -- for a step with the tangent of its own iterate the correction
        ``max|du|`` bounds it (quadratic convergence), for a chord step with contraction
        ``theta`` the estimate ``max|du| theta / (1 - theta)`` does -- or when the residual
        is below RTOL times its reference (the larger of its first value and the load
        residual), or below its round-off floor (:meth:`residual_floor`); a stagnating
        residual is accepted only below NEWTON_STAGNATION_RTOL times the reference.
        Records the achieved residual in ``last_newton``.  Raises ConvergenceError.
        """
        tol = val.tolerance("tol", tol)
        maxit = val.integer_at_least("maxit", maxit, 1)
        t0 = self.plate.thickness
        self._fresh = False
        r_ref = self.load_residual()
        r_first = self.residual_norm()
        r_ref = max(r_ref, r_first)
        hist = [r_first]
        floor = None
        stalls = 0
        chord = self.chord_usable()
        chord_ok = self.chord        # False after an undone chord step: plain Newton from there
        for it in range(1, maxit + 1):
            if not chord:
                self.assemble()
            if floor is None:
                floor = self.residual_floor()
                if r_first <= floor:
                    result = self._record(0, r_first, r_ref, floor, "floor")
                    if not chord:
                        self.factor()
                        self._fresh = True
                    return result
            if not chord:
                self.factor()
            fresh_step = not chord
            du, dmax = self._correction(check_size=fresh_step)
            self.gf.vec.data -= du
            self.stats["newton_steps"] += 1
            rn = self.residual_norm()
            if fresh_step:
                chord = chord_ok              # the next step reuses this tangent
                err = dmax
            else:
                self.stats["chord_steps"] += 1
                verdict, theta = self._chord_verdict(rn, hist[-1])
                if verdict == "undo":
                    self.gf.vec.data += du
                    self.residual_norm()          # self.res back to the kept state
                    chord = chord_ok = False
                    continue
                chord = verdict == "keep"
                err = dmax * theta / (1 - theta)
            hist.append(rn)
            if fresh_step:                    # stagnation is judged on fresh tangents
                stalls = stalls + 1 if rn > NEWTON_STAGNATION * hist[-2] else 0
            how = self._stopped_by(err, rn, tol * t0, r_ref, floor, stalls)
            if how is not None:
                result = self._record(it, rn, r_ref, floor, how)
                if how == "correction":
                    # a factor of the state before a correction < tol t0 is the tangent at
                    # the converged state to O(tol) (used by the eigen-analysis); a chord
                    # step's factor belongs to an older state
                    self._fresh = fresh_step
                return result
        raise ConvergenceError(f"Newton: no convergence in {maxit} steps at v={self.v:.6g}, "
                               f"last |du|/t0={dmax / t0:.3g}, residual {rn:.3g} "
                               f"(first {r_first:.3g}, floor {floor:.3g})")

    def _correction(self, *, check_size: bool):
        """The Newton correction ``K^-1 R`` with the current factorisation and its largest
        entry; raises ConvergenceError when it is not finite or (``check_size``: a step
        with the tangent of its own iterate) larger than half the radius."""
        t0 = self.plate.thickness
        du = self.solve(self.res)
        dmax = float(np.max(np.abs(du.FV().NumPy())))
        if not np.isfinite(dmax):
            raise ConvergenceError(f"Newton: non-finite correction at v={self.v:.6g}")
        if dmax > 0.5 * t0 * self.plate.aspect and check_size:
            raise ConvergenceError(
                f"Newton: correction {dmax / t0:.3g} t0 too large at v={self.v:.6g}")
        return du, dmax

    def _stopped_by(self, err: float, rn: float, tol_abs: float, r_ref: float, floor: float,
                    stalls: int) -> str | None:
        """Why Newton stops after a step with error estimate ``err`` and residual ``rn``
        (:meth:`_newton`): ``"correction"`` (err < tol_abs), ``"relative residual"``,
        ``"floor"``, ``"stagnation at floor"`` (two stalled steps, residual below
        NEWTON_STAGNATION_RTOL times the reference), or None to go on; two stalled steps
        above that raise ConvergenceError."""
        if err < tol_abs:
            return "correction"
        if rn <= RTOL * r_ref:
            return "relative residual"
        if rn <= floor:
            return "floor"
        if stalls >= 2:
            if rn <= NEWTON_STAGNATION_RTOL * r_ref:
                return "stagnation at floor"
            raise ConvergenceError(
                f"Newton: residual stagnates at {rn:.3g} (reference {r_ref:.3g}, floor "
                f"{floor:.3g}) at v={self.v:.6g}")
        return None

    def chord_usable(self) -> bool:
        """Whether the next Newton step may reuse the factorisation: ``chord`` is on and the
        factor belongs to the assembled matrix (whatever state that was)."""
        return (self.chord and self._inv is not None and self._assembled is not None
                and self._inv_state is self._assembled)

    def _chord_verdict(self, rn: float, r_prev: float) -> tuple[str, float]:
        """Judge a chord step by its residual contraction ``theta = rn / r_prev``:
        ``"keep"`` (theta <= CHORD_RATE), ``"refresh"`` (kept, but the next step gets a new
        tangent) or ``"undo"`` (the residual grew or the step is not finite)."""
        theta = rn / r_prev if r_prev > 0 else 0.0
        if not (np.isfinite(rn) and theta < 1.0):
            self.stats["undone_steps"] += 1
            return "undo", theta
        return ("keep" if theta <= CHORD_RATE else "refresh"), theta

    def _record(self, it, rn, r_ref, floor, how) -> NewtonResult:
        """Record (``last_newton``) and return the result of a converged Newton."""
        self.last_newton = NewtonResult(it, rn, r_ref, how, details={"floor": floor})
        return self.last_newton

    # ----------------------------------------------------------------- outputs
    #: relative offsets (of t0) towards the mid-plane tried when a point on a face is not
    #: found in the faceted mesh: the flat facets of a curved imperfect face deviate from it
    #: by ~ imperfection (h/radius)^2, below 1e-3 t0 for every admissible mesh
    _FACE_OFFSETS = (0.0, 1e-9, 1e-6, 1e-4, 1e-3, 1e-2)

    def _point(self, x, y, z):
        """The mesh point at (x, y, z); a point on a face that the faceted mesh misses is
        moved towards the mid-plane by up to 1e-2 t0 (:data:`_FACE_OFFSETS`)."""
        t0 = self.plate.thickness
        towards_mid = 1.0 if z < self.lift(x, y) + 0.5 * t0 else -1.0
        for off in self._FACE_OFFSETS:
            mp = self.mesh(x, y, z + towards_mid * off * t0)
            if mp.nr >= 0:
                return mp
        raise ValueError(
            f"point ({x:.3g}, {y:.3g}, {z:.3g}) is outside the faceted mesh: the "
            f"imperfection {self.plate.imperfection} t0 is too curved for h_rel = "
            f"{self.disc.h_rel}")

    def lift(self, x: float = 0.0, y: float = 0.0) -> float:
        """Vertical lift of the reference geometry at (x, y) (m): the imperfection, or 0
        for the perfect plate."""
        return float(self.plate.imperfection_lift(x, y)) if self.with_imperfection else 0.0

    def centre_deflection(self) -> float:
        """Vertical displacement of the centre point of the top surface / t0."""
        t0 = self.plate.thickness
        z = t0 + self.lift()
        return float(self.gf.components[0](self._point(0.0, 0.0, z - 1e-12 * t0))[2]) / t0

    def centre_midplane_deflection(self) -> float:
        """Mean vertical displacement of the top and bottom centre points / t0 (free of the
        symmetric thinning of the flat film)."""
        t0, w = self.plate.thickness, self.lift()
        ut = self.gf.components[0](self._point(0.0, 0.0, t0 + w - 1e-12 * t0))[2]
        ub = self.gf.components[0](self._point(0.0, 0.0, w + 1e-12 * t0))[2]
        return 0.5 * (ut + ub) / t0

    def centre_thickness(self) -> float:
        """Current thickness at the centre / t0 (top minus bottom vertical position)."""
        t0, w = self.plate.thickness, self.lift()
        ut = self.gf.components[0](self._point(0.0, 0.0, t0 + w - 1e-12 * t0))[2]
        ub = self.gf.components[0](self._point(0.0, 0.0, w + 1e-12 * t0))[2]
        return (t0 + ut - ub) / t0

    def centre_stress(self) -> np.ndarray:
        """Total Cauchy stress / mu_ref at the mid-plane centre (3x3), Eq. (2.33), by the
        constitutive library (numpy path) at the FE deformation gradient and field."""
        u, p = self.gf.components
        F = ngs.Id(3) + ngs.Grad(u)
        mip = self._point(0.0, 0.0, 0.5 * self.plate.thickness + self.lift())
        Fn = np.array(F(mip)).reshape(3, 3)
        EL_hat = -np.array(ngs.Grad(p)(mip))          # scaled referential field
        eps = self.material.eps
        E_L = EL_hat * np.sqrt(MU_REF / eps)
        D_L = eps * np.linalg.det(Fn) * np.linalg.solve(Fn.T @ Fn, E_L)
        return cauchy_stress(self.material, Fn, D_L) / MU_REF

    def max_true_field(self, npts: int = 40) -> float:
        """Largest scaled true field |E| sqrt(eps/mu_ref) sampled along a radius (mid-plane)."""
        u, p = self.gf.components
        F = ngs.Id(3) + ngs.Grad(u)
        E = ngs.Norm(ngs.Inv(F).trans * ngs.Grad(p))
        a, t0 = self.plate.radius, self.plate.thickness
        best = 0.0
        for r in np.linspace(0, 0.95 * a, npts):
            best = max(best, float(E(self._point(r, 0.0, 0.5 * t0 + self.lift(r, 0.0)))))
        return best
