"""The axisymmetric model of the clamped film: its state, Newton and deflection control.

:class:`AxisymModel` holds the nonlinear state on the meridian section (the formulation,
boundary conditions and axis regularity: :mod:`debench.models.buckling.axisym`), equilibrates
it at a given voltage (:meth:`AxisymModel.newton`) or at a given centre deflection with the
voltage an unknown (:meth:`AxisymModel.newton_deflection`, through the voltage maximum), and
reads its point values. Its perturbation analysis (mode forms and spectra per wavenumber) is
:class:`~debench.models.buckling.axisym.spectra.ModeAnalysis`, of which it is a subclass.
"""

from __future__ import annotations

import math
import time

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp
from debench.models import validation as val
from debench.models.buckling.axisym.kinematics import (
    lift_inverse,
    referential_field,
    section_gradient,
)
from debench.models.buckling.axisym.linalg import (
    DIRECT_RTOL,
    REFINE_RTOL,
    REFINEMENTS,
    Factor,
    csr_of,
    require_finite_step,
)
from debench.models.buckling.axisym.section import AxisymDiscretisation, section_mesh
from debench.models.buckling.axisym.spectra import ModeAnalysis
from debench.models.buckling.energy import enthalpy_cf
from debench.models.buckling.parameters import MU_REF, Plate
from debench.models.errors import ConvergenceError, require
from debench.models.materials import ngsolve_forms as ngf
from debench.models.materials.protocol import IdealDielectricElastomer
from debench.models.numerics.newton import RTOL, NewtonResult, bordered_solve, round_off_floor
from scipy.sparse.linalg import splu

NEWTON_STAGNATION_RTOL = 1e-5
"""A Newton step that cannot reduce the residual is accepted as converged only below this
residual relative to its reference: next to a singular tangent (the critical voltage of the
flat film) the correction is dominated by round-off along the near-null mode and the
residual stagnates (measured: ~1e-7 .. 1e-6 of the load on 2 graded layers); above it the
step raises. The near-null mode is antisymmetric through the thickness and the flat state
symmetric, so what is left along it moves the eigenvalues only at second order."""
NEWTON_STALL_STEPS = 4
"""... or when that many full steps of the local phase have not improved on the best
iterate: next to the singular tangent the residual can alternate between ~1e-10 and
~1e-7 .. 1e-6 of the load without converging (measured: Ogden, order 2 with 2 layers, at
v = 0.1473, within 1e-3 of its critical voltage); the best iterate is then taken, under
the same bound as a step without descent."""
NEWTON_MAXIT = 40
NEWTON_LOCAL_RTOL = 1e-1
"""Below this residual (relative to its reference) Newton takes full steps without the
descent test: inside the region of quadratic convergence a step may raise the residual and
the next one still converges (measured for the imperfect Ogden film at v = 0.15 on 2 graded
layers, past its critical voltage: 1.5e-4, 6.2e-2, 3.5e-6, 1.4e-5, 3.2e-12 of the load)."""
DV_MAX_REL = 0.05
"""Largest voltage correction of one deflection-controlled Newton step, relative to the
voltage (damped Newton)."""
DOMAIN_HALVINGS = 12
"""Halvings of a deflection-controlled Newton correction whose trial state has a non-finite
residual (outside the material's domain) before the step raises: 2^-12 of a correction is
below the deflection steps of the path (>= 1e-6 t0 on a correction of O(1) t0)."""


