"""
Check your own solver: the free neo-Hookean dielectric membrane
===============================================================

A user's own solver, checked against debench (reference problem ``ch3_free_membrane_nh``).

An incompressible neo-Hookean membrane (shear modulus mu, permittivity eps, thickness H),
free at its edge, is stretched equibiaxially by a voltage Phi. Equilibrium of the
homogeneous state: true stress mu (lam^2 - lam^-4) = eps E^2 with E = Phi lam^2 / H.
This script solves it numerically - for each stretch on the reference grid, the voltage
that holds it, by root finding - as your own code would, writes the curve to a CSV file that
``debench check`` reads, and checks it with the Python API.

Run: ``python examples/free_membrane_nh.py [out.csv]``; then
``debench check ch3_free_membrane_nh out.csv``.
"""

import sys

import numpy as np
from scipy.optimize import brentq

MU = 1.0  # stresses and voltages normalised: phibar = sqrt(eps/mu) Phi/H


def residual(phibar, lam):
    """Mechanical minus electrical true stress over mu, equibiaxial state."""
    return MU * (lam**2 - lam**-4) - phibar**2 * lam**4


def voltage(lam):
    """The voltage that holds the stretch lam (the residual falls from >= 0 at phibar = 0
    to < 0 at phibar = 1 for every lam >= 1)."""
    return brentq(residual, 0.0, 1.0, args=(lam,), xtol=1e-15, rtol=1e-15)


lam = np.linspace(1.0, 5.0, 401)  # the stretch is the coordinate: the reference grid
phibar = np.array([voltage(x) for x in lam])  # the voltage is the quantity

if __name__ == "__main__":
    from debench.testing import assert_matches

    result = assert_matches("ch3_free_membrane_nh", "phibar", phibar, {"lam": lam})
    print(result.summary())
    if len(sys.argv) > 1:
        np.savetxt(sys.argv[1], np.column_stack([lam, phibar]), delimiter=",",
                   header="lam [1],phibar [1]", comments="", fmt="%.17g")
        print(f"wrote {sys.argv[1]}")
