"""Zhai's explicit method (the kernel's own update function) on a single-DOF oscillator."""

from __future__ import annotations

import numpy as np
import pytest

from flexride.solver.kernel import zhai_update
from flexride.solver.stability import critical_step, spectral_radius


def integrate_sdof(omega: float, zeta: float, dt: float, t_end: float, x0: float = 1.0):
    """x'' = −ω²x − 2ζωx' with x(0) = x0, x'(0) = 0, using the kernel's zhai_update."""
    X = np.array([x0])
    V = np.array([0.0])
    A = np.array([-(omega**2) * x0])
    Ap = np.zeros(1)
    n = round(t_end / dt)
    xs = np.empty(n + 1)
    xs[0] = x0
    for i in range(n):
        psi = phi = 0.0 if i == 0 else 0.5  # first step: ψ = φ = 0 (no previous acceleration)
        zhai_update(X, V, A, Ap, dt, psi, phi)
        A[0] = -(omega**2) * X[0] - 2 * zeta * omega * V[0]
        xs[i + 1] = X[0]
    return xs


def exact_sdof(omega, zeta, t, x0=1.0):
    wd = omega * np.sqrt(1 - zeta**2)
    return x0 * np.exp(-zeta * omega * t) * (np.cos(wd * t) + zeta * omega / wd * np.sin(wd * t))


@pytest.mark.parametrize("zeta", [0.0, 0.05])
def test_sdof_matches_analytic_solution(zeta):
    omega = 2 * np.pi * 2.0
    dt = 1e-3
    t = np.arange(0, 2.0 + dt / 2, dt)
    x = integrate_sdof(omega, zeta, dt, 2.0)
    assert np.max(np.abs(x - exact_sdof(omega, zeta, t))) < 2e-3


def test_second_order_convergence():
    omega, zeta = 2 * np.pi * 3.0, 0.02
    errs = []
    for dt in (2e-3, 1e-3, 5e-4):
        t = np.arange(0, 1.0 + dt / 2, dt)
        x = integrate_sdof(omega, zeta, dt, 1.0)
        errs.append(np.max(np.abs(x - exact_sdof(omega, zeta, t))))
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(orders > 1.8), orders


def test_undamped_stability_limit_is_omega_dt_two():
    omega = 100.0
    stable = integrate_sdof(omega, 0.0, 1.98 / omega, 200 * 1.98 / omega)
    unstable = integrate_sdof(omega, 0.0, 2.02 / omega, 200 * 2.02 / omega)
    assert np.max(np.abs(stable)) < 10.0
    assert np.max(np.abs(unstable)) > 1e3
    # the stability module's criterion agrees: critical ω·Δt = 2 for ψ = φ = ½
    limit = critical_step(np.array([omega]), np.array([0.0]))[0] * omega
    assert limit == pytest.approx(2.0, rel=1e-4)
    assert spectral_radius(omega, 0.0, 1.9 / omega) <= 1.0 + 1e-12


def test_pure_damper_limit():
    """ẍ = −c·ẋ is stable for c·Δt ≤ 1 with ψ = φ = ½ (characteristic root −1 at c·Δt = 1)."""
    c = 50.0
    assert critical_step(np.array([0.0]), np.array([c]))[0] * c == pytest.approx(1.0, rel=1e-4)
