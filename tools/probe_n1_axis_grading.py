"""Does the wavenumber-1 critical voltage of the axisymmetric model depend on the axis mesh?

    python tools/probe_n1_axis_grading.py [ORDER ...]

adds ``k`` geometric layers (ratio 1/4) towards the axis inside the first radial element of
the section mesh (``AxisymDiscretisation(axis_layers=k)``) and computes the critical
voltages of n = 0 and n = 1 of the perfect neo-Hookean film (t0 = 1 mm, R/t0 = 10, 4 rim
and face layers), then the lowest eigenvalues of n = 0, 1, 2, 3, 7 of the flat film at v = 0.25.

Measured (one thread, load ~1; CPU s per pair of critical voltages in brackets):

    p  axis layers:   0             4             8
    3  n = 1   0.2920120851  0.2920120848  0.2920120847   (4.3 .. 6.6 s)
    4  n = 1   0.2920054679  0.2920054679  0.2920054679   (9.4 .. 16 s)
       n = 0   0.2202719725 .. 0.2202719723 (p = 4)

so neither wavenumber needs resolution at the axis: the n = 1 axis conditions (S = U + V = 0,
W = Q = 0, D = U - V free) admit the smooth fields, including the sideways translation of the
axis (D constant, S = 0). A space that pins D instead of S on the axis excludes that
translation; only a layer of vanishing width next to the axis can mimic it (the axis has zero
capacity), so its n = 1 critical voltage converges logarithmically from above: measured with
that space, p = 5: 0.2983271, 0.2947968, 0.2938106, 0.2933391 for 0, 4, 8, 12 layers.
"""

from __future__ import annotations

import sys
import time

from debench.models.buckling import axisym as ax
from debench.models.buckling.parameters import NeoHookean, Plate
from debench.reference.tasks import limit_threads

LAYERS = (0, 4, 8)
PLATE = Plate(thickness=1e-3, aspect=10.0)


def main(argv: list[str]) -> int:
    limit_threads()
    orders = [int(a) for a in argv] or [3, 4]
    for p in orders:
        for k in LAYERS:
            d = ax.AxisymDiscretisation(order=p, edge_layers=4, face_layers=4, axis_layers=k)
            t = time.process_time()
            r0 = ax.critical_voltage(PLATE, NeoHookean(), d, n=0)
            r1 = ax.critical_voltage(PLATE, NeoHookean(), d, n=1, v_start=1.3 * r0.v)
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
