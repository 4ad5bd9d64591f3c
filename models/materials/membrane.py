"""Membrane free energy (3.20), equations of state (3.14)-(3.16), (3.21)-(3.22), and the
deformation-dependent permittivities of Zhao-Suo (3.27) and Jimenez-McMeeking (3.24)-(3.26).

The thesis (Sec. 3.3.2) writes the free energy of an incompressible membrane with the
field through the thickness as a function of the in-plane stretches and
``I4 = E_L^2`` (Lagrangian field, ``E_L = lambda3 E``)::

    W(l1, l2, I4) = Ws(l1, l2) - 1/2 eps(l1, l2) l1^2 l2^2 I4                (3.20)
    sigma1 - sigma3 = l1 dW/dl1,  sigma2 - sigma3 = l2 dW/dl2                (3.14, 3.15)
    D = -2 l1^-2 l2^-2 dW/dI4 E                                              (3.16)

(``l1^2 l2^2 I4 = E^2``). Substituting (3.20) gives (3.21)-(3.22)::

    sigma1 - sigma3 = l1 dWs/dl1 - eps E^2 - l1/2 deps/dl1 E^2

:meth:`GentMembrane.equations_of_state` evaluates the closed forms (3.21)-(3.22);
:meth:`GentMembrane.equations_of_state_from_energy` differentiates (3.20) by complex step
- two independent paths that the tests compare. :meth:`ElastomerMembrane.stretching_energy_jet`
gives ``Ws`` of any library elastomer with its first and second derivatives in (l1, l2),
vectorised and complex-safe, by second-order forward differentiation of the elastomer's
one energy expression (what the Chapter 3 membrane ODE needs).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
from debench.models import validation as v
from debench.models.materials import energies as E
from debench.models.materials.constants import (
    EPS_R_ASSUMED,
    VACUUM_PERMITTIVITY,
    VHB_GENT_JM,
    VHB_SHEAR_MODULUS,
)
from debench.models.materials.jet import JET, JetOperators
from debench.models.materials.protocol import IncompressibleLimit, Material

_H = 1e-30  # complex step: no subtractive cancellation, any tiny step is exact to rounding


def _check_stretches(l1, l2):
    """In-plane stretches: finite, > 0 (complex allowed for complex-step derivatives)."""
    v.positive("lambda1", l1, complex_ok=True)
    v.positive("lambda2", l2, complex_ok=True)


def _scalar(name, value, check):
    check(name, value)
    if not isinstance(value, int | float):
        raise TypeError(f"{name} must be a real number, got {value!r}")


class MembraneJet(JetOperators):
    """A function of the membrane stretches (l1, l2) with its first and second
    derivatives, each an array over a batch of states (real or complex):
    ``v``, ``d1 = dv/dl1``, ``d2``, ``d11 = d2v/dl1^2``, ``d12``, ``d22``, stacked in
    ``x`` (shape ``(6,) + batch``).

    Arithmetic, ``**`` (a number exponent) and :func:`_membrane_log1p` propagate them
    exactly (to rounding), elementwise over the batch; products with the exact zero of an
    off-diagonal entry stay the number zero, so that a diagonal deformation gradient costs
    only its diagonal. The batched counterpart of :class:`~debench.models.materials.jet.Jet`
    for two variables.
    """

    __slots__ = ("x",)
    #: numpy arrays and scalars defer to the jet's reflected operators
    __array_ufunc__ = None

    def __init__(self, x):
        self.x = x

    v = property(lambda self: self.x[0], doc="The value.")
    d1 = property(lambda self: self.x[1], doc="d/dl1.")
    d2 = property(lambda self: self.x[2], doc="d/dl2.")
    d11 = property(lambda self: self.x[3], doc="d2/dl1^2.")
    d12 = property(lambda self: self.x[4], doc="d2/dl1 dl2.")
    d22 = property(lambda self: self.x[5], doc="d2/dl2^2.")

    @classmethod
    def seed(cls, l1, l2):
        """The jets of the variables l1 and l2 themselves (broadcast arrays)."""
        l1, l2 = np.broadcast_arrays(np.asarray(l1), np.asarray(l2))
        dtype = np.result_type(l1, l2, 1.0)
        a = np.zeros((6,) + l1.shape, dtype)
        b = np.zeros_like(a)
        a[0], a[1], b[0], b[2] = l1, 1.0, l2, 1.0
        return cls(a), cls(b)

    def _chain(self, f0, f1, f2):
        """``f(self)`` from ``f``, ``f'``, ``f''`` at ``self.v``."""
        x = self.x
        out = np.empty(x.shape, np.result_type(x, f0, f1, f2))
        out[0] = f0
        np.multiply(f1, x[1:], out=out[1:])
        out[3:] += f2 * (x[_I] * x[_J])
        return MembraneJet(out)

    def __add__(self, other):
        if isinstance(other, np.ndarray):
            return _each(other, lambda y: self + y)
        if not isinstance(other, MembraneJet):
            if other == 0:
                return self
            out = self.x.astype(np.result_type(self.x, other), copy=True)
            out[0] += other
            return MembraneJet(out)
        return MembraneJet(self.x + other.x)

    __radd__ = __add__

    def __neg__(self):
        return MembraneJet(-self.x)

    def __mul__(self, other):
        if isinstance(other, np.ndarray):
            return _each(other, lambda y: self * y)
        if not isinstance(other, MembraneJet):
            return 0.0 if other == 0 else MembraneJet(self.x * other)
        a, b = self.x, other.x
        out = a * b[0]
        out[1:] += a[0] * b[1:]
        cross = a[_I] * b[_J]
        cross += a[_J] * b[_I]
        out[3:] += cross
        return MembraneJet(out)

    __rmul__ = __mul__

    def __truediv__(self, other):
        if isinstance(other, np.ndarray):
            return _each(other, lambda y: self / y)
        return self * (other ** -1 if isinstance(other, MembraneJet) else 1.0 / other)


