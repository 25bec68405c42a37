"""The bridge from a run to its numbers: :func:`analyze` applies every analysis to a
:class:`~flexride.results.Results` and returns a :class:`Summary` ready for JSON, the dashboard
and the terminal (:func:`summary_table`, :func:`safety_table`).

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
statistics of every other acceleration channel (bogie frames, wheelsets).

A measure that cannot be computed (record too short, sample rate too low...) is left out and
its reason recorded in ``errors``; :func:`analyze` itself raises
:class:`~flexride.errors.AnalysisError` only when the run has no usable car-body channel.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from flexride.analysis._common import jsonable
from flexride.analysis.correlation import CrossCorrelation, cross_correlations
from flexride.analysis.en12299 import (
    ContinuousComfort,
    MeanComfort,
    continuous_comfort,
    mean_comfort,
)
from flexride.analysis.iso2631 import Iso2631Result, _iso_from_weighted
from flexride.analysis.quasistatic import QUASISTATIC_DEFAULTS, split_quasistatic
from flexride.analysis.safety import SAFETY_DEFAULTS, SAFETY_LIMITS, RunningSafety, running_safety
from flexride.analysis.spectra import SpectralPeak, Spectrum, dominant_peaks, welch_psd
from flexride.analysis.sperling import (
    DEFAULT_SPERLING_FORM,
    SPERLING_DEFAULTS,
    SperlingForm,
    SperlingResult,
    sperling,
)
from flexride.analysis.statistics import LinearFit, PeakStats, peak_statistics, regress_on_speed
from flexride.analysis.timefreq import Spectrogram, spectrogram
from flexride.analysis.weighting import WeightingMethod, apply_weighting
from flexride.errors import AnalysisError, FlexrideError
from flexride.units import mps_to_kmh
from flexride.vehicle.topology import PAPER_POINT_NAMES

if TYPE_CHECKING:
    from rich.console import JustifyMethod
    from rich.table import Table

    from flexride.results import Results

__all__ = [
    "CorrelationSummary",
    "DirectionSummary",
    "PointSummary",
    "Summary",
    "analyze",
    "regress_summaries",
    "safety_table",
    "summary_table",
]

_ISO_WEIGHTINGS = {"z": ("Wb", "Wk"), "y": ("Wd",), "x": ("Wd",)}
_PSD_SEGMENT_S = 8.0
_PEAK_BAND = (0.3, 100.0)


@dataclass
class DirectionSummary:
    """Everything computed for one car-body channel.

    Attributes
    ----------
    channel : str
        Channel name, e.g. ``carbody.PR.acc.z``.
    direction : str
        ``"x"``, ``"y"`` or ``"z"``.
    peaks : PeakStats
        Statistics of the raw record (m/s²).
    dynamic_peaks : PeakStats or None
        Statistics of the dynamic part (quasi-static part removed).
    quasi_static_max_abs : float or None
        Largest |quasi-static part| (m/s²).
    sperling : SperlingResult or None
        Sperling index in the default form (y, z only).
    sperling_alternative : SperlingResult or None
        Sperling index in the other form.
    iso2631 : dict of str to Iso2631Result
        ISO 2631-1 evaluation per weighting (z: Wb, Wk; x, y: Wd).
    continuous_comfort : ContinuousComfort or None
        EN 12299 C_c(t) (Wb for z, Wd for x, y).
    dominant_peaks : list of SpectralPeak
        Dominant peaks of the Welch PSD of the dynamic part ((m/s²)²/Hz).
    psd, spectrogram : optional
        Arrays for the dashboard (``analyze(arrays=True)``).
    errors : dict of str to str
        Measures that could not be computed and why.
    """

    channel: str
    direction: str
    peaks: PeakStats
    dynamic_peaks: PeakStats | None = None
    quasi_static_max_abs: float | None = None
    sperling: SperlingResult | None = None
    sperling_alternative: SperlingResult | None = None
    iso2631: dict[str, Iso2631Result] = field(default_factory=dict)
    continuous_comfort: ContinuousComfort | None = None
    dominant_peaks: list[SpectralPeak] = field(default_factory=list)
    psd: Spectrum | None = None
    spectrogram: Spectrogram | None = None
    errors: dict[str, str] = field(default_factory=dict)


@dataclass
class PointSummary:
    """One car-body output point: its directions and its EN 12299 mean comfort.

    Attributes
    ----------
    name : str
        Point name (``PR``, ``PFB``...).
    on_floor : bool or None
        Whether the point is on the floor (EN 12299 is defined there); None if unknown.
    directions : dict of str to DirectionSummary
        By direction ``"z"``, ``"y"``, ``"x"``.
    mean_comfort : MeanComfort or None
        EN 12299 N_MV from the point's directions.
    """

    name: str
    on_floor: bool | None
    directions: dict[str, DirectionSummary] = field(default_factory=dict)
    mean_comfort: MeanComfort | None = None
    notes: list[str] = field(default_factory=list)
    errors: dict[str, str] = field(default_factory=dict)


@dataclass
class CorrelationSummary:
    """Cross-correlation of a reference point with another point in one direction.

    ``result`` follows :mod:`~flexride.analysis.correlation` (a = reference, b = other;
    a maximum at τ > 0 means the other point lags the reference). ``curve`` holds lags (s) and
    the normalised correlation when arrays are requested.
    """

    reference: str
    other: str
    direction: str
    result: CrossCorrelation
    curve: dict[str, np.ndarray] | None = None


@dataclass
class Summary:
    """Analysis of one run.

    Attributes
    ----------
    run : dict
        Duration (s), sample rate (Hz), samples, speed (m/s, km/h), scenario name.
    settings : dict
        Every pinned default and the standard editions followed.
    points : dict of str to PointSummary
        Car-body output points in table order.
    correlations : list of CorrelationSummary
        Reference point against every other point, z and y.
    safety : RunningSafety or None
        Running-safety indices, if the run recorded wheel–rail forces.
    other_channels : dict of str to PeakStats
        Peak statistics of non-car-body acceleration channels.
    notes : list of str
        Remarks about the analysis (skipped channels...).
    """

    run: dict[str, Any]
    settings: dict[str, Any]
    points: dict[str, PointSummary]
    correlations: list[CorrelationSummary] = field(default_factory=list)
    safety: RunningSafety | None = None
    other_channels: dict[str, PeakStats] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-compatible dictionary (NaN and inf become None, arrays become lists)."""
        return jsonable(self)

    def to_json(self, **kwargs: Any) -> str:
        """JSON text of :meth:`to_dict` (keyword arguments go to :func:`json.dumps`)."""
        kwargs.setdefault("ensure_ascii", False)
        return json.dumps(self.to_dict(), **kwargs)

    def value(self, point: str, direction: str, quantity: str) -> float:
        """One scalar of the summary, for tables and regressions.

        Parameters
        ----------
        point : str
            Point name.
        direction : str
            ``"z"``, ``"y"`` or ``"x"``.
        quantity : str
            ``"peak"`` (largest |a| of the raw record, m/s²), ``"dynamic_peak"``,
            ``"sperling"`` (default form), ``"sperling_alternative"``, ``"a_w"`` (first ISO
            weighting: Wb for z, Wd for y), ``"a_wk"`` (Wk, z only), ``"cc_max"``, ``"rms"``
            or ``"n_mv"`` (direction ignored).
        """
        p = self.points.get(point)
        if p is None:
            raise AnalysisError(f"no point {point!r} in the summary; points: {list(self.points)}")
        if quantity == "n_mv":
            if p.mean_comfort is None:
                return math.nan
            return p.mean_comfort.value
        d = p.directions.get(direction)
        if d is None:
            raise AnalysisError(f"point {point} has no direction {direction!r}")
        if quantity == "peak":
            return float(d.peaks.max_abs)
        if quantity == "rms":
            return float(d.peaks.rms)
        if quantity == "dynamic_peak":
            return float(d.dynamic_peaks.max_abs) if d.dynamic_peaks else math.nan
        if quantity in ("sperling", "sperling_alternative"):
            s = getattr(d, quantity)
            return float(s.value) if s is not None else math.nan
        if quantity == "a_w":
            first = _ISO_WEIGHTINGS[d.direction][0]
            return d.iso2631[first].a_w if first in d.iso2631 else math.nan
        if quantity == "a_wk":
            return d.iso2631["Wk"].a_w if "Wk" in d.iso2631 else math.nan
        if quantity == "cc_max":
            return d.continuous_comfort.maximum if d.continuous_comfort else math.nan
        raise AnalysisError(f"unknown summary quantity {quantity!r}")


