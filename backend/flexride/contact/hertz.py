"""Normal wheel–rail contact: Zhai's nonlinear Hertz spring and the Hertz contact ellipse.

Units are SI throughout: lengths in m, forces in N, curvatures in 1/m, moduli in Pa.

* :func:`hertz_constant` — Zhai's contact constant G (m/N^(2/3)) from the wheel radius.
* :func:`hertz_force` — compiled scalar normal force P = (δ/G)^(3/2), zero in tension.
* :func:`hertz_ellipse` — exact Hertz semi-axis factors from the relative curvatures, solved
  with the complete elliptic integrals (no table interpolation).
* :func:`hertz_contact` — the same ellipse factors and the normal contact constant of Hertz
  theory for those curvatures, G with P = (δ/G)^(3/2) (the theoretical counterpart of Zhai's
  empirical G).
"""

from __future__ import annotations

import math
from typing import Literal

import numba

from flexride._numba_env import FASTMATH
from flexride.errors import ScenarioError

__all__ = ["hertz_constant", "hertz_contact", "hertz_ellipse", "hertz_force"]

# Zhai's empirical fits G = coef · R^expo · 1e-8 (m/N^(2/3), R in m), DESIGN §6.
_ZHAI_G = {"worn": (3.86, -0.115), "conical": (4.57, -0.149)}

# Below this value of cos θ = |A − B|/(A + B) the ellipse is circular to within ~1e-7
# and the second-order series of the Hertz relations is used instead of the root search.
_COS_THETA_SERIES = 1.0e-6


def _check_positive(name: str, value: float) -> float:
    value = float(value)
    if not (math.isfinite(value) and value > 0.0):
        raise ScenarioError(f"{name} must be a finite positive number, got {value!r}")
    return value


def _check_poisson(nu: float) -> float:
    nu = float(nu)
    if not (math.isfinite(nu) and 0.0 <= nu <= 0.5):
        raise ScenarioError(f"Poisson's ratio nu must lie in [0, 0.5], got {nu!r}")
    return nu


def hertz_constant(wheel_radius: float, tread: Literal["worn", "conical"] = "worn") -> float:
    """Zhai's Hertz contact constant for a wheel on a rail.

    Parameters
    ----------
    wheel_radius : float
        Nominal rolling radius of the wheel R in m (> 0).
    tread : {"worn", "conical"}
        Tread type: ``"worn"`` (worn / LM profile, G = 3.86·R^−0.115·1e−8) or ``"conical"``
        (G = 4.57·R^−0.149·1e−8).

    Returns
    -------
    float
        Contact constant G in m/N^(2/3), to be used as P = (δ/G)^(3/2).

    Raises
    ------
    ScenarioError
        If the radius is not positive or the tread type is unknown.
    """
    radius = _check_positive("wheel_radius (m)", wheel_radius)
    if tread not in _ZHAI_G:
        raise ScenarioError(f"tread must be one of {sorted(_ZHAI_G)}, got {tread!r}")
    coef, expo = _ZHAI_G[tread]
    return coef * radius**expo * 1.0e-8


@numba.njit(cache=True, fastmath=set(FASTMATH))
def hertz_force(delta: float, G: float) -> float:
    """Nonlinear Hertz normal contact force (Zhai), compiled scalar.

    Parameters
    ----------
    delta : float
        Normal compression of the contact δ in m; δ ≤ 0 means the wheel has lifted.
    G : float
        Contact constant in m/N^(2/3) (> 0, e.g. from :func:`hertz_constant`; not checked
        here because this runs inside the time loop).

    Returns
    -------
    float
        Normal force P = (δ/G)^(3/2) in N for δ > 0, else 0 (the contact carries no tension).
    """
    if delta > 0.0:
        return (delta / G) ** 1.5
    return 0.0


def _cos_theta_of_ratio(k: float) -> float:
    """Cos θ = (B' − A')/(A' + B') of an ellipse with semi-axis ratio k = minor/major ≤ 1.

    With e² = 1 − k², K and E the complete elliptic integrals of modulus e (parameter e²),
    Hertz's compatibility conditions give (B' − A')/(A' + B') = ((1 + k²)E − 2k²K)/(e²E).
    ``ellipkm1(k²)`` = K(1 − k²) keeps K accurate for slender ellipses.
    """
    from scipy.special import ellipe, ellipkm1  # on use: a run's import stays light

    k2 = k * k
    e2 = 1.0 - k2
    big_k = ellipkm1(k2)
    big_e = ellipe(e2)
    return ((1.0 + k2) * big_e - 2.0 * k2 * big_k) / (e2 * big_e)


def _hertz_m_n(cos_theta: float) -> tuple[float, float, float]:
    """Classic Hertz coefficients (m, n) and axis ratio k = n/m for a given cos θ.

    m³ = 2E(e)/(π k²) and n = k·m, where the major semi-axis is
    m·(3πN(k1+k2)/(4(A+B)))^(1/3) (Johnson, Contact Mechanics §4.2).
    """
    if cos_theta < _COS_THETA_SERIES:
        # Near-circular: cos θ = 3e²/8 + O(e⁴), m = 1 + e²/4 + O(e⁴), k = √(1 − e²).
        e2 = 8.0 * cos_theta / 3.0
        k = math.sqrt(1.0 - e2)
        m = 1.0 + 0.25 * e2
        return m, k * m, k
    k_lo, k_hi = 1.0e-12, 1.0 - 1.0e-7
    if _cos_theta_of_ratio(k_lo) <= cos_theta:
        raise ScenarioError(
            "the contact ellipse is too slender (curvature ratio beyond 1e12); "
            "one relative curvature is practically zero (line contact)"
        )
    from scipy.optimize import brentq
    from scipy.special import ellipe

    k = brentq(lambda kk: _cos_theta_of_ratio(kk) - cos_theta, k_lo, k_hi, xtol=1e-15, rtol=1e-13)
    e2 = 1.0 - k * k
    m = (2.0 * ellipe(e2) / (math.pi * k * k)) ** (1.0 / 3.0)
    return m, k * m, k


