"""flexride: ride comfort of metro vehicles with flexible bodies on flexible track.

The package is organised as in ``docs/architecture.md``: schemas in :mod:`flexride.scenario`,
bodies in :mod:`flexride.bodies`, the vehicle topology in :mod:`flexride.vehicle`, track and
excitation in :mod:`flexride.track`, wheel-rail contact in :mod:`flexride.contact`, the numba
time integration in :mod:`flexride.solver` and the signal analysis in :mod:`flexride.analysis`.
"""

from __future__ import annotations

from flexride._numba_env import configure_numba_cache

__version__ = "0.1.0"

configure_numba_cache(__version__)

__all__ = ["__version__", "simulate"]


def __getattr__(name: str):  # lazy: importing flexride must not compile numba kernels
    if name == "simulate":
        from flexride.solver.simulate import simulate

        return simulate
    raise AttributeError(name)
