"""Results of a job for plotting: channel list, decimated series, spectra, spectrogram,
Sperling breakdown and cross-correlation, computed from the HDF5 file with
:mod:`flexride.analysis` (the same functions and defaults as the stored summary).

Spectral quantities use the *dynamic part* by default (the quasi-static part below 0.3 Hz
removed, as :func:`flexride.analysis.analyze` does); ``dynamic=false`` takes the raw record.
"""

from __future__ import annotations

from typing import Any, Literal

import numpy as np

from flexride.analysis import (
    amplitude_spectrum,
    cross_correlations,
    dominant_peaks,
    frequency_correction,
    spectrogram,
    sperling_filter,
    sperling_spectral,
    split_quasistatic,
    welch_psd,
)
from flexride.analysis.sperling import record_sines, sperling_grade
from flexride.analysis.timefreq import spectrogram_cells
from flexride.api.deps import Services
from flexride.api.errors import NotFound
from flexride.api.services.decimate import decimate_indices, minmax_indices
from flexride.api.services.jobs import finished_job
from flexride.errors import AnalysisError, ScenarioError
from flexride.results import POINT_FRAME, Channel
from flexride.store import ChannelData

MAX_SPECTROGRAM_CELLS = 250_000
_THIRD_OCTAVE_CENTRES = (0.5, 0.63, 0.8, 1.0, 1.25, 1.6, 2.0, 2.5, 3.15, 4.0, 5.0, 6.3, 8.0,
                         10.0, 12.5, 16.0, 20.0, 25.0, 31.5, 40.0)


def _f(a: np.ndarray) -> list[Any]:
    """Array → (nested) list with non-finite values as None."""
    a = np.asarray(a, dtype=np.float64)
    finite = np.isfinite(a)
    if np.all(finite):
        return a.tolist()
    out = a.astype(object)
    out[~finite] = None
    return out.tolist()


def _num(v: Any) -> float | None:
    try:
        v = float(v)
    except (TypeError, ValueError):
        return None
    return v if np.isfinite(v) else None


def result_file(svc: Services, job_id: str) -> str:
    """Name of the result file of a succeeded job (one query of one column), or
    :class:`NotFound` / :class:`Conflict` saying why there is none.
    """
    name = svc.store.result_file_of(job_id)
    if name is None:
        return str(finished_job(svc, job_id).result_file)  # raises with the reason
    return name


def _read(svc: Services, job_id: str, channels: list[str], t_start: float | None = None,
          t_end: float | None = None) -> ChannelData:
    name = result_file(svc, job_id)
    if not channels:
        raise AnalysisError("channels: give at least one channel name")
    if len(set(channels)) != len(channels):
        raise AnalysisError("channels: names must be unique")
    try:
        return svc.files.read(name, channels, t_start, t_end)
    except KeyError as exc:
        raise AnalysisError(f"channels: {exc.args[0]}") from None


def _prepare(x: np.ndarray, fs: float, dynamic: bool) -> tuple[np.ndarray, bool]:
    if not dynamic:
        return x, False
    try:
        return split_quasistatic(x, fs).dynamic, True
    except AnalysisError:
        return x - np.mean(x, axis=-1, keepdims=True), False


def channel_list(svc: Services, job_id: str) -> dict[str, Any]:
    """Channels of a job with units and sampling, and the recorded points with their
    positions (m, nominal vehicle geometry: x from the car-body centre forward, y left, z above
    top of rail); each channel of a recorded point carries that point's ``position``.
    """
    d = svc.files.describe(result_file(svc, job_id))
    where = {(p["body"], p["name"]): [p["x"], p["y"], p["z"]] for p in d["points"]}
    chans = []
    for name, unit in sorted(d["channels"].items()):
        ch = Channel.parse(name)
        info: dict[str, Any] = {"name": name, "unit": unit}
        if ch is not None:
            info.update(body=ch.body, point=ch.point, quantity=ch.quantity,
                        direction=ch.direction, position=where.get((ch.body, ch.point)))
        chans.append(info)
    return {"job_id": job_id, "sample_rate_hz": d["sample_rate_hz"], "n_samples": d["n_samples"],
            "t_start_s": d["t_start_s"], "t_end_s": d["t_end_s"], "channels": chans,
            "points": d["points"], "point_frame": POINT_FRAME}


def summary(svc: Services, job_id: str) -> dict[str, Any]:
    """The stored analysis summary of a job."""
    job = finished_job(svc, job_id, summary=True)
    if job.summary is None:
        raise NotFound(f"job {job_id} has no summary")
    return {"job_id": job_id, "scenario": job.name, "speed_kmh": job.speed_kmh,
            "summary": job.summary}


