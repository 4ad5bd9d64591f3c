"""Chapter 3: pre-stretched circular dielectric elastomer actuator (Zeng 2020)."""
