"""Registry of every public callable of ``debench.models`` (except Chapter 5) for fuzzing.

Each :class:`Case` names one public callable (function, class constructor, method or
property), a *valid and cheap* set of keyword arguments, and the *kind* of each argument.
A kind maps to a list of invalid values (:data:`INVALID`: each must raise a project
error) and of extreme but possibly admissible values (:data:`EXTREME`: each must raise a
project error or return finite values). ``check`` applies the model's own checks to a
result (default: every number in it is finite).

Used by ``verification/test_fuzz_api.py`` (Hypothesis draws from the same lists) and by
``tools/fuzz_report.py`` (tries every listed value once and counts the outcomes).

Outcome of one call (:func:`classify`):

``clear``
    ``ValueError``, ``TypeError`` or ``ConvergenceError`` raised by debench code (the
    innermost frame of the traceback is in ``debench``), so the message is ours.
``foreign``
    any other exception, or one of the above raised inside numpy/scipy.
``silent``
    a result returned for an invalid input, or a result with NaN or inf in it.
``ok``
    a finite result that passes ``check`` for an admissible (extreme or valid) input.
"""

from __future__ import annotations

import dataclasses
import functools
import importlib
import inspect
import math
import pkgutil
import traceback
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

NAN, INF = float("nan"), float("inf")

#: public modules not fuzzed here, with the reason (the meta-test accepts only these)
EXCLUDED_MODULES = {
    "debench.models.numerics": (
        "shared numerics (roots, scans, convergence fits, GCI) on callables and level arrays: "
        "every routine runs through synthetic collections with known answers and through its "
        "failure modes (no sign change, NaN, no convergence in maxiter, non-monotone levels, "
        "bad orders) in verification/test_numerics.py; the adaptive scans "
        "(debench.models.numerics.scan) are also fuzzed here (_scan_cases)"),
    "debench.models.buckling": "Chapter 5 FE model: validated and fuzzed by its owner",
    "debench.models.materials.energies": (
        "the expressions of the energies, shared by the numpy and NGSolve backends (floats, "
        "complex numbers, arrays or CoefficientFunctions in and out, no validation): the "
        "inputs are validated once by the library's public boundary (the material classes, "
        "GentMembrane, ZhaoSuoPermittivity), which is fuzzed here; both backends are checked "
        "against each other in verification/test_materials_energies.py"),
    "debench.models.materials.protocol": (
        "the material protocol's base classes (Material, IdealDielectricElastomer), which "
        "are not materials themselves: every method of the protocol is fuzzed here through "
        "each material of the library that inherits or implements it"),
    "debench.models.materials.jet": (
        "second-order forward differentiation of the energy expressions (jets in and out, no "
        "validation, like debench.models.materials.energies): reached only through the "
        "library's response, fuzzed here for each material; checked against the hand "
        "derivation to round-off at drawn states in verification/test_materials_energies.py"),
    "debench.models.materials.ngsolve_forms": (
        "NGSolve CoefficientFunction builders (symbolic, no numbers in or out); owned "
        "with the Chapter 5 FE model"),
    "debench.models.invariants.generated": (
        "sympy-generated code (tools/derive_invariants.py): the derivatives of the invariants "
        "as straight-line arithmetic, no validation by design; the independent path the "
        "closed forms and the numerical derivatives are compared with, on validated states, "
        "in verification/test_invariants_paths.py (which also re-derives it with sympy)"),
    "debench.models.circular.integrator": (
        "the shooting method's RK4 kernels (stresses, right-hand sides, the batched "
        "integration), unchecked by design (NaN marks an inadmissible trajectory) and called "
        "in every solver round: the inputs are validated by debench.models.circular.shooting's "
        "public functions, fuzzed here; the kernels are checked against the term-by-term "
        "transcription and the sympy re-derivation in verification/test_ch3_solvers.py"),
    "debench.models.circular.generated": (
        "the sympy-generated right-hand sides and Jacobians of the annulus ODE "
        "(tools/derive_ch3.py; floats or arrays in and out, no validation), evaluated at "
        "every collocation node: the inputs are validated by "
        "debench.models.circular.collocation's public functions, fuzzed here; the "
        "expressions are compared with a fresh sympy re-derivation at drawn points in "
        "verification/test_ch3_solvers.py"),
    "debench.models.mms_generated": (
        "sympy-generated body force, free charge and fields of the manufactured solution "
        "(tools/derive_mms.py; arrays in and out, no validation by design): called through "
        "debench.models.mms.ManufacturedSolution, whose inputs are validated; compared with a "
        "fresh sympy re-derivation in verification/test_mms.py"),
    "debench.models.mms": (
        "the manufactured solution's public API: its bad geometry, material, kappa, Jm and "
        "coordinates raise naming them in verification/test_mms.py; not yet in this registry"),
    "debench.models.mms_fem": (
        "the NGSolve solver of the manufactured solution: bad degree, mesh and level inputs "
        "raise naming them in verification/test_mms.py (each call is a finite-element solve, "
        "seconds); not yet in this registry"),
    "debench.models.bilayer": (
        "the NGSolve model of lit_bilayer (each call is a finite-element continuation, "
        "seconds to minutes): bad orders, levels, voltages and parameters raise naming them "
        "in verification/test_bilayer.py; not yet in this registry"),
    "debench.models.circular.lockstep": (
        "plumbing of the Chapter 3 iterative solvers (generators in, their results out; no "
        "numbers from users): running side by side equals running alone, bit for bit, and a "
        "solver's error propagates (verification/test_ch3_chapter.py)"),
    "debench.models.circular.fe": (
        "NGSolve FE cross-check of Chapter 3 (seconds per call): validates at its boundary "
        "(ValueError naming the bound, ConvergenceError); bad inputs tested in "
        "verification/test_ch3_fe.py"),
    "debench.models.circular.fe_continuation": (
        "the bordered continuation and its linear algebra shared by the two NGSolve FE "
        "cross-checks of Chapter 3 (debench.models.circular.fe, fe_solid), which validate "
        "at their boundary; its solves are tested against round-off in "
        "verification/test_ch3_fe_roundoff.py"),
    "debench.models.circular.fe_solid": (
        "NGSolve thin-solid (r, z) FE cross-check of Chapter 3 (seconds per call): "
        "validates at its boundary (ValueError naming the bound, ConvergenceError); bad "
        "inputs tested in verification/test_ch3_fe_solid.py"),
    "debench.models.plate.generated": (
        "sympy-generated code (tools/derive_ch4.py): the coefficients a..g of (4.52)-(4.53) "
        "and the base state as straight-line arithmetic of scalars or arrays, no validation "
        "by design; called on validated inputs by debench.models.plate.coefficients (whose "
        "public functions are fuzzed here) and re-derived with sympy in "
        "verification/test_ch4_derivation.py"),
    "debench.models.plate.generated_inplane": (
        "sympy-generated code (tools/derive_ch4_inplane.py): the in-plane fibre energy "
        "matrix and base state as straight-line arithmetic, no validation by design; called "
        "on validated inputs by debench.models.plate.inplane (whose public functions are "
        "fuzzed here) and re-derived with sympy in verification/test_ch4_inplane.py"),
    "debench.models.plate.strip_fe": (
        "NGSolve strip FE cross-check of Chapter 4 (seconds per call): validates at its "
        "boundary (require, ConvergenceError); bad inputs tested in "
        "verification/test_ch4_fe.py"),
}

_F_BAD = [
    np.full((3, 3), NAN), np.where(np.eye(3) > 0, INF, 0.0), np.eye(2), np.ones(3),
    np.diag([1.0, 1.0, -1.0]), np.zeros((3, 3)), 1e-300 * np.eye(3), "x", None,
    [[1, 0, 0], [0, 1]],
]
_D_BAD = [np.array([NAN, 0.0, 0.0]), np.array([0.0, INF, 0.0]), np.zeros(2), np.zeros((3, 3)),
          "x", None]

INVALID: dict[str, list] = {
    "real": [NAN, INF, -INF, "x", None],
    "pos": [NAN, INF, -INF, 0.0, -1.0, "x", None],
    "pos_or_inf": [NAN, -INF, 0.0, -1.0, "x", None],
    "nonneg": [NAN, INF, -INF, -1.0, "x", None],
    "stretch": [NAN, INF, -INF, 0.0, -1.0, 0.5, 1e300, "x", None],
    "lam": [NAN, INF, -INF, 0.0, -1.0, "x", None],
    "lam_array": [np.array([1.5, NAN]), np.array([1.5, INF]), np.array([1.5, -1.0]), "x",
                  None],
    "tol": [NAN, INF, -INF, 0.0, -1.0, 1e300, "x", None],
    "count": [0, -1, 2.5, NAN, "3", None],
    "F": _F_BAD,
    "D": _D_BAD,
    "A": [np.array([1.0, 1.0, 0.0]), np.array([NAN, 1.0, 0.0]), np.zeros(2), "x"],
    "obj": ["x", None, 1.0],
    "choice": ["bogus", None, 3],
    "window": [(NAN, 1.0), (2.0, 1.0), (0.0, 8.0), (-1.0, 2.0), (1.0, INF), "x", (1.0,)],
    "func": ["x", None],
    "W6": [np.full(6, NAN), np.zeros(5), "x", None],
    "vec3pos": [np.array([1.0, NAN, 1.0]), np.array([1.0, -1.0, 1.0]), np.zeros(3),
                np.ones(2), "x"],
}