def series(svc: Services, job_id: str, channels: list[str], max_points: int, method: str,
           t_start: float | None, t_end: float | None, distance: bool) -> dict[str, Any]:
    """Decimated time series of ``channels`` (each with its own sample times)."""
    data = _read(svc, job_id, channels, t_start, t_end)
    n = int(data.time.size)
    if method == "none" and n > max_points:
        raise AnalysisError(
            f"method: 'none' would return {n} samples, more than max_points = {max_points}; "
            "use minmax or lttb, or a shorter time range")
    out = []
    for name in channels:
        y = data.channels[name]
        idx = decimate_indices(data.time, y, max_points, method)
        row = {"name": name, "unit": data.units[name], "time": data.time[idx].tolist(),
               "values": _f(y[idx])}
        if distance:
            row["distance"] = data.distance[idx].tolist()
        out.append(row)
    return {"job_id": job_id, "method": method, "max_points": max_points, "n_samples": n,
            "decimated": n > max_points and method != "none", "sample_rate_hz": data.sample_rate,
            "channels": out}


def _reduce_spectrum(f: np.ndarray, values: np.ndarray, max_points: int
                     ) -> tuple[np.ndarray, np.ndarray, bool]:
    """Keep at most ``max_points`` lines: the largest of each bucket (peaks survive)."""
    if f.size <= max_points:
        return f, values, False
    idx = minmax_indices(np.max(values, axis=0), max_points)
    return f[idx], values[:, idx], True


def spectrum(svc: Services, job_id: str, channels: list[str], kind: str, fmax: float,
             dynamic: bool, segment_s: float, max_points: int) -> dict[str, Any]:
    """Amplitude spectrum (whole record) or Welch PSD of ``channels`` up to ``fmax``."""
    data = _read(svc, job_id, channels)
    fs = data.sample_rate
    x = np.vstack([data.channels[c] for c in channels])
    x, used_dynamic = _prepare(x, fs, dynamic)
    if kind == "psd":
        seg = min(segment_s, x.shape[-1] / fs)
        spec = welch_psd(x, fs, segment_s=seg)
    else:
        spec = amplitude_spectrum(x, fs, detrend=True)
    keep = spec.frequencies <= fmax + 1e-9
    f = spec.frequencies[keep]
    vals = np.atleast_2d(spec.values)[:, keep]
    rows = []
    for i, name in enumerate(channels):
        peaks = dominant_peaks((f, vals[i]), n=5, rel_prominence=0.05,
                               band_hz=(0.3, fmax), kind=spec.kind)
        rows.append({"name": name,
                     "unit": f"({data.units[name]})^2/Hz" if kind == "psd" else data.units[name],
                     "peaks": [{"frequency": p.frequency, "amplitude": _num(p.amplitude),
                                "value": _num(p.value), "prominence": _num(p.prominence)}
                               for p in peaks]})
    f_out, v_out, reduced = _reduce_spectrum(f, vals, max_points)
    for i, row in enumerate(rows):
        row["values"] = _f(v_out[i])
    return {"job_id": job_id, "kind": spec.kind, "frequencies": f_out.tolist(),
            "resolution_hz": spec.resolution_hz, "window": spec.window,
            "n_averages": spec.n_averages, "scaling": spec.scaling, "dynamic": used_dynamic,
            "decimated": reduced, "channels": rows}


MAX_SPECTROGRAM_WORK = 5_000_000
"""Most values (time slices × frequency bins) a spectrogram request may compute (about
80 MB of complex numbers); beyond it the request is refused before computing."""


def spectrogram_of(svc: Services, job_id: str, channel: str, window_s: float, overlap: float,
                   fmax: float, dynamic: bool,
                   scaling: Literal["psd", "magnitude"]) -> dict[str, Any]:
    """Short-time spectrum of one channel (at most 250,000 cells: time slices are thinned)."""
    data = _read(svc, job_id, [channel])
    fs = data.sample_rate
    window_s = min(window_s, data.time.size / fs)
    cells = spectrogram_cells(data.time.size, fs, window_s, overlap)
    if cells > MAX_SPECTROGRAM_WORK:
        raise ScenarioError.at(("query", "overlap"), (
            f"window_s = {window_s:g} s with overlap {overlap:g} computes {cells:,} values, "
            f"beyond the limit of {MAX_SPECTROGRAM_WORK:,}; use a smaller overlap or a "
            "shorter window"), "spectrogram")
    x, used_dynamic = _prepare(data.channels[channel], fs, dynamic)
    sg = spectrogram(x, fs, window_s=window_s, overlap=overlap,
                     fmax=min(fmax, fs / 2.0), scaling=scaling, unit=data.units[channel])
    values, times = sg.values, sg.times + float(data.time[0])
    step = max(1, int(np.ceil(values.size / MAX_SPECTROGRAM_CELLS)))
    if step > 1:
        values, times = values[:, ::step], times[::step]
    return {"job_id": job_id, "channel": channel, "unit": sg.unit, "times": times.tolist(),
            "frequencies": sg.frequencies.tolist(), "values": _f(values), "scaling": sg.scaling,
            "window_s": sg.window_s, "hop_s": sg.hop_s * step, "resolution_hz": sg.resolution_hz,
            "method": sg.method + (f"; every {step}th slice" if step > 1 else ""),
            "dynamic": used_dynamic}


