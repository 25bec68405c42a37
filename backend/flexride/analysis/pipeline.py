"""The bridge from a run to its numbers: :func:`analyze` applies every analysis to a
:class:`~flexride.results.Results` and returns a :class:`~flexride.analysis.summary.Summary`
ready for JSON, the dashboard and the terminal (:mod:`~flexride.analysis.tables`).

Per car-body output point (channels ``carbody.<POINT>.acc.<x|y|z>``) and direction:

* peak statistics of the raw record and of its dynamic part (quasi-static part removed,
  :mod:`~flexride.analysis.quasistatic`), and the largest quasi-static value;
* Sperling index (y, z) of the dynamic part in the default form (spectral) and in the other
  form, each naming its form, with the GB 5599 grade;
* ISO 2631-1 evaluation (a_w, MTVV, VDV, crest factor, comfort band) with Wb and Wk (z) or
  Wd (x, y) on the raw record (the weightings' band limitation removes the quasi-static part);
* EN 12299 continuous comfort C_c(t) and, per point, the mean comfort N_MV;
* Welch PSD of the dynamic part and its dominant peaks (0.3 Hz to min(100 Hz, fs/2));
* with ``arrays=True`` also the PSD, a spectrogram and the correlation curves.

Per run: cross-correlations of a reference point (PRB by default, the paper's Fig. 26) with
every other point, vertical and lateral; running safety from the wheel–rail forces; peak
statistics of every other acceleration channel (bogie frames, wheelsets); and the statistics
of every recorded suspension force (channels ``<stage>.<element>.force.<x|y|z>`` of the stages
in :data:`~flexride.results.SUSPENSION_STAGES`, the air springs ``secondary.1L`` …): mean,
rms and peak of the dynamic part (record minus its mean) and the largest |value|, in N.

A measure that cannot be computed (record too short, sample rate too low...) is left out and
its reason recorded in ``errors``; :func:`analyze` itself raises
:class:`~flexride.errors.AnalysisError` only when the run has no usable car-body channel.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from flexride.analysis.correlation import cross_correlations
from flexride.analysis.en12299 import continuous_comfort, mean_comfort
from flexride.analysis.iso2631 import Iso2631Result, _iso_from_weighted
from flexride.analysis.quasistatic import QUASISTATIC_DEFAULTS, split_quasistatic
from flexride.analysis.safety import (
    CONVENTION,
    SAFETY_DEFAULTS,
    SAFETY_LIMITS,
    RunningSafety,
    running_safety,
)
from flexride.analysis.spectra import Spectrum, dominant_peaks, welch_psd
from flexride.analysis.sperling import (
    DEFAULT_SPERLING_FORM,
    SPERLING_DEFAULTS,
    SperlingForm,
    SperlingResult,
    sperling,
)
from flexride.analysis.statistics import PeakStats, peak_statistics
from flexride.analysis.summary import (
    ISO_WEIGHTINGS,
    CorrelationSummary,
    DirectionSummary,
    PointSummary,
    Summary,
    SuspensionForceSummary,
)
from flexride.analysis.timefreq import Spectrogram, spectrogram
from flexride.analysis.weighting import WeightingMethod, apply_weighting
from flexride.errors import AnalysisError, FlexrideError
from flexride.results import SUSPENSION_STAGES
from flexride.units import mps_to_kmh
from flexride.vehicle.topology import PAPER_POINT_NAMES

if TYPE_CHECKING:
    from flexride.results import Results

__all__ = ["analyze"]

_PSD_SEGMENT_S = 8.0
_PEAK_BAND = (0.3, 100.0)

#: One usable car-body channel of a direction: (point, channel name, record in m/s²).
_Channel = tuple[str, str, np.ndarray]


@dataclass
class _Signals:
    """Per-point records kept for the per-point and per-run measures, by direction and point
    (m/s²): the raw record, its dynamic part and its weighted records by weighting name.
    """

    raw: dict[str, dict[str, np.ndarray]] = field(
        default_factory=lambda: {"x": {}, "y": {}, "z": {}})
    dynamic: dict[str, dict[str, np.ndarray]] = field(
        default_factory=lambda: {"x": {}, "y": {}, "z": {}})
    weighted: dict[str, dict[str, dict[str, np.ndarray]]] = field(default_factory=dict)


def _point_order(names: Sequence[str]) -> list[str]:
    """Point names in table order: the paper's points in their order, then the others sorted."""
    std = [p for p in PAPER_POINT_NAMES if p in names]
    return std + sorted(p for p in names if p not in PAPER_POINT_NAMES)


