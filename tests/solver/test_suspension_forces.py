"""The recorded air-spring forces (channels ``secondary.<bogie><side>.force.<x|y|z>``) against
oracles independent of the force code: statics (the car body's weight and the lever rule) and
Newton's second law on the rigid car body, whose acceleration the solver records separately
(its velocity difference over each output interval, and its displacement)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from conftest import preset
from flexride.analysis import analyze
from flexride.bodies import PITCH, ROLL, YAW, Z, rigid_body
from flexride.results import Results
from flexride.solver.assemble import assemble, vehicle_for
from flexride.solver.simulate import simulate
from flexride.track.line_geometry import GRAVITY
from flexride.vehicle.topology import build_vehicle

SPRINGS = ("1L", "1R", "2L", "2R")
#: the flexible car body and frames of the other solver tests (coarse 0.5 m meshes: quick, and
#: the FE models are cached once for all of them)
FLEX = {"bodies.carbody.model": "flexible", "bodies.carbody.element_size_m": 0.5,
        "bodies.carbody.cutoff_hz": 30.0, "bodies.frames.model": "flexible",
        "bodies.frames.element_size_m": 0.5, "bodies.frames.cutoff_hz": 100.0}
#: every optional element between car body and frames fitted (none in the presets), so that
#: the Newton test sees every kind of element that acts on the car body
OPTIONAL = {"vehicle__optional__anti_roll_bar_stiffness": 2.0e6,
            "vehicle__optional__secondary_lateral_damper": 30.0e3,
            "vehicle__optional__yaw_damper": 100.0e3}


def _vertical(res: Results) -> dict[str, np.ndarray]:
    return {k: res.channels[f"secondary.{k}.force.z"] for k in SPRINGS}


def test_channels_are_named_by_stage_and_element_in_newtons():
    asm = assemble(preset(duration_s=0.1))
    names = [n for n in asm.channel_names if n.startswith("secondary.")]
    assert names == [f"secondary.{k}.force.{d}" for k in SPRINGS for d in "xyz"]
    units = dict(zip(asm.channel_names, asm.channel_units, strict=True))
    assert {units[n] for n in names} == {"N"}
    assert len(asm.channel_names) == asm.sys.par.n_ch == asm.sys.ch.shape[0]


@pytest.fixture(scope="module")
def perfect_track():
    """0.2 s on a perfect straight track: rigid, and the flexible FE car body and frames."""
    sc = preset(duration_s=0.2)
    assert not sc.excitation
    rigid = simulate(sc)
    flex_sc = preset(duration_s=0.2, **{k.replace(".", "__"): v for k, v in FLEX.items()})
    veh = vehicle_for(flex_sc)
    flex = simulate(flex_sc, vehicle=veh)
    return {"rigid": (rigid, sc.vehicle.carbody.mass), "flexible": (flex, veh.bodies[0].mass)}


@pytest.mark.parametrize("body", ["rigid", "flexible"])
def test_static_air_spring_forces_carry_the_car_body(perfect_track, body):
    """The four vertical forces sum to m_c·g (the run starts in static equilibrium: 1e-6 in the
    first output interval, 1e-4 while the wheelsets' rolling-resistance creep builds up), half
    on each bogie (the car body's CG midway between the bogies) and on each side."""
    res, m_c = perfect_track[body]
    f = _vertical(res)
    weight = m_c * GRAVITY
    total = sum(f.values())
    assert total[0] == pytest.approx(weight, rel=1e-6)
    assert np.max(np.abs(total / weight - 1.0)) < 1e-4
    front = f["1L"] + f["1R"]
    assert front[0] == pytest.approx(weight / 2.0, rel=1e-6)
    assert f["1L"][0] == pytest.approx(f["1R"][0], rel=1e-6)
    assert np.all(f["1L"] > 0.0)  # on the car body, vertical positive up
    # no lateral or longitudinal load on a perfect straight track worth speaking of
    for k in SPRINGS:
        for d in "xy":
            assert np.max(np.abs(res.channels[f"secondary.{k}.force.{d}"])) < 1e-3 * weight


def test_off_centre_car_body_splits_its_weight_by_the_lever_rule():
    """The car body's CG e = 0.8 m ahead of the centre: the front bogie carries
    W·(l_c + e)/(2·l_c). The car body then pitches, and the air springs' longitudinal stiffness
    adds forces at the air-spring height (0.6 m below the CG) whose moment shifts 4e-4 of the
    weight; with it the moment balance about the CG holds to 2e-5 of W·l_c in the first output
    interval. (The static equilibrium leaves the longitudinal coordinates alone: the 3 kN the
    pitched air springs then exert along x start the car body moving, and the balance drifts
    by 80 N·m per millisecond.)"""
    sc = preset(duration_s=0.05)
    cb = sc.vehicle.carbody
    e = 0.8
    body = rigid_body("carbody", cb.mass, (cb.ixx, cb.iyy, cb.izz), e, cb.cg_height)
    res = simulate(sc, vehicle=build_vehicle(sc.vehicle, sc.output, carbody=body))
    g = sc.vehicle.geometry
    lc = g.bogie_centre_spacing / 2.0
    weight = cb.mass * GRAVITY
    fz = {k: float(v[0]) for k, v in _vertical(res).items()}
    fx = {k: float(res.channels[f"secondary.{k}.force.x"][0]) for k in SPRINGS}
    front, rear = fz["1L"] + fz["1R"], fz["2L"] + fz["2R"]
    assert front + rear == pytest.approx(weight, rel=1e-6)
    assert front / weight == pytest.approx((lc + e) / (2 * lc), abs=1e-3)
    # moment about the CG (pitch, positive nose down for a force up at the front): the air
    # springs at x = ±l_c − e, z = h_s − h_cg
    rz = g.secondary_height - cb.cg_height
    moment = -(lc - e) * front + (lc + e) * rear + rz * sum(fx.values())
    assert abs(moment) < 1e-4 * weight * lc
    assert abs(front / weight - (lc + e) / (2 * lc)) > 1e-4  # the longitudinal part is seen


@pytest.fixture(scope="module")
def random_run():
    """1.5 s of the rigid vehicle with every optional element on the German high-disturbance
    irregularity, 80 km/h."""
    sc = preset("paper-metro-random", duration_s=1.5, **OPTIONAL)
    return sc, simulate(sc)


def test_car_body_elements_other_than_air_springs_are_vertical_free(random_run):
    """Which elements act on the car body, and that only the air springs load it vertically:
    the others (lateral dampers, anti-roll bars, yaw dampers where fitted) have no vertical
    translational rate, and rotational rates act on the rotation rows of the marker matrices,
    which have no entry in the vertical coordinate. (The traction link acts on x alone.)"""
    asm = assemble(random_run[0])
    veh, sysarr = asm.vehicle, asm.sys
    on_carbody = [(e, el) for e, el in enumerate(veh.elements) if 0 in (el.body_a, el.body_b)]
    kinds = {el.name.split(".")[0] for _, el in on_carbody}
    assert kinds == {"secondary", "anti_roll_bar", "lateral_damper", "yaw_damper"}
    carbody = veh.bodies[0]
    for e, el in on_carbody:
        assert el.body_a == 0  # the car body is body A: the channels' force acts on it
        if el.name.startswith("secondary."):
            assert sysarr.el_k[e, 2] > 0.0
            continue
        assert sysarr.el_k[e, 2] == 0.0 and sysarr.el_c[e, 2] == 0.0, el.name
        phi = carbody.markers[el.marker_a]
        assert np.all(phi[3:6, Z] == 0.0), el.name
    # the car body's vertical coordinate is moved only by vertical marker forces (row 2)
    for name, phi in carbody.markers.items():
        assert phi[2, Z] == 1.0 and phi[0, Z] == 0.0 and phi[1, Z] == 0.0, name
        assert {ROLL, PITCH, YAW} >= set(np.flatnonzero(phi[3:6].any(axis=0))), name


def test_newton_on_the_rigid_car_body(random_run):
    """m_c·a = Σ F_z(air springs) − m_c·g, sample by sample (the other elements on the car body
    are vertical-free, the test above; on straight track the frame's specific force is g).

    ``carbody.PC.acc.z`` (the floor centre lies above the CG: its vertical motion is the CG's)
    is the velocity difference over each output interval, the forces are the mean of the
    forces evaluated at the interval's steps. Through Zhai's velocity update (φ = ½) the
    velocity difference weighs the interval's accelerations from half a step earlier than the
    forces, so m·a − F = −½·Δt·d(m·a)/dt to second order; measured: raw 5.2e-4 of the dynamic
    rms, 2.6e-6 with the half-step term. The second difference of ``carbody.cg.disp.z`` (a
    triangular average over two intervals) against the mean of the two intervals' forces:
    5.3e-4 raw, 9e-5 with the half-step term.
    """
    sc, res = random_run
    m = sc.vehicle.carbody.mass
    dt = res.meta["dt"]
    T = 1.0 / res.sample_rate
    net = sum(_vertical(res).values()) - m * GRAVITY
    ma = m * res.channels["carbody.PC.acc.z"]
    keep = slice(100, -2)  # past the start transient; np.gradient's ends
    scale = np.sqrt(np.mean(ma[keep] ** 2))
    assert scale > 500.0  # N: a real dynamic load (1.5 kN rms at 80 km/h)
    r = ma - net
    lead = -0.5 * dt * np.gradient(ma, T)

    def rel(x):
        return np.sqrt(np.mean(x[keep] ** 2)) / scale

    assert rel(r) < 2e-3
    assert rel(r - lead) < 3e-5
    z = res.channels["carbody.cg.disp.z"]
    ma2 = np.full_like(z, np.nan)
    ma2[1:-1] = m * (z[2:] - 2 * z[1:-1] + z[:-2]) / T**2
    net2 = np.full_like(z, np.nan)
    net2[1:-1] = 0.5 * (net[1:-1] + net[2:])
    r2 = ma2 - net2
    assert rel(r2) < 2e-3
    assert rel(r2 + 0.5 * dt * np.gradient(ma2, T)) < 5e-4


def test_summary_and_results_file_carry_the_forces(random_run, tmp_path):
    """The analysis summary's suspension block equals NumPy on the channels; the channels go
    through the results file; the run's metadata is JSON and says the vehicle is rigid."""
    _, res = random_run
    summary = analyze(res).to_dict()
    block = summary["suspension"]
    assert sorted(block) == [f"secondary.{k}" for k in SPRINGS]
    f = res.channels["secondary.2R.force.z"]
    s = block["secondary.2R"]["z"]
    assert set(s) == {"mean", "rms_dynamic", "peak_dynamic", "max_abs"}
    assert s["mean"] == pytest.approx(np.mean(f), rel=1e-12)
    assert s["rms_dynamic"] == pytest.approx(np.std(f), rel=1e-9)
    assert s["peak_dynamic"] == pytest.approx(np.max(np.abs(f - np.mean(f))), rel=1e-12)
    assert s["max_abs"] == pytest.approx(np.max(np.abs(f)), rel=1e-12)
    assert res.meta["flexible_bodies"] == {}
    json.dumps(res.meta)
    back = Results.read_hdf5(res.write_hdf5(tmp_path / "run.h5"))
    assert set(back.channels) == set(res.channels)
    for k in SPRINGS:
        name = f"secondary.{k}.force.y"
        np.testing.assert_array_equal(back.channels[name], res.channels[name])
        assert back.units[name] == "N"


def test_flexible_bodies_in_the_run_metadata(perfect_track):
    """``meta["flexible_bodies"]``: element size and retained elastic frequencies of each
    flexible body, JSON as stored in job records."""
    res, _ = perfect_track["flexible"]
    facts = json.loads(json.dumps(res.meta))["flexible_bodies"]
    assert set(facts) == {"carbody", "frame1", "frame2"}
    cb = facts["carbody"]
    assert cb["model"] == "flexible" and cb["element_size_m"] == 0.5
    freqs = np.array(cb["elastic_frequencies_hz"])
    assert freqs.size > 5 and np.all(np.diff(freqs) >= 0.0) and 3.0 < freqs[0] < 30.0
    assert np.all(freqs <= 30.0 * 1.0001)  # the cut-off
    assert facts["frame1"]["element_size_m"] == 0.1  # the frames' rule: min(size/2, 0.1)
    assert facts["frame1"]["elastic_frequencies_hz"] == facts["frame2"]["elastic_frequencies_hz"]
