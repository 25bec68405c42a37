"""The measures the claims are judged by, against hand-made values."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from flexride.paper import measures


def test_mean_ci_is_student_t():
    est = measures.mean_ci([1.0, 2.0, 3.0])
    assert est.mean == pytest.approx(2.0)
    assert est.ci95 == pytest.approx(stats.t.ppf(0.975, 2) * 1.0 / math.sqrt(3.0))
    assert est.n == 3
    single = measures.mean_ci([1.5])
    assert single.ci95 is None and single.to_dict() == {"value": 1.5, "ci95": None, "n": 1}


def test_band_rms_and_share_of_a_flat_spectrum():
    f = np.arange(0.0, 50.0, 0.125)
    p = np.full_like(f, 2.0)  # (m/s²)²/Hz
    assert measures.band_rms(f, p, 4.0, 10.0) == pytest.approx(math.sqrt(2.0 * 6.0))
    share = measures.band_share(f, p, [(0.0, 2.5), (6.0, 9.0)], (0.0, 20.0))
    assert share == pytest.approx(5.5 / 20.0)


def _psd_with_lines(lines: dict[float, float]) -> tuple[np.ndarray, np.ndarray]:
    f = np.arange(0.0, 100.0, 0.125)
    p = np.full_like(f, 1e-4)
    for f0, height in lines.items():
        p += height * np.exp(-0.5 * ((f - f0) / 0.2) ** 2)
    return f, p


def test_spectral_peaks_finds_the_lines_most_prominent_first():
    f, p = _psd_with_lines({6.3: 1e-2, 17.6: 1e-3, 44.4: 3e-2})
    peaks = measures.spectral_peaks(f, p, (0.3, 100.0))
    assert peaks[0] == pytest.approx(44.4, abs=0.07)
    assert sorted(peaks) == [pytest.approx(x, abs=0.07) for x in (6.3, 17.6, 44.4)]
    assert measures.spectral_peaks(f, p, (10.0, 20.0)) == [pytest.approx(17.6, abs=0.07)]


def test_peak_dominance_of_one_line_and_of_broadband_noise():
    f, p = _psd_with_lines({0.95: 1.0})
    f_peak, share = measures.peak_dominance(f, p, (0.3, 20.0))
    assert f_peak == pytest.approx(0.95, abs=0.07) and share > 0.8  # Gaussian line, σ = 0.2 Hz
    flat = np.ones_like(f)
    _, share_flat = measures.peak_dominance(f, flat, (0.3, 20.0))
    assert share_flat < 0.05


def test_line_fit_of_exact_linear_data_has_r2_one():
    speeds = [50.0, 60.0, 70.0, 80.0]
    fit = measures.line_fit(speeds, [0.02 * v - 0.3 for v in speeds])
    assert fit["slope"] == pytest.approx(0.02)
    assert fit["intercept"] == pytest.approx(-0.3)
    assert fit["r_squared"] == pytest.approx(1.0)
    curved = measures.line_fit(speeds, [1.0, 0.0, 0.0, 1.0])
    assert curved["r_squared"] == pytest.approx(0.0)


def test_lag_of_a_shifted_signal():
    fs = 200.0
    rng = np.random.default_rng(3)
    a = rng.standard_normal(4000)
    shift = 114  # samples: 0.57 s
    b = np.roll(a, shift)  # b(t) = a(t − 0.57 s): b lags a
    assert measures.lag_at_max(a, b, fs) == pytest.approx(0.57, abs=1e-3)
    assert measures.lag_at_max(b, a, fs) == pytest.approx(-0.57, abs=1e-3)