#: the first-derivative rows whose products make the second derivatives (11, 12, 22)
_I, _J = np.array([1, 1, 2]), np.array([1, 2, 2])


def _each(array, op):
    out = np.empty(array.shape, dtype=object)
    for k, x in np.ndenumerate(array):
        out[k] = op(x)
    return out


def _membrane_log1p(x):
    """``log(1 + x)`` on its real domain: NaN where the real part of ``1 + x`` is not
    positive (a complex argument would otherwise continue the energy past a Gent lock)."""
    if not isinstance(x, MembraneJet):
        return np.log1p(x)
    u = 1.0 + x.v
    with np.errstate(invalid="ignore", divide="ignore"):
        f0 = np.where(np.real(u) > 0, np.log1p(x.v), np.nan)
    return x._chain(f0, 1.0 / u, -1.0 / (u * u))


def _diagonal_spectral(M, energy):
    """``energy(power_sum)`` of a diagonal ``M`` (the membrane's): its eigenvalues are
    its diagonal entries."""
    if any(not (isinstance(M[i, j], float | int) and M[i, j] == 0)
           for i in range(3) for j in range(3) if i != j):
        raise ValueError("the membrane namespace evaluates spectral energies of diagonal "
                         "matrices only")
    return energy(lambda b: sum(M[k, k] ** b for k in range(3)))


MEMBRANE_JET = dataclasses.replace(JET, name="membrane-jet", log1p=_membrane_log1p,
                                   spectral=_diagonal_spectral)
"""The namespace of 3x3 object arrays of :class:`MembraneJet` (the cofactor ``det`` and
``inv`` of :data:`~debench.models.materials.jet.JET`; the logarithm on its real domain;
spectral energies of the diagonal membrane states)."""


@dataclass(frozen=True)
class ZhaoSuoPermittivity:
    """``eps = eps_bar [1 + c (l1 + l2 - 2)]`` (eq. (3.27)); ``eps_bar = eps_r eps_0``.

    Table 3.1 lists fitted c in [-0.0892, -0.0073]; c = 0 is the ideal dielectric.
    """

    eps_bar: float = EPS_R_ASSUMED * VACUUM_PERMITTIVITY
    c: float = 0.0

    def __post_init__(self):
        _scalar("eps_bar", self.eps_bar, v.positive)
        _scalar("c", self.c, v.finite)

    @v.finite_result
    def __call__(self, l1, l2):
        _check_stretches(l1, l2)
        eps = E.zhao_suo_permittivity(l1, l2, eps_bar=self.eps_bar, c=self.c)
        if not np.all(np.real(eps) > 0):
            raise ValueError(f"permittivity must stay > 0: 1 + c (l1 + l2 - 2) > 0 violated "
                             f"at l1={l1!r}, l2={l2!r}, c={self.c}")
        return eps

    @v.finite_result
    def derivative(self, l1, l2):
        """``(deps/dl1, deps/dl2)`` with l3 = 1/(l1 l2) eliminated."""
        self(l1, l2)
        v = self.eps_bar * self.c
        return v + 0 * l1, v + 0 * l2


