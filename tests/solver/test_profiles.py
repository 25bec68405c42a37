"""Real wheel and rail profiles in the solver (S1002 on 60E1 at 1:40, two contact slots per
wheel), against oracles independent of the contact code: Klingel's kinematic wavelength with
the EN 15302 equivalent conicity at the oscillation's amplitude, the quasi-static curving
balance V²/R·cos θ − g·sin θ, and the flange root of the leading outer wheel on a curve."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import PROFILES, preset
from flexride.contact.conicity import equivalent_conicity
from flexride.solver.assemble import assemble
from flexride.solver.setup_cache import default_cache
from flexride.solver.simulate import integrate, prepare_run, simulate


def _crossings(s, y):
    sign = np.signbit(y)
    idx = np.nonzero(sign[1:] != sign[:-1])[0]
    return s[idx] - y[idx] * (s[idx + 1] - s[idx]) / (y[idx + 1] - y[idx])


def test_kinematic_wavelength_matches_klingel_with_equivalent_conicity():
    """Free wheelsets (primary suspension free in x and y) at 18 km/h, started 3 mm off centre:
    every period of the lateral oscillation of the leading wheelset has Klingel's wavelength
    2π·√(r0·b0/tan γe(ŷ)) with the equivalent conicity (EN 15302 integration of the table's
    Δr(y) with kinematic roll) at that period's amplitude ŷ, within 5 %."""
    sc = preset("paper-metro", speed_kmh=18.0, duration_s=4.5, **PROFILES,
                **{"vehicle.primary.kx": 1.0e3, "vehicle.primary.ky": 0.0,
                   "vehicle.primary.cx": 0.0, "vehicle.primary.cy": 0.0})
    asm, ready = prepare_run(sc, assemble(sc), default_cache(), check=False)
    table = asm.profiles
    assert table is not None
    X0 = ready.X0
    Xi = X0.copy()
    for w in asm.vehicle.wheelsets:
        Xi[asm.sys.body_off[w] + 1] = 0.003
    res = integrate(asm, Xi, np.zeros_like(Xi), sc, lambda f, m: None, X_ref=X0)
    y = res.channels["wheelset1.cg.disp.y"]
    s = res.distance
    xs = _crossings(s, y)
    assert xs.size >= 4
    rigid = table.single_table()
    delta_r = rigid.r[0] - rigid.r[1]
    r0 = sc.vehicle.geometry.wheel_radius
    for k in range(xs.size - 2):
        period = (s > xs[k]) & (s < xs[k + 2])
        amp = 0.5 * float(y[period].max() - y[period].min())
        cone = float(equivalent_conicity(table.y_grid, delta_r, [amp])[0])
        klingel = 2 * np.pi * np.sqrt(r0 * table.b0 / cone)
        assert xs[k + 2] - xs[k] == pytest.approx(klingel, rel=0.05), (k, amp, cone)


CURVE = {"kind": "curve", "radius_m": 800.0, "direction": "left", "superelevation_m": 0.095,
         "entry_transition_m": 55.0, "exit_transition_m": 55.0, "arc_length_m": 160.0,
         "start_m": 30.0}


def test_curving_on_real_profiles():
    """R = 800 m, 95 mm cant, 100 km/h: the car body's track-plane lateral acceleration in the
    arc is V²/R·cos θ − g·sin θ within 5 %; the leading wheelset runs toward the outer (right)
    rail into two-point contact, its outer wheel's flange root loaded at a contact angle beyond
    the tread's, while the trailing wheelset of the bogie stays on the treads."""
    sc = preset("paper-metro", line=CURVE, speed_kmh=100.0, duration_s=None, distance_m=250.0,
                **PROFILES)
    res = simulate(sc)
    s = res.distance
    arc = (s > 30 + 55 + 60) & (s < 30 + 55 + 160 - 10)
    g = 9.81
    c = res.channels
    acc = c["carbody.PC.acc.y"] - g * c["carbody.cg.rot.x"]
    v = 100.0 / 3.6
    theta = np.arcsin(0.095 / 1.5)
    exact = v**2 / 800 * np.cos(theta) - g * np.sin(theta)
    assert float(np.mean(acc[arc])) == pytest.approx(exact, rel=0.05)
    # leading wheelset toward the outer rail, its outer wheel on tread and flange root
    assert float(np.mean(c["wheelset1.cg.disp.y"][arc])) < -0.004
    flange = c["wheelset1.right.force.flange"][arc]
    assert float(np.mean(flange)) > 2e3
    assert float(np.mean(c["wheelset1.right.contact_angle.x"][arc])) > 0.08  # > tread's
    assert float(np.max(c["wheelset2.right.force.flange"][arc])) == 0.0
    assert float(np.max(c["wheelset1.left.force.flange"][arc])) == 0.0
