"""Thread counts are set in one place and no result depends on them.

Each computation runs in a fresh process with ``DEBENCH_THREADS`` = 1 and 2 (BLAS/OpenMP
and NGSolve thread pools sized by :func:`debench.threads.limit_threads`), and the values
must agree to their solver tolerances: threaded BLAS and NGSolve only reorder sums, which
moves results by round-off (~1e-15 relative), far inside these tolerances.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from debench.threads import configured_threads, limit_threads

#: ch4 FE critical stretch: eigenvalue root refined to xtol 1e-14 (brentq) on O(1)
#: stretches; thread-order round-off moves it by < 1e-13, 1e-10 keeps a 1000x margin
PLATE_RTOL = 1e-10
#: ch5 critical voltage: secant to |dv| < 1e-6 (solver.CRITICAL_VTOL); 1e-5 gives 10x
FE_ATOL = 1e-5

CODE = """
import json, sys
from debench.threads import limit_threads, thread_report
n = limit_threads()
from debench.models.plate import PlateParams
from debench.models.plate.fem import critical_stretches
from debench.models.buckling.parameters import COARSE, NeoHookean, Plate
from debench.models.buckling.solver import critical_voltage
lam = critical_stretches(2.0, PlateParams(5.0, 1.0)).lam.tolist()
v = critical_voltage(Plate(), NeoHookean(), COARSE).v
pools = {p["internal_api"]: p["num_threads"] for p in thread_report()}
print(json.dumps({"n": n, "lam": lam, "v": v, "pools": pools}))
"""


def _run(threads: int) -> dict:
    env = {**os.environ, "DEBENCH_THREADS": str(threads)}
    for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        env.pop(var, None)
    out = subprocess.run([sys.executable, "-c", CODE], env=env, capture_output=True,
                         text=True, timeout=600, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def test_values_do_not_depend_on_the_thread_count():
    one, two = _run(1), _run(2)
    assert one["n"] == 1 and two["n"] == 2
    assert all(k == 1 for k in one["pools"].values()), one["pools"]
    assert any(k == 2 for k in two["pools"].values()), two["pools"]
    assert one["lam"] == pytest.approx(two["lam"], rel=PLATE_RTOL)
    assert one["v"] == pytest.approx(two["v"], abs=FE_ATOL)


def test_thread_count_is_validated(monkeypatch):
    monkeypatch.setenv("DEBENCH_THREADS", "two")
    with pytest.raises(ValueError, match="DEBENCH_THREADS"):
        configured_threads()
    for bad in (0, -1, 1.5, True):
        with pytest.raises(ValueError, match="threads"):
            configured_threads(bad)
    monkeypatch.setenv("DEBENCH_THREADS", "1")
    assert limit_threads() == 1
