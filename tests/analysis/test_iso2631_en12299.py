"""ISO 2631-1 and EN 12299: weighted rms of sines, MTVV/VDV/crest factor, C_c and N_MV."""

from __future__ import annotations

import math

import numpy as np
import pytest

from flexride.analysis import (
    cc_scale,
    comfort_band,
    continuous_comfort,
    crest_factor,
    iso2631_comfort,
    mean_comfort,
    mtvv,
    nmv_scale,
    rms,
    running_rms,
    vdv,
    vibration_total_value,
    weighted_rms,
    weighting_response,
)
from flexride.errors import AnalysisError

FS = 500.0


def sine(f0, amp, duration=60.0, fs=FS):
    t = np.arange(round(duration * fs)) / fs
    return amp * np.sin(2 * np.pi * f0 * t)


@pytest.mark.parametrize("weighting", ["Wk", "Wd", "Wb"])
@pytest.mark.parametrize("f0", [1.0, 2.5, 6.3, 16.0, 40.0])
@pytest.mark.parametrize("method", ["iir", "fft"])
def test_weighted_rms_of_sine(weighting, f0, method):
    """rms of a weighted sine = A/√2 · |W(f)| (whole record, start-up transient included)."""
    amp = 0.5
    expected = amp / math.sqrt(2) * abs(weighting_response(weighting, f0))
    res = weighted_rms(sine(f0, amp), FS, weighting, method=method)
    assert res.weighting == weighting and res.standard.startswith("ISO 2631")
    got = float(res)
    tol = 0.003 if method == "fft" or f0 <= 16 else 0.017  # iir at 500 Hz: see weighting docs
    assert got == pytest.approx(expected, rel=tol)


def test_weighted_rms_2d_and_unweighted():
    x = np.vstack([sine(4.0, 1.0, 20.0), sine(4.0, 2.0, 20.0)])
    w = weighted_rms(x, FS, "Wb")
    assert w.value[1] == pytest.approx(2 * w.value[0]) and "EN 12299" in w.standard
    assert rms(sine(4.0, 1.0, 20.0)) == pytest.approx(1 / math.sqrt(2), rel=1e-6)


def test_sine_mtvv_vdv_crest():
    amp, duration = 0.8, 20.0
    x = sine(5.0, amp, duration)
    assert mtvv(x, FS) == pytest.approx(amp / math.sqrt(2), rel=1e-6)
    assert vdv(x, FS) == pytest.approx((3 / 8 * amp**4 * duration) ** 0.25, rel=1e-6)
    assert crest_factor(x) == pytest.approx(math.sqrt(2), rel=1e-4)
    t, r = running_rms(np.full(1000, 2.0), FS, tau=1.0)
    assert r.shape == (501,) and np.allclose(r, 2.0) and t[0] == pytest.approx(499 / FS)


def test_iso2631_result_fields():
    x = sine(6.0, 0.6, 30.0)
    res = iso2631_comfort(x, FS, "Wk")
    expected = 0.6 / math.sqrt(2) * abs(weighting_response("Wk", 6.0))
    assert res.a_w == pytest.approx(expected, rel=3e-3)
    assert res.rms == pytest.approx(0.6 / math.sqrt(2), rel=1e-6)
    assert res.weighting == "Wk" and "ISO 2631-1" in res.standard and "Wk" in res.method
    assert res.basic_method_adequate and res.crest_factor < 9
    assert res.comfort == comfort_band(res.a_w)
    # a shock raises the crest factor beyond the basic method
    shock = np.zeros(round(30 * FS))
    shock[5000] = 50.0
    assert not iso2631_comfort(x * 0.01 + shock, FS, "Wk").basic_method_adequate
    assert "ISO 2631-4" in iso2631_comfort(x, FS, "Wb").standard


def test_comfort_bands_and_scales():
    assert comfort_band(0.2) == "not uncomfortable"
    assert comfort_band(0.4) == "a little uncomfortable"
    assert comfort_band(0.55) == "a little uncomfortable / fairly uncomfortable"
    assert comfort_band(0.9) == "fairly uncomfortable / uncomfortable"
    assert comfort_band(2.2) == "very uncomfortable / extremely uncomfortable"
    assert comfort_band(3.0) == "extremely uncomfortable"
    assert [cc_scale(v) for v in (0.1, 0.2, 0.35, 0.4)] == [
        "very comfortable", "comfortable", "medium", "less comfortable"]
    assert [nmv_scale(v) for v in (1.0, 1.5, 3.0, 4.0, 4.5)] == [
        "very comfortable", "comfortable", "medium", "uncomfortable", "very uncomfortable"]
    assert vibration_total_value(0.3, 0.4, 1.2) == pytest.approx(1.3)


