"""The typed calibration of the car body as a field of the scenario
(``bodies.carbody.calibration``) and of the FE build (``ExportSpec.calibration``): the schema,
the calibration at body-build time, its cache entry, the early refusal of a target the model
cannot pair."""

from __future__ import annotations

from dataclasses import asdict

import pytest

from flexride.errors import FEModelError, ScenarioError
from flexride.fem import cache
from flexride.fem.calibration_variables import DEFAULT_BODY_VARIABLES, least_budget
from flexride.fem.defaults import CARBODY_CALIBRATED
from flexride.fem.export import ExportSpec
from flexride.fem.mode_types import MODE_TYPES, SECTION_DEFORMATION
from flexride.fem.targets import parse_targets
from flexride.scenario.bodies import (
    CARBODY_TARGET_TYPES,
    MAX_CALIBRATION_EVALUATIONS,
    BodyModel,
    CarBodyCalibration,
)
from flexride.scenario.presets import load_preset
from flexride.scenario.scenario import Scenario

#: A calibration cheap enough for a test: 0.5 m elements, one variable, 6 FE evaluations.
SMALL = {"targets": "6.5:rhombic,5.59:first vertical bending", "variables": ["floor_depth"],
         "max_evaluations": 6}


def _scenario(calibration, **body):
    return load_preset("paper-metro", {"bodies.carbody.model": "flexible",
                                       "bodies.carbody.element_size_m": 0.5,
                                       "bodies.carbody.calibration": calibration,
                                       **{f"bodies.carbody.{k}": v for k, v in body.items()}})


# -- the schema ---------------------------------------------------------------------------------


def test_targets_are_typed_with_the_classifiers_names_in_either_spelling():
    text = "5.03:Torsion, 6.11:rhombic;8.84:first vertical bending,7.4,6.5:roof-floor breathing"
    spelled = CarBodyCalibration(targets=text)
    listed = CarBodyCalibration(targets=[
        {"frequency_hz": 5.03, "mode_type": "torsion"}, "6.11:rhombic",
        {"frequency_hz": 8.84, "mode_type": "first vertical bending"}, {"frequency_hz": 7.4},
        {"frequency_hz": 6.5, "mode_type": "roof–floor breathing"}])
    assert spelled == listed
    # the command line's parser gives the same canonical types (CLI and scenario agree)
    assert [t.mode_type for t in spelled.targets] == [t.mode_type for t in parse_targets(text)]
    assert spelled.targets_spelling() == ("5.03:torsion,6.11:rhombic,8.84:first vertical "
                                          "bending,7.4,6.5:roof–floor breathing")
    assert spelled.variable_names == DEFAULT_BODY_VARIABLES and spelled.max_evaluations == 30


def test_the_json_schema_lists_the_mode_types_of_the_classifier():
    schema = Scenario.model_json_schema()["$defs"]["CalibrationTarget"]["properties"]
    enum = schema["mode_type"]["enum"]
    assert enum[:-1] == list(CARBODY_TARGET_TYPES) and enum[-1] is None
    assert set(MODE_TYPES) - {SECTION_DEFORMATION} <= set(enum)
    assert SECTION_DEFORMATION not in enum and "first vertical bending" in enum


@pytest.mark.parametrize(("calibration", "loc", "words"), [
    ({"targets": "5.03:twisting"}, ("targets", 0), "unknown mode type 'twisting'"),
    ({"targets": [{"frequency_hz": 5.03, "mode_type": "twisting"}]},
     ("targets", 0, "mode_type"), "'rhombic'"),
    ({"targets": "5.03:cross-section deformation"}, ("targets", 0), "never gives it"),
    ({"targets": "5.03:"}, ("targets", 0), "must follow ':'"),
    ({"targets": "-5"}, ("targets", 0), "greater than 0"),
    ({"targets": ""}, ("targets",), "at least 1"),
    ({"targets": "5", "variables": ["floor_thickness"]}, ("variables", 0), "'floor_depth'"),
    ({"targets": "5", "max_evaluations": 10}, (), "allowed 18–60"),
    ({"targets": "5", "max_evaluations": 61}, ("max_evaluations",), "less than or equal to 60"),
    ({"targets": "5,6", "n_modes": 1}, (), "allowed 2–40"),
])
def test_bad_calibrations_are_refused_at_their_field_with_the_allowed_range(calibration, loc,
                                                                           words):
    with pytest.raises(ScenarioError) as info:
        _scenario(calibration)
    (item,) = info.value.items
    assert item.loc == ("bodies", "carbody", "calibration", *loc), item
    assert words in item.msg