def _on_floor(results: Results) -> dict[str, bool | None]:
    """Whether each recorded car-body point is on the floor (from the run's recorded points)."""
    return {p["name"]: p.get("on_floor") for p in results.recorded_points
            if p.get("body") == "carbody"}


def _err(exc: Exception) -> str:
    """The text recorded for a measure that failed: exception class and message."""
    return f"{type(exc).__name__}: {exc}"


def _settings(sperling_form: SperlingForm, filter_method: WeightingMethod, max_lag_s: float,
              reference: str | None) -> dict[str, Any]:
    """The ``settings`` block of a summary: every pinned default and standard edition.

    Parameters
    ----------
    sperling_form : {"spectral", "filter"}
        Form reported as ``sperling``.
    filter_method : {"iir", "fft"}
        Realisation of the ISO / EN weightings.
    max_lag_s : float
        Largest correlation lag (s).
    reference : str or None
        Reference point of the correlations.
    """
    other = "filter" if sperling_form == "spectral" else "spectral"
    return {
        "sperling": {"default_form": sperling_form, "alternative_form": other,
                     "spectral": {**SPERLING_DEFAULTS,
                                  "band_hz": list(SPERLING_DEFAULTS["band_hz"])},
                     "grades": "GB 5599-1985: <2.5 excellent, <2.75 good, <=3.0 qualified",
                     "input": "dynamic part (quasi-static part removed)"},
        "quasi_static": {**QUASISTATIC_DEFAULTS, "filter": "Butterworth, forward-backward"},
        "iso2631": {"weightings": {k: list(v) for k, v in ISO_WEIGHTINGS.items()},
                    "filter": filter_method, "running_rms_s": 1.0, "edition": "ISO 2631-1:1997",
                    "Wb": "ISO 2631-4:2001 / EN 12299:2009"},
        "en12299": {"edition": "EN 12299:2009", "cc_window_s": 5.0, "cc_step_s": 1.0,
                    "nmv_block_s": 5.0, "nmv_window_s": 300.0,
                    "percentile": "nearest rank (ceil(0.95 n)-th of n)",
                    "short_run": "one window over all complete 5 s blocks, flagged short_run"},
        "spectra": {"psd": f"Welch, {_PSD_SEGMENT_S:g} s Hann segments (shorter records: the "
                           "whole record), 50 % overlap, one-sided density",
                    "peaks": f"find_peaks, prominence >= 5 % of the band maximum, "
                             f"{_PEAK_BAND[0]:g}-{_PEAK_BAND[1]:g} Hz"},
        "correlation": {"reference_point": reference, "max_lag_s": max_lag_s,
                        "convention": "R_ab(k) = sum a[n] b[n+k], a = reference; "
                                      "max at lag > 0: other point lags",
                        "local_maxima": "prominence >= 0.05 (normalised), 5 largest"},
        "suspension": {"unit": "N", "record": "the whole record analysed (mean over each "
                                              "output interval of the kernel's forces)",
                       "force": "on the car body, in its track frame; z positive up (static: "
                                "the weight share)",
                       "dynamic": "record minus its mean"},
        "safety": {**SAFETY_DEFAULTS, "limits": {**SAFETY_LIMITS,
                                                  "wheelset_lateral_force_kN": "10 + 2Q0/3"},
                   "editions": "GB 5599-1985 (limits of Y/Q and ΔQ/Q, its Q/P and ΔP/P), "
                               "EN 14363:2016 / UIC 518 (ΣY, processing)",
                   "convention": CONVENTION},
    }


