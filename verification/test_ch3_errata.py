"""Chapter 3 errata: each test is the evidence named in reference/catalogue/ch3.toml."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from debench.models.circular import analysis, law, shooting
from debench.models.circular.actuator import branch, curves
from debench.models.circular.params import Annulus

from verification._loaders import load_script

#: a solution of one ODE fails the other equation by O(1) relative: any threshold far
#: above the RK4 error (1e-6) and far below O(1) separates "satisfies" from "violates"
RESIDUAL_SATISFIED = 1e-4
RESIDUAL_VIOLATED = 1e-2


def _tool():
    return load_script("tools/derive_ch3.py")


def _membrane_residual(an: Annulus, lam: float):
    """Relative residual of d(R T1)/dR - T2 = 0 along the annulus solution of ``an``."""
    br = branch(an, lam=np.array([lam]), steps=1600)
    _, _, t, P1, P2 = shooting.integrate_inward(an, br.q, steps=1600, profile=True)
    l1, l2 = P1[:, 0], P2[:, 0]
    s1, s2, *_ = law.gent_stresses(l1, l2, an.kappa)
    T1, T2 = s1 / l1, s2 / l2
    R = np.exp(t)
    d = np.gradient(R * T1, R, edge_order=2)
    return np.max(np.abs(d - T2)[5:-5]) / np.max(np.abs(T2))


def test_eq_3_33_omits_thickness_gradient():
    """(3.33) d sigma1/dr = (sigma2 - sigma1)/r differs from the thin-membrane balance
    d(R T1)/dR = T2 by -sigma1 (dh/dr)/h (sympy: tools/derive_ch3.py), the annulus
    thickness varies (Fig. 3.3), so the solution of the printed ODE violates the membrane
    balance while the membrane variant satisfies it; and only the printed form reproduces
    the thesis' loss-of-tension stretch 6.73."""
    tool = _tool()
    s1, s2, dl2, printed, membrane = tool.annulus_rhs()
    # (3.34) follows from (3.33); the membrane form does not: checked at drawn points
    dl1 = sp.Symbol("dl1")
    R = tool.R
    eq333 = ((sp.diff(s1, tool.l1) * dl1 + sp.diff(s1, tool.l2) * (tool.l1 - tool.l2))
             / (tool.l1 * R) - (s2 - s1) / (tool.l2 * R))
    f = sp.lambdify((tool.l1, tool.l2, tool.kappa, dl1, R), eq333)
    fp = sp.lambdify((tool.l1, tool.l2, tool.kappa), printed)
    fm = sp.lambdify((tool.l1, tool.l2, tool.kappa), membrane)
    for a, b in ((0.8, 3.0), (2.0, 4.5), (1.5, 1.7)):
        assert abs(f(a, b, 1 / 120, fp(a, b, 1 / 120), 2.0)) < 1e-12
        assert abs(f(a, b, 1 / 120, fm(a, b, 1 / 120), 2.0)) > 1e-3
    assert _membrane_residual(Annulus(3.0, equilibrium="membrane"), 5.0) < RESIDUAL_SATISFIED
    assert _membrane_residual(Annulus(3.0, equilibrium="printed"), 5.0) > RESIDUAL_VIOLATED
    lot = {v: analysis.loss_of_tension_stretch(branch(Annulus(3.0, equilibrium=v)))
           for v in ("printed", "membrane")}
    assert round(lot["printed"], 2) == 6.73
    assert round(lot["membrane"], 2) != 6.73


def test_variant_changes_table():
    """How the thesis numbers change under the consistent membrane balance (the result the
    issue asks for); values asserted against each other, not against constants."""
    out = {}
    for v in ("printed", "membrane"):
        br = branch(Annulus(1.25, equilibrium=v))
        out[v] = curves(br, [0.0])[0].events["pullin"].phibar
    # pull-in voltage at lamP = 1.25 rises with the membrane balance, by ~1 %
    assert out["membrane"] > out["printed"]
    assert 0.001 < out["membrane"] / out["printed"] - 1 < 0.05


def test_eq_3_30_coefficient_is_consistent():
    """(3.21) with (3.27) at l1 = l2 = lambda gives 1 + c(5 lambda/2 - 2), as printed; the
    charge-controlled energy Ws + Dt^2/(2 eps l1^2 l2^2) gives the same."""
    tool = _tool()
    K, Kd = tool.circle_a_coefficient()
    lam, c = tool.lam, tool.c
    printed = 1 + c * (sp.Rational(5, 2) * lam - 2)
    assert sp.simplify(K - printed) == 0
    assert sp.simplify(Kd - printed) == 0


def test_eq_3_27_is_taylor_expansion_of_3_26():
    """The thesis' 'Eq. (17) ... of Eq. (16c)' means (3.27) of (3.26): the first-order
    expansion of eps3 = eps0 + c0(2 l3^2 - l1^2 - l2^2), l3 = 1/(l1 l2), about l1 = l2 = 1
    is eps0 [1 + c (l1 + l2 - 2)] with c = -6 c0/eps0."""
    l1, l2, c0, e0, d1, d2 = sp.symbols("l1 l2 c0 e0 d1 d2")
    eps3 = e0 + c0 * (2 / (l1 * l2) ** 2 - l1**2 - l2**2)
    lin = sp.series(eps3.subs({l1: 1 + d1, l2: 1 + d2}).subs({d1: d1 * sp.Symbol("s"),
                                                            d2: d2 * sp.Symbol("s")}),
                    sp.Symbol("s"), 0, 2).removeO().subs(sp.Symbol("s"), 1)
    zs = e0 * (1 + (-6 * c0 / e0) * (d1 + d2))
    assert sp.simplify(sp.expand(lin - zs)) == 0
    # and the constitutive kernel agrees
    import debench.models.materials.membrane as mm
    jm = mm.JimenezMcMeekingPermittivity(eps0_bar=2.0, c0=0.01)
    assert jm.zhao_suo_linearisation().c == pytest.approx(-6 * 0.01 / 2.0)
    # the producer's check: the statement holds, so the erratum is the equation numbers
    # only (editorial); a different relation between c and c0 fails the check
    from debench.reference import catalogue
    from debench.reference.producers.ch3 import taylor_3_27_of_3_26_holds

    assert taylor_3_27_of_3_26_holds()
    assert taylor_3_27_of_3_26_holds(c0=0.02, eps0=3.0)
    assert not taylor_3_27_of_3_26_holds(factor=-4.0)
    r = catalogue.evaluate(catalogue.by_id()["ch3.erratum.eq_17_16c"])
    assert r.status == "editorial"


def test_c_effects_are_in_section_3_5():
    """Sec. 3.3.4 says the effect of c 'will be discussed in detail in Section 4'; in the
    thesis that discussion is Sec. 3.5 (3.5.2-3.5.6; Chapter IV is the anisotropic plate).
    Evidence from the catalogue's own provenance: every claim about c cites Sec. 3.5.x
    (the check the producer of ch3.erratum.section_4_reference calls), and the check fails
    when one does not."""
    from dataclasses import replace

    from debench.reference.producers.ch3 import c_effect_claims, c_effects_cited_in_section_3_5

    claims = c_effect_claims()
    assert len(claims) >= 8
    assert c_effects_cited_in_section_3_5(claims)
    moved = [replace(claims[0], source={**claims[0].source, "section": "4.2"})] + claims[1:]
    assert not c_effects_cited_in_section_3_5(moved)
