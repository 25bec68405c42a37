"""The CLI's terminal output: tables fitted to the terminal's width without cutting words, the
legend of the measuring points under the comfort table, and EN 14363's force names in the
running-safety table."""

from __future__ import annotations

import io

import pytest
from rich.console import Console
from rich.table import Table

from analysis.conftest import make_results
from flexride.analysis import analyze, safety_table, summary_table
from flexride.cli.tables import fit_table, points_legend


@pytest.fixture(scope="module")
def summary():
    return analyze(make_results(duration=12.0, wheelsets=4))


def _render(renderable, width: int) -> str:
    console = Console(width=width, record=True, file=io.StringIO(), color_system=None)
    console.print(fit_table(renderable, console) if isinstance(renderable, Table) else renderable)
    return console.export_text()


@pytest.mark.parametrize("width", [80, 100, 160])
def test_comfort_table_fits_the_terminal_without_cutting_words(summary, width):
    out = _render(summary_table(summary), width)
    assert "…" not in out, out  # no 'excell…'
    assert max(len(line) for line in out.splitlines()) <= width
    for word in ("excellent", "N_MV", "PRA", "uncomfortable"):
        assert word in out, word


def test_a_table_that_fits_is_left_as_it_is(summary):
    table = summary_table(summary)
    box_before = table.box
    console = Console(width=400, file=io.StringIO())
    assert fit_table(table, console).box is box_before


def test_safety_table_uses_en14363_names(summary):
    out = _render(safety_table(summary), 80)
    assert "Y/Q" in out and "ΔQ/Q" in out and "ΣY kN" in out
    assert "Q/P = Y/Q" in out and "ΔP/P = ΔQ/Q" in out  # GB 5599's names in the caption
    assert "…" not in out


def test_points_legend_from_the_recorded_points():
    run = make_results(duration=6.0)
    text = points_legend(run.recorded_points, ["PR", "PC", "PLA", "NOPE"]).plain
    assert text.startswith("Points: PR roof above the front bogie centre (x 6.3, y 0, z 3.8 m)")
    assert "PC floor at the car-body centre" in text
    assert "PLA floor above the rear bogie's left air spring (x -6.3, y 0.95, z 1.1 m)" in text
    assert "NOPE" not in text
    assert points_legend([], ["PC"]).plain == ""


def test_analyze_prints_the_legend_at_80_columns(tmp_path, monkeypatch):
    from typer.testing import CliRunner

    import flexride.cli as cli

    path = make_results(duration=6.0).write_hdf5(tmp_path / "r.h5")
    console = Console(width=80, record=True, file=io.StringIO(), color_system=None)
    monkeypatch.setattr(cli, "console", console)
    result = CliRunner().invoke(cli.app, ["analyze", str(path)])
    assert result.exit_code == 0, result.output
    out = console.export_text()
    assert "Points: PR roof above the front bogie centre" in out
    assert "excellent" in out and "excell…" not in out
    assert max(len(line) for line in out.splitlines()) <= 80
