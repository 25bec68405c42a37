"""The :class:`Profile` type: one wheel or rail cross-section as a point list, and its smooth
evaluation (:class:`ProfileCurve`).

Convention (both kinds, SI units)
---------------------------------
A profile is a curve (y, z) in m in its own frame, drawn as for the **left** side of the track
in project axes (ISO 8855, y to the left, z up); the right side is its mirror image:

* ``y`` lateral, positive toward the **field side** (away from the track centre), strictly
  increasing along the point list;
* ``z`` vertical, positive **up**.

Wheel: origin at the taping line (nominal rolling circle), so y = s of EN 13715 (flange back at
s = −70 mm for S1002) and z = −F(s), the negative radius increase: the flange points down
(toward the rail) and lies at negative y. Rail: origin at the profile's reference point (for
the built-in 60E1 head the crown top on the rail axis, un-canted); the gauge side is at
negative y, the head top is the highest point.

The file readers (:mod:`flexride.contact.profiles.readers`) convert every format to this
convention; mm in the files become m here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from flexride.errors import ScenarioError

__all__ = [
    "MAX_POINTS",
    "MIN_POINTS",
    "MIN_SPACING",
    "Profile",
    "ProfileCurve",
    "ProfileKind",
    "SampledProfile",
]

ProfileKind = Literal["wheel", "rail"]

#: Fewest points a profile may have.
MIN_POINTS = 10
#: Most points a profile may have (bounds the work of an uploaded profile).
MAX_POINTS = 200_000
#: Points closer than this to the previous kept point are dropped by the readers (m).
MIN_SPACING = 1.0e-7
#: A rail's highest point must lie at least this far above both ends of the profile (m).
_RAIL_END_DROP = 1.0e-3


def _where(name: str, lines: np.ndarray | None, i: int) -> str:
    if lines is not None and 0 <= i < lines.shape[0] and lines[i] > 0:
        return f"{name}, line {int(lines[i])}"
    return f"{name}, point {i + 1}"


@dataclass(frozen=True, eq=False)
class Profile:
    """A wheel or rail cross-section (convention in the module docstring).

    Parameters
    ----------
    kind : {"wheel", "rail"}
        What the profile describes.
    y, z : array_like
        Point coordinates in m, shape [n] each, n ≥ :data:`MIN_POINTS`; y strictly increasing
        toward the field side, z up.
    name : str
        Source name used in messages: a file name (never a directory) or a standard's name.
    lines : array_like of int, optional
        Source line of each point (1-based; 0 where unknown), for error messages.

    Raises
    ------
    ScenarioError
        Naming ``name`` (and the line where known) for: wrong kind, shapes, too few or too many
        points, NaN or inf, y not strictly increasing, a wheel whose flange is not the lowest
        feature at negative y or whose taping line y = 0 is outside the profile, a rail whose
        highest point is not inside the profile.
    """

    kind: ProfileKind
    y: np.ndarray
    z: np.ndarray
    name: str
    lines: np.ndarray | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        """Check the points (finite, enough, ordered) and the kind."""
        name = self.name
        if self.kind not in ("wheel", "rail"):
            raise ScenarioError(
                f"{name}: profile kind must be 'wheel' or 'rail', got {self.kind!r}"
            )
        y = np.array(self.y, dtype=np.float64).reshape(-1)
        z = np.array(self.z, dtype=np.float64).reshape(-1)
        lines = None if self.lines is None else np.array(self.lines, dtype=np.int64).reshape(-1)
        if y.shape != z.shape:
            raise ScenarioError(f"{name}: y and z have different lengths ({y.size}, {z.size})")
        if lines is not None and lines.shape != y.shape:
            lines = None
        n = y.size
        if n < MIN_POINTS:
            raise ScenarioError(
                f"{name}: a {self.kind} profile needs at least {MIN_POINTS} points, got {n}"
            )
        if n > MAX_POINTS:
            raise ScenarioError(f"{name}: too many points ({n} > {MAX_POINTS})")
        bad = np.flatnonzero(~(np.isfinite(y) & np.isfinite(z)))
        if bad.size:
            raise ScenarioError(f"{_where(name, lines, int(bad[0]))}: coordinate is NaN or inf")
        step = np.diff(y)
        back = np.flatnonzero(step <= 0.0)
        if back.size:
            i = int(back[0]) + 1
            raise ScenarioError(
                f"{_where(name, lines, i)}: lateral coordinate not increasing "
                f"(y = {y[i] * 1e3:.6g} mm after {y[i - 1] * 1e3:.6g} mm); the profile must be "
                "a single curve without folds"
            )
        if self.kind == "wheel":
            self._check_wheel(y, z, lines)
        else:
            self._check_rail(y, z, lines)
        for arr in (y, z):
            arr.flags.writeable = False
        object.__setattr__(self, "y", y)
        object.__setattr__(self, "z", z)
        if lines is not None:
            lines.flags.writeable = False
        object.__setattr__(self, "lines", lines)

    def _check_wheel(self, y: np.ndarray, z: np.ndarray, lines: np.ndarray | None) -> None:
        name = self.name
        zmed = float(np.median(z))
        if zmed - z.min() <= z.max() - zmed:
            raise ScenarioError(
                f"{name}: wrong orientation of the wheel profile: the flange must point down "
                "(z up, z = minus the radius increase)"
            )
        tip = int(np.argmin(z))
        if y[tip] >= 0.0:
            raise ScenarioError(
                f"{_where(name, lines, tip)}: wrong orientation of the wheel profile: the flange "
                "tip is at y >= 0; the flange must lie at negative y (gauge side) with the "
                "taping line at y = 0 (mirror the profile)"
            )
        if not (y[0] < 0.0 < y[-1]):
            raise ScenarioError(
                f"{name}: the taping line y = 0 lies outside the wheel profile "
                f"({y[0] * 1e3:.6g} … {y[-1] * 1e3:.6g} mm); wheel coordinates must be measured "
                "from the taping line"
            )

    def _check_rail(self, y: np.ndarray, z: np.ndarray, lines: np.ndarray | None) -> None:
        top = int(np.argmax(z))
        if z[0] > z[top] - _RAIL_END_DROP or z[-1] > z[top] - _RAIL_END_DROP:
            raise ScenarioError(
                f"{_where(self.name, lines, top)}: wrong orientation of the rail profile: the "
                "head top must be the highest point, inside the profile and at least 1 mm above "
                "both ends (z up)"
            )

    @property
    def n(self) -> int:
        """Number of points."""
        return int(self.y.size)

    def with_name(self, name: str) -> Profile:
        """The same points under another source name."""
        return Profile(self.kind, self.y, self.z, name, self.lines)

    def digest(self) -> str:
        """SHA-256 of the kind and the point coordinates (the content hash used by caches)."""
        import hashlib

        h = hashlib.sha256(self.kind.encode())
        h.update(np.ascontiguousarray(self.y).tobytes())
        h.update(np.ascontiguousarray(self.z).tobytes())
        return h.hexdigest()

    def curve(self, smoothing_length: float = 0.0) -> ProfileCurve:
        """Smooth evaluation of the profile (see :class:`ProfileCurve`).

        Parameters
        ----------
        smoothing_length : float
            0 (default) interpolates the points with cubic splines; a positive value in m
            smooths them (measured profiles): features shorter than about this wavelength
            along the curve are attenuated.
        """
        return ProfileCurve(self, smoothing_length)


@dataclass(frozen=True)
class SampledProfile:
    """A profile sampled on a uniform lateral grid: y_i = y0 + i·h, i = 0 … n − 1.

    Attributes
    ----------
    y0 : float
        First grid point in m.
    h : float
        Grid step in m.
    z : numpy.ndarray
        Height in m, shape [n].
    angle : numpy.ndarray
        Slope angle atan(dz/dy) in rad, shape [n] (±π/2 at vertical tangents).
    curvature : numpy.ndarray
        Signed curvature in 1/m, shape [n]: positive where the curve bends upward
        (z'' > 0), e.g. −1/300 mm⁻¹ on the un-canted 60E1 crown.
    """

    y0: float
    h: float
    z: np.ndarray
    angle: np.ndarray
    curvature: np.ndarray

    @property
    def y(self) -> np.ndarray:
        """Grid in m."""
        return self.y0 + self.h * np.arange(self.z.size)


class ProfileCurve:
    """Parametric cubic-spline representation of a :class:`Profile`.

    y(σ) and z(σ) are splines of the chord length σ along the point list (interpolating, or
    smoothing splines with penalty λ∫(f'')² and λ = (ℓ/2π)⁴ for a smoothing length ℓ), so
    vertical and steep parts (flange flank, rail side) are represented as well as the tread.
    Slope angle and curvature come from the spline derivatives. Every query may rotate the
    curve first by an angle α counter-clockwise in the (y, z) plane (a rail canted toward the
    track centre: α > 0 lowers the gauge side).

    Parameters
    ----------
    profile : Profile
        The points.
    smoothing_length : float
        0 to interpolate, else the smoothing length ℓ in m.
    """

    def __init__(self, profile: Profile, smoothing_length: float = 0.0) -> None:
        ell = float(smoothing_length)
        if not (math.isfinite(ell) and ell >= 0.0):
            raise ScenarioError(f"smoothing length (m) must be >= 0, got {smoothing_length!r}")
        self.profile = profile
        self.smoothing_length = ell
        y, z = profile.y, profile.z
        sigma = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(y), np.diff(z)))])
        self.sigma = sigma
        # on use: a run whose profile table is cached does not import scipy.interpolate
        from scipy.interpolate import CubicSpline, make_smoothing_spline

        if ell > 0.0:
            lam = (ell / (2.0 * math.pi)) ** 4 / float(np.mean(np.diff(sigma)))
            self._y = make_smoothing_spline(sigma, y, lam=lam)
            self._z = make_smoothing_spline(sigma, z, lam=lam)
        else:
            self._y = CubicSpline(sigma, y)
            self._z = CubicSpline(sigma, z)
        # dense evaluation shared by the queries (≥ 8 points per data interval)
        m = max(20_001, 8 * sigma.size)
        self._sd = np.linspace(0.0, sigma[-1], m)
        self._yd = self._y(self._sd)
        self._zd = self._z(self._sd)

    def _rotated(self, s: np.ndarray, alpha: float, der: int = 0) -> tuple[np.ndarray, np.ndarray]:
        c, sn = math.cos(alpha), math.sin(alpha)
        yy, zz = self._y(s, der), self._z(s, der)
        return c * yy - sn * zz, sn * yy + c * zz

    def _dense(self, alpha: float) -> tuple[np.ndarray, np.ndarray]:
        c, sn = math.cos(alpha), math.sin(alpha)
        return c * self._yd - sn * self._zd, sn * self._yd + c * self._zd

    def y_range(self, alpha: float = 0.0) -> tuple[float, float]:
        """Lateral extent in m of the curve rotated by ``alpha`` (rad)."""
        yr, _ = self._dense(alpha)
        return float(yr.min()), float(yr.max())

    def sample(self, h: float, y0: float | None = None, y1: float | None = None,
               alpha: float = 0.0) -> SampledProfile:
        """Height, slope angle and curvature on a uniform lateral grid.

        Parameters
        ----------
        h : float
            Grid step in m (> 0).
        y0, y1 : float, optional
            Grid range in m, default the whole profile (clipped to it).
        alpha : float
            Rotation of the curve in rad (counter-clockwise in the (y, z) plane) before
            sampling; the slope angles include it, curvature does not change.

        Returns
        -------
        SampledProfile
            Where the rotated curve folds back (y decreasing along σ), its outer envelope.
        """
        yd, _ = self._dense(alpha)
        env = np.maximum.accumulate(yd)
        lo, hi = float(env[0]), float(env[-1])
        a = lo if y0 is None else max(lo, float(y0))
        b = hi if y1 is None else min(hi, float(y1))
        if not b > a:
            raise ScenarioError(f"{self.profile.name}: empty sampling range")
        n = math.floor((b - a) / h + 1e-9) + 1
        grid = a + h * np.arange(n)
        s_at = np.interp(grid, env, self._sd)
        # Newton steps on y(σ) = y_grid remove the interpolation error of σ(y)
        for _ in range(2):
            yv, _ = self._rotated(s_at, alpha)
            dy1, _ = self._rotated(s_at, alpha, 1)
            ok = dy1 > 1e-3
            s_at = np.where(ok, s_at - (yv - grid) / np.where(ok, dy1, 1.0), s_at)
            s_at = np.clip(s_at, 0.0, self.sigma[-1])
        _, z0 = self._rotated(s_at, alpha)
        y1d, z1d = self._rotated(s_at, alpha, 1)
        y2d, z2d = self._rotated(s_at, alpha, 2)
        angle = np.arctan2(z1d, np.maximum(y1d, 0.0))
        curv = (y1d * z2d - z1d * y2d) / np.power(y1d * y1d + z1d * z1d, 1.5)
        return SampledProfile(a, float(h), np.asarray(z0, float), np.asarray(angle, float),
                              np.asarray(curv, float))

    def highest_point(self, alpha: float = 0.0) -> tuple[float, float]:
        """(y, z) in m of the highest point of the curve rotated by ``alpha``."""
        _, zd = self._dense(alpha)
        i = int(np.argmax(zd))
        s = float(self._sd[i])
        lo = float(self._sd[max(i - 1, 0)])
        hi = float(self._sd[min(i + 1, self._sd.size - 1)])
        for _ in range(60):  # bisection on dz/dσ = 0 inside the cells around the sample maximum
            mid = 0.5 * (lo + hi)
            _, dz = self._rotated(np.array([mid]), alpha, 1)
            if dz[0] > 0.0:
                lo = mid
            else:
                hi = mid
            s = mid
        yv, zv = self._rotated(np.array([s]), alpha)
        return float(yv[0]), float(zv[0])

    def gauge_point(self, depth: float, alpha: float = 0.0) -> tuple[float, float]:
        """The gauge-side point ``depth`` m below the highest point of the rotated curve.

        Walking from the highest point toward the gauge side (decreasing y), the first point
        of the curve at that height.

        Returns
        -------
        (y, z) : tuple of float
            In m, in the rotated frame.

        Raises
        ------
        ScenarioError
            When the profile does not reach that depth on the gauge side.
        """
        y_top, z_top = self.highest_point(alpha)
        level = z_top - float(depth)
        yd, zd = self._dense(alpha)
        i_top = int(np.argmax(zd))
        below = np.flatnonzero(zd[: i_top + 1] <= level)
        if below.size == 0 or yd[below[-1]] >= y_top:
            raise ScenarioError(
                f"{self.profile.name}: the rail profile does not reach {depth * 1e3:.4g} mm below "
                "its highest point on the gauge side"
            )
        j = int(below[-1])
        lo, hi = float(self._sd[j]), float(self._sd[j + 1])
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            _, zv = self._rotated(np.array([mid]), alpha)
            if zv[0] <= level:
                lo = mid
            else:
                hi = mid
        yv, zv = self._rotated(np.array([0.5 * (lo + hi)]), alpha)
        return float(yv[0]), float(zv[0])
