"""Routes of FE meshes and mode shapes: a body model by its parameters, or a job's own."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import APIRouter, Path, Query, Response

from flexride.api.deps import ServicesDep, TokenOk
from flexride.api.params import JobId
from flexride.api.schemas import ErrorResponse, FEBuildStatus, FEExport, FEPairing
from flexride.api.services import fe as svc_fe
from flexride.fem.export import DEFAULT_MAX_MODES, ExportSpec
from flexride.scenario.bodies import BodyModel
from flexride.study.admission import check_fe_build

router = APIRouter(tags=["fe"])

Kind = Annotated[Literal["carbody", "frame"], Path(description="carbody or frame")]
MaxModes = Annotated[int, Query(ge=0, le=100, description="Mode shapes exported (the lowest)")]
Reduction = BodyModel.model_fields["reduction"].annotation


def _body_query(name: str) -> Any:
    """``Query`` with the description and bounds of field ``name`` of the scenario's body
    model (``bodies.carbody`` / ``bodies.frames``), so both take the same values.
    """
    info = BodyModel.model_fields[name]
    kw: dict[str, Any] = {"description": info.description}
    for m in info.metadata:
        for bound in ("gt", "ge", "lt", "le"):
            if getattr(m, bound, None) is not None:
                kw[bound] = getattr(m, bound)
    return Query(**kw)


def _preset_spec(svc: Any, kind: str, element_size_m: float, cutoff_hz: float, reduction: Any,
                 max_modes: int, preset: str) -> ExportSpec:
    """The export of a body model fitted to ``preset``'s vehicle, once the service's limits
    admit its build (422 at the query parameter otherwise).
    """
    body = BodyModel(model="flexible", reduction=reduction, cutoff_hz=cutoff_hz,
                     element_size_m=element_size_m)
    vehicle = svc_fe.preset_vehicle(preset)
    check_fe_build(kind, vehicle, element_size_m, cutoff_hz, svc.submitter.limits, ("query",))
    return ExportSpec.create(kind, vehicle, body, max_modes)


#: The defaults of a scenario's body model.
_DEFAULT = BodyModel()


RESPONSES: dict[int | str, dict[str, Any]] = {
    200: {"model": FEExport, "description": "The mesh and mode shapes"},
    202: {"model": FEBuildStatus, "description": "Being built: ask again after Retry-After s",
          "headers": {"Retry-After": {"description": "Seconds", "schema": {"type": "integer"}}}},
    422: {"model": ErrorResponse,
          "description": "Invalid parameter (field path, allowed range), or parameters that "
          "give no FE model"},
    401: {"model": ErrorResponse, "description": "The model is not built yet and submitting "
          "its build needs the API token (when the service has one)"},
    503: {"model": ErrorResponse, "description": "The build job failed (not for a model "
          "error) or too many are queued; ask again after Retry-After s"},
}


@router.get("/fe/{kind}", response_model=None, responses=RESPONSES,
            summary="FE mesh and mode shapes of a body model")
def fe_model(
    kind: Kind,
    svc: ServicesDep,
    may_build: TokenOk,
    element_size_m: Annotated[float, _body_query("element_size_m")] = _DEFAULT.element_size_m,
    cutoff_hz: Annotated[float, _body_query("cutoff_hz")] = _DEFAULT.cutoff_hz,
    reduction: Annotated[Reduction, _body_query("reduction")] = _DEFAULT.reduction,  # type: ignore
    max_modes: MaxModes = DEFAULT_MAX_MODES,
    preset: Annotated[str, Query(max_length=80, description="Preset whose vehicle (inertia, "
                                 "suspension geometry) the model is fitted to")] = "paper-metro",
) -> Response:
    """The car body's or bogie frame's FE mesh with its lowest mode shapes, as
    ``flexride fe export`` writes them (plus ``model``: what was built).

    The parameters are those of a scenario's ``bodies.carbody`` / ``bodies.frames`` (same
    names, units and ranges). 200 when the export exists; else its build is a job of kind
    ``fe_export`` run by the service's workers (one job per parameter set, however often it
    is asked for) and the answer is 202 with ``Retry-After`` and the job's state: the first
    build of the 0.2 m car body takes about a minute of computing (51 s CPU measured; several
    minutes of wall time on a busy machine), a body already in the FE cache a
    fraction of a second. Builds beyond the service's limits (``FLEXRIDE_MAX_FE_DOFS``,
    ``FLEXRIDE_MAX_FE_CUTOFF_HZ``) are refused with 422 naming the parameter.
    """
    spec = _preset_spec(svc, kind, element_size_m, cutoff_hz, reduction, max_modes, preset)
    return svc_fe.respond(svc.fe, spec, may_start=may_build)


@router.get("/fe/{kind}/pairing", response_model=None,
            responses={**RESPONSES, 200: {"model": FEPairing,
                                          "description": "The pairing of modes with targets"}},
            summary="Pairing of the car body's modes with calibration targets")
def fe_pairing(
    kind: Annotated[Literal["carbody"], Path(description="carbody (the mode types are the car "
                                             "body classifier's)")],
    svc: ServicesDep,
    may_build: TokenOk,
    targets: Annotated[str, Query(min_length=1, max_length=400, description=(
        "Targets FREQ[:TYPE],… in Hz as for flexride fe calibrate --targets, e.g. "
        "'5.03:torsion,6.11:rhombic,8.84:first vertical bending'; a typed target pairs only "
        "with a mode of its type, an untyped one with the nearest free mode"))],
    element_size_m: Annotated[float, _body_query("element_size_m")] = _DEFAULT.element_size_m,
    cutoff_hz: Annotated[float, _body_query("cutoff_hz")] = _DEFAULT.cutoff_hz,
    reduction: Annotated[Reduction, _body_query("reduction")] = _DEFAULT.reduction,  # type: ignore
    max_modes: MaxModes = DEFAULT_MAX_MODES,
    preset: Annotated[str, Query(max_length=80, description="Preset whose vehicle (inertia, "
                                 "suspension geometry) the model is fitted to")] = "paper-metro",
) -> Response:
    """How the car body model's lowest ``max_modes`` elastic modes (those of ``GET
    /fe/carbody`` with the same parameters) pair with calibration targets: for each target
    the paired mode, its frequency error and type, or why none pairs (no mode of the type
    among them). The answers while the model is not built are those of ``GET /fe/{kind}``
    (202, 401, 422, 503); targets that do not parse are a 422 at ``query.targets``.
    """
    spec = _preset_spec(svc, kind, element_size_m, cutoff_hz, reduction, max_modes, preset)
    return svc_fe.respond_pairing(svc.fe, spec, targets, may_start=may_build)


@router.get("/jobs/{job_id}/fe/{kind}", response_model=None,
            responses={**RESPONSES, 409: {"model": ErrorResponse,
                                          "description": "The job models this body as rigid"}},
            summary="FE mesh and mode shapes of a job's flexible body")
def job_fe_model(job_id: JobId, kind: Kind, svc: ServicesDep, may_build: TokenOk,
                 max_modes: MaxModes = DEFAULT_MAX_MODES) -> Response:
    """The FE model of a simulation job's flexible car body (``kind=carbody``) or bogie frames
    (``kind=frame``): its own vehicle and ``bodies`` settings, in any job state. Answers as
    ``GET /fe/{kind}`` (200, 202 while building); 409 when the job's body is rigid or the job
    is not a simulation.
    """
    return svc_fe.respond(svc.fe, svc_fe.job_spec(svc, job_id, kind, max_modes),
                          may_start=may_build)
