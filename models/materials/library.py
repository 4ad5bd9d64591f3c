"""The constitutive library: frozen parameter dataclasses that are also the energies.

Every material follows one protocol (:class:`~debench.models.materials.protocol.Material`),
so that no caller asks which material it holds:

* the energy, one expression for every backend: ``energy_expression(F, D_L, *, xp)`` and,
  where the energy has a purely mechanical part, ``mechanical_energy(F, *, xp)`` (``W`` at
  ``D_L = 0``), with ``xp`` a math namespace (:data:`~debench.models.materials.energies.NUMPY`,
  :data:`~debench.models.materials.ngsolve_forms.NGSOLVE` and its variants);
* the numpy API ``energy(F, D_L)`` and ``response(F, D_L, second=True) -> Response``
  (energy, dW/dF, dW/dD_L and the moduli (2.65)-(2.67)); invariant-based materials also
  expose their hand derivation ``invariant_derivatives(I) -> (W, W_n, W_mn)`` and
  ``invariant_response`` (the chain rule over it);
* the moduli ``shear_modulus`` and ``bulk_modulus`` (``k``; infinite when incompressible);
* admissibility: ``check_admissible(F, D_L)`` raises ``ValueError`` naming the bound.

:class:`~debench.models.materials.protocol.IdealDielectricElastomer` is the part of the
protocol the Chapter 5 finite-element models need: a compressible elastic energy plus the
ideal dielectric (5.9), whose electric enthalpy they assemble.

``incompressible`` materials are meant for det F = 1 with a Lagrange multiplier p
(eqs (2.29)-(2.34)); their energy is still evaluated off the constraint (needed for
derivatives), as printed in the thesis.

Each energy ``W`` is the one expression of :mod:`debench.models.materials.energies`
(evaluated here with numpy, by NGSolve in :mod:`debench.models.materials.ngsolve_forms`).
The stress and moduli of the invariant-based materials come from that expression, by
second-order forward differentiation
(:func:`~debench.models.materials.jet.expression_response`); their hand-written ``W_n``,
``W_mn`` are the independent check (``invariant_response``, compared in the tests, and
NGSolve's symbolic derivatives of the same expressions). Ogden's stress and moduli are
the spectral formula of the kernel.

Units: SI (Pa, F/m, C/m^2) or any consistent non-dimensional set.
"""

from __future__ import annotations

import functools
import math
import numbers
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np
from debench.models import validation as v
from debench.models.invariants import invariants, validate_state
from debench.models.materials import energies as E
from debench.models.materials.constants import (  # defined once; VACUUM_PERMITTIVITY re-exported
    EPS_R_ASSUMED,
    TABLE_5_1_BULK_MODULUS,
    TABLE_5_1_NH_SHEAR_MODULUS,
    TABLE_5_1_OGDEN_ALPHAS,
    TABLE_5_1_OGDEN_MUS,
    VACUUM_PERMITTIVITY,
    VHB_GENT_JM,
    VHB_SHEAR_MODULUS,
)
from debench.models.materials.jet import expression_response
from debench.models.materials.kernel import (
    Response,
    divided_difference_power,
    invariant_chain_rule,
    spectral_response,
)
from debench.models.materials.protocol import IdealDielectricElastomer, Material


def _positive(name: str, value: float) -> None:
    v.positive(name, value)
    if not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number, got {value!r}")


def _finite(name: str, value: float) -> None:
    v.finite(name, value)
    if not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number, got {value!r}")


def _invariant_vector(I) -> np.ndarray:
    """``I = [I1, ..., I6]`` of a physical state: finite, ``I3 = det C > 0``."""
    I = v.vector("I", I, 6)
    if not I[2] > 0:
        raise ValueError(f"I3 = det C = {I[2]:.6g} must be > 0")
    return I


