"""The chapters' studies: each chapter's plan (cases, grids, meshes, the settings of its
solvers) and the computations on it that return plain result objects, once.

Builders (:mod:`debench.reference.builders`) turn studies into datasets and figures;
producers (:mod:`debench.reference.producers`) turn study results, or the datasets, into
catalogue outcomes. Both import the studies; neither imports the other
(``verification/test_architecture.py``).
"""
