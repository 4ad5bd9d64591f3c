"""One energy per material, evaluated by numpy and by NGSolve from the same expression.

Every energy of the library is written once, in :mod:`debench.models.materials.energies`,
against a math namespace (``energies.NUMPY``, ``ngsolve_forms.NGSOLVE``). Claims checked:

* every public function of ``energies`` gives the same number with both namespaces at
  drawn states (a meta-test fails if one is not covered);
* for every material of ``MATERIALS`` the library's numpy energy ``mat.energy(F, D_L)``
  equals the NGSolve form ``ngsolve_forms.energy_cf`` at drawn states; the NGSolve form of
  Ogden (5.26) is the averaged spectral perturbation (error O(delta^2)), so for Ogden the
  one expression is also compared at the unperturbed closed-form eigenvalues;
* each energy is defined once: doubling one function of ``energies`` moves the numpy and
  the NGSolve energy of every material that uses it by the same amount (also the
  membrane (3.20) of the Ch. 3 FE and the enthalpy of the Ch. 5 FE); and the NGSolve
  forms do no arithmetic on a material parameter;
* no material constant is written as a literal outside ``materials.constants``.
"""

from __future__ import annotations

import ast
import inspect
import math
import pathlib

import debench.models
import ngsolve as ng
import numpy as np
import pytest
from debench.models.buckling import analytic, energy
from debench.models.buckling.parameters import MU_REF, NeoHookean, Ogden
from debench.models.circular import fe as circular_fe
from debench.models.invariants import invariants as closed_form_invariants
from debench.models.materials import MATERIALS, GentMembrane, ZhaoSuoPermittivity
from debench.models.materials import constants as K
from debench.models.materials import energies as E
from debench.models.materials import ngsolve_forms as ngf
from debench.models.materials.library import GentIdealDielectric
from debench.models.materials.membrane import ElastomerMembrane
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from netgen.meshing import Element3D, MeshPoint, Pnt
from netgen.meshing import Mesh as NGMesh

from verification.strategies import (
    deformation_gradients,
    isochoric_deformation_gradients,
    lagrangian_displacements,
    stretches,
    unit_vectors,
)

pytestmark = pytest.mark.fe

BACKEND_RTOL = 1e-12
"""One expression, two double-precision evaluators: the same operations except numpy's
LAPACK ``det``/``inv`` against NGSolve's closed-form 3x3 ``Det``/``Inv`` (a few ulp),
amplified by the cancellations in ``J - 1`` and ``J^{-2/3} I1 - 3`` at most ~100x
(k/mu = 50); relative to the natural scale of each quantity (its parameter modulus)."""
OGDEN_PERTURBATION_RTOL = 1e-5
"""The NGSolve form of Ogden (5.26) is the average at ``Cbar +- delta P`` (delta = 1e-3):
error O(delta^2) = 1e-6 times a constant <= 10 (as in test_materials_ngsolve)."""
EIGEN_GAP_MIN = 0.05
"""Smallest gap of the eigenvalues of Cbar at which the unperturbed closed-form
eigenvalues are compared (their rounding error grows without bound as a gap closes)."""
NAMES = sorted(MATERIALS)
NH = MATERIALS["neo_hookean_ideal_dielectric"]
GENT = MATERIALS["gent_ideal_dielectric"]
OGDEN = MATERIALS["ogden_ideal_dielectric"]
TI = MATERIALS["ti_neo_hookean_dielectric"]
DO = MATERIALS["dorfmann_ogden_electric"]
MR = MATERIALS["mooney_rivlin_ideal_dielectric"]
MEMBRANE = GentMembrane(mu=1.0, Jm=K.VHB_GENT_JM,
                        permittivity=ZhaoSuoPermittivity(eps_bar=1.0,
                                                         c=dict(K.TABLE_3_1)[56]))
"""The Ch. 3 membrane (units mu = eps_bar = 1) with c = -0.053 of Table 3.1."""
FE_MEMBRANE = ElastomerMembrane(GentIdealDielectric(mu=1.0, Jm=K.VHB_GENT_JM, eps=1.0),
                                permittivity=MEMBRANE.permittivity)
"""The same membrane as the Ch. 3 FE builds it: the library Gent's energy on J = 1."""


# ------------------------------------------------------------- NGSolve evaluation
_MIP = []