class _InvariantMaterial(Material):
    """Mixin: an invariant-based energy. ``energy`` evaluates its one expression and
    ``response`` differentiates it
    (:func:`~debench.models.materials.jet.expression_response`); ``invariant_response``
    is the same response by the hand-written ``invariant_derivatives`` and the chain rule
    (2.68)-(2.70) of the kernel, the check."""

    def _state(self, F, D_L):
        self.check_admissible(F, D_L)
        return validate_state(F, D_L, self._fibre(), numbering=self.numbering)

    @v.finite_result
    def energy(self, F, D_L) -> float:
        F, D_L, _ = self._state(F, D_L)
        return float(self.energy_expression(F, D_L, xp=E.NUMPY))

    @v.finite_result
    def response(self, F, D_L, *, second: bool = True) -> Response:
        F, D_L, _ = self._state(F, D_L)
        return expression_response(self, F, D_L, second=second)

    @v.finite_result
    def invariant_response(self, F, D_L, *, second: bool = True) -> Response:
        """The response by the hand derivation: ``invariant_derivatives`` and the chain
        rule :func:`~debench.models.materials.kernel.invariant_chain_rule`."""
        F, D_L, A = self._state(F, D_L)
        I = invariants(F, D_L, A, numbering=self.numbering)
        W, Wn, Wmn = self.invariant_derivatives(I)
        return invariant_chain_rule(W, Wn, Wmn, F, D_L, A, numbering=self.numbering,
                                    second=second)


# ----------------------------------------------------------------------------- Gent
@dataclass(frozen=True)
class GentIdealDielectric(_InvariantMaterial):
    """Incompressible Gent elastomer with an ideal dielectric (Ch. 3).

    ``W = -mu Jm/2 ln(1 - (I1 - 3)/Jm) + I5/(2 eps)`` (eq. (3.23) plus the ideal dielectric,
    the D_L form of (3.20) with constant permittivity, c = 0 in (3.27)); iso numbering.
    Thesis values: mu = 51 kPa, Jm = 120 (Sec. 3.3.3).

    Raises ``ValueError`` when ``I1 - 3 >= Jm`` (past the locking stretch).
    """

    mu: float = VHB_SHEAR_MODULUS
    Jm: float = VHB_GENT_JM
    # assumption ch2.assumption.eps_r
    eps: float = field(default=EPS_R_ASSUMED * VACUUM_PERMITTIVITY)
    numbering: ClassVar[str] = "iso"
    incompressible: ClassVar[bool] = True

    def __post_init__(self):
        _positive("mu", self.mu)
        _positive("Jm", self.Jm)
        _positive("eps", self.eps)

    def energy_expression(self, F, D_L, *, xp):
        I = E.invariants(F, D_L, xp=xp)
        return E.gent_ideal_dielectric(I["I1"], I["DCD"], mu=self.mu, Jm=self.Jm, eps=self.eps,
                                       xp=xp)

    def mechanical_energy(self, F, *, xp):
        return E.gent(E.invariants(F, xp=xp)["I1"], mu=self.mu, Jm=self.Jm, xp=xp)

    def check_admissible(self, F, D_L=None) -> None:
        """Also ``I1 - 3 < Jm`` (short of the Gent lock)."""
        super().check_admissible(F, D_L)
        self.invariant_derivatives(invariants(F, np.zeros(3)))

    def invariant_derivatives(self, I):
        """``(W, W_n, W_mn)`` at ``I = [I1, ..., I6]``; ValueError past the Gent lock."""
        I = _invariant_vector(I)
        x = (I[0] - 3.0) / self.Jm
        if not x < 1.0:
            raise ValueError(f"I1 - 3 = {I[0] - 3.0:.6g} is past the Gent lock: must be "
                             f"< Jm = {self.Jm:.6g}")
        W = E.gent_ideal_dielectric(I[0], I[4], mu=self.mu, Jm=self.Jm, eps=self.eps,
                                    xp=E.NUMPY)
        Wn = np.zeros(6)
        Wmn = np.zeros((6, 6))
        Wn[0] = 0.5 * self.mu / (1 - x)
        Wn[4] = 1 / (2 * self.eps)
        Wmn[0, 0] = 0.5 * self.mu / (self.Jm * (1 - x) ** 2)
        return W, Wn, Wmn

    @property
    def shear_modulus(self) -> float:
        """Initial shear modulus: mu."""
        return self.mu


