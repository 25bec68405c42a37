"""Time-step convergence of the car-body response: the step ``solver.dt: auto`` chooses
(the presets' default) against half of it."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import preset
from flexride.solver.simulate import simulate


@pytest.mark.parametrize(("name", "contact", "seconds"), [
    ("paper-metro-random", "conical", 4.0), ("paper-metro-random", "profiles", 2.0),
    ("paper-random-curve-80", "profiles", 6.0)])
def test_auto_step_is_converged(name, contact, seconds):
    """The conical tread and real profiles (S1002/60E1), straight and into the curve (its
    limit is the smaller of steady rolling and steady curving): the car-body rms at the
    automatic step within 1 % of half of it."""
    base = {"duration_s": seconds, "distance_m": None, "output.rate_hz": 1000.0,
            "contact.geometry": contact}
    a = simulate(preset(name, **base))
    assert a.meta["stability"]["auto"] and a.meta["stability"]["margin"] >= 1.25
    b = simulate(preset(name, **base, **{"solver.dt": a.meta["dt"] / 2}))
    for ch in ("carbody.PC.acc.z", "carbody.PR.acc.z", "carbody.PC.acc.y"):
        ra = np.sqrt(np.mean(a.channels[ch] ** 2))
        rb = np.sqrt(np.mean(b.channels[ch] ** 2))
        assert ra == pytest.approx(rb, rel=0.01), ch


def test_presets_step_keeps_the_creep_force_quiet_on_a_perfect_track():
    """The discrete map of Zhai's update with the relaxed creep forces has rail-torsion modes
    under the wheels that grow from Δt ≈ 8.0e-5 s with real profiles: at 1/12000 s a 6 kHz
    oscillation of the lateral creep force builds up on a perfect track within milliseconds
    (step-to-step jumps of 1.9 kN). At the automatic step (here 1/16000 s, the output rate's
    interval) the forces stay smooth (0.09 N)."""
    sc = preset("paper-random-straight-80", distance_m=None, duration_s=0.05, excitation=[],
                **{"output.rate_hz": 16000.0})
    res = simulate(sc)
    assert res.meta["dt"] == pytest.approx(1.0 / 16000.0)
    start = int(0.01 * res.sample_rate)
    forces = [n for n in res.channels if n.startswith("wheelset") and n.endswith(".force.y")]
    assert len(forces) == 8
    jump = max(float(np.abs(np.diff(res.channels[n][start:])).max()) for n in forces)
    assert jump < 1.0


def test_presets_step_is_converged_for_small_irregularities():
    """Irregularity at 1 % of the presets' (σ of the wheels' Δy ≈ 30 µm, the contact near its
    centred position): the lateral car-body rms at the automatic step within 1 % of half of it
    (1/12000 s was 25 % low: the creep oscillation above saturates the creep)."""
    base = {"distance_m": None, "duration_s": 8.0, "excitation.0.scale": 0.01}
    a = simulate(preset("paper-random-straight-80", **base))
    b = simulate(preset("paper-random-straight-80", **base, **{"solver.dt": a.meta["dt"] / 2}))
    skip = int(2.0 * a.sample_rate)
    for ch in ("carbody.PC.acc.y", "carbody.PR.acc.y", "wheelset1.cg.disp.y"):
        ra = float(np.std(a.channels[ch][skip:]))
        rb = float(np.std(b.channels[ch][skip:]))
        assert ra == pytest.approx(rb, rel=0.01), ch