def hertz_ellipse(A: float, B: float, E: float, nu: float) -> tuple[float, float]:
    """Hertz contact-ellipse factors for two bodies of the same elastic material.

    The semi-axes are a = ca·N^(1/3) in the rolling direction x and b = cb·N^(1/3) in the
    lateral direction y, with N the normal force in N. The larger semi-axis lies in the
    direction of the smaller relative curvature.

    Parameters
    ----------
    A : float
        Relative curvature in the rolling (x–z) plane in 1/m,
        A = ½(1/R_wheel,x + 1/R_rail,x) (> 0).
    B : float
        Relative curvature in the lateral (y–z) plane in 1/m,
        B = ½(1/R_wheel,y + 1/R_rail,y) (> 0; a concave radius enters negative).
    E : float
        Young's modulus of wheel and rail in Pa (> 0).
    nu : float
        Poisson's ratio of wheel and rail, in [0, 0.5].

    Returns
    -------
    ca, cb : float
        Semi-axis factors in m/N^(1/3).

    Raises
    ------
    ScenarioError
        For non-positive curvatures or modulus, ν outside [0, 0.5], or a degenerate (line)
        contact.

    Notes
    -----
    Classic form a = m·(3πN(k1+k2)/(4(A+B)))^(1/3), b = n·(…)^(1/3) with
    k1 = k2 = (1 − ν²)/(πE) and θ = arccos(|A − B|/(A + B)). Instead of interpolating the
    tabulated m, n, the eccentricity e is solved exactly from
    cos θ = ((1 + k²)E(e) − 2k²K(e))/(e²E(e)), k = √(1 − e²) the axis ratio, and
    m = (2E(e)/(πk²))^(1/3), n = k·m.
    """
    curv_x = _check_positive("relative curvature A (1/m)", A)
    curv_y = _check_positive("relative curvature B (1/m)", B)
    modulus = _check_positive("Young's modulus E (Pa)", E)
    nu = _check_poisson(nu)
    k_sum = 2.0 * (1.0 - nu * nu) / (math.pi * modulus)
    scale = (3.0 * math.pi * k_sum / (4.0 * (curv_x + curv_y))) ** (1.0 / 3.0)
    cos_theta = abs(curv_x - curv_y) / (curv_x + curv_y)
    m, n, _ = _hertz_m_n(cos_theta)
    if curv_x <= curv_y:  # smaller curvature along x: the major axis is in rolling direction
        return m * scale, n * scale
    return n * scale, m * scale


def hertz_contact(A: float, B: float, E: float, nu: float) -> tuple[float, float, float]:
    """Hertz ellipse factors and normal contact constant for two bodies of the same material.

    Parameters
    ----------
    A, B : float
        Relative curvatures in the rolling (x–z) and lateral (y–z) planes in 1/m (> 0), as
        for :func:`hertz_ellipse`.
    E : float
        Young's modulus in Pa (> 0).
    nu : float
        Poisson's ratio in [0, 0.5].

    Returns
    -------
    ca, cb : float
        Semi-axis factors in m/N^(1/3) (a = ca·N^(1/3) rolling, b = cb·N^(1/3) lateral).
    G : float
        Normal contact constant in m/N^(2/3): the normal approach is δ = G·N^(2/3), i.e.
        N = (δ/G)^(3/2).

    Notes
    -----
    With p0 = 3N/(2πab) and the major semi-axis a_M, the approach of two elastic half-spaces
    is δ = p0·b_m·K(e)/E* = 3N·K(e)/(2π·a_M·E*), E* = E/(2(1 − ν²)), K the complete elliptic
    integral of the first kind of the eccentricity e (Johnson, Contact Mechanics §4.2); for a
    circle it is Hertz's δ = (9N²/(16E*²R))^(1/3).
    """
    curv_x = _check_positive("relative curvature A (1/m)", A)
    curv_y = _check_positive("relative curvature B (1/m)", B)
    modulus = _check_positive("Young's modulus E (Pa)", E)
    nu = _check_poisson(nu)
    k_sum = 2.0 * (1.0 - nu * nu) / (math.pi * modulus)
    scale = (3.0 * math.pi * k_sum / (4.0 * (curv_x + curv_y))) ** (1.0 / 3.0)
    cos_theta = abs(curv_x - curv_y) / (curv_x + curv_y)
    m, n, k = _hertz_m_n(cos_theta)
    e_star = modulus / (2.0 * (1.0 - nu * nu))
    from scipy.special import ellipkm1

    big_k = float(ellipkm1(k * k))  # K(e²) with e² = 1 − k²
    g_const = 3.0 * big_k / (2.0 * math.pi * m * scale * e_star)
    if curv_x <= curv_y:
        return float(m * scale), float(n * scale), float(g_const)
    return float(n * scale), float(m * scale), float(g_const)
