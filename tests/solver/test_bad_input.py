"""Every family of invalid input gives its own clear error."""

from __future__ import annotations

import pytest

from conftest import preset
from flexride.errors import ScenarioError, StabilityError, UnknownPresetError
from flexride.scenario.presets import load_preset
from flexride.solver.simulate import simulate


def test_negative_mass():
    with pytest.raises(ScenarioError, match=r"vehicle\.carbody\.mass.*> 1"):
        preset(**{"vehicle.carbody.mass": -10.0})


def test_zero_speed():
    with pytest.raises(ScenarioError, match=r"speed_kmh.*> 0"):
        preset(speed_kmh=0.0)


def test_unknown_preset():
    with pytest.raises(UnknownPresetError, match="unknown preset 'paper-nope'"):
        load_preset("paper-nope")


def test_unstable_time_step_names_a_step_that_works():
    with pytest.raises(StabilityError) as info:
        simulate(preset(duration_s=0.1, **{"solver.dt": 5e-4}))
    err = info.value
    assert err.dt_suggested < err.dt_max < err.dt
    assert "use solver.dt =" in str(err)
    # and the suggested step does run
    simulate(preset(duration_s=0.05, **{"solver.dt": err.dt_suggested}))


def test_malformed_csv(tmp_path):
    f = tmp_path / "irr.csv"
    f.write_text("distance_m,vertical\n0,0.001\n1,abc\n")
    with pytest.raises(ScenarioError, match=r"irr\.csv"):
        simulate(preset(duration_s=0.1, excitation=[{"kind": "measured", "path": str(f)}]))


def test_missing_length_and_both_lengths():
    with pytest.raises(ScenarioError, match="exactly one of duration_s"):
        preset(duration_s=None)
    with pytest.raises(ScenarioError, match="exactly one of duration_s"):
        preset(distance_m=100.0)


def test_automatic_step_count_is_bounded_before_the_run():
    """``simulate(max_steps=…)`` (the worker's bound from the service's settings) refuses a run
    whose automatic step makes too many steps, at the length field, before it runs."""
    with pytest.raises(ScenarioError, match=r"duration_s: 16,000 time steps .* limit of 1,000"):
        simulate(preset(duration_s=1.0), max_steps=1000)
