"""Service performance (prints figures; not a timed test).

1. Requests under load, in three phases of ``--duration`` s each (default 20): ``--clients``
   (default 50) concurrent connections from two client processes (asyncio) against a real
   ``flexride serve`` with an API token on 127.0.0.1 and an idle runner, sending (a)
   anonymous health (``GET /health`` without the token), (b) reads with the token, cycling
   through the job list (``GET /jobs``), the job detail (``GET /jobs/{id}``), the summary
   and a decimated series (two channels, 2000 points, min/max) of a finished 20 s job
   (paper-random-straight-80, 20,000 samples per channel), (c) job submission with the token
   (``POST /jobs`` of that scenario: validated, admitted, checked, recorded, its results
   reused). A latency is request sent to last byte received; every status is checked and
   every tenth answer's content. Prints per phase the throughput, p50/p95/p99, the slowest
   request and the errors (wrong status or a malformed answer) per request and overall, the
   CPU the client processes used (so that the figures are the server's, not the client's)
   and the API process's CPU per request.
2. Throughput on a study of 8 short jobs (paper-random-straight at 8 speeds, 5 s simulated):
   the embedded runner (2 worker processes) and two Celery workers (1 process each, Redis
   broker), relative to running the same 8 jobs one after another in one process
   (simulate + write HDF5 + analyze, kernels already compiled).

The service runs with a temporary data directory on a free port; needs Redis on
127.0.0.1:6379 for the Celery part (``tools/ensure_services.sh``); runs everything on
loopback and stops every process it started.

Usage: ``python benchmarks/bench_service.py [--quick] [--clients N] [--duration S]
[--reads-only] [--skip-celery]``
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import functools
import gzip
import json
import multiprocessing as mp
import os
import secrets
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

import httpx

ROOT = Path(__file__).resolve().parents[1]
API = "/api/v1"
SERVICE = [sys.executable, "-m", "flexride.cli.service"]
STUDY_SPEEDS = [50, 55, 60, 65, 70, 75, 80, 85]
TOKEN = os.environ.setdefault("FLEXRIDE_BENCH_TOKEN", secrets.token_urlsafe(32))
"""The API token of the services this benchmark starts (in the environment, so that the
client processes, started with ``spawn``, send the same)."""
AUTH = {"Authorization": f"Bearer {TOKEN}"}


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _env(**values: str) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith("FLEXRIDE_")}
    env.update(values)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), env.get("PYTHONPATH", "")]).rstrip(
        os.pathsep)
    return env


def _start(args: list[str], env: dict[str, str], log: Path) -> subprocess.Popen:
    return subprocess.Popen(args, env=env, stdout=log.open("ab"), stderr=subprocess.STDOUT,
                            cwd=ROOT, start_new_session=True)


def _stop(proc: subprocess.Popen) -> None:
    """SIGTERM to the process (it stops its own children), then SIGKILL to whatever of its
    process group is left. (SIGTERM to the whole group at once can leave ``flexride serve``
    waiting for its killed workers.)"""
    with contextlib.suppress(ProcessLookupError):
        proc.send_signal(signal.SIGTERM)
    try:
        proc.wait(20)
    except subprocess.TimeoutExpired:
        pass
    with contextlib.suppress(ProcessLookupError):
        os.killpg(proc.pid, signal.SIGKILL)


def _wait(predicate, timeout: float, what: str, interval: float = 0.2):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        with contextlib.suppress(httpx.HTTPError):
            value = predicate()
            if value:
                return value
        time.sleep(interval)
    raise SystemExit(f"timed out waiting for {what}")


def _serve(tmp: Path, name: str, **settings: str) -> tuple[subprocess.Popen, str]:
    port = _free_port()
    env = _env(FLEXRIDE_DATA_DIR=str(tmp / name), FLEXRIDE_LOG_LEVEL="warning", **settings)
    proc = _start([*SERVICE, "serve", "--host", "127.0.0.1", "--port", str(port)], env,
                  tmp / f"{name}.log")
    url = f"http://127.0.0.1:{port}"
    _wait(lambda: httpx.get(f"{url}{API}/health", timeout=2).status_code == 200, 90.0,
          f"the {name} API")
    return proc, url


def _workers_alive(url: str, n: int) -> bool:
    health = httpx.get(f"{url}{API}/health", headers=AUTH, timeout=5).json()
    return sum(w["alive"] for w in health["workers"]) >= n


def _wait_job(url: str, job_id: str, timeout: float = 600.0) -> dict:
    def done():
        j = httpx.get(f"{url}{API}/jobs/{job_id}", headers=AUTH, timeout=10).json()
        return j if j["status"] not in ("queued", "running") else None

    job = _wait(done, timeout, f"job {job_id}")
    if job["status"] != "succeeded":
        raise SystemExit(f"job {job_id} {job['status']}: {job['error']}")
    return job


# -- 1. reads under load --------------------------------------------------------------------

SERIES_CHANNELS = ("carbody.PR.acc.z", "carbody.PC.acc.y")
CLIENT_PROCESSES = 2
"""The clients are spread over this many processes (asyncio in each), so that the client's own
event loop does not queue answers the service has already sent."""
SERIES_POINTS = 2000


JOB_BODY = {"preset": "paper-random-straight-80",
            "overrides": {"duration_s": 20.0, "distance_m": None}}
"""The finished job's scenario (submitted again under load: its results are reused)."""


