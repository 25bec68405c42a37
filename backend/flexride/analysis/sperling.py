"""Sperling ride index W (Wz), vertical and lateral, in its spectral and its filter form.

Spectral form (DESIGN §6; Sperling, GB 5599-1985)
    Each spectral line i of the car-body acceleration contributes
    W_i = 0.896 (a_i³ F(f_i) / f_i)^(1/10), with a_i the peak amplitude of the line in cm/s² and
    f_i in Hz; the lines combine by the 10th-power rule W = (Σ W_i¹⁰)^(1/10). The frequency
    correction F(f) is

    ==========  ======================  ======================
    direction   range (Hz)              F(f)
    ==========  ======================  ======================
    vertical    f < 5.9                 0.325 f²
                5.9 ≤ f < 20            400 / f²
                f ≥ 20                  1
    lateral     f < 5.4                 0.8 f²
                5.4 ≤ f < 26            650 / f²
                f ≥ 26                  1
    ==========  ======================  ======================

    (each range includes its lower boundary; the standard's ranges start at 0.5 Hz, the lower
    edge of the default band).

    Pinned defaults: records cut into **5 s segments** overlapping by half (line spacing
    0.2 Hz), each detrended (mean removed) and taken with a **Hann window**; the mean square of
    every line, 2|X_k|²/(N Σw²), keeps Parseval's theorem; segments are combined by **power
    averaging** (as in Welch's method). The formula is a sum over *sines*, and a sine whose
    frequency falls between two lines spreads its power over several of them, which would read
    it up to 13 % low (0.5 Hz; 6 % at 5.9 Hz). So the lines are merged into **spectral peaks**
    (:func:`peak_lines`): from the strongest line down, each line not yet taken takes its
    untaken neighbours within ±1 line; a Hann-windowed sine has 99.9 % of its power within
    ±1 line wherever it falls, so each peak is one sine of amplitude a = √(2 p) (p its summed
    mean square) at its power-weighted mean frequency. Peaks in the **band 0.5–40 Hz**
    (widened by half a line spacing, for a sine at the band edge) count. A sine of amplitude A
    anywhere between 0.5 and 30 Hz then reads within 0.4 % of W = 0.896 ((100 A)³ F(f) /
    f)^(1/10) (:func:`sperling_sine`; tested off the line grid). ``averaging="mean"`` or
    ``"max"`` instead average or take the largest of the per-segment indices; ``lines="bins"``
    sums the raw lines (the convention before 2026-12, with a rectangular window and no overlap
    it gives the earlier values).

    For broadband vibration the value depends weakly on how finely the spectrum is cut
    (W ∝ Δf^0.05, because the formula is a sum over sines), which is why the segment length
    and the peak width are pinned: merging neighbouring lines into peaks raises a broadband
    index by about 5 % against summing the raw 0.2 Hz lines of a rectangular window.

Filter form (DESIGN §6; the Wz "B filter" of UIC 513)
    W = 4.42 a_w^0.3 with a_w the rms (m/s²) of the acceleration weighted by
    B_v(f) (vertical) or B_h = 1.25 B_v (lateral), realised as in
    :mod:`flexride.analysis.weighting`. For sines between 1 and 10 Hz the two forms agree to
    within about 2.5 %; for broadband random vibration the filter form is higher (by about
    18 % for band-limited white noise with the default peaks).

Default form: **spectral** (:data:`DEFAULT_SPERLING_FORM`), as used by the paper and GB 5599.
Every :class:`SperlingResult` names the form that produced it.

Grades (GB 5599-1985, passenger vehicles): W < 2.5 excellent, 2.5 ≤ W < 2.75 good,
2.75 ≤ W ≤ 3.0 qualified, W > 3.0 fails.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal

import numba
import numpy as np
from numpy.lib.stride_tricks import sliding_window_view
from scipy import fft as sp_fft
from scipy import signal

from flexride.analysis._common import check_nyquist, check_rate, check_signal
from flexride.analysis.weighting import WeightingMethod, apply_weighting
from flexride.errors import AnalysisError

__all__ = [
    "DEFAULT_SPERLING_FORM",
    "SPERLING_DEFAULTS",
    "SperlingResult",
    "frequency_correction",
    "index_of_spectrum",
    "line_power",
    "peak_lines",
    "record_sines",
    "spectral_form_text",
    "sperling",
    "sperling_filter",
    "sperling_grade",
    "sperling_sine",
    "sperling_sines",
    "sperling_spectral",
    "sperling_total",
]

SperlingForm = Literal["spectral", "filter"]
DEFAULT_SPERLING_FORM: SperlingForm = "spectral"

#: Pinned defaults of the spectral form.
SPERLING_DEFAULTS: dict[str, Any] = {
    "segment_s": 5.0,
    "overlap": 0.5,
    "window": "hann",
    "averaging": "power",
    "band_hz": (0.5, 40.0),
    "lines": "peaks",
}

#: Lines a spectral peak takes on each side of its strongest line (Hann window: ±1).
PEAK_HALF_WIDTH = 1


def spectral_form_text(defaults: dict[str, Any] = SPERLING_DEFAULTS) -> str:
    """The spectral form's settings in words, for reports (from :data:`SPERLING_DEFAULTS`)."""
    lo, hi = defaults["band_hz"]
    lines = (f"lines merged into spectral peaks (±{PEAK_HALF_WIDTH} line)"
             if defaults["lines"] == "peaks" else "raw spectral lines")
    return (f"spectral form (GB 5599), {defaults['segment_s']:g} s "
            f"{str(defaults['window']).capitalize()} "
            f"segments with {defaults['overlap']:.0%} overlap, {defaults['averaging']} "
            f"averaging, {lines}, {lo:g}–{hi:g} Hz")