def analyze(
    results: Results,
    *,
    sperling_form: SperlingForm = DEFAULT_SPERLING_FORM,
    reference_point: str = "PRB",
    arrays: bool = False,
    correlation_max_lag_s: float = 3.0,
    filter_method: WeightingMethod = "iir",
) -> Summary:
    """Analyse a run: comfort, spectra, correlations and running safety per output point.

    Parameters
    ----------
    results : Results
        The run (car-body channels ``carbody.<POINT>.acc.<x|y|z>`` in m/s²).
    sperling_form : {"spectral", "filter"}
        Form reported as ``sperling``; the other goes to ``sperling_alternative``.
    reference_point : str
        Point correlated with all others (falls back to the first point if absent).
    arrays : bool
        Also keep arrays for the dashboard (PSD, spectrogram, C_c(t) already always,
        correlation curves, processed safety signals).
    correlation_max_lag_s : float
        Largest correlation lag (s).
    filter_method : {"iir", "fft"}
        Realisation of the ISO / EN weightings.

    Returns
    -------
    Summary

    Raises
    ------
    AnalysisError
        No car-body acceleration channel, or an unusable time axis / sample rate.
    """
    if sperling_form not in ("spectral", "filter"):
        raise AnalysisError(f"Sperling form must be 'spectral' or 'filter', got {sperling_form!r}")
    fs, time = _time_axis(results)
    t0 = float(time[0])
    notes: list[str] = []
    groups, other_acc = _acceleration_channels(results)
    point_names = _point_order(sorted({p for g in groups.values() for p, _ in g}))
    floor = _on_floor(results)
    points = {p: PointSummary(name=p, on_floor=floor.get(p)) for p in point_names}
    signals = _Signals()
    for d in ("z", "y", "x"):
        good = _usable_channels(results, groups.get(d, []), point_names, time.size, notes)
        if good:
            _analyze_direction(d, good, fs, t0, sperling_form, filter_method, arrays, points,
                               signals)
    if not any(p.directions for p in points.values()):
        raise AnalysisError("no usable car-body acceleration channel: " + "; ".join(notes))
    points = {k: v for k, v in points.items() if v.directions}
    _add_mean_comfort(points, signals, fs, filter_method)
    names = list(points)
    ref = reference_point if reference_point in names else (names[0] if names else None)
    correlations = _correlations(ref, names, signals.dynamic, fs, correlation_max_lag_s, arrays,
                                 notes)
    safety = _running_safety(results, arrays, notes)
    other_channels = _other_channel_peaks(results, other_acc, fs, t0, notes)
    suspension = _suspension_forces(results, time.size, notes)
    return Summary(run=_run_block(results, time, fs, t0),
                   settings=_settings(sperling_form, filter_method, correlation_max_lag_s, ref),
                   points=points, correlations=correlations, safety=safety,
                   other_channels=other_channels, suspension=suspension,
                   notes=[*results.meta.get("notes", []), *notes])  # the run's own first


def _time_axis(results: Results) -> tuple[float, np.ndarray]:
    """Sample rate (Hz) and time axis (s) of a run, checked.

    Raises
    ------
    AnalysisError
        If the sample rate cannot be determined or is not finite and positive, or the run has
        no samples.
    """
    try:
        fs = float(results.sample_rate)
    except FlexrideError as exc:
        raise AnalysisError(f"cannot determine the sample rate: {exc}") from None
    if not (math.isfinite(fs) and fs > 0.0):
        raise AnalysisError(f"sample rate must be finite and positive, got {fs!r}")
    time = np.asarray(results.time, dtype=np.float64)
    if time.size == 0:
        raise AnalysisError("the run has no samples")
    return fs, time


def _acceleration_channels(results: Results) -> tuple[dict[str, list[tuple[str, str]]],
                                                       list[str]]:
    """The run's acceleration channels in x, y, z: the car body's as (point, channel) pairs by
    direction, and the names of the others (frames, wheelsets).

    Raises
    ------
    AnalysisError
        If the run has no car-body acceleration channel.
    """
    groups: dict[str, list[tuple[str, str]]] = {}
    other_acc: list[str] = []
    for ch in results.parsed():
        if ch.quantity != "acc" or ch.direction not in ("x", "y", "z"):
            continue
        if ch.body == "carbody":
            groups.setdefault(ch.direction, []).append((ch.point, ch.name))
        else:
            other_acc.append(ch.name)
    if not groups:
        raise AnalysisError(
            "the run has no car-body acceleration channel (carbody.<POINT>.acc.<x|y|z>)")
    return groups, other_acc


