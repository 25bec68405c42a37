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
