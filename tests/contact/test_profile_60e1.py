"""60E1 / UIC60 head (EN 13674-1) from its construction, and its placement at 1:40.

Oracles: the construction figures of ``reference/wheel-rail-profiles.md`` §1.2 (tangent points,
centres, head width, gauge face at 14 and 16 mm, the canted head's highest point and gauge
points), the circle equations written out here, and the Manchester benchmark's UIC60 v3 head
(a variant of the same head, ≤ 0.028 mm apart).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from contact.profile_data import mbench_file
from flexride.contact.placement import Placement, place_rail
from flexride.contact.profiles import rail_60e1, read_profile
from flexride.contact.profiles.rail60e1 import rail_60e1_geometry

CANT = math.atan(1.0 / 40.0)


def test_tangent_points_centres_and_head_width() -> None:
    g = rail_60e1_geometry()
    assert g.t_crown == pytest.approx((10.228, -0.174404), abs=2e-6)
    assert g.t_shoulder == pytest.approx((26.0265, -2.302524), abs=2e-6)
    assert g.t_side == pytest.approx((35.999811, -14.299958), abs=2e-6)
    assert g.c_shoulder == pytest.approx((7.500533, -80.127896), abs=2e-6)
    assert g.c_corner == pytest.approx((23.016030, -14.949147), abs=2e-6)
    assert round(2.0 * g.t_side[0], 3) == 72.000


def test_profile_points_lie_on_the_arcs() -> None:
    p = rail_60e1()
    u, v = np.abs(p.y) * 1e3, p.z * 1e3
    arcs = [((0.0, -300.0), 300.0, 0.0, 10.228),
            ((7.500533, -80.127896), 80.0, 10.228, 26.0265),
            ((23.016030, -14.949147), 13.0, 26.0265, 35.999811)]
    for (cu, cv), r, lo, hi in arcs:
        m = (u > lo + 1e-6) & (u < hi - 1e-6) & (v > -14.2)
        assert m.sum() > 20
        assert np.abs(np.hypot(u[m] - cu, v[m] - cv) - r).max() < 1e-6
    side = v < -14.3
    assert np.abs((u[side] - 35.999811) - (-14.299958 - v[side]) / 20.0).max() < 1e-6


def test_gauge_face_at_14_and_16_mm() -> None:
    curve = rail_60e1().curve()
    for depth, width in ((0.014, 35.9813), (0.016, 36.0848)):
        y, z = curve.gauge_point(depth)
        assert z == pytest.approx(-depth, abs=1e-12)
        assert abs(y) * 1e3 == pytest.approx(width, abs=1e-4)
        assert y < 0.0  # gauge side


def test_canted_head_highest_point_and_gauge_points() -> None:
    curve = rail_60e1().curve()
    yt, zt = curve.highest_point(CANT)
    assert yt * 1e3 == pytest.approx(7.497, abs=1e-3)  # toward the field side
    assert zt * 1e3 == pytest.approx(0.094, abs=1e-3)
    for depth, dist in ((0.014, 43.032), (0.016, 43.146)):
        yg, _ = curve.gauge_point(depth, CANT)
        assert (yt - yg) * 1e3 == pytest.approx(dist, abs=1e-3)


def test_placement_puts_the_gauge_point_at_half_the_gauge() -> None:
    placed = place_rail(rail_60e1().curve(), Placement(gauge=1.435, gauge_height=0.014))
    assert placed.gauge_point == (0.7175, -0.014)
    s = placed.sample(1e-5)
    # the surface passes through the gauge point and its top is at z = 0
    assert np.interp(0.7175, s.y, s.z) == pytest.approx(-0.014, abs=2e-8)
    assert s.z.max() == pytest.approx(0.0, abs=1e-9)
    # crown-top axis: 43.032 − 7.497 mm outward of the gauge point
    assert placed.origin[0] * 1e3 == pytest.approx(717.5 + 43.032 - 7.497, abs=2e-3)


def test_benchmark_uic60_v3_matches_the_canted_60e1_head() -> None:
    mb = read_profile(mbench_file("MBench_UIC60_v3.prr"))
    pm = place_rail(mb.curve(), Placement(inclination=0.0))
    pe = place_rail(rail_60e1().curve(), Placement())
    a, b = pm.sample(2e-5), pe.sample(2e-5)
    y = np.arange(0.7175 + 0.002, pe.origin[0] + 0.030, 1e-4)  # gauge corner to field shoulder
    dz = np.interp(y, a.y, a.z) - np.interp(y, b.y, b.z)
    # the v3 head has its R80 centre at 7.7 mm instead of 7.5 mm: measured 0.043 mm here (both
    # placed by their gauge points); the reference quotes ≤ 0.028 mm for its own alignment
    assert np.abs(dz).max() * 1e3 < 0.05
