"""The command-line interface, run as a user would (subprocess, exit codes, JSON)."""

from __future__ import annotations

import json
import subprocess
import sys

from flexride.results import Results


def _run(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "flexride.cli", *args], capture_output=True,
                          text=True, cwd=cwd, timeout=600)


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


def test_presets_lists_all():
    p = _run("presets", "--json")
    assert p.returncode == 0
    assert len(json.loads(p.stdout)) >= 18


def test_errors_are_one_line_and_nonzero(tmp_path):
    p = _run("run", "--preset", "nope", "-o", str(tmp_path / "x.h5"))
    assert p.returncode == 2
    assert p.stderr.strip().startswith("error: unknown preset")
    p = _run("run", "--preset", "paper-metro", "--set", "solver.dt=1e-3", "-o",
             str(tmp_path / "x.h5"))
    assert p.returncode == 2 and "use solver.dt =" in p.stderr
    assert not (tmp_path / "x.h5").exists()
    p = _run("run", str(tmp_path / "missing.yaml"))
    assert p.returncode == 2 and "not found" in p.stderr