def _usable_channels(results: Results, members: list[tuple[str, str]], point_names: list[str],
                     n_samples: int, notes: list[str]) -> list[_Channel]:
    """The car-body channels of one direction in point order, with their records (m/s²).

    A channel whose length differs from the time axis (``n_samples``) or that holds NaN or
    infinite values is skipped with a note.
    """
    good = []
    for p, ch in sorted(members, key=lambda pn: point_names.index(pn[0])):
        arr = np.asarray(results.channels[ch], dtype=np.float64)
        if arr.ndim != 1 or arr.size != n_samples:
            notes.append(f"{ch}: length {arr.shape} differs from the time axis; skipped")
            continue
        if not np.all(np.isfinite(arr)):
            notes.append(f"{ch}: contains NaN or infinite values; skipped")
            continue
        good.append((p, ch, arr))
    return good


def _add_mean_comfort(points: dict[str, PointSummary], signals: _Signals, fs: float,
                      filter_method: WeightingMethod) -> None:
    """EN 12299 mean comfort N_MV of each point from its raw records (m/s²) and the comfort
    weighting already applied to them; a note on points off the floor.
    """
    weighted = signals.weighted
    for p, ps in points.items():
        dirs = {d: signals.raw[d][p] for d in "xyz" if p in signals.raw[d]}
        w = {d: weighted[d][p][ISO_WEIGHTINGS[d][0]] for d in dirs
             if p in weighted.get(d, {}) and ISO_WEIGHTINGS[d][0] in weighted[d][p]}
        try:
            ps.mean_comfort = mean_comfort(fs, x=dirs.get("x"), y=dirs.get("y"), z=dirs.get("z"),
                                           weighted=w, method=filter_method)
        except FlexrideError as exc:
            ps.errors["mean_comfort"] = _err(exc)
        if ps.on_floor is False:
            ps.notes.append("not a floor point: EN 12299 comfort is defined on the floor")


