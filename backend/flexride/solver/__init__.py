"""Assembly, numba kernel and run control of the vehicle–track solver."""

from flexride.solver.simulate import preflight, simulate

__all__ = ["preflight", "simulate"]
