"""Service performance (prints figures; not a timed test).

1. API latency, p50/p95, under a small concurrent load from a separate process (4 client
   threads by default): job detail (``GET /jobs/{id}``) and a decimated 10,000-point series
   (``GET /jobs/{id}/series?max_points=10000``) of a 20 s run (20,000 samples per channel).
2. Throughput on a study of 8 short jobs (paper-random-straight at 8 speeds, 5 s simulated):
   the embedded runner (2 worker processes) and two Celery workers (1 process each, Redis
   broker), relative to running the same 8 jobs one after another in one process
   (simulate + write HDF5 + analyze, kernels already compiled).

Needs Redis on 127.0.0.1:6379 for the Celery part (``tools/ensure_services.sh``); runs
everything on loopback and stops every process it started.

Usage: ``python benchmarks/bench_service.py [--quick] [--clients N] [--requests N]``
"""

from __future__ import annotations

import argparse
import contextlib
import multiprocessing as mp
import os
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import httpx

ROOT = Path(__file__).resolve().parents[1]
API = "/api/v1"
SERVICE = [sys.executable, "-m", "flexride.service_cli"]
STUDY_SPEEDS = [50, 55, 60, 65, 70, 75, 80, 85]


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
    with contextlib.suppress(ProcessLookupError):
        os.killpg(proc.pid, signal.SIGTERM)
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
    health = httpx.get(f"{url}{API}/health", timeout=5).json()
    return sum(w["alive"] for w in health["workers"]) >= n


def _wait_job(url: str, job_id: str, timeout: float = 600.0) -> dict:
    def done():
        j = httpx.get(f"{url}{API}/jobs/{job_id}", timeout=10).json()
        return j if j["status"] not in ("queued", "running") else None

    job = _wait(done, timeout, f"job {job_id}")
    if job["status"] != "succeeded":
        raise SystemExit(f"job {job_id} {job['status']}: {job['error']}")
    return job


# -- 1. latency under load -------------------------------------------------------------------


def _load(url: str, job_id: str, clients: int, requests: int, out: mp.Queue) -> None:
    """Runs in a separate process: ``clients`` threads, each sending ``requests`` requests
    alternating job detail and the 10,000-point series; puts (kind, seconds) pairs on out."""
    results: list[tuple[str, float]] = []
    lock = threading.Lock()
    detail = f"{url}{API}/jobs/{job_id}"
    series = (f"{url}{API}/jobs/{job_id}/series?channels=carbody.PR.acc.z&max_points=10000"
              "&method=lttb")

    def client(k: int) -> None:
        with httpx.Client(timeout=30) as c:
            for i in range(requests):
                kind, target = ("detail", detail) if (i + k) % 2 == 0 else ("series", series)
                t0 = time.perf_counter()
                r = c.get(target)
                dt = time.perf_counter() - t0
                r.raise_for_status()
                if kind == "series":
                    assert len(r.json()["channels"][0]["values"]) <= 10_000
                with lock:
                    results.append((kind, dt))

    threads = [threading.Thread(target=client, args=(k,)) for k in range(clients)]
    t0 = time.perf_counter()
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    out.put((results, time.perf_counter() - t0))


def _pct(values: list[float], q: float) -> float:
    return statistics.quantiles(values, n=100, method="inclusive")[q - 1] if len(values) > 1 \
        else values[0]


def latency(url: str, clients: int, requests: int) -> None:
    r = httpx.post(f"{url}{API}/jobs", timeout=60, json={
        "preset": "paper-random-straight-80", "reuse": False,
        "overrides": {"duration_s": 20.0, "distance_m": None}})
    r.raise_for_status()
    job = _wait_job(url, r.json()["id"])
    n = httpx.get(f"{url}{API}/jobs/{job['id']}/channels").json()["n_samples"]
    httpx.get(f"{url}{API}/jobs/{job['id']}/series?channels=carbody.PR.acc.z&max_points=10000"
              "&method=lttb", timeout=60)  # first call compiles/loads LTTB
    ctx = mp.get_context("spawn")
    q = ctx.Queue()
    proc = ctx.Process(target=_load, args=(url, job["id"], clients, requests, q))
    proc.start()
    results, wall = q.get(timeout=600)
    proc.join()
    print(f"\n1. API latency {_load_note()}: 20 s run ({n} samples per channel), "
          f"{clients} concurrent clients in a separate process, {len(results)} requests in "
          f"{wall:.1f} s ({len(results) / wall:.0f} req/s)")
    print(f"   {'request':<44} {'p50 ms':>8} {'p95 ms':>8} {'n':>5}")
    for kind, label in (("detail", "GET /jobs/{id}"),
                        ("series", "GET /jobs/{id}/series, 10,000 points (LTTB)")):
        v = [dt * 1000 for k, dt in results if k == kind]
        print(f"   {label:<44} {_pct(v, 50):8.1f} {_pct(v, 95):8.1f} {len(v):5d}")


# -- 2. throughput ---------------------------------------------------------------------------


def _scenarios(duration: float) -> list:
    from flexride.model.presets import load_preset

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
    r = httpx.post(f"{url}{API}/studies", json=body, timeout=120)
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
    parser.add_argument("--quick", action="store_true", help="fewer requests, shorter jobs")
    parser.add_argument("--clients", type=int, default=4, help="concurrent clients (default 4)")
    parser.add_argument("--requests", type=int, default=None,
                        help="requests per client (default 100, 25 with --quick)")
    parser.add_argument("--skip-celery", action="store_true", help="no Celery measurement")
    args = parser.parse_args()
    requests = args.requests or (25 if args.quick else 100)
    duration = 2.0 if args.quick else 5.0
    print(f"flexride service benchmark ({os.cpu_count()} cores; numbers vary with other load)")
    procs: list[subprocess.Popen] = []
    with tempfile.TemporaryDirectory(prefix="flexride-bench-") as tmpdir:
        tmp = Path(tmpdir)
        try:
            api, url = _serve(tmp, "embedded", FLEXRIDE_WORKERS="2")
            procs.append(api)
            _wait(lambda: _workers_alive(url, 2), 120.0, "2 embedded workers")
            latency(url, args.clients, requests)

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
                              FLEXRIDE_DATABASE_URL=f"sqlite:///{tmp / 'celery' / 'db.sqlite'}")
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
