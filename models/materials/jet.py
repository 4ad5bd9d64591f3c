"""Second-order forward differentiation of a library energy: its stress and moduli from the
one expression.

A :class:`Jet` carries a value with its gradient and Hessian in ``n`` independent
variables; arithmetic, ``**`` and ``log1p`` propagate them exactly (to rounding). The math
namespace :data:`JET` evaluates a material's
:meth:`~debench.models.materials.protocol.Material.energy_expression` on 3x3 object arrays
of jets (``det`` and ``inv`` by cofactors: numpy's LAPACK routines take no objects), so
:func:`expression_response` gets ``W``, ``P = dW/dF``, ``E_L = dW/dD_L`` and the moduli
``AA``, ``AAA``, ``A`` (2.65)-(2.67) from the expression itself, with the 12 variables
``(F_ia, D_La)``: no derivative is written by hand. The hand-written invariant derivatives
of the library (``invariant_derivatives`` and the chain rule of
:mod:`debench.models.materials.kernel`) are the independent check of the tests.

Principal-stretch energies (Ogden (5.26)) need eigenvalues, which jets do not have: their
``spectral`` raises, and they keep the spectral formula of the kernel.
"""

from __future__ import annotations

import numpy as np
from debench.models.materials.energies import MathNamespace
from debench.models.materials.kernel import Response

#: independent variables of a response: F_ia (9, row-major) then D_La (3)
NVAR = 12


class JetOperators:
    """The operators a jet class derives from its own ``+``, unary ``-``, ``*`` and
    ``_chain(f, f', f'')``: subtraction, division of a number by a jet and a number power."""

    __slots__ = ()

    def __sub__(self, other):
        return self + (-other)

    def __rsub__(self, other):
        return (-self) + other

    def __rtruediv__(self, other):
        return self ** -1 * other

    def __pow__(self, p):
        if isinstance(p, JetOperators):
            name = type(self).__name__
            raise TypeError(f"{name} ** {name} is not supported")
        v = self.v
        return self._chain(v ** p, p * v ** (p - 1), p * (p - 1) * v ** (p - 2))


class Jet(JetOperators):
    """``v`` with gradient ``g`` (n,) and Hessian ``h`` (n, n) (None: first order only)."""

    __slots__ = ("v", "g", "h")
    #: numpy scalars defer to the jet's reflected operators (``2.0 * jet``)
    __array_ufunc__ = None

    def __init__(self, v, g, h=None):
        self.v, self.g, self.h = v, g, h

    def _each(self, other, op):
        """``op(self, x)`` for every element ``x`` of the array ``other``."""
        out = np.empty(other.shape, dtype=object)
        for k, x in np.ndenumerate(other):
            out[k] = op(self, x)
        return out

    def __add__(self, other):
        if isinstance(other, np.ndarray):
            return self._each(other, Jet.__add__)
        if not isinstance(other, Jet):
            return Jet(self.v + other, self.g, self.h)
        return Jet(self.v + other.v, self.g + other.g, _sum(self.h, other.h))

    __radd__ = __add__

    def __neg__(self):
        return Jet(-self.v, -self.g, None if self.h is None else -self.h)

    def __mul__(self, other):
        if isinstance(other, np.ndarray):
            return self._each(other, Jet.__mul__)
        if not isinstance(other, Jet):
            return Jet(self.v * other, self.g * other, None if self.h is None else self.h * other)
        h = None
        if self.h is not None:
            cross = np.outer(self.g, other.g)
            h = self.h * other.v + other.h * self.v + cross + cross.T
        return Jet(self.v * other.v, self.g * other.v + other.g * self.v, h)

    __rmul__ = __mul__

    def _chain(self, f0, f1, f2) -> Jet:
        """``f(self)`` from ``f``, ``f'``, ``f''`` at ``self.v``."""
        h = None if self.h is None else f1 * self.h + f2 * np.outer(self.g, self.g)
        return Jet(f0, f1 * self.g, h)

    def __truediv__(self, other):
        if isinstance(other, np.ndarray):
            return self._each(other, Jet.__truediv__)
        if not isinstance(other, Jet):
            return self * (1.0 / other)
        return self * other ** -1



def _sum(a, b):
    return None if a is None or b is None else a + b


def log1p(x):
    """``log(1 + x)`` of a jet or a number."""
    if not isinstance(x, Jet):
        return np.log1p(x)
    u = 1.0 + x.v
    return x._chain(np.log1p(x.v), 1.0 / u, -1.0 / (u * u))


def _det(M):
    return (M[0, 0] * (M[1, 1] * M[2, 2] - M[1, 2] * M[2, 1])
            - M[0, 1] * (M[1, 0] * M[2, 2] - M[1, 2] * M[2, 0])
            + M[0, 2] * (M[1, 0] * M[2, 1] - M[1, 1] * M[2, 0]))


def _inv(M):
    cof = np.empty((3, 3), dtype=object)
    for i in range(3):
        for j in range(3):
            r = [k for k in range(3) if k != i]
            c = [k for k in range(3) if k != j]
            minor = M[r[0], c[0]] * M[r[1], c[1]] - M[r[0], c[1]] * M[r[1], c[0]]
            cof[j, i] = minor if (i + j) % 2 == 0 else -minor
    return cof / _det(M)


def _no_spectral(M, energy):
    raise NotImplementedError("the jet namespace has no eigenvalues: principal-stretch "
                              "energies use the spectral formula of the kernel")


JET = MathNamespace(
    name="jet", det=_det, trace=lambda M: M[0, 0] + M[1, 1] + M[2, 2], inv=_inv,
    transpose=np.transpose, matmul=lambda A, B: np.dot(A, B),
    inner=lambda a, b: np.sum(np.asarray(a) * np.asarray(b)), log1p=log1p,
    vector=lambda values: np.asarray(values, dtype=float), spectral=_no_spectral)
"""The namespace of object arrays of :class:`Jet` (module docstring)."""


def _seed(values, offset: int, second: bool) -> np.ndarray:
    eye = np.eye(NVAR)
    zero = np.zeros((NVAR, NVAR)) if second else None
    flat = [Jet(float(x), eye[offset + k], zero) for k, x in enumerate(np.ravel(values))]
    return np.array(flat, dtype=object).reshape(np.shape(values))


def expression_response(material, F, D_L, *, second: bool = True) -> Response:
    """``W`` and its first (and with ``second`` second) derivatives in ``(F, D_L)`` from
    ``material.energy_expression`` evaluated on jets (no validation: the caller checks the
    state). ``P[i, a] = dW/dF_ia``, ``AA[i, a, j, b] = d2W/dF_ia dF_jb`` and so on, as
    :class:`~debench.models.materials.kernel.Response`."""
    W = material.energy_expression(_seed(F, 0, second), _seed(D_L, 9, second), xp=JET)
    if not isinstance(W, Jet):          # an energy independent of (F, D_L)
        W = Jet(float(W), np.zeros(NVAR), np.zeros((NVAR, NVAR)) if second else None)
    g = np.asarray(W.g, dtype=float)
    P, E_L = g[:9].reshape(3, 3), g[9:]
    if not second:
        return Response(float(W.v), P, E_L, np.zeros((3, 3, 3, 3)), np.zeros((3, 3, 3)),
                        np.zeros((3, 3)))
    h = np.asarray(W.h, dtype=float)
    return Response(float(W.v), P, E_L, h[:9, :9].reshape(3, 3, 3, 3),
                    h[:9, 9:].reshape(3, 3, 3), h[9:, 9:])
