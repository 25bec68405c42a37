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


DOCS = [*sorted((README.parent / "docs").glob("*.md")), README]


def _doc_blocks(path: Path, lang: str) -> list[str]:
    return re.findall(rf"```{lang}\n(.*?)```", path.read_text(encoding="utf-8"), flags=re.S)


def test_cli_examples_in_readme_and_docs_name_existing_commands_and_presets():
    from flexride.cli import app
    from flexride.fe_cli import fe_app
    from flexride.model.presets import PRESETS

    commands = {c.name or c.callback.__name__ for c in app.registered_commands}
    groups = {g.name for g in app.registered_groups}
    fe_commands = {c.name or c.callback.__name__ for c in fe_app.registered_commands}
    seen = 0
    for path in DOCS:
        for block in _doc_blocks(path, "bash"):
            for line in block.splitlines():
                line = line.split("#")[0].strip()
                if not line.startswith("flexride "):
                    continue
                seen += 1
                words = line.split()
                assert words[1] in commands | groups, (path.name, line)
                if words[1] == "fe":
                    assert words[2] in fe_commands, (path.name, line)
                m = re.search(r"--preset (\S+)", line)
                if m:
                    assert m.group(1) in PRESETS, (path.name, line)
    assert seen >= 8