@dataclass(frozen=True)
class JimenezMcMeekingPermittivity:
    """Deformation-dependent permittivity of Jimenez & McMeeking, eqs (3.24)-(3.26).

    ``eps_i = eps0_bar + c0 (2 l_i^2 - l_j^2 - l_k^2)``; the membrane uses the thickness
    component ``eps_3`` (3.26) with ``l3 = 1/(l1 l2)``. Linearised about l1 = l2 = 1 it is
    the Zhao-Suo form (3.27) with ``eps_bar = eps0_bar`` and ``c = -6 c0/eps0_bar``.
    """

    eps0_bar: float = EPS_R_ASSUMED * VACUUM_PERMITTIVITY
    c0: float = 0.0

    def __post_init__(self):
        _scalar("eps0_bar", self.eps0_bar, v.positive)
        _scalar("c0", self.c0, v.finite)

    @v.finite_result
    def components(self, l1, l2, l3):
        """``(eps1, eps2, eps3)`` of eqs (3.24)-(3.26) for arbitrary principal stretches.

        The stretches must be finite and > 0 (complex allowed).
        """
        v.positive("l1", l1, complex_ok=True)
        v.positive("l2", l2, complex_ok=True)
        v.positive("l3", l3, complex_ok=True)
        a, b, c = l1 * l1, l2 * l2, l3 * l3
        return (self.eps0_bar + self.c0 * (2 * a - b - c),
                self.eps0_bar + self.c0 * (2 * b - a - c),
                self.eps0_bar + self.c0 * (2 * c - a - b))

    @v.finite_result
    def __call__(self, l1, l2):
        _check_stretches(l1, l2)
        eps = self.components(l1, l2, 1 / (l1 * l2))[2]
        if not np.all(np.real(eps) > 0):
            raise ValueError(f"permittivity eps3 must stay > 0, violated at l1={l1!r}, "
                             f"l2={l2!r}, c0={self.c0}")
        return eps

    @v.finite_result
    def derivative(self, l1, l2):
        """``(deps3/dl1, deps3/dl2)`` with l3 = 1/(l1 l2): ``c0 (-4 l3^2/l1 - 2 l1)``."""
        self(l1, l2)
        l3sq = 1 / (l1 * l2) ** 2
        return self.c0 * (-4 * l3sq / l1 - 2 * l1), self.c0 * (-4 * l3sq / l2 - 2 * l2)

    def zhao_suo_linearisation(self) -> ZhaoSuoPermittivity:
        """The first-order Taylor expansion about l1 = l2 = 1, in the form (3.27)."""
        return ZhaoSuoPermittivity(eps_bar=self.eps0_bar, c=-6 * self.c0 / self.eps0_bar)