# ---------------------------------------------------------------- neo-Hookean (Ch. 5)
@dataclass(frozen=True)
class NeoHookeanIdealDielectric(IdealDielectricElastomer, _InvariantMaterial):
    """Compressible neo-Hookean (5.15) + ideal dielectric (5.9), Ch. 5.

    ``W = C10 (J^{-2/3} I1 - 3) + (J - 1)^2/D1 + J^{-1} I5/(2 eps)`` with ``C10 = mu/2``
    (5.16), ``D1 = 2/k`` (5.17), ``J = sqrt(I3)``; iso numbering.
    Table 5.1: mu = 156000 Pa, k = 7748003.92 Pa.
    """

    mu: float = TABLE_5_1_NH_SHEAR_MODULUS
    k: float = TABLE_5_1_BULK_MODULUS
    # assumption ch2.assumption.eps_r
    eps: float = field(default=EPS_R_ASSUMED * VACUUM_PERMITTIVITY)
    numbering: ClassVar[str] = "iso"
    incompressible: ClassVar[bool] = False

    def __post_init__(self):
        _positive("mu", self.mu)
        _positive("k", self.k)
        _positive("eps", self.eps)

    def mechanical_energy(self, F, *, xp):
        I = E.invariants(F, xp=xp)
        return E.neo_hookean(I["I1"], I["J"], mu=self.mu, k=self.k)

    @property
    def C10(self) -> float:
        return self.mu / 2

    @property
    def D1(self) -> float:
        return 2 / self.k

    @property
    def shear_modulus(self) -> float:
        return self.mu

    def invariant_derivatives(self, I):
        """``(W, W_n, W_mn)`` at ``I = [I1, ..., I6]`` (I3 > 0)."""
        I = _invariant_vector(I)
        I1, I3, I5 = I[0], I[2], I[4]
        C10, D1, eps = self.C10, self.D1, self.eps
        W = E.neo_hookean_ideal_dielectric(I1, math.sqrt(I3), I5, mu=self.mu, k=self.k,
                                           eps=eps)
        Wn = np.zeros(6)
        Wmn = np.zeros((6, 6))
        Wn[0] = C10 * I3 ** (-1 / 3)
        Wn[2] = (-C10 / 3 * I1 * I3 ** (-4 / 3) + (1 - I3**-0.5) / D1
                 - I5 * I3**-1.5 / (4 * eps))
        Wn[4] = I3**-0.5 / (2 * eps)
        Wmn[0, 2] = Wmn[2, 0] = -C10 / 3 * I3 ** (-4 / 3)
        Wmn[2, 2] = (4 * C10 / 9 * I1 * I3 ** (-7 / 3) + I3**-1.5 / (2 * D1)
                     + 3 * I5 * I3**-2.5 / (8 * eps))
        Wmn[2, 4] = Wmn[4, 2] = -(I3**-1.5) / (4 * eps)
        return W, Wn, Wmn


