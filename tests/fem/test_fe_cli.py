"""``flexride fe`` sub-commands."""

from __future__ import annotations

import json
import re
from pathlib import Path

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
        ["fe", "calibrate", "--targets", "5:wobble"],
        ["fe", "calibrate", "--targets", "5", "--variables", "paint"],
        ["fe", "calibrate", "--targets", "5", "--measured", "m.csv"],
        ["fe", "calibrate", "--measured", "no-such-file.csv"],
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


DOCS_CSV = re.findall(r"```csv\n(.*?)```",
                      (Path(__file__).resolve().parents[2] / "docs" / "fem.md").read_text(
                          encoding="utf-8"), flags=re.S)[0]


def test_calibrate_typed_targets_reports_what_it_cannot_pair(cache_dir):
    res = runner.invoke(app, ["fe", "calibrate", "--targets", "11:torsion,6.5:rhombic",
                              "--element-size", "0.6", "--variables", "floor_depth",
                              "--n-modes", "8", "--max-evaluations", "2"])
    assert res.exit_code == 0, res.output
    assert "NOT PAIRED: target 1 (11.000 Hz torsion): no mode of type 'torsion'" in res.stdout
    assert re.search(r"2 +6\.500 +rhombic +3 ", res.stdout), res.stdout
    assert "1 target(s) NOT PAIRED" in res.output


def test_calibrate_measured_modes_json(cache_dir, tmp_path):
    path = tmp_path / "modal_test.csv"
    path.write_text(DOCS_CSV, encoding="utf-8")
    res = runner.invoke(app, ["fe", "calibrate", "--measured", str(path), "--json",
                              "--element-size", "0.6", "--variables", "floor_depth",
                              "--max-evaluations", "4"])
    assert res.exit_code == 0, res.output
    data = json.loads(res.stdout)
    assert [p["mode"] for p in data["pairs"]] == [1, 3]
    assert data["pairs"][1]["model_type"] == "rhombic" and data["pairs"][1]["mac"] > 0.9
    assert data["sensors"]["n_dofs"] == 15 and data["unpaired"] == []


def test_calibrate_measured_file_errors_name_the_line(cache_dir, tmp_path):
    path = tmp_path / "bad.csv"
    path.write_text(DOCS_CSV.replace("0,1.4,1.5,y", "0,1.4,1.5,up"), encoding="utf-8")
    res = runner.invoke(app, ["fe", "calibrate", "--measured", str(path)])
    assert res.exit_code == 2
    assert "bad.csv line 13, column 4 'direction'" in res.output
