"""Validation at the public boundary: one set of helpers, used by every model.

Each helper checks one argument and returns it converted (a ``float``, an ``int`` or a
numpy array), or raises

* ``TypeError`` when the argument is not of a usable type (a string where a number is
  expected, an object of the wrong class), and
* ``ValueError`` when it is of the right type but violates a bound (NaN, inf, a
  non-positive modulus, a stretch past the Gent lock, ``det F <= 0``, a zero iteration
  count, a non-finite tolerance).

Messages name the argument, its value and the violated bound, e.g.
``ValueError: lamP = 12 is past the Gent locking stretch 7.84 (Jm = 120)`` or
``ValueError: xtol must be a finite tolerance in (0, 1), got inf``.

Public functions and parameter dataclasses call these once, on entry (``__post_init__``
for dataclasses); private kernels are not re-validated. Arrays may be complex (the
complex-step derivatives of the models pass through public functions): finiteness is
checked on the whole value, order bounds on the real part.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import numbers

import numpy as np

__all__ = [
    "array", "at_least", "choice", "deformation_gradient", "finite", "finite_result",
    "in_range",
    "instance", "integer_at_least", "nonnegative", "positive", "tolerance", "unit_vector",
    "vector", "window",
]


def _show(x) -> str:
    """Short text of a value for a message (arrays by their extreme entries)."""
    if isinstance(x, np.ndarray) and x.size == 1 and x.dtype.kind in "fiu":
        return f"{float(x.ravel()[0]):.6g}"
    if isinstance(x, np.ndarray) and x.size > 1:
        with np.errstate(all="ignore"):
            r = np.real(x)
            if np.all(np.isnan(r)):
                return f"array of shape {x.shape} (all NaN)"
            return (f"array of shape {x.shape} with min {np.nanmin(r):.6g}, "
                    f"max {np.nanmax(r):.6g}")
    if isinstance(x, float | np.floating):
        return f"{float(x):.6g}"
    return repr(x)


def _numeric(name: str, x, *, complex_ok: bool):
    """``x`` as a float (scalar) or a numpy array; TypeError if it is not numeric."""
    if isinstance(x, bool | np.bool_) or x is None or isinstance(x, str | bytes):
        raise TypeError(f"{name} must be a real number or array, got {x!r}")
    if isinstance(x, numbers.Real):
        return float(x)
    if isinstance(x, numbers.Complex) and complex_ok:
        return complex(x)
    try:
        a = np.asarray(x)
    except (ValueError, TypeError) as exc:  # ragged nested sequences
        raise TypeError(f"{name} must be a real number or array, got {x!r}") from exc
    kinds = "biufc" if complex_ok else "biuf"
    if a.dtype.kind not in kinds or a.dtype.kind == "b":
        raise TypeError(f"{name} must be a real number or array, got {x!r}")
    if a.dtype.kind in "iu":
        a = a.astype(float)
    return a


def finite(name: str, x, *, complex_ok: bool = False):
    """``x`` (number or array) with every entry finite: no NaN, no +-inf."""
    v = _numeric(name, x, complex_ok=complex_ok)
    if not np.all(np.isfinite(v)):
        raise ValueError(f"{name} must be finite (no NaN or inf), got {_show(v)}")
    return v


def _real(v):
    return np.real(v) if isinstance(v, np.ndarray) or isinstance(v, complex) else v


def positive(name: str, x, *, complex_ok: bool = False):
    """``x`` finite and ``> 0`` (every entry of an array)."""
    v = finite(name, x, complex_ok=complex_ok)
    if not np.all(_real(v) > 0):
        raise ValueError(f"{name} must be > 0, got {_show(v)}")
    return v


def nonnegative(name: str, x, *, complex_ok: bool = False):
    """``x`` finite and ``>= 0``."""
    v = finite(name, x, complex_ok=complex_ok)
    if not np.all(_real(v) >= 0):
        raise ValueError(f"{name} must be >= 0, got {_show(v)}")
    return v


def at_least(name: str, x, lo: float, *, complex_ok: bool = False):
    """``x`` finite and ``>= lo``."""
    v = finite(name, x, complex_ok=complex_ok)
    if not np.all(_real(v) >= lo):
        raise ValueError(f"{name} must be >= {lo:.6g}, got {_show(v)}")
    return v


def in_range(name: str, x, lo: float, hi: float, *, lo_open: bool = False,
             hi_open: bool = False, bound: str | None = None, complex_ok: bool = False):
    """``x`` finite and inside ``[lo, hi]`` (``(`` / ``)`` where open).

    ``bound`` replaces the generic interval text in the message when a physical
    statement is clearer (e.g. ``"past the Gent locking stretch 7.84 (Jm = 120)"``); it
    is used only when the upper bound is violated.
    """
    v = finite(name, x, complex_ok=complex_ok)
    r = _real(v)
    low_ok = np.all(r > lo) if lo_open else np.all(r >= lo)
    high_ok = np.all(r < hi) if hi_open else np.all(r <= hi)
    if not (low_ok and high_ok):
        if bound is not None and low_ok:
            raise ValueError(f"{name} = {_show(v)} is {bound}")
        interval = f"{'(' if lo_open else '['}{lo:.6g}, {hi:.6g}{')' if hi_open else ']'}"
        raise ValueError(f"{name} must lie in {interval}, got {_show(v)}")
    return v


def integer_at_least(name: str, n, k: int) -> int:
    """``n`` an integer (int or integral numpy integer, not bool) with ``n >= k``."""
    if isinstance(n, bool | np.bool_) or not isinstance(n, numbers.Integral):
        if isinstance(n, numbers.Real) and not isinstance(n, bool):
            raise ValueError(f"{name} must be an integer >= {k}, got {_show(n)}")
        raise TypeError(f"{name} must be an integer, got {n!r}")
    if n < k:
        raise ValueError(f"{name} must be an integer >= {k}, got {n}")
    return int(n)


def tolerance(name: str, tol, *, upper: float = 1.0) -> float:
    """A solver tolerance: a finite number in ``(0, upper)``.

    A non-finite or huge tolerance would let a solver stop after one step and return an
    unconverged value; a zero or negative one can never be met.
    """
    v = finite(name, tol)
    if not isinstance(v, float):
        raise TypeError(f"{name} must be a number, got {tol!r}")
    if not (0 < v < upper):
        raise ValueError(f"{name} must be a finite tolerance in (0, {upper:g}), got {_show(v)}")
    return v


def choice(name: str, value, options) -> str:
    """``value`` one of ``options``."""
    if not isinstance(value, str) or value not in options:
        raise ValueError(f"{name} must be one of {tuple(options)}, got {value!r}")
    return value


def instance(name: str, value, cls):
    """``value`` an instance of ``cls`` (a class or a tuple of classes)."""
    if not isinstance(value, cls):
        names = (cls.__name__ if isinstance(cls, type)
                 else " or ".join(c.__name__ for c in cls))
        raise TypeError(f"{name} must be a {names}, got {type(value).__name__} {value!r:.60}")
    return value


def array(name: str, x, shape: tuple[int, ...] | None = None, *, complex_ok: bool = False):
    """A finite numpy array (of ``shape`` if given)."""
    v = _numeric(name, x, complex_ok=complex_ok)
    v = np.asarray(v)
    if shape is not None and v.shape != shape:
        raise ValueError(f"{name} must have shape {shape}, got {v.shape}")
    if not np.all(np.isfinite(v)):
        raise ValueError(f"{name} must be finite (no NaN or inf), got {_show(v)}")
    return v


def vector(name: str, v, size: int = 3, *, complex_ok: bool = False) -> np.ndarray:
    """A finite vector of ``size`` entries."""
    return array(name, v, (size,), complex_ok=complex_ok)


def unit_vector(name: str, v, *, rtol: float = 1e-12) -> np.ndarray:
    """A finite real 3-vector of unit length (to ``rtol``)."""
    a = vector(name, v)
    norm = float(np.linalg.norm(a))
    if abs(norm - 1.0) > rtol:
        raise ValueError(f"{name} must be a unit 3-vector, got |{name}| = {norm:.15g}")
    return a


def deformation_gradient(name: str, F, *, complex_ok: bool = False) -> np.ndarray:
    """A finite (3, 3) deformation gradient with a finite ``det F > 0``.

    ``det F`` is evaluated on the real part (complex-step perturbations are allowed with
    ``complex_ok``). A determinant that overflows or underflows (entries ~1e300 or
    ~1e-300) is rejected: no energy of the library is representable there.
    """
    a = array(name, F, (3, 3), complex_ok=complex_ok)
    det = float(np.linalg.det(np.real(a)))
    if not (math.isfinite(det) and det > 0):
        raise ValueError(f"det {name} must be > 0 and finite, got {det:.6g} "
                         f"(an inverted, degenerate or overflowing deformation)")
    return a


def window(name: str, w, *, lo: float = 0.0) -> tuple[float, float]:
    """A scan window ``(a, b)`` with ``lo < a < b`` both finite."""
    if isinstance(w, str | bytes) or w is None:
        raise TypeError(f"{name} must be a pair (a, b), got {w!r}")
    try:
        a, b = w
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be a pair (a, b), got {w!r}") from exc
    a = finite(f"{name}[0]", a)
    b = finite(f"{name}[1]", b)
    if not isinstance(a, float) or not isinstance(b, float):
        raise TypeError(f"{name} must be a pair of numbers, got {w!r}")
    if not (lo < a < b):
        raise ValueError(f"{name} = (a, b) must satisfy {lo:g} < a < b, got ({a:.6g}, {b:.6g})")
    return a, b


def _all_finite(x, depth: int = 0) -> bool:
    if depth > 4 or x is None or isinstance(x, str | bytes | bool | type):
        return True
    if isinstance(x, numbers.Number):
        return bool(np.isfinite(x))
    if isinstance(x, np.ndarray):
        return x.dtype.kind not in "fc" or bool(np.all(np.isfinite(x)))
    if isinstance(x, dict):
        return all(_all_finite(y, depth + 1) for y in x.values())
    if isinstance(x, list | tuple):
        return all(_all_finite(y, depth + 1) for y in x)
    if dataclasses.is_dataclass(x):
        return all(_all_finite(getattr(x, f.name), depth + 1) for f in dataclasses.fields(x))
    return True


def finite_result(func):
    """Decorator for a public function whose every returned number must be finite.

    Arguments that pass the entry checks can still be outside the range double
    precision represents (a stretch of 1e300, a modulus of 1e-300): overflow, division by
    zero or a singular matrix then raise ``ValueError`` naming the function and saying
    so, and a result containing NaN or inf raises ``ValueError`` instead of being
    returned.
    """

    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        try:
            with np.errstate(all="ignore"):
                out = func(*args, **kwargs)
        except (OverflowError, ZeroDivisionError, FloatingPointError,
                np.linalg.LinAlgError) as exc:
            raise ValueError(f"{func.__name__}: the arguments are outside the range that "
                             f"double precision represents ({type(exc).__name__}: {exc})"
                             ) from exc
        if not _all_finite(out):
            raise ValueError(f"{func.__name__}: the result overflows (NaN or inf) at these "
                             f"arguments; they are outside the representable range")
        return out

    return wrapper
