"""Line geometry along the route: curvature, cant, heading, tabulated for the kernel.

Sign conventions (ISO 8855, DESIGN §4): a left curve has positive curvature (centre at +y).
Cant raises the outer rail; the track frame is rolled by ``roll = −sign(κ)·asin(h / 2b)`` so that
positive roll lifts the left rail. Transitions are clothoids (curvature linear in s) with a
linear cant ramp.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from flexride.scenario.line import CurvedLine, StraightLine

GRAVITY = 9.81


@dataclass(frozen=True)
class LineTable:
    """Line geometry on a uniform grid ``s0 + i·ds``.

    Attributes
    ----------
    s0, ds : float
        Grid start and step (m).
    curvature : numpy.ndarray
        Signed curvature κ (1/m), left positive.
    roll : numpy.ndarray
        Roll angle of the track frame due to cant (rad).
    heading : numpy.ndarray
        Heading angle ∫κ ds relative to the start (rad).
    heading_integral : numpy.ndarray
        ∫heading ds (m): lateral offset of the centre line from the initial tangent for small
        angles; used for relative positions of nearby track frames.
    dcurvature : numpy.ndarray
        dκ/ds (1/m²).
    """

    s0: float
    ds: float
    curvature: np.ndarray
    roll: np.ndarray
    heading: np.ndarray
    heading_integral: np.ndarray
    dcurvature: np.ndarray

    def as_array(self) -> np.ndarray:
        """(5, n) contiguous array: curvature, roll, heading, heading_integral, dcurvature."""
        return np.ascontiguousarray(
            np.vstack(
                [self.curvature, self.roll, self.heading, self.heading_integral, self.dcurvature]
            )
        )


def curvature_and_cant(
    line: StraightLine | CurvedLine, s: np.ndarray, rail_half_distance: float
) -> tuple[np.ndarray, np.ndarray]:
    """Signed curvature (1/m) and track roll angle (rad) at positions ``s`` (m)."""
    s = np.asarray(s, dtype=float)
    if isinstance(line, StraightLine):
        return np.zeros_like(s), np.zeros_like(s)
    sign = 1.0 if line.direction == "left" else -1.0
    k_max = 1.0 / line.radius_m
    s1 = line.start_m
    s2 = s1 + line.entry_transition_m
    s3 = s2 + line.arc_length_m
    s4 = s3 + line.exit_transition_m
    frac = np.zeros_like(s)
    if line.entry_transition_m > 0:
        m = (s >= s1) & (s < s2)
        frac[m] = (s[m] - s1) / line.entry_transition_m
    frac[(s >= s2) & (s <= s3)] = 1.0
    if line.exit_transition_m > 0:
        m = (s > s3) & (s <= s4)
        frac[m] = (s4 - s[m]) / line.exit_transition_m
    kappa = sign * k_max * frac
    roll = -sign * np.arcsin(np.clip(line.superelevation_m / (2.0 * rail_half_distance), -1, 1))
    return kappa, roll * frac


def build_line_table(
    line: StraightLine | CurvedLine,
    s_min: float,
    s_max: float,
    rail_half_distance: float,
    ds: float = 0.25,
) -> LineTable:
    """Tabulate the line between ``s_min`` and ``s_max`` (m) on a grid of step ``ds`` (m)."""
    n = int(np.ceil((s_max - s_min) / ds)) + 2
    s = s_min + ds * np.arange(n)
    kappa, roll = curvature_and_cant(line, s, rail_half_distance)
    heading = np.concatenate([[0.0], np.cumsum(0.5 * (kappa[1:] + kappa[:-1]) * ds)])
    hint = np.concatenate([[0.0], np.cumsum(0.5 * (heading[1:] + heading[:-1]) * ds)])
    dk = np.gradient(kappa, ds)
    return LineTable(
        s0=s_min,
        ds=ds,
        curvature=kappa,
        roll=roll,
        heading=heading,
        heading_integral=hint,
        dcurvature=dk,
    )


def uncompensated_lateral_acceleration(
    speed_mps: float, radius_m: float, superelevation_m: float, rail_half_distance: float = 0.75
) -> float:
    """Uncompensated lateral acceleration in the track plane, V²/R − g·h/(2b) (m/s²)."""
    return speed_mps**2 / radius_m - GRAVITY * superelevation_m / (2.0 * rail_half_distance)
