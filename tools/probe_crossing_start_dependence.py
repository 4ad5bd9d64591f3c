"""Does the wavenumber-n eigenvalue along the axisymmetric path depend on the state the
deflection-controlled solve starts from?  (The Ogden R/t0 = 20 film of the path study.)

    python tools/probe_crossing_start_dependence.py ORDER LAYERS N [--tight]

follows the path of ``ogden_r20`` (:func:`debench.reference.studies.ch5_axisym.path_task`'s
settings) to w = 9.2 t0 with the eigenvalue of wavenumber N recorded, locates its zero
(:func:`~debench.models.buckling.axisym.zero_crossing`), then evaluates lambda_N at
deflections around that zero twice: each state reached by deflection control
(:func:`~debench.models.buckling.axisym.path.deflect_from`) from the recorded state below
the zero, and from the one above it. A single-valued, smooth lambda_N(w) gives the same
numbers both ways (to the Newton tolerance, a relative residual of 1e-11).

Measured (order 2, 6 layers, N = 12; 102 s CPU for the path; records at 8.1415 and
8.6415 t0, zero returned at 8.634389): from the record below, lambda_12 falls smoothly
(slope -3.9e-3 per t0) through zero near w = 8.6297 (+1.4e-6 at 8.629389, -6.4e-6 at
8.631389); from the record above it is not monotone: -7.3e-6 at 8.631389, +3.0e-5 at
8.633389, +1.6e-5 at 8.634389 (from below: -1.8e-5), +2.9e-6 at 8.635389, -2.8e-5 at
8.638389. The voltages of the two states at one deflection differ by up to 6e-7 (1.4e-6
relative), far above a Newton residual of 1e-11 relative. So the axisymmetric state at a
prescribed centre deflection depends on where its solve starts, at a level that moves
this zero by several 1e-3 t0: the crossings of the coarse discretisations are reproducible
only to that (the curated n = 12 crossings moved by 4.9e-3 t0 at orders 2 and 3 (6 layers),
3.9e-4 at order 4 with 6 layers and 2e-7 with 4 layers, when the path records and the root
finder changed).
The cause is the Newton tolerance: at w = 8.633389 the state from above stopped after one
iteration at a residual of 7.0e-12 of its reference (just inside NEWTON_RTOL = 1e-11), the
one from below after four at 1.5e-13; their states differ by 3e-6 relative, and the lowest
wavenumber-0 eigenvalue at fixed voltage there is only 8.7e-4 (a soft direction: state
error ~ residual / stiffness). One more Newton iteration from each (``rtol=1e-15``: both stop
at ~1e-16) gives the same state (voltages 1.4e-10 apart) and lambda_12 = -1.50978e-5 and
-1.51005e-5 (before: -1.412e-5 from below, +3.03e-5 from above). ``--tight`` repeats every
evaluation with that extra Newton solve: measured (97 s CPU for the path), the two starts
then agree to 3e-9 in lambda_12 and 1e-9 in v at every deflection, lambda_12 falls
monotonically, and its zero lies between 8.629389 (+5.31e-7) and 8.631389 (-7.29e-6):
8.62952 t0 by linear interpolation, the value of the curated file written before the
path records changed (8.629524), 4.9e-3 t0 below the current one (8.634389).

Since the deflection-controlled Newton solve takes that step itself
(:meth:`~debench.models.buckling.axisym.AxisymModel.newton_deflection`, its polishing step),
the default mode measures what ``--tight`` did (45 s CPU for the path on a quiet core):
zero_crossing returns 8.629524 t0, the two starts give voltages equal to 1e-9 and
lambda_12 within 3e-9 at every deflection (Newton residuals 3e-17 .. 1e-15 relative).
The test ``test_a_wrinkling_crossing_does_not_depend_on_the_record_its_trial_states_start_from``
(verification/test_ch5_axisym.py, ``--full``) asserts it.
"""

from __future__ import annotations

import sys
import time

import numpy as np
from debench.models.buckling import axisym as ax
from debench.models.buckling.analytic import critical_voltage_plate
from debench.models.buckling.axisym.path import deflect_from
from debench.models.buckling.parameters import Plate
from debench.reference.studies.ch5 import material
from debench.reference.studies.ch5_axisym import PATH_FILMS as CASES
from debench.reference.studies.ch5_axisym import PATH_N_R_PER_ASPECT as N_R_PER_ASPECT
from debench.reference.studies.ch5_axisym import V_SWITCH
from debench.reference.tasks import limit_threads

#: deflections / t0 around the zero at which lambda_N is evaluated from both sides
OFFSETS = np.array([-9e-3, -7e-3, -5e-3, -3e-3, -1e-3, 0.0, 1e-3, 4e-3, 7e-3])
W_STOP = 9.2


def main(argv: list[str]) -> int:
    limit_threads()
    tight = "--tight" in argv
    order, layers, n = (int(a) for a in argv if a != "--tight")
    mat_name, t0, aspect, _, w_from, spacing = CASES["ogden_r20"]
    mat = material(mat_name)
    disc = ax.AxisymDiscretisation(order=order, edge_layers=layers, face_layers=layers,
                                   n_r=max(1, round(N_R_PER_ASPECT * aspect)))
    model = ax.AxisymModel(Plate(thickness=t0, aspect=aspect), mat, disc,
                           with_imperfection=True)
    v_switch = V_SWITCH * critical_voltage_plate(mat, aspect)
    cpu = time.process_time()
    pts = ax.follow_path(model, W_STOP, v_switch=v_switch, dv=v_switch / 8,
                         record_every=spacing, wavenumbers=(0,), stop_past_maximum=True,
                         all_from=w_from, all_wavenumbers=(n,))
    print(f"path to w = {W_STOP} t0: {time.process_time() - cpu:.0f} s CPU")
    zero = ax.zero_crossing(model, pts, n)
    if zero is None:
        print(f"lambda_{n} does not change sign before w = {W_STOP} t0")
        return 1
    print(f"zero of lambda_{n}: w = {zero.w:.6f} t0 (tolerance {zero.wtol:.1e})")
    rec = [p for p in pts if n in p.lam]
    i = max(k for k, p in enumerate(rec) if p.w <= zero.w)
    for side, start in (("below", rec[i]), ("above", rec[i + 1])):
        for w in zero.w + OFFSETS:
            deflect_from(model, (start.state, start.v), start.w, float(w))
            if tight:
                model.newton_deflection(float(w), rtol=1e-15)
            lam = float(model.spectrum(n, nev=1).lam[0])
            print(f"from the record {side} (w = {start.w:.4f}): w = {w:.6f} "
                  f"lambda_{n} = {lam:+.6e} v = {float(model.v):.9f} "
                  f"(Newton residual {model.last_newton.residual_rel:.1e} relative)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