@dataclass(frozen=True)
class MooneyRivlinIdealDielectric(IdealDielectricElastomer, _InvariantMaterial):
    """Compressible Mooney-Rivlin elastomer with the ideal dielectric (5.9)::

        W = C10 (J^{-2/3} I1 - 3) + C01 (J^{-4/3} I2 - 3) + k/2 (J - 1)^2 + I5/(2 eps J)

    iso numbering, ``J = sqrt(I3)``; initial shear modulus ``2 (C10 + C01)``. ``C01 = 0``
    is the neo-Hookean (5.15) with ``mu = 2 C10``. Not a thesis material: the defaults
    split the Table 5.1 neo-Hookean shear modulus 70/30 between ``C10`` and ``C01`` (same
    initial response), with the Table 5.1 bulk modulus.
    """

    C10: float = 0.35 * TABLE_5_1_NH_SHEAR_MODULUS
    C01: float = 0.15 * TABLE_5_1_NH_SHEAR_MODULUS
    k: float = TABLE_5_1_BULK_MODULUS
    eps: float = field(default=EPS_R_ASSUMED * VACUUM_PERMITTIVITY)

    def __post_init__(self):
        _positive("C10", self.C10)
        _finite("C01", self.C01)
        if self.C01 < 0:
            raise ValueError(f"C01 must be >= 0, got {self.C01}")
        _positive("k", self.k)
        _positive("eps", self.eps)

    @property
    def shear_modulus(self) -> float:
        """Initial shear modulus ``2 (C10 + C01)``."""
        return 2 * (self.C10 + self.C01)

    def mechanical_energy(self, F, *, xp):
        I = E.invariants(F, xp=xp)
        return (E.mooney_rivlin_isochoric(I["I1"], I["I2"], I["J"], C10=self.C10, C01=self.C01)
                + E.volumetric(I["J"], k=self.k))

    def invariant_derivatives(self, I):
        """``(W, W_n, W_mn)`` at ``I = [I1, ..., I6]`` (I3 > 0)."""
        I = _invariant_vector(I)
        I1, I2, I3, I5 = I[0], I[1], I[2], I[4]
        C10, C01, k, eps = self.C10, self.C01, self.k, self.eps
        J = math.sqrt(I3)
        W = (E.mooney_rivlin_isochoric(I1, I2, J, C10=C10, C01=C01) + E.volumetric(J, k=k)
             + E.ideal_dielectric(I5, J, eps=eps))
        Wn = np.zeros(6)
        Wmn = np.zeros((6, 6))
        Wn[0] = C10 * I3 ** (-1 / 3)
        Wn[1] = C01 * I3 ** (-2 / 3)
        Wn[2] = (-C10 / 3 * I1 * I3 ** (-4 / 3) - 2 * C01 / 3 * I2 * I3 ** (-5 / 3)
                 + k / 2 * (1 - I3**-0.5) - I5 * I3**-1.5 / (4 * eps))
        Wn[4] = I3**-0.5 / (2 * eps)
        Wmn[0, 2] = Wmn[2, 0] = -C10 / 3 * I3 ** (-4 / 3)
        Wmn[1, 2] = Wmn[2, 1] = -2 * C01 / 3 * I3 ** (-5 / 3)
        Wmn[2, 2] = (4 * C10 / 9 * I1 * I3 ** (-7 / 3) + 10 * C01 / 9 * I2 * I3 ** (-8 / 3)
                     + k / 4 * I3**-1.5 + 3 * I5 * I3**-2.5 / (8 * eps))
        Wmn[2, 4] = Wmn[4, 2] = -(I3**-1.5) / (4 * eps)
        return W, Wn, Wmn


@dataclass(frozen=True)
class IdealDielectric(_InvariantMaterial):
    """The electrical part alone, ``W_ele = J^{-1} I5/(2 eps)`` (eq. (5.9)); iso numbering.

    Not a solid on its own (zero shear modulus); included so the battery checks (5.9).
    """

    eps: float = field(default=EPS_R_ASSUMED * VACUUM_PERMITTIVITY)
    numbering: ClassVar[str] = "iso"
    incompressible: ClassVar[bool] = False

    def __post_init__(self):
        _positive("eps", self.eps)

    @property
    def shear_modulus(self) -> float:
        return 0.0

    def energy_expression(self, F, D_L, *, xp):
        I = E.invariants(F, D_L, xp=xp)
        return E.ideal_dielectric(I["DCD"], I["J"], eps=self.eps)

    def invariant_derivatives(self, I):
        """``(W, W_n, W_mn)`` at ``I = [I1, ..., I6]`` (I3 > 0)."""
        I = _invariant_vector(I)
        I3, I5, eps = I[2], I[4], self.eps
        Wn = np.zeros(6)
        Wmn = np.zeros((6, 6))
        W = E.ideal_dielectric(I5, math.sqrt(I3), eps=eps)
        Wn[2] = -I5 * I3**-1.5 / (4 * eps)
        Wn[4] = I3**-0.5 / (2 * eps)
        Wmn[2, 2] = 3 * I5 * I3**-2.5 / (8 * eps)
        Wmn[2, 4] = Wmn[4, 2] = -(I3**-1.5) / (4 * eps)
        return W, Wn, Wmn


