"""The 60E1 (UIC60) rail head of EN 13674-1 from its construction.

The head is symmetric: an R300 crown, R80 shoulders, R13 gauge corners and 1:20 head sides
(one lateral per twenty vertical, widening downward), all tangent. With u lateral (mm) and v
up (mm) from the crown top on the rail axis, the breakpoints are |u| = X1 = 20.456/2 (R300/R80)
and X2 = 52.053/2 (R80/R13); each centre follows from tangency,
centre_{k+1} = centre_k + (R_k − R_{k+1})·(sin φ_k, cos φ_k) with sin φ_k the lateral offset of
the breakpoint from centre_k over R_k, and the R13/side tangent is where the R13 normal is
perpendicular to the 1:20 line. Source: ``reference/wheel-rail-profiles.md`` §1.2 (GENSYS
"Creation of a rail profile from a drawing" and the EN 13674-1:2017 breakpoints).

Only the head contour matters for wheel–rail contact; the profile ends on the head sides
:data:`HEAD_DEPTH` below the crown top (the head underside, 1:2.75, begins about 37.5 mm down).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from flexride.contact.profiles.profile import Profile
from flexride.errors import ScenarioError

__all__ = ["HEAD_DEPTH", "Rail60E1Geometry", "rail_60e1", "rail_60e1_geometry", "rail_60e1_height"]

#: Depth of the sampled head contour below the crown top (mm).
HEAD_DEPTH = 35.0

_R1, _R2, _R3 = 300.0, 80.0, 13.0
_X1, _X2 = 20.456 / 2.0, 52.053 / 2.0
_SIDE_SLOPE = 20.0  # vertical per lateral of the head side


@dataclass(frozen=True)
class Rail60E1Geometry:
    """Construction of the 60E1 head (mm, u lateral to the field side, v up, origin at the crown
    top on the rail axis; the gauge side is the mirror image).

    Attributes
    ----------
    c_crown, c_shoulder, c_corner : tuple of float
        Centres (u, v) of the R300, R80 and R13 arcs.
    t_crown, t_shoulder, t_side : tuple of float
        Tangent points R300/R80, R80/R13 and R13/side line.
    """

    c_crown: tuple[float, float]
    c_shoulder: tuple[float, float]
    c_corner: tuple[float, float]
    t_crown: tuple[float, float]
    t_shoulder: tuple[float, float]
    t_side: tuple[float, float]


def rail_60e1_geometry() -> Rail60E1Geometry:
    """Centres and tangent points of the 60E1 head construction (mm)."""
    c1 = np.array([0.0, -_R1])
    s1 = _X1 / _R1
    n1 = np.array([s1, math.sqrt(1.0 - s1 * s1)])
    c2 = c1 + (_R1 - _R2) * n1
    s2 = (_X2 - c2[0]) / _R2
    n2 = np.array([s2, math.sqrt(1.0 - s2 * s2)])
    c3 = c2 + (_R2 - _R3) * n2
    n3 = np.array([_SIDE_SLOPE, 1.0]) / math.hypot(_SIDE_SLOPE, 1.0)
    t1, t2, t3 = c1 + _R1 * n1, c2 + _R2 * n2, c3 + _R3 * n3

    def pt(a: np.ndarray) -> tuple[float, float]:
        return float(a[0]), float(a[1])

    return Rail60E1Geometry(pt(c1), pt(c2), pt(c3), pt(t1), pt(t2), pt(t3))


def rail_60e1_height(u: np.ndarray | float, depth: float = HEAD_DEPTH) -> np.ndarray:
    """Height v(u) of the 60E1 head in mm (0 at the crown top), symmetric in u.

    Parameters
    ----------
    u : array_like
        Lateral coordinate in mm; |u| up to the head side at ``depth`` below the top.
    depth : float
        Depth in mm where the head side ends.

    Returns
    -------
    numpy.ndarray
        v in mm (NaN beyond the head side at that depth).
    """
    g = rail_60e1_geometry()
    a = np.abs(np.asarray(u, dtype=np.float64))
    (c1u, c1v), (c2u, c2v), (c3u, c3v) = g.c_crown, g.c_shoulder, g.c_corner
    tu, tv = g.t_side
    with np.errstate(invalid="ignore"):
        v = np.where(
            a <= _X1,
            c1v + np.sqrt(_R1 * _R1 - (a - c1u) ** 2),
            np.where(
                a <= _X2,
                c2v + np.sqrt(_R2 * _R2 - (a - c2u) ** 2),
                np.where(a <= tu, c3v + np.sqrt(_R3 * _R3 - (a - c3u) ** 2),
                         tv - _SIDE_SLOPE * (a - tu)),
            ),
        )
    return np.where(v >= -depth - 1e-12, v, np.nan)


def rail_60e1(step: float = 5.0e-5, depth: float = HEAD_DEPTH * 1e-3,
              name: str = "60E1 (EN 13674-1)") -> Profile:
    """The 60E1 head as a rail :class:`Profile` (un-canted, origin at the crown top, m).

    Parameters
    ----------
    step : float
        Sampling step in m along the contour (default 0.05 mm), uniform in arc length on each
        element; every tangent point is a point.
    depth : float
        Depth in m where the head sides end (default 35 mm).
    name : str
        Source name.

    Returns
    -------
    Profile
    """
    h = float(step) * 1e3
    d = float(depth) * 1e3
    if not (math.isfinite(h) and 1e-4 <= h <= 1.0):
        raise ScenarioError(f"60E1 sampling step must lie in [1e-7, 1e-3] m, got {step!r}")
    g = rail_60e1_geometry()
    if not (math.isfinite(d) and -g.t_side[1] + 1.0 <= d <= 37.0):
        raise ScenarioError(f"60E1 head depth must lie in [15.3, 37] mm, got {d!r}")
    # field half, sampled uniformly in arc length element by element (tangent points included)
    parts = []
    for (cu, cv), r, (u0, v0), (u1, v1) in (
        (g.c_crown, _R1, (0.0, 0.0), g.t_crown),
        (g.c_shoulder, _R2, g.t_crown, g.t_shoulder),
        (g.c_corner, _R3, g.t_shoulder, g.t_side),
    ):
        a0, a1 = math.atan2(u0 - cu, v0 - cv), math.atan2(u1 - cu, v1 - cv)
        k = max(2, math.ceil(r * (a1 - a0) / h))
        ang = np.linspace(a0, a1, k + 1)[:-1]
        parts.append(np.stack([cu + r * np.sin(ang), cv + r * np.cos(ang)]))
    tu, tv = g.t_side
    side_len = (tv + d) * math.hypot(1.0, 1.0 / _SIDE_SLOPE)
    k = max(2, math.ceil(side_len / h))
    v_side = np.linspace(tv, -d, k + 1)
    parts.append(np.stack([tu + (tv - v_side) / _SIDE_SLOPE, v_side]))
    u, v = np.concatenate(parts, axis=1)
    yy = np.concatenate([-u[:0:-1], u]) * 1e-3
    zz = np.concatenate([v[:0:-1], v]) * 1e-3
    return Profile("rail", yy, zz, name)
