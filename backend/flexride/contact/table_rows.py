"""The contact-geometry table and the equivalent-conicity table as rows of plain numbers.

One source for what ``flexride contact table`` / ``flexride contact conicity`` print and export
and what the service answers at ``GET /api/v1/contact/geometry``: the columns of the table with
their meaning, the rows of a :class:`~flexride.contact.search.ContactGeometry` (lengths in mm,
angles in rad, rounded; non-finite values as None) and the Δy grid on which the equivalent
conicity of a profile pair is computed.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from flexride.contact.search import ContactGeometry

__all__ = [
    "CONICITY_STEP_MM",
    "CONICITY_Y_MAX_MM",
    "TABLE_COLUMNS",
    "conicity_rows",
    "rounded",
    "table_rows",
]

#: Half range (mm) of the Δy grid of the equivalent conicity of a profile pair.
CONICITY_Y_MAX_MM = 12.0
#: Step (mm) of that grid.
CONICITY_STEP_MM = 0.05

#: Columns of the contact table: (name, meaning); the name carries the unit.
TABLE_COLUMNS: tuple[tuple[str, str], ...] = (
    ("dy_mm", "wheelset lateral displacement, to the left"),
    ("dr_mm", "rolling-radius difference r_left − r_right"),
    ("dgamma_rad", "contact-angle difference γ_left − γ_right (track frame)"),
    ("roll_rad", "wheelset roll (positive raises the left wheel)"),
    ("roll_coefficient", "σ = b0·roll/Δy"),
    ("r_left_mm", "rolling radius, left"),
    ("r_right_mm", "rolling radius, right"),
    ("gamma_left_rad", "contact angle, left (track frame)"),
    ("gamma_right_rad", "contact angle, right (track frame)"),
    ("wheel_left_mm", "contact on the left wheel profile (EN 13715 s)"),
    ("wheel_right_mm", "contact on the right wheel profile (EN 13715 s)"),
    ("rail_left_mm", "contact on the left rail profile (profile y, field side +)"),
    ("rail_right_mm", "contact on the right rail profile (profile y, field side +)"),
    ("track_left_mm", "contact from the track centre line, left"),
    ("track_right_mm", "contact from the track centre line, right"),
    ("second_gap_left_mm", "gap of the other branch, left (none if absent)"),
    ("second_gap_right_mm", "gap of the other branch, right (none if absent)"),
    ("two_point_left", "two-point contact, left"),
    ("two_point_right", "two-point contact, right"),
)


def rounded(value: float, digits: int = 6) -> float | None:
    """``value`` rounded to ``digits`` decimals, None when it is NaN or infinite.

    Parameters
    ----------
    value : float
        Any number (numpy scalars too).
    digits : int
        Decimals kept.

    Returns
    -------
    float or None
    """
    return round(float(value), digits) if math.isfinite(float(value)) else None


def _roll_coefficient(geo: ContactGeometry) -> np.ndarray:
    """σ = b0·roll/Δy at every grid point [n] (-); at Δy = 0 the central difference of the
    roll (b0: the taping lines' distance from the track centre line, m).
    """
    y = geo.y
    b0 = geo.placement.taping_line
    with np.errstate(divide="ignore", invalid="ignore"):
        sigma = b0 * geo.roll / y
    i0 = geo.i0
    if 0 < i0 < y.size - 1:
        sigma[i0] = b0 * (geo.roll[i0 + 1] - geo.roll[i0 - 1]) / (y[i0 + 1] - y[i0 - 1])
    return sigma


def _row_indices(geo: ContactGeometry, every: float | None) -> np.ndarray:
    """Grid indices of the rows: every grid point, or those a multiple of ``every`` (m, at
    least one grid step) away from Δy = 0.
    """
    if every is None:
        return np.arange(geo.y.size)
    k = max(1, round(every / geo.settings.step))
    return np.flatnonzero((np.arange(geo.y.size) - geo.i0) % k == 0)


def table_rows(geo: ContactGeometry, every: float | None = None) -> list[dict[str, Any]]:
    """The rows of the contact table of ``geo`` (columns :data:`TABLE_COLUMNS`).

    Parameters
    ----------
    geo : ContactGeometry
        Result of :func:`~flexride.contact.search.search_contact`.
    every : float, optional
        Row spacing in m (rounded to a multiple of the grid step, rows aligned on Δy = 0);
        every grid point by default.

    Returns
    -------
    list of dict
        One dict per row: lengths in mm, angles in rad, the roll coefficient (-) and the
        two-point flags; a value that is not finite is None.
    """
    y = geo.y
    r = geo.at_rigid("r")
    gam = geo.gamma_track
    s = geo.at_rigid("s")
    ry = geo.at_rigid("rail_y")
    eta = geo.at_rigid("eta")
    other = 1 - geo.rigid
    gap2 = np.take_along_axis(geo.gap, other[:, None, :], axis=1)[:, 0, :]
    sigma = _roll_coefficient(geo)
    rows = []
    for i in _row_indices(geo, every):
        rows.append({
            "dy_mm": rounded(y[i] * 1e3, 4),
            "dr_mm": rounded((r[0, i] - r[1, i]) * 1e3),
            "dgamma_rad": rounded(gam[0, i] - gam[1, i]),
            "roll_rad": rounded(geo.roll[i], 9),
            "roll_coefficient": rounded(sigma[i]),
            "r_left_mm": rounded(r[0, i] * 1e3, 5),
            "r_right_mm": rounded(r[1, i] * 1e3, 5),
            "gamma_left_rad": rounded(gam[0, i]),
            "gamma_right_rad": rounded(gam[1, i]),
            "wheel_left_mm": rounded(s[0, i] * 1e3, 4),
            "wheel_right_mm": rounded(s[1, i] * 1e3, 4),
            "rail_left_mm": rounded(ry[0, i] * 1e3, 4),
            "rail_right_mm": rounded(ry[1, i] * 1e3, 4),
            "track_left_mm": rounded(eta[0, i] * 1e3, 4),
            "track_right_mm": rounded(eta[1, i] * 1e3, 4),
            "second_gap_left_mm": rounded(gap2[0, i] * 1e3),
            "second_gap_right_mm": rounded(gap2[1, i] * 1e3),
            "two_point_left": bool(geo.two_point[0, i]),
            "two_point_right": bool(geo.two_point[1, i]),
        })
    return rows


def conicity_rows(amplitudes: np.ndarray, tan_gamma_e: np.ndarray) -> list[dict[str, Any]]:
    """The rows of the equivalent-conicity table.

    Parameters
    ----------
    amplitudes : numpy.ndarray
        Amplitudes of the wheelset's lateral motion [k] in m.
    tan_gamma_e : numpy.ndarray
        Equivalent conicity at each amplitude [k] (-).

    Returns
    -------
    list of dict
        ``{"amplitude_mm": …, "tan_gamma_e": …}`` per amplitude (None where not finite).
    """
    return [{"amplitude_mm": rounded(a * 1e3, 4), "tan_gamma_e": rounded(t)}
            for a, t in zip(amplitudes, tan_gamma_e, strict=True)]
