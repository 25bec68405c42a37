"""Shared test helpers."""

from __future__ import annotations

from typing import Any

from flexride.scenario.presets import load_preset
from flexride.scenario.scenario import Scenario

#: Real profiles as a run with them is set up: S1002/60E1 at 1:40 with the EN flange-back
#: distance and the step their stiffer contact needs (docs/model.md)
PROFILES_DT = 6.25e-5
PROFILES = {"contact__geometry": "profiles", "contact__flange_back_distance": 1.36,
            "solver__dt": PROFILES_DT}


def preset(name: str = "paper-metro", **overrides: Any) -> Scenario:
    """A preset scenario with dotted-path overrides given as keyword arguments
    (``solver__dt=5e-5`` becomes ``solver.dt``)."""
    return load_preset(name, {k.replace("__", "."): v for k, v in overrides.items()})
