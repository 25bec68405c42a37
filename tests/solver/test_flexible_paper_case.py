"""The paper's straight-track random case with the flexible car body and frames from the
finite-element models (coarse 0.5 m mesh to keep the test quick; the default is 0.2 m)."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import preset
from flexride.solver import simulate
from flexride.solver.assemble import vehicle_for

FLEX = {"bodies.carbody.model": "flexible", "bodies.carbody.element_size_m": 0.5,
        "bodies.carbody.cutoff_hz": 30.0, "bodies.frames.model": "flexible",
        "bodies.frames.element_size_m": 0.5, "bodies.frames.cutoff_hz": 100.0}


@pytest.fixture(scope="module")
def runs():
    base = {"distance_m": None, "duration_s": 10.0}
    flex_sc = preset("paper-random-straight-80", **base, **FLEX)
    veh = vehicle_for(flex_sc)
    flex = simulate(flex_sc, vehicle=veh)
    rigid = simulate(preset("paper-random-straight-80", **base))
    return flex, rigid, veh.bodies[0].elastic_frequencies


def _amp(x, fs):
    w = np.hanning(x.size)
    return np.fft.rfftfreq(x.size, 1 / fs), 2 * np.abs(np.fft.rfft(x * w)) / w.sum()


def test_elastic_modes_appear_in_the_car_body_spectra(runs):
    """Around the first car-body modes (5–9 Hz) the flexible roof response is well above the
    rigid one; elsewhere (< 3 Hz, rigid-body modes) both are alike."""
    flex, rigid, freqs = runs
    f, a_f = _amp(flex.channels["carbody.PR.acc.z"], flex.sample_rate)
    _, a_r = _amp(rigid.channels["carbody.PR.acc.z"], rigid.sample_rate)
    band = (f > freqs[0] - 0.5) & (f < 9.5)
    assert a_f[band].sum() > 2.0 * a_r[band].sum()
    low = (f > 0.5) & (f < 3.0)
    assert a_f[low].sum() == pytest.approx(a_r[low].sum(), rel=0.35)


def test_flexible_model_gives_higher_car_body_accelerations(runs):
    """Paper §3 / Table 2: car-body accelerations of the flexible model exceed the rigid one."""
    flex, rigid, _ = runs
    for point in ("PR", "PFB", "PC", "PRB", "PLA", "PRA"):
        x = flex.channels[f"carbody.{point}.acc.z"]
        y = rigid.channels[f"carbody.{point}.acc.z"]
        assert np.sqrt(np.mean(x**2)) > np.sqrt(np.mean(y**2)), point


def test_roof_vibrates_most(runs):
    """Paper §5.1: the roof point PR has the largest vertical acceleration."""
    flex, _, _ = runs
    rms = {p: np.sqrt(np.mean(flex.channels[f"carbody.{p}.acc.z"] ** 2))
           for p in ("PR", "PFB", "PC", "PRB")}
    assert max(rms, key=rms.get) == "PR"
