"""The paper's study on a warm service: wall time against the time spent in the solver.

A command that prints figures, not a test. It starts a real ``flexride serve`` (embedded
runner, ``--workers`` processes, default 2) on a fresh data directory with the usual cache
directory (compiled kernels, reduced FE bodies), warms it (kernels loaded, one short rigid and
one short flexible job, so the FE bodies are built or loaded once), then submits the study
preset ``paper-table3-flexible-vs-rigid`` (16 conditions × rigid/flexible = 32 jobs) with
``duration_s`` 20 s and no reuse of stored results, and waits for it. Prints

* the wall time from the submission to the last job finished (target ≤ 30 s on 2 cores);
* the sums over the jobs of ``timings`` (setup, solve, write, analyse) and of the run times;
* the solver share: sum of solve times / (workers × wall time) (target ≥ 80 %);

for the presets as they are (real profiles: S1002 on 60E1, Δt 1/12000 s) and with the conical
tread (:data:`flexride.scenario.presets.CONICAL_TREAD`, Δt 1e-4 s) (``--variant conical``,
``profiles`` or ``both``, the default). ``--repeat N`` runs each study N times
(the set-ups of the second are cached). The load average is printed with every figure.

Usage::

    .venv/bin/python benchmarks/bench_study.py [--variant conical|profiles|both] [--repeat 2]
        [--workers 2] [--duration 20]
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
import urllib.request
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tools"))

from live_server import LiveServer, get_json, start_server

STUDY = "paper-table3-flexible-vs-rigid"
TARGET_WALL_S = 30.0
TARGET_SHARE = 0.8
FINAL = {"succeeded", "failed", "cancelled"}


def _load() -> str:
    one, five, _ = os.getloadavg()
    return f"load average {one:.2f} (1 min), {five:.2f} (5 min)"


def _post(url: str, body: dict[str, Any]) -> Any:
    req = urllib.request.Request(url, data=json.dumps(body).encode(), method="POST",
                                 headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(req, timeout=120) as r:
        return json.loads(r.read().decode())


def _wait_ready(server: LiveServer, workers: int, timeout: float = 900.0) -> None:
    """Wait until the kernels are compiled and every worker process has reported."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        h = get_json(f"{server.url}/api/v1/health")
        alive = [w for w in h.get("workers", []) if w.get("alive")]
        if (h.get("solver") or {}).get("state") == "ready" and len(alive) >= workers:
            return
        time.sleep(0.5)
    raise RuntimeError("the service did not become ready")


def _wait_jobs(server: LiveServer, ids: list[str], timeout: float = 1800.0) -> list[dict]:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        jobs = [get_json(f"{server.url}/api/v1/jobs/{i}") for i in ids]
        if all(j["status"] in FINAL for j in jobs):
            return jobs
        time.sleep(0.5)
    raise RuntimeError("jobs did not finish")


def _warm(server: LiveServer, overrides: dict[str, Any]) -> None:
    """One short rigid and one short flexible job (kernels, FE bodies, contact tables)."""
    ids = []
    for model in ("rigid", "flexible"):
        body = {"preset": "paper-random-straight-80", "reuse": False,
                "overrides": {**overrides, "duration_s": 0.05, "distance_m": None,
                              "bodies.carbody.model": model, "bodies.frames.model": model}}
        ids.append(_post(f"{server.url}/api/v1/jobs", body)["id"])
    for j in _wait_jobs(server, ids):
        if j["status"] != "succeeded":
            raise RuntimeError(f"warm-up job {j['id']} {j['status']}: {j.get('error')}")


