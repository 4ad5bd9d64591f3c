"""The thesis as data: catalogue of stated values, datasets with provenance, reports."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("debench")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0+unknown"
