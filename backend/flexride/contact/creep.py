"""Tangential wheel–rail contact: Kalker linear creep forces with Shen–Hedrick–Elkins saturation.

Compiled (numba, ``cache=True``) scalar functions that the solver kernel calls inside its
time loop: no allocation, no exceptions, tuples returned. Inputs are not validated here;
the geometry tables and the scenario schema guarantee them.

Sign convention (DESIGN §6): the creep forces act on the wheel and oppose the creepages,
F_x = −f11·ξ_x, F_y = −f22·ξ_y − f23·φ, M_z = f23·ξ_y − f33·φ, with f11 = G·a·b·C11,
f22 = G·a·b·C22, f23 = G·(ab)^(3/2)·C23, f33 = G·(ab)²·C33.
"""

from __future__ import annotations

import math

import numba

from flexride._numba_env import FASTMATH

__all__ = ["creep_forces", "she_saturation"]


@numba.njit(cache=True, fastmath=set(FASTMATH))
def she_saturation(
    Fx: float, Fy: float, Mz: float, mu: float, N: float
) -> tuple[float, float, float]:
    """Shen–Hedrick–Elkins saturation of linear creep forces to the Coulomb limit μN.

    Parameters
    ----------
    Fx, Fy : float
        Linear (unsaturated) longitudinal and lateral creep forces in N.
    Mz : float
        Linear spin moment in N·m.
    mu : float
        Coefficient of friction (dimensionless, ≥ 0).
    N : float
        Normal force in N.

    Returns
    -------
    Fx', Fy', Mz' : float
        Saturated forces in N and moment in N·m: all three scaled by ε = F'/F with
        F = √(Fx² + Fy²), x = F/(μN) and F' = μN(x − x²/3 + x³/27) for x ≤ 3, F' = μN beyond.
        Zeros when μN ≤ 0 (no load, no friction); the inputs unchanged when F = 0 (ε → 1).

    Notes
    -----
    ε is evaluated as 1 − x/3 + x²/27 (x ≤ 3) or 1/x (x > 3), so there is no 0/0 at F = 0.
    F' and dF'/dx are continuous at x = 3 (F' = μN, slope 0).
    """
    limit = mu * N
    if not limit > 0.0:
        return 0.0, 0.0, 0.0
    force = math.hypot(Fx, Fy)
    x = force / limit
    if x <= 3.0:
        eps = 1.0 - x / 3.0 + x * x / 27.0
    else:
        eps = 1.0 / x
    return Fx * eps, Fy * eps, Mz * eps


@numba.njit(cache=True, fastmath=set(FASTMATH))
def creep_forces(
    xi_x: float,
    xi_y: float,
    phi_spin: float,
    N: float,
    ca: float,
    cb: float,
    c11: float,
    c22: float,
    c23: float,
    c33: float,
    G_shear: float,
    mu: float,
) -> tuple[float, float, float]:
    """Saturated creep forces on the wheel at one contact (Kalker linear + SHE).

    Parameters
    ----------
    xi_x, xi_y : float
        Longitudinal and lateral creepages (dimensionless).
    phi_spin : float
        Spin creepage in 1/m.
    N : float
        Normal force in N; N ≤ 0 (no contact) gives zero forces.
    ca, cb : float
        Hertz ellipse factors in m/N^(1/3): a = ca·N^(1/3) (rolling), b = cb·N^(1/3) (lateral).
    c11, c22, c23, c33 : float
        Kalker's coefficients (dimensionless) for the patch's axis ratio.
    G_shear : float
        Shear modulus of wheel and rail in Pa.
    mu : float
        Coefficient of friction (dimensionless).

    Returns
    -------
    Fx, Fy : float
        Longitudinal and lateral creep forces on the wheel in N (contact frame).
    Mz : float
        Spin creep moment on the wheel in N·m.
    """
    if not N > 0.0:
        return 0.0, 0.0, 0.0
    n13 = N ** (1.0 / 3.0)
    ab = ca * cb * n13 * n13
    f11 = G_shear * ab * c11
    f22 = G_shear * ab * c22
    f23 = G_shear * ab * math.sqrt(ab) * c23
    f33 = G_shear * ab * ab * c33
    fx = -f11 * xi_x
    fy = -f22 * xi_y - f23 * phi_spin
    mz = f23 * xi_y - f33 * phi_spin
    return she_saturation(fx, fy, mz, mu, N)
