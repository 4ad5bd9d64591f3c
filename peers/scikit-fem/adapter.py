"""The scikit-fem adapters by problem id:

    python peers/scikit-fem/adapter.py PROBLEM --out DIR [--problem-json P] [--label L]

runs ``peers/scikit-fem/PROBLEM.py`` (the file ``peers/run.py scikit-fem PROBLEM`` runs in
the pinned venv) with the remaining arguments; without ``--problem-json`` the adapter
uses the problem page's parameters and grid.
"""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
PROBLEMS = ("ch3_voltage_stretch", "ch5_critical_voltage", "lit_balloon", "lit_bilayer",
            "mms_electroelastic")


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    if not argv or argv[0] not in PROBLEMS:
        print(f"usage: adapter.py PROBLEM --out DIR [--problem-json P]; PROBLEM one of "
              f"{', '.join(PROBLEMS)}", file=sys.stderr)
        return 2
    sys.path.insert(0, str(HERE))
    return importlib.import_module(argv[0]).main(argv[1:])


if __name__ == "__main__":
    raise SystemExit(main())
