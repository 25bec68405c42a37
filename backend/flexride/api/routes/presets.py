"""Routes of presets and schemas."""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import APIRouter, Path

from flexride.api.errors import NotFound
from flexride.api.schemas import PaperPointOut, PresetOut

router = APIRouter(tags=["presets"])


@router.get("/presets", response_model=list[PresetOut], summary="List presets")
def list_presets() -> list[dict[str, Any]]:
    """The named scenarios (the paper's vehicle and track and its 16 conditions)."""
    from flexride.scenario.presets import PRESETS

    return [{"name": k, "description": v.get("description", ""),
             "speed_kmh": v.get("speed_kmh")} for k, v in PRESETS.items()]


@router.get("/presets/{name}", response_model=dict[str, Any], summary="A preset's scenario")
def get_preset(name: Annotated[str, Path(max_length=80)]) -> dict[str, Any]:
    """The full, validated scenario of a preset (every default filled in)."""
    from flexride.scenario.presets import PRESETS, load_preset

    if name not in PRESETS:
        raise NotFound(f"no preset {name!r}")
    return load_preset(name).model_dump(mode="json")


@router.get("/schemas/scenario", response_model=dict[str, Any], summary="Scenario schema")
def scenario_schema() -> dict[str, Any]:
    """JSON schema of a scenario: every field with its unit, default and allowed range."""
    from flexride.scenario.scenario import Scenario

    return Scenario.model_json_schema()


@router.get("/schemas/points", response_model=list[PaperPointOut],
            summary="The paper's measurement points")
def paper_points() -> list[dict[str, Any]]:
    """The paper's car-body points (PR, PFB, PC, PRB, PLA, PRA) in channel order, with a
    one-line description and where each sits; a run's own points (with positions) are in
    ``GET /jobs/{id}/channels``.
    """
    from dataclasses import asdict

    from flexride.vehicle.topology import PAPER_POINTS

    return [asdict(p) for p in PAPER_POINTS]


@router.get("/schemas/study", response_model=dict[str, Any], summary="Study request schema")
def study_schema() -> dict[str, Any]:
    """JSON schema of a study request."""
    from flexride.api.schemas import StudyCreate

    return StudyCreate.model_json_schema()
