"""Wheel–rail contact settings."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from flexride.scenario.base import Schema, quantity


class Contact(Schema):
    """Wheel–rail contact: tread geometry, Hertz normal contact, Kalker creep with saturation.

    The tread in this version is conical (equivalent conicity) with flange contact modelled as a
    stiff lateral spring beyond the flangeway clearance; the geometry sits behind a table
    interface so that real profiles can replace it.
    """

    profile: Literal["conical"] = Field("conical", description="Tread geometry model")
    conicity: float = quantity(
        0.05, ge=0.0, le=0.5, description="Equivalent conicity tan(γ) of the tread", unit="-"
    )
    hertz_tread: Literal["worn", "conical"] = Field(
        "worn",
        description="Which Zhai Hertz constant G to use: worn/LM tread 3.86·R^-0.115e-8 or conical "
        "4.57·R^-0.149e-8 (m/N^(2/3))",
    )
    rail_head_radius: float = quantity(
        0.3, gt=0.01, le=10.0, description="Transverse radius of the rail head", unit="m"
    )
    friction: float = quantity(
        0.3, gt=0.0, le=1.0, description="Wheel–rail friction coefficient", unit="-"
    )
    shear_modulus: float = quantity(
        8.0e10, gt=1e9, le=2e11, description="Shear modulus of wheel and rail steel", unit="Pa"
    )
    poisson: float = quantity(
        0.28, ge=0.0, le=0.5, description="Poisson's ratio of steel", unit="-"
    )
    flange_clearance: float = quantity(
        0.008,
        gt=0.0,
        le=0.05,
        description="Lateral wheelset displacement at which the flange touches",
        unit="m",
    )
    flange_stiffness: float = quantity(
        1.5e8, gt=1e5, le=1e10, description="Lateral contact stiffness of the flange", unit="N/m"
    )