LineMode = Literal["peaks", "bins"]

_GRADES = ((2.5, "excellent"), (2.75, "good"), (3.0, "qualified"))
_GRADE_STANDARD = "Sperling index (DESIGN §6); grades GB 5599-1985, passenger vehicles"


def _direction(direction: str) -> str:
    d = str(direction).lower()
    if d in ("z", "vertical", "v"):
        return "vertical"
    if d in ("y", "lateral", "l", "h", "horizontal"):
        return "lateral"
    raise AnalysisError(
        f"Sperling direction must be 'vertical'/'z' or 'lateral'/'y', got {direction!r}")


@dataclass
class SperlingResult:
    """A Sperling ride index and how it was made.

    Attributes
    ----------
    value : float or numpy.ndarray
        Ride index W (-); an array for 2-D input (one value per row).
    direction : str
        ``"vertical"`` or ``"lateral"``.
    form : str
        ``"spectral"`` or ``"filter"``: the form of DESIGN §6 that produced the value.
    grade : str or list of str
        GB 5599 grade: ``"excellent"``, ``"good"``, ``"qualified"`` or ``"fails"``.
    method : str
        One-line description of the method and its parameters.
    parameters : dict
        Parameters used (segment length s, window, averaging, band Hz; or weighting).
    segment_values : numpy.ndarray
        Index of every segment (spectral form), shape ``(n_segments,)`` or
        ``(n_rows, n_segments)``; empty for the filter form.
    weighted_rms : float or numpy.ndarray or None
        Filter form only: rms of the B-weighted acceleration (m/s²).
    """

    value: float | np.ndarray
    direction: str
    form: str
    grade: str | list[str]
    method: str
    parameters: dict[str, Any] = field(default_factory=dict)
    segment_values: np.ndarray = field(default_factory=lambda: np.zeros(0))
    weighted_rms: float | np.ndarray | None = None
    standard: str = _GRADE_STANDARD


def sperling_grade(value: float) -> str:
    """GB 5599 grade of a Sperling index (passenger vehicles).

    Returns ``"excellent"`` (W < 2.5), ``"good"`` (2.5 ≤ W < 2.75), ``"qualified"``
    (2.75 ≤ W ≤ 3.0) or ``"fails"`` (W > 3.0).
    """
    v = float(value)
    if not np.isfinite(v):
        raise AnalysisError(f"cannot grade a non-finite Sperling index {value!r}")
    for limit, name in _GRADES[:2]:
        if v < limit:
            return name
    return "qualified" if v <= _GRADES[2][0] else "fails"


