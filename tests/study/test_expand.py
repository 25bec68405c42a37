"""Study expansion into job matrices; study presets."""

from __future__ import annotations

import pytest

from flexride.errors import ScenarioError
from flexride.scenario.presets import PAPER_CONDITIONS, preset_dict
from flexride.study.expand import StudyTooLarge, expand_study, merge_with_preset
from flexride.study.presets import STUDY_PRESETS, study_preset

QUICK = {"duration_s": 1.0, "distance_m": None}


def test_paper_table3_is_the_16_conditions():
    plan = expand_study({"preset": "paper-table3"}, max_jobs=100)
    assert len(plan.jobs) == 16 and [a.name for a in plan.axes] == ["condition", "speed_kmh"]
    for job in plan.jobs:
        cond, speed = job.axes["condition"], job.axes["speed_kmh"]
        ref = preset_dict(f"paper-{cond}-{int(speed)}")
        s = job.scenario
        assert s.speed_kmh == speed and s.distance_m == ref["distance_m"]
        assert s.line.kind == ref["line"]["kind"]
        assert [e.kind for e in s.excitation] == [e["kind"] for e in ref["excitation"]]
    assert {j.axes["condition"] for j in plan.jobs} == set(PAPER_CONDITIONS)


def test_paper_table2_is_rigid_against_flexible():
    plan = expand_study({"preset": "paper-table2", "overrides": QUICK}, max_jobs=10)
    models = [(j.scenario.bodies.carbody.model, j.scenario.bodies.frames.model)
              for j in plan.jobs]
    assert models == [("rigid", "rigid"), ("flexible", "flexible")]
    assert all(j.scenario.duration_s == 1.0 and j.scenario.speed_kmh == 80 for j in plan.jobs)
    assert set(STUDY_PRESETS) >= {"paper-table3", "paper-table2"}


def test_request_fields_replace_the_presets():
    merged = merge_with_preset({"preset": "paper-table3", "speeds_kmh": [60.0],
                                "description": "", "overrides": {}})
    assert merged["speeds_kmh"] == [60.0] and merged["description"]
    plan = expand_study({"preset": "paper-table3", "speeds_kmh": [60.0],
                         "conditions": ["settlement"], "overrides": QUICK}, max_jobs=10)
    assert len(plan.jobs) == 1 and plan.jobs[0].scenario.duration_s == 1.0
    with pytest.raises(ScenarioError, match="unknown study preset"):
        study_preset("nope")


def test_custom_conditions_parameters_and_names():
    plan = expand_study({
        "name": "mass", "base": {"preset": "paper-metro", "overrides": QUICK},
        "conditions": [{"name": "smooth", "set": {"excitation": []}}, "corrugation"],
        "speeds_kmh": [50, 70],
        "parameters": [{"path": "vehicle.carbody.mass", "values": [30000.0, 40000.0]}],
        "overrides": QUICK}, max_jobs=100)
    assert len(plan.jobs) == 8
    last = plan.jobs[-1]
    assert last.axes == {"condition": "corrugation", "speed_kmh": 70.0,
                         "vehicle.carbody.mass": 40000.0}
    assert last.scenario.vehicle.carbody.mass == 40000.0 and last.scenario.duration_s == 1.0
    assert last.name == "mass corrugation 70 40000" == last.scenario.name
    assert [a.describe()["name"] for a in plan.axes] == ["condition", "speed_kmh",
                                                          "vehicle.carbody.mass"]


@pytest.mark.parametrize("request_, error, match", [
    ({"preset": "paper-table3"}, StudyTooLarge, "16 jobs"),
    ({"base": {"preset": "paper-metro"}, "conditions": ["x"]}, ScenarioError, "unknown"),
    ({"base": {"preset": "paper-metro"}, "speeds_kmh": [50, 50]}, ScenarioError, "unique"),
    ({"base": {"preset": "paper-metro"}, "speeds_kmh": [500]}, ScenarioError,
     r"study job 0 \(speed_kmh=500\)"),
    ({"base": {}}, ScenarioError, "either"),
    ({"speeds_kmh": [50]}, ScenarioError, "base"),
    ({"base": {"preset": "paper-metro"}, "parameters": [
        {"path": "speed_kmh", "values": [1]}]}, ScenarioError, "already an axis"),
])
def test_bad_studies(request_, error, match):
    with pytest.raises(error, match=match):
        expand_study(request_, max_jobs=10)


def test_seeds_axis_realisations_per_random_condition():
    from flexride.paper.plan import RunSpec

    plan = expand_study({"preset": "paper-table3", "speeds_kmh": [80.0],
                         "conditions": ["random-curve", "settlement"], "seeds": 3,
                         "overrides": QUICK}, max_jobs=100)
    assert [a.name for a in plan.axes][-1] == "seed"
    random = [j for j in plan.jobs if j.axes["condition"] == "random-curve"]
    assert [j.axes["seed"] for j in random] == [1, 2, 3]
    assert [j.scenario.excitation[0].seed for j in random] == [1, 2, 3]
    # settlement has no random irregularity: one realisation, not three copies
    assert [j.axes["seed"] for j in plan.jobs if j.axes["condition"] == "settlement"] == [1]
    assert [j.index for j in plan.jobs] == [0, 1, 2, 3]
    # the paper report's realisation k is the same track
    spec = RunSpec("random-curve", 80.0, "rigid", 3, 100.0, (0.0, 100.0))
    assert spec.scenario().excitation[0].seed == random[2].scenario.excitation[0].seed


def test_seeds_count_from_the_scenarios_own_seed():
    plan = expand_study({"base": {"preset": "paper-random-straight-80", "overrides": QUICK},
                         "seeds": 2, "overrides": {"excitation.0.seed": 7}}, max_jobs=10)
    assert [j.scenario.excitation[0].seed for j in plan.jobs] == [7, 8]
