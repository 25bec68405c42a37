"""Rayleigh damping (paper Eqs. 2–4) and modal damping."""

from __future__ import annotations

import numpy as np
import pytest

from flexride.fem.damping import RayleighDamping, modal_damping_ratios


def test_rayleigh_reproduces_the_two_given_ratios():
    r = RayleighDamping(5.03, 6.11, 0.02, 0.03)
    np.testing.assert_allclose(r.ratios([5.03, 6.11]), [0.02, 0.03], rtol=1e-12)
    alpha, beta = r.coefficients
    w1, w2 = 2 * np.pi * 5.03, 2 * np.pi * 6.11
    # Eqs. (3) and (4) as printed
    assert alpha == pytest.approx(2 * w1 * w2 * (0.03 * w1 - 0.02 * w2) / (w1**2 - w2**2))
    assert beta == pytest.approx(2 * (0.02 * w1 - 0.03 * w2) / (w1**2 - w2**2))


def test_equal_ratios_give_a_minimum_between_the_modes():
    r = RayleighDamping(2.0, 20.0, 0.02, 0.02)
    z = r.ratios(np.array([1.0, 2.0, 6.3, 20.0, 40.0]))
    assert z[1] == pytest.approx(0.02) and z[3] == pytest.approx(0.02)
    assert z[2] < 0.02 and z[0] > 0.02 and z[4] > 0.02


def test_modal_damping_specs():
    f = np.array([5.0, 6.0, 7.0])
    assert np.all(modal_damping_ratios(0.02, f) == 0.02)
    np.testing.assert_allclose(modal_damping_ratios([0.01, 0.03], f), [0.01, 0.03, 0.03])
    with pytest.raises(ValueError):
        modal_damping_ratios(-0.1, f)
    with pytest.raises(ValueError):
        _ = RayleighDamping(5.0, 5.0, 0.02, 0.02).coefficients


def test_rayleigh_through_the_first_two_modes_hits_their_ratios():
    """ζ at the first two elastic modes equals the given ratios; between them it is smaller
    and above them it grows ∝ f (β K dominates) — paper Eqs. 2–4."""
    from flexride.fem.damping import RayleighThroughModes

    f = np.array([5.03, 6.11, 8.0, 20.0, 40.0])
    z = modal_damping_ratios(RayleighThroughModes(0.02, 0.03), f)
    assert z[0] == pytest.approx(0.02, rel=1e-12)
    assert z[1] == pytest.approx(0.03, rel=1e-12)
    assert z[3] < z[4] and z[4] / z[3] == pytest.approx(2.0, rel=0.05)


def test_rayleigh_through_modes_needs_those_modes():
    from flexride.errors import FEModelError
    from flexride.fem.damping import RayleighThroughModes

    with pytest.raises(FEModelError, match="modes 1 and 2"):
        modal_damping_ratios(RayleighThroughModes(0.02, 0.02), np.array([5.0]))
