"""Numerical settings: time step, integrator parameters, rail model window, output."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from flexride.scenario.base import Schema, quantity

#: The value of ``solver.dt`` that lets the solver choose the step.
AUTO = "auto"
#: ``solver.dt: auto`` takes at most this fraction of the largest stable step.
AUTO_FRACTION = 0.8
#: A time step given as a number (s).
FixedStep = Annotated[float, Field(gt=1.0e-7, le=1.0e-2)]


class Solver(Schema):
    """Time integration and rail-model settings."""

    dt: FixedStep | Literal["auto"] = quantity(
        AUTO,
        description=f"Integration time step; auto (the default): at most {AUTO_FRACTION:g} of "
        "the largest step the solver's one-step map is stable for, dividing the output "
        "interval",
        unit="s",
    )
    psi: float = quantity(0.5, ge=0.0, le=1.0, description="Zhai integration parameter ψ", unit="-")
    phi: float = quantity(0.5, ge=0.0, le=1.0, description="Zhai integration parameter φ", unit="-")
    rail_margin_m: float = quantity(
        12.0,
        ge=3.0,
        le=200.0,
        description="Rail length kept beyond the outermost wheelsets inside the moving window",
        unit="m",
    )
    rail_shift_m: float = quantity(
        6.0,
        gt=0.0,
        le=200.0,
        description="Distance the rail window moves at once; rounded to whole fastener bays",
        unit="m",
    )
    check_stability: bool = Field(
        True, description="Refuse a time step beyond the linearised stability limit before running"
    )
    progress_every_steps: int = quantity(
        4000,
        ge=100,
        le=10_000_000,
        description="Steps between progress reports and cancellation checks",
        unit="-",
    )
    runaway_displacement_m: float = quantity(
        1.0,
        gt=0.0,
        le=100.0,
        description="A body displacement beyond this (relative to static equilibrium) stops "
        "the run",
        unit="m",
    )


class OutputPoint(Schema):
    """A point on the car body where accelerations are recorded (car-body frame)."""

    name: str = Field(..., pattern=r"^[A-Za-z][A-Za-z0-9_-]{0,31}$", description="Point name")
    x: float = quantity(
        ...,
        ge=-20.0,
        le=20.0,
        description="Longitudinal position from the body centre, forward positive",
        unit="m",
    )
    y: float = quantity(
        0.0, ge=-2.0, le=2.0, description="Lateral position, left positive", unit="m"
    )
    z: float = quantity(..., ge=0.0, le=5.0, description="Height above top of rail", unit="m")


class Output(Schema):
    """What is recorded and how often."""

    rate_hz: float | None = quantity(
        None,
        gt=10.0,
        le=1.0e6,
        unit="Hz",
        description="Output sample rate. Default: at least 1 kHz and 20 samples per period of "
        "the shortest excitation wavelength passed at the running speed; a given step's rate "
        "is rounded to divide 1/dt (an automatic step divides the output interval)",
    )
    points: list[OutputPoint] = Field(
        default_factory=list,
        description="User-defined car-body points in addition to PR, PFB, PC, PRB, PLA, PRA",
    )
    floor_grid_spacing_m: float | None = quantity(
        None,
        ge=0.2,
        le=5.0,
        unit="m",
        description="Spacing of a floor grid whose vertical and lateral accelerations are "
        "recorded for comfort maps (channels carbody.F<i>_<j>.acc.*); none when omitted",
    )
    floor_height_m: float = quantity(
        1.10, ge=0.0, le=3.0, description="Floor height above TOR", unit="m"
    )
    roof_height_m: float = quantity(
        3.80, ge=0.5, le=5.0, description="Roof height above TOR", unit="m"
    )
