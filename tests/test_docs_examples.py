"""Every example in the README runs."""

from __future__ import annotations

import re
from pathlib import Path

import yaml

from flexride.model.scenario import scenario_from_dict
from flexride.solver.simulate import simulate

README = Path(__file__).resolve().parents[1] / "README.md"


def _blocks(lang: str) -> list[str]:
    return re.findall(rf"```{lang}\n(.*?)```", README.read_text(encoding="utf-8"), flags=re.S)


def test_readme_yaml_scenario_runs():
    (block,) = _blocks("yaml")
    data = yaml.safe_load(block)
    sc = scenario_from_dict(data, source="README")
    assert sc.vehicle.carbody.mass == 38000.0
    assert sc.vehicle.carbody.iyy == 1410960.0  # the rest comes from the preset
    short = sc.model_copy(update={"distance_m": 15.0})
    res = simulate(short)
    assert "carbody.SEAT12.acc.z" in res.channels


def test_readme_cli_examples_name_existing_commands_and_presets():
    from flexride.cli import app
    from flexride.model.presets import PRESETS

    commands = {c.name or c.callback.__name__ for c in app.registered_commands}
    for block in _blocks("bash"):
        for line in block.splitlines():
            line = line.split("#")[0].strip()
            if not line.startswith("flexride "):
                continue
            assert line.split()[1] in commands, line
            m = re.search(r"--preset (\S+)", line)
            if m:
                assert m.group(1) in PRESETS, line