def _point_order(names: Sequence[str]) -> list[str]:
    std = [p for p in PAPER_POINT_NAMES if p in names]
    return std + sorted(p for p in names if p not in PAPER_POINT_NAMES)


def _on_floor(results: Results) -> dict[str, bool | None]:
    """Whether each recorded car-body point is on the floor (from the run's recorded points)."""
    return {p["name"]: p.get("on_floor") for p in results.recorded_points
            if p.get("body") == "carbody"}


def _err(exc: Exception) -> str:
    return f"{type(exc).__name__}: {exc}"


def _settings(sperling_form: SperlingForm, filter_method: WeightingMethod, max_lag_s: float,
              reference: str | None) -> dict[str, Any]:
    other = "filter" if sperling_form == "spectral" else "spectral"
    return {
        "sperling": {"default_form": sperling_form, "alternative_form": other,
                     "spectral": {**SPERLING_DEFAULTS,
                                  "band_hz": list(SPERLING_DEFAULTS["band_hz"])},
                     "grades": "GB 5599-1985: <2.5 excellent, <2.75 good, <=3.0 qualified",
                     "input": "dynamic part (quasi-static part removed)"},
        "quasi_static": {**QUASISTATIC_DEFAULTS, "filter": "Butterworth, forward-backward"},
        "iso2631": {"weightings": {k: list(v) for k, v in _ISO_WEIGHTINGS.items()},
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
        "safety": {**SAFETY_DEFAULTS, "limits": {**SAFETY_LIMITS,
                                                  "wheelset_lateral_force_kN": "10 + P0/3"},
                   "editions": "GB 5599-1985 (Q/P, dP/P), EN 14363:2016 / UIC 518 (sum Y, "
                               "processing)"},
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
    try:
        fs = float(results.sample_rate)
    except FlexrideError as exc:
        raise AnalysisError(f"cannot determine the sample rate: {exc}") from None
    if not (math.isfinite(fs) and fs > 0.0):
        raise AnalysisError(f"sample rate must be finite and positive, got {fs!r}")
    time = np.asarray(results.time, dtype=np.float64)
    if time.size == 0:
        raise AnalysisError("the run has no samples")
    t0 = float(time[0])
    notes: list[str] = []

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

    point_names = _point_order(sorted({p for g in groups.values() for p, _ in g}))
    floor = _on_floor(results)
    points = {p: PointSummary(name=p, on_floor=floor.get(p)) for p in point_names}
    dynamic: dict[str, dict[str, np.ndarray]] = {"x": {}, "y": {}, "z": {}}
    weighted: dict[str, dict[str, dict[str, np.ndarray]]] = {}
    raw_sig: dict[str, dict[str, np.ndarray]] = {"x": {}, "y": {}, "z": {}}

    for d in ("z", "y", "x"):
        members = sorted(groups.get(d, []), key=lambda pn: point_names.index(pn[0]))
        good = []
        for p, ch in members:
            arr = np.asarray(results.channels[ch], dtype=np.float64)
            if arr.ndim != 1 or arr.size != time.size:
                notes.append(f"{ch}: length {arr.shape} differs from the time axis; skipped")
                continue
            if not np.all(np.isfinite(arr)):
                notes.append(f"{ch}: contains NaN or infinite values; skipped")
                continue
            good.append((p, ch, arr))
        if not good:
            continue
        x = np.vstack([g[2] for g in good])
        _analyze_direction(d, good, x, fs, t0, sperling_form, filter_method, arrays, points,
                           dynamic, weighted, raw_sig)

    if not any(p.directions for p in points.values()):
        raise AnalysisError("no usable car-body acceleration channel: " + "; ".join(notes))
    points = {k: v for k, v in points.items() if v.directions}

    for p, ps in points.items():
        dirs = {d: raw_sig[d][p] for d in "xyz" if p in raw_sig[d]}
        w = {d: weighted[d][p][_ISO_WEIGHTINGS[d][0]] for d in dirs
             if p in weighted.get(d, {}) and _ISO_WEIGHTINGS[d][0] in weighted[d][p]}
        try:
            ps.mean_comfort = mean_comfort(fs, x=dirs.get("x"), y=dirs.get("y"), z=dirs.get("z"),
                                           weighted=w, method=filter_method)
        except FlexrideError as exc:
            ps.errors["mean_comfort"] = _err(exc)
        if ps.on_floor is False:
            ps.notes.append("not a floor point: EN 12299 comfort is defined on the floor")

    names = list(points)
    ref = reference_point if reference_point in names else (names[0] if names else None)
    correlations: list[CorrelationSummary] = []
    if ref is not None:
        for d in ("z", "y"):
            if ref not in dynamic[d]:
                continue
            others = [p for p in names if p != ref and p in dynamic[d]]
            if not others:
                continue
            try:
                res = cross_correlations(
                    dynamic[d][ref], np.vstack([dynamic[d][o] for o in others]), fs,
                    max_lag_s=correlation_max_lag_s, min_prominence=0.05)
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

    safety = None
    try:
        safety = running_safety(results, keep_series=arrays)
    except FlexrideError as exc:
        notes.append(f"running safety not evaluated: {_err(exc)}")

    other_channels: dict[str, PeakStats] = {}
    for ch in sorted(other_acc):
        try:
            other_channels[ch] = peak_statistics(results.channels[ch], fs, t0=t0,
                                                 unit=results.units.get(ch, "m/s^2"))
        except FlexrideError as exc:
            notes.append(f"{ch}: {_err(exc)}")

    speed = results.running_speed()
    scen_name = results.scenario.get("name") if isinstance(results.scenario, dict) else None
    run = {"scenario": scen_name, "duration_s": time.size / fs, "sample_rate_hz": fs,
           "n_samples": int(time.size), "t0_s": t0,
           "speed_mps": float(speed) if speed is not None else None,
           "speed_kmh": mps_to_kmh(speed) if speed is not None else None}
    return Summary(run=run, settings=_settings(sperling_form, filter_method,
                                               correlation_max_lag_s, ref),
                   points=points, correlations=correlations, safety=safety,
                   other_channels=other_channels, notes=notes)


def _analyze_direction(
    d: str,
    good: list[tuple[str, str, np.ndarray]],
    x: np.ndarray,
    fs: float,
    t0: float,
    sperling_form: SperlingForm,
    filter_method: WeightingMethod,
    arrays: bool,
    points: dict[str, PointSummary],
    dynamic: dict[str, dict[str, np.ndarray]],
    weighted: dict[str, dict[str, dict[str, np.ndarray]]],
    raw_sig: dict[str, dict[str, np.ndarray]],
) -> None:
    """All per-channel measures of one direction, vectorised over the channels."""
    n = x.shape[1]
    raw_peaks = peak_statistics(x, fs, t0=t0, unit="m/s^2")
    summaries = [DirectionSummary(channel=ch, direction=d, peaks=_row(raw_peaks, i))
                 for i, (_, ch, _) in enumerate(good)]
    # quasi-static split
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
    # Sperling, default and alternative form
    if d in ("y", "z"):
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
    # ISO 2631 and EN 12299 on the raw record
    weighted[d] = {p: {} for p, _, _ in good}
    for wname in _ISO_WEIGHTINGS[d]:
        try:
            aw = apply_weighting(x, fs, wname, method=filter_method)
        except FlexrideError as exc:
            for s in summaries:
                s.errors[f"iso2631_{wname}"] = _err(exc)
            continue
        for i, (p, _, _) in enumerate(good):
            weighted[d][p][wname] = aw[i]
            try:
                if n < round(fs):
                    raise AnalysisError(f"record of {n / fs:.3g} s is shorter than the 1 s "
                                        "running rms of ISO 2631-1")
                summaries[i].iso2631[wname] = _iso_from_weighted(x[i], aw[i], fs, wname, 1.0,
                                                                 filter_method)
            except FlexrideError as exc:
                summaries[i].errors[f"iso2631_{wname}"] = _err(exc)
    cc_w = _ISO_WEIGHTINGS[d][0]
    for i, (p, _, _) in enumerate(good):
        if cc_w not in weighted[d][p]:
            continue
        try:
            cc = continuous_comfort(x[i], fs, d, method=filter_method,
                                    weighted=weighted[d][p][cc_w])
            cc.times = cc.times + t0
            cc.time_of_maximum += t0
            summaries[i].continuous_comfort = cc
        except FlexrideError as exc:
            summaries[i].errors["continuous_comfort"] = _err(exc)
    # spectra of the dynamic part
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
    if arrays:
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
    for i, (p, _, _) in enumerate(good):
        points[p].directions[d] = summaries[i]
        dynamic[d][p] = dyn[i]
        raw_sig[d][p] = x[i]


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


def regress_summaries(
    summaries: Sequence[Summary], point: str, direction: str, quantity: str = "peak"
) -> LinearFit:
    """Linear fit of one summary quantity against the running speed (km/h) over several runs.

    E.g. the paper's Fig. 21: ``regress_summaries(runs, "PR", "z", "peak")``.

    Parameters
    ----------
    summaries : sequence of Summary
        One per speed (each with ``run["speed_kmh"]``).
    point, direction, quantity : str
        See :meth:`Summary.value`.
    """
    speeds, values = [], []
    for s in summaries:
        v_kmh = s.run.get("speed_kmh")
        if v_kmh is None:
            raise AnalysisError("a summary has no running speed (run['speed_kmh'])")
        speeds.append(float(v_kmh))
        values.append(s.value(point, direction, quantity))
    unit = {"sperling": "-", "sperling_alternative": "-", "n_mv": "-"}.get(quantity, "m/s^2")
    return regress_on_speed(speeds, values, speed_unit="km/h", value_unit=unit)


def _fmt(v: float | None, digits: int = 3) -> str:
    if v is None or not math.isfinite(v):
        return "–"
    return f"{v:.{digits}g}" if abs(v) < 1000 else f"{v:.0f}"


def _as_dict(summary: Summary | dict[str, Any]) -> dict[str, Any]:
    if isinstance(summary, Summary):
        return summary.to_dict()
    if isinstance(summary, dict) and "points" in summary and "settings" in summary:
        return summary
    raise AnalysisError("expected a Summary or the dictionary of Summary.to_dict()")


def summary_table(summary: Summary | dict[str, Any]) -> Table:
    """A :class:`rich.table.Table` of the comfort results.

    Per point and direction: the Sperling index (default form) and its GB 5599 grade, the
    weighted rms a_w (Wb for z, Wd for y/x) with its ISO 2631 comfort band, the largest EN 12299
    C_c, the peak acceleration and, per point, N_MV (``*``: run shorter than 5 min).

    Parameters
    ----------
    summary : Summary or dict
        The result of :func:`analyze`, or its :meth:`Summary.to_dict`.
    """
    from rich.table import Table

    d = _as_dict(summary)
    run = d.get("run", {})
    title = "flexride analysis"
    if run.get("scenario"):
        title += f" — {run['scenario']}"
    if run.get("speed_kmh") is not None:
        title += f", {run['speed_kmh']:.4g} km/h"
    form = d["settings"]["sperling"]["default_form"]
    caption = (f"W: Sperling {form} form (dynamic part), grade GB 5599 · a_w: ISO 2631 rms, "
               "Wb (z) / Wd (y, x) · C_c: EN 12299 5 s · N_MV: EN 12299 standard method · "
               "peak: max |a| raw")
    table = Table(title=title)
    columns: tuple[tuple[str, JustifyMethod], ...] = (
        ("point", "left"), ("dir", "center"), ("W", "right"), ("grade", "left"),
        ("a_w m/s²", "right"), ("ISO 2631 comfort", "left"), ("C_c max m/s²", "right"),
        ("peak m/s²", "right"), ("N_MV", "right"))
    for col, just in columns:
        table.add_column(col, justify=just)
    short = False
    for name, p in d["points"].items():
        first = True
        mc = p.get("mean_comfort")
        for direction in ("z", "y", "x"):
            ds = p["directions"].get(direction)
            if ds is None:
                continue
            w = ds.get("sperling")
            iso = ds.get("iso2631", {}).get(_ISO_WEIGHTINGS[direction][0])
            cc = ds.get("continuous_comfort")
            grade = w["grade"] if w and isinstance(w.get("grade"), str) else "–"
            style = {"excellent": "green", "good": "green", "qualified": "yellow",
                     "fails": "bold red"}.get(grade, "")
            nmv = ""
            if first and mc and mc.get("value") is not None:
                nmv = f"{mc['value']:.2f}" + ("*" if mc.get("short_run") else "")
                short = short or bool(mc.get("short_run"))
            table.add_row(
                name if first else "", direction,
                _fmt(w["value"]) if w else "–",
                f"[{style}]{grade}[/]" if style else grade,
                _fmt(iso["a_w"]) if iso else "–", iso["comfort"] if iso else "–",
                _fmt(cc["maximum"]) if cc else "–",
                _fmt(ds["peaks"]["max_abs"]), nmv)
            first = False
    if short:
        caption += " · * run shorter than 5 min (see docs/analysis.md)"
    table.caption = caption
    return table


def safety_table(summary: Summary | dict[str, Any]) -> Table | None:
    """A :class:`rich.table.Table` of the running-safety indices (None without wheel forces).

    Parameters
    ----------
    summary : Summary or dict
        The result of :func:`analyze`, or its :meth:`Summary.to_dict`.
    """
    from rich.table import Table

    d = _as_dict(summary)
    safety = d.get("safety")
    if not safety:
        return None
    table = Table(title="running safety", caption=(
        "Q/P, ΔP/P: GB 5599 limits 1.2, 0.65 · ΣY: EN 14363 10 + P0/3 kN · 20 Hz low pass, "
        "2 m sliding mean (Q/P, ΣY), maximum"))
    columns: tuple[tuple[str, JustifyMethod], ...] = (
        ("location", "left"), ("quantity", "left"), ("value", "right"), ("limit", "right"),
        ("use", "right"), ("", "left"))
    for col, just in columns:
        table.add_column(col, justify=just)
    label = {"derailment_coefficient": "Q/P", "wheel_unloading": "ΔP/P",
             "wheelset_lateral_force": "ΣY kN"}
    for idx in safety["indices"]:
        use = idx.get("utilisation")
        table.add_row(idx["location"], label.get(idx["name"], idx["name"]), _fmt(idx["value"]),
                      _fmt(idx["limit"]), f"{use:.0%}" if use is not None else "–",
                      "[green]ok[/]" if idx["passed"] else "[bold red]exceeded[/]")
    return table