@dataclass(frozen=True)
class GentMembrane:
    """Incompressible Gent membrane (3.23) with a deformation-dependent permittivity.

    Thesis Ch. 3: mu = 51 kPa, Jm = 120, Zhao-Suo permittivity with c from Table 3.1.
    """

    mu: float = VHB_SHEAR_MODULUS
    Jm: float = VHB_GENT_JM
    permittivity: ZhaoSuoPermittivity | JimenezMcMeekingPermittivity = ZhaoSuoPermittivity()

    def __post_init__(self):
        _scalar("mu", self.mu, v.positive)
        _scalar("Jm", self.Jm, v.positive)
        v.instance("permittivity", self.permittivity,
                   (ZhaoSuoPermittivity, JimenezMcMeekingPermittivity))

    # ---- energy
    @v.finite_result
    def stretching_energy(self, l1, l2):
        """``Ws = -mu Jm/2 ln(1 - (I1 - 3)/Jm)``, ``I1 = l1^2 + l2^2 + l1^-2 l2^-2`` (3.23)."""
        _check_stretches(l1, l2)
        I1 = E.membrane_first_invariant(l1, l2)
        x = (I1 - 3) / self.Jm
        if not np.all(np.real(x) < 1):
            raise ValueError(f"I1 - 3 = {np.max(np.real(x)) * self.Jm:.6g} is past the Gent "
                             f"lock: must be < Jm = {self.Jm:.6g} (lambda1 = {l1!r:.40}, "
                             f"lambda2 = {l2!r:.40})")
        return E.gent(I1, mu=self.mu, Jm=self.Jm, xp=E.NUMPY)

    @v.finite_result
    def stretching_energy_derivative(self, l1, l2):
        """``(dWs/dl1, dWs/dl2)`` in closed form."""
        self.stretching_energy(l1, l2)
        l3sq = 1 / (l1 * l2) ** 2
        x = (l1 * l1 + l2 * l2 + l3sq - 3) / self.Jm
        g = self.mu / (1 - x)
        return g * (l1 - l3sq / l1), g * (l2 - l3sq / l2)

    @v.finite_result
    def free_energy(self, l1, l2, I4):
        """``W(l1, l2, I4) = Ws - eps l1^2 l2^2 I4/2`` (3.20), ``I4 = E_L^2``."""
        v.nonnegative("I4", I4, complex_ok=True)
        return (self.stretching_energy(l1, l2)
                + E.membrane_electric(l1, l2, I4, eps=self.permittivity(l1, l2)))

    # ---- equations of state
    @v.finite_result
    def equations_of_state(self, l1, l2, E):
        """``(sigma1 - sigma3, sigma2 - sigma3, D)`` by the closed forms (3.21), (3.22), D = eps E.

        ``E`` is the true field through the thickness (finite).
        """
        v.finite("E", E, complex_ok=True)
        dW1, dW2 = self.stretching_energy_derivative(l1, l2)
        eps = self.permittivity(l1, l2)
        de1, de2 = self.permittivity.derivative(l1, l2)
        E2 = E * E
        s13 = l1 * dW1 - eps * E2 - 0.5 * l1 * de1 * E2
        s23 = l2 * dW2 - eps * E2 - 0.5 * l2 * de2 * E2
        if not np.all(np.isfinite(s13) & np.isfinite(s23)):
            raise ValueError(f"E = {E!r:.40}: the stresses overflow (E^2 is not finite)")
        return s13, s23, eps * E

    @v.finite_result
    def equations_of_state_from_energy(self, l1, l2, E):
        """The same from (3.14)-(3.16) by complex-step differentiation of (3.20)."""
        _check_stretches(l1, l2)
        for name, value in (("lambda1", l1), ("lambda2", l2), ("E", E)):
            _scalar(name, value, v.finite)
        l1 = float(l1)
        l2 = float(l2)
        E = float(E)
        I4 = E * E / (l1 * l2) ** 2  # E_L = l3 E = E/(l1 l2)
        h = _H
        dW1 = self.free_energy(l1 + 1j * h, l2, I4).imag / h
        dW2 = self.free_energy(l1, l2 + 1j * h, I4).imag / h
        dW4 = self.free_energy(l1, l2, I4 + 1j * h).imag / h
        return l1 * dW1, l2 * dW2, -2 * dW4 * E / (l1 * l2) ** 2


