"""Helpers shared by the service tests (API, store, jobs, studies).

PostgreSQL (127.0.0.1:5432, database ``test``) and Redis (127.0.0.1:6379) must be running:
tests that need them fail, they are never skipped (``tools/ensure_services.sh`` starts them).
"""

from __future__ import annotations

import contextlib
import os
import socket
import subprocess
import sys
import time
import uuid
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np

from flexride.jobs.base import JobRunner
from flexride.results import Results
from flexride.settings import Settings
from flexride.store import Job, JobStore, ResultFiles, now

REPO = Path(__file__).resolve().parents[2]
PG_BASE = os.environ.get("FLEXRIDE_TEST_PG_URL",
                         "postgresql+psycopg://postgres@127.0.0.1:5432/test")
REDIS_BASE = os.environ.get("FLEXRIDE_TEST_REDIS_URL", "redis://127.0.0.1:6379")
SHORT = {"duration_s": 1.5, "distance_m": None}
"""Overrides of a short real run (1.5 s simulated)."""
TEST_TOKEN = "Qm7vR2xK9pLw4ZtB-e3Nc"
"""An API token strong enough for the service (tests only)."""


def make_settings(data_dir: Path, **kw: Any) -> Settings:
    """Settings for a test: data and caches under ``data_dir``, no runner unless given,
    ``testserver`` (the host of fastapi's TestClient) among the allowed hosts, and no
    ``gc.freeze`` at start-up (a test process makes and drops many apps)."""
    kw.setdefault("runner", "none")
    kw.setdefault("allowed_hosts", "testserver")
    kw.setdefault("cache_dir", data_dir / "cache")
    kw.setdefault("frontend_dir", None)
    kw.setdefault("gc_freeze", False)  # test processes make and drop many apps
    return Settings(_env_file=None, data_dir=data_dir, **kw)


@contextlib.contextmanager
def pg_schema() -> Iterator[str]:
    """A fresh PostgreSQL schema in database ``test``; yields the URL that uses it."""
    import psycopg

    name = f"flexride_t_{uuid.uuid4().hex[:10]}"
    plain = PG_BASE.replace("postgresql+psycopg://", "postgresql://")
    with psycopg.connect(plain, autocommit=True, connect_timeout=5) as conn:
        conn.execute(f'CREATE SCHEMA "{name}"')
    try:
        yield f"{PG_BASE}?options=-csearch_path%3D{name}"
    finally:
        forget_engines(name)
        with psycopg.connect(plain, autocommit=True, connect_timeout=5) as conn:
            conn.execute(f'DROP SCHEMA IF EXISTS "{name}" CASCADE')


def pg_admin() -> Any:
    """An autocommit connection to database ``test`` as the administrator of the tests."""
    import psycopg

    plain = PG_BASE.replace("postgresql+psycopg://", "postgresql://")
    return psycopg.connect(plain, autocommit=True, connect_timeout=5)


def schema_of(url: str) -> str:
    """The schema of a :func:`pg_schema` URL."""
    return url.rsplit("search_path%3D", 1)[1]


def forget_engines(fragment: str) -> None:
    """Dispose of this process's store engines whose URL contains ``fragment`` (their
    connections are closed)."""
    from flexride.store.db import _ENGINES

    for key in [k for k in _ENGINES if fragment in k[1]]:
        _ENGINES.pop(key).dispose()


@contextlib.contextmanager
def pg_role(url: str, *privileges: str) -> Iterator[str]:
    """A login role of its own with ``privileges`` (e.g. ``SELECT``) on every table of the
    schema of ``url`` (a :func:`pg_schema` URL, whose tables exist); yields ``url`` as that
    role. The role is dropped at the end."""
    from sqlalchemy.engine import make_url

    role, schema = f"flexride_r_{uuid.uuid4().hex[:10]}", schema_of(url)
    with pg_admin() as conn:
        conn.execute(f'CREATE ROLE "{role}" LOGIN')
        conn.execute(f'GRANT USAGE ON SCHEMA "{schema}" TO "{role}"')
        if privileges:
            conn.execute(f'GRANT {", ".join(privileges)} ON ALL TABLES IN SCHEMA "{schema}" '
                         f'TO "{role}"')
    try:
        yield make_url(url).set(username=role).render_as_string(hide_password=False)
    finally:
        forget_engines(role)
        with pg_admin() as conn:
            conn.execute(f'DROP OWNED BY "{role}"')
            conn.execute(f'DROP ROLE "{role}"')