def frequency_correction(f: np.ndarray | float, direction: str) -> np.ndarray:
    """Sperling's frequency-correction factor F(f) (DESIGN §6).

    Parameters
    ----------
    f : array_like
        Frequency in Hz (> 0).
    direction : str
        ``"vertical"``/``"z"`` or ``"lateral"``/``"y"``.

    Returns
    -------
    numpy.ndarray
        F(f) (-); each range includes its lower boundary (F(5.9) = 400/5.9² vertically).
    """
    f = np.asarray(f, dtype=np.float64)
    if _direction(direction) == "vertical":
        return np.where(f < 5.9, 0.325 * f**2, np.where(f < 20.0, 400.0 / f**2, 1.0))
    return np.where(f < 5.4, 0.8 * f**2, np.where(f < 26.0, 650.0 / f**2, 1.0))


def sperling_sine(amplitude: float, frequency: float, direction: str) -> float:
    """Closed-form Sperling index of a pure sine: W = 0.896 ((100 A)³ F(f) / f)^(1/10).

    Parameters
    ----------
    amplitude : float
        Peak acceleration amplitude A in m/s².
    frequency : float
        Frequency f in Hz.
    direction : str
        ``"vertical"``/``"z"`` or ``"lateral"``/``"y"``.
    """
    a_cm = 100.0 * abs(float(amplitude))
    fc = float(frequency_correction(frequency, direction))
    return float(0.896 * (a_cm**3 * fc / float(frequency)) ** 0.1)


def sperling_total(values: np.ndarray | list[float]) -> float:
    """Combine partial indices by the 10th-power rule, W = (Σ W_i¹⁰)^(1/10)."""
    v = np.asarray(values, dtype=np.float64)
    if v.size == 0 or not np.all(np.isfinite(v)):
        raise AnalysisError("sperling_total needs a non-empty array of finite indices")
    vmax = float(np.max(v))
    if vmax == 0.0:
        return 0.0
    return float(vmax * np.sum((v / vmax) ** 10) ** 0.1)


def _grade_of(value: float | np.ndarray) -> str | list[str]:
    if np.ndim(value) == 0:
        return sperling_grade(float(value))
    return [sperling_grade(v) for v in np.ravel(value)]


def _index_from_lines(amp: np.ndarray, factor: np.ndarray) -> np.ndarray:
    """W = 0.896 (Σ (100 a)³ F/f)^(1/10) over the last axis; ``factor`` is F(f)/f per line."""
    s = np.sum((100.0 * amp) ** 3 * factor, axis=-1)
    return 0.896 * s**0.1


def peak_lines(power: np.ndarray, freqs: np.ndarray,
               half_width: int = PEAK_HALF_WIDTH) -> tuple[np.ndarray, np.ndarray]:
    """Merge the spectral lines of one spectrum into peaks: the sines the index is summed over.

    Greedy from the strongest line down: a line not yet taken takes itself and the untaken
    lines within ``half_width`` lines on either side. A Hann-windowed sine spreads over at most
    three lines (99.9 % of its power within ±1 line wherever it falls between lines), so a sine
    becomes one peak of its full power wherever its frequency lies.

    Parameters
    ----------
    power : numpy.ndarray
        (n_lines,) mean square of each line ((m/s²)²), lines at ``freqs``.
    freqs : numpy.ndarray
        (n_lines,) line frequencies (Hz), ascending.
    half_width : int
        Lines taken on each side of a peak (-).

    Returns
    -------
    f_peak : numpy.ndarray
        Power-weighted mean frequency of each peak (Hz), ascending.
    p_peak : numpy.ndarray
        Mean square of each peak ((m/s²)²); its peak amplitude is √(2 p).
    """
    power = np.ascontiguousarray(power, dtype=np.float64)
    owner = _peak_owner(power, np.argsort(-power, kind="stable"), int(half_width))
    taken = owner >= 0
    keys, inverse = np.unique(owner[taken], return_inverse=True)
    p_peak = np.bincount(inverse, weights=power[taken], minlength=keys.size)
    f_peak = np.bincount(inverse, weights=power[taken] * freqs[taken],
                         minlength=keys.size) / p_peak
    order = np.argsort(f_peak)
    return f_peak[order], p_peak[order]


