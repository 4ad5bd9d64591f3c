"""The thesis as data: catalogue of stated values, datasets with provenance, reports."""

from debench import __version__

__all__ = ["__version__"]
