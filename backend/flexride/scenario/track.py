"""Track parameter schemas: rail section and discrete fasteners on a rigid base (slab track)."""

from __future__ import annotations

from pydantic import Field

from flexride.scenario.base import Schema, quantity


class RailSection(Schema):
    """Rail cross-section properties (defaults: CHN60)."""

    area: float = quantity(7.745e-3, gt=1e-4, le=0.05, description="Cross-section area", unit="m²")
    youngs_modulus: float = quantity(
        2.1e11, gt=1e9, le=5e11, description="Young's modulus E", unit="Pa"
    )
    shear_modulus: float = quantity(
        8.1e10, gt=1e9, le=2e11, description="Shear modulus G", unit="Pa"
    )
    density: float = quantity(7850.0, gt=1000.0, le=20000.0, description="Density", unit="kg/m³")
    iy: float = quantity(
        3.214e-5,
        gt=1e-7,
        le=1e-3,
        description="Second moment of area for vertical bending, about the horizontal axis",
        unit="m⁴",
    )
    iz: float = quantity(
        5.24e-6,
        gt=1e-8,
        le=1e-3,
        description="Second moment of area for lateral bending, about the vertical axis",
        unit="m⁴",
    )
    torsion_constant: float = quantity(
        2.35e-6, gt=1e-9, le=1e-3, description="Saint-Venant torsion constant J_t", unit="m⁴"
    )
    polar_moment: float = quantity(
        3.741e-5,
        gt=1e-8,
        le=1e-3,
        description="Polar second moment of area about the shear centre, I_0",
        unit="m⁴",
    )
    shear_centre_above_foot: float = quantity(
        0.045,
        ge=0.0,
        le=0.2,
        description="Height of the shear centre above the rail foot",
        unit="m",
    )
    head_above_shear_centre: float = quantity(
        0.131,
        ge=0.0,
        le=0.25,
        description="Height of the running surface above the shear centre",
        unit="m",
    )

    @property
    def mass_per_length(self) -> float:
        """Rail mass per unit length (kg/m)."""
        return self.density * self.area


class Fastener(Schema):
    """Discrete rail fastener (pad + clip) on a rigid base."""

    spacing: float = quantity(0.6, gt=0.2, le=1.5, description="Fastener spacing", unit="m")
    kz: float = quantity(3.0e7, gt=1e5, le=1e10, description="Vertical stiffness", unit="N/m")
    cz: float = quantity(1.0e4, ge=0.0, le=1e7, description="Vertical damping", unit="N·s/m")
    ky: float = quantity(3.0e7, gt=1e5, le=1e10, description="Lateral stiffness", unit="N/m")
    cy: float = quantity(1.0e4, ge=0.0, le=1e7, description="Lateral damping", unit="N·s/m")
    k_roll: float = quantity(
        5.6e4,
        gt=0.0,
        le=1e9,
        unit="N·m/rad",
        description="Rotational (rail roll) stiffness of the pad; default k_z·e²/3 for a "
        "uniform pad of half width e = 0.075 m",
    )
    c_roll: float = quantity(
        19.0,
        ge=0.0,
        le=1e6,
        unit="N·m·s/rad",
        description="Rotational (rail roll) damping of the pad; default c_z·e²/3",
    )


class Track(Schema):
    """Two rails on discrete fasteners. ``rail_centre_half_distance`` is b of DESIGN §6."""

    rail: RailSection = Field(default_factory=RailSection)
    fastener: Fastener = Field(default_factory=Fastener)
    rail_centre_half_distance: float = quantity(
        0.75,
        gt=0.3,
        le=1.0,
        unit="m",
        description="Half distance b between the rail centre lines; cant angle = h/(2b)",
    )
