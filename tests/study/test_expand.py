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
    assert len(plan.jobs) == 16
    assert [a.name for a in plan.axes] == ["condition", "speed_kmh", "body_model"]
    for job in plan.jobs:
        cond, speed = job.axes["condition"], job.axes["speed_kmh"]
        ref = preset_dict(f"paper-{cond}-{int(speed)}")
        s = job.scenario
        assert s.speed_kmh == speed and s.distance_m == ref["distance_m"]
        assert s.line.kind == ref["line"]["kind"]
        assert [e.kind for e in s.excitation] == [e["kind"] for e in ref["excitation"]]
    assert {j.axes["condition"] for j in plan.jobs} == set(PAPER_CONDITIONS)


def test_paper_table3_is_the_flexible_model_keeping_the_modes_its_excitation_drives():
    """The paper's model is flexible; 0.5 m corrugation at 80 km/h drives 44.4 Hz, so the
    bodies keep modes to 1.5 × that rounded up to 10 Hz (70 Hz) at every corrugation speed
    (one FE reduction per condition), the other conditions the scenario's 40 Hz (random down
    to λ 1 m: 22 Hz at 80 km/h); ``as_given`` keeps 40 Hz."""
    def cutoffs(request):
        plan = expand_study(request, max_jobs=100)
        return {(j.axes["condition"], j.axes["speed_kmh"]): (
            j.scenario.bodies.carbody.model, j.scenario.bodies.carbody.cutoff_hz,
            j.scenario.bodies.frames.cutoff_hz) for j in plan.jobs}

    got = cutoffs({"preset": "paper-table3"})
    assert got[("corrugation", 80.0)] == ("flexible", 70.0, 70.0)
    assert got[("corrugation", 50.0)] == ("flexible", 70.0, 70.0)  # alone 50 Hz would do
    assert got[("random-straight", 80.0)] == ("flexible", 40.0, 40.0)
    assert got[("settlement", 80.0)] == ("flexible", 40.0, 40.0)
    kept = cutoffs({"preset": "paper-table3", "cutoff": "as_given"})
    assert kept[("corrugation", 80.0)] == ("flexible", 40.0, 40.0)


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