def _point():
    """A point of a one-tetrahedron mesh (a constant CF is evaluated there)."""
    if not _MIP:
        ngm = NGMesh(dim=3)
        pts = [ngm.Add(MeshPoint(Pnt(*p)))
               for p in ((0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1))]
        ngm.Add(Element3D(1, pts))
        mesh = ng.Mesh(ngm)
        _MIP.append((mesh, mesh(0.25, 0.25, 0.25)))   # the point needs its mesh alive
    return _MIP[0][1]


def _cf(x):
    """A constant CoefficientFunction of a scalar, 3-vector or 3x3 matrix (lists of
    scalars element by element; None stays None)."""
    if x is None:
        return None
    if isinstance(x, list):
        return [_cf(e) for e in x]
    a = np.asarray(x, dtype=float)
    if a.ndim == 0:
        return ng.CoefficientFunction(float(a))
    if a.shape == (3,):
        return ng.CoefficientFunction(tuple(a))
    return ng.CoefficientFunction(tuple(a.ravel()), dims=a.shape)


def _value(cf, like=None):
    """The value of a CF at the point, shaped like ``like``."""
    v = np.array(cf(_point()), dtype=float)
    return v.reshape(np.shape(like)) if like is not None else float(v.squeeze())


def _both(fn, args, kwargs):
    """``fn`` evaluated with numpy and with NGSolve: a list of (numpy, NGSolve) pairs."""
    takes_xp = "xp" in inspect.signature(fn).parameters
    a = fn(*args, **kwargs, **({"xp": E.NUMPY} if takes_xp else {}))
    b = fn(*[(lambda *y, f=x: _cf(f(*y))) if callable(x) else _cf(x) for x in args],
           **kwargs, **({"xp": ngf.NGSOLVE} if takes_xp else {}))
    if isinstance(a, dict):
        assert set(a) == set(b)
        return [(np.asarray(a[k]), _value(b[k], a[k])) for k in a]
    return [(np.asarray(a), _value(b, a))]


# ------------------------------------------------------------- backend agreement
def _cases(F, D, A, l1, l2, I4):
    """Arguments of every public function of ``energies`` at one drawn state:
    ``{name: (args, kwargs, scale)}`` with ``scale`` the natural size of the result
    (0: the result's own size). ``D`` is dimensionless (|D| <= 1); the SI materials see
    ``D sqrt(eps mu)``, the field of the enthalpy is ``D sqrt(mu/eps)``."""
    D_si = D * math.sqrt(NH.eps * NH.mu)
    E_L = D * math.sqrt(NH.mu / NH.eps)
    Isi = E.invariants(F, D_si, xp=E.NUMPY)
    Ind = E.invariants(F, D, A, xp=E.NUMPY)
    C = E.right_cauchy_green(F, xp=E.NUMPY)
    cbar = list(np.linalg.eigvalsh(E.isochoric_right_cauchy_green(C, np.linalg.det(F))))
    I1, J, DCD = Isi["I1"], Isi["J"], Isi["DCD"]
    ogden = dict(alphas=OGDEN.alphas, mus=OGDEN.mus)
    perm = MEMBRANE.permittivity
    return {
        "right_cauchy_green": ((F,), {}, 0),
        "invariants": ((F, D, A), {}, 0),
        "isochoric_right_cauchy_green": ((C, J), {}, 0),
        "membrane_first_invariant": ((l1, l2), {}, 0),
        "gent": ((I1,), dict(mu=GENT.mu, Jm=GENT.Jm), GENT.mu),
        "gent_lock_margin": ((I1,), dict(kappa=1 / GENT.Jm), 1.0),
        "neo_hookean_isochoric": ((I1, J), dict(mu=NH.mu), NH.mu),
        "volumetric": ((J,), dict(k=NH.k), NH.mu),
        "mooney_rivlin_isochoric": ((I1, Isi["I2"], J), dict(C10=MR.C10, C01=MR.C01), MR.C10),
        "neo_hookean": ((I1, J), dict(mu=NH.mu, k=NH.k), NH.mu),
        "ogden_term": ((cbar,), dict(alpha=OGDEN.alphas[1], mu=OGDEN.mus[1]),
                       OGDEN.shear_modulus),
        "ogden_isochoric": ((cbar,), ogden, OGDEN.shear_modulus),
        "ogden_isochoric_from_power_sums": ((lambda b: sum(c**b for c in cbar),), ogden,
                                            OGDEN.shear_modulus),
        "ogden": ((cbar, J), dict(**ogden, k=OGDEN.k), OGDEN.shear_modulus),
        "ti_neo_hookean_elastic": ((Ind["I1"], Ind["ACA"]), dict(mu=TI.mu, xi=TI.xi), TI.mu),
        "ideal_dielectric": ((DCD, J), dict(eps=NH.eps), NH.mu),
        "ideal_dielectric_enthalpy": ((F, E_L), dict(eps=NH.eps), NH.mu),
        "dorfmann_ogden_electric": ((Ind["DD"], Ind["DCD"]),
                                    dict(alpha=DO.alpha, beta=DO.beta, eps=DO.eps), 1.0),
        "zhao_suo_permittivity": ((l1, l2), dict(eps_bar=perm.eps_bar, c=perm.c),
                                  perm.eps_bar),
        "membrane_electric": ((l1, l2, I4), dict(eps=perm.eps_bar), 0),
        "gent_ideal_dielectric": ((I1, DCD), dict(mu=GENT.mu, Jm=GENT.Jm, eps=GENT.eps),
                                  GENT.mu),
        "neo_hookean_ideal_dielectric": ((I1, J, DCD), dict(mu=NH.mu, k=NH.k, eps=NH.eps),
                                         NH.mu),
        "ti_neo_hookean_dielectric": ((Ind["I1"], Ind["ACA"], Ind["DD"], Ind["DCD"]),
                                      dict(mu=TI.mu, xi=TI.xi, alpha=TI.alpha, beta=TI.beta,
                                           eps=TI.eps), TI.mu),
    }


