"""Spatial → temporal PSD conversion against the time-domain generator: the band integral of the
temporal PSD is the band variance of the spatial one, and a synthetic profile from
:func:`flexride.track.spectra.random_profile`, sampled in time at the running speed, has that
variance and that PSD."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import integrate, signal

from flexride.frequency.track_input import RandomInput, rail_map
from flexride.track.spectra import band_rms, random_profile

SPEED = 80 / 3.6
INP = RandomInput("german-high", ("vertical", "alignment", "cross_level", "gauge"), 1.0, 120.0)


@pytest.mark.parametrize("component", ["vertical", "alignment", "cross_level", "gauge"])
def test_band_integral_is_the_spatial_band_variance(component):
    lo, hi = SPEED / 120.0, SPEED / 1.0
    var, _ = integrate.quad(lambda f: float(INP.temporal_psd(component, np.array([f]), SPEED,
                                                             0.75)[0]),
                            lo, hi, limit=400, epsrel=1e-10, points=[lo * 2, lo * 10])
    assert var == pytest.approx(band_rms("high", component, 1.0, 120.0) ** 2, rel=1e-7)
    assert INP.temporal_psd(component, np.array([0.9 * lo, 1.1 * hi]), SPEED, 0.75).max() == 0


def _expected_relative_scatter(length_m: float, component: str) -> float:
    """Relative std of the variance of one realisation: the synthesis gives every Fourier line
    of the period an independent χ²₂ energy, so std/mean = √ΣE_k² / ΣE_k."""
    d_om = 2 * np.pi / length_m
    om = np.arange(1, int(2 * np.pi / d_om) + 2) * d_om
    om = om[(om >= 2 * np.pi / 120) & (om <= 2 * np.pi)]
    from flexride.track.spectra import german_psd
    e = german_psd(om, component, "high") * d_om
    return float(np.sqrt(np.sum(e**2)) / np.sum(e))


@pytest.mark.parametrize("component", ["vertical", "alignment", "cross_level", "gauge"])
def test_synthetic_profile_variance_and_psd_in_time(component):
    length = 30_000.0
    prof = random_profile(length, "high", [component], 1.0, 120.0, seed=7, ds=0.05,
                          fade_in_m=0.0)
    b = 0.75
    zl, zr, yl, yr = prof.rails()
    value = {"vertical": 0.5 * (zl + zr), "cross_level": (zl - zr) / (2 * b),
             "alignment": 0.5 * (yl + yr), "gauge": yl - yr}[component]
    fs = 100.0
    t = np.arange(0.0, (length - 1.0) / SPEED, 1.0 / fs)
    x = np.interp(SPEED * t, prof.s, value)  # what a wheel sees, sampled in time
    tol = 4 * _expected_relative_scatter(prof.n * prof.ds, component)
    expected_var = band_rms("high", component, 1.0, 120.0) ** 2
    assert np.var(x) == pytest.approx(expected_var, rel=max(tol, 0.02))
    f, g = signal.welch(x, fs=fs, nperseg=8192)
    band = (f > 2 * SPEED / 120) & (f < 0.8 * SPEED)
    ratio = g[band] / INP.temporal_psd(component, f[band], SPEED, b)
    # Welch averages ≈ 70 segments: ±25 % per line, the mean of many lines within 5 %
    assert np.median(ratio) == pytest.approx(1.0, abs=0.05)
    assert np.percentile(ratio, 5) > 0.6 and np.percentile(ratio, 95) < 1.5


def test_rail_map_matches_the_synthesis_mapping():
    """z_left = z_v + b·c, z_right = z_v − b·c, y_left = y_a + g/2, y_right = y_a − g/2."""
    b = 0.75
    np.testing.assert_allclose(rail_map("vertical", b), [1, 1, 0, 0])
    np.testing.assert_allclose(rail_map("cross_level", b), [b, -b, 0, 0])
    np.testing.assert_allclose(rail_map("alignment", b), [0, 0, 1, 1])
    np.testing.assert_allclose(rail_map("gauge", b), [0, 0, 0.5, -0.5])
    for comp in ("vertical", "cross_level", "alignment", "gauge"):
        prof = random_profile(200.0, "high", [comp], seed=3, fade_in_m=0.0)
        zl, zr, yl, yr = prof.rails()
        m = rail_map(comp, b)
        k = int(np.argmax(np.abs(m)))
        unit = prof.rails()[k] / m[k]
        np.testing.assert_allclose(np.vstack([zl, zr, yl, yr]), np.outer(m, unit), atol=1e-15)