@dataclass(frozen=True)
class Target:
    """One request of the load: label, method, path (relative to the API), JSON body, whether
    it carries the token, the status it must answer."""

    label: str
    method: str
    path: str
    body: bytes = b""
    token: bool = True
    status: int = 200


def _targets(job_id: str) -> dict[str, list[Target]]:
    """The requests of each phase of the load, in the order each client cycles through
    them."""
    chans = "&".join(f"channels={c}" for c in SERIES_CHANNELS)
    submit = json.dumps({**JOB_BODY, "reuse": True}).encode()
    return {
        "anonymous health": [
            Target("GET /health (anonymous)", "GET", f"{API}/health", token=False)],
        "reads with the token": [
            Target("GET /jobs", "GET", f"{API}/jobs"),
            Target("GET /jobs/{id}", "GET", f"{API}/jobs/{job_id}"),
            Target("GET /jobs/{id}/summary", "GET", f"{API}/jobs/{job_id}/summary"),
            Target(f"GET /jobs/{{id}}/series ({SERIES_POINTS} pts)", "GET",
                   f"{API}/jobs/{job_id}/series?{chans}&max_points={SERIES_POINTS}"
                   "&method=minmax")],
        "job submission with the token": [
            Target("POST /jobs (results reused)", "POST", f"{API}/jobs", submit, status=201)],
    }


def _check(label: str, body: dict) -> bool:
    """Whether an answer has the expected shape (an error otherwise)."""
    if label.startswith("GET /health"):
        return body.get("view") == "public" and body.get("status") == "ok"
    if label == "GET /jobs":
        return bool(body.get("items"))
    if "series" in label:
        return all(0 < len(c["values"]) <= SERIES_POINTS for c in body["channels"])
    if "summary" in label:
        return bool(body.get("summary"))
    if label.startswith("POST"):
        return body.get("reused") is True and body.get("status") == "succeeded"
    return body.get("status") == "succeeded"