def redis_url(db: int = 9) -> str:
    """A Redis URL on the local server (a database number of its own)."""
    return f"{REDIS_BASE}/{db}"


def synthetic_results(duration: float = 10.0, fs: float = 1000.0, speed_kmh: float = 80.0,
                      seed: int = 0) -> Results:
    """A results object with known content: sines at 1.5 Hz and 7 Hz at PR/PC/PRB/PFB,
    PR delayed by 0.5 s against PRB, a 1 kHz sample rate."""
    rng = np.random.default_rng(seed)
    t = np.arange(round(duration * fs)) / fs
    channels, units = {}, {}

    def sig(delay: float, amp: float) -> np.ndarray:
        tt = t - delay
        return (amp * np.sin(2 * np.pi * 1.5 * tt) + 0.5 * amp * np.sin(2 * np.pi * 7.0 * tt)
                + 0.01 * rng.standard_normal(t.size))

    for point, delay in (("PR", 0.0), ("PFB", 0.1), ("PC", 0.25), ("PRB", 0.5)):
        for direction, amp in (("z", 0.2), ("y", 0.1)):
            name = f"carbody.{point}.acc.{direction}"
            channels[name] = sig(delay, amp)
            units[name] = "m/s^2"
    channels["frame1.centre.acc.z"] = sig(0.0, 1.0)
    units["frame1.centre.acc.z"] = "m/s^2"
    return Results(time=t, distance=t * speed_kmh / 3.6, channels=channels, units=units,
                   scenario={"name": "synthetic", "speed_kmh": speed_kmh},
                   meta={"output_rate": fs, "speed_kmh": speed_kmh,
                         "speed_mps": speed_kmh / 3.6, "wall_time_solve_s": 0.1})


def insert_finished_job(store: JobStore, files: ResultFiles, results: Results | None = None,
                        *, name: str = "synthetic", scenario_hash: str | None = None,
                        summary: dict[str, Any] | None = None, **fields: Any) -> str:
    """Insert a succeeded job whose result file is ``results`` (synthetic by default)."""
    from flexride.analysis import analyze
    from flexride.study.submit import new_id

    results = results or synthetic_results()
    job_id = new_id()
    file_name = files.name_for(job_id)
    results.write_hdf5(files.path(file_name))
    t = now()
    values: dict[str, Any] = dict(
        id=job_id, name=name, status="succeeded", progress=1.0, message="done",
        created_at=t, updated_at=t, started_at=t, finished_at=t, heartbeat_at=t,
        runner="none", attempts=1, max_attempts=2, cancel_requested=False,
        scenario_hash=scenario_hash or uuid.uuid4().hex, speed_kmh=results.meta["speed_kmh"],
        duration_s=float(results.time[-1]), scenario=results.scenario, axes={},
        result_file=file_name, run_meta=dict(results.meta),
        summary=summary if summary is not None else analyze(results).to_dict())
    values.update(fields)
    store.add([Job(**values)])
    return job_id


class Tmpfs:
    """A small tmpfs mounted on a directory (the tests run as root, as CI does);
    ``read_only()`` / ``writable()`` remount it, ``fill()`` fills it."""

    def __init__(self, path: Path, size_kb: int, options: str = ""):
        self.path = path
        path.mkdir(parents=True, exist_ok=True)
        self._mount("-t", "tmpfs", "-o", ",".join(filter(None, [f"size={size_kb}k", options])),
                    "tmpfs", str(path))

    @staticmethod
    def _mount(*args: str) -> None:
        import pytest

        r = subprocess.run(["mount", *args], capture_output=True, text=True)
        if r.returncode != 0:
            pytest.fail(f"storage-fault tests mount a tmpfs and need root: {r.stderr.strip()}")

    def read_only(self) -> None:
        self._mount("-o", "remount,ro", str(self.path))

    def writable(self) -> None:
        self._mount("-o", "remount,rw", str(self.path))

    def fill(self) -> None:
        """Fill the file system up to the last byte."""
        fd = os.open(self.path / "filler", os.O_WRONLY | os.O_CREAT)
        try:
            while os.write(fd, b"\0" * 4096):
                pass
        except OSError:
            pass
        finally:
            os.close(fd)

    def umount(self) -> None:
        subprocess.run(["umount", "-l", str(self.path)], check=False)


