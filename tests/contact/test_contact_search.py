"""Rigid contact-point search: closed-form cone oracle, the Manchester contact benchmark A-2.2
(CONTACT, elastic), and the rigid no-roll S1002/60E1 values of the reference (a regression
cross-check).

Oracles:
* a 1:50 cone on a round (R300) crown: the contact stays at the crown point whose slope equals
  the cone's, so r = r0 − λ·s_c with s_c = η_c − b_w ∓ Δy, Δr = 2λΔy, γ = atan λ, lateral
  curvatures 0 (cone) and 1/R (rail), all written out here;
* CONTACT's Manchester benchmark A-2.2 (``reference/wheel-rail-profiles.md`` §4.2): contact
  positions YCP of the flanging wheel, the static roll, the two-patch and flange positions;
* §4.3: an independent rigid no-roll computation of S1002 on 60E1 at 1:40 (Δr table, jump).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from contact.profile_data import LAM, cone_wheel, crown_rail, mbench_file
from flexride.contact.placement import Placement
from flexride.contact.profiles import Profile, rail_60e1, read_profile, s1002
from flexride.contact.search import ContactGeometry, SearchSettings, search_contact
from flexride.errors import ScenarioError


@pytest.fixture(scope="module")
def cone_geo() -> ContactGeometry:
    return search_contact(cone_wheel(), crown_rail(), Placement(inclination=0.0),
                          SearchSettings(y_max=0.005, roll=False))


def test_cone_on_a_round_head_no_roll(cone_geo: ContactGeometry) -> None:
    g = cone_geo
    r0, bw, radius = 0.46, g.placement.taping_line, 0.300
    # crown point with slope λ toward the gauge side, placed: η = origin + u
    u_c = -radius * math.sin(math.atan(LAM))
    eta_c = g.rail_origin[0, 0] + u_c
    assert np.all(g.rigid == 0) and np.all(g.active[:, 0])
    for side, sg in ((0, 1.0), (1, -1.0)):
        s_exp = eta_c - bw - sg * g.y
        np.testing.assert_allclose(g.at_rigid("s")[side], s_exp, atol=2e-7)
        np.testing.assert_allclose(g.at_rigid("r")[side], r0 - LAM * s_exp, atol=1e-8)
        np.testing.assert_allclose(g.at_rigid("gamma")[side], math.atan(LAM), atol=1e-6)
        np.testing.assert_allclose(g.at_rigid("eta")[side], eta_c, atol=2e-7)
        np.testing.assert_allclose(g.at_rigid("k_rail")[side], 1.0 / radius, rtol=1e-3)
        np.testing.assert_allclose(g.at_rigid("k_wheel")[side], 0.0, atol=1e-3)
    np.testing.assert_allclose(g.delta_r, 2.0 * LAM * g.y, atol=1e-8)
    assert np.all(g.roll == 0.0)


def test_cone_with_roll_keeps_track_frame_angles_on_the_rail() -> None:
    g = search_contact(cone_wheel(), crown_rail(), Placement(inclination=0.0),
                       SearchSettings(y_max=0.005, roll=True))
    # positive Δy rolls the wheelset so that the left wheel (on the larger radius) rises
    i = int(np.argmin(np.abs(g.y - 0.004)))
    assert g.roll[i] > 0.0
    # the rail's slope at the contact is the wheel's contact angle turned by the roll
    np.testing.assert_allclose(g.gamma_track, g.at_rigid("gamma_rail"), atol=2e-4)
    # the kinematic roll of a cone on round rails: lift ±λΔy over the lateral contact lever
    lever = g.at_rigid("eta")[0]
    np.testing.assert_allclose(g.roll[i], LAM * g.y[i] / lever[i], rtol=0.02)


def test_left_right_mirror_symmetry() -> None:
    g = search_contact(s1002(), rail_60e1(), Placement(), SearchSettings(y_max=0.008))
    for name in ("r", "gamma", "s", "eta", "k_wheel", "k_rail"):
        a = g.at_rigid(name)
        np.testing.assert_allclose(a[0], a[1][::-1], atol=1e-9, err_msg=name)
    np.testing.assert_allclose(g.roll, -g.roll[::-1], atol=1e-12)


# --- Manchester benchmark A-2.2 (CONTACT) ----------------------------------------------------

# y_ws (mm, toward the flanging right wheel) -> YCP(TR) of the right wheel (mm)
YCP = {0.0: 751.87, 0.5: 744.50, 1.0: 741.99, 2.0: 740.91, 3.0: 739.97, 4.0: 738.74,
       4.5: 737.89, 5.0: 727.09, 6.0: 725.14}
ROLL = {0.5: -2.304e-5, 3.0: -1.803e-4, 6.0: -6.272e-4, 6.5: -4.376e-3}


@pytest.fixture(scope="module")
def mbench() -> dict[bool, ContactGeometry]:
    wheel = read_profile(mbench_file("MBench_S1002_v3.prw"))
    rail = read_profile(mbench_file("MBench_UIC60_v3.prr"))
    place = Placement(inclination=0.0)  # the v3 rail file is already canted 1:40
    return {roll: search_contact(wheel, rail, place, SearchSettings(roll=roll))
            for roll in (True, False)}


def _at(g: ContactGeometry, y_ws_mm: float) -> int:
    # CONTACT's y_ws moves the wheelset toward the right rail: Δy = −y_ws in project axes
    i = int(np.argmin(np.abs(g.y + y_ws_mm * 1e-3)))
    assert abs(g.y[i] + y_ws_mm * 1e-3) < 1e-9
    return i


def test_mbench_contact_positions(mbench: dict[bool, ContactGeometry]) -> None:
    g = mbench[True]
    eta = g.at_rigid("eta")[1] * 1e3
    for y_ws, ycp in YCP.items():
        got = eta[_at(g, y_ws)]
        if y_ws <= 4.5:  # tread
            assert abs(got - ycp) <= 2.5, (y_ws, got, ycp)
            if y_ws >= 1.0:  # away from the jump the elastic patch centre is the rigid point
                assert abs(got - ycp) <= 0.35, (y_ws, got, ycp)
        else:  # flange root
            assert abs(got - ycp) <= 1.0, (y_ws, got, ycp)
            assert g.rigid[1, _at(g, y_ws)] == 1


def test_mbench_jump_near_zero(mbench: dict[bool, ContactGeometry]) -> None:
    g = mbench[True]
    s = g.at_rigid("s")[1] * 1e3
    assert s[_at(g, 0.0)] > 2.0 and s[_at(g, 0.5)] < -7.0  # s ≈ +3.2 → −8.2 mm


def test_mbench_static_roll(mbench: dict[bool, ContactGeometry]) -> None:
    g = mbench[True]
    for y_ws, roll in ROLL.items():
        got = g.roll[_at(g, y_ws)]
        assert got == pytest.approx(roll, rel=0.08), (y_ws, got, roll)


def test_mbench_flange_root_and_flange(mbench: dict[bool, ContactGeometry]) -> None:
    g = mbench[True]
    # CONTACT: one patch on the tread at 4.5 mm, a second (flange-root) patch at 5.0 mm
    assert g.rigid[1, _at(g, 4.5)] == 0 and g.rigid[1, _at(g, 5.0)] == 1
    assert g.two_point[1, _at(g, 5.0)]
    # flange contact at 6.5 mm with contact angle 1.16 rad (track frame)
    i = _at(g, 6.5)
    assert g.rigid[1, i] == 1
    assert g.gamma_track[1, i] == pytest.approx(1.16, abs=0.05)
    # without roll the rigid contact reaches the flange root between 5.0 and 6.5 mm
    h = mbench[False]
    onset = -h.y[(h.rigid[1] == 1) & (h.y < 0)].max() * 1e3
    assert 5.0 <= onset <= 6.5


# --- §4.3: S1002 / 60E1 at 1:40, rigid without roll ----------------------------------------

def test_s1002_60e1_rigid_no_roll_delta_r_and_jump() -> None:
    g = search_contact(s1002(), rail_60e1(), Placement(),
                       SearchSettings(y_max=0.007, roll=False))
    table = {0.5: 0.528, 1.0: 0.609, 2.0: 0.766, 3.0: 0.940, 4.0: 1.151, 5.0: 1.448,
             5.5: 3.88, 6.0: 4.27}
    for y, dr in table.items():
        i = int(np.argmin(np.abs(g.y - y * 1e-3)))
        assert g.delta_r[i] * 1e3 == pytest.approx(dr, abs=0.006), y
    s_left = g.at_rigid("s")[0] * 1e3
    i0, i5 = int(np.argmin(np.abs(g.y))), int(np.argmin(np.abs(g.y - 5e-4)))
    assert s_left[i0] == pytest.approx(3.23, abs=0.05)
    assert s_left[i5] == pytest.approx(-8.2, abs=0.05)


def test_profiles_too_short_for_the_range_are_refused() -> None:
    full = s1002()
    keep = full.y <= 0.008  # the tread ends 8 mm outside the taping line
    short = Profile("wheel", full.y[keep], full.z[keep], "short")
    with pytest.raises(ScenarioError, match="end of a profile"):
        search_contact(short, rail_60e1(), Placement(), SearchSettings(y_max=0.012))
