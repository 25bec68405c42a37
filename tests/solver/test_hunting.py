"""Kinematic hunting: a wheelset free to yaw and move laterally on a conical tread at low speed
follows Klingel's wavelength 2π·√(r0·b/λ)."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import preset
from flexride.solver.assemble import assemble
from flexride.solver.setup_cache import default_cache
from flexride.solver.simulate import integrate, prepare_run


def test_klingel_wavelength():
    speed_kmh = 18.0
    sc = preset(
        "paper-metro",
        speed_kmh=speed_kmh,
        duration_s=11.0,
        contact__geometry="conical",
        # primary suspension free in x and y: the wheelsets are kinematically free to hunt
        **{"vehicle.primary.kx": 1.0e3, "vehicle.primary.ky": 0.0,
           "vehicle.primary.cx": 0.0, "vehicle.primary.cy": 0.0},
    )
    asm, ready = prepare_run(sc, assemble(sc), default_cache(), check=False)
    X0 = ready.X0
    Xi = X0.copy()
    for w in asm.vehicle.wheelsets:
        Xi[asm.sys.body_off[w] + 1] = 0.003  # 3 mm lateral offset, inside the flange clearance
    res = integrate(asm, Xi, np.zeros_like(Xi), sc, lambda f, m: None, X_ref=X0)
    y = res.channels["wheelset1.cg.disp.y"]
    s = res.distance
    sign = np.signbit(y)
    idx = np.nonzero(sign[1:] != sign[:-1])[0]
    # interpolate the crossings
    xs = s[idx] - y[idx] * (s[idx + 1] - s[idx]) / (y[idx + 1] - y[idx])
    assert xs.size >= 4
    wavelength = 2 * np.mean(np.diff(xs))
    g = sc.vehicle.geometry
    klingel = 2 * np.pi * np.sqrt(g.wheel_radius * g.rolling_circle_half_distance
                                  / sc.contact.conicity)
    assert wavelength == pytest.approx(klingel, rel=0.05)