@numba.njit(cache=True)
def _peak_owner(power: np.ndarray, order: np.ndarray,
                half_width: int) -> np.ndarray:  # pragma: no cover - numba
    """The peak (index of its strongest line) each line belongs to, -1 for lines of no power."""
    n = power.size
    owner = np.full(n, -1, dtype=np.int64)
    for k in order:
        if owner[k] >= 0 or power[k] <= 0.0:
            continue
        for j in range(max(k - half_width, 0), min(k + half_width + 1, n)):
            if owner[j] < 0:
                owner[j] = k
    return owner


def index_of_spectrum(power: np.ndarray, freqs: np.ndarray, direction: str,
                      band_hz: tuple[float, float] = SPERLING_DEFAULTS["band_hz"],
                      lines: LineMode = SPERLING_DEFAULTS["lines"]) -> float:
    """Spectral-form Sperling index of one line spectrum (module docstring).

    Parameters
    ----------
    power : numpy.ndarray
        (n_lines,) mean square of each line ((m/s²)²) at ``freqs``, from the first line above
        0 Hz to at least two lines beyond the band.
    freqs : numpy.ndarray
        (n_lines,) uniformly spaced line frequencies (Hz).
    direction : str
        ``"vertical"``/``"z"`` or ``"lateral"``/``"y"``.
    band_hz : (float, float)
        Sines whose frequency lies in the band count (-, Hz).
    lines : {"peaks", "bins"}
        Sum over merged peaks (:func:`peak_lines`, default) or over the raw lines.
    """
    f, p = sperling_sines(power, freqs, band_hz, lines)
    factor = frequency_correction(f, direction) / f
    return float(_index_from_lines(np.sqrt(2.0 * p), factor))


def sperling_sines(power: np.ndarray, freqs: np.ndarray,
                   band_hz: tuple[float, float] = SPERLING_DEFAULTS["band_hz"],
                   lines: LineMode = SPERLING_DEFAULTS["lines"]
                   ) -> tuple[np.ndarray, np.ndarray]:
    """The sines the spectral form sums over: their frequencies (Hz) and mean squares
    ((m/s²)²), from a line spectrum (see :func:`index_of_spectrum` for the arguments).

    A peak counts when its frequency lies in the band widened by half a line spacing (a sine
    at the band edge falls between two lines); a raw line counts when it lies in the band.
    """
    lo, hi = band_hz
    df = float(freqs[1] - freqs[0]) if freqs.size > 1 else 1.0
    if lines == "peaks":
        f, p = peak_lines(power, freqs)
        tol = 0.5 * df
    else:
        f, p = freqs, power
        tol = 1e-9 * df
    sel = (f >= lo - tol) & (f <= hi + tol) & (f > 0.0)
    return f[sel], p[sel]