class AxisymModel(ModeAnalysis):
    """The axisymmetric film: nonlinear state on the section, spectra per wavenumber.

    ``plate``, ``material`` (a library elastomer with the ideal dielectric:
    neo-Hookean, Ogden, ...), ``disc``; ``with_imperfection``
    lifts the reference body by the plate's axisymmetric imperfection (the non-axisymmetric
    ``wrinkle_imperfection`` of :class:`Plate` has no place in this model and is refused).
    ``mu_ref``: the normalising modulus.
    """

    def __init__(self, plate: Plate, material: IdealDielectricElastomer,
                 disc: AxisymDiscretisation | None = None, *, with_imperfection: bool = True,
                 mu_ref: float = MU_REF):
        val.instance("plate", plate, Plate)
        val.instance("material", material, IdealDielectricElastomer)
        disc = AxisymDiscretisation() if disc is None else disc
        val.instance("disc", disc, AxisymDiscretisation)
        require(plate.wrinkle_imperfection == 0.0,
                "plate.wrinkle_imperfection must be 0 for the axisymmetric model (a "
                "non-axisymmetric seed is no body of revolution)")
        self.plate, self.material, self.disc = plate, material, disc
        self.mu_ref = float(val.positive("mu_ref", mu_ref))
        self.with_imperfection = bool(with_imperfection)
        self.mesh = section_mesh(plate, disc)
        self.R = ngs.x
        a, t0 = plate.radius, plate.thickness
        amp = plate.imperfection * t0 if with_imperfection else 0.0
        # G0^-1 of the lift: (R, Z) -> (R, Z + w0(R)), w0' = -4 amp R/a^2 (1 - R^2/a^2)
        self.w0p = -4.0 * amp * ngs.x / a**2 * (1.0 - ngs.x**2 / a**2)
        self._amp = amp
        p = disc.order
        Ur = ngs.H1(self.mesh, order=p, dirichlet="axis|rim")
        Uz = ngs.H1(self.mesh, order=p, dirichlet="rim")
        P = ngs.H1(self.mesh, order=p, dirichlet="top|bottom")
        self.X = Ur * Uz * P
        (ur, uz, pp), _ = self.X.TnT()
        F, E = self._state_kinematics(ur, uz, pp)
        self.a = ngs.BilinearForm(self.X, symmetric=False)
        self.a += ngs.Variation((self._enthalpy(F, E) * self.R).Compile() * ngs.dx)
        self.gf = ngs.GridFunction(self.X)
        self.free = np.array(self.X.FreeDofs(), dtype=bool)
        nu = Ur.ndof + Uz.ndof
        self.is_u = np.zeros(self.X.ndof, dtype=bool)
        self.is_u[:nu] = True
        lift = ngs.GridFunction(self.X)
        lift.components[2].Set(ngs.y)
        self._linear = np.array(lift.vec.FV(), copy=True)   # p = Z, u = 0: uniform field
        self.v = 0.0
        self.stats = {"newton_steps": 0, "assemble_s": 0.0, "solve_s": 0.0, "eig_s": 0.0,
                      "eigen_analyses": 0, "domain_halvings": 0}
        self.last_newton = NewtonResult(0, math.nan, math.nan, "not run")
        self._forms: dict[int, tuple] = {}

    # --------------------------------------------------------------- kinematics
    def _ginv(self):
        return lift_inverse(self.w0p)

    def _state_kinematics(self, ur, uz, pp):
        """F and E_L (scaled) of an axisymmetric state (:mod:`debench.models.buckling.axisym`)."""
        F = section_gradient(ur, uz, self.R, self.w0p) * self._ginv()
        E = referential_field(self._ginv(), pp)
        return F, E

    def _enthalpy(self, F, E, about=None):
        """The enthalpy density (units of ``mu_ref``) at ``F``, ``E``: exact at an
        axisymmetric state (``about`` None), or to second order in ``F - about`` about the
        axisymmetric state ``about`` (:meth:`_mechanical_energy`)."""
        return enthalpy_cf(F, E, self.material, mu_ref=self.mu_ref, xp=ngf.axisymmetric(about))

    # --------------------------------------------------------------- state
    @property
    def ndof(self) -> int:
        return self.X.ndof

    def set_voltage(self, v: float) -> None:
        """Impose the normalised voltage ``v`` on the top electrode (bottom grounded); the
        potential changes by the uniform field of the voltage change (the predictor)."""
        v = float(val.finite("v", v))
        x = self.gf.vec.FV().NumPy()
        x += (v - self.v) * self._linear
        self.v = v

    def reset(self) -> None:
        """The undeformed film at zero voltage."""
        self.gf.vec[:] = 0.0
        self.v = 0.0

    def state(self) -> np.ndarray:
        return np.array(self.gf.vec.FV(), copy=True)

    def set_state(self, x: np.ndarray) -> None:
        self.gf.vec.FV().NumPy()[:] = x

    def residual_norm(self) -> float:
        """Euclidean norm of the residual on the free DOFs at the current state."""
        return float(np.linalg.norm(self._residual()[self.free]))

    def _residual(self) -> np.ndarray:
        r = self.gf.vec.CreateVector()
        self.a.Apply(self.gf.vec, r)
        return np.array(r.FV(), copy=True)

    def _tangent(self) -> sp.csr_matrix:
        t = time.perf_counter()
        self.a.AssembleLinearization(self.gf.vec)
        K = csr_of(self.a.mat, self.ndof)
        self.stats["assemble_s"] += time.perf_counter() - t
        return K

    def load_scale(self) -> float:
        """The scale of the load the voltage applies: the residual norm (free DOFs) of the
        undeformed section under the uniform field of the current voltage (u = 0,
        p = v Z/t0), i.e. the consistent nodal forces of the Maxwell traction on the faces.
        The state is restored."""
        x = self.state()
        self.set_state(self.v * self._linear)
        r0 = float(np.linalg.norm(self._residual()[self.free]))
        self.set_state(x)
        return r0

    def _converged(self, it: int, residual: float, ref: float, reason: str,
                   **details) -> NewtonResult:
        """Record (``last_newton``) and return the result of a converged Newton."""
        self.last_newton = NewtonResult(it, residual, ref, reason, details=details)
        return self.last_newton

    def newton(self, *, rtol: float = RTOL, maxit: int = NEWTON_MAXIT) -> NewtonResult:
        """Equilibrate the state at the current voltage (full Newton with the exact tangent,
        damped by halving when a step does not reduce the residual). Stops on the residual
        relative to its reference (the larger of the first residual and
        :meth:`load_scale`, a physical scale that does not change with the mesh: 5.66e-7 on
        1 .. 8 graded layers at v = 0.2) or at its round-off floor (the package's policy,
        :mod:`debench.models.numerics.newton`); returns the
        :class:`~debench.models.numerics.newton.NewtonResult` (also ``last_newton``);
        raises ConvergenceError when neither is reached in ``maxit`` steps."""
        rtol = val.tolerance("rtol", rtol)
        maxit = val.integer_at_least("maxit", maxit, 1)
        fr = self.free
        ref = max(self.load_scale(), 1e-300)
        r = self._residual()
        rn = float(np.linalg.norm(r[fr]))
        ref = max(ref, rn)
        best = (math.inf, None, 0)           # (residual, state, step) of the best iterate
        for it in range(maxit + 1):
            if rn <= rtol * ref:
                # converged on the residual alone: no tangent is needed to decide
                return self._converged(it, rn, ref, "relative residual")
            K = self._tangent()
            require_finite_step(r[fr], K, f"AxisymModel.newton at v = {self.v:.8g} (step {it})")
            x = self.state()
            floor = round_off_floor(abs(K), np.abs(x), fr)
            if rn <= floor:
                return self._converged(it, rn, ref, "floor")
            if rn < best[0]:
                best = (rn, x, it)
            elif it - best[2] >= NEWTON_STALL_STEPS and best[0] <= NEWTON_STAGNATION_RTOL * ref:
                # the local phase oscillates along the near-null mode without improving on
                # its best iterate: that iterate, as for a step without descent
                self.set_state(best[1])
                return self._converged(it, best[0], ref, "stagnation (best iterate)")
            if it == maxit:
                break
            dx = self._solve(K[fr][:, fr], -r[fr])
            step = 1.0
            for _ in range(12):
                y = x.copy()
                y[fr] += step * dx
                self.set_state(y)
                rt = self._residual()
                rtn = float(np.linalg.norm(rt[fr]))
                # full steps in the local phase (the residual non-monotone there at
                # the 1e-7 level, measured for the Ogden evaluation); halving before it
                if np.isfinite(rtn) and (rtn < rn * (1.0 - 1e-4 * step) or rtn <= floor
                                         or rn <= NEWTON_LOCAL_RTOL * ref):
                    break
                step *= 0.5
            else:
                self.set_state(x)
                if rn <= NEWTON_STAGNATION_RTOL * ref:
                    return self._converged(it, rn, ref, "stagnation (no descent)")
                raise ConvergenceError(
                    f"AxisymModel.newton: no descent at v = {self.v:.8g} (residual {rn:.3e}, "
                    f"relative {rn / ref:.3e})")
            r, rn = rt, rtn
            self.stats["newton_steps"] += 1
        raise ConvergenceError(f"AxisymModel.newton: residual {rn:.3e} (relative "
                               f"{rn / ref:.3e}) after {maxit} steps at v = {self.v:.8g}")

    def _solve(self, A: sp.spmatrix, b: np.ndarray) -> np.ndarray:
        t = time.perf_counter()
        x = Factor(A, f"AxisymModel.newton at v = {self.v:.8g}").solve(b)
        self.stats["solve_s"] += time.perf_counter() - t
        return x

    # --------------------------------------------------------------- deflection control
    def _centre_dof(self) -> int:
        """DOF of u_z at the top-surface centre (R, Z) = (0, t0): a mesh vertex, where the
        hierarchical H1 basis has only its vertex function non-zero."""
        t0 = self.plate.thickness
        for k, vert in enumerate(self.mesh.vertices):
            x, y = vert.point
            if abs(x) < 1e-12 * t0 and abs(y - t0) < 1e-12 * t0:
                return self.X.components[0].ndof + k
        raise RuntimeError("no mesh vertex at the top-surface centre")

    def newton_deflection(self, c: float, *, rtol: float = RTOL,
                          maxit: int = NEWTON_MAXIT, stall: int | None = None) -> NewtonResult:
        """Equilibrate at the prescribed centre deflection ``c`` (units of t0, the top-surface
        centre, :meth:`centre_deflection`), the voltage an unknown: Newton on the bordered
        system ``[[K_ff, K_fd dx_d/dv], [e_c^T, 0]]`` (regular at a voltage maximum, where
        K_ff is singular), solved by block elimination with iterative refinement of the
        bordered residual. Once the stopping rule of :meth:`newton` holds it takes one more
        step (:meth:`_polish`), so that the state at a prescribed deflection is independent
        of the start to round-off. Returns the NewtonResult (steps to the stopping rule); raises
        ConvergenceError when it is not reached in ``maxit``, or (``stall``: a number of
        steps, e.g. :data:`~debench.models.buckling.axisym.path.PATH_STALL_STEPS`) when
        ``stall`` steps in a row have not lowered the best residual."""
        c = float(val.finite("c", c))
        rtol = val.tolerance("rtol", rtol)
        maxit = val.integer_at_least("maxit", maxit, 1)
        if stall is not None:
            stall = val.integer_at_least("stall", stall, 1)
        best = (math.inf, 0)                  # (residual, step) of the best iterate
        fr = self.free
        k = self._centre_dof()
        kf = int(np.count_nonzero(fr[:k]))
        t0 = self.plate.thickness
        dirv = np.where(fr, 0.0, self._linear)       # d x / d v: the electrode values
        ref = max(self.load_scale(), 1e-300)
        for it in range(maxit + 1):
            r = self._residual()
            g = self.state()[k] - c * t0
            rn = float(np.linalg.norm(r[fr]))
            ref = max(ref, rn) if it == 0 else ref
            K = self._tangent()
            require_finite_step(r[fr], K, f"AxisymModel.newton_deflection at c = {c:.6g} "
                                      f"(step {it})")
            floor = round_off_floor(abs(K), np.abs(self.state()), fr)
            if (rn <= rtol * ref or rn <= floor) and abs(g) <= 1e-12 * t0:
                # one more step even at the floor estimate, which bounds the residual's
                # round-off from above (the residual itself reaches ~1e-3 of it, measured)
                rn_final = self._polish(K, r, g, kf, dirv, c, rn)
                polished, rn = rn_final < rn, rn_final
                return self._converged(it, rn, ref, "relative residual or floor",
                                       polished=bool(polished))
            if it == maxit:
                break
            if rn < best[0]:
                best = (rn, it)
            elif stall is not None and it - best[1] >= stall:
                raise ConvergenceError(
                    f"AxisymModel.newton_deflection: no lower residual than {best[0]:.3e} "
                    f"(relative {best[0] / ref:.3e}) in {stall} steps at c = {c:.6g}")
            dx, dv = self._bordered_step(K, r, g, kf, dirv, c)
            # damping: a voltage correction above DV_MAX_REL of the voltage is a step
            # outside the linearisation's reach (the deflection responds to the voltage
            # steeply near the critical voltage): take the part of it that stays inside
            damp = min(1.0, DV_MAX_REL * max(abs(self.v), 1e-3) / max(abs(dv), 1e-300))
            self._step_inside_domain(damp * dx, damp * dv, c)
            self.stats["newton_steps"] += 1
        raise ConvergenceError(f"AxisymModel.newton_deflection: residual {rn:.3e} (relative "
                               f"{rn / ref:.3e}) after {maxit} steps at c = {c:.6g}")

    def _polish(self, K, r, g, kf, dirv, c, rn) -> float:
        """One more deflection-controlled Newton step from a converged state (residual norm
        ``rn``): kept when it lowers the residual and holds the deflection, else undone
        (at the round-off floor a step may raise it by round-off). Returns the residual
        norm of the state it leaves.

        Why: along the path the fixed-voltage tangent has a soft wavenumber-0 direction
        (lowest eigenvalue ~1e-3 near the voltage maximum), so a state at a relative
        residual of 1e-11 can differ from the exact discrete one by ~1e-6 relative, and two
        solves from different starts by as much (measured, Ogden R/t0 = 20 film, order 2:
        3e-6 relative in the state, 1.4e-6 in the voltage, 4.5e-5 in the wavenumber-12
        eigenvalue, enough to move its zero by 5e-3 t0). One quadratically convergent step
        from there reaches the round-off floor (~1e-16 relative): the two starts then agree
        to 1e-9 in the voltage and 3e-9 in that eigenvalue."""
        fr, t0 = self.free, self.plate.thickness
        x0, v0 = self.state(), self.v
        try:
            self._step_inside_domain(*self._bordered_step(K, r, g, kf, dirv, c), c)
        except ConvergenceError:
            pass
        else:
            rt = float(np.linalg.norm(self._residual()[fr]))
            if rt < rn and abs(self.state()[self._centre_dof()] - c * t0) <= 1e-12 * t0:
                self.stats["newton_steps"] += 1
                return rt
        self.set_state(x0)
        self.v = v0
        return rn

    def _bordered_step(self, K, r, g, kf, dirv, c) -> tuple[np.ndarray, float]:
        """The deflection-controlled Newton correction (free DOFs, voltage) at the tangent
        ``K``, residual ``r`` and deflection misfit ``g``."""
        fr = self.free
        Kff = K[fr][:, fr]
        b = (K @ dirv)[fr]
        rhs_x, rhs_g = -r[fr], -g
        try:
            return self._bordered_by_blocks(Kff, b, kf, rhs_x, rhs_g, c)
        except ConvergenceError:
            # K_ff singular to working precision: at the voltage maximum itself, where
            # the bordered system is regular -- factorise it whole, with pivoting
            nf = Kff.shape[0]
            e = sp.csr_matrix(([1.0], ([0], [kf])), shape=(1, nf))
            B = sp.bmat([[Kff, sp.csr_matrix(b[:, None])], [e, None]]).tocsc()
            try:
                sol = splu(B).solve(np.concatenate([rhs_x, [rhs_g]]))
            except RuntimeError as exc:
                raise ConvergenceError(f"AxisymModel.newton_deflection at c = {c:.6g}: "
                                       f"bordered system singular ({exc})") from exc
            res = float(np.linalg.norm(B @ sol - np.concatenate([rhs_x, [rhs_g]])))
            if not (np.all(np.isfinite(sol))
                    and res <= DIRECT_RTOL * max(float(np.linalg.norm(rhs_x)), 1e-300)):
                raise
            return sol[:nf], float(sol[nf])

    def _step_inside_domain(self, dx: np.ndarray, dv: float, c: float) -> None:
        """Apply the deflection-controlled Newton correction (``dx`` on the free DOFs, ``dv``
        on the voltage), halved while the trial state leaves the material's domain (a
        non-finite residual, e.g. an inverted element after a long jump in the deflection):
        the undamped step is a linearisation, and a shorter one along it stays admissible.
        Raises ConvergenceError when :data:`DOMAIN_HALVINGS` halvings do not bring it back."""
        fr = self.free
        x0, v0 = self.state(), self.v
        for _ in range(DOMAIN_HALVINGS + 1):
            x = x0.copy()
            x[fr] += dx
            x[~fr] += dv * self._linear[~fr]
            self.set_state(x)
            self.v = v0 + dv
            if np.all(np.isfinite(self._residual()[fr])):
                return
            dx, dv = 0.5 * dx, 0.5 * dv
            self.stats["domain_halvings"] += 1
        self.set_state(x0)
        self.v = v0
        raise ConvergenceError(f"AxisymModel.newton_deflection at c = {c:.6g}: every step "
                               f"down to 2^-{DOMAIN_HALVINGS} of the Newton correction leaves "
                               f"the material's domain (non-finite residual)")

    @staticmethod
    def _bordered_by_blocks(Kff, b, kf, rhs_x, rhs_g, c):
        """Solve ``[[Kff, b], [e_kf^T, 0]] (dx, dv) = (rhs_x, rhs_g)`` by block elimination
        with one factorisation of Kff and iterative refinement of the bordered residual."""
        fac = Factor(Kff, f"AxisymModel.newton_deflection at c = {c:.6g}")
        row = np.zeros(Kff.shape[0])
        row[kf] = 1.0
        return bordered_solve(lambda y: fac.solve(y, check=False), b, row, rhs_x, rhs_g,
                              apply=Kff.__matmul__, refinements=REFINEMENTS, rtol=REFINE_RTOL,
                              what=f"AxisymModel.newton_deflection at c = {c:.6g}")

    # --------------------------------------------------------------- point values
    def _at(self, comp: int, r: float, z: float) -> float:
        return float(self.gf.components[comp](self.mesh(r, z)))

    def centre_deflection(self) -> float:
        """Vertical displacement of the top-surface centre / t0 (as the 3D model's)."""
        t0 = self.plate.thickness
        return self._at(1, 0.0, t0) / t0

    def centre_thickness(self) -> float:
        """Current thickness at the centre / t0."""
        t0 = self.plate.thickness
        return 1.0 + (self._at(1, 0.0, t0) - self._at(1, 0.0, 0.0)) / t0

    def centre_field(self) -> float:
        """Normalised nominal-thickness-free true field v t0 / (current centre thickness):
        the field of a uniform film with the centre's thickness."""
        return self.v / self.centre_thickness()

