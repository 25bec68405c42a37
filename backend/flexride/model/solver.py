"""Numerical settings: time step, integrator parameters, rail model window, output."""

from __future__ import annotations

from pydantic import Field

from flexride.model.base import Schema


class Solver(Schema):
    """Time integration and rail-model settings."""

    dt: float = Field(1.0e-4, gt=1.0e-7, le=1.0e-2, description="Integration time step (s)")
    psi: float = Field(0.5, ge=0.0, le=1.0, description="Zhai integration parameter ψ (-)")
    phi: float = Field(0.5, ge=0.0, le=1.0, description="Zhai integration parameter φ (-)")
    rail_margin_m: float = Field(
        12.0,
        ge=3.0,
        le=200.0,
        description="Rail length kept beyond the outermost wheelsets inside the moving window (m)",
    )
    rail_shift_m: float = Field(
        6.0,
        gt=0.0,
        le=200.0,
        description="Distance the rail window moves at once; rounded to whole fastener bays (m)",
    )
    check_stability: bool = Field(
        True, description="Refuse a time step beyond the linearised stability limit before running"
    )
    progress_every_steps: int = Field(
        4000,
        ge=100,
        le=10_000_000,
        description="Steps between progress reports and cancellation checks (-)",
    )
    runaway_displacement_m: float = Field(
        1.0,
        gt=0.0,
        le=100.0,
        description="A body displacement beyond this (relative to static equilibrium) stops the "
        "run (m)",
    )


class OutputPoint(Schema):
    """A point on the car body where accelerations are recorded (car-body frame)."""

    name: str = Field(..., pattern=r"^[A-Za-z][A-Za-z0-9_-]{0,31}$", description="Point name")
    x: float = Field(
        ...,
        ge=-20.0,
        le=20.0,
        description="Longitudinal position from the body centre, forward positive (m)",
    )
    y: float = Field(0.0, ge=-2.0, le=2.0, description="Lateral position, left positive (m)")
    z: float = Field(..., ge=0.0, le=5.0, description="Height above top of rail (m)")


class Output(Schema):
    """What is recorded and how often."""

    rate_hz: float | None = Field(
        None,
        gt=10.0,
        le=1.0e6,
        description="Output sample rate (Hz). Default: at least 1 kHz and 20 samples per period of "
        "the shortest excitation wavelength passed at the running speed, rounded to divide 1/dt",
    )
    points: list[OutputPoint] = Field(
        default_factory=list,
        description="User-defined car-body points in addition to PR, PFB, PC, PRB, PLA, PRA",
    )
    floor_grid_spacing_m: float | None = Field(
        None, ge=0.2, le=5.0,
        description="Record the vertical and lateral floor acceleration on a grid of this spacing "
        "(m) for comfort maps (channels carbody.F<i>_<j>.acc.*); none when omitted",
    )
    floor_height_m: float = Field(1.10, ge=0.0, le=3.0, description="Floor height above TOR (m)")
    roof_height_m: float = Field(3.80, ge=0.5, le=5.0, description="Roof height above TOR (m)")
