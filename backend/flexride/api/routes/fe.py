"""Routes of FE meshes and mode shapes: a body model by its parameters, or a job's own."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import APIRouter, Depends, Path, Query, Request, Response
from pydantic import ValidationError

from flexride.api.deps import ServicesDep, TokenOk
from flexride.api.params import JobId
from flexride.api.schemas import ErrorResponse, FEBuildStatus, FEExport, FEPairing
from flexride.api.services import fe as svc_fe
from flexride.errors import ErrorItem, ScenarioError
from flexride.fem.export import BODY_FIELDS, DEFAULT_MAX_MODES, ExportSpec
from flexride.scenario.bodies import BodyModel, CarBodyCalibration
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


#: The defaults of a scenario's body model.
_DEFAULT = BodyModel()
_CAL_LIMITS = CarBodyCalibration.model_fields
#: Query parameters of a calibration, by the field of ``bodies.carbody.calibration`` each sets.
CALIBRATION_QUERY = {"targets": "calibration_targets", "variables": "calibration_variables",
                     "max_evaluations": "calibration_max_evaluations",
                     "n_modes": "calibration_n_modes"}


def body_spec(
    request: Request,
    svc: ServicesDep,
    element_size_m: Annotated[float, _body_query("element_size_m")] = _DEFAULT.element_size_m,
    cutoff_hz: Annotated[float, _body_query("cutoff_hz")] = _DEFAULT.cutoff_hz,
    reduction: Annotated[Reduction, _body_query("reduction")] = _DEFAULT.reduction,  # type: ignore
    max_modes: MaxModes = DEFAULT_MAX_MODES,
    preset: Annotated[str, Query(max_length=80, description="Preset whose vehicle (inertia, "
                                 "suspension geometry) the model is fitted to")] = "paper-metro",
    calibration_targets: Annotated[str | None, Query(max_length=400, description=(
        "The car body only: calibrate the model to these targets before it is reduced, "
        "FREQ[:TYPE],… in Hz as bodies.carbody.calibration.targets and flexride fe calibrate "
        "--targets, e.g. '5.03:torsion,6.11:rhombic,8.84:first vertical bending' (types: the "
        "classifier's names); absent: the default body"))] = None,
    calibration_variables: Annotated[str | None, Query(max_length=200, description=(
        "Calibration variables, comma-separated (absent: those of the default body's "
        "calibration); with calibration_targets only"))] = None,
    calibration_max_evaluations: Annotated[int, Query(
        description=_CAL_LIMITS["max_evaluations"].description)] = 30,
    calibration_n_modes: Annotated[int | None, Query(
        description=_CAL_LIMITS["n_modes"].description)] = None,
) -> ExportSpec | None:
    """The export of a body model fitted to ``preset``'s vehicle, from the query parameters
    every FE route shares (those of a scenario's ``bodies.carbody`` / ``bodies.frames``, the
    calibration flattened), once the service's limits admit its build; 422 at the query
    parameter otherwise.

    The body kind is the route's path parameter, which each route declares (and checks) with
    the kinds it serves; None for another kind (the route's own check answers 422 then).
    """
    kind = request.path_params.get("kind")
    if kind not in BODY_FIELDS:
        return None
    calibration = _query_calibration(kind, calibration_targets, calibration_variables,
                                     calibration_max_evaluations, calibration_n_modes)
    body = BodyModel(model="flexible", reduction=reduction, cutoff_hz=cutoff_hz,
                     element_size_m=element_size_m, calibration=calibration)
    vehicle = svc_fe.preset_vehicle(preset)
    check_fe_build(kind, vehicle, element_size_m, cutoff_hz, svc.submitter.limits, ("query",))
    return ExportSpec.create(kind, vehicle, body, max_modes)


def _query_calibration(kind: str, targets: str | None, variables: str | None,
                       max_evaluations: int, n_modes: int | None) -> CarBodyCalibration | None:
    """The calibration of the query (None without ``calibration_targets``); every problem a
    :class:`ScenarioError` at its query parameter (422).
    """
    if targets is None:
        if variables is not None:
            raise ScenarioError.at(("query", "calibration_variables"), "give "
                                   "calibration_targets to calibrate", "GET /fe")
        return None
    if kind != "carbody":
        raise ScenarioError.at(("query", "calibration_targets"), "a calibration is the car "
                               "body's (its mode types): the bogie frame has none", "GET /fe")
    data: dict[str, Any] = {"targets": targets, "max_evaluations": max_evaluations,
                            "n_modes": n_modes}
    if variables is not None:
        data["variables"] = [v.strip() for v in variables.split(",") if v.strip()]
    try:
        return CarBodyCalibration.model_validate(data)
    except ValidationError as exc:
        items = [ErrorItem(("query", _query_name(err["loc"])), _message(err))
                 for err in exc.errors()]
        raise ScenarioError("GET /fe: " + "; ".join(f"{it.path}: {it.msg}" for it in items),
                            items) from None


def _query_name(loc: tuple[Any, ...]) -> str:
    """The query parameter of a calibration field's error location (a whole-calibration
    check: the budget's).
    """
    field = str(loc[0]) if loc else "max_evaluations"
    return CALIBRATION_QUERY.get(field, CALIBRATION_QUERY["max_evaluations"])


def _message(err: Any) -> str:
    """A validation error's message, with the target it is about."""
    msg = str(err["msg"]).removeprefix("Value error, ")
    loc = err["loc"]
    if len(loc) > 1 and loc[0] == "targets":
        return f"target {int(loc[1]) + 1}: {msg}"
    return msg


BodySpec = Annotated[ExportSpec | None, Depends(body_spec)]


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
    spec: BodySpec,
    svc: ServicesDep,
    may_build: TokenOk,
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

    With ``calibration_targets`` (the car body only; 422 for the frame) the build job first
    calibrates the model to the typed targets (``bodies.carbody.calibration``; its cost
    bounded by ``calibration_max_evaluations``, about 5 s per evaluation at 0.2 m, 0.4 s at
    0.5 m; cached by content, so it runs once) and ``model.calibration`` reports the
    calibrated values and the pairing with each target's frequency error. A target type
    the starting model has no mode of fails the build early (422).
    """
    assert spec is not None  # the kind was checked
    return svc_fe.respond(svc.fe, spec, may_start=may_build)


@router.get("/fe/{kind}/pairing", response_model=None,
            responses={**RESPONSES, 200: {"model": FEPairing,
                                          "description": "The pairing of modes with targets"}},
            summary="Pairing of the car body's modes with calibration targets")
def fe_pairing(
    kind: Annotated[Literal["carbody"], Path(description="carbody (the mode types are the car "
                                             "body classifier's)")],
    spec: BodySpec,
    svc: ServicesDep,
    may_build: TokenOk,
    targets: Annotated[str, Query(min_length=1, max_length=400, description=(
        "Targets FREQ[:TYPE],… in Hz as for flexride fe calibrate --targets, e.g. "
        "'5.03:torsion,6.11:rhombic,8.84:first vertical bending'; a typed target pairs only "
        "with a mode of its type, an untyped one with the nearest free mode"))],
) -> Response:
    """How the car body model's lowest ``max_modes`` elastic modes (those of ``GET
    /fe/carbody`` with the same parameters) pair with calibration targets: for each target
    the paired mode, its frequency error and type, or why none pairs (no mode of the type
    among them). The answers while the model is not built are those of ``GET /fe/{kind}``
    (202, 401, 422, 503); targets that do not parse are a 422 at ``query.targets``. With
    ``calibration_targets`` it is the pairing of the calibrated model (``GET /fe/carbody``
    with the same parameters).
    """
    assert spec is not None  # the kind was checked
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
