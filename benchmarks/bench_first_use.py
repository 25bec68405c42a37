"""First use of the service with nothing compiled: cold compile, submission latency while
compiling, and the time until a first 5 s job has results.

A command that prints figures, not a test. With an empty numba cache (``NUMBA_CACHE_DIR`` in a
fresh temporary directory; the installed packages and the FE cache are what they are) it

1. starts ``flexride serve`` (embedded runner, ``--workers`` processes) and times until its
   health answers ``ok``;
2. reads ``solver`` from ``GET /health`` (``compiling`` and its estimate);
3. submits the paper's 80 km/h random case for 5 s (``POST /jobs``) and times the answer
   (target ≤ 100 ms: it must not wait for the compilation), five times (median, max);
4. waits for the first job's results and prints the time from the start of the service
   (the target, ≤ 3 min from a fresh clone, also includes the installation, which this
   command does not time: run it after ``python3 tools/dev.py`` has made ``.venv``);
5. prints the cold compile time recorded by the worker that compiled
   (``flexride-solver.json``, target ≤ 10 s).

Usage::

    .venv/bin/python benchmarks/bench_first_use.py [--workers 2]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import tempfile
import time
import urllib.request
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tools"))

from live_server import get_json, start_server

TARGET_POST_S = 0.1
TARGET_FIRST_S = 180.0
TARGET_COMPILE_S = 10.0
JOB = {"preset": "paper-random-straight-80", "reuse": False,
       "overrides": {"duration_s": 5.0, "distance_m": None}}


def _load() -> str:
    one, five, _ = os.getloadavg()
    return f"load average {one:.2f} (1 min), {five:.2f} (5 min)"


def _post(url: str) -> tuple[float, dict]:
    req = urllib.request.Request(url, data=json.dumps(JOB).encode(), method="POST",
                                 headers={"Content-Type": "application/json"})
    t = time.perf_counter()
    with urllib.request.urlopen(req, timeout=120) as r:
        body = json.loads(r.read().decode())
    return time.perf_counter() - t, body


def _verdict(value: float, target: float) -> str:
    return f"target ≤ {target:g} s: {'met' if value <= target else 'MISSED'}, ratio " \
           f"{value / target:.2f}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args()
    print(f"flexride first-use benchmark: empty numba cache, {args.workers} workers, "
          f"{os.cpu_count()} cores; {_load()}")
    with tempfile.TemporaryDirectory(prefix="flexride-first-use-") as d:
        numba_dir = Path(d) / "numba"
        t0 = time.monotonic()
        server = start_server(Path(d) / "data", workers=args.workers, log=Path(d) / "serve.log",
                              env={"NUMBA_CACHE_DIR": str(numba_dir)}, timeout=300.0)
        try:
            print(f"service healthy after          : {time.monotonic() - t0:7.2f} s")
            solver = get_json(f"{server.url}/api/v1/health").get("solver")
            print(f"health solver                  : {solver}")
            times, first = [], None
            for _ in range(5):
                dt, body = _post(f"{server.url}/api/v1/jobs")
                times.append(dt)
                first = first or body
            assert first is not None
            print(f"POST /jobs while compiling     : median {statistics.median(times) * 1e3:.0f} "
                  f"ms, max {max(times) * 1e3:.0f} ms ({_verdict(max(times), TARGET_POST_S)}); "
                  f"preflight {first.get('preflight')}")
            while True:
                job = get_json(f"{server.url}/api/v1/jobs/{first['id']}")
                if job["status"] in ("succeeded", "failed", "cancelled"):
                    break
                time.sleep(0.5)
            first_s = time.monotonic() - t0
            print(f"first 5 s job {job['status']:<9}        : {first_s:7.1f} s after the start "
                  f"({_verdict(first_s, TARGET_FIRST_S)}, without the installation); "
                  f"timings {job.get('timings')}")
            state = json.loads((numba_dir / "flexride-solver.json").read_text())
            compile_s = float(state.get("compile_s") or 0.0)
            print(f"cold compile (one worker)      : {compile_s:7.1f} s "
                  f"({_verdict(compile_s, TARGET_COMPILE_S)})")
            print(f"health solver now              : "
                  f"{get_json(f'{server.url}/api/v1/health').get('solver')}")
        finally:
            server.stop()
    print(_load())


if __name__ == "__main__":
    main()
