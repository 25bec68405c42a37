"""Spectra of acceleration records: one-sided amplitude spectrum, Welch PSD, dominant peaks.

Scaling
-------
Amplitude spectrum (:func:`amplitude_spectrum`)
    One-sided *peak* amplitude, a_0 = |X_0| / Σw, a_k = 2 |X_k| / Σw for 0 < k < N/2 and
    a_{N/2} = |X_{N/2}| / Σw (X the DFT of the windowed record, Σw the window sum, "coherent
    gain" correction): a sine of amplitude A at a line frequency shows as A for any window.
    With the default rectangular window Parseval holds as
    mean(x²) = a_0² + Σ_{0<k<N/2} a_k² / 2 + a_{N/2}². Unit: that of the signal (m/s²).
Welch PSD (:func:`welch_psd`)
    One-sided power spectral density, :func:`scipy.signal.welch` with ``scaling="density"``:
    ∫ PSD df = variance. Defaults: 8 s Hann segments, 50 % overlap, mean removed per segment;
    resolution 1/segment_s. Unit: (m/s²)²/Hz. White noise of variance σ² sampled at fs has the
    level 2σ²/fs.
Dominant peaks (:func:`dominant_peaks`)
    Interior local maxima (:func:`scipy.signal.find_peaks`) inside a band whose prominence is
    at least ``rel_prominence`` (default 10 %) of the largest spectral value in the band,
    largest first. A spectrum falling from a band edge has no peak there. Each peak reports its
    frequency and the amplitude of the equivalent sine: the line value of an amplitude
    spectrum, or √(2 Δf Σ PSD) over the peak line ± 2 lines (the Hann main lobe) of a PSD.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import fft as sp_fft
from scipy import signal

from flexride.analysis._common import check_rate, check_signal
from flexride.errors import AnalysisError

__all__ = ["SpectralPeak", "Spectrum", "amplitude_spectrum", "dominant_peaks", "welch_psd"]


@dataclass
class Spectrum:
    """A one-sided spectrum.

    Attributes
    ----------
    frequencies : numpy.ndarray
        Frequencies in Hz.
    values : numpy.ndarray
        Spectrum, shape ``(..., n_freq)``, in ``unit``.
    kind : str
        ``"amplitude"`` (peak amplitude per line) or ``"psd"`` (one-sided density).
    unit : str
        Unit of ``values``.
    resolution_hz : float
        Line spacing in Hz.
    window : str
        Window used.
    n_averages : int
        Number of averaged segments (1 for the amplitude spectrum).
    scaling : str
        Description of the scaling.
    """

    frequencies: np.ndarray
    values: np.ndarray
    kind: str
    unit: str
    resolution_hz: float
    window: str
    n_averages: int
    scaling: str


@dataclass
class SpectralPeak:
    """A dominant spectral peak.

    Attributes
    ----------
    frequency : float
        Frequency of the peak line in Hz.
    amplitude : float
        Peak amplitude of the equivalent sine (unit of the signal): the line value for an
        amplitude spectrum; √(2 Δf Σ PSD) over the peak line and two lines either side (the
        Hann main lobe) for a PSD.
    value : float
        Spectral value at the peak (unit of the spectrum).
    prominence : float
        Prominence of the peak (unit of the spectrum).
    """

    frequency: float
    amplitude: float
    value: float
    prominence: float


def amplitude_spectrum(
    x: np.ndarray,
    fs: float,
    *,
    window: str | tuple = "boxcar",
    detrend: bool = False,
    unit: str = "m/s^2",
) -> Spectrum:
    """One-sided peak-amplitude spectrum of a whole record (see module docs for the scaling).

    Parameters
    ----------
    x : array_like
        Signal, shape ``(n,)`` or ``(m, n)``.
    fs : float
        Sample rate in Hz.
    window : str or tuple
        Window for :func:`scipy.signal.get_window`; default rectangular.
    detrend : bool
        Remove the mean first.
    unit : str
        Unit of the signal, copied to the result.
    """
    fs = check_rate(fs)
    x = check_signal(x, fs, name="signal", min_samples=2, method="an amplitude spectrum")
    n = x.shape[-1]
    if detrend:
        x = x - x.mean(axis=-1, keepdims=True)
    w = signal.get_window(window, n, fftbins=True)
    spec = np.abs(sp_fft.rfft(x * w, axis=-1)) / np.sum(w)
    if n % 2 == 0:
        spec[..., 1:-1] *= 2.0
    else:
        spec[..., 1:] *= 2.0
    win_name = window if isinstance(window, str) else "/".join(map(str, window))
    return Spectrum(frequencies=sp_fft.rfftfreq(n, 1.0 / fs), values=spec, kind="amplitude",
                    unit=unit, resolution_hz=fs / n, window=win_name, n_averages=1,
                    scaling="one-sided peak amplitude, coherent-gain corrected")


def welch_psd(
    x: np.ndarray,
    fs: float,
    *,
    segment_s: float = 8.0,
    overlap: float = 0.5,
    window: str | tuple = "hann",
    unit: str = "m/s^2",
) -> Spectrum:
    """One-sided Welch power spectral density.

    Parameters
    ----------
    x : array_like
        Signal, shape ``(n,)`` or ``(m, n)``; at least one segment long.
    fs : float
        Sample rate in Hz.
    segment_s : float
        Segment length in s (resolution 1/segment_s Hz).
    overlap : float
        Overlap fraction of consecutive segments, in [0, 1).
    window : str or tuple
        Window for :func:`scipy.signal.get_window`.
    unit : str
        Unit of the signal; the PSD is in unit²/Hz.
    """
    fs = check_rate(fs)
    if not 0.0 <= overlap < 1.0:
        raise AnalysisError(f"overlap must be in [0, 1), got {overlap!r}")
    x = check_signal(x, fs, name="signal", min_duration=segment_s,
                     method=f"a Welch PSD with {segment_s:g} s segments")
    nper = max(2, round(segment_s * fs))
    nover = min(nper - 1, round(overlap * nper))
    f, p = signal.welch(x, fs=fs, window=window, nperseg=nper, noverlap=nover,
                        detrend="constant", scaling="density", axis=-1)
    n_avg = 1 + (x.shape[-1] - nper) // (nper - nover)
    win_name = window if isinstance(window, str) else "/".join(map(str, window))
    return Spectrum(frequencies=f, values=p, kind="psd", unit=f"({unit})^2/Hz",
                    resolution_hz=fs / nper, window=win_name, n_averages=int(n_avg),
                    scaling=(f"one-sided PSD (Welch, {segment_s:g} s {win_name} segments, "
                             f"{overlap:.0%} overlap, mean removed)"))


def dominant_peaks(
    spectrum: Spectrum | tuple[np.ndarray, np.ndarray],
    *,
    n: int = 5,
    rel_prominence: float = 0.1,
    band_hz: tuple[float, float] | None = None,
    kind: str = "amplitude",
) -> list[SpectralPeak]:
    """Dominant peaks of a 1-D spectrum, largest first.

    Parameters
    ----------
    spectrum : Spectrum or (frequencies, values)
        One spectrum (1-D values).
    kind : {"amplitude", "psd"}
        Kind of a spectrum given as a tuple (a :class:`Spectrum` says it itself); decides how
        :attr:`SpectralPeak.amplitude` is obtained.
    n : int
        Most peaks returned.
    rel_prominence : float
        Minimum prominence as a fraction of the largest value in the band.
    band_hz : (float, float), optional
        Frequency band searched (inclusive); default all lines above 0 Hz.

    Returns
    -------
    list of SpectralPeak
    """
    if isinstance(spectrum, Spectrum):
        f, v, kind = spectrum.frequencies, spectrum.values, spectrum.kind
    else:
        f, v = spectrum
    if kind not in ("amplitude", "psd"):
        raise AnalysisError(f"spectrum kind must be 'amplitude' or 'psd', got {kind!r}")
    f = np.asarray(f, dtype=np.float64)
    v = check_signal(v, name="spectrum", min_samples=1, ndim=(1,), method="peak search")
    if f.shape != v.shape:
        raise AnalysisError(f"frequencies {f.shape} and values {v.shape} differ in shape")
    lo, hi = band_hz if band_hz is not None else (np.finfo(float).tiny, np.inf)
    sel = (f >= lo) & (f <= hi)
    if not np.any(sel):
        return []
    fb, vb = f[sel], v[sel]
    vmax = float(np.max(vb))
    if vmax <= 0.0:
        return []
    # interior local maxima only: a slope cut by a band edge is not a peak
    idx, props = signal.find_peaks(vb, prominence=rel_prominence * vmax)
    order = np.argsort(vb[idx])[::-1][:n]
    df = float(np.mean(np.diff(f))) if f.size > 1 else 0.0
    out = []
    for i in order:
        k = int(idx[i])
        if kind == "psd":
            lobe = vb[max(0, k - 2): k + 3]
            amp = float(np.sqrt(2.0 * df * np.sum(lobe)))
        else:
            amp = float(vb[k])
        out.append(SpectralPeak(frequency=float(fb[k]), amplitude=amp, value=float(vb[k]),
                                prominence=float(props["prominences"][i])))
    return out
