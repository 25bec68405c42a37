"""Weighting filters: the digital realisations against the analogue definitions."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import signal

from flexride.analysis import (
    WEIGHTINGS,
    apply_weighting,
    weighting_response,
    weighting_sos,
    weighting_zpk,
)
from flexride.errors import AnalysisError

NAMES = ("Wk", "Wd", "Wb", "Bv", "Bh")
F_LOW = np.geomspace(0.5, 40.0, 300)
F_HIGH = np.geomspace(40.0, 80.0, 100)

# (fs, band) -> (max relative magnitude error, max phase error in degrees)
TOLERANCES = {
    (2000.0, "low"): (0.002, 0.3),
    (2000.0, "high"): (0.006, 0.4),
    (1000.0, "low"): (0.006, 1.1),
    (1000.0, "high"): (0.022, 1.5),
}


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("fs", [1000.0, 2000.0])
def test_digital_matches_analogue(name, fs):
    """Magnitude and phase of the realised filter within the stated tolerances, 0.5–80 Hz."""
    sos = weighting_sos(name, fs)
    for band, f in (("low", F_LOW), ("high", F_HIGH)):
        _, hd = signal.sosfreqz(sos, worN=f, fs=fs)
        ha = weighting_response(name, f)
        ratio = hd / ha
        mag_tol, ph_tol = TOLERANCES[(fs, band)]
        assert np.max(np.abs(np.abs(ratio) - 1.0)) < mag_tol, (name, fs, band)
        assert np.max(np.abs(np.degrees(np.angle(ratio)))) < ph_tol, (name, fs, band)


@pytest.mark.parametrize("name", NAMES)
def test_zpk_is_the_formula(name):
    f = np.geomspace(0.01, 500.0, 400)
    z, p, k = weighting_zpk(name)
    _, h = signal.freqs_zpk(z, p, k, worN=2 * np.pi * f)
    np.testing.assert_allclose(h, weighting_response(name, f), rtol=1e-10)
    assert np.all(p.real < 0.0)  # stable analogue filter


def test_iso_table_values():
    """Independent oracle: ISO 2631-1:1997 Table 3 weighting factors (× 1000)."""
    wk = {0.5: 418, 1.0: 482, 2.0: 531, 4.0: 967, 5.0: 1039, 6.3: 1054, 8.0: 1036, 10.0: 988,
          12.5: 902, 16.0: 768, 20.0: 636, 25.0: 513, 31.5: 405, 40.0: 314, 50.0: 246,
          63.0: 186, 80.0: 132}
    wd = {0.5: 853, 1.0: 1011, 2.0: 890, 4.0: 512}
    for name, table in (("Wk", wk), ("Wd", wd)):
        f = np.array(list(table))
        got = np.abs(weighting_response(name, f)) * 1000.0
        np.testing.assert_allclose(got, list(table.values()), rtol=0.006, atol=1.0)


def test_sperling_b_magnitude_is_design_formula():
    f = np.geomspace(0.1, 100.0, 200)
    bv = 0.588 * np.sqrt((1.911 * f**2 + (0.25 * f**2) ** 2)
                         / ((1 - 0.2777 * f**2) ** 2 + (1.563 * f - 0.0368 * f**3) ** 2))
    np.testing.assert_allclose(np.abs(weighting_response("Bv", f)), bv, rtol=1e-12)
    np.testing.assert_allclose(np.abs(weighting_response("Bh", f)), 1.25 * bv, rtol=1e-12)


def _slope(name, f1, f2, fs=None):
    f = np.array([f1, f2])
    if fs is None:
        h = np.abs(weighting_response(name, f))
    else:
        _, h = signal.sosfreqz(weighting_sos(name, fs), worN=f, fs=fs)
        h = np.abs(h)
    return np.log(h[1] / h[0]) / np.log(f2 / f1)


@pytest.mark.parametrize(
    ("name", "f1", "f2", "slope", "tol"),
    [
        ("Wk", 0.005, 0.01, 2.0, 0.01),    # band-limiting high pass: +40 dB/decade
        ("Wd", 0.005, 0.01, 2.0, 0.01),
        ("Wb", 0.005, 0.01, 2.0, 0.01),
        ("Wk", 2e3, 4e3, -3.0, 0.02),     # 1/f of Ht times the 100 Hz low pass: −60 dB/dec
        ("Wd", 2e3, 4e3, -3.0, 0.02),
        ("Wd", 15.0, 30.0, -1.0, 0.03),   # acceleration → velocity: −20 dB/decade
        ("Wk", 30.0, 50.0, -1.0, 0.15),
        ("Bv", 0.005, 0.01, 1.0, 0.01),   # Sperling B: ∝ f at low, ∝ 1/f at high frequency
        ("Bv", 500.0, 1000.0, -1.0, 0.02),
    ],
)
def test_asymptotic_slopes(name, f1, f2, slope, tol):
    assert _slope(name, f1, f2) == pytest.approx(slope, abs=tol)
    if f2 < 100.0:  # the digital filter follows inside its band
        assert _slope(name, f1, f2, fs=2000.0) == pytest.approx(slope, abs=tol + 0.01)


def test_wd_has_no_step_and_wb_gain():
    assert np.isinf(WEIGHTINGS["Wd"].f5)
    assert WEIGHTINGS["Wb"].k == pytest.approx(1.024)


@pytest.mark.parametrize("method", ["iir", "fft"])
def test_apply_weighting_sine_and_2d(method):
    fs, f0, amp = 1000.0, 8.0, 0.7
    t = np.arange(round(20 * fs)) / fs
    x = amp * np.sin(2 * np.pi * f0 * t)
    y = apply_weighting(np.vstack([x, 2 * x]), fs, "Wk", method=method)
    mid = slice(round(5 * fs), round(15 * fs))
    expected = amp / np.sqrt(2) * abs(weighting_response("Wk", f0))
    assert np.sqrt(np.mean(y[0, mid] ** 2)) == pytest.approx(expected, rel=2e-3)
    np.testing.assert_allclose(y[1], 2 * y[0], rtol=1e-9, atol=1e-12)


def test_bad_input():
    with pytest.raises(AnalysisError, match="unknown weighting"):
        weighting_sos("Wx", 1000.0)
    with pytest.raises(AnalysisError, match="too low"):
        weighting_sos("Wk", 200.0)
    with pytest.raises(AnalysisError, match="NaN"):
        apply_weighting(np.array([0.0, np.nan, 1.0]), 1000.0, "Wd")
    with pytest.raises(AnalysisError, match="empty"):
        apply_weighting(np.array([]), 1000.0, "Wd")
    with pytest.raises(AnalysisError, match="sample rate"):
        apply_weighting(np.zeros(10), -5.0, "Wd")
    with pytest.raises(AnalysisError, match="method"):
        apply_weighting(np.zeros(10), 1000.0, "Wd", method="magic")
