"""Deployment files: docker-compose.yml (parsed with PyYAML: no Docker engine or compose
plugin is needed), the Dockerfile, and tools/ensure_services.sh.

When the compose CLI plugin is installed, ``docker compose config`` validates the file too.
"""

from __future__ import annotations

import re
import shutil
import subprocess

import pytest
import typer
import yaml

from flexride.cli.service import register
from flexride.settings import Settings
from service.svc_testkit import REPO

_VAR = re.compile(r"\$\{([A-Z_][A-Z0-9_]*)(?::?-([^}]*))?\}")


def _interpolate(value: str) -> str:
    return _VAR.sub(lambda m: m.group(2) or "", value)


@pytest.fixture(scope="module")
def compose():
    return yaml.safe_load((REPO / "docker-compose.yml").read_text())


def _parses(argv: list[str]) -> None:
    """The command line is accepted by the registered typer commands."""
    app = typer.Typer()
    register(app)
    cmd = typer.main.get_command(app)
    sub = cmd.get_command(None, argv[0])
    assert sub is not None, argv
    sub.make_context(argv[0], list(argv[1:]))


def test_compose_services_volumes_and_commands(compose):
    services = compose["services"]
    assert set(services) == {"api", "worker", "redis", "postgres"}
    api, worker = services["api"], services["worker"]
    assert api["image"] == worker["image"] and api["build"] == worker["build"] == "."
    for svc in (api, worker):
        assert "results:/data" in svc["volumes"]
        assert set(svc["depends_on"]) == {"redis", "postgres"}
        assert svc["environment"]["FLEXRIDE_DATA_DIR"] == "/data"
        assert svc["environment"]["FLEXRIDE_BROKER_URL"].startswith("redis://redis:6379")
        assert svc["environment"]["FLEXRIDE_DATABASE_URL"].startswith(
            "postgresql+psycopg://")
    # `--scale worker=N`: nothing that would clash between replicas
    assert "container_name" not in worker and "ports" not in worker
    assert set(compose["volumes"]) >= {"results", "pgdata"}
    # every FLEXRIDE_* variable is a setting
    fields = {f"FLEXRIDE_{name.upper()}" for name in Settings.model_fields}
    assert set(api["environment"]) <= fields
    # the commands are the ones the tests run (tests/service/test_cli.py: serve --host
    # --port; tests/jobs/test_celery_e2e.py: worker --concurrency)
    api_cmd = [_interpolate(a) for a in api["command"]]
    worker_cmd = [_interpolate(a) for a in worker["command"]]
    assert api_cmd[:2] == ["flexride", "serve"] and {"--host", "--port"} <= set(api_cmd)
    assert worker_cmd[:2] == ["flexride", "worker"] and "--concurrency" in worker_cmd
    _parses(api_cmd[1:])
    _parses(worker_cmd[1:])
    assert api["ports"][0].endswith(":8000") and "127.0.0.1" in _interpolate(api["ports"][0])
    for name in ("redis", "postgres"):
        assert "healthcheck" in services[name]


def _compose_command() -> list[str]:
    """``docker compose`` (v2 plugin) if present, else Debian's ``docker-compose``; neither
    needs a Docker engine for ``config``. .ci/run installs ``docker-compose`` when both are
    missing, so this check fails rather than skips."""
    docker = shutil.which("docker")
    if docker and subprocess.run([docker, "compose", "version"],
                                 capture_output=True).returncode == 0:
        return [docker, "compose"]
    legacy = shutil.which("docker-compose")
    assert legacy, "neither `docker compose` nor `docker-compose` is installed"
    return [legacy]


def test_docker_compose_config_validates_without_an_engine():
    r = subprocess.run([*_compose_command(), "-f", str(REPO / "docker-compose.yml"),
                        "--project-directory", str(REPO), "config", "-q"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_dockerfile_builds_the_service_image():
    text = (REPO / "Dockerfile").read_text()
    assert re.search(r'^CMD \["flexride", "serve", "--host", "0.0.0.0", "--port", "8000"\]',
                     text, re.M)
    # the Celery app is part of the installed package: nothing beside it on the path
    assert "worker ./worker" not in text and "PYTHONPATH" not in text
    assert "COPY frontend ./frontend" in text and "FLEXRIDE_FRONTEND_DIR=/app/frontend" in text
    assert "FLEXRIDE_DATA_DIR=/data" in text and "warm_numba" in text
    assert re.search(r"^USER flexride", text, re.M)


def test_ensure_services_script():
    script = REPO / "tools" / "ensure_services.sh"
    assert subprocess.run(["bash", "-n", str(script)]).returncode == 0
    r = subprocess.run(["bash", str(script)], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert "Redis OK" in r.stderr and "PostgreSQL OK" in r.stderr
