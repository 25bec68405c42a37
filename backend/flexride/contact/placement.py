"""Placement of wheel and rail profiles in the track (``reference/wheel-rail-profiles.md`` §3).

Per side of the track, positions are measured in a *side frame*: η lateral from the track
centre line toward the field side (outward) and z up from the top of rail (the highest point of
the canted head). In project axes (ISO 8855, y left) the left side is y = η and the right side
its mirror image y = −η; profiles (:mod:`flexride.contact.profiles.profile`) are drawn in the
same orientation as the side frame, so the left side needs no mirroring and the right side is
mirrored.

Rule:

1. Rotate the rail profile by the rail inclination (1:40, 1:20 or none) toward the track centre:
   the head top tilts inward, the gauge side goes down.
2. Find the highest point of the canted head and the gauge point: walking from the highest point
   toward the gauge side, the first point ``gauge_height`` below it.
3. Place the gauge point at η = gauge/2 and the highest point at z = 0.
4. Place the wheel's taping line (profile origin) at η = flange_back/2 + taping_line_offset and
   its nominal rolling circle (radius r0) on the axle.

Nothing depends on the particular profile: inclination, gauge, gauge height, flange-back
distance, taping-line offset and r0 are parameters. A rail file that is already canted (such
as the Manchester benchmark's UIC60 v3 ``.prr``) is placed with ``inclination=0``.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from flexride.contact.profiles.profile import ProfileCurve, SampledProfile
from flexride.errors import ScenarioError

__all__ = ["PlacedRail", "Placement", "parse_inclination", "place_rail"]


def parse_inclination(text: str | float) -> float:
    """Rail inclination in rad from ``"1:40"``, ``"1:20"``, ``"none"``/``"0"`` or a number
    (taken as the angle in rad).

    Raises
    ------
    ScenarioError
        For anything else, or an angle outside [0, 0.1] rad.
    """
    if isinstance(text, (int, float)):
        value = float(text)
    else:
        t = str(text).strip().lower()
        m = re.fullmatch(r"1\s*:\s*(\d+(?:\.\d+)?)", t)
        if t in ("none", "0", "vertical"):
            value = 0.0
        elif m:
            denom = float(m.group(1))
            if denom <= 0.0:
                raise ScenarioError(f"rail inclination {text!r}: denominator must be positive")
            value = math.atan(1.0 / denom)
        else:
            try:
                value = float(t)
            except ValueError as exc:
                raise ScenarioError(
                    f"rail inclination must be '1:N' (e.g. 1:40), 'none' or an angle in rad, "
                    f"got {text!r}"
                ) from exc
    if not (math.isfinite(value) and 0.0 <= value <= 0.1):
        raise ScenarioError(f"rail inclination must lie in [0, 0.1] rad, got {value!r}")
    return value


def _positive(name: str, value: float, lo: float, hi: float) -> float:
    value = float(value)
    if not (math.isfinite(value) and lo <= value <= hi):
        raise ScenarioError(f"{name} must lie in [{lo:g}, {hi:g}], got {value!r}")
    return value


@dataclass(frozen=True)
class Placement:
    """Track and wheelset parameters of the placement rule (SI units).

    Attributes
    ----------
    inclination : float
        Rail inclination toward the track centre in rad (atan(1/40) default; 0 for none or for a
        rail profile that is already canted).
    gauge : float
        Track gauge in m (1.435), measured between the gauge points.
    gauge_height : float
        Depth of the gauge point below the top of rail in m (0.014 in Europe, 0.016 in China).
    flange_back : float
        Flange-back (back-to-back) distance of the wheelset in m (1.360; 1.353 for Chinese
        metro wheelsets).
    r0 : float
        Nominal rolling radius at the taping line in m (0.46 for a 920 mm wheel).
    taping_line_offset : float
        Distance from the flange back to the taping line in m (0.070, EN 13715).
    """

    inclination: float = math.atan(1.0 / 40.0)
    gauge: float = 1.435
    gauge_height: float = 0.014
    flange_back: float = 1.360
    r0: float = 0.46
    taping_line_offset: float = 0.070

    def __post_init__(self) -> None:
        """Check and normalise the placement parameters."""
        object.__setattr__(self, "inclination", parse_inclination(self.inclination))
        object.__setattr__(self, "gauge", _positive("gauge (m)", self.gauge, 0.3, 3.0))
        object.__setattr__(self, "gauge_height",
                           _positive("gauge height (m)", self.gauge_height, 0.0, 0.03))
        object.__setattr__(self, "flange_back",
                           _positive("flange-back distance (m)", self.flange_back, 0.3, 3.0))
        object.__setattr__(self, "r0", _positive("nominal rolling radius r0 (m)", self.r0,
                                                 0.1, 1.5))
        object.__setattr__(self, "taping_line_offset",
                           _positive("taping-line offset (m)", self.taping_line_offset, 0.0, 0.2))
        if self.flange_back >= self.gauge:
            raise ScenarioError(
                f"flange-back distance ({self.flange_back} m) must be smaller than the gauge "
                f"({self.gauge} m)"
            )

    @property
    def taping_line(self) -> float:
        """η of the wheels' taping lines in m: flange_back/2 + taping_line_offset."""
        return 0.5 * self.flange_back + self.taping_line_offset

    def as_dict(self) -> dict[str, float]:
        """The parameters by name (SI units)."""
        return {
            "inclination": self.inclination,
            "gauge": self.gauge,
            "gauge_height": self.gauge_height,
            "flange_back": self.flange_back,
            "r0": self.r0,
            "taping_line_offset": self.taping_line_offset,
        }


