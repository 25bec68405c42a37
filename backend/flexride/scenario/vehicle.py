"""Vehicle parameter schemas: inertia of each body, geometry, suspensions.

All values SI. Stiffness and damping of the primary suspension are per axle box (two per
wheelset), of the secondary suspension per air spring (two per bogie), as in the paper's
Table 4. Heights are measured above the top of rail (TOR) in the nominal, unloaded geometry.
"""

from __future__ import annotations

from pydantic import Field, model_validator

from flexride.scenario.base import Schema, quantity


class RigidInertia(Schema):
    """Mass and principal moments of inertia of one body (about its centre of gravity)."""

    mass: float = quantity(..., gt=1.0, le=2.0e5, description="Mass", unit="kg")
    ixx: float = quantity(
        ..., gt=0.0, le=1.0e7, description="Roll moment of inertia about x", unit="kg·m²"
    )
    iyy: float = quantity(
        ..., gt=0.0, le=1.0e8, description="Pitch moment of inertia about y", unit="kg·m²"
    )
    izz: float = quantity(
        ..., gt=0.0, le=1.0e8, description="Yaw moment of inertia about z", unit="kg·m²"
    )
    cg_height: float = quantity(
        ...,
        ge=0.0,
        le=5.0,
        description="Height of the centre of gravity above top of rail",
        unit="m",
    )


class SpringDamper3(Schema):
    """Linear three-directional spring–damper (x longitudinal, y lateral, z vertical)."""

    kx: float = quantity(..., ge=0.0, le=1.0e9, description="Longitudinal stiffness", unit="N/m")
    ky: float = quantity(..., ge=0.0, le=1.0e9, description="Lateral stiffness", unit="N/m")
    kz: float = quantity(..., ge=0.0, le=1.0e9, description="Vertical stiffness", unit="N/m")
    cx: float = quantity(..., ge=0.0, le=1.0e7, description="Longitudinal damping", unit="N·s/m")
    cy: float = quantity(..., ge=0.0, le=1.0e7, description="Lateral damping", unit="N·s/m")
    cz: float = quantity(..., ge=0.0, le=1.0e7, description="Vertical damping", unit="N·s/m")


class VehicleGeometry(Schema):
    """Positions of bogies, wheelsets and suspension elements."""

    bogie_centre_spacing: float = quantity(
        12.6, gt=1.0, le=30.0, description="Distance between the two bogie centres", unit="m"
    )
    wheelbase: float = quantity(2.2, gt=0.5, le=5.0, description="Bogie wheelbase", unit="m")
    wheel_radius: float = quantity(
        0.42, gt=0.2, le=0.7, description="Nominal rolling radius", unit="m"
    )
    rolling_circle_half_distance: float = quantity(
        0.7465,
        gt=0.4,
        le=1.0,
        description="Half distance between the nominal rolling circles",
        unit="m",
    )
    primary_lateral_half_spacing: float = quantity(
        1.0,
        gt=0.1,
        le=1.5,
        description="Lateral distance of each axle-box spring from the centre line",
        unit="m",
    )
    primary_height: float = quantity(
        0.50,
        ge=0.0,
        le=1.5,
        description="Height of the primary springs' acting point above TOR",
        unit="m",
    )
    secondary_lateral_half_spacing: float = quantity(
        0.95,
        gt=0.1,
        le=1.6,
        description="Lateral distance of each air spring from the centre line",
        unit="m",
    )
    secondary_height: float = quantity(
        0.90,
        ge=0.0,
        le=2.0,
        description="Height of the air springs' acting point above TOR",
        unit="m",
    )


class OptionalSuspension(Schema):
    """Optional suspension elements. A zero value means the element is absent."""

    anti_roll_bar_stiffness: float = quantity(
        0.0,
        ge=0.0,
        le=1.0e8,
        description="Anti-roll bar roll stiffness between car body and each bogie frame",
        unit="N·m/rad",
    )
    secondary_lateral_damper: float = quantity(
        0.0,
        ge=0.0,
        le=1.0e6,
        description="Secondary lateral damper between car body and each bogie frame",
        unit="N·s/m",
    )
    secondary_lateral_damper_height: float = quantity(
        0.75,
        ge=0.0,
        le=2.0,
        description="Height of the secondary lateral damper above TOR",
        unit="m",
    )
    yaw_damper: float = quantity(
        0.0,
        ge=0.0,
        le=1.0e7,
        description="Longitudinal yaw damper per side between car body and each frame",
        unit="N·s/m",
    )
    yaw_damper_lateral_half_spacing: float = quantity(
        1.3,
        gt=0.1,
        le=1.6,
        description="Lateral distance of each yaw damper from the centre line",
        unit="m",
    )


class Vehicle(Schema):
    """Metro vehicle: one car body, two bogie frames, four wheelsets and their suspensions."""

    carbody: RigidInertia = Field(..., description="Car body (including passengers)")
    frame: RigidInertia = Field(..., description="One bogie frame")
    wheelset: RigidInertia = Field(..., description="One wheelset")
    geometry: VehicleGeometry = Field(default_factory=VehicleGeometry)
    primary: SpringDamper3 = Field(..., description="Primary suspension, per axle box")
    secondary: SpringDamper3 = Field(..., description="Secondary suspension, per air spring")
    optional: OptionalSuspension = Field(default_factory=OptionalSuspension)

    @model_validator(mode="after")
    def _check_geometry(self) -> Vehicle:
        g = self.geometry
        if g.wheelbase >= g.bogie_centre_spacing:
            raise ValueError(
                f"geometry.wheelbase ({g.wheelbase} m) must be smaller than "
                f"geometry.bogie_centre_spacing ({g.bogie_centre_spacing} m)"
            )
        if abs(self.wheelset.cg_height - g.wheel_radius) > 1e-9:
            raise ValueError(
                f"wheelset.cg_height ({self.wheelset.cg_height} m) must equal "
                f"geometry.wheel_radius ({g.wheel_radius} m): the axle centre is the wheelset's CG"
            )
        return self