def _correlations(ref: str | None, names: list[str], dynamic: dict[str, dict[str, np.ndarray]],
                  fs: float, max_lag_s: float, arrays: bool,
                  notes: list[str]) -> list[CorrelationSummary]:
    """Cross-correlations of the dynamic part of point ``ref`` with every other point, z then y.

    Each keeps its five largest local maxima; with ``arrays`` also the curve (lags in s and the
    normalised correlation, at most about 2000 points). A direction that fails is noted.
    """
    correlations: list[CorrelationSummary] = []
    if ref is None:
        return correlations
    for d in ("z", "y"):
        if ref not in dynamic[d]:
            continue
        others = [p for p in names if p != ref and p in dynamic[d]]
        if not others:
            continue
        try:
            res = cross_correlations(
                dynamic[d][ref], np.vstack([dynamic[d][o] for o in others]), fs,
                max_lag_s=max_lag_s, min_prominence=0.05)
        except FlexrideError as exc:
            notes.append(f"cross-correlation ({d}) failed: {_err(exc)}")
            continue
        for o, r in zip(others, res, strict=True):
            r.local_maxima = sorted(r.local_maxima, key=lambda m: -m["value"])[:5]
            curve = None
            if arrays:
                step = max(1, r.lags.size // 2000)
                curve = {"lags_s": r.lags[::step], "normalised": r.normalised[::step]}
            correlations.append(CorrelationSummary(reference=ref, other=o, direction=d,
                                                   result=r, curve=curve))
    return correlations


def _running_safety(results: Results, arrays: bool, notes: list[str]) -> RunningSafety | None:
    """Running-safety indices of the run, or None (with a note) when they cannot be evaluated
    (e.g. no wheel–rail forces).
    """
    try:
        return running_safety(results, keep_series=arrays)
    except FlexrideError as exc:
        notes.append(f"running safety not evaluated: {_err(exc)}")
        return None


def _other_channel_peaks(results: Results, channels: list[str], fs: float, t0: float,
                         notes: list[str]) -> dict[str, PeakStats]:
    """Peak statistics of the acceleration channels off the car body (in their unit, times
    from ``t0`` s), by name; a channel that fails is noted.
    """
    other_channels: dict[str, PeakStats] = {}
    for ch in sorted(channels):
        try:
            other_channels[ch] = peak_statistics(results.channels[ch], fs, t0=t0,
                                                 unit=results.units.get(ch, "m/s^2"))
        except FlexrideError as exc:
            notes.append(f"{ch}: {_err(exc)}")
    return other_channels


def _suspension_forces(results: Results, n_samples: int, notes: list[str]
                       ) -> dict[str, dict[str, SuspensionForceSummary]]:
    """Statistics (N) of the recorded suspension forces over the whole record handed to
    :func:`analyze` (the evaluated window), by element (``<stage>.<element>``, e.g.
    ``secondary.1L``) and direction; a channel of the wrong length or with NaN or infinite
    values is skipped with a note.
    """
    out: dict[str, dict[str, SuspensionForceSummary]] = {}
    for ch in results.parsed():
        if ch.body not in SUSPENSION_STAGES or ch.quantity != "force":
            continue
        f = np.asarray(results.channels[ch.name], dtype=np.float64)
        if f.ndim != 1 or f.size != n_samples or f.size == 0:
            notes.append(f"{ch.name}: length {f.shape} differs from the time axis; skipped")
            continue
        if not np.all(np.isfinite(f)):
            notes.append(f"{ch.name}: contains NaN or infinite values; skipped")
            continue
        out.setdefault(f"{ch.body}.{ch.point}", {})[ch.direction] = SuspensionForceSummary.of(f)
    return out


def _run_block(results: Results, time: np.ndarray, fs: float, t0: float) -> dict[str, Any]:
    """The ``run`` block of a summary: scenario name, duration (s), sample rate (Hz), number of
    samples, start time (s) and running speed (m/s, km/h; None if unknown).
    """
    speed = results.running_speed()
    scen_name = results.scenario.get("name") if isinstance(results.scenario, dict) else None
    return {"scenario": scen_name, "duration_s": time.size / fs, "sample_rate_hz": fs,
            "n_samples": int(time.size), "t0_s": t0,
            "speed_mps": float(speed) if speed is not None else None,
            "speed_kmh": mps_to_kmh(speed) if speed is not None else None}


def _analyze_direction(
    d: str,
    good: list[_Channel],
    fs: float,
    t0: float,
    sperling_form: SperlingForm,
    filter_method: WeightingMethod,
    arrays: bool,
    points: dict[str, PointSummary],
    signals: _Signals,
) -> None:
    """All per-channel measures of one direction, vectorised over the channels.

    Parameters
    ----------
    d : {"x", "y", "z"}
        Direction.
    good : list of (point, channel, record)
        The direction's usable channels (records in m/s², on the run's time axis).
    fs : float
        Sample rate (Hz).
    t0 : float
        Time of the first sample (s).
    sperling_form, filter_method, arrays :
        As for :func:`analyze`.
    points : dict of str to PointSummary
        Receives each point's :class:`DirectionSummary`.
    signals : _Signals
        Receives the raw, dynamic and weighted records of each point.
    """
    x = np.vstack([g[2] for g in good])
    raw_peaks = peak_statistics(x, fs, t0=t0, unit="m/s^2")
    summaries = [DirectionSummary(channel=ch, direction=d, peaks=_row(raw_peaks, i))
                 for i, (_, ch, _) in enumerate(good)]
    dyn = _split_quasi_static(x, fs, t0, summaries)
    if d in ("y", "z"):
        _add_sperling(dyn, fs, d, sperling_form, summaries)
    signals.weighted[d] = _add_iso2631(x, fs, d, filter_method, good, summaries)
    _add_continuous_comfort(x, fs, t0, d, filter_method, good, signals.weighted[d], summaries)
    _add_psd(dyn, fs, arrays, summaries)
    if arrays:
        _add_spectrograms(dyn, fs, t0, summaries)
    for i, (p, _, _) in enumerate(good):
        points[p].directions[d] = summaries[i]
        signals.dynamic[d][p] = dyn[i]
        signals.raw[d][p] = x[i]


def _split_quasi_static(x: np.ndarray, fs: float, t0: float,
                        summaries: list[DirectionSummary]) -> np.ndarray:
    """The dynamic part of the records ``x`` (channels × samples, m/s²), with the peak
    statistics of the dynamic part and the largest |quasi-static part| (m/s²) of each channel.

    When the split fails the error is recorded and the raw records are returned.
    """
    dyn = x
    try:
        split = split_quasistatic(x, fs)
        dyn = split.dynamic
        qs_max = np.max(np.abs(split.quasi_static), axis=-1)
        dpk = peak_statistics(dyn, fs, t0=t0, unit="m/s^2")
        for i, s in enumerate(summaries):
            s.quasi_static_max_abs = float(qs_max[i])
            s.dynamic_peaks = _row(dpk, i)
    except FlexrideError as exc:
        for s in summaries:
            s.errors["quasi_static"] = _err(exc) + " (raw record used)"
    return dyn


def _add_sperling(dyn: np.ndarray, fs: float, d: str, sperling_form: SperlingForm,
                  summaries: list[DirectionSummary]) -> None:
    """Sperling index of the dynamic parts ``dyn`` (m/s²; direction ``d`` = y or z) in the
    default form (``sperling``) and in the other form (``sperling_alternative``).
    """
    direction = "vertical" if d == "z" else "lateral"
    alternative: SperlingForm = "filter" if sperling_form == "spectral" else "spectral"
    forms: tuple[tuple[str, SperlingForm], ...] = (("sperling", sperling_form),
                                                   ("sperling_alternative", alternative))
    for attr, form in forms:
        try:
            res = sperling(dyn, fs, direction, form=form)
            for i, s in enumerate(summaries):
                setattr(s, attr, _sperling_row(res, i))
        except FlexrideError as exc:
            for s in summaries:
                s.errors[attr] = _err(exc)


def _add_iso2631(x: np.ndarray, fs: float, d: str, filter_method: WeightingMethod,
                 good: list[_Channel],
                 summaries: list[DirectionSummary]) -> dict[str, dict[str, np.ndarray]]:
    """ISO 2631-1 evaluation of the raw records ``x`` (m/s²) with each weighting of direction
    ``d`` (:data:`~flexride.analysis.summary.ISO_WEIGHTINGS`).

    Returns
    -------
    dict
        The weighted records (m/s²) by point and weighting name, for C_c and N_MV.
    """
    n = x.shape[1]
    weighted: dict[str, dict[str, np.ndarray]] = {p: {} for p, _, _ in good}
    for wname in ISO_WEIGHTINGS[d]:
        try:
            aw = apply_weighting(x, fs, wname, method=filter_method)
        except FlexrideError as exc:
            for s in summaries:
                s.errors[f"iso2631_{wname}"] = _err(exc)
            continue
        for i, (p, _, _) in enumerate(good):
            weighted[p][wname] = aw[i]
            try:
                summaries[i].iso2631[wname] = _iso2631_of(x[i], aw[i], n, fs, wname,
                                                          filter_method)
            except FlexrideError as exc:
                summaries[i].errors[f"iso2631_{wname}"] = _err(exc)
    return weighted


def _iso2631_of(x: np.ndarray, aw: np.ndarray, n: int, fs: float, wname: str,
                filter_method: WeightingMethod) -> Iso2631Result:
    """ISO 2631-1 result of one raw record ``x`` and its weighted record ``aw`` (m/s², ``n``
    samples at ``fs`` Hz) with a 1 s running rms.

    Raises
    ------
    AnalysisError
        If the record is shorter than 1 s.
    """
    if n < round(fs):
        raise AnalysisError(f"record of {n / fs:.3g} s is shorter than the 1 s "
                            "running rms of ISO 2631-1")
    return _iso_from_weighted(x, aw, fs, wname, 1.0, filter_method)


def _add_continuous_comfort(x: np.ndarray, fs: float, t0: float, d: str,
                            filter_method: WeightingMethod, good: list[_Channel],
                            weighted: dict[str, dict[str, np.ndarray]],
                            summaries: list[DirectionSummary]) -> None:
    """EN 12299 continuous comfort C_c(t) of each record (m/s², times from ``t0`` s), from its
    comfort-weighted record; records without one are left out.
    """
    cc_w = ISO_WEIGHTINGS[d][0]
    for i, (p, _, _) in enumerate(good):
        if cc_w not in weighted[p]:
            continue
        try:
            cc = continuous_comfort(x[i], fs, d, method=filter_method, weighted=weighted[p][cc_w])
            cc.times = cc.times + t0
            cc.time_of_maximum += t0
            summaries[i].continuous_comfort = cc
        except FlexrideError as exc:
            summaries[i].errors["continuous_comfort"] = _err(exc)


def _add_psd(dyn: np.ndarray, fs: float, arrays: bool,
             summaries: list[DirectionSummary]) -> None:
    """Welch PSD ((m/s²)²/Hz) of the dynamic parts and its dominant peaks between 0.3 Hz and
    min(100 Hz, fs/2); with ``arrays`` the PSD up to that frequency too.
    """
    n = dyn.shape[1]
    seg = min(_PSD_SEGMENT_S, n / fs)
    hi = min(_PEAK_BAND[1], fs / 2.0)
    try:
        psd = welch_psd(dyn, fs, segment_s=seg)
        keep = psd.frequencies <= hi + 1e-9
        for i, s in enumerate(summaries):
            s.dominant_peaks = dominant_peaks((psd.frequencies, psd.values[i]), n=5,
                                              rel_prominence=0.05, band_hz=(_PEAK_BAND[0], hi),
                                              kind="psd")
            if arrays:
                s.psd = Spectrum(frequencies=psd.frequencies[keep], values=psd.values[i, keep],
                                 kind=psd.kind, unit=psd.unit, resolution_hz=psd.resolution_hz,
                                 window=psd.window, n_averages=psd.n_averages,
                                 scaling=psd.scaling)
    except FlexrideError as exc:
        for s in summaries:
            s.errors["psd"] = _err(exc)


def _add_spectrograms(dyn: np.ndarray, fs: float, t0: float,
                      summaries: list[DirectionSummary]) -> None:
    """Spectrogram of each dynamic part (2 s windows or the whole record, up to
    min(50 Hz, fs/2); times from ``t0`` s).
    """
    n = dyn.shape[1]
    try:
        sg = spectrogram(dyn, fs, window_s=min(2.0, n / fs), fmax=min(50.0, fs / 2.0))
        for i, s in enumerate(summaries):
            s.spectrogram = Spectrogram(times=sg.times + t0, frequencies=sg.frequencies,
                                        values=sg.values[i], scaling=sg.scaling,
                                        unit=sg.unit, window_s=sg.window_s, hop_s=sg.hop_s,
                                        resolution_hz=sg.resolution_hz, window=sg.window,
                                        method=sg.method)
    except FlexrideError as exc:
        for s in summaries:
            s.errors["spectrogram"] = _err(exc)


def _row(ps: PeakStats, i: int) -> PeakStats:
    """Row ``i`` of a vectorised :class:`PeakStats`."""
    def pick(v: Any) -> float:
        return float(np.asarray(v).reshape(-1)[i]) if np.ndim(v) else float(v)
    return PeakStats(max_abs=pick(ps.max_abs), time_of_max_abs=pick(ps.time_of_max_abs),
                     max=pick(ps.max), min=pick(ps.min), mean=pick(ps.mean), rms=pick(ps.rms),
                     std=pick(ps.std), peak_to_peak=pick(ps.peak_to_peak),
                     p99_85_abs=pick(ps.p99_85_abs), n=ps.n, unit=ps.unit)


def _sperling_row(res: SperlingResult, i: int) -> SperlingResult:
    """Row ``i`` of a vectorised :class:`SperlingResult`."""
    value = float(np.asarray(res.value).reshape(-1)[i])
    seg = res.segment_values[i] if res.segment_values.ndim == 2 else res.segment_values
    aw = None if res.weighted_rms is None else float(np.asarray(res.weighted_rms).reshape(-1)[i])
    grade = res.grade[i] if isinstance(res.grade, list) else res.grade
    return SperlingResult(value=value, direction=res.direction, form=res.form, grade=grade,
                          method=res.method, parameters=dict(res.parameters),
                          segment_values=np.asarray(seg), weighted_rms=aw,
                          standard=res.standard)