def test_the_budget_bound_follows_the_variables_and_the_frames_have_no_calibration():
    assert least_budget(1) == 4 and least_budget(len(DEFAULT_BODY_VARIABLES)) == 18
    assert MAX_CALIBRATION_EVALUATIONS == 60
    CarBodyCalibration(targets="5", variables=["floor_depth"], max_evaluations=4)
    with pytest.raises(ScenarioError) as info:
        load_preset("paper-metro", {"bodies.frames.calibration": {"targets": "5"}})
    assert info.value.items[0].loc == ("bodies", "frames")
    assert "car body" in info.value.items[0].msg


def test_the_default_body_variables_are_those_of_fem_defaults():
    assert tuple(CARBODY_CALIBRATED) == DEFAULT_BODY_VARIABLES


def test_the_export_spec_carries_the_calibration_and_keeps_the_default_key(vehicle):
    plain = ExportSpec.create("carbody", vehicle, BodyModel(model="flexible"))
    cal = CarBodyCalibration(targets="6.11:rhombic")
    spec = ExportSpec.create("carbody", vehicle, BodyModel(model="flexible", calibration=cal))
    assert spec.key != plain.key and plain.calibration is None
    assert ExportSpec.from_dict(asdict(spec)) == spec
    assert ExportSpec.from_dict(asdict(plain)).key == plain.key
    legacy = {k: v for k, v in asdict(plain).items() if k != "calibration"}
    assert ExportSpec.from_dict(legacy).key == plain.key  # a job stored before the field
    assert spec.body_calibration() == cal and spec.parameters()["calibration"]["targets"]
    with pytest.raises(ValueError, match="car body"):
        ExportSpec.create("frame", vehicle, BodyModel(model="flexible", calibration=cal))


# -- the calibration at body-build time ---------------------------------------------------------


def test_a_calibrated_body_is_built_once_cached_and_moves_toward_the_targets(cache_dir,
                                                                           monkeypatch):
    """0.5 m elements, one variable, six FE evaluations: the body is built from the calibrated
    values and reports them with the pairing; a second build loads both the calibration and
    the body from the FE cache (the calibration code is not called again); each paired
    frequency is nearer its target than at the start."""
    from flexride.fem import calibration as calibration_module
    from flexride.fem.calibrated_body import calibration_key
    from flexride.fem.flexible import build_flexible_body

    sc = _scenario(SMALL)
    b = sc.bodies.carbody
    evaluations = []
    fb = build_flexible_body("carbody", sc.vehicle, method=b.reduction, cutoff_hz=b.cutoff_hz,
                             element_size=b.element_size_m, calibration=b.calibration,
                             calibration_progress=lambda n, f: evaluations.append(n))
    cal = fb.calibration
    assert cal is not None and not cal["from_cache"] and not fb.from_cache
    assert 1 <= cal["n_evaluations"] == len(evaluations) <= SMALL["max_evaluations"]
    assert fb.body.info["calibration"] is cal
    assert cal["targets"] == "6.5:rhombic,5.59:first vertical bending"
    assert set(cal["values"]) == {"floor_depth"}
    assert cal["values"]["floor_depth"] != pytest.approx(CARBODY_CALIBRATED["floor_depth"])
    for pair, start in zip(cal["pairs"], cal["initial_frequencies_hz"], strict=True):
        assert pair["mode"] is not None and pair["model_type"]
        assert abs(pair["model_hz"] - pair["target_hz"]) < abs(start - pair["target_hz"])
        assert pair["error"] == pytest.approx(pair["model_hz"] / pair["target_hz"] - 1)
    # the calibration is an entry of the FE cache under its content key
    key = calibration_key(sc.vehicle, b.calibration, b.element_size_m)
    assert cal["key"] == key and cache.load(key) is not None
    # the body of the calibrated values is another model than the default one
    default = build_flexible_body("carbody", sc.vehicle, method=b.reduction,
                                  cutoff_hz=b.cutoff_hz, element_size=b.element_size_m)
    assert default.calibration is None and not default.from_cache
    assert default.body.elastic_frequencies[0] != pytest.approx(
        fb.body.elastic_frequencies[0], rel=1e-4)

    def no_calibration(*_a, **_k):
        raise AssertionError("the calibration ran again")

    monkeypatch.setattr(calibration_module, "calibrate_carbody", no_calibration)
    again = build_flexible_body("carbody", sc.vehicle, method=b.reduction,
                                cutoff_hz=b.cutoff_hz, element_size=b.element_size_m,
                                calibration=b.calibration)
    assert again.from_cache and again.calibration["from_cache"]
    assert again.calibration["values"] == cal["values"]
    assert list(again.body.elastic_frequencies) == list(fb.body.elastic_frequencies)