EXTREME: dict[str, list] = {
    "real": [1e300, -1e300],
    "pos": [1e300, 1e-300],
    "pos_or_inf": [1e300],
    "nonneg": [1e300],
    "lam": [1e300, 1e-300],
    "F": [1e300 * np.eye(3), np.diag([1e150, 1e150, 1e-300])],
    "D": [np.full(3, 1e300)],
}


@dataclass(frozen=True)
class Case:
    """One public callable: ``call(**valid)`` must succeed and pass ``check``."""

    name: str
    call: Callable
    valid: dict
    kinds: dict
    check: Callable | None = None
    #: extra invalid values per argument, beyond those of its kind
    extra: dict = field(default_factory=dict)
    #: values of the kind lists that are admissible for this argument (not invalid)
    allowed: dict = field(default_factory=dict)

    def inputs(self):
        """``(argument, value, invalid?)`` for every listed value of every argument."""
        for arg, kind in self.kinds.items():
            ok = self.allowed.get(arg, [])
            for v in INVALID.get(kind, []) + self.extra.get(arg, []):
                if not any(_same(v, a) for a in ok):
                    yield arg, v, True
            for v in EXTREME.get(kind, []):
                yield arg, v, False


def _same(a, b) -> bool:
    if isinstance(a, float) and isinstance(b, float):
        return a == b or (math.isnan(a) and math.isnan(b))
    return a is b


# ----------------------------------------------------------------------- result checks
def numbers_in(x, depth: int = 0):
    """Every number (as float arrays) found in a result: arrays, tuples, dicts,
    dataclasses, scalars; strings and types are skipped."""
    if depth > 4 or x is None or isinstance(x, str | bytes | type):
        return
    if isinstance(x, bool | np.bool_):
        return
    if isinstance(x, int | float | complex | np.number):
        yield np.asarray(x)
        return
    if isinstance(x, np.ndarray):
        if x.dtype.kind in "fciu":
            yield x
        elif x.dtype == object:
            for v in x.ravel():
                yield from numbers_in(v, depth + 1)
        return
    if isinstance(x, dict):
        for v in x.values():
            yield from numbers_in(v, depth + 1)
        return
    if isinstance(x, list | tuple):
        for v in x:
            yield from numbers_in(v, depth + 1)
        return
    if dataclasses.is_dataclass(x):
        for f in dataclasses.fields(x):
            yield from numbers_in(getattr(x, f.name), depth + 1)


def all_finite(result) -> None:
    for a in numbers_in(result):
        if not np.all(np.isfinite(a)):
            raise AssertionError(f"non-finite value in the result: {a!r:.200}")


def classify(case: Case, arg: str | None, value, invalid: bool) -> tuple[str, str]:
    """Run one call (``arg`` replaced by ``value``) and return (outcome, detail)."""
    from debench.models.errors import ConvergenceError

    kw = dict(case.valid)
    if arg is not None:
        kw[arg] = value
    try:
        with np.errstate(all="ignore"):
            res = case.call(**kw)
    except (ValueError, TypeError, ConvergenceError) as exc:
        tb = traceback.extract_tb(exc.__traceback__)
        where = tb[-1].filename if tb else ""
        if "debench" in where or "/models/" in where:
            return "clear", f"{type(exc).__name__}: {exc}"[:200]
        return "foreign", f"{type(exc).__name__} from {where.split('/')[-1]}: {exc}"[:200]
    except Exception as exc:  # noqa: BLE001 - classified, not swallowed
        return "foreign", f"{type(exc).__name__}: {exc}"[:200]
    try:
        (case.check or all_finite)(res)
    except AssertionError as exc:
        return "silent", str(exc)[:200]
    if invalid:
        return "silent", f"accepted: returned {type(res).__name__}"
    return "ok", ""


# --------------------------------------------------------------------------- fixtures
@functools.cache
def _annulus():
    from debench.models.circular.params import Annulus
    return Annulus(2.0, 15.0)


@functools.cache
def _branch():
    from debench.models.circular.actuator import branch
    return branch(_annulus(), n=40)


@functools.cache
def _curve():
    from debench.models.circular.actuator import curves
    return curves(_branch(), [0.0])[0]


@functools.cache
def _plate():
    from debench.models.plate.coefficients import PlateParams
    return PlateParams(xi=0.0, Dhat=0.0)


_F0 = np.array([[1.2, 0.1, 0.0], [0.05, 0.9, 0.02], [0.0, 0.03, 1.0 / 1.08]])
_D0 = np.array([0.1, 0.2, 0.3])
_A0 = np.array([0.0, 1.0, 0.0])


# ------------------------------------------------------------------------- the cases
def _invariant_cases():
    from debench.models.invariants import closed_form as cf
    from debench.models.invariants import numerical as nm
    from debench.models.invariants import printed as pr

    out = [
        Case("debench.models.invariants.closed_form.validate_state", cf.validate_state,
             {"F": _F0, "D_L": _D0}, {"F": "F", "D_L": "D"}),
        Case("debench.models.invariants.closed_form.invariants", cf.invariants,
             {"F": _F0, "D_L": _D0, "A": _A0, "numbering": "ti"},
             {"F": "F", "D_L": "D", "A": "A", "numbering": "choice"}),
        Case("debench.models.invariants.closed_form.derivatives", cf.derivatives,
             {"F": _F0, "D_L": _D0}, {"F": "F", "D_L": "D", "numbering": "choice"}),
        Case("debench.models.invariants.closed_form.InvariantDerivatives",
             lambda F, D_L: cf.derivatives(F, D_L), {"F": _F0, "D_L": _D0},
             {"F": "F", "D_L": "D"}),
        Case("debench.models.invariants.numerical.derivatives", nm.derivatives,
             {"F": _F0, "D_L": _D0, "h2": 1e-4},
             {"F": "F", "D_L": "D", "h2": "tol", "numbering": "choice"}),
        Case("debench.models.invariants.numerical.complex_step_gradients",
             nm.complex_step_gradients, {"F": _F0, "D_L": _D0},
             {"F": "F", "D_L": "D", "numbering": "choice"}),
        Case("debench.models.invariants.numerical.central_difference_F",
             nm.central_difference_F, {"fun": lambda F: F @ F, "F": _F0, "h": 1e-4},
             {"fun": "func", "F": "F", "h": "tol"}),
    ]
    for name, f in vars(pr).items():
        if name.startswith("_") or not inspect.isfunction(f) or f.__module__ != pr.__name__:
            continue
        params = list(inspect.signature(f).parameters)
        valid = {"F": _F0, "D": _D0, "D_L": _D0, "E_L": _D0, "A": _A0, "p": 0.3,
                 "W": np.array([0.5, 0.1, 0.2, 0.3, 0.4, 0.05]), "C10": 0.5, "D1": 0.1,
                 "eps": 1.0, "k": 10.0, "alphas": (1.3, 2.3), "mus": (0.5, 0.4),
                 "lam": np.array([1.2, 0.9, 1 / 1.08])}
        kinds = {"F": "F", "D": "D", "D_L": "D", "E_L": "D", "A": "A", "p": "real",
                 "W": "W6", "C10": "pos", "D1": "pos", "eps": "pos", "k": "pos",
                 "lam": "vec3pos", "alphas": "obj", "mus": "obj"}
        if "A" in params and "ti" not in name:
            params.remove("A")  # the iso formulas ignore the fibre
        out.append(Case(f"debench.models.invariants.printed.{name}", f,
                        {p: valid[p] for p in params}, {p: kinds[p] for p in params}))
    return out


