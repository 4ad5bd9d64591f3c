"""Clean-room ch5_pullin, written from its ``debench problems ID --markdown`` page (and that
of ch5_critical_voltage, whose film it extends) only: numpy, scipy, scikit-fem and the
sibling clean room ``buckling`` (nothing from debench).

The page: the film of ch5_critical_voltage (a = 10 t0, compressible neo-Hookean (5.15)-(5.17)
ideal dielectric (5.9), clamped rim face, electrodes on both faces, insulated rim), its
reference body lifted by the axisymmetric imperfection w0(R) = 1e-3 t0 (1 - R^2/a^2)^2:
0 <= R <= a, w0(R) <= Z <= t0 + w0(R). Its axisymmetric equilibrium path, the saddle point
of int Omega dV, is followed from Phi = 0 through the voltage maximum (pull-in); v_pullin
is Phi/t0 sqrt(eps/mu_ref) there and w_pullin the vertical displacement of the top-surface
centre (R = 0, Z = t0 + w0(0)) there, over t0.

Units as in ``buckling``: lengths in t0, stresses in mu_ref, permittivity in eps, so Phi
itself is v.

Exact geometry: the lifted body is the image of the flat section (Rh, Zh) in [0, a] x [0, 1]
under the map X = (Rh, Zh + w0(Rh)), whose gradient (in (R, Theta, Z)) is

    G0 = [[1, 0, 0], [0, 1, 0], [w0'(Rh), 0, 1]],   det G0 = 1,  R = Rh.

The fields live on the flat mesh as functions of (Rh, Zh) (the displacement u = x - X and
the potential phi); the deformation gradient from the lifted body is F = Grad x = (G0 +
Grad_h u) G0^-1 = I + Grad_h u G0^-1 and the field E_L = -Grad phi = -G0^-T Grad_h phi, so
with s = w0'(Rh) the seven arguments of Omega (``buckling.enthalpy``) are

    u_r,R = u_r,Rh - s u_r,Zh,  u_z,R = u_z,Rh - s u_z,Zh,  phi_R = phi_Rh - s phi_Zh,

the Z derivatives and the hoop term u_r/R unchanged; and R dR dZ = Rh dRh dZh. No mesh
node is moved: the map is exact, there is no geometric discretisation error. The faces are
Zh = 0 (bottom electrode, phi = 0), Zh = 1 (top, phi = Phi), Rh = a (clamped rim), and w is
u_z at (Rh, Zh) = (0, 1). The linear combinations are carried by the ``Jet`` arithmetic, so
the gradient and Hessian of Omega come out in the flat-mesh derivatives that the forms of
``buckling`` (BLOCKS, RESIDUALS) integrate.

Path: voltage control (Newton at fixed Phi, from the previous state with its potential
scaled) from Phi = 0 up to V_SWITCH (0.2 neo-Hookean, 0.12 Ogden, below the flat film's
n = 0 bifurcation at ~0.2203 / ~0.1469 of ch5_critical_voltage, where the imperfect film
has deflected towards +Z, the side the imperfection selects); then deflection control:
u_z at the top-surface centre is
prescribed and Phi is the unknown (bordered Newton: the column of that dof in the
fixed-voltage tangent replaced by dr/dPhi; the system stays regular at the voltage
maximum, where the fixed-voltage tangent is singular), with a tangent predictor and an
adaptive step in w. Along it dv/dw comes from the same bordered matrix (one more solve at
each converged state); pull-in is its first zero, bracketed by the continuation and then
located by the Illinois variant of regula falsi in w until the bracket is W_TOL = 1e-9
(the page's secant tolerance) wide. That is the zero of the n = 0 condensed eigenvalue of
the page: at a regular point of the path dv/dw = 0 exactly when the fixed-voltage tangent
(and so S_0) is singular; ``Pullin.lowest_at_max`` reports that eigenvalue at the located
state (relative to its value at Phi = 0) as the check. No mid-plane symmetry projection
(the imperfection selects the branch). Newton that does not converge in MAX_NEWTON steps
raises (after halving the deflection step down to MIN_STEP on the path; never in the
location of the maximum).

Measured convergence (CPU seconds of one ``pullin`` call on a loaded 2-core machine; the
mesh of ``buckling.mesh``: n_r radial intervals, a quarter of them over the last thickness
before the rim, n_z layers, ``levels`` refinements at each clamped corner, ``ratio`` < 1 a
geometric grading of the rim intervals towards R = a):

    p  n_r n_z levels ratio  v_pullin      w_pullin    dofs   CPU s
    2  20  2   0      1      0.6794642095  5.5521728     615    2.0
    2  20  2   2      1      0.6794932788  5.5612337     735    2.5
    3  20  2   2      1      0.6795758447  5.5606494    1533    3.6  default test
    3  20  4   2      1      0.6795769659  5.5608326    2631    7.6
    2  40  4   6      1      0.6795684942  5.5601881    2547   10.3
    3  40  4   6      1      0.6795774692  5.5609514    5475   18.4
    4  20  4   6      1      0.6795775375  5.5610130    5427   18.6
    4  40  4   2      1      0.6795775149  5.5609952    8643   27.3
    4  40  4   6      1      0.6795775298  5.5610092    9507   37.5
    4  40  6   6      1      0.6795775443  5.5610151   13371   50.9
    2  40  8   6      1      0.6795742135  5.5608863    4491   19.2
    3  40  8   6      1      0.6795775090  5.5610046    9831   37.8
    4  40  8   6      1      0.6795775475  5.5610160   17235   85.1  slow test, default
    2  80  8   6      1      0.6795770559  5.5608135    8571   37.6
    3  80  8   6      1      0.6795775520  5.5610059   18831   73.8
    4  80  8   6      1      0.6795775470  5.5610157   33075  202.1  finest
    4  40  4   6      0.7    0.6795774919  5.5609412    9507   33.8  graded
    4  40  8   6      0.7    0.6795775334  5.5610049   17235   83.3  graded

The finest's error, as Roache's estimate with three orders (safety 1.25 times the larger
of the p-step P3 -> P4 at 80 x 8 and the mesh step 40 x 8 -> 80 x 8 at P4): v 1.25 x
5.0e-9 = 6e-9, w 1.25 x 9.8e-6 = 1.2e-5 (2e-6 relative). The page's reference (0.6795775428
+- 2.4e-6, 5.5609852 +- 8.5e-4) lies 4e-9 and 3.0e-5 from it. The order matters most, the
layers next (P3 20 x 2 -> 20 x 4: 1.1e-6 in v); the corner refinements and the radial
resolution little; the geometric grading towards the rim does not help (it makes the rim
elements tall: dZ/dR up to ~20 at 0.7 with 4 layers) and moves w by -7.5e-5 at 4 layers.

Not in the table (an unexplained discretisation sensitivity, reported): meshes whose rim
elements are taller than 2.5 x their width with n_r >= 60 (dZ/dR = n_r/(4 n_z) in the rim
zone) deviate more than the table's differences: P4 60 x 4: v 0.6795776280, w 5.5610235;
P4 80 x 6: 0.6795781831, 5.5611443; P4 80 x 4 with 0, 2, 6 corner refinements:
0.6795786988 / 0.6795788208 / 0.6795788275, w up to 5.5612588 (+1.3e-6 in v, +2.4e-4 in w
from the finest, both inside the reference's stated accuracy); P4 40 x 2: 0.6795774550,
5.5609188. In the P4 80 x 4 state the top-surface u_z within R = 9.45..9.75 (where the top
face dips to u_z ~ -0.014 below its reference near the clamp) has a mesh-scale
non-smooth part of 1.7e-3 t0 (2.5e-4 at 40 x 4, 2e-5 at 80 x 8; the mid-plane is smooth to
1e-6); quadrature order (+4) changes nothing, and the spectrum of S_0 there is positive
(no unstable mode). The S_0 eigenvalue above the zero one differs by 2 % from the
40 x 4 / 40 x 8 values (which agree to 5e-5). These meshes are also where Newton needs
the step halving (P4 160 x 4 fails at w = 5.16 with 0.1 steps).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from skfem import Basis

from . import buckling

ASPECT = buckling.ASPECT
CASES = ("nh_r10", "ogden_r10")
#: the material of each case in ``buckling.enthalpy``'s names (the same films at a = 10 t0)
MATERIAL = {"nh_r10": "nh_t1", "ogden_r10": "ogden_t1"}
#: imperfection amplitude / t0
IMPERFECTION = 1e-3
#: voltage control up to here (below the flat film's v_cr ~ 0.2203), deflection control on
V_SWITCH = {"nh_r10": 0.2, "ogden_r10": 0.12}
"""Per case: below the flat film's n = 0 critical voltage of ch5_critical_voltage (0.2203
neo-Hookean, 0.1469 Ogden)."""
V_STEPS = 4
#: Newton: increment below NEWTON_RTOL of the solution's size (quadratic convergence, so
#: the state is then good to round-off); at most MAX_NEWTON iterations
NEWTON_RTOL = 1e-10
MAX_NEWTON = 20
#: deflection steps: first, largest, smallest (below it the path raises) and the growth
#: when Newton took at most FAST_NEWTON iterations
FIRST_STEP = 0.1
MAX_STEP = 0.6
MIN_STEP = 1e-3
GROWTH = 1.5
FAST_NEWTON = 4
#: deflection past which no voltage maximum is searched (the page's lies near 5.56)
W_MAX = 12.0
#: the maximum is located to this width in w (t0), as the page's reference
W_TOL = 1e-9
MAX_ROOT = 60
#: certificate at the maximum, eigenvalues of S_0 relative to lambda_1 at Phi = 0: the one
#: nearest zero within this of zero (measured: <= 1e-8), no other below it (the next is
#: ~6 lambda_1(0))
CERTIFY_RTOL = 1e-6


def w0(R):
    """The imperfection w0(R) = 1e-3 (1 - R^2/a^2)^2 (in t0)."""
    return IMPERFECTION * (1 - (R / ASPECT) ** 2) ** 2


def w0_slope(R):
    """w0'(R) = -4e-3 R/a^2 (1 - R^2/a^2)."""
    return -4 * IMPERFECTION * R / ASPECT**2 * (1 - (R / ASPECT) ** 2)


