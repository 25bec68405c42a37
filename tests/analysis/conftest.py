"""Synthetic inputs for the analysis tests (the solver is not needed)."""

from __future__ import annotations

import numpy as np
import pytest

from flexride.results import Results

POINTS = ("PR", "PFB", "PC", "PRB", "PLA", "PRA")


def make_results(
    *,
    fs: float = 500.0,
    duration: float = 30.0,
    speed_kmh: float = 80.0,
    amplitude: float = 0.3,
    delays: dict[str, float] | None = None,
    wheelsets: int = 2,
    seed: int = 0,
    meta_loads: object = "nested",
) -> Results:
    """A run with car-body accelerations at the paper's points and wheel-rail forces.

    Every point carries the same band-limited random signal, delayed by ``delays[point]`` s
    (default: PR and PFB lead, the rear points lag 0.5 s), plus a sine of ``amplitude`` at
    6 Hz (z) or 1 Hz (y), scaled with the speed so that peaks grow linearly with it.
    """
    rng = np.random.default_rng(seed)
    n = round(duration * fs)
    t = np.arange(n) / fs
    v = speed_kmh / 3.6
    scale = speed_kmh / 80.0
    delays = delays if delays is not None else {
        "PR": 0.0, "PFB": 0.0, "PC": 1.0 / 3.0, "PRB": 0.5, "PLA": 0.5, "PRA": 0.5}
    spec = np.fft.rfft(rng.standard_normal(n + round(2 * fs)))
    f = np.fft.rfftfreq(n + round(2 * fs), 1 / fs)
    spec[(f < 0.5) | (f > 20.0)] = 0.0
    base = np.fft.irfft(spec, n + round(2 * fs))
    base *= 0.1 / base.std()
    channels: dict[str, np.ndarray] = {}
    units: dict[str, str] = {}
    for p in POINTS:
        lag = round(delays.get(p, 0.0) * fs)
        seg = base[round(fs) - lag: round(fs) - lag + n]
        channels[f"carbody.{p}.acc.z"] = scale * (seg + amplitude * np.sin(2 * np.pi * 6.0 * t))
        channels[f"carbody.{p}.acc.y"] = scale * (0.5 * seg
                                                  + 0.5 * amplitude * np.sin(2 * np.pi * 1.0 * t))
        units[f"carbody.{p}.acc.z"] = units[f"carbody.{p}.acc.y"] = "m/s^2"
    channels["frame1.centre.acc.z"] = rng.standard_normal(n)
    units["frame1.centre.acc.z"] = "m/s^2"
    loads = []
    for w in range(1, wheelsets + 1):
        for side, sign in (("left", 1.0), ("right", -1.0)):
            channels[f"wheelset{w}.{side}.force.z"] = 70e3 + 2e3 * np.sin(2 * np.pi * 3 * t)
            channels[f"wheelset{w}.{side}.force.y"] = -sign * 10e3 + 0 * t
            units[f"wheelset{w}.{side}.force.z"] = units[f"wheelset{w}.{side}.force.y"] = "N"
        loads.append([70e3, 70e3])
    meta: dict[str, object] = {"output_rate": fs, "speed_mps": v}
    if meta_loads == "nested":
        meta["static_wheel_loads"] = loads
    elif meta_loads == "flat":
        meta["static_wheel_loads"] = [x for pair in loads for x in pair]
    return Results(time=t, distance=v * t, channels=channels, units=units,
                   scenario={"name": "synthetic", "speed_kmh": speed_kmh}, meta=meta,
                   points=paper_vehicle_points())


def paper_vehicle_points() -> list[dict]:
    """The recorded points of the paper's vehicle, as the solver writes them."""
    from flexride.scenario.presets import load_preset
    from flexride.vehicle.topology import recorded_points

    return [p.to_dict() for p in recorded_points(load_preset("paper-metro").vehicle)]


@pytest.fixture(scope="module")
def run() -> Results:
    return make_results()


@pytest.fixture(scope="session")
def results_factory():
    """The :func:`make_results` factory, for tests that need several runs."""
    return make_results