def _material_cases():
    from debench.models.materials import energies, kernel, library, membrane, response

    out = []
    mats = {
        "GentIdealDielectric": ({"mu": 51e3, "Jm": 120.0, "eps": 4e-11},
                                {"mu": "pos", "Jm": "pos", "eps": "pos"}),
        "NeoHookeanIdealDielectric": ({"mu": 156e3, "k": 7.7e6, "eps": 4e-11},
                                      {"mu": "pos", "k": "pos", "eps": "pos"}),
        "IdealDielectric": ({"eps": 4e-11}, {"eps": "pos"}),
        "DorfmannOgdenElectric": ({"alpha": 0.3, "beta": 0.5, "eps": 1.0},
                                  {"alpha": "real", "beta": "real", "eps": "pos"}),
        "OgdenIdealDielectric": ({"k": 7.7e6, "eps": 4e-11}, {"k": "pos", "eps": "pos"}),
        "TransverselyIsotropicNeoHookean": (
            {"mu": 1.0, "xi": 5.0, "alpha": 0.0, "beta": 0.5, "eps": 1.0},
            {"mu": "pos", "xi": "nonneg", "alpha": "real", "beta": "real", "eps": "pos"}),
        "MooneyRivlinIdealDielectric": ({"C10": 54.6e3, "C01": 23.4e3, "k": 7.7e6, "eps": 4e-11},
                                        {"C10": "pos", "C01": "nonneg", "k": "pos",
                                         "eps": "pos"}),
    }
    for cname, (valid, kinds) in mats.items():
        cls = getattr(library, cname)
        base = f"debench.models.materials.library.{cname}"
        out.append(Case(base, cls, valid, kinds))
        m0 = cls(**valid)
        # Gent: a state below the lock; the others: a general state
        F = _F0 if cname != "OgdenIdealDielectric" else _F0
        D = _D0 * (1e-3 if "eps" in valid and valid["eps"] < 1e-6 else 1.0)
        meths = ("energy", "response") + (("invariant_response",)
                                          if hasattr(cls, "invariant_response") else ())
        for meth in meths:
            out.append(Case(f"{base}.{meth}", lambda F, D_L, m0=m0, meth=meth:
                            getattr(m0, meth)(F, D_L), {"F": F, "D_L": D},
                            {"F": "F", "D_L": "D"}))
        out.append(Case(f"{base}.shear_modulus", lambda m0=m0: m0.shear_modulus, {}, {}))
        out.append(Case(f"{base}.bulk_modulus", lambda m0=m0: m0.bulk_modulus, {}, {},
                        check=lambda r: r > 0))
        out.append(Case(f"{base}.check_admissible", lambda F, D_L, m0=m0:
                        m0.check_admissible(F, D_L), {"F": F, "D_L": D},
                        {"F": "F", "D_L": "D"}))
        # the expression methods build W for any backend without validation (like
        # debench.models.materials.energies): their valid call, in numpy
        for meth, args in (("energy_expression", (F, D)), ("mechanical_energy", (F,))):
            out.append(Case(f"{base}.{meth}", lambda m0=m0, meth=meth, args=args:
                            getattr(m0, meth)(*args, xp=energies.NUMPY), {}, {}))
        if hasattr(cls, "invariant_derivatives"):
            from debench.models.invariants import invariants
            I0 = invariants(_F0, D, np.asarray(getattr(m0, "A", _A0), float),
                            numbering=cls.numbering)
            out.append(Case(f"{base}.invariant_derivatives", m0.invariant_derivatives,
                            {"I": I0}, {"I": "W6"}))
    nh = library.NeoHookeanIdealDielectric()
    out += [
        Case("debench.models.materials.library.material", library.material, {"name": "nh"},
             {"name": "choice"}),
        Case("debench.models.materials.library.NeoHookeanIdealDielectric.C10",
             lambda: nh.C10, {}, {}),
        Case("debench.models.materials.library.NeoHookeanIdealDielectric.D1",
             lambda: nh.D1, {}, {}),
    ]
    Dsi = _D0 * 1e-3
    gent = library.GentIdealDielectric()
    out += [
        Case("debench.models.materials.response.first_piola", response.first_piola,
             {"material": gent, "F": _F0, "D_L": Dsi, "p": 1e3},
             {"material": "obj", "F": "F", "D_L": "D", "p": "real"}),
        Case("debench.models.materials.response.cauchy_stress", response.cauchy_stress,
             {"material": gent, "F": _F0, "D_L": Dsi, "p": 1e3},
             {"material": "obj", "F": "F", "D_L": "D", "p": "real"}),
        Case("debench.models.materials.response.electric_field", response.electric_field,
             {"material": nh, "F": _F0, "D_L": Dsi},
             {"material": "obj", "F": "F", "D_L": "D"}),
        Case("debench.models.materials.response.eulerian_displacement",
             response.eulerian_displacement, {"F": _F0, "D_L": Dsi}, {"F": "F", "D_L": "D"}),
        Case("debench.models.materials.response.moduli", response.moduli,
             {"material": nh, "F": _F0, "D_L": Dsi},
             {"material": "obj", "F": "F", "D_L": "D"}),
        Case("debench.models.materials.response.push_forward", response.push_forward,
             {"F": _F0, "AA": np.ones((3, 3, 3, 3)), "AAA": np.ones((3, 3, 3)),
              "A": np.eye(3)}, {"F": "F", "AA": "obj", "AAA": "obj", "A": "obj"}),
        Case("debench.models.materials.response.pressure_from_traction_free_face",
             response.pressure_from_traction_free_face,
             {"material": gent, "F": _F0, "D_L": Dsi, "normal": np.array([0.0, 0.0, 1.0])},
             {"material": "obj", "F": "F", "D_L": "D", "normal": "A"}),
        Case("debench.models.materials.kernel.Response",
             lambda W: kernel.Response(W, np.eye(3), np.zeros(3), np.zeros((3, 3, 3, 3)),
                                       np.zeros((3, 3, 3)), np.eye(3)),
             {"W": 1.0}, {"W": "real"}),
        Case("debench.models.materials.kernel.invariant_chain_rule",
             kernel.invariant_chain_rule,
             {"W": 1.0, "W_n": np.ones(6), "W_mn": np.eye(6), "F": _F0, "D_L": _D0,
              "numbering": "iso"},
             {"W": "real", "W_n": "W6", "W_mn": "obj", "F": "F", "D_L": "D",
              "numbering": "choice"}),
        Case("debench.models.materials.kernel.divided_difference_power",
             kernel.divided_difference_power, {"x": 1.2, "y": 1.1, "q": 0.5},
             {"x": "lam", "y": "lam", "q": "real"}),
        Case("debench.models.materials.kernel.spectral_response", kernel.spectral_response,
             {"phi": library.OgdenIdealDielectric()._phi, "F": _F0},
             {"phi": "func", "F": "F"}),
    ]
    zs = membrane.ZhaoSuoPermittivity
    jm = membrane.JimenezMcMeekingPermittivity
    gm = membrane.GentMembrane
    em = membrane.ElastomerMembrane
    em0 = em(library.GentIdealDielectric(), zs(c=-0.05))   # the lock: l1 = 20 inadmissible
    m = "debench.models.materials.membrane"
    l12 = {"l1": 1.5, "l2": 1.3}
    lk = {"l1": "lam", "l2": "lam"}
    out += [
        Case(f"{m}.ZhaoSuoPermittivity", zs, {"eps_bar": 4e-11, "c": -0.05},
             {"eps_bar": "pos", "c": "real"}),
        Case(f"{m}.ZhaoSuoPermittivity.__call__", lambda l1, l2: zs(c=-0.05)(l1, l2),
             l12, lk),
        Case(f"{m}.ZhaoSuoPermittivity.derivative",
             lambda l1, l2: zs(c=-0.05).derivative(l1, l2), l12, lk),
        Case(f"{m}.JimenezMcMeekingPermittivity", jm, {"eps0_bar": 4e-11, "c0": 1e-13},
             {"eps0_bar": "pos", "c0": "real"}),
        Case(f"{m}.JimenezMcMeekingPermittivity.__call__",
             lambda l1, l2: jm(c0=1e-13)(l1, l2), l12, lk),
        Case(f"{m}.JimenezMcMeekingPermittivity.components",
             lambda l1, l2, l3: jm(c0=1e-13).components(l1, l2, l3),
             {"l1": 1.5, "l2": 1.3, "l3": 0.5}, {"l1": "lam", "l2": "lam", "l3": "lam"}),
        Case(f"{m}.JimenezMcMeekingPermittivity.derivative",
             lambda l1, l2: jm(c0=1e-13).derivative(l1, l2), l12, lk),
        Case(f"{m}.JimenezMcMeekingPermittivity.zhao_suo_linearisation",
             lambda c0: jm(c0=c0).zhao_suo_linearisation(), {"c0": 1e-13}, {"c0": "real"}),
        Case(f"{m}.GentMembrane", gm, {"mu": 51e3, "Jm": 120.0, "permittivity": zs()},
             {"mu": "pos", "Jm": "pos", "permittivity": "obj"}),
        Case(f"{m}.GentMembrane.stretching_energy",
             lambda l1, l2: gm().stretching_energy(l1, l2), l12, lk,
             extra={"l1": [20.0]}),
        Case(f"{m}.GentMembrane.stretching_energy_derivative",
             lambda l1, l2: gm().stretching_energy_derivative(l1, l2), l12, lk,
             extra={"l1": [20.0]}),
        Case(f"{m}.GentMembrane.free_energy",
             lambda l1, l2, I4: gm().free_energy(l1, l2, I4), {**l12, "I4": 1e12},
             {**lk, "I4": "nonneg"}),
        Case(f"{m}.GentMembrane.equations_of_state",
             lambda l1, l2, E: gm().equations_of_state(l1, l2, E), {**l12, "E": 1e7},
             {**lk, "E": "real"}),
        Case(f"{m}.GentMembrane.equations_of_state_from_energy",
             lambda l1, l2, E: gm().equations_of_state_from_energy(l1, l2, E),
             {**l12, "E": 1e7}, {**lk, "E": "real"}),
        Case(f"{m}.ElastomerMembrane", em, {"elastomer": library.GentIdealDielectric(),
                                            "permittivity": zs()},
             {"elastomer": "obj", "permittivity": "obj"}),
        Case(f"{m}.ElastomerMembrane.shear_modulus", lambda: em0.shear_modulus, {}, {}),
        Case(f"{m}.ElastomerMembrane.stretching_energy",
             lambda l1, l2: em0.stretching_energy(l1, l2), l12, lk, extra={"l1": [20.0]}),
        Case(f"{m}.ElastomerMembrane.stretching_energy_derivative",
             lambda l1, l2: em0.stretching_energy_derivative(l1, l2), l12, lk,
             extra={"l1": [20.0]}),
        Case(f"{m}.ElastomerMembrane.stretching_energy_jet",
             lambda l1, l2: em0.stretching_energy_jet(l1, l2), l12, lk,
             check=_check_membrane_jet, extra={"l1": [20.0]}),
        Case(f"{m}.MembraneJet", lambda: membrane.MembraneJet.seed(1.5, 1.3), {}, {},
             check=lambda r: all(_check_membrane_jet(j) for j in r)),
    ]
    # the jet's parts (value, first and second derivatives) of l1 * l2^2 at a state
    out += [
        Case(f"{m}.MembraneJet.{k}",
             functools.partial(lambda k: getattr(_jet_product(), k), k), {}, {})
        for k in ("v", "d1", "d2", "d11", "d12", "d22")
    ]
    out += [
        Case(f"{m}.ElastomerMembrane.electric_energy_derivative",
             lambda l1, l2: em0.electric_energy_derivative(l1, l2), l12, lk),
        Case(f"{m}.ElastomerMembrane.free_energy",
             lambda l1, l2, I4: em0.free_energy(l1, l2, I4), {**l12, "I4": 1e12},
             {**lk, "I4": "nonneg"}),
    ]
    return out


