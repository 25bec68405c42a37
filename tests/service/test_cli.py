"""`flexride serve` and `flexride worker`: registered on a typer app and run as processes."""

from __future__ import annotations

import os
import signal
import subprocess
import time
from pathlib import Path

import httpx
import pytest
import typer
from typer.testing import CliRunner

from flexride.cli.service import register
from service.svc_testkit import (
    free_port,
    service_command,
    service_env,
    start_process,
    stop_process,
    wait_for,
)


def _app() -> typer.Typer:
    app = typer.Typer()
    register(app)
    return app


def _processes_with(env_value: str) -> list[int]:
    """Pids of processes whose environment contains ``env_value``."""
    pids = []
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                if env_value.encode() in (d / "environ").read_bytes():
                    pids.append(int(d.name))
            except OSError:
                pass
    return pids


def test_register_adds_serve_and_worker():
    result = CliRunner().invoke(_app(), ["--help"])
    assert result.exit_code == 0 and "serve" in result.output and "worker" in result.output
    result = CliRunner().invoke(_app(), ["serve", "--help"])
    assert "--host" in result.output and "--port" in result.output
    assert "--concurrency" in CliRunner().invoke(_app(), ["worker", "--help"]).output


def test_worker_needs_a_broker(monkeypatch):
    monkeypatch.delenv("FLEXRIDE_BROKER_URL", raising=False)
    from flexride.settings import get_settings

    get_settings.cache_clear()
    try:
        result = CliRunner().invoke(_app(), ["worker"])
    finally:
        get_settings.cache_clear()
    assert result.exit_code == 2 and "FLEXRIDE_BROKER_URL" in result.output


def test_invalid_settings_are_one_line_errors(monkeypatch):
    from flexride.settings import get_settings

    monkeypatch.setenv("FLEXRIDE_BROKER_URL", "redis://127.0.0.1:6379/9")
    try:
        result = CliRunner().invoke(_app(), ["worker", "--concurrency", "0"])
        assert result.exit_code == 2 and "FLEXRIDE_WORKERS" in result.output
        result = CliRunner().invoke(_app(), ["serve", "--port", "99999"])
        assert result.exit_code == 2 and "FLEXRIDE_PORT" in result.output
    finally:
        # the CLI writes its options into os.environ itself; monkeypatch.delenv would record
        # and later restore them, so remove them directly
        os.environ.pop("FLEXRIDE_WORKERS", None)
        os.environ.pop("FLEXRIDE_PORT", None)
        get_settings.cache_clear()


def test_serve_starts_the_api_and_the_embedded_runner(tmp_path):
    port = free_port()
    data = tmp_path / "data"
    log = tmp_path / "serve.log"
    proc = start_process([*service_command(), "serve", "--host", "127.0.0.1", "--port",
                          str(port)],
                         service_env(FLEXRIDE_DATA_DIR=str(data), FLEXRIDE_WORKERS="1"), log)
    url = f"http://127.0.0.1:{port}/api/v1"
    try:
        def healthy():
            try:
                r = httpx.get(f"{url}/health", timeout=2)
                return r.status_code == 200 and r.json()
            except httpx.HTTPError:
                return None

        body = wait_for(healthy, 60.0, 0.3, "the API")
        assert body["runner"] == "embedded" and body["database"]["ok"]
        assert (data / "flexride.db").is_file() and (data / "results").is_dir()
        wait_for(lambda: any(w["alive"] for w in healthy()["workers"]), 60.0, 0.5,
                 "the embedded worker")
        out = log.read_text()
        assert f"API docs at http://127.0.0.1:{port}/docs" in out
        assert httpx.get(f"http://127.0.0.1:{port}/docs").status_code == 200
        assert len(_processes_with(str(data))) >= 2  # the API and its worker process
        proc.send_signal(signal.SIGTERM)  # graceful: uvicorn shuts down, then re-raises it
        assert proc.wait(30) == 128 + signal.SIGTERM  # through SystemExit: exit handlers ran
        assert "Application shutdown complete" in log.read_text()
    except (AssertionError, subprocess.TimeoutExpired):
        print(log.read_text())
        raise
    finally:
        stop_process(proc)
    wait_for(lambda: not _processes_with(str(data)), 15.0, 0.3, "no process left behind")


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_a_stop_signal_to_the_process_group_ends_everything_cleanly(tmp_path, sig):
    """SIGTERM (a process manager) or Ctrl-C (SIGINT to the terminal's group) reaches the API
    and its workers at once, one of them busy with a job: everything exits within 10 s, with
    no traceback, no worker reported dead or restarted, no leaked semaphore, and the running
    job is queued again."""
    from flexride.store import JobStore

    port, data, log = free_port(), tmp_path / "data", tmp_path / "serve.log"
    proc = start_process([*service_command(), "serve", "--host", "127.0.0.1", "--port",
                          str(port)],
                         service_env(FLEXRIDE_DATA_DIR=str(data), FLEXRIDE_WORKERS="1"), log)
    url = f"http://127.0.0.1:{port}/api/v1"
    try:
        def worker_alive():
            try:
                return httpx.get(f"{url}/health", timeout=2).json()["workers"][0]["alive"]
            except (httpx.HTTPError, KeyError, IndexError):
                return False

        wait_for(worker_alive, 90.0, 0.5, "the embedded worker")
        r = httpx.post(f"{url}/jobs", json={"preset": "paper-metro",
                                             "overrides": {"duration_s": 60.0}}, timeout=60)
        job = r.json()["id"]
        wait_for(lambda: httpx.get(f"{url}/jobs/{job}", timeout=5).json()["status"] == "running",
                 120.0, 0.3, "the job to run")
        t0 = time.monotonic()
        os.killpg(proc.pid, sig)
        proc.wait(10)
        assert time.monotonic() - t0 < 10.0
        wait_for(lambda: not _processes_with(str(data)), 10.0, 0.2, "no process left behind")
    except (AssertionError, subprocess.TimeoutExpired):
        print(log.read_text())
        raise
    finally:
        stop_process(proc)
    out = log.read_text()
    for bad in ("Traceback", "leaked semaphore", "died (exit code", "KeyboardInterrupt"):
        assert bad not in out, out
    store = JobStore.from_url(f"sqlite:///{data / 'flexride.db'}", create=False)
    assert store.get_job(job).status == "queued"
