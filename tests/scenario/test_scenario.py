"""Scenario loading, validation messages and presets."""

from __future__ import annotations

import json

import pytest
import yaml

from flexride.errors import ScenarioError
from flexride.scenario.presets import PAPER_CONDITIONS, PAPER_SPEEDS_KMH, PRESETS, preset_dict
from flexride.scenario.scenario import Scenario, apply_overrides, load_scenario


def test_sixteen_paper_conditions_exist():
    names = [f"paper-{c}-{v}" for c in PAPER_CONDITIONS for v in PAPER_SPEEDS_KMH]
    assert len(names) == 16
    for n in names:
        assert n in PRESETS
        sc = Scenario.model_validate(PRESETS[n])
        assert sc.speed_kmh == float(n.rsplit("-", 1)[1])
    for n in ("paper-random-straight-80", "paper-random-curve-60", "paper-corrugation-70",
              "paper-settlement-50"):
        assert n in PRESETS


def test_paper_table4_values_in_preset():
    v = Scenario.model_validate(PRESETS["paper-metro"]).vehicle
    assert v.carbody.mass == 35443.0
    assert (v.carbody.ixx, v.carbody.iyy, v.carbody.izz) == (50929.0, 1410960.0, 1401490.0)
    assert (v.primary.kx, v.primary.ky, v.primary.kz) == (7.0e6, 4.0e6, 0.9e6)
    assert (v.secondary.cz, v.secondary.kz) == (8.0e4, 341.9e3)


@pytest.mark.parametrize("suffix", [".yaml", ".json"])
def test_load_yaml_and_json(tmp_path, suffix):
    data = preset_dict("paper-corrugation-70")
    f = tmp_path / f"s{suffix}"
    f.write_text(json.dumps(data) if suffix == ".json" else yaml.safe_dump(data))
    sc = load_scenario(f)
    assert sc.speed_kmh == 70.0 and sc.excitation[0].kind == "corrugation"


def test_invalid_file_names_field_and_range(tmp_path):
    data = apply_overrides(preset_dict("paper-metro"), {"track.fastener.spacing": 5.0})
    f = tmp_path / "bad.yaml"
    f.write_text(yaml.safe_dump(data))
    with pytest.raises(ScenarioError) as info:
        load_scenario(f)
    msg = str(info.value)
    assert "bad.yaml" in msg and "track.fastener.spacing" in msg and "≤ 1.5" in msg


def test_unknown_field_rejected():
    data = preset_dict("paper-metro")
    data["vehicle"]["carbody"]["mas"] = 1.0
    with pytest.raises(Exception, match="mas"):
        Scenario.model_validate(data)


def test_unparsable_file(tmp_path):
    f = tmp_path / "x.yaml"
    f.write_text("vehicle: [unclosed")
    with pytest.raises(ScenarioError, match="cannot parse"):
        load_scenario(f)


def test_every_numeric_field_has_its_unit_as_data():
    """Every numeric field carries ``unit`` in its JSON schema, and its description ends with
    that unit (both from one argument of :func:`flexride.scenario.base.quantity`)."""
    schema = Scenario.model_json_schema()
    missing = []
    for name, d in schema["$defs"].items():
        for field, spec in d.get("properties", {}).items():
            types = {spec.get("type")} | {a.get("type") for a in spec.get("anyOf", [])}
            if not types & {"number", "integer"}:
                continue
            unit = spec.get("unit")
            if not unit or not spec.get("description", "").endswith(f" ({unit})"):
                missing.append(f"{name}.{field}")
    assert not missing, missing
