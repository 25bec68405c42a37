"""A Docker engine for the deployment test: the one named by ``FLEXRIDE_DOCKER_HOST``, or a
``dockerd`` of its own, started as root with its own data root, exec root, socket and no default
bridge, so that a system daemon (``/var/run/docker.sock``, ``/var/lib/docker``, ``docker0``)
is left alone.

Its data root (``FLEXRIDE_DOCKER_ROOT``, default ``/var/lib/flexride-docker``) outlives the
test session: the debootstrap base and the images built from it are found there by the next
run (tools/docker_images.py rebuilds only what changed). Test sessions running at the same
time share the daemon: each holds a shared lock on ``users.lock`` while it uses it, and the
last one to finish stops it.
"""

from __future__ import annotations

import fcntl
import os
import re
import shutil
import signal
import subprocess
import time
from dataclasses import dataclass, field
from pathlib import Path

DATA_ROOT = Path(os.environ.get("FLEXRIDE_DOCKER_ROOT", "/var/lib/flexride-docker"))
RUN_DIR = Path("/run/flexride-docker")
SOCKET = RUN_DIR / "docker.sock"
PIDFILE = RUN_DIR / "dockerd.pid"
START_TIMEOUT_S = 90.0


class EngineUnavailable(RuntimeError):
    """No Docker engine can be reached or started; the message says why in one line."""


@dataclass
class Engine:
    """A reachable Docker engine: its ``DOCKER_HOST``, and for the test's own daemon the
    shared lock that marks this session as one of its users."""

    host: str
    own: bool = False
    users_lock: int | None = None
    env: dict[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.env = {**os.environ, "DOCKER_HOST": self.host}

    def docker(self, *args: str, check: bool = True, timeout: float = 600.0,
               ) -> subprocess.CompletedProcess[str]:
        """Run ``docker ARGS`` against this engine."""
        r = subprocess.run(["docker", *args], capture_output=True, text=True, env=self.env,
                           timeout=timeout)
        if check and r.returncode != 0:
            raise AssertionError(f"docker {' '.join(args)}: {r.stderr.strip()[-2000:]}")
        return r

    def answers(self) -> bool:
        """Whether the engine answers ``docker version``."""
        try:
            return self.docker("version", "--format", "{{.Server.Version}}", check=False,
                               timeout=20).returncode == 0
        except subprocess.TimeoutExpired:
            return False

    def release(self) -> None:
        """End this session's use; the last user of the test's own daemon stops it (its
        images stay in the data root). Other engines are left alone."""
        if not self.own or self.users_lock is None:
            return
        with _locked("start.lock"):
            os.close(self.users_lock)
            self.users_lock = None
            fd = os.open(RUN_DIR / "users.lock", os.O_RDWR | os.O_CREAT)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:  # another session still uses the daemon
                return
            finally:
                os.close(fd)
            _stop_dockerd()


class _locked:
    """An exclusive lock on ``RUN_DIR / name`` for the ``with`` block."""

    def __init__(self, name: str):
        RUN_DIR.mkdir(parents=True, exist_ok=True)
        self.fd = os.open(RUN_DIR / name, os.O_RDWR | os.O_CREAT)

    def __enter__(self) -> None:
        fcntl.flock(self.fd, fcntl.LOCK_EX)

    def __exit__(self, *exc: object) -> None:
        os.close(self.fd)


def _shared_use() -> int:
    """A shared lock on ``users.lock``, held while this session uses the daemon."""
    fd = os.open(RUN_DIR / "users.lock", os.O_RDWR | os.O_CREAT)
    fcntl.flock(fd, fcntl.LOCK_SH)
    return fd


def _stop_dockerd() -> None:
    """SIGTERM to the test's daemon (from its pid file); wait until it is gone."""
    try:
        pid = int(PIDFILE.read_text().strip())
        os.kill(pid, signal.SIGTERM)
    except (OSError, ValueError):
        return
    deadline = time.monotonic() + 60.0
    while not _gone(pid) and time.monotonic() < deadline:
        time.sleep(0.2)
    if not _gone(pid):
        os.kill(pid, signal.SIGKILL)


def _gone(pid: int) -> bool:
    """Whether process ``pid`` has ended (reaped here when this session started it)."""
    try:
        os.waitpid(pid, os.WNOHANG)
    except ChildProcessError:  # not a child of this process
        pass
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (OSError, IndexError):
        return True
    return state in ("Z", "X")


def _why_not(log: Path) -> str:
    """The daemon's last error line (or its last line) from ``log``."""
    lines = log.read_text(errors="replace").splitlines() if log.exists() else []
    errors = [ln for ln in lines if re.search(r"level=(fatal|error)|^failed|Error", ln)]
    last = (errors or lines or ["no output"])[-1]
    m = re.search(r'msg="([^"]*)"', last)
    return (m.group(1) if m else last).strip()[:300]


def _start_dockerd() -> None:
    dockerd = shutil.which("dockerd") or shutil.which("dockerd", path="/usr/sbin:/usr/bin")
    if dockerd is None:
        raise EngineUnavailable("dockerd is not installed (apt-get install docker.io)")
    if os.geteuid() != 0:
        raise EngineUnavailable("dockerd needs root to start (or set FLEXRIDE_DOCKER_HOST)")
    (RUN_DIR / "exec").mkdir(parents=True, exist_ok=True)
    DATA_ROOT.mkdir(parents=True, exist_ok=True)
    log = RUN_DIR / "dockerd.log"
    cmd = [dockerd, f"--data-root={DATA_ROOT}", f"--exec-root={RUN_DIR / 'exec'}",
           f"--pidfile={PIDFILE}", f"--host=unix://{SOCKET}", "--bridge=none",
           "--log-level=warn"]
    with log.open("wb") as out:
        proc = subprocess.Popen(cmd, stdout=out, stderr=subprocess.STDOUT,
                                stdin=subprocess.DEVNULL, start_new_session=True)
    probe = Engine(f"unix://{SOCKET}")
    deadline = time.monotonic() + START_TIMEOUT_S
    while not probe.answers():
        if proc.poll() is not None:
            raise EngineUnavailable(f"dockerd exited with code {proc.returncode}: "
                                    f"{_why_not(log)}")
        if time.monotonic() > deadline:
            _stop_dockerd()
            raise EngineUnavailable(f"dockerd did not answer within {START_TIMEOUT_S:g} s: "
                                    f"{_why_not(log)}")
        time.sleep(0.5)


def get_engine() -> Engine:
    """The engine of ``FLEXRIDE_DOCKER_HOST``, the test's daemon if it runs already, or a
    daemon started now.

    Raises
    ------
    EngineUnavailable
        With one line saying why no engine is available.
    """
    if shutil.which("docker") is None:
        raise EngineUnavailable("the docker client is not installed (apt-get install docker.io)")
    given = os.environ.get("FLEXRIDE_DOCKER_HOST")
    if given:
        engine = Engine(given)
        if not engine.answers():
            raise EngineUnavailable(f"no Docker engine answers at FLEXRIDE_DOCKER_HOST={given}")
        return engine
    if os.geteuid() != 0:
        raise EngineUnavailable("dockerd needs root to start (or set FLEXRIDE_DOCKER_HOST)")
    with _locked("start.lock"):  # one session starts it, the others join
        engine = Engine(f"unix://{SOCKET}", own=True)
        if not (SOCKET.exists() and engine.answers()):
            _start_dockerd()
        engine.users_lock = _shared_use()
    return engine
