"""Method 3: plane-strain strip of the plate over one wavelength, 2D finite elements (NGSolve).

Independent of the determinant (:mod:`debench.models.plate.ansatz`) and of the 1D
through-thickness discretisation (:mod:`debench.models.plate.fem`): no exponential
ansatz, no boundary rows (4.69)-(4.80), no coefficients (4.54)-(4.60) and no
``coefficients.energy_matrix``. The incremental moduli come from the constitutive
library: :class:`~debench.models.materials.TransverselyIsotropicNeoHookean` (energy
(4.22)) gives AA, AAA, A (2.65)-(2.67) at the homogeneous state, and
:func:`~debench.models.materials.push_forward` (2.72)-(2.73) pushes them forward.

Base state (Sec. 4.3.1). F = diag(lam, lam^-2, lam) (equibiaxial in-plane stretch, plane
strain of the increment in (x1, x2)), D_L = (0, lam^2 Dhat, 0) (Eulerian D = Dhat e2), the
Lagrange multiplier p from the traction-free faces (total Cauchy stress tau22 = 0,
:func:`~debench.models.materials.pressure_from_traction_free_face`). Units mu = eps = 1.

Incremental problem (Sec. 4.3.2, re-derived). With L = grad u (current configuration)
and Ddot the pushed-forward increment of D_L, the incremental energy per unit current
volume is

    2 Q = L_ip AA0_ipjq L_jq + 2 L_ip AAA0_ipq Ddot_q + Ddot_p A0_pq Ddot_q + p L_ij L_ji,

the last term from the linearised -p F^-1 of the incompressible nominal stress (2.29).
Incompressibility tr L = 0 is imposed by a mixed u-q form (q the incremental pressure,
Taylor-Hood: u of order ``order``, q of order ``order - 1``, continuous), and
div Ddot = 0 exactly by a stream function, ``Ddot = (phi_,2, -phi_,1)``. Traction-free faces
and equipotential electrodes (E_L0,1 = 0; charge control fixes only the total charge,
which periodic phi keeps) are the natural conditions of the energy. The rigid
translations and the constant phi are removed by zero-mean constraints (Lagrange
multipliers); they are orthogonal to every mode with k != 0.

Domain: the strip [0, 2 pi/k] x [-h/2, h/2] in the current configuration, lengths
scaled by h = H lam^-2, so that the width is 2 pi/(k h), k h = kH lam^-2; u, q and phi are
periodic in x1 (NGSolve ``Periodic``). The mesh is a structured quadrilateral mesh of
the unit square mapped affinely in x1 (the width enters through the derivative scale
1/w, so the mesh is fixed while lam varies) and graded towards the faces in x2.

Stability: the plate is stable iff the incremental energy is positive on the
constraint, i.e. iff every finite eigenvalue omega of the generalised eigenproblem
K v = omega M v is positive (K: the saddle-point Hessian, M: the L2 Gram matrix of
(u, phi), zero on q and the multipliers). The eigenvalues nearest zero are computed by
shift-invert Lanczos (ARPACK). A periodic strip over one wavelength also carries the
harmonics n k (n = 0, 2, 3, ...); each eigenvector is therefore classified by its
Fourier index n in x1 and by its parity in x2 ("E": u2 even, flexural; "O": u2 odd,
extensional). lam_cr at given kH is the zero, in lam, of the lowest eigenvalue of class
(n = 1, parity), refined by brentq.

Voltage control (beyond the thesis, as :mod:`debench.models.plate.voltage`): with
electrodes on both faces the incremental conditions for k != 0 are those of charge
control; only the base state differs. Here Dhat(lam) at fixed Vhat = V sqrt(eps/mu)/H is
computed from the library's electric field E = F^-T dW/dD_L (2.32): V = E2 h with
h = H lam^-2, and E2 is linear in Dhat.

Accuracy contract: eigenvalue and critical-stretch errors converge like h_e^(2 order)
for smooth modes (energy-norm error h_e^order); the measured orders are asserted in
``verification/test_ch4_fe.py``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sps
from debench.models.errors import ConvergenceError, require
from debench.models.materials import (
    TransverselyIsotropicNeoHookean,
    electric_field,
    pressure_from_traction_free_face,
    push_forward,
)
from debench.models.numerics.roots import zero_near
from scipy.sparse.linalg import LinearOperator, eigsh, splu
from scipy.sparse.linalg import norm as spnorm

PARITIES = ("E", "O")
#: number of x1-derivatives in z = (L11, L12, L21, L22, Dd1, Dd2)
_N_D1 = (1, 0, 1, 0, 0, 1)
CONTROLS = ("charge", "voltage")
#: shift of the shift-invert Lanczos iteration (eigenvalues nearest it are computed);
#: slightly below zero so that K - sigma M is regular at the critical stretch itself
SIGMA = -1e-3
#: eigenpairs computed per evaluation: enough to hold the (degenerate cos/sin) pairs of
#: the harmonics n = 0, 1, 2, 3 of both parities near zero
N_EIG = 10
#: upper bound when the n = 1 class is not among the first N_EIG pairs (doubling)
N_EIG_MAX = 80
#: stopping tolerance of ARPACK (relative, on the Ritz values)
EIG_TOL = 1e-13
#: a mode belongs to class n when that harmonic carries at least this share of its L2
#: norm (discrete modes of a structured periodic mesh are pure harmonics up to rounding)
PURITY = 0.9
#: brentq tolerance in lam (well below the coarse-mesh error ~1e-5, above round-off)
XTOL = 1e-11


@dataclass(frozen=True)
class StripMesh:
    """Discretisation of the strip.

    Parameters
    ----------
    nx, ny
        Quadrilaterals along the wavelength and through the thickness.
    order
        Polynomial order of u and phi (q has ``order - 1``), >= 2.
    grading
        In [0, 0.9]: x2 = (1 - g) s + g sin(pi s)/2 on s in [-1/2, 1/2]; g > 0 refines
        towards the faces (boundary layers of width ~1/(k h) in thick plates).
    """

    nx: int = 8
    ny: int = 4
    order: int = 3
    grading: float = 0.0

    def __post_init__(self):
        require(isinstance(self.nx, int) and self.nx >= 3, f"nx must be an int >= 3, got "
                f"{self.nx!r}")
        require(isinstance(self.ny, int) and self.ny >= 1, f"ny must be an int >= 1, got "
                f"{self.ny!r}")
        require(isinstance(self.order, int) and self.order >= 2,
                f"order must be an int >= 2, got {self.order!r}")
        require(np.isfinite(self.grading) and 0 <= self.grading <= 0.9,
                f"grading must be in [0, 0.9], got {self.grading}")


def default_mesh(kH: float, order: int = 3, level: int = 0) -> StripMesh:
    """A mesh suited to kH (level 0 = coarse; each level refines nx and ny by sqrt 2).

    Thick plates (kH >~ 3) get faces-graded meshes and more layers (the mode decays like
    exp(-k s x2) away from the faces); thin plates need only a few layers.
    """
    require(np.isfinite(kH) and kH > 0, f"kH must be finite and > 0, got {kH}")
    require(isinstance(level, int) and level >= 0, f"level must be an int >= 0, got {level}")
    ny = 2 if kH < 1 else (4 if kH < 5 else (6 if kH < 15 else 10))
    g = min(0.8, 0.8 * kH / (kH + 4.0))
    r = 2 ** (level / 2)
    return StripMesh(nx=round(8 * r), ny=round(ny * r), order=order, grading=g)


@dataclass(frozen=True)
class BaseState:
    """Homogeneous pre-stretched state at lam (units mu = eps = 1, lengths / H)."""

    lam: float
    Dhat: float
    F: np.ndarray
    D_L: np.ndarray
    p: float
    S: np.ndarray  # 6x6 energy matrix in z = (L11, L12, L21, L22, Dd1, Dd2)


def material_for(xi: float, beta: float = 0.5, alpha: float = 0.0):
    """The library energy (4.22) in units mu = eps = 1, fibre A = e2 (thickness)."""
    return TransverselyIsotropicNeoHookean(mu=1.0, xi=xi, alpha=alpha, beta=beta, eps=1.0,
                                           A=(0.0, 1.0, 0.0))


def base_state(lam: float, Dhat: float, material) -> BaseState:
    """Base state and plane-strain incremental energy matrix from the library moduli."""
    require(np.isfinite(lam) and lam > 0, f"lam must be finite and > 0, got {lam}")
    require(np.isfinite(Dhat) and Dhat >= 0, f"Dhat must be finite and >= 0, got {Dhat}")
    F = np.diag([lam, lam**-2, lam])
    D_L = np.array([0.0, lam**2 * Dhat, 0.0])
    r = material.response(F, D_L, second=True)
    AA0, AAA0, A0 = push_forward(F, r.AA, r.AAA, r.A)
    p = pressure_from_traction_free_face(material, F, D_L, (0.0, 1.0, 0.0))
    pairs = ((0, 0), (0, 1), (1, 0), (1, 1))
    S = np.zeros((6, 6))
    for a, (i, j) in enumerate(pairs):
        for b, (k, m) in enumerate(pairs):
            S[a, b] = AA0[i, j, k, m] + (p if (i == m and j == k) else 0.0)
        for q in range(2):
            S[a, 4 + q] = S[4 + q, a] = AAA0[i, j, q]
    S[4:, 4:] = A0[:2, :2]
    return BaseState(float(lam), float(Dhat), F, D_L, float(p), S)


def dhat_at_voltage(lam: float, Vhat: float, material) -> float:
    """Dhat at fixed Vhat = V sqrt(eps/mu)/H: V = E2 h, E = F^-T dW/dD_L (2.32), h = lam^-2.

    E2 is linear in D_L for (4.20), so Dhat = Vhat / (E2(Dhat = 1) lam^-2).
    """
    require(np.isfinite(Vhat) and Vhat >= 0, f"Vhat must be finite and >= 0, got {Vhat}")
    require(np.isfinite(lam) and lam > 0, f"lam must be finite and > 0, got {lam}")
    F = np.diag([lam, lam**-2, lam])
    e2 = electric_field(material, F, np.array([0.0, lam**2, 0.0]))[1]
    return float(Vhat / (e2 * lam**-2))


class _Strip:
    """NGSolve spaces, forms and evaluation grid of one mesh (built once per root)."""

    def __init__(self, mesh: StripMesh):
        import ngsolve as ng
        from ngsolve.meshes import MakeStructured2DMesh

        g = mesh.grading

        def mapping(x, y):
            s = y - 0.5
            return (x, (1 - g) * s + g * 0.5 * math.sin(math.pi * s))

        self.ng = ng
        self.mesh = MakeStructured2DMesh(quads=True, nx=mesh.nx, ny=mesh.ny,
                                         periodic_x=True, mapping=mapping)
        V = ng.Periodic(ng.H1(self.mesh, order=mesh.order))
        Q = ng.Periodic(ng.H1(self.mesh, order=mesh.order - 1))
        N = ng.NumberSpace(self.mesh)
        self.fes = ng.FESpace([V, V, Q, V, N, N, N])
        self.ndof = int(sum(self.fes.FreeDofs()))
        (u1, u2, q, ph, l1, l2, l3), (v1, v2, r, ps, m1, m2, m3) = self.fes.TnT()

        def z(a1, a2, f):
            """(L11, L12, L21, L22, Dd1, Dd2) in unit-width coordinates (x1 = w xi1)."""
            d1 = [ng.grad(a)[0] for a in (a1, a2, f)]
            d2 = [ng.grad(a)[1] for a in (a1, a2, f)]
            return [d1[0], d2[0], d1[1], d2[1], d2[2], -d1[2]]

        self._zt, self._zs = z(u1, u2, ph), z(v1, v2, ps)
        # the integral over the strip of width w scales each term by w^(1 - n_d1)
        # (n_d1 = number of x1-derivatives, each 1/w); assembled once per mesh
        self._blocks: dict[tuple[int, int], object] = {}
        c0 = -q * self._zs[0] - r * self._zt[0]
        c1 = (-q * self._zs[3] - r * self._zt[3] + l1 * v1 + m1 * u1 + l2 * v2 + m2 * u2
              + l3 * ps + m3 * ph)
        self.free = np.array(list(self.fes.FreeDofs()), dtype=bool)
        self._C0, self._C1 = self._assemble(c0), self._assemble(c1)
        self._M1 = self._assemble(u1 * v1 + u2 * v2 + ph * ps)
        self.gf = ng.GridFunction(self.fes)
        # evaluation grid: x1 uniform (FFT), x2 symmetric about the mid-plane (parity)
        nxe = 4 * mesh.nx
        xs = np.arange(nxe) / nxe
        ys = np.linspace(-0.45, 0.45, 10)
        X, Y = np.meshgrid(xs, ys, indexing="ij")
        self._pts = self.mesh(X.ravel(), Y.ravel())
        self._shape = X.shape

    def _csr(self, mat):
        rows, cols, vals = mat.COO()
        n = self.fes.ndof
        A = sps.csr_matrix((np.asarray(vals), (np.asarray(rows), np.asarray(cols))),
                           shape=(n, n))
        return A[self.free][:, self.free]

    def _assemble(self, integrand):
        ng = self.ng
        bf = ng.BilinearForm(self.fes)
        bf += integrand * ng.dx
        bf.Assemble()
        return self._csr(bf.mat)

    def _block(self, a: int, b: int):
        if (a, b) not in self._blocks:
            self._blocks[(a, b)] = self._assemble(self._zt[b] * self._zs[a])
        return self._blocks[(a, b)]

    def matrices(self, state: BaseState, kh: float):
        """(K, M) at the state for k h = ``kh`` (strip width w = 2 pi/kh)."""
        w = 2 * math.pi / kh
        K = self._C0 + w * self._C1
        for a in range(6):
            for b in range(6):
                if state.S[a, b] != 0.0:
                    K = K + (state.S[a, b] * w ** (1 - _N_D1[a] - _N_D1[b])) * self._block(a, b)
        return K.tocsc(), (w * self._M1).tocsc()

    def classify(self, vec):
        """(Fourier index n, parity, purity) of a free-dof eigenvector."""
        full = np.zeros(self.fes.ndof)
        full[self.free] = vec
        self.gf.vec.FV().NumPy()[:] = full
        comps = self.gf.components
        u1 = np.asarray(comps[0](self._pts)).reshape(self._shape)
        u2 = np.asarray(comps[1](self._pts)).reshape(self._shape)
        ph = np.asarray(comps[3](self._pts)).reshape(self._shape)
        power = sum(np.abs(np.fft.rfft(f, axis=0)) ** 2 for f in (u1, u2, ph)).sum(axis=1)
        power[1:] *= 2
        n = int(np.argmax(power))
        purity = float(power[n] / power.sum())
        # E: (u1, u2, phi) = (odd, even, odd) in x2; O: (even, odd, even)
        flip = np.concatenate([u1[:, ::-1], -u2[:, ::-1], ph[:, ::-1]])
        both = np.concatenate([u1, u2, ph])
        even = np.linalg.norm(both - flip)
        odd = np.linalg.norm(both + flip)
        return n, ("E" if even >= odd else "O"), purity


def _eigs(K, M, count):
    try:
        lu = splu(K - SIGMA * M)
    except RuntimeError as exc:
        raise ConvergenceError(f"K - sigma M is singular: {exc}") from exc
    op = LinearOperator(K.shape, matvec=lu.solve, dtype=float)

    try:
        w, v = eigsh(K, k=count, M=M, sigma=SIGMA, which="LM", tol=EIG_TOL, OPinv=op)
    except Exception as exc:  # ARPACK errors are not all ArpackNoConvergence
        raise ConvergenceError(f"shift-invert Lanczos failed: {exc}") from exc
    order = np.argsort(w)
    return w[order], v[:, order]


@dataclass(frozen=True)
class Modes:
    """Eigenpairs nearest zero at one (lam, kH): eigenvalues, classes, residuals."""

    lam: float
    kH: float
    Dhat: float
    omega: np.ndarray
    n: tuple[int, ...]
    parity: tuple[str, ...]
    purity: np.ndarray
    residual: np.ndarray  # ||K v - omega M v|| / ||K v|| per pair
    ndof: int


def modes(lam: float, kH: float, material, *, Dhat: float | None = None,
          Vhat: float | None = None, mesh: StripMesh | None = None, count: int = N_EIG,
          _strip: _Strip | None = None) -> Modes:
    """The ``count`` eigenpairs of K v = omega M v nearest zero, classified.

    Give exactly one of ``Dhat`` (charge control) or ``Vhat`` (voltage control).
    """
    require(np.isfinite(kH) and kH > 0, f"kH must be finite and > 0, got {kH}")
    require((Dhat is None) != (Vhat is None), "give exactly one of Dhat and Vhat")
    D = dhat_at_voltage(lam, Vhat, material) if Dhat is None else Dhat
    strip = _strip if _strip is not None else _Strip(mesh or default_mesh(kH))
    state = base_state(lam, D, material)
    K, M = strip.matrices(state, kH * lam**-2)
    w, v = _eigs(K, M, count)
    cls = [strip.classify(v[:, j]) for j in range(v.shape[1])]
    # backward error of each pair: ||K v - omega M v|| / ((||K||_1 + |omega| ||M||_1) ||v||)
    scale = spnorm(K, 1) + np.abs(w) * spnorm(M, 1)
    res = (np.linalg.norm(K @ v - (M @ v) * w, axis=0)
           / (scale * np.linalg.norm(v, axis=0)))
    return Modes(float(lam), float(kH), float(D), w, tuple(c[0] for c in cls),
                 tuple(c[1] for c in cls), np.array([c[2] for c in cls]), res, strip.ndof)


def branch_eigenvalue(m: Modes, parity: str, n: int = 1) -> float:
    """Lowest eigenvalue of class (n, parity) among the computed pairs."""
    sel = [w for w, nn, pp, pu in zip(m.omega, m.n, m.parity, m.purity, strict=True)
           if nn == n and pp == parity and pu >= PURITY]
    if not sel:
        raise ConvergenceError(f"no eigenpair of class (n={n}, {parity}) among the "
                               f"{m.omega.size} nearest zero at lam={m.lam}, kH={m.kH}")
    return float(min(sel))


@dataclass(frozen=True)
class StripRoot:
    """Critical stretch found by the strip model, with what was achieved."""

    lam: float
    kH: float
    parity: str
    control: str
    load: float           # Dhat (charge control) or Vhat (voltage control)
    Dhat: float           # Dhat at the critical stretch
    evaluations: int
    eigen_residual: float  # max relative residual of the eigenpairs at the root
    purity: float          # share of the n = 1 harmonic in the critical mode
    ndof: int
    mesh: StripMesh


def critical_stretch(kH: float, bracket: tuple[float, float], parity: str, material, *,
                     Dhat: float | None = None, Vhat: float | None = None,
                     mesh: StripMesh | None = None, guess: float | None = None,
                     _strip: _Strip | None = None) -> StripRoot:
    """lam_cr in ``bracket``: zero of the lowest (n = 1, ``parity``) eigenvalue, located
    to XTOL.

    With ``guess`` (an estimate inside ``bracket``, e.g. the determinant root), secant
    steps start there and brentq finishes on the narrowest interval where the eigenvalue
    changed sign (:func:`debench.models.numerics.roots.zero_near`: 4-6 eigen-solves where a
    search of the whole bracket needs ~9); without it, or when they find no sign change,
    the eigenvalue must change sign across ``bracket`` (else :class:`ConvergenceError`).
    Give exactly one of ``Dhat`` (charge control) or ``Vhat`` (voltage control);
    ``_strip`` (the assembled ``mesh``) may be shared by the roots of one mesh.
    """
    require(parity in PARITIES, f"parity must be one of {PARITIES}, got {parity!r}")
    lo, hi = (float(b) for b in bracket)
    require(np.isfinite(lo) and np.isfinite(hi) and 0 < lo < hi,
            f"bracket must satisfy 0 < lo < hi, got {bracket}")
    require(guess is None or (np.isfinite(guess) and lo < guess < hi),
            f"guess must lie inside the bracket ({lo}, {hi}), got {guess}")
    require((Dhat is None) != (Vhat is None), "give exactly one of Dhat and Vhat")
    mesh = mesh or default_mesh(kH)
    strip = _strip if _strip is not None else _Strip(mesh)
    # the pair count that reached the n = 1 class (kept for the next evaluations of this
    # root) and the modes of every evaluated stretch
    count = [N_EIG]
    seen: dict[float, Modes] = {}

    def f(x):
        while True:
            m = modes(x, kH, material, Dhat=Dhat, Vhat=Vhat, _strip=strip, count=count[0])
            try:
                value = branch_eigenvalue(m, parity)
            except ConvergenceError:
                # thick plates: the harmonics n k share the half-space limit and crowd
                # zero, so more pairs are needed to reach the n = 1 class
                if count[0] >= N_EIG_MAX:
                    raise
                count[0] *= 2
                continue
            seen[float(x)] = m
            return value

    r = zero_near(f, guess, lo, hi, XTOL, what=f"the ({parity}, n=1) eigenvalue at kH={kH}").root
    m = seen[r]
    j = int(np.argmin(np.abs(m.omega)))
    control = "charge" if Dhat is not None else "voltage"
    return StripRoot(float(r), float(kH), parity, control,
                     float(Dhat if Dhat is not None else Vhat), m.Dhat, len(seen),
                     float(np.max(m.residual)), float(m.purity[j]), m.ndof, mesh)
