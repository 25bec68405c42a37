"""Shared test helpers."""

from __future__ import annotations

from typing import Any

from flexride.scenario.presets import CONICAL_TREAD, REAL_PROFILES, load_preset
from flexride.scenario.scenario import Scenario

#: Real profiles as a run with them is set up (flexride.scenario.presets.REAL_PROFILES), as
#: keyword overrides of :func:`preset`
PROFILES = {k.replace(".", "__"): v for k, v in REAL_PROFILES.items()}
#: The conical tread of the first releases (flexride.scenario.presets.CONICAL_TREAD), as
#: keyword overrides of :func:`preset`
CONICAL = {k.replace(".", "__"): v for k, v in CONICAL_TREAD.items()}


def preset(name: str = "paper-metro", **overrides: Any) -> Scenario:
    """A preset scenario with dotted-path overrides given as keyword arguments
    (``solver__dt=5e-5`` becomes ``solver.dt``)."""
    return load_preset(name, {k.replace("__", "."): v for k, v in overrides.items()})


def beam_carbody(params: Any, f1_hz: float, n_modes: int = 3, zeta: float = 0.0,
                 length: float = 19.0) -> Any:
    """The uniform beam car body (:func:`flexride.fem.beam.beam_carbody`, tested against the
    closed forms in tests/fem/test_beam.py) with its first ``n_modes`` bending modes: a
    flexible body independent of the finite-element code, its shapes the free–free beam's."""
    from flexride.fem.beam import beam_carbody as beam
    from flexride.fem.beam import free_free_roots

    roots = free_free_roots(n_modes)
    cutoff = f1_hz * (roots[-1] / roots[0]) ** 2 * (1.0 + 1e-9)
    return beam(params, f1_hz, cutoff, zeta, length, "uniform")
