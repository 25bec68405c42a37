"""Stability limit of Zhai's explicit method for the linearised system.

For the scalar test equation ẍ = −ω²x − c·ẋ the method is a linear map of
(x_n, v_n, a_{n−1}); it is stable while the spectral radius of that 3 × 3 map is ≤ 1. The
coupled system is linearised at static equilibrium (finite differences, creep damping at the
running speed included), decomposed into the modes of its symmetric stiffness, and each mode's
(ω, c) is checked with the scalar criterion. The smallest critical step is the estimate.
Non-symmetric (creep, gyroscopic) coupling is not in the modal decomposition; a safety factor
covers it.
"""

from __future__ import annotations

import numpy as np

from flexride.errors import StabilityError
from flexride.solver.assemble import Assembly
from flexride.solver.linearise import jacobian
from flexride.solver.system import CT_CA

#: The requested step must stay below this fraction of the estimated limit.
SAFETY = 0.9


def amplification_matrix(
    omega: np.ndarray, c: np.ndarray, dt: np.ndarray | float, psi: float = 0.5, phi: float = 0.5
) -> np.ndarray:
    """Zhai's one-step map of (x, v, a_prev) for ẍ = −ω²x − c·ẋ, shape (..., 3, 3)."""
    omega, c, dt = np.broadcast_arrays(
        np.asarray(omega, float), np.asarray(c, float), np.asarray(dt, float)
    )
    w2 = omega**2
    m = np.zeros((*omega.shape, 3, 3))
    m[..., 0, 0] = 1.0 - (0.5 + psi) * dt**2 * w2
    m[..., 0, 1] = dt - (0.5 + psi) * dt**2 * c
    m[..., 0, 2] = -psi * dt**2
    m[..., 1, 0] = -(1.0 + phi) * dt * w2
    m[..., 1, 1] = 1.0 - (1.0 + phi) * dt * c
    m[..., 1, 2] = -phi * dt
    m[..., 2, 0] = -w2
    m[..., 2, 1] = -c
    return m


def spectral_radius(omega, c, dt, psi: float = 0.5, phi: float = 0.5) -> np.ndarray:
    """Spectral radius of :func:`amplification_matrix`."""
    return np.abs(np.linalg.eigvals(amplification_matrix(omega, c, dt, psi, phi))).max(axis=-1)


def critical_step(
    omega: np.ndarray, c: np.ndarray, psi: float = 0.5, phi: float = 0.5, tol: float = 1e-6
) -> np.ndarray:
    """Largest stable step (s) per mode (ω in rad/s, c in 1/s), by bisection."""
    omega = np.atleast_1d(np.asarray(omega, float))
    c = np.atleast_1d(np.asarray(c, float))
    rate = np.maximum(np.maximum(omega, c), 1e-12)
    lo = np.zeros_like(rate)
    hi = 8.0 / rate
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        ok = spectral_radius(omega, c, mid, psi, phi) <= 1.0 + 1e-9
        lo = np.where(ok, mid, lo)
        hi = np.where(ok, hi, mid)
        if np.all(hi - lo <= tol * hi):
            break
    return lo


def creep_relaxation_time(asm: Assembly) -> float:
    """Relaxation time of the creep forces at the static wheel load, τ = a/V (s)."""
    sys = asm.sys
    n_wheels = 2 * len(asm.vehicle.wheelsets)
    load = asm.vehicle.total_mass * sys.par.gravity / n_wheels
    i0 = round(-sys.par.ct_y0 / (asm.contact.dy))
    a = sys.ct[0, CT_CA, i0] * load ** (1.0 / 3.0)
    return float(a / max(sys.par.speed, sys.par.v_min))


def _nice_step(dt: float) -> float:
    """Round a step down to 1, 2 or 5 × 10^k."""
    e = np.floor(np.log10(dt))
    for m in (5.0, 2.0, 1.0):
        if m * 10**e <= dt:
            return float(m * 10**e)
    return float(10**e)


def stability_limit(asm: Assembly, X0: np.ndarray, s: float, s_win0: float) -> dict:
    """Estimate the largest stable time step of the linearised system at ``X0``.

    Returns
    -------
    dict
        ``dt_max`` (s), ``omega_max`` (rad/s), ``critical_dof`` (name of the coordinate with the
        largest share in the critical mode) and ``dt_suggested`` (s).
    """
    sys = asm.sys
    n = X0.shape[0]
    V0 = np.zeros(n)
    cols = np.arange(n)
    K = -jacobian(sys, X0, V0, s, s_win0, cols)  # = M⁻¹K
    C = -jacobian(sys, X0, V0, s, s_win0, cols, wrt_velocity=True)  # = M⁻¹C
    # creep forces relax over τ = a/V (transient rolling contact): the creep "damper" c acts in
    # series with the contact's tangential stiffness c/τ. Take the creep part of C (difference
    # to a run without friction) into the stiffness.
    no_friction = sys._replace(par=sys.par._replace(mu=0.0))
    C0 = -jacobian(no_friction, X0, V0, s, s_win0, cols, wrt_velocity=True)
    tau = creep_relaxation_time(asm)
    K = K + (C - C0) / tau
    C = C0
    sq = np.sqrt(1.0 / sys.minv)
    isq = 1.0 / sq
    Ks = sq[:, None] * K * isq[None, :]
    Cs = sq[:, None] * C * isq[None, :]
    Ks = 0.5 * (Ks + Ks.T)
    Cs = 0.5 * (Cs + Cs.T)
    lam, vec = np.linalg.eigh(Ks)
    omega = np.sqrt(np.clip(lam, 0.0, None))
    cm = np.sum(vec * (Cs @ vec), axis=0)  # modal damping vᵀCv of each mode (BLAS, not einsum)
    cm = np.clip(cm, 0.0, None)
    dts = critical_step(omega, cm, sys.par.psi, sys.par.phi)
    j = int(np.argmin(dts))
    dt_max = float(dts[j]) * SAFETY
    dof = asm.dof_names[int(np.argmax(np.abs(vec[:, j])))]
    return {
        "dt_max": dt_max,
        "omega_max": float(omega.max()),
        "critical_dof": dof,
        "critical_frequency_hz": float(omega[j] / (2 * np.pi)),
        "dt_suggested": _nice_step(0.8 * dt_max),
    }


def check_stability(asm: Assembly, X0: np.ndarray, s: float, s_win0: float) -> dict:
    """Raise :class:`StabilityError` if the scenario's step exceeds the estimated limit."""
    return check_step(stability_limit(asm, X0, s, s_win0), float(asm.sys.par.dt))


def check_step(info: dict, dt: float) -> dict:
    """Raise :class:`StabilityError` if the step ``dt`` (s) exceeds the limit ``info`` of
    :func:`stability_limit`; return ``info``.
    """
    if dt > info["dt_max"]:
        raise StabilityError(
            f"time step solver.dt = {dt:g} s is beyond the stability limit of Zhai's explicit "
            f"method for this system (estimated {info['dt_max']:.3g} s, set by a "
            f"{info['critical_frequency_hz']:.0f} Hz mode dominated by {info['critical_dof']}); "
            f"use solver.dt = {info['dt_suggested']:g} s",
            dt=dt,
            dt_max=info["dt_max"],
            dt_suggested=info["dt_suggested"],
        )
    return info
