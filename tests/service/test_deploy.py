"""Deployment files: docker-compose.yml (parsed with PyYAML: no Docker engine or compose
plugin is needed), docker/compose.secrets.yml, the Dockerfile and its context, and
tools/ensure_services.sh. A Compose CLI (``docker compose config``, or Debian's
``docker-compose``) validates the compose files too. The deployment itself is run by
tests/deploy.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys

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
    assert api["image"] == worker["image"] and api["build"] == worker["build"]
    assert api["build"]["context"] == "." and "BASE_IMAGE" in api["build"]["args"]
    # each image chosen by a variable: official images by default, local builds by
    # tools/docker_images.py (FLEXRIDE_IMAGE, FLEXRIDE_REDIS_IMAGE, FLEXRIDE_POSTGRES_IMAGE)
    assert _interpolate(api["image"]) == "flexride:latest"
    assert _interpolate(services["redis"]["image"]).startswith("redis:")
    assert _interpolate(services["postgres"]["image"]).startswith("postgres:")
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
    # only the API is published: Redis and PostgreSQL of the host keep their ports
    assert [name for name, svc in services.items() if "ports" in svc] == ["api"]
    for name, svc in services.items():
        assert svc["healthcheck"]["test"] and not svc["healthcheck"].get("disable"), name
    assert api["healthcheck"]["test"] == ["CMD", "flexride-healthcheck", "api"]
    assert worker["healthcheck"]["test"] == ["CMD", "flexride-healthcheck", "worker"]


def test_secrets_come_from_the_environment_or_files(compose):
    """No secret has a value in the compose files but the quick-start password default;
    docker/compose.secrets.yml reads both from files mounted under /run/secrets."""
    env = compose["services"]["api"]["environment"]
    assert env["FLEXRIDE_API_TOKEN"] == "${FLEXRIDE_API_TOKEN:-}"
    assert "${POSTGRES_PASSWORD:-flexride}" in env["FLEXRIDE_DATABASE_URL"]
    override = yaml.safe_load((REPO / "docker" / "compose.secrets.yml").read_text())
    services = override["services"]
    assert services["api"]["environment"]["FLEXRIDE_API_TOKEN_FILE"] == "/run/secrets/api_token"
    assert services["postgres"]["environment"]["POSTGRES_PASSWORD"] == ""
    for name in ("api", "worker"):
        assert (services[name]["environment"]["FLEXRIDE_DATABASE_PASSWORD_FILE"]
                == "/run/secrets/postgres_password")
    assert set(override["secrets"]) == {"api_token", "postgres_password"}


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


def test_docker_compose_config_validates_without_an_engine(tmp_path):
    r = subprocess.run([*_compose_command(), "-f", str(REPO / "docker-compose.yml"),
                        "--project-directory", str(REPO), "config", "-q"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    for name in ("api_token", "postgres_password"):
        (tmp_path / name).write_text("x\n")
    r = subprocess.run([*_compose_command(), "-f", str(REPO / "docker-compose.yml"),
                        "-f", str(REPO / "docker" / "compose.secrets.yml"),
                        "--project-directory", str(REPO), "config", "-q"],
                       capture_output=True, text=True,
                       env={**os.environ, "FLEXRIDE_SECRETS_DIR": str(tmp_path)})
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
    # built on a Debian base chosen by BASE_IMAGE (debian:bookworm-slim, or the local
    # debootstrap base of tools/docker_images.py); the build stage's arguments stay there
    assert re.search(r"^ARG BASE_IMAGE=debian:bookworm-slim$", text, re.M)
    final = text[text.rindex("\nFROM "):]
    assert "ARG " not in final and "EXTRA_CA_CERTS" not in final
    assert 'ENTRYPOINT ["tini", "--", "flexride-entrypoint"]' in final


def test_dockerignore_admits_what_the_build_tool_hashes():
    """The build context (.dockerignore's allowlist) is what tools/docker_images.py hashes
    to find an image built from the same inputs."""
    sys.path.insert(0, str(REPO / "tools"))
    import docker_images

    allowed = [line[1:] for line in (REPO / ".dockerignore").read_text().splitlines()
               if line.startswith("!")]
    assert sorted(allowed) == sorted(docker_images.FLEXRIDE_INPUTS)


def test_ensure_services_script():
    script = REPO / "tools" / "ensure_services.sh"
    assert subprocess.run(["bash", "-n", str(script)]).returncode == 0
    r = subprocess.run(["bash", str(script)], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert "Redis OK" in r.stderr and "PostgreSQL OK" in r.stderr