class _Conn:
    """A minimal keep-alive HTTP/1.1 client on asyncio streams (gzip accepted like a browser),
    so that the client process costs little CPU next to the service on a 2-core machine:
    httpx spends several ms of CPU per request, as much as the service."""

    def __init__(self, host: str, port: int):
        self.host, self.port = host, port
        self.reader: asyncio.StreamReader | None = None
        self.writer: asyncio.StreamWriter | None = None

    async def request(self, target: Target, timeout: float = 30.0) -> tuple[int, bytes, bool]:
        """Status, body as received and whether it is gzip-encoded, of ``target``;
        reconnects when needed, and drops the connection after a failure or a timeout (s)."""
        try:
            return await asyncio.wait_for(self._request(target), timeout)
        except BaseException:
            self.close()
            raise

    async def _request(self, t: Target) -> tuple[int, bytes, bool]:
        if self.writer is None:
            self.reader, self.writer = await asyncio.open_connection(self.host, self.port)
        assert self.reader is not None
        head = [f"{t.method} {t.path} HTTP/1.1", f"Host: {self.host}:{self.port}",
                "Accept-Encoding: gzip"]
        if t.token:
            head.append(f"Authorization: Bearer {TOKEN}")
        if t.body:
            head += ["Content-Type: application/json", f"Content-Length: {len(t.body)}"]
        self.writer.write("\r\n".join([*head, "", ""]).encode() + t.body)
        lines = (await self.reader.readuntil(b"\r\n\r\n")).decode("latin-1").split("\r\n")
        headers = dict(_header(line) for line in lines[1:] if line)
        if "content-length" in headers:
            body = await self.reader.readexactly(int(headers["content-length"]))
        else:
            body = await self._chunked()
        if headers.get("connection", "").lower() == "close":
            self.close()
        return (int(lines[0].split(" ", 2)[1]), body,
                headers.get("content-encoding") == "gzip")

    async def _chunked(self) -> bytes:
        """A body sent with ``Transfer-Encoding: chunked`` (no trailers)."""
        assert self.reader is not None
        parts = []
        while True:
            size = int((await self.reader.readline()).split(b";")[0], 16)
            chunk = await self.reader.readexactly(size + 2)  # data and its CRLF
            if size == 0:
                return b"".join(parts)
            parts.append(chunk[:-2])

    def close(self) -> None:
        if self.writer is not None:
            self.writer.close()
        self.reader = self.writer = None


def _header(line: str) -> tuple[str, str]:
    key, _, value = line.partition(":")
    return key.strip().lower(), value.strip()


CHECK_EVERY = 10
"""Every answer's status is checked; its content (decompressed, parsed, shape checked) on every
``CHECK_EVERY``-th answer of each client, after the latency is taken: the time is the
service's (request sent to last byte received), not the client's JSON parsing."""


async def _client_loop(send, targets: list[Target], k: int, deadline: float,
                       out: list) -> None:
    """One client: requests back to back until ``deadline``, starting at target ``k``;
    ``send(target)`` returns (status, raw body, whether it is gzip)."""
    i = k
    while time.perf_counter() < deadline:
        target = targets[i % len(targets)]
        i += 1
        t0 = time.perf_counter()
        why = ""
        try:
            status, body, packed = await send(target)
            elapsed = time.perf_counter() - t0
            ok = status == target.status
            if not ok:
                why = f"{status} {body[:200]!r}"
            elif i % CHECK_EVERY == 0:
                ok = _check(target.label,
                            json.loads(gzip.decompress(body) if packed else body))
                why = "" if ok else "unexpected content"
        except Exception as exc:  # any failure counts as an error
            elapsed, ok, why = time.perf_counter() - t0, False, type(exc).__name__
        out.append((target.label, elapsed, ok, why))


async def _httpx_send(client: httpx.AsyncClient, t: Target) -> tuple[int, bytes, bool]:
    r = await client.request(t.method, t.path, content=t.body or None,
                             headers={**(AUTH if t.token else {}),
                                      **({"Content-Type": "application/json"} if t.body
                                         else {})})
    return r.status_code, r.content, False  # httpx has decompressed it


async def _run_load(base: str, job_id: str, phase: str, clients: int, duration: float,
                    kind: str) -> tuple[list, float]:
    targets = _targets(job_id)[phase]
    out: list = []
    limits = httpx.Limits(max_connections=clients, max_keepalive_connections=clients)
    conns = [_Conn("127.0.0.1", int(base.rsplit(":", 1)[1])) for _ in range(clients)]
    async with contextlib.AsyncExitStack() as stack:
        if kind == "httpx":
            client = await stack.enter_async_context(
                httpx.AsyncClient(base_url=base, limits=limits, timeout=30.0))
            sends = [functools.partial(_httpx_send, client)] * clients
        else:
            sends = [c.request for c in conns]
        deadline = time.perf_counter() + duration
        t0 = time.perf_counter()
        await asyncio.gather(*(_client_loop(sends[k], targets, k, deadline, out)
                               for k in range(clients)))
        wall = time.perf_counter() - t0
    for c in conns:
        c.close()
    return out, wall


