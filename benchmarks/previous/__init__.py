"""Frozen copies of the code paths the benchmarks compare against (see each module)."""
