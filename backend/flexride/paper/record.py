"""One run of the study, reduced to what the report needs: simulate, cut the evaluated stretch,
analyse, and keep the summary plus a few decimated arrays (time histories, PSDs, the PRB
spectrogram, the cross-correlation curves).

:func:`execute` is the worker function of the process pool (picklable, top level).
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np
from scipy import signal

from flexride.analysis import analyze
from flexride.analysis._common import jsonable
from flexride.analysis.summary import Summary
from flexride.errors import AnalysisError
from flexride.paper.plan import RECORD_VERSION, RunSpec
from flexride.results import Results

__all__ = ["execute", "record_from_results", "window_results"]

SERIES_RATE_HZ = 250.0
"""Rate of the stored time histories (Hz; decimated with an anti-aliasing filter)."""
PSD_MAX_HZ = 100.0
SPECTROGRAM_POINT = "PRB"
SPECTROGRAM_MAX_HZ = 20.0
CURVE_POINTS = 600
"""Largest number of points kept of a cross-correlation curve."""
_LONG_LIST = 64


def window_results(results: Results, window_m: tuple[float, float]) -> Results:
    """The part of a run while the vehicle centre is within ``window_m`` (m along the line).

    Raises
    ------
    AnalysisError
        If fewer than two samples lie in the window.
    """
    s = np.asarray(results.distance)
    keep = (s >= window_m[0] - 1e-9) & (s <= window_m[1] + 1e-9)
    if int(np.count_nonzero(keep)) < 2:
        raise AnalysisError(f"the evaluated stretch {window_m[0]:g}–{window_m[1]:g} m holds "
                            "fewer than two samples of the run")
    return Results(time=results.time[keep], distance=s[keep],
                   channels={k: np.asarray(v)[keep] for k, v in results.channels.items()},
                   units=dict(results.units), scenario=results.scenario,
                   meta=dict(results.meta), points=results.points)


def _sig(values: np.ndarray, digits: int = 4) -> list[float | None]:
    """Values rounded to ``digits`` significant digits, as JSON numbers (NaN → None)."""
    return [float(f"{v:.{digits}g}") if np.isfinite(v) else None
            for v in np.asarray(values, dtype=float).ravel().tolist()]


def _prune(obj: Any) -> Any:
    """A summary dict without its long arrays (lists longer than 64 items become None)."""
    if isinstance(obj, dict):
        return {k: _prune(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return None if len(obj) > _LONG_LIST else [_prune(v) for v in obj]
    return obj


def _series(results: Results) -> dict[str, Any]:
    """Car-body accelerations decimated to about :data:`SERIES_RATE_HZ` (m/s²)."""
    fs = float(results.sample_rate)
    q = max(1, round(fs / SERIES_RATE_HZ))
    out: dict[str, Any] = {"t0": float(results.time[0]), "s0": float(results.distance[0]),
                           "rate_hz": fs / q}
    for ch in results.parsed():
        if ch.body == "carbody" and ch.quantity == "acc":
            x = np.asarray(results.channels[ch.name], dtype=float)
            y = signal.decimate(x, q, ftype="fir", zero_phase=True) if q > 1 else x
            out[f"{ch.point}.{ch.direction}"] = _sig(y)
    return out


def _psd(summary: Summary) -> dict[str, Any]:
    """Welch PSDs of the dynamic parts up to :data:`PSD_MAX_HZ` ((m/s²)²/Hz), by point.dir."""
    out: dict[str, Any] = {}
    for p, ps in summary.points.items():
        for d, ds in ps.directions.items():
            if ds.psd is None:
                continue
            keep = ds.psd.frequencies <= PSD_MAX_HZ + 1e-9
            out.setdefault("f", _sig(ds.psd.frequencies[keep], 6))
            out[f"{p}.{d}"] = _sig(ds.psd.values[keep])
    return out


def _spectrogram(summary: Summary) -> dict[str, Any] | None:
    """Spectrogram of the vertical acceleration at PRB up to 20 Hz ((m/s²)²/Hz)."""
    ps = summary.points.get(SPECTROGRAM_POINT)
    ds = ps.directions.get("z") if ps is not None else None
    if ds is None or ds.spectrogram is None:
        return None
    sg = ds.spectrogram
    keep = sg.frequencies <= SPECTROGRAM_MAX_HZ + 1e-9
    vals = np.asarray(sg.values)[keep]
    return {"point": SPECTROGRAM_POINT, "t": _sig(sg.times, 5), "f": _sig(sg.frequencies[keep]),
            "values": [_sig(row, 3) for row in vals]}


def _correlations(summary: Summary) -> list[dict[str, Any]]:
    """Each cross-correlation of the reference point: lag (s) and value of its maximum, its
    local maxima and, for z, the normalised curve (at most :data:`CURVE_POINTS` points).
    """
    out = []
    for c in summary.correlations:
        r = c.result
        item: dict[str, Any] = {
            "reference": c.reference, "other": c.other, "direction": c.direction,
            "lag_s": float(r.lag_at_max_interpolated), "raw_max": float(r.value_at_max),
            "normalised_max": float(r.normalised_at_max),
            "maxima": [{k: float(v) for k, v in m.items()} for m in r.local_maxima]}
        if c.direction == "z" and c.curve is not None:
            lags = np.asarray(c.curve["lags_s"])
            step = max(1, lags.size // CURVE_POINTS)
            item["curve"] = {"lag_s": _sig(lags[::step], 5),
                             "normalised": _sig(np.asarray(c.curve["normalised"])[::step])}
        out.append(item)
    return out


def compact_record(spec: RunSpec, summary: Summary, window: Results,
                   wall_time_s: float) -> dict[str, Any]:
    """The stored record of one run (plain JSON).

    Parameters
    ----------
    spec : RunSpec
        The run.
    summary : Summary
        :func:`~flexride.analysis.analyze` of the evaluated stretch, with arrays.
    window : Results
        The evaluated stretch.
    wall_time_s : float
        Wall time of simulation and analysis (s).
    """
    meta = window.meta
    return {
        "version": RECORD_VERSION, "key": spec.key(), "spec": spec.to_dict(),
        "run": {"wall_time_s": wall_time_s, "sample_rate_hz": float(window.sample_rate),
                "window_s": [float(window.time[0]), float(window.time[-1])],
                "n_samples": int(window.time.size), "dt": meta.get("dt"),
                "n_dof": meta.get("n_dof"),
                "flexible_bodies": jsonable(meta.get("flexible_bodies") or {})},
        "summary": _prune(summary.to_dict()),
        "psd": _psd(summary),
        "series": _series(window),
        "spectrogram": _spectrogram(summary),
        "correlations": _correlations(summary),
    }


def execute(spec: RunSpec) -> dict[str, Any]:
    """Simulate one run of the study and return its record (see :func:`compact_record`).

    Raises
    ------
    FlexrideError
        Whatever the scenario, the solver or the analysis raises.
    """
    from flexride.solver.simulate import simulate

    t0 = time.perf_counter()
    results = simulate(spec.scenario())
    return record_from_results(spec, results, t0)


def record_from_results(spec: RunSpec, results: Results, t0: float) -> dict[str, Any]:
    """The record of one run from its results: cut the evaluated stretch, analyse it
    (:func:`compact_record`). Also how the service's report study reads its jobs' files.

    Parameters
    ----------
    spec : RunSpec
        The run the results are of.
    results : Results
        The whole run.
    t0 : float
        ``time.perf_counter()`` when the run started (the record's wall time ends now).
    """
    window = window_results(results, spec.window_m)
    summary = analyze(window, arrays=True)
    return compact_record(spec, summary, window, time.perf_counter() - t0)
