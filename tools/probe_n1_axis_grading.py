"""Does the wavenumber-1 critical voltage of the axisymmetric model converge?

    python tools/probe_n1_axis_grading.py [ORDER ...]

adds ``k`` geometric layers (ratio 1/4) towards the axis inside the first radial element of
the section mesh (``AxisymDiscretisation(axis_layers=k)``) and computes the critical
voltages of n = 0 and n = 1 of the perfect neo-Hookean film (t0 = 1 mm, R/t0 = 10, 4 rim
and face layers), then the lowest eigenvalues of n = 0, 1, 2, 3, 7 of the flat film at v = 0.25.

Measured (one thread, load ~1-2; CPU s per pair of critical voltages in brackets):

    p  axis layers:   0            4            8            12
    3  n = 1   0.3003188    0.2950966    0.2939457    0.2934204   (4.9 .. 8.9 s)
    4  n = 1   0.2990475    0.2949145    0.2938609    0.2933675   (10 .. 42 s)
    5  n = 1   0.2983271    0.2947968    0.2938106    0.2933391   (42 .. 75 s)
       n = 0   0.22027113 at every layer count (p = 5; changes <= 2e-10)

and at v = 0.25 (p = 3) lambda_1 = 4.357e-3, 3.891e-3, 3.789e-3 for 0, 4, 8 axis layers,
while lambda_0, lambda_2, lambda_3, lambda_7 agree to 7 digits. So only wavenumber 1 needs
resolution at the axis, and with it its critical voltage keeps falling (by 1.2e-3, 5.3e-4,
4.7e-4 t0-normalised per 4 layers at p = 5) without a visible limit: the curated n = 1
values (no axis grading: 0.2978424 at p = 6, error estimate 6.0e-4) and the n = 1
eigenvalues along the path are too high by more than their estimates (measured separately on
the imperfect R/t0 = 10 paths at order 3, 4 layers: lambda_1 at the voltage maximum 1.19076e-2
-> 1.16083e-2 (NH) and 5.34304e-3 -> 5.21018e-3 (Ogden) with 8 axis layers, -2.5 %, the
maximum itself and lambda_2, lambda_3 there unchanged). Not explained: the
n = 1 axis conditions (S = U + V = 0, W = Q = 0, D = U - V free) admit the smooth n = 1
modes; whether the decrease converges (an axis boundary layer of the physical mode) or not
(a singular, non-physical minimiser of the discrete condensed tangent) is open.
"""

from __future__ import annotations

import sys
import time

from debench.models.buckling import axisym as ax
from debench.models.buckling.parameters import NeoHookean, Plate
from debench.reference.tasks import limit_threads

LAYERS = (0, 4, 8, 12)
PLATE = Plate(thickness=1e-3, aspect=10.0)


def main(argv: list[str]) -> int:
    limit_threads()
    orders = [int(a) for a in argv] or [3, 4]
    for p in orders:
        for k in LAYERS:
            d = ax.AxisymDiscretisation(order=p, edge_layers=4, face_layers=4, axis_layers=k)
            t = time.process_time()
            r0 = ax.critical_voltage(PLATE, NeoHookean(), d, n=0)
            r1 = ax.critical_voltage(PLATE, NeoHookean(), d, n=1, v_start=1.34 * r0.v)
            print(f"p = {p}, {k:2d} axis layers: v_cr n = 0 {r0.v:.10f}, n = 1 "
                  f"{r1.v:.10f} ({time.process_time() - t:.1f} s CPU)", flush=True)
            if p == orders[0]:
                m = ax.AxisymModel(PLATE, NeoHookean(), d, with_imperfection=False)
                m.set_voltage(0.25)
                m.newton()
                lam = {n: m.spectrum(n, nev=1).lam[0] for n in (0, 1, 2, 3, 7)}
                print("    at v = 0.25: " + ", ".join(f"lambda_{n} {x:.6e}"
                                                   for n, x in lam.items()), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
