"""Checks of the Chapter 4 errata: one function per erratum, called by its producer and by
its evidence test (``verification/test_ch4_derivation.py``).

Each check evaluates the printed form and the form re-derived from the energy (4.22) on
a grid of stretches and anisotropies and returns an :class:`ErratumCheck`: whether the
printed form is wrong, whether the corrected form is right, and the measured residuals.
The status is computed from those two booleans (``confirmed`` only when the printed form
fails and the corrected one holds; ``refuted`` when the printed form holds).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from debench.models.invariants import printed as pr
from debench.models.plate import PlateParams, coefficients
from debench.models.plate.analysis import thin_limit
from debench.models.plate.ansatz import critical_stretches, row_coefficients
from debench.models.plate.coefficients import printed_coefficients, reduced_quartic

#: exact algebra in floating point on O(10) numbers: rounding ~1e-15, 100x margin
ALG_TOL = 1e-12
#: finite differences of second order, step 1e-5 on O(1) quantities: truncation
#: ~h^2 |w'''| ~ 1e-9 and rounding ~eps/h ~ 1e-11
FD_TOL = 1e-6
#: roots refined by brentq to xtol 1e-13; a residual of the symbol below this is a root
ROOT_TOL = 1e-7
#: a printed form that is wrong misses a term of size >= 2 xi lam^-8 >= 1e-2 on the grid
WRONG = 1e-3
LAMS = (0.7, 1.0, 1.3, 2.1)
XIS = (0.0, 3.0, 5.0, 10.0)


@dataclass(frozen=True)
class ErratumCheck:
    printed_wrong: bool
    corrected_right: bool
    details: dict = field(default_factory=dict)

    @property
    def confirmed(self) -> bool:
        return self.printed_wrong and self.corrected_right


def b_c_terms(lam: float, xi: float, D: float = 1.3, beta: float = 0.5) -> np.ndarray:
    """Derived minus printed coefficients (a, 2b, c, d, e, f, g) of (4.54)-(4.60)."""
    der = coefficients(np.array(lam), PlateParams(xi, D, beta, 0.0, "derived"))
    pri = printed_coefficients(np.array(lam), xi, 0.0, beta, D)
    return np.array(der, float) - np.array(pri, float)


def eq4_55_b() -> ErratumCheck:
    """(4.55): the printed 2b lacks -2 xi lam^-4 (the I4 - 1 term of (4.22))."""
    miss = [b_c_terms(lam, xi)[1] + 2 * xi * lam**-4 for lam in LAMS for xi in XIS]
    diff = [b_c_terms(lam, xi)[1] for lam in LAMS for xi in XIS]
    return ErratumCheck(max(abs(d) for d in diff) > WRONG,
                        max(abs(m) for m in miss) < ALG_TOL * 100,
                        {"max_abs_printed_minus_derived": max(abs(d) for d in diff),
                         "max_abs_residual_of_correction": max(abs(m) for m in miss)})


def lateral_stress_identity(lam: float, xi: float, D: float = 1.1, beta: float = 0.5,
                            h: float = 1e-5) -> tuple[float, float]:
    """(a - c) - tau11 for the derived and the printed coefficients.

    A0_1212 - A0_2121 = tau11 - tau22 is a universal identity of incremental elasticity;
    tau11 = (lam/2) dw/dlam of (4.28) at fixed D_L2 (central difference) and tau22 = 0.
    """
    DL2 = lam**2 * D

    def w(x):  # (4.28), mu = eps = 1, alpha = 0
        return (0.5 * (2 * x**2 + x**-4 - 3) + 0.5 * xi * (x**-8 - 2 * x**-4 + 1)
                + beta * x**-4 * DL2**2 / 2)

    tau11 = lam / 2 * (w(lam + h) - w(lam - h)) / (2 * h)
    a, _, c, *_ = coefficients(np.array(lam), PlateParams(xi, D, beta, 0.0, "derived"))
    ap, _, cp, *_ = printed_coefficients(np.array(lam), xi, 0.0, beta, D)
    return float(a - c) - tau11, float(ap - cp) - tau11


def eq4_56_c() -> ErratumCheck:
    """(4.56): the printed c violates A0_1212 - A0_2121 = tau11 (by -2 xi lam^-4)."""
    res = [lateral_stress_identity(lam, xi) for lam in LAMS for xi in XIS]
    der = max(abs(r[0]) for r in res)
    pri = max(abs(r[1]) for r in res)
    return ErratumCheck(pri > WRONG, der < FD_TOL,
                        {"max_identity_residual_derived": der,
                         "max_identity_residual_printed": pri})


def symbol_det(s, cf):
    """det of the 2x2 symbol M(s) of the plane-strain incremental equations (4.61)."""
    a, b2, c, d, e, f, g = cf
    return (a - b2 * s**2 + c * s**4) * (f * s**2 - g) - (s * (e - d - d * s**2))**2


def bicubic_residuals(xi: float, lam: float = 1.2, D: float = 2.0) -> dict[str, float]:
    """Residuals of the symbol at the roots of the printed and derived quartics (4.63)."""
    der = coefficients(np.array(lam), PlateParams(xi, D, 0.5, 0.0, "derived"))
    pri = printed_coefficients(np.array(lam), xi, 0.0, 0.5, D)
    out = {}
    for name, variant in (("printed", "literal"), ("derived", "derived")):
        qa, qb, qc = reduced_quartic(np.array(lam), PlateParams(xi, D, variant=variant))
        s = np.sqrt(np.roots([float(qc), -float(qb), float(qa)]).astype(complex))
        out[f"{name}_roots_on_derived_symbol"] = float(np.max(np.abs(symbol_det(s, der))))
        out[f"{name}_roots_on_printed_symbol"] = float(np.max(np.abs(symbol_det(s, pri))))
    out["s1_on_derived_symbol"] = float(abs(symbol_det(1.0, der)))
    return out


def eq4_63_bicubic() -> ErratumCheck:
    """(4.63): the printed roots annihilate the printed symbol, not the derived one."""
    res = {xi: bicubic_residuals(xi) for xi in XIS if xi > 0}
    wrong = min(r["printed_roots_on_derived_symbol"] for r in res.values())
    right = max(r["derived_roots_on_derived_symbol"] for r in res.values())
    return ErratumCheck(wrong > WRONG, right < ROOT_TOL,
                        {"min_printed_root_residual": wrong, "max_derived_root_residual": right})


def literal_rows_vs_beta(D: float, kH: float = 1.5) -> dict[str, np.ndarray]:
    """Critical stretches at xi = 0 with the literal rows, beta = 1, and beta = 0.5 at
    Dhat sqrt(2) and at Dhat."""
    return {
        "literal": critical_stretches(kH, PlateParams(0.0, D, variant="literal")).lam,
        "beta_one": critical_stretches(kH, PlateParams(0.0, D, beta=1.0,
                                                       variant="derived")).lam,
        "beta_half_D_sqrt2": critical_stretches(kH, PlateParams(0.0, D * np.sqrt(2), 0.5,
                                                                variant="derived")).lam,
        "stated": critical_stretches(kH, PlateParams(0.0, D, 0.5, variant="derived")).lam,
    }


def _maxrel(a: np.ndarray, b: np.ndarray) -> float:
    if a.size != b.size:
        return np.inf
    return float(np.max(np.abs(a - b) / np.abs(b))) if a.size else 0.0


def eq4_75_80_beta() -> ErratumCheck:
    """(4.75)-(4.80): the literal rows are the consistent rows with beta = 1."""
    rel_b1, rel_stated = 0.0, np.inf
    for D in (1.0, 2.0, 3.0):
        r = literal_rows_vs_beta(D)
        rel_b1 = max(rel_b1, _maxrel(r["literal"], r["beta_one"]),
                     _maxrel(r["literal"], r["beta_half_D_sqrt2"]))
        rel_stated = min(rel_stated, _maxrel(r["literal"], r["stated"]))
    return ErratumCheck(rel_stated > 1e-3, rel_b1 < 1e-9,
                        {"max_rel_literal_vs_beta_one": rel_b1,
                         "min_rel_literal_vs_stated_beta": rel_stated})


def normal_traction_xi_term(lam: float, xi: float = 5.0) -> float:
    """(2b + c) from the printed (4.55)-(4.56) minus the literal (4.76) coefficient."""
    c, b2, *_ = row_coefficients(np.array(lam), PlateParams(xi, 0.0, 1.0, variant="printed"))
    c_l, b2_l, *_ = row_coefficients(np.array(lam), PlateParams(xi, 0.0, variant="literal"))
    return float(b2 + c) - float(b2_l + c_l)


def eq4_76_xi_term() -> ErratumCheck:
    """(4.76) prints 6 xi lam^-8 where the printed (4.55)+(4.56) give 8 xi lam^-8."""
    xi = 5.0
    res = [normal_traction_xi_term(lam, xi) - 2 * xi * lam**-8 for lam in LAMS]
    diff = [normal_traction_xi_term(lam, xi) for lam in LAMS]
    return ErratumCheck(min(abs(d) for d in diff) > WRONG,
                        max(abs(r) for r in res) < ALG_TOL * 100,
                        {"min_abs_difference": min(abs(d) for d in diff),
                         "max_residual_2_xi_lam^-8": max(abs(r) for r in res)})


def s_one_mode(xi: float, variant: str, lam: float = 1.15) -> dict[str, float]:
    """M(1) residuals of the electric mode (0, 1) and of the printed mechanical mode (1, 0),
    and a - 2b + c + 4 xi lam^-8."""
    a, b2, c, d, e, f, g = (float(x) for x in coefficients(
        np.array(lam), PlateParams(xi, 2.0, variant=variant)))
    M1 = np.array([[a - b2 + c, e - 2 * d], [e - 2 * d, f - g]])
    return {"electric_residual": float(np.linalg.norm(M1 @ [0.0, 1.0])),
            "mechanical_residual": float(np.linalg.norm(M1 @ [1.0, 0.0])),
            "a_2b_c_plus_4xi_lam^-8": a - b2 + c + 4 * xi * lam**-8}


def eq4_81_amplitude() -> ErratumCheck:
    """(4.81): at s = +-1 the mode is electric, (A, B) = (0, 1), for xi > 0."""
    res = [s_one_mode(xi, v) for xi in XIS if xi > 0 for v in ("derived", "printed")]
    return ErratumCheck(min(r["mechanical_residual"] for r in res) > WRONG,
                        max(r["electric_residual"] for r in res) < ALG_TOL,
                        {"min_mechanical_residual": min(r["mechanical_residual"] for r in res),
                         "max_electric_residual": max(r["electric_residual"] for r in res)})


def dI4_dF(seed: int = 38, h: float = 1e-6) -> dict[str, np.ndarray]:
    """Printed (as extracted) and corrected dI4/dF and a central difference of
    I4 = A.F^T F A at a seeded state."""
    rng = np.random.default_rng(seed)
    F = np.eye(3) + 0.3 * rng.standard_normal((3, 3))
    a = rng.standard_normal(3)
    a /= np.linalg.norm(a)
    fd = np.zeros((3, 3))
    for i in range(3):
        for al in range(3):
            E = np.zeros((3, 3))
            E[i, al] = h
            fd[i, al] = ((a @ (F + E).T @ (F + E) @ a) - (a @ (F - E).T @ (F - E) @ a)) / (2 * h)
    return {"printed": np.outer(F @ a - F @ a, a), "corrected": 2 * np.outer(F @ a, a),
            "fd": fd}


def eq4_38_dI4() -> ErratumCheck:
    """(4.38) as extracted is identically zero; 2 F_ik a_k a_a matches the difference."""
    r = dI4_dF()
    err_p = float(np.abs(r["printed"] - r["fd"]).max())
    err_c = float(np.abs(r["corrected"] - r["fd"]).max())
    return ErratumCheck(err_p > WRONG, err_c < FD_TOL,
                        {"printed_error": err_p, "corrected_error": err_c})


CHECKS = {
    "eq4_55_b": eq4_55_b, "eq4_56_c": eq4_56_c, "eq4_63_bicubic": eq4_63_bicubic,
    "eq4_75_80_beta": eq4_75_80_beta, "eq4_76_xi_term": eq4_76_xi_term,
    "eq4_81_amplitude": eq4_81_amplitude, "eq4_38_dI4": eq4_38_dI4,
}


# --------------------------------------------------------------------------- root causes
def c_misses_the_term_b_misses() -> bool:
    """(4.56) is the root error of (4.55) again: on the grid, the derived minus printed c
    equals the derived minus printed 2b, and both are -2 xi lam^-4."""
    return all(abs(t[2] - t[1]) < ALG_TOL * 100 and abs(t[1] + 2 * xi * lam**-4) < ALG_TOL * 100
               for lam in LAMS for xi in XIS for t in [b_c_terms(lam, xi)])


def bicubic_follows_from_printed_b_c() -> bool:
    """(4.63) carries no error of its own: its printed roots annihilate the symbol built
    from the printed (4.54)-(4.60) at every grid point."""
    return all(bicubic_residuals(xi, lam)["printed_roots_on_printed_symbol"] < ROOT_TOL
               for lam in LAMS for xi in XIS)


def ellipticity_loss_is_the_missing_term(xi: float = 5.0, D: float = 0.0,
                                         beta: float = 0.5) -> bool:
    """The TI curves of Figs 4.2/4.5 lie where (4.22) is not strongly elliptic because of the
    term (4.55)-(4.56) omit: at the start of each printed-coefficient upper curve
    (Dhat = 0, 1, 2) c - beta Dhat^2 is positive with the printed c and negative with the
    derived one, which differ by exactly that term."""
    for Dh in (0.0, 1.0, 2.0):
        lam = float(thin_limit(PlateParams(xi, Dh, beta, 0.0, "printed")).max())
        der = coefficients(np.array(lam), PlateParams(xi, Dh, beta, 0.0, "derived"))
        pri = printed_coefficients(np.array(lam), xi, 0.0, beta, Dh)
        if not (float(pri[2]) - beta * Dh**2 > 0 > float(der[2]) - beta * Dh**2):
            return False
    return True


def dI4_is_the_appendix_formula(seed: int = 38) -> bool:
    """(4.38) is the formula (A.4) prints (one transcription serves both labels), and that
    formula evaluates to what the (4.38) check tests: zero at the seeded state."""
    if pr.SAME_FORMULA.get("A.4") != "4.38":
        return False
    rng = np.random.default_rng(seed)
    F = np.eye(3) + 0.3 * rng.standard_normal((3, 3))
    a = rng.standard_normal(3)
    a /= np.linalg.norm(a)
    func = pr.PRINTED_DERIVATIVES["A.4"][3]
    return bool(np.allclose(func(F, np.zeros(3), a), dI4_dF(seed)["printed"], atol=ALG_TOL))


#: the check that an entry's root cause is the erratum it names (entries whose
#: ``root_cause`` is another entry than themselves)
ROOT_CAUSE_CHECKS = {
    "ch4.erratum.eq4_38_dI4": dI4_is_the_appendix_formula,
    "ch4.erratum.eq4_56_c": c_misses_the_term_b_misses,
    "ch4.erratum.eq4_63_bicubic": bicubic_follows_from_printed_b_c,
    "ch4.ellipticity.ti_curves_well_posed": ellipticity_loss_is_the_missing_term,
}
