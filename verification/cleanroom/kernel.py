"""Clean-room ch2_kernel_states, written from ``debench problems ch2_kernel_states
--markdown`` only (mpmath; nothing from debench).

The page: six energies W(F, D_L) with their parameters, the five states (F, D_L), the
incompressible ones extended off J = 1 as written and their stress taken at p = 0,
sigma = J^-1 (dW/dF) F^T. Here dW/dF is taken by mpmath's numerical differentiation in
DIGITS digits (no closed-form stress is used), so the result is independent of any
hand-derived stress.
"""

from __future__ import annotations

import mpmath as mp

DIGITS = 30
EPS = mp.mpf("4.1595e-11")
STATES = {
    "reference": ((1, 1), 0, (0, 0, 0)),
    "uniaxial_1p5": ((mp.mpf("1.5"), mp.mpf("1.5") ** mp.mpf("-0.5")), 0, (0, 0, 0)),
    "equibiaxial_2_poled": ((2, 2), 0, (0, 0, mp.mpf("0.5"))),
    "simple_shear_0p5_poled": ((1, 1), mp.mpf("0.5"), (0, mp.mpf("0.3"), mp.mpf("0.4"))),
    "general": ((mp.mpf("1.3"), mp.mpf("0.9")), mp.mpf("0.2"),
                (mp.mpf("0.2"), mp.mpf("-0.1"), mp.mpf("0.6"))),
}
OGDEN_ALPHAS = (mp.mpf("1.293"), mp.mpf("2.3252"), mp.mpf("2.561"))
OGDEN_MUS = (mp.mpf(8580), mp.mpf(84300), mp.mpf(-23300))
K_BULK = mp.mpf("7748003.92")


def _invariants(F, D):
    C = F.T * F
    I1 = C[0, 0] + C[1, 1] + C[2, 2]
    J = mp.det(F)
    I5 = (D.T * C * D)[0]
    I4iso = (D.T * D)[0]
    return C, I1, J, I5, I4iso


def _gent(F, D):
    C, I1, J, I5, _ = _invariants(F, D)
    mu, Jm = mp.mpf(51000), mp.mpf(120)
    return -mu * Jm / 2 * mp.log(1 - (I1 - 3) / Jm) + I5 / (2 * EPS)


def _neo_hooke(F, D):
    C, I1, J, I5, _ = _invariants(F, D)
    mu = mp.mpf(156000)
    return (mu / 2 * (J ** (-mp.mpf(2) / 3) * I1 - 3) + K_BULK / 2 * (J - 1) ** 2
            + I5 / (2 * EPS * J))


def _ogden(F, D):
    C, I1, J, I5, _ = _invariants(F, D)
    ev = mp.eigsy(C, eigvals_only=True)
    lam = [mp.sqrt(e) for e in ev]
    W = mp.mpf(0)
    for a, m in zip(OGDEN_ALPHAS, OGDEN_MUS, strict=True):
        W += 2 * m / a**2 * (sum((J ** (-mp.mpf(1) / 3) * x) ** a for x in lam) - 3)
    return W + K_BULK / 2 * (J - 1) ** 2 + I5 / (2 * EPS * J)


def _ideal(F, D):
    C, I1, J, I5, _ = _invariants(F, D)
    return I5 / (2 * EPS * J)


def _ti(F, D):
    C, I1, J, I5, _ = _invariants(F, D)
    mu, xi, beta = mp.mpf(51000), mp.mpf(5), mp.mpf("0.5")
    I4 = C[1, 1]                       # A = e2: A.C A
    return mu / 2 * (I1 - 3) + mu * xi / 2 * (I4 - 1) ** 2 + beta * I5 / (2 * EPS)


def _dorfmann_ogden(F, D):
    C, I1, J, I5, I4 = _invariants(F, D)
    return (mp.mpf("0.3") * I4 + mp.mpf("0.5") * I5) / (2 * EPS)


#: name: (energy, shear modulus that scales D_L)
MATERIALS = {
    "gent_ideal_dielectric": (_gent, mp.mpf(51000)),
    "neo_hookean_ideal_dielectric": (_neo_hooke, mp.mpf(156000)),
    "ogden_ideal_dielectric": (_ogden, sum(OGDEN_MUS)),
    "ideal_dielectric": (_ideal, mp.mpf(100000)),
    "ti_neo_hookean_dielectric": (_ti, mp.mpf(51000)),
    "dorfmann_ogden_electric": (_dorfmann_ogden, mp.mpf(100000)),
}


def state(material: str, name: str):
    """(F, D_L) of the page's loading for ``material`` (D_L = d sqrt(eps mu_0))."""
    (l1, l2), gamma, d = STATES[name]
    l1, l2, gamma = mp.mpf(l1), mp.mpf(l2), mp.mpf(gamma)
    F = mp.matrix([[l1, gamma * l2, 0], [0, l2, 0], [0, 0, 1 / (l1 * l2)]])
    scale = mp.sqrt(EPS * MATERIALS[material][1])
    return F, mp.matrix([mp.mpf(x) * scale for x in d])


def energy(material: str, name: str) -> float:
    with mp.workdps(DIGITS):
        F, D = state(material, name)
        return float(MATERIALS[material][0](F, D))


def stress(material: str, name: str) -> list[list[float]]:
    """sigma = J^-1 (dW/dF) F^T at p = 0 (3 x 3, rows i, columns alpha)."""
    with mp.workdps(DIGITS):
        F, D = state(material, name)
        W = MATERIALS[material][0]
        P = mp.matrix(3, 3)
        for i in range(3):
            for a in range(3):
                def f(x, i=i, a=a):
                    G = F.copy()
                    G[i, a] = x
                    return W(G, D)
                P[i, a] = mp.diff(f, F[i, a])
        sig = P * F.T / mp.det(F)
        return [[float(sig[i, a]) for a in range(3)] for i in range(3)]