class NewtonError(RuntimeError):
    """Newton did not converge (the state, the target and the iterations say where)."""


class State:
    """One converged equilibrium: the fields x (u_r, u_z, phi on the flat-mesh dofs), the
    voltage v, the deflection w, dv/dw (None under voltage control), its tangent dx/dw,
    the Newton iterations and the final residual's max norm."""

    def __init__(self, x, v, w, dvdw, dxdw, iterations, residual):
        self.x, self.v, self.w, self.dvdw, self.dxdw = x, v, w, dvdw, dxdw
        self.iterations, self.residual = iterations, residual


class Pullin:
    """The voltage maximum of one discretisation: v_pullin, w_pullin, the final bracket in
    w and dv/dw at its ends, the lowest eigenvalue of S_0 at the maximum relative to that at
    Phi = 0 (~0: the page's criterion) and the smallest algebraic ones (LOBPCG, the
    certificate that none is negative), the continuation's states (w, v, dv/dw; dv/dw nan
    under voltage control), the size, the Newton iterations, the largest final residual
    (max norm, in mu_ref t0^2 per radian), the film and the state at the maximum (the
    bracket end of the higher voltage)."""

    def __init__(self, **kw):
        self.__dict__.update(kw)

    def __repr__(self):
        return (f"Pullin(case={self.case!r}, v_pullin={self.v_pullin!r}, "
                f"w_pullin={self.w_pullin!r}, ndofs={self.ndofs})")