@dataclass(frozen=True)
class DorfmannOgdenElectric(_InvariantMaterial):
    """The Dorfmann-Ogden electrical part alone, eq. (4.20), isotropic numbering::

        W_el = (alpha D_L.D_L + beta D_L.C D_L)/(2 eps) = (alpha I4 + beta I5)/(2 eps)

    (the same as ``(alpha I6 + beta I5)/(2 eps)`` in the Ch. 4 numbering). Incompressible
    (used with the Ch. 4 plate); ``alpha = 0, beta = 0.5`` of Sec. 4.4, non-dimensional eps.
    """

    alpha: float = 0.0
    beta: float = 0.5
    eps: float = 1.0
    numbering: ClassVar[str] = "iso"
    incompressible: ClassVar[bool] = True

    def __post_init__(self):
        _finite("alpha", self.alpha)
        _finite("beta", self.beta)
        _positive("eps", self.eps)

    @property
    def shear_modulus(self) -> float:
        return 0.0

    def energy_expression(self, F, D_L, *, xp):
        I = E.invariants(F, D_L, xp=xp)
        return E.dorfmann_ogden_electric(I["DD"], I["DCD"], alpha=self.alpha, beta=self.beta,
                                         eps=self.eps)

    def invariant_derivatives(self, I):
        """``(W, W_n, W_mn)`` at ``I = [I1, ..., I6]``."""
        I = _invariant_vector(I)
        Wn = np.zeros(6)
        Wn[3] = self.alpha / (2 * self.eps)
        Wn[4] = self.beta / (2 * self.eps)
        W = E.dorfmann_ogden_electric(I[3], I[4], alpha=self.alpha, beta=self.beta,
                                      eps=self.eps)
        return W, Wn, np.zeros((6, 6))