def _jet_product():
    """``l1 l2^2`` as a :class:`~debench.models.materials.membrane.MembraneJet` at
    (1.5, 1.3)."""
    from debench.models.materials.membrane import MembraneJet
    a, b = MembraneJet.seed(1.5, 1.3)
    return a * b * b


def _check_membrane_jet(W) -> bool:
    """A :class:`~debench.models.materials.membrane.MembraneJet`: every entry finite."""
    return all(np.all(np.isfinite(getattr(W, k))) for k in ("v", "d1", "d2", "d11", "d12",
                                                             "d22"))


def _circular_cases():
    from debench.models.circular import (
        actuator,
        analysis,
        chapter_pass,
        circle_a,
        collocation,
        events,
        law,
        lockstep,
        params,
        shooting,
    )
    from debench.models.materials import library

    c = "debench.models.circular"
    # a library elastomer for the ODE model, and a Gent of Jm = 10 whose lock (equibiaxial
    # stretch 2.547) a pre-stretch of 3 is past
    _MR = library.MooneyRivlinIdealDielectric(C10=0.35, C01=0.15)
    _GENT_JM10 = library.GentIdealDielectric(mu=1.0, Jm=10.0, eps=1.0)
    lock10 = law.locking_stretch_equibiaxial(10.0)
    an = _annulus
    spec = chapter_pass.ChapterSpec(lamPs=(2.0,), cs=(0.0, -0.05), n=20, steps=40)
    return [
        # the chapter pass: its specification's values are checked where the pass uses
        # them (branches, CircularActuator), so a bad field raises naming it
        Case(f"{c}.chapter_pass.chapter", chapter_pass.chapter, {"spec": spec},
             {"spec": "obj"},
             extra={"spec": [dataclasses.replace(spec, n=0),
                             dataclasses.replace(spec, steps=2),
                             dataclasses.replace(spec, lamPs=(0.5,)),
                             dataclasses.replace(spec, states=((2.0, 0.2, -10.0),))]}),
        Case(f"{c}.chapter_pass.ChapterSpec",
             lambda n, steps: chapter_pass.chapter(
                 chapter_pass.ChapterSpec(lamPs=(2.0,), cs=(0.0,), n=n, steps=steps)),
             {"n": 20, "steps": 40}, {"n": "count", "steps": "count"}),
        Case(f"{c}.chapter_pass.ChapterSpec.Jm", lambda: spec.Jm, {}, {}),
        Case(f"{c}.chapter_pass.ChapterSpec.mu", lambda: spec.mu, {}, {}),
        Case(f"{c}.chapter_pass.ChapterSpec.eps_r", lambda: spec.eps_r, {}, {}),
        Case(f"{c}.chapter_pass.ChapterSpec.curve_keys", lambda: spec.curve_keys(), {}, {}),
        Case(f"{c}.chapter_pass.Chapter", lambda: chapter_pass.chapter(spec), {}, {}),
        Case(f"{c}.chapter_pass.current_constants", chapter_pass.current_constants, {}, {}),
        # forgets the memo of this process: the next chapter pass is computed again
        Case(f"{c}.chapter_pass.clear_memo", chapter_pass.clear_memo, {}, {}),
        Case(f"{c}.params.Annulus", params.Annulus,
             {"lamP": 2.0, "radius_ratio": 15.0, "Jm": 120.0, "equilibrium": "printed"},
             {"lamP": "stretch", "radius_ratio": "pos", "Jm": "pos_or_inf",
              "equilibrium": "choice"}, extra={"radius_ratio": [1.0, 0.5]},
             allowed={"Jm": [None]}),
        Case(f"{c}.params.Annulus.kappa", lambda Jm: params.Annulus(2.0, Jm=Jm).kappa,
             {"Jm": 120.0}, {"Jm": "pos_or_inf"}, allowed={"Jm": [None]}),
        Case(f"{c}.params.Annulus[elastomer]", params.Annulus,
             {"lamP": 3.0, "elastomer": _MR}, {"lamP": "stretch", "elastomer": "obj"},
             allowed={"elastomer": [None]}, extra={"elastomer": [_GENT_JM10]}),
        Case(f"{c}.params.Annulus.law", lambda Jm: params.Annulus(2.0, Jm=Jm).law,
             {"Jm": 120.0}, {"Jm": "pos_or_inf"}, allowed={"Jm": [None]}),
        # the membrane laws: constructors and membrane_law validate; the stresses are the
        # integrator's kernels (no checks, NaN marks an inadmissible state), called here at
        # a valid state and compared with each other in verification/test_ch3_any_material.py
        Case(f"{c}.params.membrane_law", params.membrane_law,
             {"Jm": None, "elastomer": _MR, "lamP": 2.0},
             {"Jm": "pos_or_inf", "elastomer": "obj", "lamP": "stretch"},
             allowed={"Jm": [None], "elastomer": [None]}),
        Case(f"{c}.law.GentLaw", law.GentLaw, {"kappa": 1 / 120, "Jm": 120.0},
             {"kappa": "nonneg", "Jm": "pos_or_inf"}),
        Case(f"{c}.law.gent_stresses", lambda: law.gent_stresses(1.5, 1.3, 1 / 120), {}, {}),
        Case(f"{c}.law.GentLaw.stresses",
             lambda: law.GentLaw.of_Jm(120.0).stresses(1.5, 1.3), {}, {}),
        Case(f"{c}.law.GentLaw.equibiaxial_stress",
             lambda: law.GentLaw.of_Jm(120.0).equibiaxial_stress(2.0), {}, {}),
        Case(f"{c}.law.GentLaw.locking_stretch",
             lambda Jm: law.GentLaw.of_Jm(Jm).locking_stretch(), {"Jm": 120.0},
             {"Jm": "pos_or_inf"}, check=lambda r: r > 1),
        Case(f"{c}.law.ElastomerLaw", law.ElastomerLaw, {"elastomer": _MR},
             {"elastomer": "obj"}, extra={"elastomer": [library.IdealDielectric()]}),
        Case(f"{c}.law.ElastomerLaw.stresses",
             lambda: law.ElastomerLaw(_MR).stresses(1.5, 1.3), {}, {}),
        Case(f"{c}.law.ElastomerLaw.equibiaxial_stress",
             lambda: law.ElastomerLaw(_MR).equibiaxial_stress(2.0), {}, {}),
        Case(f"{c}.law.ElastomerLaw.locking_stretch",
             lambda: law.ElastomerLaw(_GENT_JM10).locking_stretch(), {}, {},
             check=lambda r: abs(r - lock10) <= 1e-12 * lock10),
        Case(f"{c}.params.CircularActuator", params.CircularActuator,
             {"annulus": params.Annulus(2.0), "c": -0.05, "eps_r": 4.7, "mu": 51e3},
             {"annulus": "obj", "c": "real", "eps_r": "pos", "mu": "pos"},
             extra={"c": [-0.9, -10.0]}),
        Case(f"{c}.law.locking_stretch_equibiaxial", law.locking_stretch_equibiaxial,
             {"Jm": 120.0}, {"Jm": "pos_or_inf"}),
        Case(f"{c}.params.film_elastomer",
             lambda lamP, elastomer: params.film_elastomer(lamP, None, elastomer),
             {"lamP": 2.0, "elastomer": params.GentIdealDielectric()},
             {"lamP": "stretch", "elastomer": "obj"}, extra={"lamP": [12.0]}),
        Case(f"{c}.circle_a.gent_equibiaxial_stress", circle_a.gent_equibiaxial_stress,
             {"lam": 2.0, "kappa": 1 / 120}, {"lam": "lam", "kappa": "nonneg"},
             extra={"lam": [12.0]}),
        Case(f"{c}.circle_a.electrostriction_factor", circle_a.electrostriction_factor,
             {"lam": 2.0, "c": -0.05}, {"lam": "lam", "c": "real"}),
        Case(f"{c}.circle_a.permittivity_ratio", circle_a.permittivity_ratio,
             {"lam": 2.0, "c": -0.05}, {"lam": "lam", "c": "real"}),
        Case(f"{c}.circle_a.phibar_squared", circle_a.phibar_squared,
             {"lam": 2.0, "T1B": 0.5, "c": -0.05, "kappa": 1 / 120},
             {"lam": "lam", "T1B": "real", "c": "real", "kappa": "nonneg"},
             extra={"lam": [12.0], "c": [-10.0]}),
        Case(f"{c}.circle_a.phibar_squared[elastomer]",
             lambda lam, T1B, c, elastomer: circle_a.phibar_squared(lam, T1B, c,
                                                                    elastomer=elastomer),
             {"lam": 2.0, "T1B": 0.5, "c": -0.05, "elastomer": _MR},
             {"lam": "lam", "T1B": "real", "c": "real", "elastomer": "obj"},
             extra={"c": [-10.0], "elastomer": [library.IdealDielectric()]}),
        Case(f"{c}.circle_a.phibar_squared_where_defined",
             lambda lam, T1B, c, kappa: (
                 circle_a.phibar_squared_where_defined(lam, T1B, c, kappa), lam, c),
             {"lam": np.array([2.0, 3.0]), "T1B": 0.5, "c": -0.2, "kappa": 1 / 120},
             {"lam": "lam_array", "T1B": "real", "c": "real", "kappa": "nonneg"},
             check=_check_where_defined, extra={"lam": [np.array([2.0, 12.0])]}),
        Case(f"{c}.circle_a.sigma1_circle_a", circle_a.sigma1_circle_a,
             {"lam": 2.0, "phibar": 0.3, "c": -0.05, "kappa": 1 / 120},
             {"lam": "lam", "phibar": "real", "c": "real", "kappa": "nonneg"},
             extra={"lam": [12.0]}),
        Case(f"{c}.circle_a.voltage_weight", circle_a.voltage_weight,
             {"lam": 2.0, "c": -0.05, "kappa": 1 / 120},
             {"lam": "lam", "c": "real", "kappa": "nonneg"}),
        Case(f"{c}.circle_a.breakdown_phibar", circle_a.breakdown_phibar,
             {"lam": 2.0, "eps_r": 4.7, "mu": 51e3}, {"lam": "lam", "eps_r": "pos", "mu": "pos"}),
        Case(f"{c}.circle_a.free_membrane_phibar", circle_a.free_membrane_phibar,
             {"lam": 2.0, "c": -0.05, "kappa": 1 / 120},
             {"lam": "lam", "c": "real", "kappa": "nonneg"}, extra={"lam": [12.0, 0.5]}),
        Case(f"{c}.shooting.integrate_inward", shooting.integrate_inward,
             {"annulus": params.Annulus(2.0), "q": np.array([1.9]), "steps": 20},
             {"annulus": "obj", "q": "lam_array", "steps": "count"},
             extra={"q": [np.array([1e-3])]}),
        Case(f"{c}.shooting.interface_state", shooting.interface_state,
             {"annulus": params.Annulus(2.0), "q": np.array([1.9]), "steps": 20},
             {"annulus": "obj", "q": "lam_array", "steps": "count"},
             extra={"q": [np.array([1e-3])]}),
        Case(f"{c}.shooting.interface_state_solver",
             lambda annulus, q, steps, lamP=None: lockstep.run(
                 shooting.interface_state_solver(annulus, q, steps=steps, lamP=lamP)),
             {"annulus": params.Annulus(2.0), "q": np.array([1.9]), "steps": 20},
             {"annulus": "obj", "q": "lam_array", "steps": "count", "lamP": "lam_array"},
             allowed={"lamP": [None]}),
        Case(f"{c}.shooting.InterfaceState",
             lambda q: shooting.interface_state(params.Annulus(2.0), q, steps=20),
             {"q": np.array([1.9])}, {"q": "lam_array"}),
        Case(f"{c}.shooting.q_for_stretch", shooting.q_for_stretch,
             {"annulus": params.Annulus(2.0), "lam": np.array([2.5]),
              "q0": float(np.interp(2.5, _branch().lam, _branch().q)),
              "steps": 20, "rtol": 1e-13, "maxiter": 30},
             {"annulus": "obj", "lam": "lam_array", "q0": "lam", "steps": "count",
              "rtol": "tol", "maxiter": "count"}),
        Case(f"{c}.collocation.nominal_radial_stress", collocation.nominal_radial_stress,
             {"l1": 1.5, "l2": 1.3, "kappa": 1 / 120},
             {"l1": "lam", "l2": "lam", "kappa": "nonneg"}, extra={"l1": [20.0]}),
        Case(f"{c}.collocation.solve", collocation.solve,
             {"annulus": params.Annulus(2.0), "lam": 2.5, "tol": 1e-6},
             {"annulus": "obj", "lam": "stretch", "tol": "tol", "guess": "obj"},
             allowed={"guess": [None]}),
        Case(f"{c}.collocation.CollocationSolution",
             lambda lam: collocation.solve(params.Annulus(2.0), lam, tol=1e-6),
             {"lam": 2.5}, {"lam": "stretch"}),
        Case(f"{c}.collocation.branch", collocation.branch,
             {"annulus": params.Annulus(2.0), "lam": np.array([2.2, 2.5]), "tol": 1e-6,
              "substeps": 1},
             {"annulus": "obj", "lam": "lam_array", "tol": "tol", "substeps": "count"}),
        Case(f"{c}.collocation.CollocationBranch",
             lambda lam: collocation.branch(params.Annulus(2.0), lam, tol=1e-6),
             {"lam": np.array([2.2, 2.5])}, {"lam": "lam_array"}),
        Case(f"{c}.actuator.branch", actuator.branch,
             {"annulus": params.Annulus(2.0), "n": 20, "steps": 40},
             {"annulus": "obj", "n": "count", "steps": "count", "lam_end": "lam",
              "lam": "lam_array"}, allowed={"lam_end": [None], "lam": [None]}),
        Case(f"{c}.actuator.Branch", lambda n: actuator.branch(an(), n=n, steps=40),
             {"n": 20}, {"n": "count"}),
        Case(f"{c}.actuator.Branch.dT1_dlam", lambda: _branch().dT1_dlam, {}, {}),
        Case(f"{c}.actuator.branches", actuator.branches,
             {"annuli": [params.Annulus(2.0), params.Annulus(2.5)], "n": 20, "steps": 40},
             {"annuli": "obj", "n": "count", "steps": "count"}),
        Case(f"{c}.actuator.branches_solver",
             lambda annuli, n, steps: lockstep.run(
                 actuator.branches_solver(annuli, n=n, steps=steps)),
             {"annuli": [params.Annulus(2.0), params.Annulus(2.5)], "n": 20, "steps": 40},
             {"annuli": "obj", "n": "count", "steps": "count"}),
        Case(f"{c}.events.event_function", events.event_function,
             {"kinds": np.array(["loss_of_tension"]), "annulus": params.Annulus(2.0),
              "q": np.array([1.9]), "c": [0.0], "eps_r": [4.7], "mu": 51e3, "steps": 20},
             {"kinds": "choice", "annulus": "obj", "q": "lam_array", "c": "real",
              "eps_r": "pos", "mu": "pos", "steps": "count", "lamP": "lam_array"},
             allowed={"lamP": [None]}, extra={"q": [np.array([1e-3])]}),
        Case(f"{c}.events.locate", events.locate,
             {"kinds": np.array(["loss_of_tension"]), "annulus": params.Annulus(2.0),
              "qa": [float(_branch().q[0])], "qb": [float(_branch().q[-1])], "c": [0.0],
              "eps_r": [4.7], "mu": 51e3, "steps": 200, "xtol": 1e-12, "maxiter": 100},
             {"kinds": "choice", "annulus": "obj", "c": "real", "eps_r": "pos", "mu": "pos",
              "steps": "count", "xtol": "tol", "maxiter": "count"}),
        Case(f"{c}.actuator.curves", actuator.curves,
             {"br": _branch(), "cs": [0.0, -0.05], "eps_r": 4.7, "mu": 51e3},
             {"br": "obj", "cs": "obj", "eps_r": "pos", "mu": "pos", "steps": "count"},
             check=_check_curves, allowed={"steps": [None], "eps_r": [None], "mu": [None]},
             extra={"cs": [[NAN], [-10.0]]}),
        Case(f"{c}.actuator.curves_many", actuator.curves_many,
             {"jobs": [(_branch(), [0.0], 4.7)], "mu": 51e3},
             {"jobs": "obj", "mu": "pos", "steps": "count"},
             check=lambda r: [_check_curves(x) for x in r],
             allowed={"steps": [None], "mu": [None]},
             extra={"jobs": [[("x", [0.0], 4.7)], [(_branch(), [NAN], 4.7)]]}),
        Case(f"{c}.actuator.curve", actuator.curve,
             {"actuator": params.CircularActuator(params.Annulus(2.0)), "n": 40,
              "steps": 40}, {"actuator": "obj", "n": "count", "steps": "count"},
             check=lambda r: _check_curves([r])),
        Case(f"{c}.actuator.Curve", lambda c: actuator.curves(_branch(), [c])[0],
             {"c": 0.0}, {"c": "real"}, check=lambda r: _check_curves([r])),
        Case(f"{c}.actuator.Event", lambda: _curve().failure, {}, {}),
        Case(f"{c}.actuator.Curve.lam_max", lambda: _curve().lam_max, {}, {}),
        Case(f"{c}.actuator.Curve.phibar_max", lambda: _curve().phibar_max, {}, {}),
        Case(f"{c}.actuator.Curve.pullin_suppressed", lambda: _curve().pullin_suppressed,
             {}, {}),
        Case(f"{c}.analysis.dphibar2_dlam", analysis.dphibar2_dlam,
             {"br": _branch(), "c": -0.05}, {"br": "obj", "c": "real"},
             extra={"c": [-10.0]}),
        Case(f"{c}.analysis.state_at_voltage", analysis.state_at_voltage,
             {"br": _branch(), "c": 0.0, "phibar": 0.2},
             {"br": "obj", "c": "real", "phibar": "nonneg"}, extra={"phibar": [5.0]}),
        Case(f"{c}.analysis.states_at_voltage_many", analysis.states_at_voltage_many,
             {"brs": [_branch()], "cs": [0.0], "phibars": [0.2]},
             {"brs": "obj", "cs": "obj", "phibars": "obj"},
             extra={"brs": [["x"]], "cs": [[NAN], [-10.0], [0.0, 0.0]],
                    "phibars": [[NAN], [-1.0], [5.0]]}),
        Case(f"{c}.analysis.branches_at", analysis.branches_at,
             {"brs": [_branch()], "lams": [np.array([2.2, 2.5])], "maxiter": 30},
             {"brs": "obj", "lams": "obj", "maxiter": "count"},
             extra={"brs": [["x"]], "lams": [[np.array([1.5])], [np.array([NAN])],
                                             [np.array([2.2]), np.array([2.3])]]}),
        Case(f"{c}.analysis.min_slope", analysis.min_slope,
             {"br": _branch(), "c": 0.0, "definition": "monotonic"},
             {"br": "obj", "c": "real", "definition": "choice", "lam_lot": "lam"},
             allowed={"lam_lot": [None]}, extra={"c": [-10.0]}),
        Case(f"{c}.analysis.dphibar2_dlam_continued", analysis.dphibar2_dlam_continued,
             {"br": _branch(), "c": -0.05}, {"br": "obj", "c": "real"}),
        Case(f"{c}.analysis.loss_of_tension_stretch", analysis.loss_of_tension_stretch,
             {"br": _branch()}, {"br": "obj"}),
        Case(f"{c}.analysis.pullin_c_threshold", analysis.pullin_c_threshold,
             {"annulus": params.Annulus(1.5), "n": 200},
             {"annulus": "obj", "n": "count", "definition": "choice", "c_range": "window"},
             extra={"c_range": [(-10.0, 0.0)]}, allowed={"c_range": [INVALID["window"][3]]}),
        Case(f"{c}.analysis.pullin_c_threshold_closed_form",
             analysis.pullin_c_threshold_closed_form, {"annulus": params.Annulus(1.5)},
             {"annulus": "obj"}),
        Case(f"{c}.analysis.pullin_suppression_prestretch",
             analysis.pullin_suppression_prestretch, {"c": 0.0, "n": 100, "xtol": 1e-6},
             {"c": "real", "radius_ratio": "pos", "Jm": "pos_or_inf",
              "equilibrium": "choice", "definition": "choice", "bracket": "window",
              "n": "count", "xtol": "tol"}, allowed={"Jm": [None]}),
        Case(f"{c}.analysis.pullin_suppression_prestretches",
             analysis.pullin_suppression_prestretches,
             {"c": 0.0, "equilibria": ("printed",), "n": 60, "xtol": 1e-6},
             {"c": "real", "equilibria": "obj", "radius_ratio": "pos", "Jm": "pos_or_inf",
              "definition": "choice", "bracket": "window", "n": "count", "xtol": "tol",
              "bracket_branches": "obj"},
             allowed={"Jm": [None], "bracket_branches": [None]},
             extra={"equilibria": [("bogus",)], "bracket_branches": [[_branch()]]}),
    ]


