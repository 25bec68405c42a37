"""Time–frequency energy: short-time Fourier spectrogram and a Morlet wavelet scalogram.

Spectrogram (:func:`spectrogram`)
    :class:`scipy.signal.ShortTimeFFT`, Hann window of ``window_s`` seconds (default 2 s),
    hop ``(1 − overlap)·window_s`` (default 75 % overlap: 0.5 s), one-sided with doubled
    non-DC lines, each slice detrended (mean removed). Resolution: Δf = 1/window_s
    (0.5 Hz by default), Δt = hop. Only slices lying wholly inside the record are kept; their
    times are the slice centres. ``scaling="psd"`` gives a one-sided PSD per slice in
    (m/s²)²/Hz; ``scaling="magnitude"`` gives the peak amplitude of a sine (m/s²).
Scalogram (:func:`scalogram`), optional
    Continuous wavelet transform with the analytic Morlet wavelet ψ̂(sω) = 2 exp(−(sω − ω0)²/2)
    (ω > 0, ω0 = 6 by default), scale s = ω0/(2πf), computed by FFT of the zero-padded record.
    Normalised so that a sine of amplitude A at f gives |W| = A on the ridge: the values are
    amplitudes in m/s². Relative bandwidth Δf/f ≈ 1/ω0 (≈ 17 %), time resolution ≈ ω0/(2πf).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from scipy import fft as sp_fft
from scipy import signal

from flexride.analysis._common import check_nyquist, check_rate, check_signal
from flexride.errors import AnalysisError

__all__ = ["Scalogram", "Spectrogram", "scalogram", "spectrogram"]


@dataclass
class Spectrogram:
    """Short-time Fourier spectrogram.

    Attributes
    ----------
    times : numpy.ndarray
        Slice centres in s.
    frequencies : numpy.ndarray
        Frequencies in Hz.
    values : numpy.ndarray
        Shape ``(n_freq, n_times)`` (or ``(m, n_freq, n_times)`` for 2-D input), in ``unit``.
    scaling : str
        ``"psd"`` or ``"magnitude"``.
    unit : str
        Unit of ``values``.
    window_s, hop_s, resolution_hz : float
        Window length, hop (time resolution) and frequency resolution.
    """

    times: np.ndarray
    frequencies: np.ndarray
    values: np.ndarray
    scaling: str
    unit: str
    window_s: float
    hop_s: float
    resolution_hz: float
    window: str = "hann"
    method: str = ""


def window_and_hop(fs: float, window_s: float, overlap: float) -> tuple[int, int]:
    """Samples per window and between windows of :func:`spectrogram` (fs in Hz, window in s,
    overlap as a fraction).
    """
    nwin = max(4, round(window_s * fs))
    return nwin, max(1, round(nwin * (1.0 - overlap)))


def spectrogram_cells(n: int, fs: float, window_s: float, overlap: float) -> int:
    """Values :func:`spectrogram` computes for ``n`` samples before it keeps the band up to
    ``fmax``: time slices × one-sided frequency bins (its cost and memory are of this order).
    """
    nwin, hop = window_and_hop(fs, window_s, overlap)
    sft = signal.ShortTimeFFT(np.ones(nwin), hop, fs)  # only its slice count is used
    return int(sft.p_max(n) - sft.p_min) * (nwin // 2 + 1)


def spectrogram(
    x: np.ndarray,
    fs: float,
    *,
    window_s: float = 2.0,
    overlap: float = 0.75,
    window: str = "hann",
    fmax: float | None = None,
    scaling: Literal["psd", "magnitude"] = "psd",
    unit: str = "m/s^2",
) -> Spectrogram:
    """Short-time Fourier spectrogram with :class:`scipy.signal.ShortTimeFFT`.

    Parameters
    ----------
    x : array_like
        Signal, shape ``(n,)`` or ``(m, n)``; at least one window long.
    fs : float
        Sample rate in Hz.
    window_s : float
        Window length in s (frequency resolution 1/window_s).
    overlap : float
        Overlap fraction of consecutive windows, in [0, 1).
    window : str
        Window name.
    fmax : float, optional
        Highest frequency kept (Hz); must not exceed fs/2.
    scaling : {"psd", "magnitude"}
        PSD per slice ((unit)²/Hz) or sine peak amplitude (unit).
    unit : str
        Unit of the signal.
    """
    fs = check_rate(fs)
    if not 0.0 <= overlap < 1.0:
        raise AnalysisError(f"overlap must be in [0, 1), got {overlap!r}")
    if scaling not in ("psd", "magnitude"):
        raise AnalysisError(f"scaling must be 'psd' or 'magnitude', got {scaling!r}")
    x = check_signal(x, fs, name="signal", min_duration=window_s,
                     method=f"a spectrogram with {window_s:g} s windows")
    if fmax is not None:
        check_nyquist(fs, fmax, f"a spectrogram up to {fmax:g} Hz")
    nwin, hop = window_and_hop(fs, window_s, overlap)
    sft = signal.ShortTimeFFT(signal.get_window(window, nwin), hop, fs,
                              fft_mode="onesided2X", scale_to=scaling)
    n = x.shape[-1]
    p0 = sft.lower_border_end[1]
    p1 = sft.upper_border_begin(n)[1]
    if p1 <= p0:  # record of about one window: take the slice(s) overlapping it anyway
        p0, p1 = sft.p_min, sft.p_max(n)
    detrended = sft.stft_detrend(x, "constant", p0=p0, p1=p1)
    vals = np.abs(detrended) ** 2 if scaling == "psd" else np.abs(detrended)
    f = sft.f
    if fmax is not None:
        keep = f <= fmax + 1e-9
        f, vals = f[keep], vals[..., keep, :]
    t = sft.t(n, p0, p1)
    unit_out = f"({unit})^2/Hz" if scaling == "psd" else unit
    desc = (f"ShortTimeFFT: {window_s:g} s {window} window, hop {hop / fs:g} s, one-sided "
            f"({scaling}), mean removed per slice, Δf = {fs / nwin:g} Hz")
    return Spectrogram(times=t, frequencies=f, values=vals, scaling=scaling, unit=unit_out,
                       window_s=nwin / fs, hop_s=hop / fs, resolution_hz=fs / nwin,
                       window=window, method=desc)


@dataclass
class Scalogram:
    """Morlet wavelet scalogram.

    Attributes
    ----------
    times : numpy.ndarray
        Times in s.
    frequencies : numpy.ndarray
        Analysis frequencies in Hz.
    amplitude : numpy.ndarray
        |W|, shape ``(n_freq, n_times)``, in the unit of the signal (sine amplitude).
    omega0 : float
        Morlet centre frequency (-).
    """

    times: np.ndarray
    frequencies: np.ndarray
    amplitude: np.ndarray
    omega0: float
    method: str = ""


def scalogram(
    x: np.ndarray,
    fs: float,
    *,
    frequencies: np.ndarray | None = None,
    omega0: float = 6.0,
    time_step_s: float | None = None,
) -> Scalogram:
    """Continuous wavelet transform (analytic Morlet) amplitude of a 1-D record.

    Parameters
    ----------
    x : array_like
        Signal, shape ``(n,)``.
    fs : float
        Sample rate in Hz.
    frequencies : array_like, optional
        Analysis frequencies in Hz (each below fs/2); default 48 log-spaced from 0.5 Hz to
        min(50 Hz, fs/4).
    omega0 : float
        Morlet centre frequency (≥ 5 for admissibility in practice).
    time_step_s : float, optional
        Output time step in s (decimates the output columns to save memory); default 1/fs.
    """
    fs = check_rate(fs)
    x = check_signal(x, fs, name="signal", min_samples=8, ndim=(1,), method="a scalogram")
    if frequencies is None:
        frequencies = np.geomspace(0.5, min(50.0, fs / 4.0), 48)
    freqs = np.asarray(frequencies, dtype=np.float64)
    if freqs.ndim != 1 or freqs.size == 0 or np.any(freqs <= 0) or np.any(freqs >= fs / 2):
        raise AnalysisError(f"scalogram frequencies must lie in (0, {fs / 2:g}) Hz")
    n = x.shape[-1]
    step = 1 if time_step_s is None else max(1, round(time_step_s * fs))
    # pad with the wavelet's longest support (≈ 4 ω0 / (2π f_min) s) to limit wrap-around
    pad = min(4 * n, int(np.ceil(4.0 * omega0 / (2 * np.pi * freqs.min()) * fs)))
    nfft = sp_fft.next_fast_len(n + pad)
    xf = sp_fft.fft(x - x.mean(), nfft)
    omega = 2 * np.pi * sp_fft.fftfreq(nfft, 1.0 / fs)
    pos = omega > 0
    out = np.empty((freqs.size, len(range(0, n, step))))
    for i, f in enumerate(freqs):
        s = omega0 / (2 * np.pi * f)
        psi = np.zeros(nfft)
        psi[pos] = 2.0 * np.exp(-0.5 * (s * omega[pos] - omega0) ** 2)
        out[i] = np.abs(sp_fft.ifft(xf * psi)[:n:step])
    desc = (f"analytic Morlet CWT (ω0 = {omega0:g}) by FFT, amplitude-normalised "
            "(a sine of amplitude A gives A)")
    return Scalogram(times=np.arange(0, n, step) / fs, frequencies=freqs, amplitude=out,
                     omega0=omega0, method=desc)
