"""S1002 (EN 13715) built from its analytic definition.

Oracles, independent of the code under test:
* the Manchester benchmark's ``MBench_S1002_v3.prw`` (CONTACT, Apache-2.0), parsed here with a
  few lines of plain Python (y = −s, z = radius increase);
* the standard's nominal features: flange height 28.000, flange thickness 32.500 (flange face at
  F = 10 mm), qR 10.794 (face point 2 mm below the flange tip), found here by bisection;
* the boundary values and slopes listed in ``reference/wheel-rail-profiles.md`` §1.1.
"""

from __future__ import annotations

import numpy as np
import pytest

from contact.profile_data import mbench_file
from flexride.contact.profiles.s1002 import (
    BLEND_HALF_WIDTH,
    BLEND_MAX_CHANGE,
    S1002_JOINS,
    s1002,
    s1002_radius,
    s1002_radius_raw,
)


def _prw_points() -> tuple[np.ndarray, np.ndarray]:
    """(s, F) in mm of the benchmark file: rows of two numbers between point.begin/point.end."""
    s, f = [], []
    inside = False
    for line in mbench_file("MBench_S1002_v3.prw").read_text().splitlines():
        text = line.split("!")[0].strip()
        if text == "point.begin":
            inside = True
        elif text == "point.end":
            inside = False
        elif inside and text:
            a, b = text.split()
            s.append(-float(a))  # the file stores y = −s
            f.append(float(b))
    return np.array(s), np.array(f)


def _bisect(fun, lo: float, hi: float) -> float:
    flo = fun(lo)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if (fun(mid) > 0) == (flo > 0):
            lo, flo = mid, fun(mid)
        else:
            hi = mid
    return 0.5 * (lo + hi)


def F(s: float) -> float:
    return float(s1002_radius_raw(np.array([s]))[0])


def test_definition_matches_the_benchmark_file_where_it_has_points() -> None:
    s, f = _prw_points()
    assert s.size == 399 and s.min() < -69.5 and s.max() == pytest.approx(60.0)
    err = np.abs(s1002_radius_raw(s) - f)
    assert err.max() <= 1e-5, f"max |F - file| = {err.max():.3g} mm"


def test_flange_height_thickness_and_qr_are_the_nominal_values() -> None:
    assert F(-55.0) - F(0.0) == pytest.approx(28.000, abs=5e-4)
    assert F(0.0) == 0.0
    # flange face points at F = 10 and F = 26 (2 mm below the tip), between the tip and the root
    s10 = _bisect(lambda s: F(s) - 10.0, -45.0, -36.0)
    s26 = _bisect(lambda s: F(s) - 26.0, -55.0, -45.0)
    assert s10 == pytest.approx(-37.500, abs=5e-4)
    assert s10 + 70.0 == pytest.approx(32.500, abs=5e-4)  # Sd from the flange back
    assert s26 == pytest.approx(-48.294, abs=5e-4)
    assert s10 - s26 == pytest.approx(10.794, abs=5e-4)  # qR


@pytest.mark.parametrize(
    ("s", "value", "tol"),
    [
        (-70.0, 9.519259, 1e-6),
        (60.0, -2.635676, 1e-6),
        (-62.7647, 25.149281, 1e-4),
        (-49.6625, 26.747614, 1e-4),
        (-39.7645, 15.675327, 1e-4),
        (-38.4267, 11.999738, 1e-4),
        (-35.0, 6.8674, 1e-4),
        (-26.0, 2.7410, 1e-4),
        (32.15796, -0.779540, 1e-6),
    ],
)
def test_boundary_values(s: float, value: float, tol: float) -> None:
    assert F(s) == pytest.approx(value, abs=tol)


def test_tread_slopes() -> None:
    h = 1e-4
    assert (F(h) - F(-h)) / (2 * h) == pytest.approx(-0.0336, abs=1e-4)
    assert (F(10 + h) - F(10 - h)) / (2 * h) == pytest.approx(-0.0113, abs=1e-4)


def test_joins_are_continuous_except_the_two_published_steps() -> None:
    h = 1e-7
    for join in S1002_JOINS:
        left, right = F(join - h), F(join + h)
        step = abs(right - left)
        if join in (-26.0, -35.0):
            assert 2e-5 < step < 2e-4, (join, step)  # 3.65e-5 and 1.18e-4 mm
        else:
            assert step < 1e-5, (join, step)


def test_blend_removes_the_steps_and_changes_nothing_elsewhere() -> None:
    s = np.linspace(-70.0, 60.0, 260_001)
    raw, smooth = s1002_radius_raw(s), s1002_radius(s)
    outside = (np.abs(s + 26.0) >= BLEND_HALF_WIDTH) & (np.abs(s + 35.0) >= BLEND_HALF_WIDTH)
    assert np.array_equal(raw[outside], smooth[outside])
    change = np.abs(smooth - raw).max()
    assert 5e-5 < change <= BLEND_MAX_CHANGE  # half of the 1.18e-4 mm step at s = −35
    for join in (-26.0, -35.0):
        h = 1e-9  # the raw steps are 3.65e-5 and 1.18e-4 mm
        assert abs(float(s1002_radius(join + h)) - float(s1002_radius(join - h))) < 1e-8
        h = 1e-5
        slope = [float((s1002_radius(x + h) - s1002_radius(x - h)) / (2 * h))
                 for x in (join - 2 * h, join + 2 * h)]
        assert abs(slope[1] - slope[0]) < 1e-4


def test_profile_curve_reproduces_the_benchmark_file() -> None:
    s, f = _prw_points()
    p = s1002()
    assert p.kind == "wheel" and p.n > 2500
    curve = p.curve()
    m = s > -69.0  # away from the vertical tangent of the flange back
    sample = curve.sample(1e-5, y0=-0.069, y1=0.060)
    z = np.interp(s[m] * 1e-3, sample.y, sample.z) * 1e3
    err = np.abs(-z - f[m])
    assert err.max() < 2e-4, err.max()  # blend (≤ 6e-5) + spline and sampling
    # the contact angle on the tread: atan(−dF/ds) = atan(0.0336) at the taping line
    i = int(np.argmin(np.abs(sample.y)))
    assert sample.angle[i] == pytest.approx(np.arctan(0.0336), abs=2e-4)


def test_smoothing_spline_filters_measurement_noise() -> None:
    # S1002 every 0.2 mm with 5 µm of noise, as a measured profile: the interpolating spline
    # follows the noise (curvature scatter of hundreds of 1/m), the smoothing one does not
    from flexride.contact.profiles import Profile

    p = s1002(step=2e-4)
    noisy = Profile("wheel", p.y, p.z + np.random.default_rng(1).normal(0.0, 5e-6, p.n), "noisy")
    y = np.linspace(-0.025, 0.025, 501)
    s = y * 1e3
    h = 1e-3
    f2 = (s1002_radius(s + h) - 2 * s1002_radius(s) + s1002_radius(s - h)) / h**2
    f1 = (s1002_radius(s + h) - s1002_radius(s - h)) / (2 * h)
    exact = -f2 / (1 + f1**2) ** 1.5 * 1e3  # 1/m, z = −F
    errs = {}
    for ell in (0.0, 3e-3):
        smp = noisy.curve(ell).sample(1e-5, y0=-0.026, y1=0.026)
        errs[ell] = np.std(np.interp(y, smp.y, smp.curvature) - exact)
        height = np.abs(np.interp(y, smp.y, smp.z) + s1002_radius(s) * 1e-3).max()
        assert height < 2e-5  # 0.02 mm
    assert errs[0.0] > 100.0 and errs[3e-3] < 0.1 * errs[0.0]
