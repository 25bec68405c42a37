"""Route of the wheel–rail contact geometry of a profile pair: the table of ``flexride contact
table``, the conicity of ``flexride contact conicity`` and the placed profiles for drawing.

Profiles are the built-in ``s1002`` wheel and ``60e1`` rail or uploads (``POST /profiles``)
named by their id; a request never names a file. The bounds of the placement parameters are
those of a scenario's ``contact`` settings (and the vehicle's wheel radius), in mm.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import APIRouter, Query, Request, Response
from pydantic import BaseModel

from flexride.api.deps import ServicesDep
from flexride.api.schemas import ContactGeometryOut
from flexride.api.services.contact import MAX_ROWS, GeometryQuery, geometry_answer
from flexride.contact.placement import (
    FLANGE_BACK_MM,
    GAUGE_HEIGHT_MM,
    GAUGE_MM,
    R0_MM,
)
from flexride.scenario.contact import Contact
from flexride.scenario.vehicle import VehicleGeometry

router = APIRouter(prefix="/contact", tags=["contact"])

_BOUNDS = ("gt", "ge", "lt", "le")


def _mm_query(model: type[BaseModel], field: str, description: str) -> Any:
    """``Query`` in mm with the bounds of ``field`` of ``model`` (in m), so that the API
    takes the values a scenario takes.
    """
    kw: dict[str, Any] = {"description": description}
    for m in model.model_fields[field].metadata:
        for bound in _BOUNDS:
            if getattr(m, bound, None) is not None:
                kw[bound] = round(getattr(m, bound) * 1e3, 6)
    return Query(**kw)


Wheel = Annotated[str, Query(
    pattern=r"^(s1002|S1002|[0-9a-f]{64})$",
    description="Wheel profile: s1002 (EN 13715) or the id of an uploaded wheel profile "
    "(64 hexadecimal digits, from POST /profiles); never a file path")]
Rail = Annotated[str, Query(
    pattern=r"^(60e1|60E1|[0-9a-f]{64})$",
    description="Rail profile: 60e1 (EN 13674-1) or the id of an uploaded rail profile "
    "(64 hexadecimal digits); never a file path")]
Inclination = Annotated[Literal["1:40", "1:20", "none"], Query(
    description="Rail inclination toward the track centre ('none' for a rail profile that "
    "is already canted)")]
GaugeMm = Annotated[float, _mm_query(Contact, "gauge", "Track gauge (mm)")]
GaugeHeightMm = Annotated[float, _mm_query(
    Contact, "gauge_height", "Gauge point below the top of rail (mm)")]
FlangeBackMm = Annotated[float, _mm_query(
    Contact, "flange_back_distance", "Flange-back distance of the wheelset (mm); smaller than "
    "the gauge")]
R0Mm = Annotated[float, _mm_query(
    VehicleGeometry, "wheel_radius", "Nominal rolling radius at the taping line (mm)")]
Roll = Annotated[bool, Query(
    description="Solve the wheelset roll from both wheels touching (true) or keep it 0")]
YMaxMm = Annotated[float, Query(ge=0.1, le=20.0, description="Half range of the Δy grid (mm)")]
StepMm = Annotated[float, Query(
    ge=0.01, le=1.0, description=f"Step of the Δy grid (mm); at most {MAX_ROWS} rows "
    "(2·y_max_mm/step_mm + 1)")]

RESPONSES: dict[int | str, dict[str, Any]] = {
    422: {"description": "A parameter out of its range (field path, allowed range), more "
          f"than {MAX_ROWS} rows, an unknown upload or one of the other kind, or a placement "
          "in which the wheels do not rest on their rails (at the parameter)"},
}


@router.get("/geometry", response_model=ContactGeometryOut, responses=RESPONSES,
            summary="Contact geometry of a wheel and rail profile pair")
def contact_geometry(
    request: Request,
    svc: ServicesDep,
    wheel: Wheel = "s1002",
    rail: Rail = "60e1",
    inclination: Inclination = "1:40",
    gauge_mm: GaugeMm = GAUGE_MM,
    gauge_height_mm: GaugeHeightMm = GAUGE_HEIGHT_MM,
    flange_back_mm: FlangeBackMm = FLANGE_BACK_MM,
    r0_mm: R0Mm = R0_MM,
    roll: Roll = True,
    y_max_mm: YMaxMm = 12.0,
    step_mm: StepMm = 0.05,
) -> Response:
    """Rolling-radius difference, contact-angle difference, roll, roll coefficient and
    contact positions of the rigid contact against the wheelset's lateral displacement Δy
    (``rows``, as ``flexride contact table --json``), the EN 15302 equivalent conicity
    against the amplitude (``conicity``, as ``flexride contact conicity --json``), the left
    rail and the left wheel at Δy = 0 in track coordinates (``profiles``) and, per row, the
    axle height and the contact points (``contacts``), to draw the wheel moving with Δy.

    A pure function of its parameters, kept once computed: the first request of a parameter
    set takes about 0.3 s (default grid, with roll), up to about 1 s for the largest grid.
    """
    query = GeometryQuery(
        wheel=wheel, rail=rail, inclination=inclination, gauge_mm=gauge_mm,
        gauge_height_mm=gauge_height_mm, flange_back_mm=flange_back_mm, r0_mm=r0_mm,
        roll=roll, y_max_mm=y_max_mm, step_mm=step_mm)
    return geometry_answer(request, query, svc.uploads.sources)
