"""One loader for files, mappings and presets with overrides: bounded parsing and errors
located at their field, the same for the CLI, the API and studies."""

from __future__ import annotations

import pytest

from flexride.errors import ScenarioError
from flexride.scenario.loading import (
    MAX_NESTING,
    read_scenario_file,
    resolve_scenario,
    safe_overrides,
)
from flexride.scenario.scenario import load_scenario


@pytest.mark.parametrize(("kwargs", "loc"), [
    ({"preset": "nope"}, ("preset",)),
    ({"scenario": {"preset": "nope"}}, ("preset",)),
    ({"preset": "paper-metro", "overrides": {"excitation.9.seed": 3}},
     ("overrides", "excitation.9.seed")),
    ({"preset": "paper-metro", "overrides": {"excitation.x": 1}}, ("overrides", "excitation.x")),
    ({"preset": "paper-metro", "overrides": {"a..b": 1}}, ("overrides", "a..b")),
])
def test_errors_are_located(kwargs, loc):
    with pytest.raises(ScenarioError) as info:
        resolve_scenario(**kwargs)
    assert info.value.items[0].loc == loc


def test_override_index_error_says_what_is_wrong():
    with pytest.raises(ScenarioError, match="no such list item"):
        resolve_scenario(preset="paper-metro", overrides={"excitation.9.seed": 3})


def test_study_overrides_are_located_under_their_place():
    with pytest.raises(ScenarioError) as info:
        safe_overrides({"a": []}, {"a.3": 1}, source="base.overrides",
                       loc=("base", "overrides"))
    assert info.value.items[0].loc == ("base", "overrides", "a.3")


@pytest.mark.parametrize(("text", "needle"), [
    ("a:\n" + "".join("  " * i + "  b:\n" for i in range(MAX_NESTING + 5)) + "x: 1\n",
     "levels deep"),
    ("[" * 100_000, "levels deep"),
    ("a: &a [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]\n" + "".join(
        f"{c}: &{c} [{', '.join(['*' + p] * 10)}]\n"
        for p, c in zip("abcdefg", "bcdefgh", strict=True)), "values"),
])
def test_bounded_parsing_of_files(tmp_path, text, needle):
    f = tmp_path / "deep.yaml"
    f.write_text(text)
    for load in (read_scenario_file, load_scenario):
        with pytest.raises(ScenarioError, match=needle):
            load(f)


def test_non_utf8_file(tmp_path):
    f = tmp_path / "s.yaml"
    f.write_bytes(b"name: \xff\n")
    with pytest.raises(ScenarioError, match="not UTF-8"):
        load_scenario(f)
