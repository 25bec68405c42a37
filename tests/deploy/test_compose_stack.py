"""The Docker deployment, really run: images built without a registry, ``docker compose up``
with the API, two workers, Redis and PostgreSQL, jobs end to end through the published port.

A Docker engine is started when none runs (tests/deploy/engine.py: its own data root and socket);
tools/docker_images.py makes the Debian base with debootstrap and builds the flexride, Redis
and PostgreSQL images on it, or finds them built from the same inputs by an earlier run. The
stack runs with secrets from files (docker/compose.secrets.yml), the API on a free port of
127.0.0.1 and nothing else published; a short job and a small study go through the API, the
HDF5 file is downloaded, a worker container is restarted while it runs a job, and
``docker compose down -v`` removes everything. Without an engine the tests fail with one line.
"""

from __future__ import annotations

import io
import json
import sys
import time
from collections.abc import Iterator
from typing import Any

import h5py
import httpx
import pytest

from deploy.engine import Engine, EngineUnavailable, get_engine
from deploy.figures import record
from deploy.stack import PROJECT, REPO, Stack

sys.path.insert(0, str(REPO / "tools"))
import docker_images

WORKERS = 2
JOB = {"preset": "paper-random-straight-80", "reuse": False}


@pytest.fixture(scope="module")
def engine() -> Iterator[Engine]:
    try:
        eng = get_engine()
    except EngineUnavailable as exc:
        pytest.fail(f"no Docker engine: {exc}", pytrace=False)
    yield eng
    eng.release()


