"""Track parameter schemas: rail section and discrete fasteners on a rigid base (slab track)."""

from __future__ import annotations

from pydantic import Field

from flexride.model.base import Schema


class RailSection(Schema):
    """Rail cross-section properties (defaults: CHN60)."""

    area: float = Field(7.745e-3, gt=1e-4, le=0.05, description="Cross-section area (m²)")
    youngs_modulus: float = Field(2.1e11, gt=1e9, le=5e11, description="Young's modulus E (Pa)")
    shear_modulus: float = Field(8.1e10, gt=1e9, le=2e11, description="Shear modulus G (Pa)")
    density: float = Field(7850.0, gt=1000.0, le=20000.0, description="Density (kg/m³)")
    iy: float = Field(
        3.214e-5,
        gt=1e-7,
        le=1e-3,
        description="Second moment of area for vertical bending, about the horizontal axis (m⁴)",
    )
    iz: float = Field(
        5.24e-6,
        gt=1e-8,
        le=1e-3,
        description="Second moment of area for lateral bending, about the vertical axis (m⁴)",
    )
    torsion_constant: float = Field(
        2.35e-6, gt=1e-9, le=1e-3, description="Saint-Venant torsion constant J_t (m⁴)"
    )
    polar_moment: float = Field(
        3.741e-5,
        gt=1e-8,
        le=1e-3,
        description="Polar second moment of area about the shear centre, I_0 (m⁴)",
    )
    shear_centre_above_foot: float = Field(
        0.045, ge=0.0, le=0.2, description="Height of the shear centre above the rail foot (m)"
    )
    head_above_shear_centre: float = Field(
        0.131,
        ge=0.0,
        le=0.25,
        description="Height of the running surface above the shear centre (m)",
    )

    @property
    def mass_per_length(self) -> float:
        """Rail mass per unit length (kg/m)."""
        return self.density * self.area


class Fastener(Schema):
    """Discrete rail fastener (pad + clip) on a rigid base."""

    spacing: float = Field(0.6, gt=0.2, le=1.5, description="Fastener spacing (m)")
    kz: float = Field(3.0e7, gt=1e5, le=1e10, description="Vertical stiffness (N/m)")
    cz: float = Field(1.0e4, ge=0.0, le=1e7, description="Vertical damping (N·s/m)")
    ky: float = Field(3.0e7, gt=1e5, le=1e10, description="Lateral stiffness (N/m)")
    cy: float = Field(1.0e4, ge=0.0, le=1e7, description="Lateral damping (N·s/m)")
    k_roll: float = Field(
        5.6e4,
        gt=0.0,
        le=1e9,
        description="Rotational (rail roll) stiffness of the pad (N·m/rad); default k_z·e²/3 for a "
        "uniform pad of half width e = 0.075 m",
    )
    c_roll: float = Field(
        19.0,
        ge=0.0,
        le=1e6,
        description="Rotational (rail roll) damping of the pad (N·m·s/rad); default c_z·e²/3",
    )


class Track(Schema):
    """Two rails on discrete fasteners. ``rail_centre_half_distance`` is b of DESIGN §6."""

    rail: RailSection = Field(default_factory=RailSection)
    fastener: Fastener = Field(default_factory=Fastener)
    rail_centre_half_distance: float = Field(
        0.75,
        gt=0.3,
        le=1.0,
        description="Half distance between the rail centre lines, b (m); cant angle = h/(2b)",
    )
