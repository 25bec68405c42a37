"""Small readers of an estimate: the rms over a frequency band of a response PSD and the
coupled eigenmode a coordinate dominates."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import preset
from flexride.frequency import estimate
from flexride.frequency.modes import mode_of


@pytest.fixture(scope="module")
def rigid():
    """The frequency-domain estimate of the paper's random straight case at 80 km/h."""
    return estimate(preset("paper-random-straight-80"), points=["PC"])


def test_band_rms_adds_up_to_the_rms(rigid):
    """Over the whole grid the band rms is the channel's rms; two adjacent bands add in
    quadrature (the shared grid point's trapezoid halves on both sides)."""
    resp = rigid.response
    ch = "carbody.PC.acc.z"
    f = resp.frequencies
    total = float(np.sqrt(resp.variance()[resp.index(ch)]))
    assert resp.band_rms(ch, f[0], f[-1]) == pytest.approx(total, rel=1e-12)
    split = float(f[np.searchsorted(f, 3.0)])
    low, high = resp.band_rms(ch, f[0], split), resp.band_rms(ch, split, f[-1])
    assert np.hypot(low, high) == pytest.approx(total, rel=1e-12)


def test_mode_of_finds_the_car_body_bounce(rigid):
    """The car body's bounce coordinate dominates one mode near 1 Hz (a sprung mass of 35 t on
    four air springs of 342 kN/m in series with the primary springs); a coordinate that
    dominates nothing is an error."""
    bounce = mode_of(rigid.model.mode_info, "carbody.z")
    assert 0.5 < bounce.frequency_hz < 1.5
    assert dict(bounce.dominant)["carbody.z"] > 0.5
    with pytest.raises(ValueError, match="dominates no eigenmode"):
        mode_of(rigid.model.mode_info, "carbody.mode1")
