"""A user's own solver, checked against debench: the free neo-Hookean dielectric membrane.

An incompressible neo-Hookean membrane (shear modulus mu, permittivity eps, thickness H),
free at its edge, is stretched equibiaxially by a voltage Phi. Equilibrium of the
homogeneous state: true stress mu (lam^2 - lam^-4) = eps E^2 with E = Phi lam^2 / H.
This script solves it numerically - for each voltage, the stretch on the stable branch
by root finding - as your own code would, writes the curve to a CSV file that
``debench check`` reads, and checks it with the Python API.

Run: ``python examples/free_membrane_nh.py [out.csv]``; then
``debench check ch3_free_membrane_nh out.csv``.
"""

import sys

import numpy as np
from scipy.optimize import brentq

MU = 1.0  # stresses and voltages normalised: phibar = sqrt(eps/mu) Phi/H


def residual(lam, phibar):
    """Mechanical minus electrical true stress over mu, equibiaxial state."""
    return MU * (lam**2 - lam**-4) - phibar**2 * lam**4


def stretch(phibar):
    """Stretch on the stable branch (below the pull-in stretch 2^(1/3))."""
    return brentq(residual, 1.0, 2.0 ** (1 / 3), args=(phibar,), xtol=1e-15, rtol=1e-15)


phibar = np.linspace(0.05, 0.68, 30)
lam = np.array([stretch(p) for p in phibar])

if __name__ == "__main__":
    from debench.testing import assert_matches

    result = assert_matches("ch3_free_membrane_nh", "phibar", phibar, {"lam": lam})
    print(result.summary())
    if len(sys.argv) > 1:
        np.savetxt(sys.argv[1], np.column_stack([lam, phibar]), delimiter=",",
                   header="lam [1],phibar [1]", comments="", fmt="%.17g")
        print(f"wrote {sys.argv[1]}")
