"""Parameters of the Chapter 5 buckling-membrane model (thesis Table 5.1, §5.2.3).

Frozen dataclasses, SI units. Every default is either a value the thesis states
(Table 5.1, §5.2.3) or a catalogued assumption (``reference/catalogue/ch5.toml``):

* ``NeoHookean``: mu = 156000 Pa, k = 7748003.92 Pa (Table 5.1), energy (5.15)-(5.17).
* ``Ogden``: alpha = (1.293, 2.3252, 2.561), mu_p = (8580, 84300, -23300) Pa (Table 5.1),
  energy (5.26) read as ``sum 2 mu_p / alpha_p**2 (lam1b**a + lam2b**a + lam3b**a - 3)``
  (the Abaqus convention, consistent with the Kirchhoff stress (5.27)); initial shear
  modulus ``sum(mu_p)`` = 69580 Pa. The bulk modulus is that of the neo-Hookean row
  (Table 5.1 gives one k; assumption ``ch5.assumption.ogden_bulk_modulus``).
* ``Plate``: radius/thickness = 10, t0 = 1 mm or 0.5 mm, imperfection amplitude
  1e-3 t0 (§5.2.3), relative permittivity 4.7 (assumption: not stated in Ch. 5).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from debench.models.errors import require

EPS0 = 8.8541878128e-12  # F/m, vacuum permittivity (CODATA 2018)
MU_REF = 156000.0        # Pa, Table 5.1 shear modulus: the normalising modulus (assumption)
K_TABLE = 7748003.92     # Pa, Table 5.1 bulk modulus


@dataclass(frozen=True)
class NeoHookean:
    """Compressible neo-Hookean mechanical part, Eq. (5.15) with C10 = mu/2, D1 = 2/k."""

    mu: float = MU_REF
    k: float = K_TABLE
    name: str = field(default="nh", init=False)

    def __post_init__(self):
        require(self.mu > 0, f"mu must be > 0, got {self.mu}")
        require(self.k > 0, f"k must be > 0, got {self.k}")

    @property
    def mu0(self) -> float:
        """Initial shear modulus."""
        return self.mu


@dataclass(frozen=True)
class Ogden:
    """Three-term Ogden mechanical part, Eq. (5.26)-(5.27), plus k/2 (J-1)^2.

    ``delta`` is the size of the symmetric spectral perturbation used to evaluate the
    principal stretches without the equal-eigenvalue singularity (see
    :mod:`debench.models.buckling.fem`); the energy error it causes is O(delta**2).
    """

    alphas: tuple[float, ...] = (1.293, 2.3252, 2.561)
    mus: tuple[float, ...] = (8580.0, 84300.0, -23300.0)
    k: float = K_TABLE
    delta: float = 1e-3
    name: str = field(default="ogden", init=False)

    def __post_init__(self):
        require(len(self.alphas) == len(self.mus) and len(self.mus) > 0,
                "alphas and mus must have the same non-zero length")
        require(all(a != 0 for a in self.alphas), "alphas must be non-zero")
        require(self.k > 0, f"k must be > 0, got {self.k}")
        require(self.mu0 > 0, f"initial shear modulus sum(mus) must be > 0, got {self.mu0}")
        require(0 < self.delta < 0.1, f"delta must be in (0, 0.1), got {self.delta}")

    @property
    def mu0(self) -> float:
        """Initial shear modulus ``sum(mu_p)`` (small-strain limit of (5.26))."""
        return float(sum(self.mus))


@dataclass(frozen=True)
class Plate:
    """Clamped circular membrane, §5.2.3: radius = aspect * thickness."""

    thickness: float = 1e-3
    aspect: float = 10.0
    imperfection: float = 1e-3
    eps_r: float = 4.7

    def __post_init__(self):
        require(self.thickness > 0, f"thickness must be > 0, got {self.thickness}")
        require(self.aspect >= 2, f"aspect (radius/thickness) must be >= 2, got {self.aspect}")
        require(0 <= self.imperfection < 0.5,
                f"imperfection (fraction of t0) must be in [0, 0.5), got {self.imperfection}")
        require(self.eps_r >= 1, f"eps_r must be >= 1, got {self.eps_r}")

    @property
    def radius(self) -> float:
        return self.aspect * self.thickness

    @property
    def eps(self) -> float:
        return self.eps_r * EPS0

    def volts(self, v: float, mu_ref: float = MU_REF) -> float:
        """Voltage of the normalised voltage ``v = Phi/t0 sqrt(eps/mu_ref)``."""
        return v * self.thickness * (mu_ref / self.eps) ** 0.5

    def field_V_per_um(self, e_hat: float, mu_ref: float = MU_REF) -> float:
        """True field in V/um of the normalised field ``e = E sqrt(eps/mu_ref)``."""
        return e_hat * (mu_ref / self.eps) ** 0.5 * 1e-6


@dataclass(frozen=True)
class Discretisation:
    """Extruded prism mesh: in-plane size ``h_rel * t0``, ``layers`` through thickness,
    polynomial ``order`` for displacement and potential."""

    h_rel: float = 1.5
    layers: int = 2
    order: int = 2

    def __post_init__(self):
        require(self.h_rel > 0, f"h_rel must be > 0, got {self.h_rel}")
        require(self.layers >= 1, f"layers must be >= 1, got {self.layers}")
        require(self.order >= 1, f"order must be >= 1, got {self.order}")