def sperling_spectral(
    x: np.ndarray,
    fs: float,
    direction: str,
    *,
    segment_s: float = SPERLING_DEFAULTS["segment_s"],
    overlap: float = SPERLING_DEFAULTS["overlap"],
    window: str | tuple = SPERLING_DEFAULTS["window"],
    averaging: Literal["power", "mean", "max"] = SPERLING_DEFAULTS["averaging"],
    band_hz: tuple[float, float] = SPERLING_DEFAULTS["band_hz"],
    lines: LineMode = SPERLING_DEFAULTS["lines"],
) -> SperlingResult:
    """Sperling index, spectral form (frequency correction per sine, 10th-power sum).

    Parameters
    ----------
    x : array_like
        Car-body acceleration in m/s² (quasi-static part already removed on curves), shape
        ``(n,)`` or ``(m, n)``.
    fs : float
        Sample rate in Hz; must be at least twice the upper band edge.
    direction : str
        ``"vertical"``/``"z"`` or ``"lateral"``/``"y"``.
    segment_s : float
        Segment length in s (line spacing 1/segment_s); default 5 s.
    overlap : float
        Fraction of a segment that consecutive segments share, in [0, 1); default 0.5.
    window : str or tuple
        Window name for :func:`scipy.signal.get_window`; default ``"hann"``.
    averaging : {"power", "mean", "max"}
        How segments combine: average line power (default), or the mean or maximum of the
        per-segment indices.
    band_hz : (float, float)
        Sines with band_hz[0] ≤ f ≤ band_hz[1] count; default (0.5, 40) Hz.
    lines : {"peaks", "bins"}
        Sum over spectral peaks (neighbouring lines merged, :func:`peak_lines`; default) or
        over the raw lines (the convention before 2026-12; a sine between lines reads up to
        13 % low).

    Returns
    -------
    SperlingResult
        ``form == "spectral"``.

    Raises
    ------
    AnalysisError
        Bad input, a record shorter than one segment or a sample rate below 2 × band_hz[1].
    """
    direction = _direction(direction)
    fs = check_rate(fs)
    lo, hi = _check_spectral_options(fs, overlap, averaging, band_hz, lines)
    x = check_signal(x, fs, name="acceleration", min_duration=segment_s,
                     method=f"the spectral Sperling index ({segment_s:g} s segments)")
    one_d = x.ndim == 1
    freqs, power = _record_power(x if not one_d else x[np.newaxis, :], fs, segment_s, overlap,
                                 window, (lo, hi))
    seg_w, w_val = _segment_indices(power, freqs, direction, (lo, hi), lines, averaging)

    value: float | np.ndarray = float(w_val[0]) if one_d else w_val
    seg_values = seg_w[0] if one_d else seg_w
    n_segs = power.shape[1]
    win_name = window if isinstance(window, str) else "/".join(map(str, window))
    params = {"segment_s": float(segment_s), "overlap": float(overlap), "window": win_name,
              "averaging": averaging, "band_hz": [lo, hi], "lines": lines,
              "line_spacing_hz": float(freqs[0]), "n_segments": int(n_segs)}
    summed = "spectral peaks (±1 line merged)" if lines == "peaks" else "spectral lines"
    method = (f"Sperling spectral form (DESIGN §6, GB 5599-1985): {segment_s:g} s "
              f"{win_name} segments, overlap {overlap:g}, {averaging} averaging over "
              f"{n_segs} segment(s), {summed} {lo:g}–{hi:g} Hz")
    return SperlingResult(value=value, direction=direction, form="spectral",
                          grade=_grade_of(value), method=method, parameters=params,
                          segment_values=seg_values)


def record_sines(x: np.ndarray, fs: float) -> tuple[np.ndarray, np.ndarray]:
    """The sines the spectral form (pinned defaults, power averaging) sums over for a record.

    Parameters
    ----------
    x : array_like
        (n,) car-body acceleration (m/s²), at least one segment long.
    fs : float
        Sample rate (Hz).

    Returns
    -------
    f : numpy.ndarray
        Frequencies of the sines in the band (Hz).
    amplitude : numpy.ndarray
        Their peak amplitudes (m/s²).
    """
    d = SPERLING_DEFAULTS
    fs = check_rate(fs)
    lo, hi = _check_spectral_options(fs, d["overlap"], d["averaging"], d["band_hz"], d["lines"])
    x = check_signal(x, fs, name="acceleration", min_duration=d["segment_s"],
                     method=f"the spectral Sperling index ({d['segment_s']:g} s segments)")
    freqs, power = _record_power(np.atleast_2d(x), fs, d["segment_s"], d["overlap"],
                                 d["window"], (lo, hi))
    f, p = sperling_sines(power[0].mean(axis=0), freqs, (lo, hi), d["lines"])
    return f, np.sqrt(2.0 * p)