def _direction(name: str) -> str:
    """Sperling's direction of an acceleration channel."""
    ch = Channel.parse(name)
    d = ch.direction if ch is not None and ch.quantity == "acc" else None
    if d == "z":
        return "vertical"
    if d == "y":
        return "lateral"
    raise AnalysisError(f"channels: {name!r}: the Sperling index needs a vertical (.z) or "
                        "lateral (.y) acceleration channel")


def sperling_breakdown(svc: Services, job_id: str, channels: list[str],
                       dynamic: bool) -> dict[str, Any]:
    """Sperling index per channel with its contribution per spectral peak (sine) and per
    third-octave band (spectral form, pinned defaults of :mod:`flexride.analysis.sperling`).
    """
    data = _read(svc, job_id, channels)
    fs = data.sample_rate
    rows = []
    used_dynamic = dynamic
    for name in channels:
        direction = _direction(name)
        x, used_dynamic = _prepare(data.channels[name], fs, dynamic)
        res = sperling_spectral(x, fs, direction)
        f, amp = record_sines(x, fs)
        w_i = 0.896 * ((100.0 * amp) ** 3 * frequency_correction(f, direction) / f) ** 0.1
        bands = []
        for c in _THIRD_OCTAVE_CENTRES:
            lo, hi = c * 2 ** (-1 / 6), c * 2 ** (1 / 6)
            m = (f >= lo) & (f < hi)
            w = float(np.sum(w_i[m] ** 10) ** 0.1) if np.any(m) else None
            bands.append({"f_low_hz": lo, "f_high_hz": hi, "w": w})
        try:
            filt = sperling_filter(x, fs, direction).value
        except AnalysisError:
            filt = None
        value = float(res.value)
        rows.append({"name": name, "direction": direction, "value": _num(value),
                     "grade": sperling_grade(value) if np.isfinite(value) else "unknown",
                     "filter_value": _num(filt), "frequencies": f.tolist(),
                     "line_amplitudes": _f(amp), "line_w": _f(w_i), "bands": bands,
                     "segment_values": _f(np.atleast_1d(res.segment_values)),
                     "method": res.method})
    return {"job_id": job_id, "dynamic": used_dynamic, "channels": rows}


def correlation(svc: Services, job_id: str, reference: str, channels: list[str],
                max_lag_s: float, dynamic: bool, max_points: int) -> dict[str, Any]:
    """Cross-correlation of ``reference`` with each of ``channels``."""
    if reference in channels:
        raise AnalysisError("channels: the reference channel is correlated with the others; "
                            "do not list it again")
    data = _read(svc, job_id, [reference, *channels])
    fs = data.sample_rate
    x = np.vstack([data.channels[c] for c in [reference, *channels]])
    x, used_dynamic = _prepare(x, fs, dynamic)
    res = cross_correlations(x[0], x[1:], fs, max_lag_s=max_lag_s, min_prominence=0.05)
    rows = []
    for name, r in zip(channels, res, strict=True):
        idx = decimate_indices(r.lags, r.normalised, max_points, "minmax")
        maxima = sorted(r.local_maxima, key=lambda m: -m["value"])[:5]
        rows.append({"name": name, "lag_at_max_s": _num(r.lag_at_max),
                     "lag_at_max_interpolated_s": _num(r.lag_at_max_interpolated),
                     "value_at_max": _num(r.value_at_max),
                     "normalised_at_max": _num(r.normalised_at_max),
                     "local_maxima": [{k: _num(v) for k, v in m.items()} for m in maxima],
                     "lags_s": r.lags[idx].tolist(), "normalised": _f(r.normalised[idx])})
    conv = res[0].convention if res else ""
    return {"job_id": job_id, "reference": reference, "max_lag_s": max_lag_s,
            "convention": conv, "dynamic": used_dynamic, "channels": rows}


def result_path(svc: Services, job_id: str) -> tuple[Any, str]:
    """Path of a job's HDF5 file and a download name."""
    job = finished_job(svc, job_id)
    path = svc.files.path(str(job.result_file))
    if not path.is_file():
        raise NotFound(f"the results file of job {job_id} is missing")
    safe = "".join(ch if ch.isalnum() or ch in "-_." else "_" for ch in job.name)[:60]
    return path, f"{safe or 'flexride'}-{job_id}.h5"
