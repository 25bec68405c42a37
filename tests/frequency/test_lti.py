"""FRF and PSD machinery against analytic one- and two-degree-of-freedom systems under base
excitation (hand-built M, C, K, B; the oracle is the closed-form FRF written out here)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from flexride.frequency.lti import OutputMap, SecondOrderSystem, output_frf
from flexride.frequency.response import channel_frf

F = np.geomspace(0.1, 80.0, 300)


def _one_dof(m=1200.0, k=4.0e5, c=3.0e3):
    """Mass on a spring–damper whose base moves by u: ẍ = −(k/m)(x − u) − (c/m)(ẋ − u̇)."""
    sys = SecondOrderSystem(K=np.array([[k / m]]), C=np.array([[c / m]]),
                            B0=np.array([[k / m]]), B1=np.array([[c / m]]),
                            B2=np.zeros((1, 1)))
    w = 2 * np.pi * F
    analytic = -(w**2) * (k + 1j * w * c) / (k - m * w**2 + 1j * w * c)
    return sys, analytic


@pytest.mark.parametrize("method", ["modal", "direct"])
def test_one_dof_base_excitation_acceleration(method):
    sys, analytic = _one_dof()
    out = OutputMap(["a"], np.array([[1.0]]), np.zeros((1, 1)), np.zeros((1, 1)))
    h = output_frf(sys, out, F, method=method)[:, 0, 0]
    np.testing.assert_allclose(h, analytic, rtol=1e-9)


def test_one_dof_white_base_acceleration_variance():
    """Relative displacement of a base-excited oscillator under white base acceleration of
    one-sided PSD G_a: σ² = G_a/(8ζω_n³) (closed form), from ∫|H|² G_u df with G_u = G_a/ω⁴."""
    m, k, c = 1000.0, 1.0e5, 2.0e3
    sys, _ = _one_dof(m, k, c)
    out = OutputMap(["x - u"], np.zeros((1, 1)), np.array([[1.0]]), np.array([[-1.0]]))
    f = np.linspace(1e-4, 400.0, 400_001)
    w = 2 * np.pi * f
    h = output_frf(sys, out, f)[:, 0, 0]
    g_a = 1e-2
    var = np.trapezoid(np.abs(h) ** 2 * g_a / w**4, f)
    wn, zeta = np.sqrt(k / m), c / (2 * np.sqrt(k * m))
    assert var == pytest.approx(g_a / (8 * zeta * wn**3), rel=1e-4)


def _pitch_plane(a=6.3, m=30000.0, inertia=1.2e6, k=3.0e5, c=2.0e4):
    """Rigid body (bounce z, pitch θ) on two spring–dampers at x = ±a, inputs under each."""
    K = np.array([[2 * k / m, 0.0], [0.0, 2 * k * a**2 / inertia]])
    C = np.array([[2 * c / m, 0.0], [0.0, 2 * c * a**2 / inertia]])
    # inputs grouped per "wheelset" in fours (z left, z right, y left, y right): front, rear
    B0 = np.zeros((2, 8))
    B1 = np.zeros((2, 8))
    for w, sign in ((0, 1.0), (1, -1.0)):
        B0[:, 4 * w] = (k / m, sign * k * a / inertia)
        B1[:, 4 * w] = (c / m, sign * c * a / inertia)
    return SecondOrderSystem(K, C, B0, B1, np.zeros((2, 8)))


def test_two_dof_with_delays_and_geometric_filter():
    """Bounce/pitch body excited at front and rear: the FRF with the delay τ = 2a/V and its
    notches at f = (2k+1)V/(4a) (bounce) and f = kV/(2a) (pitch) are the closed forms."""
    a, m, inertia, k, c, speed = 6.3, 30000.0, 1.2e6, 3.0e5, 2.0e4, 22.0
    sys = _pitch_plane(a, m, inertia, k, c)
    model = SimpleNamespace(system=sys, modes=sys.modes(), wheelset_x=np.array([a, -a]),
                            delays=lambda: np.array([0.0, 2 * a / speed]))
    out = OutputMap(["centre", "front"], np.array([[1.0, 0.0], [1.0, a]]), np.zeros((2, 2)),
                    np.zeros((2, 8)))
    maps = np.array([[1.0, 1.0, 0.0, 0.0]])
    f = np.concatenate([F, [(2 * j + 1) * speed / (4 * a) for j in range(3)]])
    Y, _eta, _rows = channel_frf(model, out, f, maps)
    w = 2 * np.pi * f
    e = np.exp(-1j * w * 2 * a / speed)
    hz = -(w**2) * (k + 1j * w * c) * (1 + e) / (2 * k - m * w**2 + 2j * w * c)
    ht = -(w**2) * a * (k + 1j * w * c) * (1 - e) / (2 * k * a**2 - inertia * w**2
                                                      + 2j * w * c * a**2)
    np.testing.assert_allclose(Y[:, 0, 0], hz, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(Y[:, 0, 1], hz + a * ht, rtol=1e-8, atol=1e-12)
    notch = np.abs(Y[-3:, 0, 0])
    assert np.all(notch < 1e-9 * np.abs(Y[:-3, 0, 0]).max())


def test_modal_and_direct_agree_on_an_unsymmetric_system():
    """Gyroscopic/creep-like unsymmetric coupling: both evaluations give the same FRF."""
    rng = np.random.default_rng(3)
    n = 6
    K = np.diag(rng.uniform(10, 1e4, n)) + 50 * rng.standard_normal((n, n))
    C = np.diag(rng.uniform(1, 30, n)) + rng.standard_normal((n, n))
    sys = SecondOrderSystem(K, C, rng.standard_normal((n, 3)), rng.standard_normal((n, 3)),
                            rng.standard_normal((n, 3)) * 1e-3)
    assert np.all(sys.modes().lam.real < 0)
    np.testing.assert_allclose(sys.frf_modal(F), sys.frf_direct(F), rtol=1e-7, atol=1e-12)
