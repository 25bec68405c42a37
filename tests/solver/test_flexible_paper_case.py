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


def test_floor_centre_ratio_moves_to_the_rigid_value_as_the_car_body_stiffens(runs):
    """PC/PFB (rms vertical) falls from the default body through a stiffer body towards the
    rigid body's value: the floor-centre excess comes from the low elastic modes with a mid-floor
    antinode (docs/fem.md, "Floor centre vs above the bogies"). Stiff limit = rigid is the
    oracle; the paper's "PC smallest" is not asserted (it depends on mode shapes we lack)."""
    from flexride.fem.defaults import default_carbody_params
    from flexride.fem.flexible import build_flexible_body
    from flexride.vehicle.topology import build_vehicle

    flex, rigid, _ = runs
    sc = preset("paper-random-straight-80", distance_m=None, duration_s=10.0)
    stiff_params = default_carbody_params().with_values(
        floor_depth=0.08, beam_scale=2.0, nsm_underfloor=0.35, wall_depth=0.04, roof_depth=0.03)
    body = build_flexible_body("carbody", sc.vehicle, "modal", 30.0, 0.02, 0.5,
                               params=stiff_params).body
    stiff = simulate(sc, vehicle=build_vehicle(sc.vehicle, sc.output, carbody=body))

    def ratio(res):
        rms = [np.sqrt(np.mean(res.channels[f"carbody.{p}.acc.z"] ** 2)) for p in ("PC", "PFB")]
        return rms[0] / rms[1]

    r_default, r_stiff, r_rigid = ratio(flex), ratio(stiff), ratio(rigid)
    assert r_default > r_stiff > r_rigid
    assert r_rigid < 0.8  # rigid pitch adds above the bogies