class ImperfectFilm(buckling.Film):
    """The discretised imperfect film: the flat mesh of ``buckling.mesh`` carrying the
    fields of the lifted body (module docstring). Inherits the condensed-tangent operators
    and the eigenvalue search of ``buckling.Film``; no symmetry projection."""

    def __init__(self, case: str, order: int = 2, n_r: int = 40, n_z: int = 4,
                 levels: int = 6, ratio: float = 1.0):
        if case not in CASES:
            raise ValueError(f"case must be one of {CASES}, got {case!r}")
        if order not in buckling.ELEMENTS:
            raise ValueError(f"order must be one of {sorted(buckling.ELEMENTS)}, got {order}")
        self.case, self.material = case, MATERIAL[case]
        self.mesh = buckling.mesh(n_r, n_z, levels, ratio)
        self.basis = Basis(self.mesh, buckling.ELEMENTS[order](), intorder=2 * order + 2)
        n = self.n = self.basis.N
        x = self.basis.doflocs

        tol = buckling.face_tolerance(self.mesh)

        def on(c, val):  # on a face: within buckling.FACE_TOL_FRACTION of the mesh's height
            return np.abs(x[c] - val) <= tol

        rim = np.flatnonzero(on(0, ASPECT))
        axis = np.flatnonzero(on(0, 0.0))
        self.bottom = np.flatnonzero(on(1, 0.0))
        self.top = np.flatnonzero(on(1, 1.0))
        centre = np.flatnonzero(on(0, 0.0) & on(1, 1.0))
        if centre.size != 1:
            raise RuntimeError(f"expected one dof at the top-surface centre, found {centre}")
        self.centre = n + int(centre[0])  # u_z there
        self.D = np.unique(np.concatenate((rim, axis, n + rim, 2 * n + self.bottom,
                                           2 * n + self.top)))
        self.free = np.setdiff1d(np.arange(3 * n), self.D)
        self.free_u = self.free[self.free < 2 * n]
        self.nu = self.free_u.size
        self.i_centre = int(np.searchsorted(self.free, self.centre))
        m = buckling._mass.assemble(self.basis)
        self.M = sp.block_diag((m, m)).tocsr()[self.free_u][:, self.free_u]
        self.newton_iterations = 0
        self.assemblies = 0
        R = np.asarray(self.basis.global_coordinates())[0]
        self.slope = w0_slope(R)
        self._op = self._local_operator()

    def _local_operator(self):
        """B[e, q, k, I]: the seven arguments of Omega (the lifted body's g, module
        docstring) at quadrature point q of element e as linear functions of the element's
        dofs I = (field, local function), fields u_r, u_z, phi; and the global dof of each
        (e, I). The hat-derivative rows first, then d/dR = d/dRh - s d/dZh."""
        b = self.basis
        nb, ne, nq = len(b.basis), b.nelems, b.dx.shape[1]
        R = np.asarray(b.global_coordinates())[0]
        B = np.zeros((ne, nq, 7, 3 * nb))
        for k, (field, kind) in enumerate(buckling.G_MAP):
            for i in range(nb):
                phi = b.basis[i][0]
                B[:, :, k, field * nb + i] = (phi.grad[0] if kind == 0 else phi.grad[1]
                                              if kind == 1 else np.asarray(phi) / R)
        for k in (0, 3, 5):
            B[:, :, k] -= self.slope[:, :, None] * B[:, :, k + 1]
        dofs = np.concatenate([field * self.n + b.element_dofs.T for field in range(3)],
                              axis=1)
        return B, dofs, b.dx * R

    def assemble(self, x):
        """Tangent K (3n x 3n, symmetric) and residual r of the state x, in the flat-mesh
        dofs: Omega of the lifted body's F and E_L (module docstring), its Jet gradient
        and Hessian in the seven g integrated element by element with the local operator
        B (K_e = sum_q B^T H B R dx, r_e = sum_q B^T dOmega R dx)."""
        B, dofs, wR = self._op
        g = np.einsum("eqkI,eI->keq", B, x[dofs])
        om = buckling.enthalpy(buckling.Jet.seed(list(g)), self.material)
        H = np.moveaxis(om.h, (0, 1), (2, 3))  # (e, q, 7, 7)
        ne, nq, _, m = B.shape
        HB = (H @ B).reshape(ne, nq * 7, m)
        BW = (B * wR[:, :, None, None]).reshape(ne, nq * 7, m)
        Ke = np.swapaxes(BW, 1, 2) @ HB
        re = np.einsum("eqkI,keq->eI", B * wR[:, :, None, None], om.g)
        rows = np.repeat(dofs, m, axis=1).ravel()
        cols = np.tile(dofs, (1, m)).ravel()
        K = sp.coo_matrix((Ke.ravel(), (rows, cols)), shape=(3 * self.n,) * 2).tocsr()
        r = np.bincount(dofs.ravel(), weights=re.ravel(), minlength=3 * self.n)
        self.assemblies += 1
        return K, r

    def assemble_forms(self, x):
        """The same K and r by scikit-fem's forms of ``buckling`` (BLOCKS, RESIDUALS, in
        the flat-mesh derivatives), the lifted body's g formed by Jet arithmetic from the
        hat derivatives: the independent check of ``assemble`` (slower: the forms loop
        over pairs of local functions)."""
        n, s = self.n, self.slope
        fields = [self.basis.interpolate(x[i * n:(i + 1) * n]) for i in range(3)]
        R = np.asarray(self.basis.global_coordinates())[0]
        gh = buckling.Jet.seed([buckling._component(fields[f], kind, R)
                                for f, kind in buckling.G_MAP])
        g = list(gh)
        for k in (0, 3, 5):  # d/dR = d/dRh - s d/dZh, for u_r, u_z and phi
            g[k] = gh[k] - gh[k + 1] * s
        om = buckling.enthalpy(g, self.material)
        blocks = [[None] * 3 for _ in range(3)]
        for (a, b), form in buckling.BLOCKS.items():
            blocks[a][b] = form.assemble(self.basis, H=om.h)
            if a != b:
                blocks[b][a] = blocks[a][b].T
        K = sp.bmat(blocks, format="csr")
        r = np.concatenate([f.assemble(self.basis, dO=om.g) for f in buckling.RESIDUALS])
        return K, r

    def _set_voltage(self, x, v):
        x[self.D[self.D < 2 * self.n]] = 0.0
        x[2 * self.n + self.bottom] = 0.0
        x[2 * self.n + self.top] = v

    def _converged(self, dx, x):
        return np.max(np.abs(dx)) <= NEWTON_RTOL * max(1.0, np.max(np.abs(x)))

    def at_voltage(self, v: float, x0) -> State:
        """Newton at the fixed voltage v from x0 (its Dirichlet values reset); raises
        NewtonError if not converged in MAX_NEWTON iterations."""
        x = x0.copy()
        self._set_voltage(x, v)
        for it in range(1, MAX_NEWTON + 1):
            K, r = self.assemble(x)
            Kf = K[self.free][:, self.free].tocsc()
            dx = spla.spsolve(Kf, -r[self.free])
            x[self.free] += dx
            self.newton_iterations += 1
            if self._converged(dx, x):
                _, r = self.assemble(x)
                return State(x, v, float(x[self.centre]), None, None, it,
                             float(np.max(np.abs(r[self.free]))))
        raise NewtonError(f"Newton at fixed v = {v} did not converge in {MAX_NEWTON} steps")

    def _bordered(self, K):
        """The bordered matrix: the free block of K with the centre's column replaced by
        dr/dv (the columns of the top electrode summed), factorised; and that centre
        column (for the tangent)."""
        Kf = K[self.free][:, self.free].tocsc()
        b = np.asarray(K[self.free][:, 2 * self.n + self.top].sum(axis=1)).ravel()
        ic = self.i_centre
        col = Kf[:, ic].toarray().ravel()
        keep = np.ones(self.free.size)
        keep[ic] = 0.0
        nz = np.flatnonzero(b)
        J = Kf @ sp.diags(keep) + sp.csc_matrix((b[nz], (nz, np.full(nz.size, ic))),
                                                 shape=Kf.shape)
        return spla.splu(J.tocsc()), col

    def at_deflection(self, w: float, x0, v0: float) -> State:
        """Bordered Newton at the prescribed centre deflection w, the voltage unknown, from
        (x0, v0); returns the state with dv/dw and dx/dw; raises NewtonError if not
        converged in MAX_NEWTON iterations (or on a singular bordered matrix)."""
        x, v, ic = x0.copy(), float(v0), self.i_centre
        self._set_voltage(x, v)
        x[self.centre] = w
        for it in range(1, MAX_NEWTON + 1):
            K, r = self.assemble(x)
            try:
                lu, _ = self._bordered(K)
            except RuntimeError as e:  # splu: exactly singular
                raise NewtonError(f"bordered matrix singular at w = {w}: {e}") from e
            z = lu.solve(-r[self.free])
            if not np.all(np.isfinite(z)):
                raise NewtonError(f"bordered Newton at w = {w}: non-finite increment")
            dv, z[ic] = z[ic], 0.0
            x[self.free] += z
            v += dv
            self._set_voltage(x, v)
            self.newton_iterations += 1
            if self._converged(np.append(z, dv), x):
                K, r = self.assemble(x)
                lu, col = self._bordered(K)
                t = lu.solve(-col)
                dvdw, t[ic] = float(t[ic]), 1.0
                dxdw = np.zeros_like(x)
                dxdw[self.free] = t
                dxdw[2 * self.n + self.top] = dvdw
                return State(x, v, w, dvdw, dxdw, it, float(np.max(np.abs(r[self.free]))))
        raise NewtonError(f"bordered Newton at w = {w} (from v = {v0}) did not converge "
                          f"in {MAX_NEWTON} steps")

    def predict(self, s: State, w: float):
        """The tangent predictor at w from the state s: (x, v)."""
        return s.x + (w - s.w) * s.dxdw, s.v + (w - s.w) * s.dvdw


