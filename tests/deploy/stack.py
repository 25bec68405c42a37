"""A docker-compose.yml deployment run by the deployment test: its own project name, the API
published on a free loopback port, secrets from files in a temporary directory."""

from __future__ import annotations

import json
import os
import secrets
import shutil
import socket
import subprocess
import time
from pathlib import Path

from deploy.engine import Engine

REPO = Path(__file__).resolve().parents[2]
#: Project name: one per test session (sessions may share the engine)
PROJECT_PREFIX = "flexride-deploytest"
PROJECT = f"{PROJECT_PREFIX}-{os.getpid()}"
FILES = (REPO / "docker-compose.yml", REPO / "docker" / "compose.secrets.yml")


def compose_command(engine: Engine) -> list[str]:
    """``docker compose`` (v2 plugin) if the client has it, else Debian's ``docker-compose``."""
    if subprocess.run(["docker", "compose", "version"], capture_output=True,
                      env=engine.env).returncode == 0:
        return ["docker", "compose"]
    legacy = shutil.which("docker-compose")
    assert legacy, "neither `docker compose` nor `docker-compose` is installed"
    return [legacy]


def free_loopback_port() -> int:
    """A TCP port of 127.0.0.1 that nothing listens on now."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


class Stack:
    """The compose project: ``up``, health, containers, logs, ``down -v``.

    Parameters
    ----------
    engine : Engine
        Where the containers run.
    images : dict
        Compose variables that select the images (``FLEXRIDE_IMAGE``, …).
    tmp : Path
        A directory for the secret files and the compose variables.
    """

    def __init__(self, engine: Engine, images: dict[str, str], tmp: Path):
        self.engine, self.port = engine, free_loopback_port()
        self.token = secrets.token_urlsafe(32)
        self.db_password = secrets.token_urlsafe(24)
        secret_dir = tmp / "secrets"
        secret_dir.mkdir(mode=0o755)
        for name, value in (("api_token", self.token), ("postgres_password", self.db_password)):
            (secret_dir / name).write_text(value + "\n")
            (secret_dir / name).chmod(0o644)  # read by the containers' own users
        variables = {**images, "FLEXRIDE_PUBLISH": f"127.0.0.1:{self.port}",
                     "FLEXRIDE_SECRETS_DIR": str(secret_dir), "FLEXRIDE_WORKERS": "1",
                     "FLEXRIDE_HEARTBEAT_TIMEOUT_S": "20", "FLEXRIDE_LOG_LEVEL": "info"}
        self.env_file = tmp / "compose.env"
        self.env_file.write_text("".join(f"{k}={v}\n" for k, v in variables.items()))
        self.cmd = [*compose_command(engine), "--env-file", str(self.env_file),
                    *(a for f in FILES for a in ("-f", str(f)))]

    @property
    def url(self) -> str:
        """Base URL of the API as the host reaches it."""
        return f"http://127.0.0.1:{self.port}/api/v1"

    def compose(self, *args: str, timeout: float = 600.0, project: str = PROJECT) -> str:
        """Run a compose command of ``project`` (this session's); return its output, raise
        on failure."""
        r = subprocess.run([*self.cmd, "-p", project, *args], capture_output=True, text=True,
                           cwd=REPO, env=self.engine.env, timeout=timeout)
        if r.returncode != 0:
            raise AssertionError(f"compose {' '.join(args)}: {r.stderr.strip()[-3000:]}")
        return r.stdout + r.stderr

    def up(self, workers: int) -> None:
        """``up -d --scale worker=N`` with the images built beforehand."""
        self.compose("up", "-d", "--no-build", "--scale", f"worker={workers}")

    def containers(self) -> list[dict]:
        """``docker inspect`` of every container of the project."""
        ids = self.engine.docker("ps", "-aq", "--filter",
                                 f"label=com.docker.compose.project={PROJECT}").stdout.split()
        return json.loads(self.engine.docker("inspect", *ids).stdout) if ids else []

    def health(self) -> dict[str, str]:
        """Container name → health status (``healthy``, ``starting``, …, or its state)."""
        return {c["Name"].lstrip("/"): (c["State"].get("Health") or {}).get(
                    "Status", c["State"]["Status"]) for c in self.containers()}

    def wait_healthy(self, count: int, timeout: float = 300.0) -> None:
        """Wait until ``count`` containers are all healthy; fail with their states."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            states = self.health()
            if len(states) == count and set(states.values()) == {"healthy"}:
                return
            time.sleep(2.0)
        raise AssertionError(f"not healthy after {timeout:g} s: {self.health()}\n{self.logs()}")

    def service_containers(self, service: str) -> list[dict]:
        """The containers of one compose service."""
        return [c for c in self.containers()
                if c["Config"]["Labels"].get("com.docker.compose.service") == service]

    def logs(self, tail: int = 60) -> str:
        """The last lines of every container's log."""
        try:
            return self.compose("logs", "--no-color", "--tail", str(tail), timeout=60)
        except (AssertionError, subprocess.TimeoutExpired) as exc:
            return f"(no logs: {exc})"

    def down(self, project: str = PROJECT) -> None:
        """``down -v``: containers, network and volumes of the project removed."""
        self.compose("down", "-v", "--remove-orphans", "-t", "20", project=project)

    def remove_stale(self) -> None:
        """``down -v`` the projects of earlier test sessions whose process is gone."""
        out = self.engine.docker("ps", "-a", "--format",
                                 '{{.Label "com.docker.compose.project"}}').stdout
        for project in set(out.split()):
            owner = project.removeprefix(f"{PROJECT_PREFIX}-")
            if project.startswith(PROJECT_PREFIX) and project != PROJECT and not (
                    owner.isdigit() and Path(f"/proc/{owner}").exists()):
                self.down(project)
