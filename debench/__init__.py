"""debench: verification and reproducibility benchmark for dielectric elastomer actuators.

The distribution installs one namespace:

* :mod:`debench.models` - the physics (pure functions, no I/O);
* :mod:`debench.reference` - the thesis as data: catalogue, datasets, verdict, CLI;
* ``debench.data`` - the curated netCDF datasets, their manifest and data card
  (package data; see :func:`debench.reference.datasets.data_dir`).
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("debench")
except PackageNotFoundError:  # pragma: no cover - imported from a source tree
    __version__ = "0+unknown"

__all__ = ["__version__"]