# ------------------------------------------------------------- Ogden (Ch. 5, 5.26)
@dataclass(frozen=True)
class OgdenIdealDielectric(IdealDielectricElastomer):
    """Compressible three-term Ogden (5.26) + volumetric (J-1)^2/D1 + ideal dielectric (5.9).

    ``W = sum_p 2 mu_p/alpha_p^2 (lb1^a_p + lb2^a_p + lb3^a_p - 3) + k/2 (J - 1)^2
    + J^{-1} I5/(2 eps)`` with deviatoric stretches ``lb_k = J^{-1/3} lambda_k``.

    Convention: (5.26) prints ``2 mu_i/alpha_i^2`` (the Abaqus/Ogden "mu_i" convention),
    consistent with the Kirchhoff stress (5.27) ``2 mu_p/alpha_p (...)``. The initial
    shear modulus is then ``sum_p mu_p`` = 69580 Pa for Table 5.1 (the other common
    convention ``mu_p/alpha_p`` would give ``sum mu_p alpha_p / 2`` = 73718 Pa).
    Table 5.1 states no bulk modulus for Ogden; the neo-Hookean k is used (assumption
    ``ch2.assumption.ogden_bulk_modulus``).
    """

    alphas: tuple[float, ...] = TABLE_5_1_OGDEN_ALPHAS
    mus: tuple[float, ...] = TABLE_5_1_OGDEN_MUS
    k: float = TABLE_5_1_BULK_MODULUS
    eps: float = field(default=EPS_R_ASSUMED * VACUUM_PERMITTIVITY)
    numbering: ClassVar[str] = "iso"
    incompressible: ClassVar[bool] = False

    def __post_init__(self):
        for name in ("alphas", "mus"):
            seq = getattr(self, name)
            if isinstance(seq, str | bytes) or not hasattr(seq, "__len__"):
                raise TypeError(f"{name} must be a sequence of numbers, got {seq!r}")
        if len(self.alphas) != len(self.mus) or not len(self.alphas):
            raise ValueError(f"alphas and mus must have equal non-zero length, got "
                             f"{len(self.alphas)} and {len(self.mus)}")
        for a in self.alphas:
            _finite("alpha", a)
            if a == 0:
                raise ValueError("alpha_p must be != 0, got 0")
        for m in self.mus:
            _finite("mu_p", m)
        _positive("k", self.k)
        _positive("eps", self.eps)
        if not self.shear_modulus > 0:
            raise ValueError(f"initial shear modulus sum(mu_p) must be > 0, got "
                             f"{self.shear_modulus}")

    @property
    def shear_modulus(self) -> float:
        """Initial shear modulus ``sum_p mu_p`` (convention 2 mu_p/alpha_p^2 of (5.26))."""
        return float(sum(self.mus))

    def mechanical_energy(self, F, *, xp):
        """(5.26) + k/2 (J - 1)^2 through the power sums of the eigenvalues of ``Cbar``,
        which the namespace evaluates (``xp.spectral``: numpy exactly, NGSolve by its
        regularised or axisymmetric forms)."""
        J = xp.det(F)
        Cb = E.isochoric_right_cauchy_green(E.right_cauchy_green(F, xp=xp), J)
        isochoric = functools.partial(E.ogden_isochoric_from_power_sums, alphas=self.alphas,
                                      mus=self.mus)
        return xp.spectral(Cb, isochoric) + E.volumetric(J, k=self.k)

    def _phi(self, c):
        """Energy of the eigenvalues c_k of C and its derivatives (see spectral_response):
        the energy is :func:`debench.models.materials.energies.ogden` at the eigenvalues
        ``J^{-2/3} c_k`` of Cbar, the derivatives are written out here."""
        c = np.asarray(c, dtype=float)
        Pc = float(np.prod(c))
        J = math.sqrt(Pc)
        W = E.ogden(E.isochoric_right_cauchy_green(c, J), J, alphas=self.alphas, mus=self.mus,
                    k=self.k)
        phik = np.zeros(3)
        phikl = np.zeros((3, 3))
        A_common = 0.0
        theta = np.zeros((3, 3))
        inv_c = 1 / c
        for a, m in zip(self.alphas, self.mus, strict=True):
            ap = 2 * m / a**2
            e = -a / 6            # J^{-a/3} = Pc^e
            q = a / 2
            Pe = Pc**e
            s = float(np.sum(c**q))
            A_common += ap * e * Pe * s
            B = ap * Pe * q
            phik += B * c ** (q - 1)
            phikl += ap * (e * e * Pe * s * np.outer(inv_c, inv_c)
                           - np.diag(e * Pe * s * inv_c**2)
                           + e * Pe * q * np.outer(inv_c, c ** (q - 1))
                           + e * Pe * q * np.outer(c ** (q - 1), inv_c)
                           + np.diag(Pe * q * (q - 1) * c ** (q - 2)))
            theta += B * divided_difference_power(c[:, None], c[None, :], q - 1)
        # volumetric k/2 (J-1)^2
        U1, U2 = self.k * (J - 1), self.k
        A_common += U1 * J / 2
        phikl += (U2 * J**2 / 4 * np.outer(inv_c, inv_c)
                  + U1 * (J / 4 * np.outer(inv_c, inv_c) - np.diag(J / 2 * inv_c**2)))
        phik += A_common * inv_c
        theta += -A_common * np.outer(inv_c, inv_c)
        return W, phik, phikl, theta

    @v.finite_result
    def energy(self, F, D_L) -> float:
        return self.response(F, D_L, second=False).W

    @v.finite_result
    def response(self, F, D_L, *, second: bool = True) -> Response:
        F, D_L, _ = validate_state(F, D_L)
        mech = spectral_response(self._phi, F, second=second)
        return mech + IdealDielectric(eps=self.eps).response(F, D_L, second=second)


