"""Zhai's explicit method (the kernel's own update function) on a single-DOF oscillator."""

from __future__ import annotations

import numpy as np
import pytest

from flexride.solver import step_map as sm
from flexride.solver.kernel import zhai_update
from flexride.solver.stability import LIMIT_MARGIN, point_limit


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


def oscillator_limit(omega: float, damping: float, psi: float = 0.5, phi: float = 0.5):
    """The time-step check's limit (the same code as for a vehicle) of ẍ = −ω²x − c·ẋ."""
    jac = sm.oscillator_jacobian(omega, damping)
    return point_limit(lambda dt: jac, psi, phi, lambda shape: "x")


def test_undamped_stability_limit_is_omega_dt_two():
    omega = 100.0
    stable = integrate_sdof(omega, 0.0, 1.98 / omega, 200 * 1.98 / omega)
    unstable = integrate_sdof(omega, 0.0, 2.02 / omega, 200 * 2.02 / omega)
    assert np.max(np.abs(stable)) < 10.0
    assert np.max(np.abs(unstable)) > 1e3
    # the time-step check agrees: critical ω·Δt = 2 for ψ = φ = ½, a period-two root (at a
    # frequency whose limit lies below the checked range's ceiling)
    omega = 1000.0
    lim = oscillator_limit(omega, 0.0)
    assert lim.kind == "period-two"
    crossing = lim.dt_max / (1.0 - LIMIT_MARGIN["rolling"])
    assert crossing * omega == pytest.approx(2.0, rel=1e-3)
    mu = np.linalg.eigvals(sm.one_step_map(sm.oscillator_jacobian(omega, 0.0), 1.9 / omega))
    assert np.abs(mu).max() <= 1.0 + 1e-12


def test_pure_damper_limit():
    """ẍ = −c·ẋ is stable for c·Δt ≤ 1 with ψ = φ = ½ (characteristic root −1 at c·Δt = 1)."""
    c = 500.0
    crossing = oscillator_limit(0.0, c).dt_max / (1.0 - LIMIT_MARGIN["rolling"])
    assert crossing * c == pytest.approx(1.0, rel=1e-3)


@pytest.mark.parametrize(("omega", "zeta"), [(300.0, 0.05), (300.0, 0.6), (50.0, 3.0)])
def test_damped_oscillator_limit_is_where_the_kernel_update_grows(omega, zeta):
    """The check's limit of a damped oscillator against the kernel's own update run at 0.99
    and 1.01 of it (bounded, growing)."""
    c = 2.0 * zeta * omega
    dt = oscillator_limit(omega, c).dt_max / (1.0 - LIMIT_MARGIN["rolling"])
    x_in = integrate_damped(omega, c, 0.99 * dt, 20000)
    x_out = integrate_damped(omega, c, 1.01 * dt, 20000)
    assert np.max(np.abs(x_in[-1000:])) <= 1.0
    grown = x_out[-1000:]
    assert not np.all(np.isfinite(grown)) or np.max(np.abs(grown)) > 10.0


def integrate_damped(omega: float, c: float, dt: float, n: int) -> np.ndarray:
    """ẍ = −ω²x − c·ẋ from x = 1 with the kernel's update, ``n`` steps (ψ = φ = ½)."""
    X, V = np.array([1.0]), np.array([0.0])
    A = np.array([-(omega**2)])
    Ap = A.copy()
    xs = np.empty(n)
    for i in range(n):
        zhai_update(X, V, A, Ap, dt, 0.5, 0.5)
        A[0] = -(omega**2) * X[0] - c * V[0]
        xs[i] = X[0]
    return xs
