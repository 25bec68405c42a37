"""``flexride fe`` sub-commands."""

from __future__ import annotations

import json

import typer
from typer.testing import CliRunner

from flexride.cli.fe import fe_app

app = typer.Typer()
app.add_typer(fe_app, name="fe")
runner = CliRunner()


def test_modes_frame_json(cache_dir):
    res = runner.invoke(app, ["fe", "modes", "frame", "--json", "--n-modes", "4"])
    assert res.exit_code == 0, res.output
    data = json.loads(res.stdout)
    assert len(data["modes"]) == 4 and data["modes"][0]["frequency_hz"] > 10.0
    assert abs(data["mass"]["errors"]["mass"]) < 1e-3


def test_modes_carbody_table(cache_dir):
    res = runner.invoke(app, ["fe", "modes", "carbody", "--element-size", "0.6", "--n-modes", "3"])
    assert res.exit_code == 0, res.output
    assert "mass 35443" in res.stdout and "Ixx/Iyy/Izz" in res.stdout


def test_reduce_frame_table_and_json(cache_dir):
    res = runner.invoke(
        app, ["fe", "reduce", "frame", "--method", "craig-bampton", "--cutoff", "80"]
    )
    assert res.exit_code == 0, res.output
    assert "craig-bampton reduction" in res.stdout and "MAC" in res.stdout
    res = runner.invoke(
        app, ["fe", "reduce", "frame", "--method", "guyan", "--cutoff", "80", "--json"]
    )
    data = json.loads(res.stdout)
    assert data["method"] == "guyan" and data["guyan_error"] is not None


def test_user_errors_exit_2(cache_dir):
    for args in (
        ["fe", "reduce", "frame", "--method", "ritz"],
        ["fe", "reduce", "bogie"],
        ["fe", "reduce", "frame", "--cutoff", "-5"],
        ["fe", "calibrate", "--targets", "5,abc"],
        ["fe", "calibrate", "--targets", "8,5"],
        ["fe", "calibrate", "--targets", "5", "--variables", "paint"],
    ):
        res = runner.invoke(app, args)
        assert res.exit_code == 2, (args, res.output)
        assert "error" in res.output.lower()


def test_export_writes_json(cache_dir, tmp_path):
    out = tmp_path / "frame.json"
    res = runner.invoke(app, ["fe", "export", "frame", "--out", str(out), "--cutoff", "60"])
    assert res.exit_code == 0, res.output
    data = json.loads(out.read_text())
    assert data["beams"] and data["modes"]