def _check_curves(curves) -> None:
    """A curve is finite up to its failure point; events are finite points."""
    for cv in curves:
        fail = cv.failure
        assert fail is not None, "curve without a failure event"
        assert math.isfinite(fail.lam), f"failure stretch {fail.lam}"
        upto = cv.lam <= fail.lam
        all_finite((cv.lam, cv.phibar[upto], cv.sigma1A[upto], cv.phibar_breakdown[upto]))
        for ev in cv.events.values():
            if ev is not None:
                all_finite((ev.lam, ev.phibar, ev.q))


def _check_where_defined(res) -> None:
    """(Phibar^2, lam, c): NaN exactly where K = 1 + c(5 lam/2 - 2) <= 0, finite elsewhere."""
    p2, lam, c = res
    with np.errstate(all="ignore"):
        defined = 1 + c * (2.5 * np.asarray(lam) - 2) > 0
    assert np.array_equal(np.isnan(p2), ~defined), "NaN where K > 0, or a number at K <= 0"
    all_finite(p2[defined])


def _check_padded(res) -> None:
    """(lam, parity) arrays: NaN exactly where the parity code is -1 (padding)."""
    lam, par = res
    assert np.array_equal(np.isnan(lam), par == -1), "NaN outside the padding"


def _inplane_cases():
    """The in-plane fibre model (beyond the thesis): small discretisations and scans."""
    from debench.models.plate import inplane, inplane_fe, inplane_symbol
    from debench.models.plate.coefficients import PlateParams

    p = "debench.models.plate.inplane"
    ps = "debench.models.plate.inplane_symbol"
    pfe = "debench.models.plate.inplane_fe"
    PD = PlateParams(xi=5.0, Dhat=0.0, variant="derived")
    th = {"theta": "real"}
    bad_theta = {"theta": [-1.0, 91.0]}
    common = {"lam": "lam", **th, "params": "obj"}
    return [
        Case(f"{ps}.energy_matrix", inplane_symbol.energy_matrix,
             {"lam": 0.97, "theta": 30.0, "params": PD}, common, extra=bad_theta),
        Case(f"{ps}.base_state", inplane_symbol.base_state,
             {"lam": 0.97, "theta": 30.0, "params": PD}, common, extra=bad_theta),
        Case(f"{ps}.symbol", inplane_symbol.symbol,
             {"lam": 0.97, "theta": 30.0, "params": PD, "s": np.array([0.3j, 1.1j])},
             {**common, "s": "real"},
             extra={**bad_theta, "s": [np.array([0.3j, complex(NAN, 1.0)])]}),
        Case(f"{ps}.characteristic_roots", inplane_symbol.characteristic_roots,
             {"lam": 0.97, "theta": 30.0, "params": PD}, common, extra=bad_theta),
        Case(f"{ps}.strongly_elliptic", inplane_symbol.strongly_elliptic,
             {"lam": 0.97, "theta": 30.0, "params": PD}, common, extra=bad_theta),
        Case(f"{p}.det_function", inplane.det_function,
             {"lam": 0.97, "kH": 2.0, "theta": 30.0, "params": PD},
             {**common, "kH": "pos"}, extra=bad_theta),
        Case(f"{p}.boundary_singularity", inplane.boundary_singularity,
             {"lam": 0.97, "kH": 2.0, "theta": 30.0, "params": PD},
             {**common, "kH": "pos"}, extra=bad_theta),
        Case(f"{pfe}.fe_stiffness", inplane_fe.fe_stiffness,
             {"lam": 0.97, "kH": 2.0, "theta": 30.0, "params": PD, "n": 4},
             {**common, "kH": "pos", "n": "count"}, extra=bad_theta),
        Case(f"{pfe}.fe_eigenvalues", inplane_fe.fe_eigenvalues,
             {"lam": 0.97, "kH": 2.0, "theta": 30.0, "params": PD, "n": 4, "count": 3},
             {**common, "kH": "pos", "n": "count", "count": "count"}, extra=bad_theta),
        Case(f"{p}.critical_stretches_det", inplane.critical_stretches_det,
             {"kH": 2.0, "theta": 30.0, "params": PD, "n_scan": 30},
             {"kH": "pos", **th, "params": "obj", "window": "window", "n_scan": "count"},
             extra=bad_theta),
        Case(f"{p}.critical_stretches_det_many", inplane.critical_stretches_det_many,
             {"scans": [(2.0, 30.0, PD, {"n_scan": 30})]}, {"scans": "obj"},
             extra={"scans": [[(2.0, 30.0, PD)], [(2.0, 30.0, PD, None)],
                              [(-1.0, 30.0, PD, {})], [(2.0, 30.0, PD, {"window": (2.0, 1.0)})]]}),
        Case(f"{pfe}.critical_stretches_fe", inplane_fe.critical_stretches_fe,
             {"kH": 2.0, "theta": 30.0, "params": PD, "n_scan": 12, "n": 4},
             {"kH": "pos", **th, "params": "obj", "window": "window", "n_scan": "count",
              "n": "count", "max_index": "count"}, extra=bad_theta),
        Case(f"{p}.membrane_limit", inplane.membrane_limit,
             {"theta": 30.0, "params": PD},
             {**th, "params": "obj", "window": "window"}, extra=bad_theta),
        Case(f"{p}.ellipticity_limit", inplane.ellipticity_limit,
             {"theta": 30.0, "params": PD, "n_scan": 20},
             {**th, "params": "obj", "window": "window", "n_scan": "count"},
             extra=bad_theta),
    ] + _scan_cases()