def _public_functions():
    return sorted(n for n, f in vars(E).items() if inspect.isfunction(f)
                  and f.__module__ == E.__name__ and not n.startswith("_"))


def test_every_energy_function_is_in_the_backend_agreement_test():
    """Meta-test: a new function of ``energies`` must be given arguments in ``_cases``."""
    F, D, A = np.eye(3), np.zeros(3), np.array([0.0, 1.0, 0.0])
    assert sorted(_cases(F, D, A, 1.0, 1.0, 0.0)) == _public_functions()


def test_both_namespaces_provide_the_same_operations():
    """NUMPY and NGSOLVE are the same kind of namespace (one set of operation names)."""
    assert type(E.NUMPY) is type(ngf.NGSOLVE) is E.MathNamespace
    assert (E.NUMPY.name, ngf.NGSOLVE.name) == ("numpy", "ngsolve")


@pytest.mark.parametrize("name", _public_functions())
@settings(max_examples=10)
@given(F=deformation_gradients(0.8, 1.3), D=lagrangian_displacements(1.0), A=unit_vectors(),
       l1=stretches(0.6, 3.0), l2=stretches(0.6, 3.0), I4=st.floats(0.0, 1.0))
def test_numpy_and_ngsolve_evaluate_each_expression_alike(name, F, D, A, l1, l2, I4):
    """Each function of ``energies``: numpy and NGSolve agree to BACKEND_RTOL."""
    args, kwargs, scale = _cases(F, D, A, l1, l2, I4)[name]
    for a, b in _both(getattr(E, name), args, kwargs):
        s = max(float(np.max(np.abs(a))), scale)
        assert np.max(np.abs(a - b)) <= BACKEND_RTOL * s, (name, a, b)


@pytest.mark.parametrize("I1", [3.0, 3.5, 20.0, 100.0])
def test_gent_lock_margin_is_the_inverse_stiffening_of_the_gent_energy(I1):
    """``gent_lock_margin`` (the Gent factor of the Chapter 3 membrane kernels) is
    ``mu/2 / (dWs/dI1)`` of the Gent energy (3.23), the derivative by complex step (exact
    to rounding: no subtraction)."""
    h = 1e-30
    dW = E.gent(I1 + 1j * h, mu=GENT.mu, Jm=GENT.Jm, xp=E.NUMPY).imag / h
    margin = E.gent_lock_margin(I1, kappa=1 / GENT.Jm)
    assert margin == pytest.approx(0.5 * GENT.mu / dW, rel=BACKEND_RTOL)