def _load(url: str, job_id: str, phase: str, clients: int, duration: float, kind: str,
          out: mp.Queue) -> None:
    """Runs in a separate process: ``clients`` concurrent connections, each sending requests
    back to back for ``duration`` s, cycling through the four endpoints; puts
    ``([(label, seconds, ok)], wall s, client CPU s)`` on ``out``."""
    import resource

    if not url.startswith("http://127.0.0.1:"):
        raise SystemExit("the load only goes to 127.0.0.1")
    results, wall = asyncio.run(_run_load(url, job_id, phase, clients, duration, kind))
    use = resource.getrusage(resource.RUSAGE_SELF)
    out.put((results, wall, use.ru_utime + use.ru_stime))


def _pct(values: list[float], q: float) -> float:
    return statistics.quantiles(values, n=100, method="inclusive")[q - 1] if len(values) > 1 \
        else values[0]


def _submit_finished_job(url: str, copies: int) -> str:
    """The finished 20 s job (paper-random-straight-80) and ``copies`` jobs reusing its
    results, so that the job list has that many more rows; returns the first job's id."""
    body = {**JOB_BODY, "reuse": False}
    r = httpx.post(f"{url}{API}/jobs", timeout=120, json=body, headers=AUTH)
    r.raise_for_status()
    job = _wait_job(url, r.json()["id"])
    for _ in range(copies):
        r = httpx.post(f"{url}{API}/jobs", timeout=120, json={**body, "reuse": True},
                       headers=AUTH)
        r.raise_for_status()
    return job["id"]


_CLIENTS = {"raw": "asyncio streams", "httpx": "asyncio + httpx"}


def _print_table(results: list, wall: float) -> None:
    print(f"   {'request':<36} {'req/s':>7} {'p50 ms':>8} {'p95 ms':>8} {'p99 ms':>8} "
          f"{'max ms':>8} {'errors':>7}")
    labels = list(dict.fromkeys(label for label, _, _, _ in results))
    for label in [*labels, "overall"]:
        rows = [r for r in results if label in ("overall", r[0])]
        v = [dt * 1000 for _, dt, _, _ in rows]
        errors = sum(not ok for _, _, ok, _ in rows)
        print(f"   {label:<36} {len(rows) / wall:7.1f} {_pct(v, 50):8.1f} {_pct(v, 95):8.1f} "
              f"{_pct(v, 99):8.1f} {max(v):8.1f} {errors:7d}")