@dataclass(frozen=True)
class PlacedRail:
    """A rail profile placed in the side frame by :func:`place_rail`.

    A profile point (y, z) maps to η = gauge/2 + (y' − y'_g), z = z' − z'_top, where (y', z')
    is the point rotated by the inclination, (y'_g, ·) the gauge point and z'_top the height of
    the highest point.

    Attributes
    ----------
    curve : ProfileCurve
        The rail curve.
    alpha : float
        Rotation (inclination) in rad.
    eta_shift : float
        η = y' + eta_shift, in m.
    z_shift : float
        z = z' + z_shift, in m.
    top : tuple of float
        (η, z) of the highest point in m (z = 0).
    gauge_point : tuple of float
        (η, z) of the gauge point in m (η = gauge/2, z = −gauge_height).
    origin : tuple of float
        (η, z) of the profile origin (0, 0) in m, e.g. the crown top on the rail axis of an
        un-canted 60E1 head.
    """

    curve: ProfileCurve
    alpha: float
    eta_shift: float
    z_shift: float
    top: tuple[float, float]
    gauge_point: tuple[float, float]
    origin: tuple[float, float]

    def to_profile(self, eta: float, z: float) -> tuple[float, float]:
        """Profile coordinates (y, z) in m (un-rotated rail frame) of the side-frame point
        (η, z) in m.
        """
        yp, zp = eta - self.eta_shift, z - self.z_shift
        c, sn = math.cos(self.alpha), math.sin(self.alpha)
        return c * yp + sn * zp, -sn * yp + c * zp

    def sample(self, h: float) -> SampledProfile:
        """The placed rail sampled on a uniform η grid of step ``h`` (m) whose points are
        multiples of ``h``; heights from the top of rail, slope angles in the side frame,
        curvatures (rotation invariant).
        """
        lo, _ = self.curve.y_range(self.alpha)
        start = math.ceil((lo + self.eta_shift) / h - 1e-9) * h
        s = self.curve.sample(h, y0=start - self.eta_shift, alpha=self.alpha)
        return SampledProfile(start, h, s.z + self.z_shift, s.angle, s.curvature)


def place_rail(curve: ProfileCurve, placement: Placement) -> PlacedRail:
    """Place a rail curve by the rule of the module docstring.

    Parameters
    ----------
    curve : ProfileCurve
        Curve of a rail :class:`~flexride.contact.profiles.profile.Profile`.
    placement : Placement
        Inclination, gauge and gauge height.

    Returns
    -------
    PlacedRail

    Raises
    ------
    ScenarioError
        When the curve is not a rail or does not reach the gauge height on its gauge side.
    """
    if curve.profile.kind != "rail":
        raise ScenarioError(f"{curve.profile.name}: expected a rail profile, got a wheel")
    alpha = placement.inclination
    y_top, z_top = curve.highest_point(alpha)
    y_g, _ = curve.gauge_point(placement.gauge_height, alpha)
    eta_shift = 0.5 * placement.gauge - y_g
    z_shift = -z_top
    return PlacedRail(
        curve=curve,
        alpha=alpha,
        eta_shift=eta_shift,
        z_shift=z_shift,
        top=(y_top + eta_shift, 0.0),
        gauge_point=(0.5 * placement.gauge, -placement.gauge_height),
        origin=(eta_shift, z_shift),
    )


_DEFAULT = Placement()
#: The default placement in mm (EN: gauge 1435 mm at 14 mm, flange backs 1360 mm, r0 460 mm),
#: the defaults of the contact commands and of ``GET /contact/geometry``.
GAUGE_MM = round(_DEFAULT.gauge * 1e3, 6)
GAUGE_HEIGHT_MM = round(_DEFAULT.gauge_height * 1e3, 6)
FLANGE_BACK_MM = round(_DEFAULT.flange_back * 1e3, 6)
R0_MM = round(_DEFAULT.r0 * 1e3, 6)
