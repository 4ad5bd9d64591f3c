"""
A Gent membrane: the pull-in, and how far each point is from the reference
==========================================================================

A free equibiaxial Gent ideal-dielectric membrane (locking parameter Jm = 120, the
Chapter 3 elastomer) solved as your own code would: for each stretch, the voltage that
balances the stresses, by root finding. Strain stiffening gives the voltage a local
maximum (pull-in) and a local minimum. :func:`~debench.reference.comparison.compare` then puts every
point beside the reference problem ``ch3_free_membrane_gent`` and its stated accuracy.
"""

import matplotlib.pyplot as plt
import numpy as np
from scipy.optimize import brentq

from debench.testing import compare

JM = 120.0  # Gent locking parameter; stresses over mu, voltages phibar = sqrt(eps/mu) Phi/H


def residual(phibar, lam):
    """Mechanical minus electrical true stress over mu (incompressible, equibiaxial)."""
    mech = (lam**2 - lam**-4) / (1.0 - (2 * lam**2 + lam**-4 - 3) / JM)
    return mech - phibar**2 * lam**4


lam = np.linspace(1.0, 7.8, 401)  # the reference grid of the problem
phibar = np.array([brentq(residual, 0.0, 2.0, args=(x,), xtol=1e-15, rtol=1e-15)
                   for x in lam])

result = compare("ch3_free_membrane_gent", "phibar", phibar, {"lam": lam})
print(result.summary())

# %%
# The curve and its pull-in (the local maximum of the voltage, here at the best grid
# point):
i = int(np.argmax(phibar[lam < 3]))
fig, ax = plt.subplots(figsize=(6, 4), layout="constrained")
ax.plot(lam, phibar, label="your solver")
ax.plot(lam[i], phibar[i], "o",
        label=f"pull-in (grid): lam = {lam[i]:.3f}, phibar = {phibar[i]:.4f}")
ax.set_xlabel("equibiaxial stretch lam")
ax.set_ylabel("normalised voltage phibar")
ax.legend()
plt.show()

# %%
# Each point's error over the tolerance the check applies (a point fails above 1):
fig, ax = plt.subplots(figsize=(6, 4), layout="constrained")
ax.semilogy(lam, np.maximum(result.ratio, 1e-18))
ax.axhline(1.0, color="crimson", ls="--", label="fails above")
ax.set_xlabel("equibiaxial stretch lam")
ax.set_ylabel("|error| / tolerance")
ax.legend()
plt.show()