@contextlib.contextmanager
def tmpfs(path: Path, size_kb: int = 4096, options: str = "") -> Iterator[Tmpfs]:
    """A :class:`Tmpfs` on ``path`` for the duration of the block."""
    fs = Tmpfs(path, size_kb, options)
    try:
        yield fs
    finally:
        fs.umount()


def wait_for(predicate: Callable[[], Any], timeout: float, interval: float = 0.2,
             what: str = "condition") -> Any:
    """Poll ``predicate`` until it returns a truthy value; fail after ``timeout`` s."""
    deadline = time.monotonic() + timeout
    last = None
    while time.monotonic() < deadline:
        last = predicate()
        if last:
            return last
        time.sleep(interval)
    raise AssertionError(f"timed out after {timeout:g} s waiting for {what} (last: {last!r})")


def service_command() -> list[str]:
    """How to run ``flexride serve|worker``: the CLI when it has the commands, else
    ``python -m flexride.cli.service`` (same functions)."""
    try:
        from flexride.cli import app

        names = {c.name or (c.callback.__name__ if c.callback else "")
                 for c in app.registered_commands}
        if {"serve", "worker"} <= names:
            exe = Path(sys.executable).with_name("flexride")
            if exe.exists():
                return [str(exe)]
    except Exception:
        pass
    return [sys.executable, "-m", "flexride.cli.service"]


def free_port() -> int:
    """A free TCP port on 127.0.0.1."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def start_process(args: list[str], env: dict[str, str], log: Path) -> subprocess.Popen:
    """Start a service process in its own session (so the test can kill its whole group)."""
    fh = open(log, "ab")
    return subprocess.Popen(args, env=env, stdout=fh, stderr=subprocess.STDOUT, cwd=REPO,
                            start_new_session=True)


def stop_process(proc: subprocess.Popen, sig: int | None = None, timeout: float = 15.0) -> None:
    """Stop a process started by :func:`start_process` and everything in its group."""
    import signal

    if proc.poll() is None:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, sig or signal.SIGTERM)
        try:
            proc.wait(timeout)
        except subprocess.TimeoutExpired:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(proc.pid, signal.SIGKILL)
            proc.wait(5)
    with contextlib.suppress(ProcessLookupError):
        os.killpg(proc.pid, signal.SIGKILL)  # children left behind by a killed parent


def service_env(**values: str) -> dict[str, str]:
    """The environment of a service process: this one without FLEXRIDE_* plus ``values``."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("FLEXRIDE_")}
    env.update({k: str(v) for k, v in values.items()})
    env["PYTHONPATH"] = os.pathsep.join([str(REPO), env.get("PYTHONPATH", "")]).rstrip(
        os.pathsep)
    return env


def services(client: Any) -> Any:
    """The service objects of a TestClient's app."""
    return client.app.state.services


def fake_fe_export(spec: Any, progress: Callable[[float, str], None] | None = None
                   ) -> dict[str, Any]:
    """Stand-in for :func:`flexride.fem.export.build_export` (the ``fe_build`` of a
    :class:`~flexride.study.run_job.JobContext`): a one-quad export that follows the real
    export's layout (and its ``model`` block), at once."""
    if progress is not None:
        progress(0.5, "building the FE model of the stand-in")
    model = {**spec.parameters(), "key": spec.key, "n_nodes": 4, "n_elastic_modes": 1,
             "frequencies_hz": [5.0], "from_cache": False, "build_seconds": 0.0}
    return {"units": {"length": "m", "frequency": "Hz"},
            "nodes": [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]],
            "quads": [[0, 1, 3, 2]], "beams": [], "named_nodes": {},
            "modes": [{"index": 1, "frequency_hz": 5.0, "classification": "", "scale_m": 0.01,
                       "displacements": [[0.0, 0.0, 1.0]] * 4}][:spec.max_modes],
            "model": model}