def _scan_cases():
    """The refinement of sign-change scans (synthetic functions: |x - 0.37| and its V)."""
    from debench.models.numerics import scan as sc

    p = "debench.models.numerics.scan"
    x = np.linspace(0.0, 1.0, 5)
    m = np.abs(x - 0.37)
    bad_x = [np.array([0.0, 1.0, 0.5, 2.0, 3.0]), np.array([0.0, NAN, 1.0, 2.0, 3.0])]
    bad_m = [-np.ones(5), np.ones(4), np.array([1.0, INF, 1.0, 1.0, 1.0])]
    bad_usable = [np.ones(4), np.ones(3, bool)]

    def ev_many(which, pts):
        return (pts - 0.37)[None], np.abs(pts - 0.37)

    def refine(samples, **kw):
        # fresh lists: refine_samples refines them in place
        if isinstance(samples, list):
            samples = [list(s) if isinstance(s, list) else s for s in samples]
        return sc.refine_samples(samples=samples, **kw)

    return [
        Case(f"{p}.refinement_points", sc.refinement_points,
             {"x": x, "m": m, "width": 1e-3},
             {"x": "obj", "m": "obj", "width": "tol", "usable": "obj"},
             extra={"x": bad_x, "m": bad_m, "usable": bad_usable},
             allowed={"usable": [None]}),
        Case(f"{p}.sign_change_brackets", sc.sign_change_brackets,
             {"x": x, "f": x - 0.37}, {"x": "obj", "f": "obj", "usable": "obj"},
             extra={"x": bad_x, "f": [np.ones(4)], "usable": bad_usable},
             allowed={"usable": [None]}),
        Case(f"{p}.refine_samples", refine,
             {"evaluate": ev_many, "samples": [[x, (x - 0.37)[None], m, None]],
              "width": 1e-3},
             {"evaluate": "func", "samples": "obj", "width": "tol"},
             extra={"samples": [[(x, x, m, None)], [[x, x[:3], m, None]],
                                [[x, x, -m, None]]]}),
        Case(f"{p}.scan_brackets", sc.scan_brackets,
             {"evaluate": lambda pts: (pts - 0.37, np.abs(pts - 0.37)), "x": x,
              "width": 1e-3},
             {"evaluate": "func", "x": "obj", "width": "tol", "usable": "obj"},
             extra={"x": bad_x, "usable": bad_usable}, allowed={"usable": [None]}),
    ]


