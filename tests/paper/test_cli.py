"""``flexride paper report``: one readable error line and exit code 2 for user errors; the
report of the tiny study through the command line."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from flexride.cli import app
from flexride.paper.claims import CLAIMS
from paper.conftest import TINY_MESH, TINY_OVERRIDES


def _invoke(args: list[str]):
    return CliRunner().invoke(app, ["paper", "report", *args])


@pytest.mark.parametrize(("args", "words"), [
    (["--seeds", "0"], "--seeds"),
    (["--jobs", "0"], "--jobs"),
    (["--conditions", "tunnel"], "tunnel"),
    (["--speeds", "fast"], "--speeds"),
    (["--mesh-sizes", "0.2"], "mesh sizes"),
])
def test_user_errors_are_one_line_and_exit_code_2(tmp_path, args, words):
    r = _invoke(["-o", str(tmp_path / "r"), *args])
    assert r.exit_code == 2
    lines = [ln for ln in r.output.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("error:") and words in lines[0]


def test_output_that_is_a_file_is_refused(tmp_path):
    target = tmp_path / "file.txt"
    target.write_text("x")
    r = _invoke(["-o", str(target), "--conditions", "settlement", "--speeds", "50"])
    assert r.exit_code == 2 and "not a directory" in r.output


def test_report_through_the_cli_reuses_the_tiny_study(tiny_report, monkeypatch):
    from dataclasses import replace

    from flexride.paper import report as paper_report

    real = paper_report.run_report

    def with_test_mesh(directory, options=None, progress=None):
        return real(directory, replace(options, overrides=TINY_OVERRIDES), progress)

    monkeypatch.setattr(paper_report, "run_report", with_test_mesh)
    directory, _ = tiny_report
    r = _invoke(["-o", str(directory), "--conditions", "random-straight,settlement",
                 "--speeds", "50", "--distance-scale", "0.01", "--jobs", "1",
                 "--mesh-sizes", ",".join(str(h) for h in TINY_MESH)])
    assert r.exit_code == 0, r.output
    # Table 3's 4 runs and the pre-calculation's 2 tracks x 3 meshes
    assert "10 from the cache" in r.output and f"{len(CLAIMS)} claims" in r.output
