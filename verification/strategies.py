"""Public Hypothesis strategies for the electroelastic kernel (and every chapter).

Import these instead of writing ad-hoc generators, so that the bounds of the physical
states every test explores are stated once::

    from verification.strategies import rotations, isochoric_deformation_gradients
    @given(Q=rotations(), F=isochoric_deformation_gradients())
    def test_energy_is_objective(Q, F): ...

All strategies draw ``numpy.float64`` arrays. Bounds are keyword arguments with physical
meaning (stretches, field magnitudes) so a chapter can narrow them to its regime.

Strategies
----------
rotations
    proper orthogonal 3x3 matrices (det Q = +1), from unit quaternions.
unit_vectors
    unit 3-vectors (fibre directions A of the transversely isotropic model, Ch. 4).
stretches
    scalar stretches within ``[min_stretch, max_stretch]``.
principal_stretches_isochoric
    ``(l1, l2, 1/(l1 l2))`` with in-plane stretches within bounds (det F = 1).
deformation_gradients
    ``F = R diag(l) Q^T`` with principal stretches in bounds and det F > 0
    (compressible models, Ch. 5).
isochoric_deformation_gradients
    the same with det F = 1 exactly up to rounding (incompressible models, Ch. 2-4).
lagrangian_displacements
    Lagrangian electric displacement vectors D_L with ``|D_L| <= max_norm`` (in units the
    caller chooses; the kernel tests use dimensionless sqrt(eps mu) units).
"""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st

__all__ = [
    "finite_floats",
    "rotations",
    "unit_vectors",
    "stretches",
    "principal_stretches_isochoric",
    "deformation_gradients",
    "isochoric_deformation_gradients",
    "lagrangian_displacements",
    "quaternion_to_rotation",
]


def finite_floats(min_value: float, max_value: float) -> st.SearchStrategy[float]:
    """Finite floats in a closed interval (no NaN, no infinities, no subnormals)."""
    return st.floats(min_value=min_value, max_value=max_value, allow_nan=False,
                     allow_infinity=False, allow_subnormal=False)


def quaternion_to_rotation(q: np.ndarray) -> np.ndarray:
    """Rotation matrix of the (normalised) quaternion ``q = (w, x, y, z)``."""
    q = np.asarray(q, dtype=float)
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


@st.composite
def _nonzero_vector(draw, dim: int, lo: float = -1.0, hi: float = 1.0,
                    min_norm: float = 0.1) -> np.ndarray:
    v = np.array(draw(st.lists(finite_floats(lo, hi), min_size=dim, max_size=dim)))
    if np.linalg.norm(v) < min_norm:
        # deterministic, still-reachable fallback instead of a filter (keeps shrinking sane)
        v = v + min_norm * np.eye(dim)[0]
    return v


def rotations() -> st.SearchStrategy[np.ndarray]:
    """Proper rotations Q (Q^T Q = I, det Q = +1), via unit quaternions."""
    return _nonzero_vector(4, min_norm=0.1).map(quaternion_to_rotation)


def unit_vectors() -> st.SearchStrategy[np.ndarray]:
    """Unit 3-vectors (e.g. the fibre direction A of Ch. 4, eq. (4.19))."""
    return _nonzero_vector(3, min_norm=0.1).map(lambda v: v / np.linalg.norm(v))


def stretches(min_stretch: float = 0.6, max_stretch: float = 3.0) -> st.SearchStrategy[float]:
    """Scalar stretches within ``[min_stretch, max_stretch]`` (both > 0)."""
    if not 0.0 < min_stretch <= max_stretch:
        raise ValueError(f"need 0 < min_stretch <= max_stretch, got {min_stretch}, {max_stretch}")
    return finite_floats(min_stretch, max_stretch)


@st.composite
def principal_stretches_isochoric(draw, min_stretch: float = 0.6,
                                  max_stretch: float = 2.5) -> np.ndarray:
    """Principal stretches ``(l1, l2, 1/(l1 l2))`` (det F = 1).

    ``l1``, ``l2`` are drawn within bounds; the third one follows from incompressibility
    (eq. (2.41)) and may lie outside the bounds (e.g. 1/2.5^2 = 0.16).
    """
    l1 = draw(stretches(min_stretch, max_stretch))
    l2 = draw(stretches(min_stretch, max_stretch))
    return np.array([l1, l2, 1.0 / (l1 * l2)])


@st.composite
def deformation_gradients(draw, min_stretch: float = 0.6, max_stretch: float = 2.0,
                          isochoric: bool = False) -> np.ndarray:
    """Deformation gradients ``F = R diag(l) Q^T`` with det F > 0.

    Parameters
    ----------
    min_stretch, max_stretch
        bounds of the drawn principal stretches (the third one is ``1/(l1 l2)`` when
        ``isochoric``).
    isochoric
        if True, det F = 1 (to rounding): the incompressible kinematics of eq. (2.41).
    """
    if isochoric:
        lam = draw(principal_stretches_isochoric(min_stretch, max_stretch))
    else:
        lam = np.array([draw(stretches(min_stretch, max_stretch)) for _ in range(3)])
    R = draw(rotations())
    Q = draw(rotations())
    return R @ np.diag(lam) @ Q.T


def isochoric_deformation_gradients(min_stretch: float = 0.6,
                                    max_stretch: float = 2.0) -> st.SearchStrategy[np.ndarray]:
    """Deformation gradients with det F = 1 (incompressible, eq. (2.41))."""
    return deformation_gradients(min_stretch, max_stretch, isochoric=True)


def lagrangian_displacements(max_norm: float = 1.0) -> st.SearchStrategy[np.ndarray]:
    """Lagrangian electric displacements D_L with components in ``[-max_norm, max_norm]/sqrt 3``.

    Zero is reachable (reference/unpoled state).
    """
    if not max_norm > 0:
        raise ValueError(f"max_norm must be > 0, got {max_norm}")
    c = max_norm / np.sqrt(3.0)
    return st.lists(finite_floats(-c, c), min_size=3, max_size=3).map(np.array)