def _cpu_s(pid: int) -> float:
    """CPU time (user + system, s) used so far by process ``pid`` itself (Linux; 0 elsewhere)."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return 0.0
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def latency(url: str, clients: int, duration: float, copies: int, kind: str,
            api_pid: int) -> None:
    """Each phase of load on one finished 20 s job while the runner is idle; prints a table
    per phase, the CPU the client processes used and the CPU time the API process spent per
    request."""
    job_id = _submit_finished_job(url, copies)
    n = httpx.get(f"{url}{API}/jobs/{job_id}/channels").json()["n_samples"]
    phases = _targets(job_id)
    for t in (t for targets in phases.values() for t in targets):  # one each, not timed
        r = httpx.request(t.method, f"{url}{t.path}", content=t.body or None, timeout=60,
                          headers={**(AUTH if t.token else {}),
                                   "Content-Type": "application/json"})
        if r.status_code != t.status:
            raise SystemExit(f"{t.label}: {r.status_code} {r.text[:300]}")
    print(f"\n1. Requests under load: a finished 20 s run ({n} samples per channel), "
          f"{copies + 1} jobs in the list at the start, runner idle, service with an API "
          f"token; in each phase {clients} concurrent clients ({_CLIENTS[kind]}, "
          f"{CLIENT_PROCESSES} processes) send requests back to back for {duration:g} s; "
          f"latency = request sent to last byte received, content checked on 1 answer in "
          f"{CHECK_EVERY}")
    for phase in phases:
        _phase(url, job_id, phase, clients, duration, kind, api_pid)


def _phase(url: str, job_id: str, phase: str, clients: int, duration: float, kind: str,
           api_pid: int) -> None:
    ctx = mp.get_context("spawn")
    q = ctx.Queue()
    shares = [clients // CLIENT_PROCESSES + (i < clients % CLIENT_PROCESSES)
              for i in range(CLIENT_PROCESSES)]
    procs = [ctx.Process(target=_load, args=(url, job_id, phase, n_c, duration, kind, q))
             for n_c in shares if n_c]
    load0 = _load_note()
    for proc in procs:
        proc.start()
    api0 = _cpu_s(api_pid)
    parts = [q.get(timeout=duration + 600) for _ in procs]
    api_cpu = _cpu_s(api_pid) - api0
    for proc in procs:
        proc.join()
    results = [r for part in parts for r in part[0]]
    wall = max(part[1] for part in parts)
    cpu = sum(part[2] for part in parts)
    print(f"\n   {phase}, {clients} clients {load0}: {len(results)} requests in {wall:.1f} s")
    _print_table(results, wall)
    failures = Counter(f"{label}: {why}" for label, _, ok, why in results if not ok)
    for what, count in failures.most_common(5):
        print(f"   error ×{count}: {what}")
    print(f"   client processes: {cpu / wall:.0%} of a core "
          f"({1000 * cpu / max(1, len(results)):.2f} ms CPU per request); "
          f"API process: {api_cpu / wall:.0%} of a core "
          f"({1000 * api_cpu / max(1, len(results)):.2f} ms CPU per request); "
          f"load average at the end {os.getloadavg()[0]:.1f}")


# -- 2. throughput ---------------------------------------------------------------------------


def _scenarios(duration: float) -> list:
    from flexride.scenario.presets import load_preset

    return [load_preset("paper-random-straight-80",
                        {"speed_kmh": float(v), "duration_s": duration, "distance_m": None})
            for v in STUDY_SPEEDS]


def sequential(duration: float, tmp: Path) -> float:
    """The 8 jobs one after another in this process (after a warm-up run), with one BLAS
    thread like the workers."""
    from flexride.analysis import analyze
    from flexride.jobs.warmup import limit_blas_threads, warm_numba
    from flexride.solver import simulate

    limit_blas_threads(1)
    warm_numba()
    t0 = time.perf_counter()
    for i, s in enumerate(_scenarios(duration)):
        res = simulate(s)
        res.write_hdf5(tmp / f"seq{i}.h5")
        analyze(res).to_dict()
    return time.perf_counter() - t0


def _load_note() -> str:
    return f"(load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)"


def study(url: str, duration: float) -> tuple[float, float, float, float]:
    """Submit the study and wait for it: total wall time, submission time, time from the
    first job's start to the last job's end (s), and the mean number of jobs running at once
    (sum of the jobs' run times over that span)."""
    from datetime import datetime

    body = {"name": "bench", "base": {"preset": "paper-random-straight-80"},
            "speeds_kmh": STUDY_SPEEDS, "reuse": False,
            "overrides": {"duration_s": duration, "distance_m": None}}
    t0 = time.perf_counter()
    r = httpx.post(f"{url}{API}/studies", json=body, timeout=120, headers=AUTH)
    r.raise_for_status()
    submitted = time.perf_counter() - t0
    study_id = r.json()["id"]

    def done():
        d = httpx.get(f"{url}{API}/studies/{study_id}", timeout=30).json()
        return d if d["status"] not in ("queued", "running") else None

    d = _wait(done, 900.0, "the study", 0.1)
    wall = time.perf_counter() - t0
    if d["status"] != "succeeded":
        raise SystemExit(f"study {d['status']}: {d['counts']}")
    jobs = httpx.get(f"{url}{API}/jobs", params={"study_id": study_id, "limit": 100}).json()
    start = min(datetime.fromisoformat(j["started_at"]) for j in jobs["items"])
    end = max(datetime.fromisoformat(j["finished_at"]) for j in jobs["items"])
    span = (end - start).total_seconds()
    busy = sum(j["run_time_s"] for j in jobs["items"])
    return wall, submitted, span, busy / span


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true",
                        help="10 s of read load (unless --duration), shorter study jobs")
    parser.add_argument("--clients", type=int, default=50,
                        help="concurrent clients (default 50)")
    parser.add_argument("--duration", type=float, default=None,
                        help="seconds of load per phase (default 20, 5 with --quick)")
    parser.add_argument("--list-jobs", type=int, default=20,
                        help="jobs in the job list during the read load (default 20)")
    parser.add_argument("--client", choices=sorted(_CLIENTS), default="raw",
                        help="HTTP client of the read load: raw (a minimal keep-alive client "
                        "on asyncio streams, default) or httpx (costs more CPU per request)")
    parser.add_argument("--reads-only", action="store_true",
                        help="only the requests under load (no throughput measurement)")
    parser.add_argument("--skip-celery", action="store_true", help="no Celery measurement")
    args = parser.parse_args()
    load_s = args.duration or (5.0 if args.quick else 20.0)
    duration = 2.0 if args.quick else 5.0
    print(f"flexride service benchmark ({os.cpu_count()} cores; numbers vary with other load)")
    procs: list[subprocess.Popen] = []
    with tempfile.TemporaryDirectory(prefix="flexride-bench-") as tmpdir:
        tmp = Path(tmpdir)
        try:
            api, url = _serve(tmp, "embedded", FLEXRIDE_WORKERS="2", FLEXRIDE_API_TOKEN=TOKEN)
            procs.append(api)
            _wait(lambda: _workers_alive(url, 2), 120.0, "2 embedded workers")
            latency(url, args.clients, load_s, max(0, args.list_jobs - 1), args.client, api.pid)
            if args.reads_only:
                return

            print(f"\n2. Throughput: study of 8 jobs (paper-random-straight, "
                  f"{len(STUDY_SPEEDS)} speeds, {duration:g} s simulated each)")
            seq = sequential(duration, tmp)
            print(f"   one process, one after another      {seq:7.1f} s   1.00x  "
                  f"({seq / len(STUDY_SPEEDS):.2f} s per job) {_load_note()}")
            emb, sub, run, par = study(url, duration)
            print(f"   embedded runner, 2 worker processes {emb:7.1f} s   {seq / emb:4.2f}x  "
                  f"(submission {sub:.1f} s; first start to last end {run:.1f} s with "
                  f"{par:.1f} jobs at once) {_load_note()}")
            _stop(api)
            procs.remove(api)
            if not args.skip_celery:
                queue = f"flexride-bench-{os.getpid()}"
                celery = dict(FLEXRIDE_BROKER_URL="redis://127.0.0.1:6379/10",
                              FLEXRIDE_CELERY_QUEUE=queue,
                              FLEXRIDE_DATABASE_URL=f"sqlite:///{tmp / 'celery' / 'db.sqlite'}",
                              FLEXRIDE_API_TOKEN=TOKEN)
                api, url = _serve(tmp, "celery", **celery)
                procs.append(api)
                for i in range(2):
                    procs.append(_start([*SERVICE, "worker", "--concurrency", "1"],
                                        _env(FLEXRIDE_DATA_DIR=str(tmp / "celery"), **celery),
                                        tmp / f"worker{i}.log"))
                _wait(lambda: _workers_alive(url, 2), 120.0, "2 Celery workers")
                time.sleep(2.0)  # both pools ready (warm-up done before they report)
                cel, sub, run, par = study(url, duration)
                print(f"   two Celery workers (Redis broker)   {cel:7.1f} s   {seq / cel:4.2f}x  "
                      f"(submission {sub:.1f} s; first start to last end {run:.1f} s with "
                      f"{par:.1f} jobs at once) {_load_note()}")
        finally:
            for p in procs:
                _stop(p)


if __name__ == "__main__":
    main()
