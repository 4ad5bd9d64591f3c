"""scikit-fem adapter of ch5_critical_voltage: the axisymmetric (R, Z) finite-element model
of the clamped dielectric film, its flat state by Newton in the voltage and the first zero
of the lowest eigenvalue of the condensed fixed-voltage tangent (n = 0).

    python peers/run.py scikit-fem ch5_critical_voltage             # in the pinned venv
    python peers/scikit-fem/adapter.py ch5_critical_voltage --out DIR   # by hand

The physics (scikit-fem Basis / BilinearForm / LinearForm, ``condense``; Lagrange P_p
triangles for u_r, u_z and phi, mid-plane-symmetric mesh refined at the clamped corners)
is the repository's clean room ``verification/cleanroom/buckling.py`` (written from the
problem page with numpy, scipy and scikit-fem only; loaded here by its path, so the peer
venv needs nothing from debench). This adapter runs it along a p- and h-refinement
sequence and reports the finest value, its stated error from the sequence.
"""

from __future__ import annotations

import time
from pathlib import Path

import _common
import skfem

PROBLEM = "ch5_critical_voltage"
CLEAN_ROOM = Path(__file__).resolve().parents[2] / "verification" / "cleanroom" / "buckling.py"
#: the refinement sequence (order p, radial intervals, layers, corner refinements): the
#: last is reported; the others are its p-step (P3, same mesh) and its layer step (half
#: the layers, same order), whose larger change sets the stated error
SEQUENCE = ((4, 40, 4, 6), (3, 40, 8, 6), (4, 40, 8, 6))
#: Roache's grid-convergence safety factor for a two-direction (p and layers) estimate
SAFETY = 3.0




def main(argv=None):
    a = _common.arguments(PROBLEM, argv)
    doc = _common.problem_json(a.problem_json)
    cases = (doc["spec"]["parameters"]["case"]["value"] if doc is not None
             else ["nh_t1", "ogden_t1"])
    b = _common.load_clean_room(CLEAN_ROOM, "cleanroom_buckling")
    rows, log = [], {}
    for case in cases:
        seq = []
        for order, n_r, n_z, levels in SEQUENCE:
            t0 = time.perf_counter()
            c = b.critical_voltage(case, order=order, n_r=n_r, n_z=n_z, levels=levels)
            seq.append((order, n_r, n_z, levels, c.v_cr, c.ndofs,
                        round(time.perf_counter() - t0, 1)))
            print(f"{case} p={order} n_r={n_r} n_z={n_z} levels={levels}: v_cr = "
                  f"{c.v_cr!r} ({c.ndofs} dofs, {seq[-1][-1]} s)", flush=True)
        err = SAFETY * max(abs(seq[-1][4] - step[4]) for step in seq[:-1])
        log[case] = (seq, err)
        rows.append((case, seq[-1][4]))
    _common.write_results(a.out, "case,v_cr [1]", rows)
    worst = max(err / v for (_, err), (_, v) in zip(log.values(), rows, strict=True))
    steps = "; ".join(f"{case}: " + ", ".join(f"p{o} {nr}x{nz} L{lv} {v:.10f}"
                                              for o, nr, nz, lv, v, _, _ in seq)
                      + f" (error {err:.1e})" for case, (seq, err) in log.items())
    p, nr, nz, lv = SEQUENCE[-1]
    _common.write_adapter_json(a.out, quantity="v_cr", method={
        "description": "axisymmetric (R, Z) displacement-potential finite-element model of "
                       "the clamped film (electric enthalpy, hoop stretch 1 + u_r/R, weight "
                       "R, u_r = 0 on the axis); flat state by Newton continuation in the "
                       "voltage (mid-plane symmetry imposed); S_0 = K_uu - K_up K_pp^-1 "
                       "K_pu at n = 0; v_cr the zero of its lowest eigenvalue",
        "discretisation": f"Lagrange P{p} triangles (skfem ElementTriP{p}) for u_r, u_z, phi; "
                          f"quadrature order {2 * p + 2}; exact Hessian of the enthalpy by "
                          "second-order forward differentiation",
        "mesh_or_resolution": f"{nr} radial intervals x {nz} layers, {lv} refinements at "
                              f"each clamped corner, mirror-symmetric about Z = t0/2; "
                              f"sequence: {steps}",
        "solver": "Newton (scipy sparse direct via skfem condense), eigsh shift-invert at 0 "
                  "(one LU of the free tangent), Illinois regula falsi on lambda_1(v), "
                  "LOBPCG certificate of the smallest eigenvalue at the lower bracket end",
        "tolerances": "Newton increment <= 1e-10 relative; bracket <= 1e-10 relative",
        "physics_differences": "none (Ogden in-plane stretch sum evaluated exactly by its "
                               "series near repeated stretches, no regularisation)"},
        check={"rtol": worst,
               "reason": f"{SAFETY:g} x the larger change of the reported value from its "
                         f"p-step and its layer step ({steps})"},
        code_version=skfem.__version__)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