def _determinants_and_ellipticity(lam, kH, params, parities=("E", "O")):
    """ansatz.determinants with the strong ellipticity of ``lam``, for
    :func:`_check_nan_where_not_elliptic` (NaN is its answer where not elliptic)."""
    from debench.models.plate import ansatz
    from debench.models.plate.coefficients import strongly_elliptic

    return ansatz.determinants(lam, kH, params, parities), strongly_elliptic(lam, params)


def _check_nan_where_not_elliptic(res):
    dets, elliptic = res
    for det in dets:
        ell = np.broadcast_to(elliptic, det.shape)
        assert np.all(np.isfinite(det[ell])), f"non-finite at elliptic points: {det!r:.200}"
        assert np.all(np.isnan(det[~ell])), f"a value where not elliptic: {det!r:.200}"


def _plate_cases():
    from debench.models.plate import analysis, ansatz, fem, voltage

    # the package re-exports the function ``coefficients``, which shadows the module
    coefficients = importlib.import_module("debench.models.plate.coefficients")

    p = "debench.models.plate"
    P0 = _plate()
    PP = coefficients.PlateParams
    pk = {"params": "obj"}
    return [
        Case(f"{p}.coefficients.PlateParams", PP,
             {"xi": 3.0, "Dhat": 0.5, "beta": 0.5, "alpha": 0.0, "variant": "derived"},
             {"xi": "nonneg", "Dhat": "nonneg", "beta": "pos", "alpha": "nonneg",
              "variant": "choice"}),
        Case(f"{p}.coefficients.printed_coefficients", coefficients.printed_coefficients,
             {"lam": 1.2, "xi": 3.0, "alpha": 0.0, "beta": 0.5, "Dhat": 0.5},
             {"lam": "lam", "xi": "nonneg", "alpha": "nonneg", "beta": "pos",
              "Dhat": "nonneg"}),
        Case(f"{p}.coefficients.coefficients", coefficients.coefficients,
             {"lam": 1.2, "params": P0}, {"lam": "lam", **pk}),
        Case(f"{p}.coefficients.energy_matrix", coefficients.energy_matrix,
             {"lam": 1.2, "params": P0}, {"lam": "lam", **pk}),
        Case(f"{p}.coefficients.base_state", coefficients.base_state,
             {"lam": 1.2, "params": P0}, {"lam": "lam", **pk}),
        Case(f"{p}.coefficients.reduced_quartic", coefficients.reduced_quartic,
             {"lam": 1.2, "params": P0}, {"lam": "lam", **pk}),
        Case(f"{p}.coefficients.strongly_elliptic", coefficients.strongly_elliptic,
             {"lam": 1.2, "params": P0}, {"lam": "lam", **pk}),
        Case(f"{p}.coefficients.ellipticity_limit_stretch",
             coefficients.ellipticity_limit_stretch, {"params": P0}, pk,
             check=lambda r: None if r > 1 else (_ for _ in ()).throw(AssertionError(r))),
        Case(f"{p}.ansatz.determinant", ansatz.determinant,
             {"lam": 1.2, "kH": 1.0, "params": P0, "parity": "E"},
             {"lam": "lam", "kH": "pos", "params": "obj", "parity": "choice"}),
        Case(f"{p}.ansatz.determinants", _determinants_and_ellipticity,
             {"lam": 1.2, "kH": 1.0, "params": P0},
             {"lam": "lam", "kH": "pos", "params": "obj", "parities": "obj"},
             check=_check_nan_where_not_elliptic),
        Case(f"{p}.ansatz.row_coefficients", ansatz.row_coefficients,
             {"lam": 1.2, "params": P0}, {"lam": "lam", **pk}),
        Case(f"{p}.ansatz.quartic_roots", ansatz.quartic_roots,
             {"lam": 1.2, "params": P0}, {"lam": "lam", **pk}),
        Case(f"{p}.ansatz.scan_grid", ansatz.scan_grid,
             {"window": (0.4, 8.0), "n": 10}, {"window": "window", "n": "count"},
             extra={"n": [1]}),
        Case(f"{p}.ansatz.critical_stretches", ansatz.critical_stretches,
             {"kH": 1.0, "params": P0, "n_scan": 40},
             {"kH": "pos", "params": "obj", "window": "window", "n_scan": "count",
              "parities": "obj"}, extra={"n_scan": [1]}),
        Case(f"{p}.ansatz.Roots", lambda kH: ansatz.critical_stretches(kH, P0, n_scan=40),
             {"kH": 1.0}, {"kH": "pos"}),
        Case(f"{p}.ansatz.curves", ansatz.curves,
             {"kH_values": np.array([0.5, 1.0]), "params": P0, "n_scan": 40},
             {"kH_values": "lam_array", "params": "obj", "window": "window",
              "n_scan": "count", "max_roots": "count"}, check=_check_padded),
        Case(f"{p}.ansatz.curves_vectorised", ansatz.curves_vectorised,
             {"kH_values": np.array([0.5, 1.0]), "params": P0, "n_scan": 40},
             {"kH_values": "lam_array", "params": "obj", "window": "window",
              "n_scan": "count", "max_roots": "count", "xtol": "tol"},
             check=_check_padded),
        Case(f"{p}.fem.elements_for", fem.elements_for, {"t": 1.0}, {"t": "pos"}),
        Case(f"{p}.fem.grading", fem.grading, {"t": 1.0}, {"t": "pos"}),
        Case(f"{p}.fem.stiffness", fem.stiffness,
             {"lam": 1.2, "kH": 1.0, "params": P0, "n": 4},
             {"lam": "lam", "kH": "pos", "params": "obj", "n": "count"}),
        Case(f"{p}.fem.eigenvalues", fem.eigenvalues,
             {"lam": 1.2, "kH": 1.0, "params": P0, "n": 4, "count": 3},
             {"lam": "lam", "kH": "pos", "params": "obj", "n": "count", "count": "count"},
             allowed={"count": [None]}, extra={"count": [10**6]}),
        Case(f"{p}.fem.critical_stretches", fem.critical_stretches,
             {"kH": 1.0, "params": P0, "n_scan": 12, "n": 4, "max_index": 3},
             {"kH": "pos", "params": "obj", "window": "window", "n_scan": "count",
              "n": "count", "max_index": "count"}),
        Case(f"{p}.fem.FemRoots",
             lambda kH: fem.critical_stretches(kH, P0, n_scan=12, n=4, max_index=3),
             {"kH": 1.0}, {"kH": "pos"}),
        Case(f"{p}.fem.refine_root", fem.refine_root,
             {"lam0": 0.97, "kH": 1.0, "params": P0, "n": 6, "index": 0, "rel": 0.05},
             {"lam0": "lam", "kH": "pos", "params": "obj", "n": "count", "index": "count",
              "rel": "tol"}, allowed={"index": [0]}),
        Case(f"{p}.voltage.dhat_at_voltage", voltage.dhat_at_voltage,
             {"lam": 1.2, "Vhat": 0.5, "params": P0},
             {"lam": "lam", "Vhat": "nonneg", "params": "obj"}),
        Case(f"{p}.voltage.determinant_at_voltage", voltage.determinant_at_voltage,
             {"lam": 1.2, "kH": 1.0, "Vhat": 0.5, "params": P0, "parity": "E"},
             {"lam": "lam", "kH": "pos", "Vhat": "nonneg", "params": "obj",
              "parity": "choice"}),
        Case(f"{p}.voltage.critical_stretches_at_voltage",
             voltage.critical_stretches_at_voltage,
             {"kH": 1.0, "Vhat": 0.5, "params": P0, "n_scan": 40},
             {"kH": "pos", "Vhat": "nonneg", "params": "obj", "window": "window",
              "n_scan": "count"}),
        Case(f"{p}.voltage.curves_at_voltage", voltage.curves_at_voltage,
             {"kH_values": np.array([0.5, 1.0]), "Vhat": 0.5, "params": P0, "n_scan": 40},
             {"kH_values": "lam_array", "Vhat": "nonneg", "params": "obj",
              "window": "window", "n_scan": "count", "max_roots": "count"},
             check=_check_padded),
        Case(f"{p}.voltage.fe_root_at_voltage", voltage.fe_root_at_voltage,
             {"lam0": 0.97, "kH": 1.0, "Vhat": 0.0, "params": P0, "n": 6, "rel": 0.05},
             {"lam0": "lam", "kH": "pos", "Vhat": "nonneg", "params": "obj", "n": "count",
              "rel": "tol"}),
        Case(f"{p}.analysis.membrane_stress", analysis.membrane_stress,
             {"lam": 1.2, "params": P0}, {"lam": "lam", **pk}),
        Case(f"{p}.analysis.thin_limit", analysis.thin_limit, {"params": P0, "n": 200},
             {"params": "obj", "window": "window", "n": "count"}),
        Case(f"{p}.analysis.euler_coefficient_isotropic",
             analysis.euler_coefficient_isotropic, {}, {}),
        Case(f"{p}.analysis.half_space_determinant", analysis.half_space_determinant,
             {"lam": 0.7, "params": P0}, {"lam": "lam", **pk}),
        Case(f"{p}.analysis.half_space_limit", analysis.half_space_limit, {"params": P0},
             {"params": "obj", "window": "window"}),
        Case(f"{p}.analysis.biot_equibiaxial_closed_form",
             analysis.biot_equibiaxial_closed_form, {}, {}),
        Case(f"{p}.analysis.region", analysis.region,
             {"params": P0, "kH": np.array([0.5, 1.0]), "lam": np.array([0.8, 1.0, 1.2])},
             {"params": "obj", "kH": "lam_array", "lam": "lam_array"}),
        Case(f"{p}.analysis.Region",
             lambda kH: analysis.region(P0, kH, np.array([0.8, 1.0, 1.2])),
             {"kH": np.array([0.5, 1.0])}, {"kH": "lam_array"}),
        Case(f"{p}.analysis.Region.area",
             lambda which: analysis.region(P0, np.array([0.5, 1.0]),
                                           np.array([0.8, 1.0, 1.2])).area(which),
             {"which": "thesis"}, {"which": "choice"}),
        Case(f"{p}.analysis.area_curve", analysis.area_curve,
             {"params": P0, "Dhats": np.array([0.0, 0.5]), "kH": np.array([0.5, 1.0]),
              "lam": np.array([0.8, 1.0, 1.2])},
             {"params": "obj", "Dhats": "lam_array", "kH": "lam_array", "lam": "lam_array",
              "which": "choice"}, allowed={"Dhats": []}),
        Case(f"{p}.analysis.critical_D_max_area", analysis.critical_D_max_area,
             {"params": PP(xi=0.0), "Dhats": np.linspace(0.0, 3.0, 7),
              "kH": np.geomspace(0.1, 10, 8), "lam": np.linspace(0.5, 3.0, 30)},
             {"params": "obj", "Dhats": "lam_array", "kH": "lam_array", "lam": "lam_array",
              "which": "choice"}),
        Case(f"{p}.analysis.critical_D_thin_extensional",
             analysis.critical_D_thin_extensional, {"params": PP(xi=0.0)},
             {"params": "obj", "D_window": "window", "kH": "pos", "lam_window": "window"},
             allowed={"D_window": [INVALID["window"][2]]}),
    ]


