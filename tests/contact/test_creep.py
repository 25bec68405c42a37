"""Tests of the compiled creep-force laws (Kalker linear + Shen–Hedrick–Elkins).

Oracles: the SHE polynomial evaluated by hand (exact fractions), the Coulomb limit μN, Kalker's
linear law written out from DESIGN §6, and symmetry (the law is odd in the creepages).
"""

from __future__ import annotations

import math

import pytest

from flexride.contact import creep_forces, she_saturation

MU = 0.3
N_LOAD = 1.0e5
LIMIT = MU * N_LOAD
# Patch and material: N = 1000 N gives N^(1/3) = 10, so a = 1.5 mm, b = 1.2 mm
# (at N = 100 kN a = 7.0 mm, b = 5.6 mm, a typical wheel-rail patch).
CA, CB = 1.5e-4, 1.2e-4
C11, C22, C23, C33 = 4.12, 3.67, 1.47, 1.19
G_SHEAR = 8.0e10


def _kalker_linear(xi_x, xi_y, phi, n_load):
    """DESIGN §6 written out, with a = ca·N^(1/3), b = cb·N^(1/3)."""
    a = CA * n_load ** (1 / 3)
    b = CB * n_load ** (1 / 3)
    fx = -G_SHEAR * a * b * C11 * xi_x
    fy = -G_SHEAR * a * b * C22 * xi_y - G_SHEAR * (a * b) ** 1.5 * C23 * phi
    mz = G_SHEAR * (a * b) ** 1.5 * C23 * xi_y - G_SHEAR * (a * b) ** 2 * C33 * phi
    return fx, fy, mz


def _creep(xi_x, xi_y, phi, n_load=N_LOAD, mu=MU):
    return creep_forces(xi_x, xi_y, phi, n_load, CA, CB, C11, C22, C23, C33, G_SHEAR, mu)


# --- SHE saturation ---------------------------------------------------------------------------

# x = F/(μN) and F'/(μN) = x − x²/3 + x³/27 worked out by hand.
_SHE_POINTS = [
    (0.3, 0.3 - 0.03 + 0.001),  # 0.271
    (1.0, 19.0 / 27.0),
    (1.5, 7.0 / 8.0),
    (2.25, 63.0 / 64.0),
    (3.0, 1.0),
]


@pytest.mark.parametrize(("x", "ratio"), _SHE_POINTS)
def test_she_matches_closed_form(x: float, ratio: float) -> None:
    fx, fy, mz = she_saturation(x * LIMIT, 0.0, 10.0, MU, N_LOAD)
    assert fx == pytest.approx(ratio * LIMIT, rel=1e-12)
    assert fy == 0.0
    assert mz == pytest.approx(10.0 * ratio / x, rel=1e-12)  # moment scaled by F'/F


@pytest.mark.parametrize(("x", "ratio"), _SHE_POINTS)
def test_she_keeps_direction_of_the_resultant(x: float, ratio: float) -> None:
    # F at 3-4-5 proportions: the resultant is scaled, its direction kept.
    fx, fy, _ = she_saturation(-0.6 * x * LIMIT, 0.8 * x * LIMIT, 0.0, MU, N_LOAD)
    assert math.hypot(fx, fy) == pytest.approx(ratio * LIMIT, rel=1e-12)
    assert fy / fx == pytest.approx(-0.8 / 0.6, rel=1e-12)
    assert fx < 0.0 < fy


@pytest.mark.parametrize("x", [3.0 + 1e-9, 3.5, 10.0, 1.0e8])
def test_she_is_coulomb_beyond_x_three(x: float) -> None:
    fx, fy, mz = she_saturation(0.6 * x * LIMIT, 0.8 * x * LIMIT, 50.0, MU, N_LOAD)
    assert math.hypot(fx, fy) == pytest.approx(LIMIT, rel=1e-12)
    assert mz == pytest.approx(50.0 / x, rel=1e-12)


def test_she_continuous_with_zero_slope_at_x_three() -> None:
    h = 1e-6

    def sat(x: float) -> float:
        return she_saturation(x * LIMIT, 0.0, 0.0, MU, N_LOAD)[0] / LIMIT

    assert sat(3.0 - 1e-12) == pytest.approx(sat(3.0 + 1e-12), abs=1e-12)
    # F'(x) = 1 − 2x/3 + x²/9 vanishes at x = 3: C¹ join to the Coulomb plateau.
    assert (sat(3.0) - sat(3.0 - h)) / h == pytest.approx(0.0, abs=1e-5)
    assert (sat(3.0 + h) - sat(3.0)) / h == pytest.approx(0.0, abs=1e-9)


def test_she_small_forces_are_unchanged_to_first_order() -> None:
    # F'/F = 1 − x/3 + x²/27: at x = 1e-8 the correction is 3.3e-9.
    fx, _, mz = she_saturation(1e-8 * LIMIT, 0.0, 7.0, MU, N_LOAD)
    assert fx == pytest.approx(1e-8 * LIMIT, rel=1e-8)
    assert mz == pytest.approx(7.0, rel=1e-8)