@dataclass(frozen=True)
class ElastomerMembrane:
    """Incompressible membrane of any library elastomer, with a deformation-dependent
    permittivity: (3.20) with the stretching energy of the elastomer on ``J = 1``,

        Ws(l1, l2) = W_mech(diag(l1, l2, 1/(l1 l2)))

    (:meth:`~debench.models.materials.protocol.Material.mechanical_energy`, the elastomer's
    incompressible limit, :class:`~debench.models.materials.protocol.IncompressibleLimit`):
    ``GentIdealDielectric(mu, Jm)`` gives the Ws of :class:`GentMembrane` ``(mu, Jm)``.
    The Chapter 3 finite-element models evaluate the same ``mechanical_energy`` with NGSolve.

    ``stretching_energy_derivative`` comes from the elastomer's own stress
    (``response(...).P``: ``dWs/dl1 = P11 - P33 l3/l1``, as ``dl3/dl1 = -l3/l1``), so it is
    exact for every library material (the spectral Ogden too).
    """

    elastomer: Material
    permittivity: ZhaoSuoPermittivity | JimenezMcMeekingPermittivity = ZhaoSuoPermittivity()

    def __post_init__(self):
        # a compressible elastomer enters in its incompressible limit (which refuses
        # anything that is not a library material)
        if not getattr(self.elastomer, "incompressible", False):
            object.__setattr__(self, "elastomer", IncompressibleLimit(self.elastomer))
        v.instance("permittivity", self.permittivity,
                   (ZhaoSuoPermittivity, JimenezMcMeekingPermittivity))

    @property
    def shear_modulus(self) -> float:
        """The elastomer's initial shear modulus."""
        return self.elastomer.shear_modulus

    def _each(self, l1, l2, fn):
        l1, l2 = np.broadcast_arrays(np.asarray(l1, dtype=float), np.asarray(l2, dtype=float))
        out = [fn(np.diag([a, b, 1 / (a * b)])) for a, b in zip(l1.ravel(), l2.ravel(),
                                                                  strict=True)]
        return np.reshape(out, l1.shape + np.shape(out[0]) if out else l1.shape)

    @v.finite_result
    def stretching_energy(self, l1, l2):
        """``Ws(l1, l2)`` (real stretches > 0; ValueError naming the bound where the
        elastomer is not admissible, e.g. past a Gent lock)."""
        _check_stretches(l1, l2)

        def ws(F):
            self.elastomer.check_admissible(F)
            return self.elastomer.mechanical_energy(F, xp=E.NUMPY)

        return self._each(l1, l2, ws)[()]

    @v.finite_result
    def stretching_energy_derivative(self, l1, l2):
        """``(dWs/dl1, dWs/dl2)`` from the elastomer's first Piola stress."""
        _check_stretches(l1, l2)

        def d(F):
            self.elastomer.check_admissible(F)
            P = self.elastomer.response(F, np.zeros(3), second=False).P
            l3 = F[2, 2]
            return (P[0, 0] - P[2, 2] * l3 / F[0, 0], P[1, 1] - P[2, 2] * l3 / F[1, 1])

        out = self._each(l1, l2, d)
        return out[..., 0][()], out[..., 1][()]

    def stretching_energy_jet(self, l1, l2) -> MembraneJet:
        """``Ws(l1, l2)`` with its first and second derivatives in (l1, l2), per unit the
        elastomer's shear modulus, vectorised over broadcast arrays of stretches (real or
        complex: complex-step derivatives through it are exact).

        The elastomer's ``mechanical_energy`` evaluated on ``F = diag(l1, l2, 1/(l1 l2))``
        with :class:`MembraneJet` entries (:data:`MEMBRANE_JET`): no derivative is written
        by hand. The stretches must be finite and > 0, the states in the energy's real
        domain (ValueError past a Gent lock or where the energy overflows).
        """
        _check_stretches(l1, l2)
        W = self._stretching_energy_jet(l1, l2)
        if not all(np.all(np.isfinite(x)) for x in (W.v, W.d1, W.d2, W.d11, W.d12, W.d22)):
            raise ValueError(f"lambda1 = {l1!r:.40}, lambda2 = {l2!r:.40}: outside the "
                             f"elastomer's energy domain (past a lock, or it overflows)")
        return W

    def _stretching_energy_jet(self, l1, l2) -> MembraneJet:
        """:meth:`stretching_energy_jet` without checks (NaN stretches give NaN: the
        integrator's inadmissible trajectories)."""
        a, b = MembraneJet.seed(l1, l2)
        F = np.array([[a, 0.0, 0.0], [0.0, b, 0.0], [0.0, 0.0, 1.0 / (a * b)]], dtype=object)
        with np.errstate(all="ignore"):
            W = self.elastomer.mechanical_energy(F, xp=MEMBRANE_JET)
            if not isinstance(W, MembraneJet):      # an energy independent of F
                x = np.zeros_like(a.x)
                x[0] = W
                W = MembraneJet(x)
            return W * (1.0 / self.shear_modulus)

    @v.finite_result
    def free_energy(self, l1, l2, I4):
        """``W(l1, l2, I4) = Ws - eps l1^2 l2^2 I4/2`` (3.20), ``I4 = E_L^2``."""
        v.nonnegative("I4", I4)
        return (self.stretching_energy(l1, l2)
                + E.membrane_electric(l1, l2, I4, eps=self.permittivity(l1, l2)))

    @v.finite_result
    def electric_energy_derivative(self, l1, l2):
        """``d/dl1`` of the electric part of (3.20) per unit ``I4``: ``-(eps + l1/2
        deps/dl1) l1 l2^2`` (the derivative (3.21) takes)."""
        eps = self.permittivity(l1, l2)
        de1, _ = self.permittivity.derivative(l1, l2)
        return -(eps + 0.5 * l1 * de1) * l1 * l2 * l2
