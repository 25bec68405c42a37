"""Spectra: Parseval, a known sine, the level of white noise, dominant peaks; spectrogram and
scalogram of known signals."""

from __future__ import annotations

import numpy as np
import pytest

from flexride.analysis import (
    amplitude_spectrum,
    dominant_peaks,
    scalogram,
    spectrogram,
    welch_psd,
)
from flexride.errors import AnalysisError

RNG = np.random.default_rng(42)


@pytest.mark.parametrize("n", [4000, 4001])
def test_parseval_amplitude_spectrum(n):
    x = RNG.standard_normal(n) + 0.3
    s = amplitude_spectrum(x, 100.0)
    a = s.values
    last = a[-1] ** 2 if n % 2 == 0 else a[-1] ** 2 / 2
    power = a[0] ** 2 + np.sum(a[1:-1] ** 2) / 2 + last
    assert power == pytest.approx(np.mean(x**2), rel=1e-10)
    assert s.resolution_hz == pytest.approx(100.0 / n)
    assert s.kind == "amplitude"


@pytest.mark.parametrize("window", ["boxcar", "hann", "flattop"])
def test_sine_found_at_frequency_and_amplitude(window):
    fs, f0, amp = 500.0, 7.25, 0.35
    t = np.arange(round(40 * fs)) / fs  # 40 s: 7.25 Hz is a line
    x = amp * np.cos(2 * np.pi * f0 * t + 0.3) + 0.01 * RNG.standard_normal(t.size)
    s = amplitude_spectrum(x, fs, window=window, detrend=True)
    peaks = dominant_peaks(s, n=3, rel_prominence=0.2)
    assert peaks[0].frequency == pytest.approx(f0)
    assert peaks[0].value == pytest.approx(amp, rel=0.01)
    assert peaks[0].amplitude == peaks[0].value
    assert len(peaks) == 1


def test_welch_white_noise_level_and_integral():
    fs, sigma = 200.0, 0.7
    x = sigma * RNG.standard_normal(round(600 * fs))
    p = welch_psd(x, fs, segment_s=4.0)
    inner = (p.frequencies > 1.0) & (p.frequencies < fs / 2 - 1.0)
    assert np.mean(p.values[inner]) == pytest.approx(2 * sigma**2 / fs, rel=0.02)
    assert np.trapezoid(p.values, p.frequencies) == pytest.approx(np.var(x), rel=0.02)
    assert p.unit == "(m/s^2)^2/Hz" and p.resolution_hz == pytest.approx(0.25)


def test_welch_sine_power():
    fs, f0, amp = 200.0, 12.0, 0.5
    t = np.arange(round(64 * fs)) / fs
    p = welch_psd(amp * np.sin(2 * np.pi * f0 * t), fs)
    band = np.abs(p.frequencies - f0) < 1.0
    assert np.sum(p.values[band]) * p.resolution_hz == pytest.approx(amp**2 / 2, rel=1e-3)
    peak = dominant_peaks(p, n=1)[0]
    assert peak.frequency == pytest.approx(f0)
    assert peak.amplitude == pytest.approx(amp, rel=1e-3)  # sine amplitude from the PSD


def test_dominant_peaks_order_prominence_and_band():
    f = np.linspace(0, 50, 501)
    v = 1.0 * np.exp(-((f - 6.3) / 0.3) ** 2) + 0.4 * np.exp(-((f - 17.6) / 0.3) ** 2) \
        + 0.05 * np.exp(-((f - 30.0) / 0.3) ** 2)
    peaks = dominant_peaks((f, v), n=5, rel_prominence=0.1)
    assert [round(p.frequency, 1) for p in peaks] == [6.3, 17.6]
    assert peaks[0].prominence == pytest.approx(1.0, rel=1e-3)
    assert len(dominant_peaks((f, v), rel_prominence=0.01)) == 3
    assert dominant_peaks((f, v), band_hz=(10, 40))[0].frequency == pytest.approx(17.6)
    assert dominant_peaks((f, np.zeros_like(f))) == []


def test_spectra_bad_input():
    with pytest.raises(AnalysisError, match="too short"):
        welch_psd(np.zeros(100), 100.0, segment_s=8.0)
    with pytest.raises(AnalysisError, match="NaN"):
        amplitude_spectrum(np.array([1.0, np.inf, 2.0]), 10.0)
    with pytest.raises(AnalysisError, match="empty"):
        amplitude_spectrum([], 10.0)
    with pytest.raises(AnalysisError, match="differ"):
        dominant_peaks((np.arange(3.0), np.arange(4.0)))
    with pytest.raises(AnalysisError, match="kind"):
        dominant_peaks((np.arange(3.0), np.arange(3.0)), kind="energy")


def test_spectrogram_sine_steps():
    fs = 200.0
    t = np.arange(round(40 * fs)) / fs
    x = np.where(t < 20, 0.4 * np.sin(2 * np.pi * 2.0 * t), 0.2 * np.sin(2 * np.pi * 8.0 * t))
    sg = spectrogram(x, fs, scaling="magnitude", fmax=20.0)
    assert sg.resolution_hz == pytest.approx(0.5) and sg.hop_s == pytest.approx(0.5)
    assert sg.values.shape == (sg.frequencies.size, sg.times.size)
    assert sg.times[0] >= 1.0 - 1e-9 and sg.times[-1] <= 39.0 + 1e-9
    early, late = sg.times < 18, sg.times > 22
    ridge = sg.frequencies[np.argmax(sg.values, axis=0)]
    assert np.all(ridge[early] == 2.0) and np.all(ridge[late] == 8.0)
    assert np.max(sg.values[:, early], axis=0) == pytest.approx(0.4, rel=1e-6)
    assert np.max(sg.values[:, late], axis=0) == pytest.approx(0.2, rel=1e-6)
    psd = spectrogram(x, fs, scaling="psd")
    power = np.sum(psd.values[:, psd.times < 18], axis=0) * psd.resolution_hz
    assert power == pytest.approx(0.4**2 / 2, rel=1e-3)


def test_scalogram_amplitude():
    fs, f0, amp = 200.0, 5.0, 0.3
    t = np.arange(round(30 * fs)) / fs
    sc = scalogram(amp * np.sin(2 * np.pi * f0 * t), fs, frequencies=[2.0, 5.0, 12.0],
                   time_step_s=0.1)
    mid = (sc.times > 5) & (sc.times < 25)
    assert sc.amplitude[1, mid] == pytest.approx(amp, rel=0.01)
    assert np.all(sc.amplitude[0, mid] < 0.05 * amp) and np.all(sc.amplitude[2, mid] < 0.05 * amp)


def test_timefreq_bad_input():
    with pytest.raises(AnalysisError, match="too short"):
        spectrogram(np.zeros(100), 100.0, window_s=2.0)
    with pytest.raises(AnalysisError, match="too low"):
        spectrogram(np.zeros(1000), 100.0, fmax=80.0)
    with pytest.raises(AnalysisError, match="frequencies"):
        scalogram(np.zeros(1000), 100.0, frequencies=[60.0])
