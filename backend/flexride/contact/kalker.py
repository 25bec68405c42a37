"""Kalker's linear creep coefficients C11, C22, C23, C33 and the creep coefficients f_ij.

Source: Kalker, *Three-dimensional elastic bodies in rolling contact* (1990), Table E.3, as
reproduced in ``reference/kalker-coefficients.md``. a is the contact semi-axis in the rolling
direction x, b the lateral one; g = a/b for a ≤ b and g = b/a for a > b.

Interpolation is linear in ν (grid 0, 0.25, 0.5) and linear in g (grid 0.1 … 1.0). The a > b
branch shares the g = 1 row of the a ≤ b table (a = b is the same circle in both branches), so
the coefficients are continuous across a = b.

Below g = 0.1 Kalker's asymptotes (exact as g → 0) are used, multiplied by the factor
ρ^(g/0.1) with ρ = table(0.1)/asymptote(0.1). The asymptotes differ from the table by up to
~6 % at g = 0.1, so using them raw would put a jump into the coefficients exactly where a
contact patch becomes slender; the factor removes the jump and tends to 1 as g → 0. For
a ≫ b Kalker gives no spin (C33) asymptote; C33 is held at its g = 0.1 table value there
(it varies slowly: 0.828 → 0.795 from g = 0.2 to 0.1 at ν = 0).
"""

from __future__ import annotations

import math

import numpy as np

from flexride.errors import ScenarioError

__all__ = ["creep_coefficients", "kalker_coefficients", "kalker_from_axes"]

_NU_GRID = np.array([0.0, 0.25, 0.5])

# [g index (0.1 … 1.0), coefficient (C11, C22, C23, C33), ν index (0, 0.25, 0.5)]
_TABLE_A_LE_B = np.array(
    [
        [[2.51, 3.31, 4.85], [2.51, 2.52, 2.53], [0.334, 0.473, 0.731], [6.42, 8.28, 11.7]],
        [[2.59, 3.37, 4.81], [2.59, 2.63, 2.66], [0.483, 0.603, 0.809], [3.46, 4.27, 5.66]],
        [[2.68, 3.44, 4.80], [2.68, 2.75, 2.81], [0.607, 0.715, 0.889], [2.49, 2.96, 3.72]],
        [[2.78, 3.53, 4.82], [2.78, 2.88, 2.98], [0.720, 0.823, 0.977], [2.02, 2.32, 2.77]],
        [[2.88, 3.62, 4.83], [2.88, 3.01, 3.14], [0.827, 0.929, 1.07], [1.74, 1.93, 2.22]],
        [[2.98, 3.72, 4.91], [2.98, 3.14, 3.31], [0.930, 1.03, 1.18], [1.56, 1.68, 1.86]],
        [[3.09, 3.81, 4.97], [3.09, 3.28, 3.48], [1.03, 1.14, 1.29], [1.43, 1.50, 1.60]],
        [[3.19, 3.91, 5.05], [3.19, 3.41, 3.65], [1.13, 1.25, 1.40], [1.34, 1.37, 1.42]],
        [[3.29, 4.01, 5.12], [3.29, 3.54, 3.82], [1.23, 1.36, 1.51], [1.27, 1.27, 1.27]],
        [[3.40, 4.12, 5.20], [3.40, 3.67, 3.98], [1.33, 1.47, 1.63], [1.21, 1.19, 1.16]],
    ]
)

