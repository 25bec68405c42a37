"""Bodies of the contact-geometry route (``GET /contact/geometry``).

The table rows have the columns of ``flexride contact table --json`` (their meaning from
:data:`flexride.contact.table_rows.TABLE_COLUMNS`, the one source), the conicity rows those of
``flexride contact conicity --json``. Lengths are in mm, angles in rad; a value that is not
finite is null.
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, Field

from flexride.contact.table_rows import CONICITY_STEP_MM, CONICITY_Y_MAX_MM, TABLE_COLUMNS

_MEANING = dict(TABLE_COLUMNS)


def _column(name: str, unit: str) -> Any:
    """``Field`` of table column ``name``: its meaning from the library and its unit."""
    return Field(description=f"{_MEANING[name]} ({unit})")


class ContactTableRow(BaseModel):
    """One row of the contact table: the rigid contact of both wheels at one Δy."""

    dy_mm: float = _column("dy_mm", "mm")
    dr_mm: float | None = _column("dr_mm", "mm")
    dgamma_rad: float | None = _column("dgamma_rad", "rad")
    roll_rad: float | None = _column("roll_rad", "rad")
    roll_coefficient: float | None = _column("roll_coefficient", "-")
    r_left_mm: float | None = _column("r_left_mm", "mm")
    r_right_mm: float | None = _column("r_right_mm", "mm")
    gamma_left_rad: float | None = _column("gamma_left_rad", "rad")
    gamma_right_rad: float | None = _column("gamma_right_rad", "rad")
    wheel_left_mm: float | None = _column("wheel_left_mm", "mm")
    wheel_right_mm: float | None = _column("wheel_right_mm", "mm")
    rail_left_mm: float | None = _column("rail_left_mm", "mm")
    rail_right_mm: float | None = _column("rail_right_mm", "mm")
    track_left_mm: float | None = _column("track_left_mm", "mm")
    track_right_mm: float | None = _column("track_right_mm", "mm")
    second_gap_left_mm: float | None = _column("second_gap_left_mm", "mm")
    second_gap_right_mm: float | None = _column("second_gap_right_mm", "mm")
    two_point_left: bool = _column("two_point_left", "-")
    two_point_right: bool = _column("two_point_right", "-")


class ConicityPoint(BaseModel):
    """The equivalent conicity at one amplitude."""

    amplitude_mm: float = Field(description="Amplitude of the wheelset's lateral motion (mm)")
    tan_gamma_e: float | None = Field(
        description="Equivalent conicity tan γe (-); null where the Δr table gives none")


class ContactPoints(BaseModel):
    """Where the wheelset is and where its wheels touch the rails at one Δy (the row of the
    same index in ``rows``), in track coordinates: y lateral from the track centre line,
    positive to the left (the right side at negative y), z up from the top of rail.
    """

    dy_mm: float = Field(description="Wheelset lateral displacement Δy, to the left (mm)")
    axle_z_left_mm: float = Field(
        description="Height of the axle centre above the top of rail at which the left wheel "
        "touches (mm); with roll both sides are equal")
    axle_z_right_mm: float = Field(
        description="Height of the axle centre above the top of rail at which the right wheel "
        "touches (mm)")
    left_y_mm: float | None = Field(description="Contact point, left: lateral position (mm)")
    left_z_mm: float | None = Field(description="Contact point, left: height (mm)")
    right_y_mm: float | None = Field(
        description="Contact point, right: lateral position (mm, negative)")
    right_z_mm: float | None = Field(description="Contact point, right: height (mm)")
    left_second_y_mm: float | None = Field(
        description="Point of least gap of the other branch (tread or flange), left: lateral "
        "position (mm); null when that branch has no candidate")
    left_second_z_mm: float | None = Field(
        description="The same point's height on the rail (mm)")
    right_second_y_mm: float | None = Field(
        description="Point of least gap of the other branch, right: lateral position (mm)")
    right_second_z_mm: float | None = Field(
        description="The same point's height on the rail (mm)")


class ProfileLine(BaseModel):
    """A profile drawn in track coordinates (at most 1500 of its points)."""

    y_mm: list[float] = Field(description="Lateral position from the track centre line, "
                              "positive to the left (mm)")
    z_mm: list[float] = Field(description="Height above the top of rail (mm)")
    points: int = Field(description="Points of the whole profile (before decimation)")


class PlacedProfiles(BaseModel):
    """The left rail and the left wheel placed in the track at Δy = 0.

    The left wheel at row i is this wheel moved rigidly: rotated by ``rows[i].roll_rad −
    roll_rad`` about the axle centre (``axle_y_mm``, ``axle_z_mm``), then shifted by
    (``contacts[i].dy_mm``, ``contacts[i].axle_z_left_mm − axle_z_mm``).
    """

    rail: ProfileLine = Field(description="Left rail, canted by the inclination, gauge point "
                              "at y = gauge/2, highest point at z = 0")
    wheel: ProfileLine = Field(description="Left wheel at Δy = 0, resting on its rail")
    axle_y_mm: float = Field(description="Axle centre at Δy = 0: lateral position (mm)")
    axle_z_mm: float = Field(description="Axle centre at Δy = 0: height above the top of "
                             "rail at which the left wheel touches (mm)")
    roll_rad: float = Field(description="Wheelset roll at Δy = 0 (rad)")
    taping_line_y_mm: float = Field(description="Lateral position of the left wheel's taping "
                                    "line at Δy = 0 (mm): flange_back/2 + 70 mm")
    gauge_point_y_mm: float = Field(description="Gauge point of the left rail: lateral "
                                    "position, gauge/2 (mm)")
    gauge_point_z_mm: float = Field(description="Gauge point of the left rail: height, "
                                    "−gauge height (mm)")


class ContactParameters(BaseModel):
    """The parameters the answer was computed with (Δy half range rounded to a multiple of
    the step).
    """

    wheel: str = Field(description="s1002 or the id of the uploaded wheel profile")
    rail: str = Field(description="60e1 or the id of the uploaded rail profile")
    inclination: Literal["1:40", "1:20", "none"] = Field(description="Rail inclination")
    gauge_mm: float = Field(description="Track gauge (mm)")
    gauge_height_mm: float = Field(description="Gauge point below the top of rail (mm)")
    flange_back_mm: float = Field(description="Flange-back distance of the wheelset (mm)")
    r0_mm: float = Field(description="Nominal rolling radius (mm)")
    roll: bool = Field(description="Wheelset roll solved (true) or kept 0")
    y_max_mm: float = Field(description="Half range of the Δy grid (mm)")
    step_mm: float = Field(description="Step of the Δy grid (mm)")


class ContactGeometryOut(BaseModel):
    """Contact geometry of a wheel and rail profile pair against the wheelset's lateral
    displacement Δy, its equivalent conicity and the profiles placed for drawing.
    """

    parameters: ContactParameters
    wheel_name: str = Field(description="Name of the wheel profile (standard or file kind)")
    rail_name: str = Field(description="Name of the rail profile")
    columns: dict[str, str] = Field(description="Meaning of each column of ``rows`` (the "
                                    "unit is the name's suffix: _mm, _rad)")
    rows: list[ContactTableRow] = Field(
        description="The contact table, one row per Δy of the grid (as `flexride contact "
        "table --json`)")
    contacts: list[ContactPoints] = Field(
        description="Axle position and contact points per row, for drawing (same order)")
    conicity_method: Literal["integration"] = Field(
        description="EN 15302 integration of the kinematic wheelset motion")
    conicity: list[ConicityPoint] = Field(
        description="Equivalent conicity against the amplitude, from the Δr of a "
        f"±{CONICITY_Y_MAX_MM:g} mm grid in {CONICITY_STEP_MM:g} mm steps (as `flexride "
        "contact conicity --json`); empty when the profiles do not cover that range "
        "(``conicity_note`` says why)")
    conicity_note: str | None = Field(
        None, description="Why there is no conicity, when there is none")
    profiles: PlacedProfiles
