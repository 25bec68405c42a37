"""Cross-correlation (delay of a copy, local maxima) and statistics (peaks, regression)."""

from __future__ import annotations

import numpy as np
import pytest

from flexride.analysis import (
    cross_correlation,
    cross_correlations,
    linear_regression,
    peak_statistics,
    regress_on_speed,
)
from flexride.errors import AnalysisError

FS = 100.0


def noise(n, seed=0):
    rng = np.random.default_rng(seed)
    spec = np.fft.rfft(rng.standard_normal(n))
    spec[np.fft.rfftfreq(n, 1 / FS) > 15.0] = 0.0  # smooth, band-limited
    return np.fft.irfft(spec, n)


@pytest.mark.parametrize("delay", [57, -23, 0])
def test_delayed_copy_returns_delay(delay):
    a = noise(6000)
    b = np.roll(a, delay)  # b(t) = a(t − delay/fs)
    r = cross_correlation(a, b, FS)
    assert r.lag_at_max == pytest.approx(delay / FS)
    assert r.lag_at_max_interpolated == pytest.approx(delay / FS, abs=1e-3)
    assert r.normalised_at_max == pytest.approx(1.0, abs=0.02)
    assert any(m["lag"] == pytest.approx(delay / FS) for m in r.local_maxima)
    assert r.raw.size == r.lags.size == 2 * a.size - 1


def test_paper_sign_convention():
    """A front point leads: R(rear, front) peaks at a negative lag (paper Fig. 26: −0.57 s)."""
    front = noise(6000, seed=3)
    rear = np.roll(front, 57)  # the rear point sees the same excitation 0.57 s later
    assert cross_correlation(rear, front, FS).lag_at_max == pytest.approx(-0.57)
    assert cross_correlation(front, rear, FS).lag_at_max == pytest.approx(0.57)


def test_two_paths_give_two_local_maxima():
    a = np.random.default_rng(1).standard_normal(8000)  # white: narrow correlation peaks
    b = 0.5 * np.roll(a, 10) + np.roll(a, 120)
    r = cross_correlation(a, b, FS, max_lag_s=3.0, min_prominence=0.1)
    lags = sorted(m["lag"] for m in r.local_maxima)
    assert lags == pytest.approx([0.1, 1.2], abs=0.011)
    assert r.lag_at_max == pytest.approx(1.2)
    assert np.all(np.abs(r.lags) <= 3.0 + 1e-9)


def test_subsample_delay_interpolated():
    n = 4096
    a = noise(n, seed=2)
    shift = 7.4  # samples, by a phase shift in the frequency domain
    f = np.fft.rfftfreq(n)
    b = np.fft.irfft(np.fft.rfft(a) * np.exp(-2j * np.pi * f * shift), n)
    r = cross_correlation(a, b, FS)
    assert r.lag_at_max == pytest.approx(7 / FS)
    assert r.lag_at_max_interpolated == pytest.approx(shift / FS, abs=0.1 / FS)


def test_batched_equals_single():
    a = noise(3000, seed=4)
    others = np.vstack([np.roll(a, 30), noise(3000, seed=5), np.roll(a, -12)])
    many = cross_correlations(a, others, FS, max_lag_s=2.0)
    for k in range(3):
        one = cross_correlation(a, others[k], FS, max_lag_s=2.0)
        np.testing.assert_allclose(many[k].raw, one.raw, atol=1e-9 * np.max(np.abs(one.raw)))
        assert many[k].lag_at_max == one.lag_at_max
        assert many[k].normalised_at_max == pytest.approx(one.normalised_at_max)


def test_correlation_bad_input():
    with pytest.raises(AnalysisError, match="empty"):
        cross_correlation([], [1.0, 2.0], FS)
    with pytest.raises(AnalysisError, match="NaN"):
        cross_correlation([1.0, np.nan, 3.0], [1.0, 2.0, 3.0], FS)
    with pytest.raises(AnalysisError, match="dimension"):
        cross_correlation(np.zeros((2, 5)), np.zeros(5), FS)
    with pytest.raises(AnalysisError, match="equal length"):
        cross_correlations(np.zeros(5), np.zeros((2, 6)), FS, max_lag_s=1.0)


def test_peak_statistics():
    x = np.array([0.0, 1.0, -3.0, 2.0, 0.5])
    ps = peak_statistics(x, 10.0, t0=1.0, unit="m/s^2")
    assert ps.max_abs == 3.0 and ps.time_of_max_abs == pytest.approx(1.2)
    assert ps.max == 2.0 and ps.min == -3.0 and ps.peak_to_peak == 5.0
    assert ps.rms == pytest.approx(np.sqrt(np.mean(x**2)))
    assert ps.mean == pytest.approx(0.1) and ps.n == 5
    two = peak_statistics(np.vstack([x, 2 * x]), 10.0)
    np.testing.assert_allclose(two.max_abs, [3.0, 6.0])


def test_regression_exact_and_noisy():
    v = np.array([50.0, 60.0, 70.0, 80.0])
    fit = regress_on_speed(v, 0.02 * v - 0.4, value_unit="m/s^2")
    assert fit.r_squared == pytest.approx(1.0, abs=1e-12)
    assert fit.slope == pytest.approx(0.02) and fit.intercept == pytest.approx(-0.4)
    assert fit.x_unit == "km/h" and fit.predict(100.0) == pytest.approx(1.6)
    noisy = linear_regression(v, 0.02 * v + np.array([0.05, -0.05, 0.05, -0.05]))
    assert 0.0 < noisy.r_squared < 1.0
    flat = linear_regression(v, np.full(4, 2.0))
    assert flat.slope == pytest.approx(0.0, abs=1e-12) and flat.r_squared == 1.0


def test_regression_bad_input():
    with pytest.raises(AnalysisError, match="at least 2"):
        linear_regression([1.0], [2.0])
    with pytest.raises(AnalysisError, match="different x"):
        linear_regression([1.0, 1.0], [2.0, 3.0])
    with pytest.raises(AnalysisError, match="length"):
        linear_regression([1.0, 2.0, 3.0], [2.0, 3.0])
    with pytest.raises(AnalysisError, match="NaN"):
        linear_regression([1.0, 2.0], [np.nan, 3.0])
