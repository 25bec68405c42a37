"""Print how fast the dashboard is on this machine (a command that prints figures, not a test).

Starts ``flexride serve`` (embedded runner, temporary data directory), runs one job of
``--duration`` simulated seconds (default 20 s: the "20 s run at full width" of the dashboard
issue) and times

1. the API requests behind the job view: summary, channel list, the time histories of three
   channels decimated to a full-width plot (2,400 points), a zoomed range, amplitude spectrum,
   PSD, spectrogram, Sperling breakdown and cross-correlation;
2. with the system Chromium (``/usr/bin/chromium`` or ``FLEXRIDE_CHROMIUM``) or, with
   ``--browser firefox``, the system Firefox (``/usr/bin/firefox-esr`` or ``FLEXRIDE_FIREFOX``),
   headless, never downloaded (skipped when absent):
   the first view (jobs list on screen, target < 1.5 s), Plotly (4.6 MB) loaded in the
   background after it, the job view with its summary, the
   time-history plot drawn at 1280 px, a zoom round trip (server decimation of the new range
   and redraw) and a hover, which tells whether the plot stays responsive.

Usage::

    .venv/bin/python benchmarks/bench_dashboard.py [--duration 20] [--repeat 5]
        [--browser chromium|firefox] [--no-browser]
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
import time
import urllib.request
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
from live_server import BROWSERS, browser_path, launch_browser, start_server  # noqa: E402

CHANNELS = ["carbody.PC.acc.z", "carbody.PR.acc.z", "carbody.PRB.acc.z"]


def _get(url: str, body: dict | None = None) -> tuple[float, int, object]:
    data = json.dumps(body).encode() if body is not None else None
    req = urllib.request.Request(
        url, data=data, headers={"Content-Type": "application/json"} if data else {}
    )
    t = time.perf_counter()
    with urllib.request.urlopen(req, timeout=120) as r:
        raw = r.read()
    dt = time.perf_counter() - t
    return dt, len(raw), json.loads(raw) if raw[:1] in (b"{", b"[") else None


def _q(params: dict) -> str:
    from urllib.parse import urlencode

    return urlencode(params, doseq=True)


def run_job(url: str, duration: float) -> str:
    _, _, job = _get(
        f"{url}/api/v1/jobs",
        {
            "preset": "paper-random-straight-80",
            "overrides": {"duration_s": duration, "distance_m": None},
            "reuse": False,
        },
    )
    t = time.perf_counter()
    while True:
        _, _, j = _get(f"{url}/api/v1/jobs/{job['id']}")
        if j["status"] not in ("queued", "running"):
            break
        time.sleep(0.3)
    if j["status"] != "succeeded":
        raise SystemExit(f"job {j['status']}: {j.get('error')}")
    print(
        f"job of {duration:g} s simulated: {time.perf_counter() - t:.1f} s wall "
        f"(solver {j['solver_wall_time_s']:.1f} s)"
    )
    return job["id"]


def bench_api(url: str, job: str, duration: float, repeat: int) -> None:
    base = f"{url}/api/v1/jobs/{job}"
    mid = duration / 2
    cases = [
        ("summary", f"{base}/summary"),
        ("channels", f"{base}/channels"),
        (
            "series 3 ch, 2400 pts",
            f"{base}/series?" + _q({"channels": CHANNELS, "max_points": 2400}),
        ),
        (
            "series zoom 1 s",
            f"{base}/series?"
            + _q({"channels": CHANNELS, "max_points": 2400, "t_start": mid, "t_end": mid + 1}),
        ),
        (
            "spectrum 2 ch",
            f"{base}/spectrum?" + _q({"channels": CHANNELS[:2], "fmax": 30, "max_points": 4000}),
        ),
        (
            "psd 2 ch",
            f"{base}/psd?" + _q({"channels": CHANNELS[:2], "fmax": 30, "max_points": 4000}),
        ),
        (
            "spectrogram",
            f"{base}/spectrogram?" + _q({"channel": CHANNELS[0], "window_s": 1, "fmax": 30}),
        ),
        (
            "sperling z+y",
            f"{base}/sperling?" + _q({"channels": ["carbody.PC.acc.z", "carbody.PC.acc.y"]}),
        ),
        (
            "correlation",
            f"{base}/correlation?"
            + _q({"reference": "carbody.PRB.acc.z", "channels": ["carbody.PR.acc.z"]}),
        ),
    ]
    print(f"\nAPI behind the job view ({repeat} runs each, median):")
    print(f"  {'request':<24}{'time (ms)':>10}{'size (kB)':>11}")
    for name, u in cases:
        times = []
        size = 0
        for _ in range(repeat):
            dt, size, _ = _get(u)
            times.append(dt)
        print(f"  {name:<24}{1e3 * statistics.median(times):>10.1f}{size / 1e3:>11.1f}")


def bench_browser(url: str, job: str, repeat: int, browser: str = "chromium") -> None:
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        print("\nbrowser: skipped (no playwright)")
        return
    if not browser_path(browser):
        print(f"\nbrowser: skipped (no system {browser}: apt-get install {BROWSERS[browser]})")
        return
    rows: dict[str, list[float]] = {}
    with sync_playwright() as p:
        b = launch_browser(p, browser)
        version = b.version
        for _ in range(repeat):
            ctx = b.new_context(viewport={"width": 1280, "height": 800})
            pg = ctx.new_page()
            pg.goto(f"{url}/#/")
            pg.wait_for_selector("#jobs-table tbody tr[data-id], .notice-empty")
            rows.setdefault("first view: jobs list (ms)", []).append(
                pg.evaluate("performance.now()")
            )
            pg.wait_for_function("() => !!window.Plotly", timeout=30_000)
            rows.setdefault("Plotly loaded in the background (ms)", []).append(
                pg.evaluate("performance.now()")
            )
            t = time.perf_counter()
            pg.goto(f"{url}/#/jobs/{job}")
            pg.wait_for_selector("#summary-cards")
            rows.setdefault("job view with summary (ms)", []).append(
                1e3 * (time.perf_counter() - t)
            )
            t = time.perf_counter()
            pg.get_by_role("tab", name="Time histories").click()
            pg.wait_for_selector("#plot-time .plot[data-state=ready]")
            rows.setdefault("time histories drawn (ms)", []).append(1e3 * (time.perf_counter() - t))
            t = time.perf_counter()
            with pg.expect_response(lambda r: "/series" in r.url and "t_start" in r.url):
                pg.eval_on_selector(
                    "#plot-time .plot", "e => Plotly.relayout(e, {'xaxis.range': [2, 4]})"
                )
            pg.wait_for_function(
                "() => document.querySelector('#plot-time .plot').data[0].x[0] >= 1.99"
            )
            rows.setdefault("zoom round trip (ms)", []).append(1e3 * (time.perf_counter() - t))
            box = pg.locator("#plot-time .plot").bounding_box()
            t = time.perf_counter()
            for k in range(20):
                pg.mouse.move(box["x"] + 80 + 40 * k, box["y"] + box["height"] / 2)
            pg.evaluate("() => new Promise(r => requestAnimationFrame(() => r()))")
            rows.setdefault("20 hover moves (ms)", []).append(1e3 * (time.perf_counter() - t))
            ctx.close()
        b.close()
    print(f"\nbrowser, system {browser} {version} headless at 1280×800 ({repeat} runs, median):")
    for name, vals in rows.items():
        print(f"  {name:<38}{statistics.median(vals):>9.0f}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--duration", type=float, default=20.0, help="simulated time of the job (s)")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--browser", choices=list(BROWSERS), default="chromium",
                    help="the system browser to time the views in (default: chromium)")
    ap.add_argument("--no-browser", action="store_true")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="flexride-bench-") as tmp:
        server = start_server(Path(tmp))
        try:
            job = run_job(server.url, args.duration)
            bench_api(server.url, job, args.duration, args.repeat)
            if not args.no_browser:
                bench_browser(server.url, job, max(1, min(args.repeat, 3)), args.browser)
        finally:
            server.stop()


if __name__ == "__main__":
    main()
