"""Print the time flexride's analysis layer needs (a command that prints figures, not a test).

1. ``analyze()`` of a 60 s run sampled at 2 kHz with 20 car-body acceleration channels
   (10 points × lateral and vertical) and the wheel–rail forces of 4 wheelsets
   (target: well under 1 s).
2. A comfort map of 2,000 floor nodes (modal superposition of 20 modes, 60 s at 500 Hz) for
   several measures.

Usage::

    .venv/bin/python benchmarks/bench_analysis.py [--repeat 3] [--nodes 2000]
        [--map-duration 60] [--map-rate 500]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from flexride.analysis import analyze, comfort_map
from flexride.results import Results


def synthetic_run(duration: float = 60.0, fs: float = 2000.0, n_points: int = 10,
                  wheelsets: int = 4, seed: int = 0) -> Results:
    """Band-limited random car-body accelerations with bending-mode sines, and wheel forces."""
    rng = np.random.default_rng(seed)
    n = round(duration * fs)
    t = np.arange(n) / fs
    spec = np.fft.rfft(rng.standard_normal(n))
    f = np.fft.rfftfreq(n, 1 / fs)
    spec *= 1.0 / (1.0 + (f / 8.0) ** 2)
    spec[f < 0.3] = 0.0
    base = np.fft.irfft(spec, n)
    base *= 0.15 / base.std()
    channels: dict[str, np.ndarray] = {}
    units: dict[str, str] = {}
    points = ["PR", "PFB", "PC", "PRB", "PLA", "PRA"] + [f"P{i}" for i in range(n_points - 6)]
    for k, p in enumerate(points):
        lag = round(0.05 * k * fs)
        for d, fm in (("z", 6.3), ("y", 0.95)):
            name = f"carbody.{p}.acc.{d}"
            channels[name] = (np.roll(base, lag) + 0.05 * np.sin(2 * np.pi * fm * t)
                              + 0.01 * rng.standard_normal(n))
            units[name] = "m/s^2"
    for w in range(1, wheelsets + 1):
        for side, sign in (("left", 1.0), ("right", -1.0)):
            channels[f"wheelset{w}.{side}.force.z"] = 70e3 + 3e3 * rng.standard_normal(n)
            channels[f"wheelset{w}.{side}.force.y"] = -sign * 5e3 + 1e3 * rng.standard_normal(n)
            units[f"wheelset{w}.{side}.force.z"] = units[f"wheelset{w}.{side}.force.y"] = "N"
    v = 80.0 / 3.6
    return Results(time=t, distance=v * t, channels=channels, units=units,
                   scenario={"name": "bench", "speed_kmh": 80.0},
                   meta={"output_rate": fs, "speed_mps": v,
                         "static_wheel_loads": [[70e3, 70e3]] * wheelsets})


def _timed(fn, repeat: int) -> tuple[float, float, object]:
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), statistics.median(times), out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--nodes", type=int, default=2000)
    ap.add_argument("--map-duration", type=float, default=60.0)
    ap.add_argument("--map-rate", type=float, default=500.0)
    args = ap.parse_args()

    run = synthetic_run()
    n_acc = len(run.names(quantity="acc"))
    print(f"run: {run.time.size / run.sample_rate:g} s at {run.sample_rate:g} Hz, "
          f"{n_acc} car-body acceleration channels, {len(run.names(quantity='force'))} force "
          f"channels ({sum(a.nbytes for a in run.channels.values()) / 1e6:.0f} MB)")
    analyze(run)  # warm-up (filter design caches, imports)
    best, med, summary = _timed(lambda: analyze(run), args.repeat)
    print(f"analyze()                 best {best:6.3f} s   median {med:6.3f} s")
    best, med, _ = _timed(lambda: analyze(run, arrays=True), args.repeat)
    print(f"analyze(arrays=True)      best {best:6.3f} s   median {med:6.3f} s")
    best, med, text = _timed(lambda: summary.to_json(), args.repeat)
    print(f"Summary.to_json()         best {best:6.3f} s   ({len(text) / 1e3:.0f} kB)")

    rng = np.random.default_rng(1)
    n = round(args.map_duration * args.map_rate)
    shapes = rng.standard_normal((args.nodes, 20))
    modal = rng.standard_normal((20, n)) * 0.05
    acc = shapes @ modal
    print(f"\ncomfort map: {args.nodes} nodes, {args.map_duration:g} s at {args.map_rate:g} Hz "
          f"({acc.nbytes / 1e6:.0f} MB of accelerations)")
    for measure, kw in (("sperling", {}), ("sperling", {"form": "filter"}),
                        ("weighted_rms", {}), ("cc_max", {}), ("peak", {})):
        label = measure + (f" ({kw['form']} form)" if kw else "")
        best, med, m = _timed(lambda measure=measure, kw=kw: comfort_map(
            acc, args.map_rate, measure=measure, direction="z", **kw), args.repeat)
        print(f"  {label:26s} best {best:6.3f} s   median {med:6.3f} s   "
              f"({best / args.nodes * 1e3:.3f} ms/node, max {m.max_value:.3g} {m.unit})")


if __name__ == "__main__":
    main()