def run_study(server: LiveServer, overrides: dict[str, Any], workers: int) -> dict[str, Any]:
    """Submit the study, wait for it; return its figures."""
    t0 = time.monotonic()
    study = _post(f"{server.url}/api/v1/studies",
                  {"preset": STUDY, "reuse": False, "overrides": overrides})
    t_submit = time.monotonic() - t0
    ids = [j["id"] for j in study["jobs"]]
    jobs = _wait_jobs(server, ids)
    wall = time.monotonic() - t0
    failed = [j for j in jobs if j["status"] != "succeeded"]
    sums = {k: 0.0 for k in ("setup_s", "solve_s", "write_s", "analyze_s")}
    run_time = 0.0
    for j in jobs:
        for k, v in (j.get("timings") or {}).items():
            sums[k] += float(v or 0.0)
        run_time += float(j.get("run_time_s") or 0.0)
    return {"n": len(jobs), "failed": len(failed), "wall_s": wall, "submit_s": t_submit,
            "sums": sums, "run_time_s": run_time,
            "share": sums["solve_s"] / (workers * wall) if wall > 0 else 0.0,
            "errors": [j.get("error") for j in failed][:3]}


def _print(label: str, r: dict[str, Any], workers: int) -> None:
    s = r["sums"]
    met = "met" if r["wall_s"] <= TARGET_WALL_S else "MISSED"
    share_met = "met" if r["share"] >= TARGET_SHARE else "MISSED"
    print(f"{label}: {r['n']} jobs ({r['failed']} failed), POST /studies {r['submit_s']:.2f} s")
    print(f"  wall time               : {r['wall_s']:7.1f} s  (target ≤ {TARGET_WALL_S:.0f} s: "
          f"{met}, ratio {r['wall_s'] / TARGET_WALL_S:.2f})")
    print(f"  sum of solve times      : {s['solve_s']:7.1f} s  (setup {s['setup_s']:.1f} s, "
          f"write {s['write_s']:.1f} s, analyse {s['analyze_s']:.1f} s; run times "
          f"{r['run_time_s']:.1f} s)")
    print(f"  solver share            : {r['share'] * 100:6.1f} %  = sum of solve / ({workers} "
          f"workers × wall) (target ≥ {TARGET_SHARE * 100:.0f} %: {share_met}, ratio "
          f"{r['share'] / TARGET_SHARE:.2f})")
    print(f"  {_load()}")
    for e in r["errors"]:
        print(f"  failed: {e}")


def _variants() -> dict[str, dict[str, Any]]:
    """Overrides of the two set-ups of the paper presets: as the presets are (real profiles,
    no override) and with the conical tread of the first releases
    (:data:`~flexride.scenario.presets.CONICAL_TREAD`).
    """
    from flexride.scenario import presets

    return {"conical": dict(presets.CONICAL_TREAD), "profiles": {}}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--variant", choices=("conical", "profiles", "both"), default="both")
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--duration", type=float, default=20.0)
    args = ap.parse_args()

    variants = _variants()
    chosen = list(variants) if args.variant == "both" else [args.variant]
    print(f"variants: {variants}")
    print(f"flexride study benchmark: {STUDY}, {args.duration:g} s per job, {args.workers} "
          f"workers, {os.cpu_count()} cores; {_load()}")
    with tempfile.TemporaryDirectory(prefix="flexride-bench-study-") as d:
        server = start_server(Path(d), workers=args.workers, log=Path(d) / "serve.log",
                              timeout=300.0)
        try:
            t = time.monotonic()
            _wait_ready(server, args.workers)
            print(f"service ready (kernels loaded, {args.workers} workers) after "
                  f"{time.monotonic() - t:.1f} s")
            for name in chosen:
                overrides = {**variants[name], "duration_s": args.duration, "distance_m": None}
                t = time.monotonic()
                _warm(server, variants[name])
                print(f"[{name}] warm-up jobs (rigid + flexible, 0.05 s): "
                      f"{time.monotonic() - t:.1f} s")
                for k in range(args.repeat):
                    _print(f"[{name}] study run {k + 1}", run_study(server, overrides,
                                                                  args.workers), args.workers)
        finally:
            server.stop()


if __name__ == "__main__":
    main()
