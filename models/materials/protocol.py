"""The material protocol of the constitutive library: what every material provides.

A material (:class:`Material`) provides

* its energy as one expression for every backend: ``energy_expression(F, D_L, *, xp)``
  and ``mechanical_energy(F, *, xp)`` (``W(F, 0)``), evaluated by a math namespace ``xp``
  (:data:`~debench.models.materials.energies.NUMPY`,
  :data:`~debench.models.materials.ngsolve_forms.NGSOLVE` and its variants) -- the callers
  (the NGSolve forms, the finite-element models) call these methods and never ask which
  class they hold;
* the numpy API ``energy(F, D_L)`` and ``response(F, D_L, second=True)``;
* its moduli ``shear_modulus`` and ``bulk_modulus``;
* its admissibility: ``check_admissible(F, D_L)`` raises ``ValueError`` naming the bound.

:class:`IdealDielectricElastomer` is the part of the protocol the Chapter 5 finite-element
models need: a compressible elastic energy plus the ideal dielectric (5.9), whose electric
enthalpy they assemble. :class:`IncompressibleLimit` is how the incompressible models
(Chapters 3 and 4) take any of them. The materials themselves are in
:mod:`debench.models.materials.library`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from debench.models.invariants import validate_state
from debench.models.materials import energies as E


class Material:
    """The protocol of every library material (module docstring).

    Subclasses provide ``energy_expression`` (and may give ``mechanical_energy`` a form of
    its own), ``energy``, ``response`` and ``shear_modulus``; ``energy_expression`` here
    raises ``NotImplementedError`` naming the class.
    """

    numbering: ClassVar[str] = "iso"
    incompressible: ClassVar[bool] = False

    def _fibre(self):
        return None

    def energy_expression(self, F, D_L, *, xp):
        """``W(F, D_L)`` evaluated by the math namespace ``xp`` (no validation)."""
        raise NotImplementedError(f"{type(self).__name__} has no energy expression")

    def mechanical_energy(self, F, *, xp):
        """``W(F, 0)``, the strain energy, evaluated by the math namespace ``xp`` (by
        default the energy expression at ``D_L = 0``)."""
        return self.energy_expression(F, xp.vector((0.0, 0.0, 0.0)), xp=xp)

    @property
    def bulk_modulus(self) -> float:
        """Initial bulk modulus: infinite for an incompressible material, 0 without one."""
        return math.inf if self.incompressible else 0.0

    def check_admissible(self, F, D_L=None) -> None:
        """Raise ``ValueError`` naming the bound unless ``(F, D_L)`` is a state of this
        material's domain (finite, ``det F > 0``; ``D_L`` None: zero)."""
        validate_state(F, np.zeros(3) if D_L is None else D_L, self._fibre(),
                       numbering=self.numbering)


class IdealDielectricElastomer(Material):
    """A compressible elastic energy plus the ideal dielectric (5.9)::

        W(F, D_L) = mechanical_energy(F) + I5/(2 eps J)

    Subclasses are dataclasses with the fields ``k`` (bulk modulus) and ``eps`` and provide
    ``mechanical_energy``. The Chapter 5 finite-element models accept any of them: they
    assemble ``mechanical_energy`` and the enthalpy of (5.9)
    (:func:`~debench.models.materials.energies.ideal_dielectric_enthalpy`).
    """

    incompressible: ClassVar[bool] = False

    def mechanical_energy(self, F, *, xp):
        raise NotImplementedError(f"{type(self).__name__} has no mechanical energy")

    def energy_expression(self, F, D_L, *, xp):
        I = E.invariants(F, D_L, xp=xp)
        return self.mechanical_energy(F, xp=xp) + E.ideal_dielectric(I["DCD"], I["J"],
                                                                     eps=self.eps)

    @property
    def bulk_modulus(self) -> float:
        return self.k


@dataclass(frozen=True)
class IncompressibleLimit(Material):
    """``material`` constrained to ``J = det F = 1``: its energy, response and moduli,
    marked incompressible, so that a model that imposes ``J = 1`` and adds the pressure
    ``-p I`` of the constraint (2.33) (the Chapter 3 membrane, the Chapter 4 plate) accepts
    any library material, compressible ones included.

    At ``J = 1`` a volumetric energy such as ``k/2 (J - 1)^2`` vanishes with its first
    derivative, and the hydrostatic stress of the isochoric factors ``J^(-2/3)`` is
    absorbed into ``p``; the tangent's volumetric terms act on ``tr L`` only, which the
    constraint sets to zero. So the wrapped energy on the constraint manifold is the
    incompressible limit of ``material`` (a neo-Hookean ``C10 (J^(-2/3) I1 - 3) + ...``
    becomes ``C10 (I1 - 3)``). The admissible states are the wrapped material's.
    """

    material: Material
    incompressible: ClassVar[bool] = True

    def __post_init__(self):
        if not all(callable(getattr(self.material, name, None))
                   for name in ("energy_expression", "response")):
            raise TypeError(f"material must be a library material (with energy_expression "
                            f"and response), got {type(self.material).__name__}")

    @property
    def numbering(self) -> str:
        return self.material.numbering

    def _fibre(self):
        return self.material._fibre()

    def energy_expression(self, F, D_L, *, xp):
        return self.material.energy_expression(F, D_L, xp=xp)

    def mechanical_energy(self, F, *, xp):
        return self.material.mechanical_energy(F, xp=xp)

    def energy(self, F, D_L) -> float:
        return self.material.energy(F, D_L)

    def response(self, F, D_L, *, second: bool = True):
        return self.material.response(F, D_L, second=second)

    @property
    def shear_modulus(self) -> float:
        return self.material.shear_modulus

    def check_admissible(self, F, D_L=None) -> None:
        self.material.check_admissible(F, D_L)
