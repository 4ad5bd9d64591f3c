r"""Manufactured solution for code verification of compressible nonlinear electro-elasticity.

The model (normalised: stresses by the shear modulus ``mu``, lengths by the domain size
``L``, the potential by ``L sqrt(mu/eps)``, so that ``mu = eps = L = 1``) is the
Chapter 5 electric enthalpy (the partial Legendre transform of the ideal dielectric (5.9),
as in :func:`debench.models.materials.energies.ideal_dielectric_enthalpy`)

.. math::

    \Omega(F, E_L) = W(F) - \tfrac12 J\, C^{-1} : (E_L \otimes E_L), \qquad E_L = -\nabla\phi,

with the compressible neo-Hookean (5.15)-(5.17) ``W = 1/2 (J^(-2/3) I1 - 3) + kappa/2
(J - 1)^2`` or its Gent variant ``W = -Jm/2 log(1 - (J^(-2/3) I1 - 3)/Jm) + kappa/2
(J - 1)^2`` (``kappa = k/mu``). The equations ``Div P + b = 0`` (``P = dOmega/dF``) and
``Div D_L = q`` (``D_L = -dOmega/dE_L = J C^-1 E_L``) hold with the body force ``b`` and
the free charge ``q`` derived by sympy (``tools/derive_mms.py``) from the manufactured

* plane strain, unit square (X, Y)::

      u_X = sin(pi X) cos(pi Y)/20,  u_Y = (cos(pi X/2) sin(pi Y) + X^2 Y)/20,
      phi = (sin(pi X) sin(pi Y) + X + Y/2)/10

* axisymmetric, (R, Z) in [0, 1]^2 including the axis (u_R odd in R, u_Z and phi even;
  components in the cylindrical basis, ``F_TT = 1 + u_R/R``)::

      u_R = R cos(pi R/2) cos(pi Z)/20,  u_Z = (cos(pi R) sin(pi Z) + R^2 Z)/20,
      phi = (cos(pi R) sin(pi Z) + Z + R^2/2)/10

* 3D, unit cube (X, Y, Z)::

      u_X = sin(pi X) cos(pi Y) cos(pi Z/2)/20,
      u_Y = (cos(pi X/2) sin(pi Y) cos(pi Z) + X^2 Y)/20,
      u_Z = (cos(pi X) cos(pi Y/2) sin(pi Z) + Y Z^2)/20,
      phi = (sin(pi X) sin(pi Y) sin(pi Z) + X + Y/2 + Z/3)/10

On the whole boundary ``u`` and ``phi`` are prescribed by their exact values (non-zero
data). ``J`` stays within [0.71, 1.55] (plane strain [0.71, 1.34]; see
:meth:`ManufacturedSolution.jacobian_range`).

Examples
--------
>>> import numpy as np
>>> from debench.models.mms import ManufacturedSolution
>>> s = ManufacturedSolution("plane_strain", "neo_hookean", kappa=10.0)
>>> f = s.evaluate(np.array([0.3]), np.array([0.6]))
>>> sorted(f)
['J', 'b', 'grad_phi', 'grad_u', 'phi', 'q', 'u']
>>> s.formulas("python")["u"][0]
'sin(pi*X)*cos(pi*Y)/20'
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from debench.models import mms_generated
from debench.models import validation as val

GEOMETRIES = ("plane_strain", "axisymmetric", "three_d")
MATERIALS = ("neo_hookean", "gent")
LANGUAGES = ("python", "c")
DOMAINS = {"plane_strain": ((0.0, 1.0), (0.0, 1.0)),
           "axisymmetric": ((0.0, 1.0), (0.0, 1.0)),
           "three_d": ((0.0, 1.0), (0.0, 1.0), (0.0, 1.0))}
"""The domain of each geometry, per coordinate (the fields are defined everywhere; the
stated problem is posed here)."""
DOMAIN_SLACK = 1e-12
"""Coordinates may leave the domain by this much (round-off of mapped quadrature points)."""


@dataclass(frozen=True)
class ManufacturedSolution:
    """The manufactured solution of one geometry and material (module docstring).

    Parameters
    ----------
    geometry : {"plane_strain", "axisymmetric", "three_d"}
    material : {"neo_hookean", "gent"}
    kappa : float
        Bulk-to-shear modulus ratio ``k/mu`` (> 0), e.g. 10.
    Jm : float
        Gent locking parameter (> 0; used by ``material = "gent"`` only), e.g. 50.
    """

    geometry: str = "plane_strain"
    material: str = "neo_hookean"
    kappa: float = 10.0
    Jm: float = 50.0

    def __post_init__(self):
        val.choice("geometry", self.geometry, GEOMETRIES)
        val.choice("material", self.material, MATERIALS)
        object.__setattr__(self, "kappa", val.positive("kappa", self.kappa))
        object.__setattr__(self, "Jm", val.positive("Jm", self.Jm))

    @property
    def coordinates(self) -> tuple[str, ...]:
        """Coordinate names: ("X", "Y"), ("R", "Z") or ("X", "Y", "Z")."""
        return tuple(mms_generated.FORMULAS[self.name]["coordinates"])

    @property
    def name(self) -> str:
        return f"{self.geometry}_{self.material}"

    @property
    def dim(self) -> int:
        return len(DOMAINS[self.geometry])

    def _params(self) -> dict:
        return {"kappa": self.kappa} | ({"Jm": self.Jm} if self.material == "gent" else {})

    def evaluate(self, *coords, ns=None) -> dict:
        """Exact ``u``, ``phi``, ``grad_u``, ``grad_phi``, ``J`` and the data ``b``, ``q``.

        With numpy (``ns=None``) the coordinates are arrays (broadcast together) inside
        :data:`DOMAINS`, and ``R > 0`` in the axisymmetric case (``b`` and ``q`` contain
        ``1/R``; their limits on the axis are finite but not evaluated). Vector entries are
        lists over components (``grad_u[i][j] = d u_i / d x_j``) of arrays of the
        broadcast shape. With ``ns=ngsolve`` the coordinates are CoefficientFunctions
        (``ngsolve.x, ngsolve.y[, ngsolve.z]``) and so is every entry.
        """
        if len(coords) != self.dim:
            raise ValueError(f"{self.geometry} takes {self.dim} coordinates "
                             f"{self.coordinates}, got {len(coords)}")
        if ns is None:
            cs = []
            for name, c, (lo, hi) in zip(self.coordinates, coords, DOMAINS[self.geometry],
                                         strict=True):
                c = np.asarray(val.finite(name, c), dtype=float)
                if np.any(c < lo - DOMAIN_SLACK) or np.any(c > hi + DOMAIN_SLACK):
                    raise ValueError(f"{name} must lie in [{lo}, {hi}], got values in "
                                     f"[{c.min():.6g}, {c.max():.6g}]")
                cs.append(c)
            if self.geometry == "axisymmetric" and np.any(cs[0] <= 0):
                raise ValueError("R must be > 0 (b and q contain 1/R), got min R = "
                                 f"{cs[0].min():.6g}")
            shape = np.broadcast(*cs).shape
            raw = getattr(mms_generated, self.name)(*cs, ns=np, **self._params())

            def full(v):
                if isinstance(v, list):
                    return [full(w) for w in v]
                return np.broadcast_to(np.asarray(v, dtype=float), shape).copy()

            return {k: full(v) for k, v in raw.items()}
        return getattr(mms_generated, self.name)(*coords, ns=ns, **self._params())

    def formulas(self, language: str = "python") -> dict:
        """The formula strings (``assignments`` first, then ``u``, ``phi``, ``grad_u``,
        ``grad_phi``, ``J``, ``b``, ``q``) in ``language`` ("python": UFL, NGSolve,
        numpy with ``sin``, ``cos``, ``pi`` in scope; "c": C99), in the coordinates
        :attr:`coordinates` and the parameters ``kappa`` (and ``Jm``)."""
        val.choice("language", language, LANGUAGES)
        return mms_generated.FORMULAS[self.name][language]

    def jacobian_range(self, n: int = 81) -> tuple[float, float]:
        """(min, max) of ``J = det F`` on an ``n``-point-per-direction grid of the domain
        (the axis excluded: the grid starts at R = 1/(2n))."""
        n = val.integer_at_least("n", n, 2)
        axes = []
        for k, (lo, hi) in enumerate(DOMAINS[self.geometry]):
            if self.geometry == "axisymmetric" and k == 0:
                axes.append(np.linspace(lo + (hi - lo) / (2 * n), hi, n))
            else:
                axes.append(np.linspace(lo, hi, n))
        grid = np.meshgrid(*axes, indexing="ij")
        J = self.evaluate(*grid)["J"]
        return float(J.min()), float(J.max())

    def gent_argument_max(self, n: int = 81) -> float:
        """max of ``(J^(-2/3) I1 - 3)/Jm`` on the grid of :meth:`jacobian_range` (the Gent
        energy needs < 1)."""
        n = val.integer_at_least("n", n, 2)
        grid = np.meshgrid(*[np.linspace(lo + 1e-3, hi, n)
                             for lo, hi in DOMAINS[self.geometry]], indexing="ij")
        f = self.evaluate(*grid)
        d = self.dim
        G = np.array(f["grad_u"])
        F = np.zeros((3, 3) + grid[0].shape)
        for i in range(3):
            F[i, i] = 1.0
        if self.geometry == "axisymmetric":
            F[0, 0] += G[0, 0]
            F[0, 2] = G[0, 1]
            F[1, 1] += f["u"][0] / grid[0]
            F[2, 0] = G[1, 0]
            F[2, 2] += G[1, 1]
        else:
            F[:d, :d] += G
        I1 = np.sum(F**2, axis=(0, 1))
        return float(np.max((f["J"] ** (-2 / 3) * I1 - 3) / self.Jm))

