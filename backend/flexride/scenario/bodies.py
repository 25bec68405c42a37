"""Per-body modelling choice: rigid, or flexible from a reduced finite-element model."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from flexride.scenario.base import Schema, quantity


class BodyModel(Schema):
    """How one body (or both bogie frames) is modelled."""

    model: Literal["rigid", "flexible"] = Field("rigid", description="Rigid or flexible body")
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


class BodyModels(Schema):
    """Modelling choice for the car body and the bogie frames (wheelsets are always rigid)."""

    carbody: BodyModel = Field(
        default_factory=BodyModel, description="Car body: rigid, or flexible from its FE model"
    )
    frames: BodyModel = Field(
        default_factory=BodyModel,
        description="Both bogie frames: rigid, or flexible from their FE model",
    )
