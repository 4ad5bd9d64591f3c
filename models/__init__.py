"""Physics of dielectric elastomer actuators (Zeng 2020): pure functions, no I/O.

Subpackages
-----------
invariants   invariants I1..I6 of both numberings and their derivatives
materials    energies, stresses and electroelastic moduli
circular     Chapter 3: pre-stretched circular actuator
plate        Chapter 4: bifurcation of the pre-stretched anisotropic plate
buckling     Chapter 5: NGSolve finite-element model of the buckling membrane
"""
