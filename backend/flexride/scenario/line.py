"""Line (alignment) schemas: straight track, or a curve with clothoid transitions and cant."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from flexride.scenario.base import Schema, quantity


class StraightLine(Schema):
    """Straight, level track without cant."""

    kind: Literal["straight"] = "straight"


class CurvedLine(Schema):
    """Straight lead-in, entry transition, circular arc, exit transition, straight lead-out.

    Curvature and superelevation vary linearly along the transitions (clothoid with linear cant
    ramp). ``start_m`` is the distance along the line where the entry transition begins.
    """

    kind: Literal["curve"] = "curve"
    radius_m: float = quantity(
        800.0, ge=50.0, le=1.0e5, description="Radius of the circular arc", unit="m"
    )
    direction: Literal["left", "right"] = Field("left", description="Direction of the curve")
    superelevation_m: float = quantity(
        0.095, ge=0.0, le=0.2, description="Superelevation (cant) of the outer rail", unit="m"
    )
    entry_transition_m: float = quantity(
        55.0, ge=0.0, le=1000.0, description="Entry transition length", unit="m"
    )
    exit_transition_m: float = quantity(
        55.0, ge=0.0, le=1000.0, description="Exit transition length", unit="m"
    )
    arc_length_m: float = quantity(
        200.0, ge=0.0, le=1.0e5, description="Length of the circular arc", unit="m"
    )
    start_m: float = quantity(
        40.0,
        ge=0.0,
        le=1.0e6,
        description="Position of the start of the entry transition",
        unit="m",
    )


Line = Annotated[StraightLine | CurvedLine, Field(discriminator="kind")]