# -------------------------------------------- transversely isotropic (Ch. 4, 4.22)
@dataclass(frozen=True)
class TransverselyIsotropicNeoHookean(_InvariantMaterial):
    """Incompressible transversely isotropic neo-Hookean dielectric, eq. (4.22).

    ``W = mu/2 (I1 - 3) + mu/2 xi (I4 - 1)^2 + (alpha I6 + beta I5)/(2 eps)`` in the ``ti``
    numbering (I4 = A.CA, I5 = D_L.C D_L, I6 = D_L.D_L). The electric part is the
    Dorfmann-Ogden form (4.20); ``eps`` is the vacuum permittivity there. ``xi = 0`` gives
    the isotropic neo-Hookean dielectric of Dorfmann & Ogden. Thesis uses A = (0, 1, 0),
    xi in {0, 3, 5, 10}.
    """

    mu: float = 1.0
    xi: float = 5.0
    alpha: float = 0.0
    beta: float = 0.5
    eps: float = 1.0
    A: tuple[float, float, float] = (0.0, 1.0, 0.0)
    numbering: ClassVar[str] = "ti"
    incompressible: ClassVar[bool] = True

    def __post_init__(self):
        _positive("mu", self.mu)
        _finite("xi", self.xi)
        if self.xi < 0:
            raise ValueError(f"xi must be >= 0, got {self.xi}")
        _finite("alpha", self.alpha)
        _finite("beta", self.beta)
        _positive("eps", self.eps)
        v.unit_vector("A", self.A)

    def _fibre(self):
        return np.asarray(self.A, dtype=float)

    def energy_expression(self, F, D_L, *, xp):
        I = E.invariants(F, D_L, xp.vector(self.A), xp=xp)
        return E.ti_neo_hookean_dielectric(I["I1"], I["ACA"], I["DD"], I["DCD"], mu=self.mu,
                                           xi=self.xi, alpha=self.alpha, beta=self.beta,
                                           eps=self.eps)

    def mechanical_energy(self, F, *, xp):
        I = E.invariants(F, A=xp.vector(self.A), xp=xp)
        return E.ti_neo_hookean_elastic(I["I1"], I["ACA"], mu=self.mu, xi=self.xi)

    @property
    def shear_modulus(self) -> float:
        """Shear modulus for shear in the plane transverse to A: mu."""
        return self.mu

    def invariant_derivatives(self, I):
        """``(W, W_n, W_mn)`` at ``I = [I1, ..., I6]`` (ti numbering)."""
        I = _invariant_vector(I)
        mu, xi = self.mu, self.xi
        W = E.ti_neo_hookean_dielectric(I[0], I[3], I[5], I[4], mu=mu, xi=xi,
                                        alpha=self.alpha, beta=self.beta, eps=self.eps)
        Wn = np.zeros(6)
        Wmn = np.zeros((6, 6))
        Wn[0] = mu / 2
        Wn[3] = mu * xi * (I[3] - 1)
        Wn[4] = self.beta / (2 * self.eps)
        Wn[5] = self.alpha / (2 * self.eps)
        Wmn[3, 3] = mu * xi
        return W, Wn, Wmn


# ------------------------------------------------------------------------ registry
MATERIALS: dict[str, Material] = {
    "gent_ideal_dielectric": GentIdealDielectric(),
    "neo_hookean_ideal_dielectric": NeoHookeanIdealDielectric(),
    "ogden_ideal_dielectric": OgdenIdealDielectric(),
    "ideal_dielectric": IdealDielectric(),
    "ti_neo_hookean_dielectric": TransverselyIsotropicNeoHookean(),
    "dorfmann_ogden_electric": DorfmannOgdenElectric(alpha=0.3, beta=0.5),
    "mooney_rivlin_ideal_dielectric": MooneyRivlinIdealDielectric(),
}
"""Every 3-D material of the library, by name: the one registry (the battery and the
backend tests loop over it, :func:`material` looks names up in it). A material is added to
the library by its class and one entry here.

``ti_neo_hookean_dielectric`` is non-dimensional (mu = eps = 1, xi = 5, alpha = 0,
beta = 0.5 of Sec. 4.4); ``dorfmann_ogden_electric`` (4.20) alone is non-dimensional with
alpha = 0.3 (the thesis uses alpha = 0; nonzero here so the battery exercises the I4 = D.D
term); the others are SI with the thesis parameters.
"""

THESIS_MATERIALS = ("gent_ideal_dielectric", "neo_hookean_ideal_dielectric",
                    "ogden_ideal_dielectric", "ideal_dielectric", "ti_neo_hookean_dielectric",
                    "dorfmann_ogden_electric")
"""The names of :data:`MATERIALS` that are materials of the thesis (the Chapter 2 kernel
dataset holds these)."""

ALIASES = {"nh": "neo_hookean_ideal_dielectric", "ogden": "ogden_ideal_dielectric"}
"""Short names of the Chapter 5 cases for entries of :data:`MATERIALS`."""


def material(name: str) -> Material:
    """The material of :data:`MATERIALS` registered as ``name`` (or as its alias in
    :data:`ALIASES`); ``ValueError`` naming the argument and the valid names otherwise."""
    key = ALIASES.get(name, name) if isinstance(name, str) else None
    if key not in MATERIALS:
        raise ValueError(f"name must be a library material, one of "
                         f"{sorted(MATERIALS) + sorted(ALIASES)}, got {name!r}")
    return MATERIALS[key]
