"""Scenario resolution for requests, content hashes, the cached submission check."""

from __future__ import annotations

import pytest

import flexride.study.scenarios as sc
from flexride.errors import ScenarioError, StabilityError
from flexride.scenario.loading import check_finite, resolve_scenario, safe_overrides
from flexride.study.scenarios import (
    PreflightCache,
    check_submission,
    scenario_hash,
    stability_key,
)

SHORT = {"duration_s": 1.0, "distance_m": None}


def test_resolve_from_preset_or_scenario():
    a = resolve_scenario(preset="paper-settlement-60", overrides=SHORT)
    assert a.speed_kmh == 60 and a.duration_s == 1.0 and a.excitation[0].kind == "settlement"
    b = resolve_scenario(scenario={"preset": "paper-settlement-60", **SHORT})
    assert scenario_hash(a) == scenario_hash(b)
    c = resolve_scenario(scenario={"preset": "paper-metro", "speed_kmh": 60},
                         overrides={"excitation": [{"kind": "settlement", "wavelength_m": 20,
                                                    "depth_m": 0.1, "position_m": 40}],
                                    **SHORT})
    assert c.excitation[0].depth_m == 0.1


@pytest.mark.parametrize("kwargs, match", [
    ({}, "either"),
    ({"preset": "paper-metro", "scenario": {}}, "either"),
    ({"preset": "nope"}, "unknown preset"),
    ({"preset": "paper-metro", "overrides": {"": 1}}, "dotted field path"),
    ({"preset": "paper-metro", "overrides": {"excitation.x": 1}}, "cannot set"),
    ({"preset": "paper-metro", "overrides": {"speed_kmh.deeper": 1}}, "cannot set"),
    ({"preset": "paper-metro", "overrides": {"speed_kmh": float("nan")}}, "speed_kmh"),
    ({"scenario": []}, "mapping"),
])
def test_bad_requests_are_scenario_errors(kwargs, match):
    with pytest.raises(ScenarioError, match=match):
        resolve_scenario(**kwargs)


def test_non_finite_values_are_refused():
    with pytest.raises(ScenarioError, match="y: Input should be less"):
        resolve_scenario(preset="paper-metro",
                         overrides={"output.points": [{"name": "P", "x": 0.0,
                                                       "y": float("inf"), "z": 1.0}]})
    with pytest.raises(ScenarioError, match=r"a.1: must be a finite number"):
        check_finite({"a": [1.0, float("nan")]})  # fields without bounds
    assert safe_overrides({"a": 1}, None) == {"a": 1}


def test_hash_ignores_names_and_keys_follow_the_step_map():
    a = resolve_scenario(preset="paper-random-straight-80", overrides=SHORT)
    b = resolve_scenario(preset="paper-random-straight-80", overrides={**SHORT, "name": "x"})
    c = resolve_scenario(preset="paper-random-straight-60", overrides=SHORT)
    assert scenario_hash(a) == scenario_hash(b) != scenario_hash(c)
    assert stability_key(a) != stability_key(c)  # the creep damping ∝ 1/V is in the map
    seed = resolve_scenario(preset="paper-random-straight-80",
                            overrides={**SHORT, "excitation.0.seed": 7})
    assert stability_key(seed) == stability_key(a) != scenario_hash(seed)
    d = resolve_scenario(preset="paper-random-straight-80",
                         overrides={**SHORT, "solver.dt": 5e-5})
    assert stability_key(d) != stability_key(a)
    e = resolve_scenario(preset="paper-random-straight-80",
                         overrides={**SHORT, "bodies.carbody.model": "flexible"})
    assert stability_key(e) == stability_key(a)


def test_check_is_cached_per_stability_key(monkeypatch):
    calls = []

    def fake(scenario, _sources):
        calls.append(scenario.excitation[0].seed)
        dt = scenario.solver.dt
        if not isinstance(dt, str) and dt > 1e-3:
            raise StabilityError("too big", dt=dt, dt_max=1e-4, dt_suggested=5e-5)
        return {"n_dof": 1, "output_rate_hz": 1000.0, "stability": {}}

    monkeypatch.setattr(sc, "_preflight", fake)
    cache = PreflightCache(size=2)
    for seed in (1, 2, 3, 4):  # the realisations of a condition: one check
        check_submission(resolve_scenario(preset="paper-random-straight-80",
                                          overrides={**SHORT, "excitation.0.seed": seed}),
                         cache=cache)
    assert calls == [1]
    unstable = resolve_scenario(preset="paper-random-straight-80",
                                overrides={"solver.dt": 5e-3})
    for _ in range(2):
        with pytest.raises(StabilityError) as err:
            check_submission(unstable, cache=cache)
        assert err.value.dt_suggested == 5e-5
    assert len(calls) == 2  # the refusal is cached too
    off = resolve_scenario(preset="paper-metro", overrides={"solver.check_stability": False})
    assert check_submission(off, cache=cache) == {"stability": None}


def test_flexible_bodies_need_the_fe_module(monkeypatch):
    monkeypatch.setattr(sc, "flexible_available", lambda: False)
    s = resolve_scenario(preset="paper-metro", overrides={"bodies.frames.model": "flexible"})
    with pytest.raises(ScenarioError, match=r"bodies\.frames\.model: flexible bodies are not"):
        check_submission(s)


def test_real_check_reports_the_stability_limit():
    info = check_submission(resolve_scenario(preset="paper-metro", overrides=SHORT))
    stab = info["stability"]
    assert stab["auto"] and stab["dt"] == stab["dt_suggested"] <= 0.8 * stab["dt_max"]
    assert stab["margin"] == pytest.approx(stab["dt_max"] / stab["dt"])
    assert info["n_dof"] > 100