# a > b, g = b/a, ordered g = 0.1 … 0.9; the g = 1.0 row is shared with the a ≤ b table.
_TABLE_A_GT_B = np.concatenate(
    [
        np.array(
            [
                [[10.7, 11.7, 12.9], [10.7, 12.8, 16.0], [12.2, 14.6, 18.0], [0.795, 0.526, 0.228]],
                [[6.96, 7.78, 8.82], [6.96, 8.14, 9.79], [5.72, 6.63, 7.89], [0.828, 0.601, 0.341]],
                [[5.57, 6.34, 7.34], [5.57, 6.40, 7.51], [3.79, 4.32, 5.01], [0.868, 0.674, 0.446]],
                [[4.84, 5.57, 6.57], [4.84, 5.48, 6.31], [2.88, 3.24, 3.70], [0.912, 0.747, 0.549]],
                [[4.37, 5.10, 6.11], [4.37, 4.90, 5.56], [2.35, 2.62, 2.96], [0.958, 0.819, 0.650]],
                [[4.06, 4.78, 5.80], [4.06, 4.50, 5.04], [2.01, 2.23, 2.50], [1.01, 0.892, 0.751]],
                [[3.82, 4.54, 5.58], [3.82, 4.21, 4.67], [1.76, 1.95, 2.18], [1.05, 0.965, 0.852]],
                [[3.65, 4.36, 5.42], [3.65, 3.99, 4.39], [1.58, 1.75, 1.94], [1.10, 1.04, 0.954]],
                [[3.51, 4.22, 5.30], [3.51, 3.81, 4.16], [1.44, 1.59, 1.77], [1.16, 1.11, 1.06]],
            ]
        ),
        _TABLE_A_LE_B[-1:],
    ]
)

_G_MIN_TABLE = 0.1


def _check_nu(nu: float) -> float:
    nu = float(nu)
    if not (math.isfinite(nu) and 0.0 <= nu <= 0.5):
        raise ScenarioError(f"Poisson's ratio nu must lie in [0, 0.5], got {nu!r}")
    return nu


def _table_value(g: float, nu: float, a_le_b: bool) -> np.ndarray:
    """Bilinear interpolation of (C11, C22, C23, C33) for 0.1 ≤ g ≤ 1."""
    table = _TABLE_A_LE_B if a_le_b else _TABLE_A_GT_B
    # ν first: [g, coefficient]
    j = min(int(nu / 0.25), 1)
    t_nu = (nu - _NU_GRID[j]) / 0.25
    by_g = (1.0 - t_nu) * table[:, :, j] + t_nu * table[:, :, j + 1]
    pos = round((g - 0.1) / 0.1, 12)  # rounded so that grid points give t_g of exactly 0 or 1
    i = min(int(pos), 8)
    t_g = pos - i
    return (1.0 - t_g) * by_g[i] + t_g * by_g[i + 1]


def _asymptote(g: float, nu: float, a_le_b: bool) -> np.ndarray:
    """Kalker's slender-ellipse asymptotes of (C11, C22, C23, C33) for g → 0.

    For a ≫ b, C33 has no asymptote in the reference; the g = 0.1 table value is returned.
    """
    pi = math.pi
    if a_le_b:
        c11 = pi**2 / (4.0 * (1.0 - nu))
        c22 = pi**2 / 4.0
        c23 = pi * math.sqrt(g) / (3.0 * (1.0 - nu)) * (1.0 + nu * (math.log(16.0 / g) - 5.0))
        c33 = pi**2 / (16.0 * (1.0 - nu) * g)
        return np.array([c11, c22, c23, c33])
    al = math.log(16.0 / g**2)
    ln4 = math.log(4.0)
    c11 = 2.0 * pi / ((al - 2.0 * nu) * g) * (1.0 + (3.0 - ln4) / (al - 2.0 * nu))
    den = (1.0 - nu) * al + 2.0 * nu
    c22 = 2.0 * pi / g * (1.0 + (1.0 - nu) * (3.0 - ln4) / den) / den
    c23 = 2.0 * pi / (3.0 * g**1.5 * ((1.0 - nu) * al - 2.0 + 4.0 * nu))
    c33 = _table_value(_G_MIN_TABLE, nu, a_le_b=False)[3]
    return np.array([c11, c22, c23, c33])


