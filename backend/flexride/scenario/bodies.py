"""Per-body modelling choice: rigid, flexible from a reduced finite-element model, or (the car
body) a free–free beam.
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, field_validator

from flexride.scenario.base import Schema, quantity


class BodyModel(Schema):
    """How one body (or both bogie frames) is modelled."""

    model: Literal["rigid", "flexible", "beam"] = Field(
        "rigid",
        description="Rigid, flexible (from the FE model) or beam (the car body only: a "
        "free–free Euler–Bernoulli beam bending first at first_bending_hz)")
    reduction: Literal["modal", "guyan", "craig-bampton"] = Field(
        "modal",
        description="Reduction of the FE model (free-interface modal truncation, Guyan, "
        "Craig–Bampton)",
    )
    cutoff_hz: float = quantity(
        40.0, gt=1.0, le=500.0, description="Highest elastic mode frequency kept", unit="Hz"
    )
    damping_ratio: float = quantity(
        0.02,
        ge=0.0,
        le=0.5,
        unit="-",
        description="Damping ratio of the elastic modes: "
        "of every mode (modal), or of the first two (rayleigh)",
    )
    damping_model: Literal["modal", "rayleigh"] = Field(
        "modal",
        description="Damping of the elastic modes: modal (the same ratio for every "
        "mode) or rayleigh (C = αM + βK through the first two elastic modes, paper Eqs. 2–4; "
        "the ratio grows with frequency above them)",
    )
    element_size_m: float = quantity(
        0.2, ge=0.05, le=1.0, description="Finite-element size of the generated mesh", unit="m"
    )
    first_bending_hz: float = quantity(
        10.0, ge=2.0, le=50.0, unit="Hz",
        description="First vertical bending frequency of the beam car body (model: beam)",
    )
    beam_mass: Literal["pitch_inertia", "uniform"] = Field(
        "pitch_inertia",
        description="Mass distribution of the beam car body (model: beam): pitch_inertia (a "
        "uniform beam plus point masses at its ends, or its centre, carrying the vehicle's mass "
        "and pitch inertia) or uniform (mass spread evenly, the classical beam of the "
        "literature, whose pitch inertia mL²/12 is not the vehicle's)",
    )

    @property
    def elastic(self) -> bool:
        """Whether the body has elastic modes (kept up to ``cutoff_hz``)."""
        return self.model != "rigid"

    @property
    def finite_elements(self) -> bool:
        """Whether the body is built from its finite-element model."""
        return self.model == "flexible"


class BodyModels(Schema):
    """Modelling choice for the car body and the bogie frames (wheelsets are always rigid)."""

    carbody: BodyModel = Field(
        default_factory=BodyModel, description="Car body: rigid, or flexible from its FE model"
    )
    frames: BodyModel = Field(
        default_factory=BodyModel,
        description="Both bogie frames: rigid, or flexible from their FE model",
    )

    @field_validator("frames")
    @classmethod
    def _frames_are_no_beams(cls, frames: BodyModel) -> BodyModel:
        if frames.model == "beam":
            raise ValueError("model beam is a car-body model; the frames are rigid or "
                             "flexible")
        return frames
