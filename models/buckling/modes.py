"""Mode diagnostics of the Chapter 5 finite-element model
(:class:`~debench.models.buckling.fem.MembraneModel`): the displacement of a mode or of
the state on the mid-plane circle r = a/2 and its angular harmonics (how axisymmetric a
buckling mode is, which wavenumber a wrinkling deflection has).
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np
from debench.models import validation as val
from debench.models.buckling.fem import MembraneModel


def ring_displacement(model: MembraneModel, vec: np.ndarray | None = None,
                      n_theta: int = 24) -> np.ndarray:
    """Cylindrical displacement components (u_r, u_theta, u_z), shape (n_theta, 3), at
    ``n_theta`` equally spaced points of the mid-plane circle r = a/2 of the reference
    geometry: of the vector ``vec`` of the compound space (a mode), or of the current state
    (``vec=None``)."""
    n_theta = val.integer_at_least("n_theta", n_theta, 4)
    if vec is None:
        gu = model.gf.components[0]
    else:
        gf = ngs.GridFunction(model.X)
        gf.vec.FV().NumPy()[:] = vec
        gu = gf.components[0]
    r, t0 = 0.5 * model.plate.radius, model.plate.thickness
    comps = []
    for th in np.linspace(0, 2 * np.pi, n_theta, endpoint=False):
        x, y = r * np.cos(th), r * np.sin(th)
        ux, uy, uz = gu(model._point(x, y, 0.5 * t0 + model.lift(x, y)))
        comps.append((ux * np.cos(th) + uy * np.sin(th), -ux * np.sin(th) + uy * np.cos(th), uz))
    return np.array(comps)


def _harmonic_power(samples: np.ndarray) -> np.ndarray:
    """Power of the angular harmonics n = 0 .. n_theta/2 of ring samples (n_theta, k)
    (discrete Parseval, the +n and -n terms added), summed over the k components."""
    n_theta = samples.shape[0]
    c = np.fft.fft(samples, axis=0) / n_theta                 # (harmonic, component)
    power = np.sum(np.abs(c) ** 2, axis=1)
    half = n_theta // 2
    out = np.zeros(half + 1)
    out[0] = power[0]
    for n in range(1, half + 1):
        out[n] = power[n] + (power[n_theta - n] if n_theta - n != n else 0.0)
    return out


def mode_harmonics(model: MembraneModel, mode: np.ndarray, n_theta: int = 24) -> np.ndarray:
    """Fractions of a mode's displacement in the angular harmonics n = 0 .. n_theta/2.

    The mode's cylindrical components (u_r, u_theta, u_z) are sampled at ``n_theta``
    equally spaced points of the mid-plane circle r = a/2 (:func:`ring_displacement`) and
    Fourier-analysed (discrete Parseval): entry n is
    ``sum_c (|c_n|^2 + |c_-n|^2) / mean_theta sum_c |u_c|^2``, so the entries sum to 1;
    entry 0 is 1 for an axisymmetric mode, a wrinkling mode of angular wavenumber n has
    its weight at n (resolved for n < n_theta/2).
    """
    power = _harmonic_power(ring_displacement(model, mode, n_theta))
    total = float(np.sum(power))
    if total == 0:
        raise ValueError("mode is zero on the sampling circle")
    return power / total


def deflection_asymmetry(model: MembraneModel, n_theta: int = 24) -> tuple[float, int]:
    """Non-axisymmetric part of the current deflection: the amplitude / t0 of the largest
    angular harmonic n >= 1 of u_z on the mid-plane circle r = a/2 (the peak of its
    cos(n theta - phase) term, 2 |c_n|; resolved for n < n_theta/2) and that n. Zero on an
    axisymmetric state; it grows from the seed of a non-axisymmetric imperfection as the
    film follows a wrinkling mode."""
    uz = ring_displacement(model, None, n_theta)[:, 2:]
    amp = np.sqrt(_harmonic_power(uz))                       # |c_n|, +n and -n together
    amp[1:] *= np.sqrt(2.0)                                  # peak of a real cos(n theta)
    n = 1 + int(np.argmax(amp[1:n_theta // 2]))
    return float(amp[n]) / model.plate.thickness, n


def mode_axisymmetry(model: MembraneModel, mode: np.ndarray, n_theta: int = 24) -> float:
    """Fraction of a mode's displacement in the angular harmonic n = 0 (1 for an
    axisymmetric mode, 0 for a pure n >= 1 wrinkling mode): :func:`mode_harmonics`."""
    return float(mode_harmonics(model, mode, n_theta)[0])
