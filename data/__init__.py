"""Curated debench datasets (netCDF), their ``MANIFEST.json`` and data card.

Shipped as package data of the ``debench`` distribution; located at run time by
:func:`debench.reference.datasets.data_dir`. No code lives here.
"""
