"""Chapter 5: the clamped dielectric-elastomer buckling membrane (NGSolve)."""