def _check_discretisation(order, n_r, n_z, levels, ratio):
    for name, val in (("n_r", n_r), ("n_z", n_z), ("levels", levels)):
        if not isinstance(val, int | np.integer):
            raise TypeError(f"{name} must be an integer, got {val!r}")
    if not (isinstance(ratio, float | int) and np.isfinite(ratio)):
        raise TypeError(f"ratio must be a finite number, got {ratio!r}")


def pullin(case: str = "nh_r10", order: int = 4, n_r: int = 40, n_z: int = 8,
           levels: int = 6, ratio: float = 1.0) -> Pullin:
    """v_pullin and w_pullin of ``case`` on one discretisation (Lagrange P``order``, the mesh
    of ``buckling.mesh(n_r, n_z, levels, ratio)``; the default P4 40 x 8 is within 1e-9
    in v and 3e-7 in w (relative) of the finest, itself good to ~1e-8 and ~2e-6: the table
    of the module docstring): the path of the module docstring, its
    first zero of dv/dw located to W_TOL in w, certified at the maximum by the smallest
    algebraic eigenvalue of S_0 (LOBPCG: no negative one, the zero one is the located
    maximum). Raises ValueError/TypeError on bad input, NewtonError when a state cannot be
    computed, RuntimeError when no maximum is found up to W_MAX or the certificate fails."""
    _check_discretisation(order, n_r, n_z, levels, ratio)
    film = ImperfectFilm(case, order, n_r, n_z, levels, ratio)
    # voltage control from 0
    s = film.at_voltage(0.0, film.initial(0.0))
    if abs(s.w) > 1e-12:
        raise RuntimeError(f"the unloaded film deflects: w = {s.w}")
    K0, _ = film.assemble(s.x)
    lam0 = film.lowest(K0)
    path = [(s.w, s.v, np.nan)]
    residual = s.residual
    for v in np.linspace(0.0, V_SWITCH[case], V_STEPS + 1)[1:]:
        # the previous state, its potential scaled (from 0: the linear potential v Zh)
        guess = s.x.copy()
        guess[2 * film.n:] = (guess[2 * film.n:] * (v / s.v) if s.v > 0
                              else film.initial(float(v))[2 * film.n:])
        s = film.at_voltage(float(v), guess)
        path.append((s.w, s.v, np.nan))
        residual = max(residual, s.residual)
    if not s.w > 0:
        raise RuntimeError(f"the film deflects towards -Z (w = {s.w} at v = {s.v}): not the "
                           "branch the imperfection selects")
    # deflection control from there, tangent predictor, adaptive step
    s = film.at_deflection(s.w, s.x, s.v)
    step, first = FIRST_STEP, True
    while True:
        if s.w + step > W_MAX:
            raise RuntimeError(f"no voltage maximum up to w = {W_MAX}")
        w = s.w + step
        x, v = film.predict(s, w)
        if first:
            # the first step leaves the steep start of the path (dv/dw ~ 4 near the flat
            # film's bifurcation, ~0.02 a step later): the voltage and the potential are
            # held, the displacement follows the tangent
            v = s.v
            x[2 * film.n:] = s.x[2 * film.n:]
        try:
            new = film.at_deflection(w, x, v)
        except NewtonError:
            step *= 0.5
            if step < MIN_STEP:
                raise
            continue
        path.append((new.w, new.v, new.dvdw))
        residual, first = max(residual, new.residual), False
        if new.dvdw <= 0:
            break
        s = new
        if new.iterations <= FAST_NEWTON:
            step = min(GROWTH * step, MAX_STEP)
    # Illinois on dv/dw(w) in [s.w, new.w]
    lo, hi, last = s, new, 0
    flo, fhi = lo.dvdw, hi.dvdw
    for _ in range(MAX_ROOT):
        if hi.w - lo.w <= W_TOL:
            break
        width = hi.w - lo.w
        w = lo.w - flo * width / (fhi - flo)
        w = min(max(w, lo.w + 1e-3 * width), hi.w - 1e-3 * width)
        near = lo if w - lo.w < hi.w - w else hi
        mid = film.at_deflection(w, *film.predict(near, w))
        residual = max(residual, mid.residual)
        if mid.dvdw > 0:
            lo, flo = mid, mid.dvdw
            fhi = 0.5 * fhi if last == 1 else fhi
            last = 1
        else:
            hi, fhi = mid, mid.dvdw
            flo = 0.5 * flo if last == -1 else flo
            last = -1
    else:
        raise RuntimeError(f"maximum not bracketed to {W_TOL} in {MAX_ROOT} steps")
    # the zero inside the final bracket by the secant; v from the bracket end of the
    # higher voltage (v is flat there: it differs from the maximum by ~ v'' W_TOL^2)
    w_max = lo.w - lo.dvdw * (hi.w - lo.w) / (hi.dvdw - lo.dvdw)
    top = max(lo, hi, key=lambda st: st.v)
    K_top, _ = film.assemble(top.x)
    lowest = film.lowest(K_top) / lam0
    smallest = film.smallest_algebraic(K_top, shift=lam0) / lam0
    if not (abs(lowest) < CERTIFY_RTOL and smallest[0] > -CERTIFY_RTOL
            and smallest[1] > CERTIFY_RTOL):
        raise RuntimeError(f"maximum not certified: eigenvalues of S_0 / lambda_1(0) "
                           f"nearest zero {lowest}, smallest {smallest}")
    return Pullin(case=case, v_pullin=float(top.v), w_pullin=float(w_max),
                  bracket=(lo.w, hi.w), dvdw_at_bracket=(lo.dvdw, hi.dvdw),
                  lowest_at_max=lowest, smallest_at_max=smallest, path=np.array(path),
                  ndofs=int(3 * film.n), newton_iterations=film.newton_iterations,
                  residual=residual, film=film, state=top)
