"""The solver's compile state: ``GET /health`` says ``compiling`` (with an estimate) until the
kernels are in the cache, and ``POST /jobs`` answers without waiting for a compilation (the
time-step check is left to the worker then); one process compiles, recording the state.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from flexride.jobs import warmup

ROOT = Path(__file__).resolve().parents[2]

_COLD_SERVICE = textwrap.dedent("""
    import json, sys, time, warnings
    sys.path.insert(0, sys.argv[2])
    from pathlib import Path
    from fastapi.testclient import TestClient
    from flexride.api import create_app
    from service.svc_testkit import make_settings

    out = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        app = create_app(make_settings(Path(sys.argv[1])))
    with TestClient(app) as client:
        out["health"] = client.get("/api/v1/health").json()["solver"]
        body = {"preset": "paper-random-straight-80", "reuse": False,
                "overrides": {"duration_s": 0.5, "distance_m": None}}
        t = time.perf_counter()
        r = client.post("/api/v1/jobs", json=body)
        out["post_s"] = time.perf_counter() - t
        out["status"], out["preflight"] = r.status_code, r.json().get("preflight")
        body["overrides"]["solver.dt"] = 5e-3
        r = client.post("/api/v1/jobs/validate", json=body)
        out["unstable"] = r.status_code, r.json().get("preflight")
        body["overrides"]["speed_kmh"] = -1
        out["invalid"] = client.post("/api/v1/jobs", json=body).status_code
    print(json.dumps(out))
""")


def test_a_cold_service_says_compiling_and_queues_without_waiting(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba"),
           "FLEXRIDE_SETUP_CACHE": "off"}
    script = tmp_path / "cold_service.py"
    script.write_text(_COLD_SERVICE)
    t = time.monotonic()
    done = subprocess.run([sys.executable, str(script), str(tmp_path / "data"),
                           str(ROOT / "tests")], env=env, cwd=ROOT, capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
    out = json.loads(done.stdout.strip().splitlines()[-1])
    assert out["health"]["state"] == "compiling"
    assert out["health"]["estimate_s"] > 0
    assert out["status"] == 201
    assert "deferred" in out["preflight"] and "compiled" in out["preflight"]["deferred"]
    # the unstable step is left to the worker while compiling; invalid fields still refused
    assert out["unstable"][0] == 200 and "deferred" in out["unstable"][1]
    assert out["invalid"] == 422
    # the compiling child process was stopped with the service (it did not run to its end)
    assert time.monotonic() - t < 240
    assert not (tmp_path / "numba" / warmup.STATE_FILE).exists() or \
        json.loads((tmp_path / "numba" / warmup.STATE_FILE).read_text())["state"] == "compiling"


@pytest.fixture
def cache_dir(tmp_path, monkeypatch):
    monkeypatch.setattr(warmup, "numba_cache_dir", lambda: tmp_path)
    return tmp_path


def test_the_state_file_gives_the_health_answer(cache_dir):
    state = warmup.SolverState()
    unknown = state.status()
    assert unknown == {"state": "compiling", "estimate_s": warmup.DEFAULT_COMPILE_S}
    (cache_dir / warmup.STATE_FILE).write_text(json.dumps({
        "stamp": warmup.solver_stamp(), "state": "compiling", "started_at": time.time() - 10.0,
        "expected_s": 40.0}))
    assert state.status()["state"] == "compiling"
    assert 25.0 <= state.status()["estimate_s"] <= 30.5
    (cache_dir / warmup.STATE_FILE).write_text(json.dumps({
        "stamp": "another build", "state": "ready"}))
    assert state.status()["state"] == "compiling"
    (cache_dir / warmup.STATE_FILE).write_text(json.dumps({
        "stamp": warmup.solver_stamp(), "state": "ready", "compile_s": 12.0}))
    assert state.status() == {"state": "ready", "estimate_s": None}


def test_one_compilation_records_its_start_and_duration(cache_dir, monkeypatch):
    seen = []
    monkeypatch.setattr(warmup, "_warm_run", lambda: seen.append(warmup.read_state()))
    warmup.warm_numba()
    assert seen[0]["state"] == "compiling" and seen[0]["expected_s"] > 0
    done = warmup.read_state()
    assert done["state"] == "ready" and done["stamp"] == warmup.solver_stamp()
    assert done["compile_s"] >= 0.0
    warmup.warm_numba()  # ready: loads, the record stays
    assert warmup.read_state() == done and len(seen) == 2


def test_a_process_that_never_started_the_loader_checks_in_the_request():
    assert warmup.SolverState().usable(wait_s=0.0)