def test_a_target_type_the_model_cannot_pair_is_refused_after_one_evaluation(cache_dir):
    """Torsion lies above the lowest modes computed for two targets (docs/fem.md): the
    calibration stops after its first evaluation, with the reason, before its budget."""
    from flexride.fem.flexible import build_flexible_body

    sc = _scenario({**SMALL, "targets": "5.03:torsion,6.11:rhombic", "n_modes": 4})
    b = sc.bodies.carbody
    evaluations = []
    with pytest.raises(FEModelError, match="no mode of type 'torsion'") as info:
        build_flexible_body("carbody", sc.vehicle, method=b.reduction, cutoff_hz=b.cutoff_hz,
                            element_size=b.element_size_m, calibration=b.calibration,
                            calibration_progress=lambda n, f: evaluations.append(n))
    assert evaluations == [1] and "5.030 Hz torsion" in str(info.value)


def test_a_calibration_of_the_frame_or_with_params_is_refused(vehicle):
    from flexride.fem.flexible import build_flexible_body

    cal = CarBodyCalibration(targets="6.11:rhombic")
    with pytest.raises(FEModelError, match="car body"):
        build_flexible_body("frame", vehicle, calibration=cal)


def test_the_cli_builds_the_calibrated_body_with_the_same_spelling(cache_dir, tmp_path):
    """``flexride fe export --calibration-targets`` takes the spelling of ``fe calibrate
    --targets`` and of the scenario, and writes the calibration beside the modes; a bad type
    is one line and exit code 2."""
    import json

    from typer.testing import CliRunner

    from flexride.cli import app

    out = tmp_path / "cal.json"
    args = ["fe", "export", "carbody", "--element-size", "0.5", "--n-modes", "3",
            "--cutoff", "20", "--out", str(out), "--calibration-targets", SMALL["targets"],
            "--calibration-variables", "floor_depth", "--calibration-max-evaluations", "4"]
    r = CliRunner().invoke(app, args)
    assert r.exit_code == 0, r.output
    data = json.loads(out.read_text())
    cal = data["calibration"]
    assert cal["targets"] == CarBodyCalibration(targets=SMALL["targets"]).targets_spelling()
    assert [p["target_type"] for p in cal["pairs"]] == ["rhombic", "first vertical bending"]
    assert len(data["modes"]) == 3
    r = CliRunner().invoke(app, [*args[:-6], "--calibration-targets", "5:twisting"])
    assert r.exit_code == 2 and "unknown mode type 'twisting'" in r.output
    r = CliRunner().invoke(app, ["fe", "export", "frame", "--calibration-targets", "5"])
    assert r.exit_code == 2 and "car body" in r.output


def test_the_assembled_vehicle_of_a_calibrated_scenario_has_the_calibrated_car_body(
        cache_dir):
    from flexride.solver.assemble import vehicle_for

    sc = _scenario(SMALL, cutoff_hz=20.0)
    veh = vehicle_for(sc)
    carbody = next(b for b in veh.bodies if b.name == "carbody")
    assert carbody.info["calibration"]["targets"] == "6.5:rhombic,5.59:first vertical bending"
    # the run's metadata says what the car body was calibrated to
    import json

    from flexride.solver.assemble import flexible_body_facts

    facts = json.loads(json.dumps(flexible_body_facts(sc, veh)))
    assert facts["carbody"]["calibration"] == json.loads(json.dumps(
        carbody.info["calibration"]))