def test_numpy_kinematics_of_the_expressions_are_the_library_invariants():
    """``energies.invariants`` (numpy) is the library's closed-form I1, I2, I3 = J^2, I4, I5
    of both numberings (iso: I4 = D.D; ti: I4 = A.CA, I6 = D.D)."""
    rng = np.random.default_rng(3)
    F = np.eye(3) + 0.2 * rng.standard_normal((3, 3))
    D, A = rng.standard_normal(3), np.array([0.0, 0.6, 0.8])
    got = E.invariants(F, D, A, xp=E.NUMPY)
    iso = closed_form_invariants(F, D, numbering="iso")
    ti = closed_form_invariants(F, D, A, numbering="ti")
    want = {"I1": iso[0], "I2": iso[1], "J": math.sqrt(iso[2]), "DD": iso[3], "DCD": iso[4],
            "ACA": ti[3]}
    assert ti[5] == pytest.approx(iso[3], rel=1e-14)
    for k, w in want.items():
        assert got[k] == pytest.approx(w, rel=1e-13), k


# ------------------------------------------------------------- materials
def _state(mat, data):
    F = data.draw(isochoric_deformation_gradients(0.7, 1.6) if mat.incompressible
                  else deformation_gradients(0.8, 1.3))
    D = data.draw(lagrangian_displacements(1.0)) * math.sqrt(mat.eps * (mat.shear_modulus
                                                                        or NH.mu))
    return F, D


def _ngsolve_energy(mat, F, D):
    return _value(ngf.energy_cf(mat, _cf(F), _cf(D)))


@pytest.mark.parametrize("name", NAMES)
@settings(max_examples=20)
@given(data=st.data())
def test_numpy_and_ngsolve_energies_of_each_material_agree(name, data):
    """``mat.energy`` (numpy) equals ``ngsolve_forms.energy_cf`` (NGSolve) at drawn states:
    to BACKEND_RTOL, Ogden to the O(delta^2) of its averaged spectral perturbation."""
    mat = MATERIALS[name]
    F, D = _state(mat, data)
    want = mat.energy(F, D)
    scale = max(abs(want), mat.shear_modulus or 1.0)
    rtol = OGDEN_PERTURBATION_RTOL if name == "ogden_ideal_dielectric" else BACKEND_RTOL
    assert abs(_ngsolve_energy(mat, F, D) - want) <= rtol * scale


#: the stress and moduli by the jets of the expression and by the hand derivation are two
#: double-precision evaluations of the same derivatives: a few ulp each, amplified by the
#: same cancellations as BACKEND_RTOL; relative to each block's largest entry
DERIVATIVE_RTOL = 1e-12
INVARIANT_NAMES = [n for n in NAMES if hasattr(MATERIALS[n], "invariant_derivatives")]


@pytest.mark.parametrize("name", INVARIANT_NAMES)
@settings(max_examples=15)
@given(data=st.data())
def test_response_from_the_expression_is_the_hand_derived_one(name, data):
    """``mat.response`` (forward differentiation of the one expression) equals
    ``mat.invariant_response`` (the hand-written W_n, W_mn and the chain rule (2.68)-(2.70))
    at drawn states: W, P, E_L, AA, AAA, A."""
    mat = MATERIALS[name]
    F, D = _state(mat, data)
    auto, hand = mat.response(F, D), mat.invariant_response(F, D)
    for block in ("W", "P", "E_L", "AA", "AAA", "A"):
        a, b = np.asarray(getattr(auto, block)), np.asarray(getattr(hand, block))
        scale = max(np.max(np.abs(b)), 1e-300)
        assert np.max(np.abs(a - b)) <= DERIVATIVE_RTOL * scale, (name, block)


@settings(max_examples=20)
@given(data=st.data())
def test_ogden_expression_at_unperturbed_eigenvalues_agrees_to_rounding(data):
    """The one Ogden expression (5.26) + k/2 (J-1)^2 + (5.9), evaluated by NGSolve at the
    closed-form eigenvalues of Cbar (no perturbation), equals the library's numpy energy to
    BACKEND_RTOL at drawn states with distinct eigenvalues (gaps above EIGEN_GAP_MIN; at
    equal ones the closed form's acos has an infinite slope: the reason for the
    perturbation)."""
    F, D = _state(OGDEN, data)
    gaps = np.diff(np.linalg.eigvalsh(E.isochoric_right_cauchy_green(F.T @ F,
                                                                      np.linalg.det(F))))
    assume(np.min(gaps) > EIGEN_GAP_MIN)
    Fcf, Dcf = _cf(F), _cf(D)
    I = E.invariants(Fcf, Dcf, xp=ngf.NGSOLVE)
    cbar = ngf.symmetric_eigenvalues(E.isochoric_right_cauchy_green(Fcf.trans * Fcf, I["J"]))
    got = (E.ogden(cbar, I["J"], alphas=OGDEN.alphas, mus=OGDEN.mus, k=OGDEN.k)
           + E.ideal_dielectric(I["DCD"], I["J"], eps=OGDEN.eps))
    want = OGDEN.energy(F, D)
    assert abs(_value(got) - want) <= BACKEND_RTOL * max(abs(want), OGDEN.shear_modulus)


