"""End to end through the embedded runner: real simulations in real worker processes.

A short run (2 s simulated) is submitted, its progress polled and its summary, series and
spectrum read; a worker process killed with SIGKILL mid-job gets its job retried; a service
stop interrupts a job and the next start finishes it (nothing lost across a restart).
"""

from __future__ import annotations

import json
import os
import signal
import warnings

import pytest

from flexride.jobs.presence import parse_worker_name
from service.svc_testkit import make_settings, wait_for

API = "/api/v1"
pytestmark = pytest.mark.filterwarnings("ignore:Using `httpx`")


def _client(data_dir, **kw):
    from fastapi.testclient import TestClient

    from flexride.api import create_app

    settings = make_settings(data_dir, runner="embedded", workers=1, heartbeat_interval_s=1.0,
                             heartbeat_timeout_s=20.0, reaper_interval_s=1.0, **kw)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return TestClient(create_app(settings), raise_server_exceptions=False)


def _submit(client, duration, **overrides):
    r = client.post(f"{API}/jobs", json={"preset": "paper-random-straight-80", "reuse": False,
                                         "overrides": {"duration_s": duration,
                                                       "distance_m": None, **overrides}})
    assert r.status_code == 201, r.text
    return r.json()["id"]


def _job(client, job_id):
    return client.get(f"{API}/jobs/{job_id}").json()


def _final(client, job_id, timeout=120.0):
    return wait_for(lambda: (j := _job(client, job_id))["status"] not in ("queued", "running")
                    and j, timeout, 0.25, f"job {job_id} to finish")


def test_embedded_runner_end_to_end(tmp_path):
    data = tmp_path / "data"
    with _client(data) as client:
        job_id = _submit(client, 2.0)
        seen = set()

        def progressed():
            j = _job(client, job_id)
            seen.add((j["status"], round(j["progress"], 2)))
            return j["status"] in ("succeeded", "failed", "cancelled") and j

        job = wait_for(progressed, 120.0, 0.1, "the short job")
        assert job["status"] == "succeeded", job["error"]
        assert any(s == "running" for s, _ in seen) or job["run_time_s"] < 1.0
        assert job["attempts"] == 1 and job["worker"].startswith("embedded-")
        assert job["progress"] == 1.0 and job["solver_wall_time_s"] > 0
        assert job["queue_time_s"] >= 0 and job["run_time_s"] > 0
        summary = client.get(f"{API}/jobs/{job_id}/summary").json()["summary"]
        pc = summary["points"]["PC"]["directions"]["z"]
        assert pc["peaks"]["max_abs"] > 0 and summary["run"]["speed_kmh"] == 80.0
        series = client.get(f"{API}/jobs/{job_id}/series",
                            params={"channels": ["carbody.PR.acc.z"], "max_points": 300}).json()
        ch = series["channels"][0]
        assert len(ch["time"]) <= 300 and ch["time"][-1] == pytest.approx(2.0, abs=0.01)
        spec = client.get(f"{API}/jobs/{job_id}/spectrum",
                          params={"channels": ["carbody.PR.acc.z"], "fmax": 50}).json()
        assert spec["frequencies"][-1] <= 50 and len(spec["channels"][0]["values"]) > 10
        assert (data / "results" / f"{job_id}.h5").is_file()
        health = client.get(f"{API}/health").json()
        assert health["status"] == "ok" and health["runner"] == "embedded"
        assert any(w["alive"] and w["kind"] == "embedded" for w in health["workers"])

        # a worker process killed mid-job: the job is retried on a fresh process
        long_id = _submit(client, 25.0)
        job = wait_for(lambda: (j := _job(client, long_id))["status"] == "running"
                       and j["progress"] >= 0.05 and j, 120.0, 0.1, "the long job to run")
        _, pid, _ = parse_worker_name(job["worker"])
        os.kill(pid, signal.SIGKILL)
        job = _final(client, long_id, 180.0)
        assert job["status"] == "succeeded", job
        assert job["attempts"] == 2 and "requeued" not in job["message"]
        assert str(pid) not in job["worker"]

        # a stop while a job runs: it is requeued (the attempt does not count)...
        stop_id = _submit(client, 25.0)
        wait_for(lambda: _job(client, stop_id)["status"] == "running", 120.0, 0.1,
                 "the third job to run")
    with _client(data) as client:  # ...and the restarted service finishes it
        assert _job(client, job_id)["status"] == "succeeded"  # records survive
        assert client.get(f"{API}/jobs/{job_id}/download").status_code == 200
        job = _final(client, stop_id, 180.0)
        assert job["status"] == "succeeded" and job["attempts"] == 1, job


def test_fe_export_job_on_the_embedded_runner(tmp_path, monkeypatch):
    """``GET /fe/carbody`` for a model not built yet: a job of kind fe_export that a worker
    process builds (a real coarse car body, 0.5 m elements, modes to 30 Hz) with progress in
    its record; the API serves the file it wrote — the same JSON as ``flexride fe export`` —
    and other modes of the body come from the FE cache the worker filled."""
    from typer.testing import CliRunner

    from flexride.cli.fe import fe_app

    data = tmp_path / "data"
    params = {"element_size_m": 0.5, "cutoff_hz": 30, "max_modes": 6}
    with _client(data, fe_wait_s=0.0) as client:
        r = client.get(f"{API}/fe/carbody", params=params)
        assert r.status_code == 202, r.text
        job_id = r.json()["job_id"]
        seen: list[tuple[str, str]] = []

        def built():
            r = client.get(f"{API}/fe/carbody", params=params)
            if r.status_code == 202:
                assert r.json()["job_id"] == job_id  # one job, however often asked for
                seen.append((r.json()["status"], r.json()["message"]))
            return r.status_code != 202 and r

        r = wait_for(built, 180.0, 0.1, "the FE export")
        assert r.status_code == 200, r.text
        got = r.json()
        model = got.pop("model")
        assert (model["element_size_m"], model["cutoff_hz"], model["max_modes"]) == (0.5, 30.0, 6)
        assert not model["from_cache"] and model["n_elastic_modes"] >= len(got["modes"]) == 6
        assert len(got["nodes"]) > 500
        assert any(s == "building" and m.startswith("building the FE model of the car body")
                   for s, m in seen), seen
        job = _job(client, job_id)
        assert job["kind"] == "fe_export" and job["status"] == "succeeded", job
        assert job["worker"].startswith("embedded-") and job["attempts"] == 1
        _, pid, _ = parse_worker_name(job["worker"])
        assert pid != os.getpid()  # built in a worker process, not in the API
        # other modes of the same body: a new job, loaded from the FE cache of the service
        client.app.state.services.fe.wait_s = 60.0
        r = client.get(f"{API}/fe/carbody", params={**params, "max_modes": 2})
        assert r.status_code == 200 and r.json()["model"]["from_cache"] is True
        assert len(r.json()["modes"]) == 2
        listed = client.get(f"{API}/jobs", params={"kind": "fe_export"}).json()
        assert listed["total"] == 2 and client.get(f"{API}/jobs").json()["total"] == 0
        cache_dir = client.app.state.services.settings.cache_dir
    # the same JSON as `flexride fe export` (its own process, the same FE cache)
    monkeypatch.setenv("FLEXRIDE_CACHE_DIR", str(cache_dir))
    out = tmp_path / "carbody.json"
    res = CliRunner().invoke(fe_app, ["export", "carbody", "--element-size", "0.5", "--cutoff",
                                      "30", "--n-modes", "6", "--out", str(out)])
    assert res.exit_code == 0, res.output
    assert got == json.loads(out.read_text())