def _record_power(x: np.ndarray, fs: float, segment_s: float, overlap: float,
                  window: str | tuple, band: tuple[float, float]
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Line frequencies (Hz) and ``(records, segments, lines)`` mean square per line
    ((m/s²)²) of the 2-D records ``x``.

    Raises
    ------
    AnalysisError
        A segment of fewer than 8 samples or without a line in the band.
    """
    seg = round(segment_s * fs)
    if seg < 8:
        raise AnalysisError(f"segment of {segment_s:g} s has only {seg} samples at {fs:g} Hz")
    hop = max(1, seg - round(overlap * seg))
    freqs = _analysis_lines(seg, fs, band[0], band[1], segment_s)
    win = signal.get_window(window, seg, fftbins=True)
    segs = sliding_window_view(x, seg, axis=-1)[:, ::hop, :]
    return freqs, line_power(segs, win, freqs.size)


def _check_spectral_options(fs: float, overlap: float, averaging: str,
                            band_hz: tuple[float, float], lines: str) -> tuple[float, float]:
    """The band edges (Hz) of the spectral form, after checking the band against the sample
    rate ``fs`` (Hz), the segment overlap, the averaging and the line mode.

    Raises
    ------
    AnalysisError
        A band not satisfying 0 < low < high ≤ fs/2, an overlap outside [0, 1), an unknown
        averaging or line mode.
    """
    lo, hi = (float(b) for b in band_hz)
    if not (0.0 < lo < hi):
        raise AnalysisError(f"Sperling band must satisfy 0 < low < high (Hz), got {band_hz!r}")
    check_nyquist(fs, hi, f"the Sperling band up to {hi:g} Hz")
    if not 0.0 <= overlap < 1.0:
        raise AnalysisError(f"segment overlap must be in [0, 1), got {overlap!r}")
    if averaging not in ("power", "mean", "max"):
        raise AnalysisError(f"averaging must be 'power', 'mean' or 'max', got {averaging!r}")
    if lines not in ("peaks", "bins"):
        raise AnalysisError(f"lines must be 'peaks' or 'bins', got {lines!r}")
    return lo, hi


def _analysis_lines(seg: int, fs: float, lo: float, hi: float, segment_s: float) -> np.ndarray:
    """Frequencies (Hz) of the lines of a ``seg``-sample segment at ``fs`` Hz that the spectral
    form looks at: from the first line above 0 Hz to two lines beyond ``hi`` (or Nyquist), so
    that a peak at the band edge is whole.

    Raises
    ------
    AnalysisError
        If no line lies in the band ``lo``–``hi`` Hz.
    """
    freqs = sp_fft.rfftfreq(seg, 1.0 / fs)
    tol = 1e-9 * fs
    if not np.any((freqs >= lo - tol) & (freqs <= hi + tol) & (freqs > 0.0)):
        raise AnalysisError(
            f"no spectral line in the band {lo:g}–{hi:g} Hz with {segment_s:g} s segments"
        )
    n_top = int(np.searchsorted(freqs, hi + tol, side="right")) + PEAK_HALF_WIDTH + 1
    return freqs[1:min(n_top, freqs.size)]


def line_power(segs: np.ndarray, win: np.ndarray, n_lines: int) -> np.ndarray:
    """Mean square of lines 1 … ``n_lines`` of every windowed, mean-removed segment.

    Parameters
    ----------
    segs : numpy.ndarray
        ``(records, segments, samples)`` view of the records (m/s²).
    win : numpy.ndarray
        Window of a segment.
    n_lines : int
        Lines kept, from the first above 0 Hz.

    Returns
    -------
    numpy.ndarray
        ``(records, segments, n_lines)`` mean square per line ((m/s²)²): 2|X_k|²/(N Σw²),
        which keeps Parseval's theorem for any window (a sine on a line of a rectangular
        segment: A²/2).
    """
    n_rows, n_segs, seg = segs.shape
    scale = 2.0 / (seg * np.sum(win**2))
    # process rows in blocks to bound memory (rows × segments × seg samples)
    rows_per_block = max(1, int(4_000_000 // max(1, n_segs * seg)))
    out = np.empty((n_rows, n_segs, n_lines))
    for r0 in range(0, n_rows, rows_per_block):
        block = segs[r0:r0 + rows_per_block]
        block = block - block.mean(axis=-1, keepdims=True)
        spec = sp_fft.rfft(block * win, axis=-1)[..., 1:n_lines + 1]
        out[r0:r0 + rows_per_block] = scale * (spec.real**2 + spec.imag**2)
    return out


def _segment_indices(power: np.ndarray, freqs: np.ndarray, direction: str,
                     band: tuple[float, float], lines: LineMode,
                     averaging: str) -> tuple[np.ndarray, np.ndarray]:
    """Sperling indices of every segment and of every record.

    Parameters
    ----------
    power : numpy.ndarray
        ``(records, segments, lines)`` mean square per line ((m/s²)²).
    freqs : numpy.ndarray
        Line frequencies (Hz).
    direction, band, lines, averaging
        As in :func:`sperling_spectral`.

    Returns
    -------
    seg_w : numpy.ndarray
        ``(records, segments)`` index of each segment (-).
    w_val : numpy.ndarray
        ``(records,)`` index of each record (-).
    """
    def index(p: np.ndarray) -> float:
        return index_of_spectrum(p, freqs, direction, band, lines)

    n_rows, n_segs, _ = power.shape
    seg_w = np.array([[index(power[r, s]) for s in range(n_segs)] for r in range(n_rows)])
    if averaging == "power":
        w_val = np.array([index(power[r].mean(axis=0)) for r in range(n_rows)])
    elif averaging == "mean":
        w_val = seg_w.mean(axis=1)
    else:
        w_val = seg_w.max(axis=1)
    return seg_w, w_val


def sperling_filter(
    x: np.ndarray,
    fs: float,
    direction: str,
    *,
    method: WeightingMethod = "iir",
) -> SperlingResult:
    """Sperling index, filter form: W = 4.42 a_w^0.3 with a_w the rms of the B-weighted record.

    Parameters
    ----------
    x : array_like
        Car-body acceleration in m/s², shape ``(n,)`` or ``(m, n)``.
    fs : float
        Sample rate in Hz (≥ 100 Hz).
    direction : str
        ``"vertical"``/``"z"`` (B_v) or ``"lateral"``/``"y"`` (B_h = 1.25 B_v).
    method : {"iir", "fft"}
        Realisation of the B filter (:func:`~flexride.analysis.weighting.apply_weighting`).

    Returns
    -------
    SperlingResult
        ``form == "filter"``; ``weighted_rms`` holds a_w (m/s²).
    """
    direction = _direction(direction)
    name = "Bv" if direction == "vertical" else "Bh"
    x = check_signal(x, fs, name="acceleration", min_duration=1.0,
                     method="the filter-form Sperling index")
    aw_sig = apply_weighting(x, fs, name, method=method)
    a_w = np.sqrt(np.mean(aw_sig**2, axis=-1))
    w = 4.42 * a_w**0.3
    value: float | np.ndarray = float(w) if x.ndim == 1 else w
    aw_out: float | np.ndarray = float(a_w) if x.ndim == 1 else a_w
    desc = (f"Sperling filter form (DESIGN §6, UIC 513 B filter): W = 4.42·a_w^0.3, a_w = rms "
            f"of the {name}-weighted acceleration over the whole record ({method} filter)")
    return SperlingResult(value=value, direction=direction, form="filter",
                          grade=_grade_of(value), method=desc,
                          parameters={"weighting": name, "filter": method},
                          weighted_rms=aw_out)


def sperling(
    x: np.ndarray,
    fs: float,
    direction: str,
    form: SperlingForm = DEFAULT_SPERLING_FORM,
    **kwargs: Any,
) -> SperlingResult:
    """Sperling ride index in the requested form (default: spectral, see module docs).

    Parameters
    ----------
    x : array_like
        Car-body acceleration in m/s².
    fs : float
        Sample rate in Hz.
    direction : str
        ``"vertical"``/``"z"`` or ``"lateral"``/``"y"``.
    form : {"spectral", "filter"}
        Which form of DESIGN §6.
    **kwargs
        Passed to :func:`sperling_spectral` or :func:`sperling_filter`.
    """
    if form == "spectral":
        return sperling_spectral(x, fs, direction, **kwargs)
    if form == "filter":
        return sperling_filter(x, fs, direction, **kwargs)
    raise AnalysisError(f"Sperling form must be 'spectral' or 'filter', got {form!r}")