@pytest.mark.parametrize(("direction", "weighting"), [("y", "Wd"), ("z", "Wb"), ("x", "Wd")])
def test_continuous_comfort_of_sine(direction, weighting):
    f0, amp = 2.0, 0.4  # 10 periods per 5 s window
    cc = continuous_comfort(sine(f0, amp, 30.0), FS, direction)
    expected = amp / math.sqrt(2) * abs(weighting_response(weighting, f0))
    assert cc.weighting == weighting and "EN 12299" in cc.standard
    assert cc.times[0] == pytest.approx(5.0) and np.diff(cc.times) == pytest.approx(1.0)
    assert cc.values[3:] == pytest.approx(expected, rel=2e-3)  # after the filter settles
    assert cc.scale == cc_scale(cc.maximum)


def test_mean_comfort_of_sines_full_window():
    fy, ay, fz, az = 1.0, 0.3, 5.0, 0.5
    y, z = sine(fy, ay, 300.0, 250.0), sine(fz, az, 300.0, 250.0)
    res = mean_comfort(250.0, y=y, z=z)
    a_y = ay / math.sqrt(2) * abs(weighting_response("Wd", fy))
    a_z = az / math.sqrt(2) * abs(weighting_response("Wb", fz))
    assert not res.short_run and len(res.windows) == 1 and res.windows[0]["n_blocks"] == 60
    assert res.value == pytest.approx(6 * math.sqrt(a_y**2 + a_z**2), rel=5e-3)
    assert res.directions_used == ["y", "z"] and "x taken as 0" in res.method
    assert res.scale == nmv_scale(res.value)


def test_mean_comfort_percentile_rule_and_windows():
    """Nearest rank: the 57th of 60 block values; one N_MV per complete 5 min window."""
    fs, nb = 250.0, 1250
    rng = np.random.default_rng(7)
    levels = np.concatenate([rng.permutation(np.arange(1, 61)),
                             2 * rng.permutation(np.arange(1, 61))])
    levels = np.concatenate([levels, [1.0] * 30])  # 150 s left over
    w = np.repeat(levels * 0.01, nb)  # block rms = level · 0.01 exactly (constant blocks)
    res = mean_comfort(fs, z=np.zeros_like(w), weighted={"z": w})
    assert [win["n_blocks"] for win in res.windows] == [60, 60]
    assert res.windows[0]["a_zp95"] == pytest.approx(0.57)
    assert res.windows[1]["a_zp95"] == pytest.approx(1.14)
    assert res.value == pytest.approx(6 * 1.14) and res.unused_s == pytest.approx(150.0)
    short = mean_comfort(fs, z=np.zeros(15 * nb),
                         weighted={"z": np.repeat(np.arange(1, 16) * 0.01, nb)})
    assert short.short_run and short.windows[0]["n_blocks"] == 15
    assert short.windows[0]["a_zp95"] == pytest.approx(0.15)  # < 20 blocks: the largest
    assert "SHORT RUN" in short.method


def test_iso_en_bad_input():
    with pytest.raises(AnalysisError, match="too short"):
        mtvv(np.zeros(100), FS)
    with pytest.raises(AnalysisError, match="too low"):
        weighted_rms(np.zeros(1000), 200.0, "Wk")
    with pytest.raises(AnalysisError, match="NaN"):
        iso2631_comfort(np.full(1000, np.nan), FS)
    with pytest.raises(AnalysisError, match="too short"):
        continuous_comfort(np.zeros(1000), FS, "z")
    with pytest.raises(AnalysisError, match="at least one"):
        mean_comfort(FS)
    with pytest.raises(AnalysisError, match="too short"):
        mean_comfort(FS, y=np.zeros(1000))
    with pytest.raises(AnalysisError, match="same length"):
        mean_comfort(FS, y=np.zeros(3000), z=np.zeros(3001))
    with pytest.raises(AnalysisError, match="weighting"):
        iso2631_comfort(np.zeros(1000), FS, "Bv")