# ------------------------------------------------------------- defined once
PARTS = {
    "gent_ideal_dielectric": ("gent", "ideal_dielectric"),
    "neo_hookean_ideal_dielectric": ("neo_hookean_isochoric", "volumetric", "ideal_dielectric"),
    "ogden_ideal_dielectric": ("ogden_isochoric_from_power_sums", "volumetric",
                               "ideal_dielectric"),
    "ideal_dielectric": ("ideal_dielectric",),
    "ti_neo_hookean_dielectric": ("ti_neo_hookean_elastic", "dorfmann_ogden_electric"),
    "dorfmann_ogden_electric": ("dorfmann_ogden_electric",),
    "mooney_rivlin_ideal_dielectric": ("mooney_rivlin_isochoric", "volumetric",
                                       "ideal_dielectric"),
}
"""The functions of ``energies`` each material's energy is built from."""


def _double(monkeypatch, part):
    orig = getattr(E, part)
    monkeypatch.setattr(E, part, lambda *a, **kw: 2 * orig(*a, **kw))


def _fixed_state(mat):
    F = np.array([[1.2, 0.1, 0.05], [-0.08, 0.9, 0.1], [0.02, -0.1, 1.05]])
    if mat.incompressible:
        F = F / np.cbrt(np.linalg.det(F))
    D = np.array([0.3, -0.5, 0.6]) * math.sqrt(mat.eps * (mat.shear_modulus or NH.mu))
    return F, D


def test_every_material_lists_its_parts():
    """Meta-test: every material of MATERIALS is in the mutation test."""
    assert sorted(PARTS) == NAMES


@pytest.mark.parametrize(("name", "part"),
                         [(n, p) for n, parts in PARTS.items() for p in parts])
def test_doubling_one_expression_moves_numpy_and_ngsolve_energies_alike(name, part,
                                                                       monkeypatch):
    """The numpy library and the NGSolve form draw the energy from the same function:
    doubling it changes both by the same (nonzero) amount."""
    mat = MATERIALS[name]
    F, D = _fixed_state(mat)
    before = mat.energy(F, D), _ngsolve_energy(mat, F, D)
    _double(monkeypatch, part)
    after = mat.energy(F, D), _ngsolve_energy(mat, F, D)
    d_np, d_ng = after[0] - before[0], after[1] - before[1]
    rtol = OGDEN_PERTURBATION_RTOL if name == "ogden_ideal_dielectric" else BACKEND_RTOL
    assert d_np != 0
    assert abs(d_np - d_ng) <= rtol * max(abs(before[0]), mat.shear_modulus or 1.0)


@pytest.mark.parametrize("part", ["gent", "membrane_electric", "zhao_suo_permittivity"])
def test_membrane_energy_of_the_library_and_of_the_fe_is_one_expression(part, monkeypatch):
    """(3.20) with (3.23), (3.27): ``GentMembrane.free_energy`` (numpy) and the CFs of the
    Ch. 3 membrane FE (``circular.fe.energy_cf``, ``w = Ws + I4 dW/dI4``) move together.
    (The FE's I1 is the library's ``invariants`` at F = diag(l1, l2, 1/(l1 l2)), the
    membrane's ``membrane_first_invariant``: the next test shows them equal.)"""
    l1, l2, I4 = 1.7, 2.3, 0.04

    def both():
        ws, we = circular_fe.energy_cf(_cf(l1), _cf(l2), FE_MEMBRANE)
        return MEMBRANE.free_energy(l1, l2, I4), _value(ws) + I4 * _value(we)

    before = both()
    assert before[1] == pytest.approx(before[0], rel=BACKEND_RTOL)
    _double(monkeypatch, part)
    after = both()
    assert after[0] != before[0]
    assert after[1] == pytest.approx(after[0], rel=BACKEND_RTOL)