@pytest.mark.parametrize(
    ("args", "expected"),
    [
        ((1.0e3, 2.0e3, 5.0, MU, 0.0), (0.0, 0.0, 0.0)),  # no load
        ((1.0e3, 2.0e3, 5.0, MU, -1.0e3), (0.0, 0.0, 0.0)),  # lifted wheel
        ((1.0e3, 2.0e3, 5.0, 0.0, N_LOAD), (0.0, 0.0, 0.0)),  # no friction
        ((0.0, 0.0, 0.0, MU, N_LOAD), (0.0, 0.0, 0.0)),  # no creep
        ((0.0, 0.0, 3.0, MU, N_LOAD), (0.0, 0.0, 3.0)),  # F = 0: ε → 1
    ],
)
def test_she_degenerate_inputs_are_finite(args, expected) -> None:
    assert she_saturation(*args) == expected


# --- creep_forces -----------------------------------------------------------------------------


def test_patch_factors_give_the_intended_semi_axes() -> None:
    # Sanity of the fixture itself: 1000^(1/3) = 10.
    assert 1000.0 ** (1 / 3) == pytest.approx(10.0, rel=1e-15)


@pytest.mark.parametrize(
    "creep",
    [(1e-9, 0.0, 0.0), (0.0, 1e-9, 0.0), (0.0, 0.0, 1e-7), (-3e-10, 5e-10, -2e-8)],
)
def test_small_creepage_equals_kalker_linear(creep) -> None:
    # Here x = F/(μN) < 1e-6, so SHE changes the forces by less than x/3.
    got = _creep(*creep)
    expected = _kalker_linear(*creep, N_LOAD)
    assert math.hypot(expected[0], expected[1]) / LIMIT < 1e-6
    assert got == pytest.approx(expected, rel=1e-6, abs=0.0)


def test_kalker_linear_signs() -> None:
    # Forces oppose the creepage; a lateral creepage gives a positive spin moment (+f23·ξy).
    fx, _, _ = _creep(1e-7, 0.0, 0.0)
    _, fy, mz = _creep(0.0, 1e-7, 0.0)
    _, fy_spin, mz_spin = _creep(0.0, 0.0, 1e-6)
    assert fx < 0.0
    assert fy < 0.0 < mz
    assert fy_spin < 0.0 and mz_spin < 0.0


def test_small_creepage_numeric_example() -> None:
    # N = 1000 N: a = 1.5 mm, b = 1.2 mm, ab = 1.8e-6 m²; f11 = 8e10·1.8e-6·4.12 = 593280 N.
    # ξx = 1e-5 → linear Fx = −5.9328 N; μN = 300 N, x = 0.019776, SHE factor 0.993422.
    fx, fy, mz = _creep(1e-5, 0.0, 0.0, n_load=1000.0)
    assert fx == pytest.approx(-5.9328 * 0.993422, rel=1e-6)
    assert fy == 0.0 and mz == 0.0


@pytest.mark.parametrize("creep", [(0.05, 0.0, 0.0), (0.0, -0.02, 0.0), (0.01, 0.01, 2.0)])
def test_large_creepage_saturates_to_mu_n(creep) -> None:
    fx, fy, _ = _creep(*creep)
    assert math.hypot(fx, fy) == pytest.approx(LIMIT, rel=1e-12)


def test_creep_forces_follow_she_of_kalker_linear() -> None:
    # Intermediate creepage, x ≈ 1.5: the composition written out.
    lin = _kalker_linear(2.5e-3, -2.0e-3, 0.3, N_LOAD)
    x = math.hypot(lin[0], lin[1]) / LIMIT
    assert 0.5 < x < 3.0
    eps = 1 - x / 3 + x * x / 27
    assert _creep(2.5e-3, -2.0e-3, 0.3) == pytest.approx(tuple(v * eps for v in lin), rel=1e-10)


@pytest.mark.parametrize(
    ("creep", "n_load"),
    [
        ((0.0, 0.0, 0.0), N_LOAD),
        ((1e-3, 1e-3, 0.1), 0.0),
        ((1e-3, 1e-3, 0.1), -5.0e3),
        ((1e6, -1e6, 1e6), N_LOAD),
        ((1e6, 0.0, 0.0), 1e-30),
    ],
)
def test_creep_forces_finite_at_extremes(creep, n_load: float) -> None:
    out = _creep(*creep, n_load=n_load)
    assert all(math.isfinite(v) for v in out)
    if n_load <= 0.0 or creep == (0.0, 0.0, 0.0):
        assert out == (0.0, 0.0, 0.0)
    elif n_load > 0.0:
        assert math.hypot(out[0], out[1]) <= MU * n_load * (1 + 1e-12)


@pytest.mark.parametrize(
    "creep", [(1e-4, 2e-4, 0.05), (-3e-3, 1e-3, -0.4), (0.2, -0.1, 3.0), (0.0, 0.0, 0.7)]
)
def test_creep_forces_are_odd_in_the_creepages(creep) -> None:
    pos = _creep(*creep)
    neg = _creep(*(-c for c in creep))
    assert neg == pytest.approx(tuple(-v for v in pos), rel=1e-13, abs=0.0)