def _balloon_cases():
    from debench.models import balloon

    b = "debench.models.balloon"
    ext = balloon.Extremum(lam=1.4, value=1.2, residual=0.0)
    return [
        Case(f"{b}.locking_stretch", balloon.locking_stretch, {"Jm": 97.2},
             {"Jm": "pos_or_inf"}),
        Case(f"{b}.pressure", balloon.pressure, {"lam": 2.0, "vbar": 0.3, "Jm": 97.2},
             {"lam": "lam", "vbar": "nonneg", "Jm": "pos_or_inf"},
             extra={"lam": [0.5, 7.1, np.array([1.5, 0.9])]}),
        Case(f"{b}.pressure_slope", balloon.pressure_slope,
             {"lam": np.array([1.0, 3.0]), "vbar": 0.3, "Jm": 50.0},
             {"lam": "lam_array", "vbar": "nonneg", "Jm": "pos_or_inf"},
             extra={"lam": [5.2]}),
        Case(f"{b}.voltage_squared", balloon.voltage_squared,
             {"lam": 1.3, "pbar": 0.5, "Jm": 97.2},
             {"lam": "lam", "pbar": "real", "Jm": "pos_or_inf"}, extra={"lam": [0.5]}),
        Case(f"{b}.pressure_extrema", balloon.pressure_extrema, {"vbar": 0.3, "Jm": 97.2},
             {"vbar": "nonneg", "Jm": "pos_or_inf"}),
        Case(f"{b}.voltage_limit", balloon.voltage_limit, {"pbar": 0.5, "Jm": 50.0},
             {"pbar": "real", "Jm": "pos_or_inf"}),
        Case(f"{b}.Extremum", balloon.Extremum, {"lam": 1.4, "value": 1.2, "residual": 0.0},
             {}),
        Case(f"{b}.PressureExtrema", balloon.PressureExtrema,
             {"maximum": ext, "minimum": None}, {}),
    ]


def _error_cases():
    from debench.models import errors

    return [
        Case("debench.models.errors.ConvergenceError",
             lambda message: errors.ConvergenceError(message), {"message": "m"}, {}),
        Case("debench.models.errors.require", errors.require,
             {"condition": True, "message": "m"}, {}),
    ]


def _validation_cases():
    from debench.models import validation as v

    m = "debench.models.validation"
    return [
        Case(f"{m}.finite", v.finite, {"name": "x", "x": 1.0}, {"x": "real"}),
        Case(f"{m}.positive", v.positive, {"name": "x", "x": 1.0}, {"x": "pos"}),
        Case(f"{m}.nonnegative", v.nonnegative, {"name": "x", "x": 1.0}, {"x": "nonneg"}),
        Case(f"{m}.at_least", v.at_least, {"name": "x", "x": 1.0, "lo": 1.0},
             {"x": "stretch"}, allowed={"x": [1e300]}),
        Case(f"{m}.in_range", v.in_range, {"name": "x", "x": 1.0, "lo": 0.0, "hi": 2.0},
             {"x": "lam"}, allowed={"x": [0.0]}, extra={"x": [3.0]}),
        Case(f"{m}.integer_at_least", v.integer_at_least, {"name": "n", "n": 3, "k": 1},
             {"n": "count"}),
        Case(f"{m}.tolerance", v.tolerance, {"name": "tol", "tol": 1e-8}, {"tol": "tol"}),
        Case(f"{m}.choice", v.choice, {"name": "c", "value": "a", "options": ("a", "b")},
             {"value": "choice"}),
        Case(f"{m}.instance", v.instance, {"name": "o", "value": 1.0, "cls": float},
             {"value": "obj"}, allowed={"value": [1.0]}),
        Case(f"{m}.array", v.array, {"name": "a", "x": np.ones(3)}, {"x": "D"},
             allowed={"x": [_D_BAD[2], _D_BAD[3]]}),
        Case(f"{m}.vector", v.vector, {"name": "a", "v": np.ones(3)}, {"v": "D"}),
        Case(f"{m}.unit_vector", v.unit_vector, {"name": "a", "v": _A0}, {"v": "A"}),
        Case(f"{m}.deformation_gradient", v.deformation_gradient,
             {"name": "F", "F": _F0}, {"F": "F"}),
        Case(f"{m}.finite_result", lambda x: v.finite_result(lambda y: y * 2.0)(x),
             {"x": 1.0}, {"x": "real"}, allowed={"x": ["x", None]}),
        Case(f"{m}.window", v.window, {"name": "w", "w": (0.4, 8.0)}, {"w": "window"},
             allowed={"w": [INVALID["window"][2]]}),
    ]


@functools.cache
def cases() -> tuple[Case, ...]:
    """Every registered case (built once; fixtures are computed lazily)."""
    out = (_invariant_cases() + _material_cases() + _circular_cases() + _plate_cases()
           + _inplane_cases() + _balloon_cases() + _error_cases())
    try:
        out += _validation_cases()
    except ImportError:
        pass
    return tuple(out)


def public_names() -> set[str]:
    """Qualified names of every public callable of ``debench.models`` that is fuzzed.

    Public modules (no underscore in the path, not in :data:`EXCLUDED_MODULES`); in each,
    the non-underscore callables defined there (``__all__`` when present), and the public
    methods and properties of its classes (inherited ones included; ``__call__`` counts).
    """
    import debench.models as pkg

    names = set()
    for info in pkgutil.walk_packages(pkg.__path__, "debench.models."):
        mod_name = info.name
        if any(part.startswith("_") for part in mod_name.split(".")):
            continue
        if any(mod_name == ex or mod_name.startswith(ex + ".") for ex in EXCLUDED_MODULES):
            continue
        mod = importlib.import_module(mod_name)
        listed = getattr(mod, "__all__", None)
        for n, obj in vars(mod).items():
            if n.startswith("_") or not callable(obj):
                continue
            if getattr(obj, "__module__", None) != mod_name:
                continue
            if listed is not None and n not in listed:
                continue
            names.add(f"{mod_name}.{n}")
            if inspect.isclass(obj):
                for k in dir(obj):
                    if k.startswith("_") and k != "__call__":
                        continue
                    if k == "__call__" and "__call__" not in vars(obj):
                        continue
                    a = inspect.getattr_static(obj, k)
                    if isinstance(a, property) or inspect.isfunction(a):
                        if dataclasses.is_dataclass(obj) and k in {
                                f.name for f in dataclasses.fields(obj)}:
                            continue
                        if issubclass(obj, BaseException):
                            continue
                        names.add(f"{mod_name}.{n}.{k}")
    return names