def kalker_coefficients(
    g_ratio: float, nu: float, a_le_b: bool
) -> tuple[float, float, float, float]:
    """Kalker's linear creep coefficients for an elliptic contact patch.

    Parameters
    ----------
    g_ratio : float
        Axis ratio g ≤ 1 (dimensionless): a/b if ``a_le_b`` else b/a, in (0, 1].
    nu : float
        Poisson's ratio, in [0, 0.5].
    a_le_b : bool
        True when the rolling-direction semi-axis a is not larger than the lateral one b.

    Returns
    -------
    C11, C22, C23, C33 : float
        Dimensionless coefficients (longitudinal, lateral, lateral–spin, spin).

    Raises
    ------
    ScenarioError
        If g is outside (0, 1] or ν outside [0, 0.5].

    Notes
    -----
    Linear interpolation in ν and g inside the table (0.1 ≤ g ≤ 1); below g = 0.1 Kalker's
    asymptotes blended continuously into the table (see the module docstring).
    """
    g = float(g_ratio)
    if not (math.isfinite(g) and 0.0 < g <= 1.0):
        raise ScenarioError(f"axis ratio g must lie in (0, 1], got {g_ratio!r}")
    nu = _check_nu(nu)
    a_le_b = bool(a_le_b)
    if g >= _G_MIN_TABLE:
        c = _table_value(g, nu, a_le_b)
    else:
        ratio = _table_value(_G_MIN_TABLE, nu, a_le_b) / _asymptote(_G_MIN_TABLE, nu, a_le_b)
        c = _asymptote(g, nu, a_le_b) * ratio ** (g / _G_MIN_TABLE)
    return float(c[0]), float(c[1]), float(c[2]), float(c[3])


def kalker_from_axes(a: float, b: float, nu: float) -> tuple[float, float, float, float]:
    """Kalker's coefficients for the contact semi-axes a (rolling direction) and b (lateral).

    Parameters
    ----------
    a, b : float
        Contact semi-axes in m (> 0); only their ratio matters, so the N-independent
        factors ca, cb (m/N^(1/3)) may be passed as well.
    nu : float
        Poisson's ratio, in [0, 0.5].

    Returns
    -------
    C11, C22, C23, C33 : float
        Dimensionless coefficients; branch a ≤ b with g = a/b, else a > b with g = b/a.
    """
    a, b = _check_axes(a, b)
    if a <= b:
        return kalker_coefficients(a / b, nu, a_le_b=True)
    return kalker_coefficients(b / a, nu, a_le_b=False)


def _check_axes(a: float, b: float) -> tuple[float, float]:
    a, b = float(a), float(b)
    for name, value in (("a", a), ("b", b)):
        if not (math.isfinite(value) and value > 0.0):
            raise ScenarioError(
                f"contact semi-axis {name} (m) must be a finite positive number, got {value!r}"
            )
    return a, b


def creep_coefficients(
    a: float,
    b: float,
    G_shear: float,
    nu: float,
) -> tuple[float, float, float, float]:
    """Kalker's linear creep coefficients f11, f22, f23, f33 of one contact.

    Parameters
    ----------
    a, b : float
        Contact semi-axes in m (a rolling direction, b lateral), > 0.
    G_shear : float
        Combined shear modulus of wheel and rail G in Pa (> 0), G = E/(2(1 + ν)).
    nu : float
        Poisson's ratio, in [0, 0.5].

    Returns
    -------
    f11 : float
        Longitudinal coefficient G·a·b·C11 in N.
    f22 : float
        Lateral coefficient G·a·b·C22 in N.
    f23 : float
        Lateral/spin coefficient G·(ab)^(3/2)·C23 in N·m.
    f33 : float
        Spin coefficient G·(ab)²·C33 in N·m².
    """
    a, b = _check_axes(a, b)
    shear = float(G_shear)
    if not (math.isfinite(shear) and shear > 0.0):
        raise ScenarioError(f"shear modulus G_shear (Pa) must be positive, got {G_shear!r}")
    c11, c22, c23, c33 = kalker_from_axes(a, b, nu)
    ab = a * b
    return shear * ab * c11, shear * ab * c22, shear * ab**1.5 * c23, shear * ab**2 * c33
