"""Every Python example in the docs runs: the blocks of docs/*.md and README.md are executed
here, in order, in a directory holding the files they name; the worked examples of
"Bring your own FE model" (docs/fem.md) need FE files made by fixtures and run in
tests/fem/test_importers.py."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = [*sorted((ROOT / "docs").glob("*.md")), ROOT / "README.md"]
ELSEWHERE = {("fem.md", "## Bring your own FE model"): 3}
"""Sections (file, heading start) whose blocks run in another test, and how many they hold."""


def _sections(path: Path) -> list[tuple[str, str]]:
    """(heading, text) of the level-2 sections of a markdown file."""
    parts = re.split(r"^(## .*)$", path.read_text(encoding="utf-8"), flags=re.M)
    return [("", parts[0]), *zip(parts[1::2], parts[2::2], strict=True)]


def _blocks() -> list[tuple[str, str]]:
    out = []
    for path in DOCS:
        for heading, text in _sections(path):
            blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
            key = next((k for k in ELSEWHERE
                        if k[0] == path.name and heading.startswith(k[1])), None)
            if key is not None:
                assert len(blocks) == ELSEWHERE[key], key
                continue
            out += [(f"{path.name}, {heading.strip() or 'top'}, block {i + 1}", b)
                    for i, b in enumerate(blocks)]
    return out


BLOCKS = _blocks()


def test_the_docs_have_python_examples():
    assert len(BLOCKS) >= 2


@pytest.mark.parametrize(("where", "block"), BLOCKS, ids=[w for w, _ in BLOCKS])
def test_python_example_runs(where, block, tmp_path, monkeypatch, capsys):
    from service.svc_testkit import synthetic_results

    monkeypatch.setenv("FLEXRIDE_CACHE_DIR", str(tmp_path / "cache"))
    synthetic_results(duration=10.0).write_hdf5(tmp_path / "out.h5")  # the file examples read
    monkeypatch.chdir(tmp_path)
    ns: dict = {}
    exec(compile(block, where, "exec"), ns)
    printed = capsys.readouterr().out
    if "summary.to_json" in block:
        assert json.loads(printed[: printed.rindex("}") + 1])["run"]["sample_rate_hz"] == 1000.0
    if "calibration=b.calibration" in block:  # the calibrated car body (docs/fem.md)
        cal = ns["fb"].calibration
        assert cal["n_evaluations"] == 6 and not cal["from_cache"]
        assert "6.5 rhombic 2 6.492 -0.13 % rhombic" in printed
        assert "5.59 first vertical bending 1 5.57 -0.36 %" in printed
    elif "build_flexible_body" in block:
        cb = ns["cb"]
        shape = cb.shape_at((6.3, 0.95, 0.90 - cb.body.cg_height))
        assert shape.shape == (6, 113) and len(cb.floor_grid_nodes()[0]) == 95
        assert set(cb.export(max_modes=12)) >= {"nodes", "quads", "modes"}