@settings(max_examples=30)
@given(l1=st.floats(0.3, 6.0), l2=st.floats(0.3, 6.0))
def test_membrane_first_invariant_is_the_invariant_of_the_membrane_stretch(l1, l2):
    """``membrane_first_invariant(l1, l2)`` (Sec. 3.3.2) is ``I1 = tr C`` of the library's
    ``invariants`` at F = diag(l1, l2, 1/(l1 l2)) (to rounding: a few ulps of I1)."""
    F = np.diag([l1, l2, 1 / (l1 * l2)])
    want = E.invariants(F, xp=E.NUMPY)["I1"]
    assert E.membrane_first_invariant(l1, l2) == pytest.approx(want, rel=1e-14)


@pytest.mark.parametrize(("mat", "part"),
                         [(NeoHookean(), p) for p in ("neo_hookean_isochoric", "volumetric",
                                                      "ideal_dielectric_enthalpy")]
                         + [(Ogden(), p) for p in ("ogden_isochoric_from_power_sums",
                                                   "volumetric", "ideal_dielectric_enthalpy")])
def test_chapter_5_enthalpy_of_the_closed_forms_and_of_the_fe_is_one_expression(mat, part,
                                                                             monkeypatch):
    """The electric enthalpy ``W_mech - eps/2 J C^-1:(E_L x E_L)`` assembled by the Ch. 5
    FE (``buckling.energy.enthalpy_cf``) and its numpy closed form
    (``buckling.analytic.enthalpy_numpy``) move together."""
    eps = NH.eps
    F, _ = _fixed_state(mat)
    E_hat = np.array([0.1, 0.05, 0.3])
    E_L = E_hat * math.sqrt(MU_REF / eps)

    def both():
        return (analytic.enthalpy_numpy(F, E_L, mat, eps) / MU_REF,
                _value(energy.enthalpy_cf(_cf(F), _cf(E_hat), mat)))

    rtol = BACKEND_RTOL if isinstance(mat, NeoHookean) else OGDEN_PERTURBATION_RTOL
    before = both()
    assert before[1] == pytest.approx(before[0], rel=rtol)
    _double(monkeypatch, part)
    after = both()
    assert after[0] != before[0]
    assert after[1] - before[1] == pytest.approx(after[0] - before[0], rel=rtol, abs=rtol)


PARAMETER_NAMES = {"mu", "mus", "k", "eps", "eps_bar", "Jm", "xi", "alpha", "alphas", "beta",
                   "c", "C10", "D1"}
"""Names of material parameters (arguments and dataclass fields)."""


def _arithmetic_on_parameters(source: str) -> list[str]:
    """Expressions in ``source`` that compute with a material parameter (a formula)."""
    bad = []
    for node in ast.walk(ast.parse(source)):
        operands = ((node.left, node.right) if isinstance(node, ast.BinOp)
                    else (node.operand,) if isinstance(node, ast.UnaryOp) else ())
        for x in operands:
            name = x.id if isinstance(x, ast.Name) else getattr(x, "attr", None)
            if name in PARAMETER_NAMES:
                bad.append(ast.unparse(node))
    return bad


def test_ngsolve_forms_write_no_energy_of_their_own():
    """The NGSolve forms (and the Ch. 3 FE's membrane CF) only pass parameters on to
    ``energies``: no arithmetic on a material parameter."""
    import textwrap

    assert _arithmetic_on_parameters("x = mu * I1 / 2") == ["mu * I1"]   # the check bites
    assert not _arithmetic_on_parameters(inspect.getsource(ngf))
    assert not _arithmetic_on_parameters(textwrap.dedent(
        inspect.getsource(circular_fe.energy_cf)))


def test_no_material_constant_is_written_as_a_literal_outside_constants():
    """Every float literal of ``models`` that equals a material constant of
    :mod:`debench.models.materials.constants` (up to sign) is the constants module's own."""
    values = {K.VACUUM_PERMITTIVITY, K.EPS_R_ASSUMED, K.VHB_SHEAR_MODULUS, K.VHB_GENT_JM,
              K.TABLE_5_1_NH_SHEAR_MODULUS, K.TABLE_5_1_BULK_MODULUS,
              *K.TABLE_5_1_OGDEN_ALPHAS, *K.TABLE_5_1_OGDEN_MUS,
              *(c for _, c in K.TABLE_3_1)}
    values |= {-x for x in values}
    root = pathlib.Path(debench.models.__file__).parent
    found = []
    for path in sorted(root.rglob("*.py")):
        if path.name == "constants.py" and path.parent.name == "materials":
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if (isinstance(node, ast.Constant) and type(node.value) is float
                    and node.value in values):
                found.append(f"{path.relative_to(root)}:{node.lineno}: {node.value}")
    assert not found, "\n".join(found)
