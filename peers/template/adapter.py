"""Template of a peer adapter: copy it to ``peers/<library>/<problem_id>.py`` and replace
:func:`solve` with your code.

    python peers/run.py <library> <problem_id> [--label L]      # in the library's venv
    python peers/template/adapter.py --problem-json P --out W  # by hand

The protocol (``peers/run.py``): read the problem (``debench problems ID --json``, passed
as ``--problem-json``: the spec with every parameter, and the reference grid), compute the
quantity at the reference's own points (they are exact; a curve may be given at any points
at least as dense), and write into ``--out``:

* ``results.csv``: the header ``name [units]`` per column (coordinates, then the
  quantity), one row per point; leave out points outside the problem's domain (where
  the reference is NaN);
* ``adapter.json``: ``code`` (name, version, commit_or_release, url, license),
  ``method`` (description, discretisation, mesh_or_resolution, solver, tolerances,
  physics_differences) and, optionally, ``check`` (your stated accuracy: ``rtol`` and/or
  ``atol`` with its ``reason``, and ``partial: true`` if you cover only part).

``peers/run.py`` adds the environment, hardware, timing, command, submitter and date, the
checksum and the check outcome. As shipped, :func:`solve` knows one problem,
``ch3_free_membrane_nh`` (its closed form, eq. 3.21 with c = 0: a worked example of the
protocol, not a peer code); every other problem raises until you write your solver.
"""

from __future__ import annotations

import argparse
import itertools
import json
import platform
from pathlib import Path

import numpy as np


def solve(problem: str, parameters: dict, point: dict) -> float:
    """Your code: the quantity at one point (``point``: coordinate name -> value;
    ``parameters``: the spec's parameters, each ``{"value": ..., "units": ...}``)."""
    if problem == "ch3_free_membrane_nh":
        lam = point["lam"]
        return float(np.sqrt(lam**-2 - lam**-8))
    raise NotImplementedError(f"write the solver of {problem} here")


def points(ref: dict):
    """Every reference point of one quantity: (coordinates, reference value)."""
    dims, coords = ref["dims"], ref["coords"]
    values = np.asarray(ref["values"], dtype=float)
    along = ref.get("along")
    along_values = np.asarray(along["values"], dtype=float) if along else None
    for idx in itertools.product(*(range(len(coords[d])) for d in dims)):
        pt = {d: coords[d][i] for d, i in zip(dims, idx, strict=True) if d != "point"}
        if along is not None:
            sub = tuple(idx[dims.index(d)] for d in along["dims"])
            pt[along["name"]] = float(along_values[sub])
        yield pt, float(values[idx])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--problem-json", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--label", default="default")
    a = ap.parse_args()
    doc = json.loads(Path(a.problem_json).read_text())
    spec = doc["spec"]
    [q] = spec["quantities"][:1]  # the first quantity; choose yours if there are several
    ref = doc["reference"][q["name"]]
    cols = list(q["coordinates"])
    units = q.get("coordinate_units", {})
    rows = []
    for pt, value in points(ref):
        if not np.isfinite(value):  # outside the domain: no reference there
            continue
        rows.append([pt[c] for c in cols] + [solve(spec["id"], spec["parameters"], pt)])
    out = Path(a.out)
    with (out / "results.csv").open("w") as fh:
        head = [f"{c} [{units[c]}]" if units.get(c) else c for c in cols]
        fh.write(",".join(head + [f"{q['name']} [{q['units']}]"]) + "\n")
        for r in rows:
            fh.write(",".join(repr(x) if isinstance(x, float) else str(x) for x in r) + "\n")
    meta = {
        "quantity": q["name"],
        "code": {"name": "debench adapter template", "version": "1",
                 "commit_or_release": "the template as shipped",
                 "url": "https://example.org/your-code"},  # replace with yours
        "method": {"description": "closed form of the free membrane (the template's worked "
                                  "example)",
                   "discretisation": "none (closed form)",
                   "mesh_or_resolution": "none (closed form)",
                   "solver": f"numpy {np.__version__} on Python {platform.python_version()}",
                   "tolerances": "none (closed form)",
                   "physics_differences": "none"},
        "check": {"rtol": 1e-12, "reason": "closed form in double precision"},
    }
    (out / "adapter.json").write_text(json.dumps(meta, indent=1))


if __name__ == "__main__":
    main()
