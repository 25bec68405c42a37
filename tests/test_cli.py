"""The command-line interface: one run as a user would (a subprocess: entry point, exit code,
JSON), the rest in-process with typer's runner (same exit codes and messages, no start-up)."""

from __future__ import annotations

import json
import subprocess
import sys

import h5py
import pytest

from flexride.results import Results


def _run(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "flexride.cli", *args], capture_output=True,
                          text=True, cwd=cwd, timeout=600)


def _invoke(*args):
    """The CLI in this process: (exit code, standard output, standard error, one line)."""
    from typer.testing import CliRunner

    from flexride.cli import app

    r = CliRunner().invoke(app, list(args))
    return r.exit_code, r.stdout, r.stderr, " ".join(r.stderr.split())


def test_run_preset_json(tmp_path):
    out = tmp_path / "r.h5"
    p = _run("run", "--preset", "paper-random-straight-80", "--duration", "1", "-o", str(out),
             "--json")
    assert p.returncode == 0, p.stderr
    summary = json.loads(p.stdout)
    names = {r["channel"] for r in summary["accelerations"]}
    for point in ("PR", "PFB", "PC", "PRB", "PLA", "PRA"):
        assert f"carbody.{point}.acc.z" in names and f"carbody.{point}.acc.y" in names
    res = Results.read_hdf5(out)
    assert res.time[-1] > 0.99 and res.scenario["speed_kmh"] == 80.0
    # the automatic step, its limit and margin in the summary and the file's attributes
    step = summary["time_step"]
    assert step["auto"] and step["s"] == pytest.approx(1.0 / 16000.0)
    assert step["margin"] == pytest.approx(step["limit_s"] / step["s"]) and step["margin"] > 1.25
    with h5py.File(out) as f:
        assert f.attrs["time_step_s"] == step["s"] and f.attrs["time_step_auto"]
        assert f.attrs["time_step_margin"] == pytest.approx(step["margin"])
        assert "steady rolling" in f.attrs["time_step_limited_by"]


def test_presets_lists_all():
    code, out, _, _ = _invoke("presets", "--json")
    assert code == 0
    assert len(json.loads(out)) >= 18


def test_errors_are_one_line_and_nonzero(tmp_path):
    code, _, _, line = _invoke("run", "--preset", "nope", "-o", str(tmp_path / "x.h5"))
    assert code == 2 and line.startswith("error: unknown preset")
    code, _, _, line = _invoke("run", "--preset", "paper-metro", "--set", "solver.dt=1e-3",
                               "-o", str(tmp_path / "x.h5"))
    assert code == 2 and "use solver.dt = auto or" in line
    assert "largest stable step" in line and "period-two" in line
    assert not (tmp_path / "x.h5").exists()
    code, _, _, line = _invoke("run", "--preset", "paper-metro", "--set", "solver.dt=1.0",
                               "-o", str(tmp_path / "x.h5"))
    assert code == 2 and line.startswith("error: ") and "solver.dt:" in line
    assert "or 'auto', got 1.0" in line and line.count("\n") == 0
    code, _, _, line = _invoke("run", str(tmp_path / "missing.yaml"))
    assert code == 2 and "not found" in line
    code, _, err, line = _invoke("run", "--preset", "paper-metro", "--set",
                                 "excitation.9.seed=3", "-o", str(tmp_path / "x.h5"))
    assert code == 2 and "Traceback" not in err and "overrides.excitation.9.seed" in line


def _nested_files(tmp_path):
    """Scenario files nested too deeply or expanding to too much data."""
    laughs = ['l0: &l0 ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]']
    laughs += [f"l{i}: &l{i} [" + ", ".join([f"*l{i - 1}"] * 9) + "]" for i in range(1, 9)]
    files = {
        "brackets.yaml": "[" * 100_000,
        "mapping.yaml": "\n".join("  " * i + "a:" for i in range(3000)),
        "brackets.json": "[" * 100_000,
        "just-too-deep.yaml": "{a: " * 65 + "1" + "}" * 65,
        "aliases.yaml": "\n".join(laughs),
    }
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    (tmp_path / "binary.yaml").write_bytes(b"name: \xff\xfe\n")
    return [tmp_path / name for name in [*files, "binary.yaml"]]


def test_deeply_nested_scenario_file_is_one_line(tmp_path):
    deep = _nested_files(tmp_path)[0]
    code, _, err, line = _invoke("run", str(deep), "-o", str(tmp_path / "x.h5"))
    assert code == 2 and "Traceback" not in err, err
    assert line == f"error: {deep}: nested more than 64 levels deep"


def test_nested_or_expanding_files_are_refused_before_anything_runs(tmp_path):
    from typer.testing import CliRunner

    from flexride.cli import app

    expected = {"binary.yaml": "not UTF-8 text", "aliases.yaml": "more than 2,000,000 values"}
    for path in _nested_files(tmp_path):
        r = CliRunner().invoke(app, ["run", str(path), "-o", str(tmp_path / "x.h5")])
        assert r.exit_code == 2 and isinstance(r.exception, SystemExit | None), r.output
        message = " ".join(r.output.split())  # rich wraps long lines
        assert message.startswith("error: ") and str(path.name) in message, r.output
        assert expected.get(path.name, "nested more than 64 levels deep") in message, r.output
    r = CliRunner().invoke(app, ["run", "--preset", "paper-metro", "--set", "x=" + "[" * 5000])
    assert r.exit_code == 2 and "--set x: nested more than 64 levels deep" in r.output
    ok = tmp_path / "ok.yaml"  # 64 levels are fine for the parser (the scenario is invalid)
    ok.write_text("{a: " * 63 + "1" + "}" * 63)
    r = CliRunner().invoke(app, ["run", str(ok), "-o", str(tmp_path / "x.h5")])
    assert r.exit_code == 2 and "nested more" not in r.output
    assert "ok.yaml: speed_kmh: Field required" in r.output