@pytest.fixture(scope="module")
def images(engine: Engine, request: pytest.FixtureRequest) -> list[docker_images.Built]:
    """Every image of the compose file, built (or found) once per session; figures shown."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DOCKER_HOST", engine.host)
        start = time.monotonic()
        try:
            built = docker_images.build_all()
        except SystemExit as exc:  # the tool's own message (debootstrap, a build failed)
            pytest.fail(str(exc), pytrace=False)
    record(request.config, f"images ready in {time.monotonic() - start:.0f} s:\n"
           + docker_images.report(built))
    return built


@pytest.fixture(scope="module")
def stack(engine: Engine, images: list[docker_images.Built], request: pytest.FixtureRequest,
          tmp_path_factory: pytest.TempPathFactory) -> Iterator[Stack]:
    s = Stack(engine, docker_images.compose_env(images), tmp_path_factory.mktemp("stack"))
    s.remove_stale()  # what interrupted earlier runs left
    try:
        start = time.monotonic()
        s.up(WORKERS)
        s.wait_healthy(3 + WORKERS)
        record(request.config, f"compose up -d --scale worker={WORKERS}: all "
               f"{3 + WORKERS} containers healthy in {time.monotonic() - start:.0f} s")
        yield s
    finally:
        s.down()


@pytest.fixture(scope="module")
def api(stack: Stack) -> Iterator[httpx.Client]:
    """A client of the published API port, with the token read from the secret file."""
    with httpx.Client(base_url=stack.url, timeout=30.0,
                      headers={"Authorization": f"Bearer {stack.token}"}) as client:
        yield client


def _wait(what: str, probe: Any, timeout: float, stack: Stack) -> Any:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = probe()
        if value:
            return value
        time.sleep(0.5)
    raise AssertionError(f"timed out waiting for {what}\n{stack.logs()}")


def _final(api: httpx.Client, job_id: str, stack: Stack, timeout: float = 240.0) -> dict:
    def done() -> dict | None:
        job = api.get(f"/jobs/{job_id}").json()
        return job if job["status"] not in ("queued", "running") else None
    return _wait(f"job {job_id}", done, timeout, stack)


def _submit(api: httpx.Client, duration_s: float) -> str:
    r = api.post("/jobs", json={**JOB, "overrides": {"duration_s": duration_s,
                                                       "distance_m": None}})
    assert r.status_code == 201, r.text
    return str(r.json()["id"])


def _image(images: list[docker_images.Built], name: str) -> str:
    return next(b.tag for b in images if b.name == name)


def test_flexride_image_is_lean_and_holds_no_build_secrets(engine, images):
    tag = _image(images, "flexride")
    script = ("for c in gcc cc c++ make pip pip3; do command -v $c && exit 10; done; "
              "test -z \"$(ls -A /var/lib/apt/lists)\" || exit 11; "
              "test ! -e /root/.cache && test ! -e /home/flexride/.cache || exit 12; "
              "find /opt/flexride-numba -name '*.nbi' | grep -q . || exit 13; "
              "grep -q '\"ready\"' /opt/flexride-numba/flexride-solver.json || exit 13; "
              "test -s /opt/flexride/lib/python3.11/site-packages/plotly/package_data/"
              "plotly.min.js || exit 14; "
              "python -c 'import flexride.api.main, flexride.fem, pyfe3d.quad4r, h5py, "
              "scipy.sparse.linalg, celery, psycopg' || exit 15; id -u")
    r = engine.docker("run", "--rm", "--network=none", "--entrypoint=sh", tag, "-c", script,
                      check=False)
    assert r.returncode == 0 and r.stdout.strip() == "1000", (r.returncode, r.stdout, r.stderr)
    # the build arguments (pip's index settings, CA certificates) stay in the build stage
    meta = engine.docker("image", "inspect", tag).stdout + engine.docker(
        "history", "--no-trunc", tag).stdout
    assert "BEGIN CERTIFICATE" not in meta and "EXTRA_CA_CERTS" not in meta
    assert all(b.size_mb > 0 for b in images)


def test_entrypoint_waits_for_the_services_then_says_why(engine, images):
    r = engine.docker("run", "--rm", "--network=none", "-e", "FLEXRIDE_WAIT_S=2",
                      "-e", "FLEXRIDE_BROKER_URL=redis://redis:6379/0",
                      _image(images, "flexride"), "true", check=False, timeout=120)
    last = r.stderr.strip().splitlines()[-1]
    assert r.returncode == 1 and last.startswith(
        "flexride-entrypoint: Redis is not reachable after 2 s"), r.stderr


def test_stack_is_healthy_with_secrets_from_files(stack, api):
    states = stack.health()
    assert len(states) == 3 + WORKERS and set(states.values()) == {"healthy"}, states
    health = _wait("both workers in /health", lambda: (h := api.get("/health").json())
                   and sum(w["kind"] == "celery" and w["alive"] for w in h["workers"])
                   >= WORKERS and h, 120.0, stack)
    assert health["runner"] == "celery" and health["broker"]["ok"]
    # the token is required, and no secret is in a container's environment
    assert httpx.post(f"{stack.url}/jobs", json=JOB).status_code == 401
    env = json.dumps([c["Config"]["Env"] for c in stack.containers()])
    assert stack.token not in env and stack.db_password not in env
    # only the API is published, on loopback
    ports = [p for c in stack.containers() for p in (c["HostConfig"]["PortBindings"] or {})
             .values() for p in p]
    assert ports == [{"HostIp": "127.0.0.1", "HostPort": str(stack.port)}]


def test_short_job_end_to_end_with_its_hdf5_file(stack, api):
    job_id = _submit(api, 2.0)
    job = _final(api, job_id, stack)
    assert job["status"] == "succeeded", (job, stack.logs())
    assert job["runner"] == "celery"
    hosts = {c["Config"]["Hostname"] for c in stack.service_containers("worker")}
    assert job["worker"].rpartition("@")[2] in hosts
    summary = api.get(f"/jobs/{job_id}/summary").json()["summary"]
    assert summary["points"]["PR"]["directions"]["z"]["peaks"]["max_abs"] > 0
    r = api.get(f"/jobs/{job_id}/download")
    assert r.status_code == 200, r.text
    with h5py.File(io.BytesIO(r.content), "r") as f:
        assert f["time"].shape[0] > 100 and "carbody.PC.acc.z" in f["channels"]
        assert json.loads(f.attrs["scenario_json"])["duration_s"] == 2.0


def test_small_study(stack, api):
    r = api.post("/studies", json={
        "name": "deploy-study", "base": {"preset": JOB["preset"]}, "speeds_kmh": [60, 80],
        "overrides": {"duration_s": 1.5, "distance_m": None}, "reuse": False})
    assert r.status_code == 201, r.text
    study_id = r.json()["id"]
    detail = _wait("the study", lambda: (d := api.get(f"/studies/{study_id}").json())["status"]
                   not in ("queued", "running") and d, 300.0, stack)
    assert detail["status"] == "succeeded", detail["counts"]
    rows = [t for t in detail["tables"]["peak_vs_speed"]
            if t["point"] == "PR" and t["direction"] == "z"]
    assert rows and rows[0]["speed_kmh"] == [60.0, 80.0]


def test_job_finishes_when_its_worker_container_restarts(stack, api, request):
    job_id = _submit(api, 20.0)
    job = _wait("the job to run", lambda: (j := api.get(f"/jobs/{job_id}").json())["status"]
                == "running" and j["progress"] >= 0.05 and j, 240.0, stack)
    host = job["worker"].rpartition("@")[2]
    (container,) = [c for c in stack.service_containers("worker")
                    if c["Config"]["Hostname"] == host]
    start = time.monotonic()
    stack.engine.docker("restart", "-t", "10", container["Id"])
    job = _final(api, job_id, stack, timeout=360.0)
    assert job["status"] == "succeeded", (job, stack.logs())
    record(request.config, "worker container restarted mid-job: the job succeeded "
           f"{time.monotonic() - start:.0f} s later, attempt {job['attempts']}")
    assert api.get(f"/jobs/{job_id}/summary").status_code == 200
    stack.wait_healthy(3 + WORKERS, timeout=120.0)


def test_down_removes_containers_and_volumes(stack, engine):
    stack.down()
    assert stack.containers() == []
    left = [v for v in engine.docker("volume", "ls", "-q").stdout.split()
            if v.startswith(f"{PROJECT}_")]
    assert not left, left
