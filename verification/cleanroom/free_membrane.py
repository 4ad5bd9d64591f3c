"""Clean-room ch3_free_membrane_nh and ch3_free_membrane_gent, written from their
``debench problems ID --markdown`` pages only (numpy; nothing from debench).

The pages: the equibiaxial stress balance s(lam) = Phibar^2 lam^4 at the traction-free
edge, s = lam^2 - lam^-4 (neo-Hookean) or (lam^2 - lam^-4)/(1 - (2 lam^2 + lam^-4 - 3)/Jm)
(Gent); the stretch is prescribed, the voltage is the quantity. Solved here as
a user's code would, by Newton iteration on Phibar^2 from Phibar^2 = 0 (no closed form
used), stopping at a relative step of STEP_RTOL.
"""

from __future__ import annotations

import numpy as np

#: Newton stops when the step in Phibar^2 is below this fraction of Phibar^2: an
#: iterative solver's typical tolerance (the page's rtol 1e-10 is argued for it)
STEP_RTOL = 1e-12
MAX_ITER = 50


def phibar(lam, Jm: float = np.inf, top: float = 5.0) -> np.ndarray:
    """Phibar at each stretch lam in [1, top] (the page's window: 5 neo-Hookean, 7.8 Gent
    with Jm = 120)."""
    lam = np.asarray(lam, dtype=float)
    if np.any(~np.isfinite(lam)) or np.any(lam < 1) or np.any(lam > top):
        raise ValueError(f"lam must lie in [1, {top}]")
    stress = (lam**2 - lam**-4) / (1 - (2 * lam**2 + lam**-4 - 3) / Jm)
    x = np.zeros_like(lam)  # x = Phibar^2
    for _ in range(MAX_ITER):
        r = stress - x * lam**4               # stress residual over mu
        step = r / lam**4                     # Newton: dr/dx = -lam^4
        x = x + step
        if np.all(np.abs(step) <= STEP_RTOL * np.maximum(np.abs(x), 1e-300)):
            break
    else:
        raise RuntimeError(f"Newton did not converge in {MAX_ITER} iterations")
    return np.sqrt(np.maximum(x, 0.0))