def write_fake_export(path: Path, spec: Any) -> None:
    """Put the stand-in export of ``spec`` at ``path`` (as if a job had built it)."""
    import json

    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(fake_fe_export(spec)), encoding="utf-8")


def fe_job_context(svc: Any, build: Callable[..., dict[str, Any]] = fake_fe_export,
                   worker: str | None = None) -> Any:
    """A :class:`~flexride.study.run_job.JobContext` of this process for an app's services
    whose FE export jobs run ``build`` (a stand-in of ``build_export``)."""
    from flexride.jobs.presence import worker_name
    from flexride.study.run_job import JobContext

    return JobContext(store=svc.store, files=svc.files, settings=svc.settings,
                      worker=worker or worker_name("inline"), fe_build=build)


def run_fe_jobs(client: Any, build: Callable[..., dict[str, Any]] = fake_fe_export
                ) -> dict[str, str]:
    """Run the queued FE export jobs of an app (runner ``none``) in this process, through
    :func:`flexride.study.run_job.claim_and_run` with ``build``; their final states by id."""
    from flexride.study.run_job import claim_and_run

    svc = getattr(client, "app", client).state.services
    ctx = fe_job_context(svc, build)
    queued, _ = svc.store.list_jobs(status="queued", kind="fe_export", limit=500)
    return {row.id: claim_and_run(row.id, ctx) for row in reversed(queued)}


class InlineFERunner(JobRunner):
    """A runner for API tests: FE export jobs run in a thread of this process through
    :func:`flexride.study.run_job.claim_and_run` (the workers' code path) with a stand-in
    build; simulation jobs are recorded, not run (as with runner ``none``)."""

    kind = "none"

    def __init__(self, svc: Any, build: Callable[..., dict[str, Any]] = fake_fe_export):
        self.svc = svc
        self.ctx = fe_job_context(svc, build)
        self.pool: ThreadPoolExecutor | None = None
        self.ran: list[str] = []

    def start(self) -> None:
        """Nothing to start (the thread starts with the first job)."""

    def stop(self) -> None:
        """Wait for the job in progress (an app's lifespan may start the runner again)."""
        pool, self.pool = self.pool, None
        if pool is not None:
            pool.shutdown(wait=True, cancel_futures=True)

    def submit(self, job_ids: Sequence[str]) -> None:
        """Run the FE export jobs among ``job_ids`` (one at a time, in a thread)."""
        from flexride.study.run_job import claim_and_run

        for job_id in job_ids:
            job = self.svc.store.get_job(job_id)
            if job is not None and job.kind == "fe_export":
                if self.pool is None:
                    self.pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="inline-fe")
                self.ran.append(job_id)
                self.pool.submit(claim_and_run, job_id, self.ctx)

    def status(self) -> dict[str, Any]:
        """Always healthy."""
        return {"kind": self.kind, "ok": True, "detail": "FE jobs run in the test process"}


def use_fe_builds(client: Any, build: Callable[..., dict[str, Any]] = fake_fe_export,
                  **kw: Any) -> Any:
    """Let an app (or a TestClient's app) with runner ``none`` run its FE export jobs in this
    process (:class:`InlineFERunner`) with ``build``; ``kw`` sets attributes of its
    :class:`flexride.api.services.fe.FEExports` (``wait_s`` defaults to 0). Returns the
    runner."""
    svc = getattr(client, "app", client).state.services
    runner = InlineFERunner(svc, build)
    svc.runner = svc.submitter.runner = runner
    svc.reaper.runner = runner
    kw.setdefault("wait_s", 0.0)
    for name, value in kw.items():
        if not hasattr(svc.fe, name):
            raise AttributeError(f"FEExports has no {name!r}")
        setattr(svc.fe, name, value)
    return runner


def fe_jobs(client: Any) -> list[Any]:
    """The FE export jobs of an app, newest first."""
    svc = getattr(client, "app", client).state.services
    return svc.store.list_jobs(kind="fe_export", limit=500)[0]
