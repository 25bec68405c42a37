"""Route of the frequency-domain comfort estimate (``flexride estimate`` over HTTP), of one
scenario or of a sweep of one of its fields; computed at once, in the request.
"""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter, Request, Response

from flexride.api.deps import AUTH, ServicesDep
from flexride.api.schemas import ErrorResponse
from flexride.api.schemas.estimates import (
    MAX_SWEEP_VALUES,
    EstimateCreate,
    EstimateOut,
    NotApplicableOut,
    SweepOut,
)
from flexride.api.services import estimates as svc_est

router = APIRouter(prefix="/estimates", tags=["estimates"])

_REFUSED_EXAMPLE = {
    "detail": [{"loc": ["strict"], "type": "LinearisationError",
                "msg": "wheelset1 right wheel is in flange contact at equilibrium (steady "
                       "curving): flange contact is not linear; use the time-domain solver",
                "ctx": {"reason": "flange_contact"}}],
    "message": "wheelset1 right wheel is in flange contact at equilibrium (steady curving): "
               "flange contact is not linear; use the time-domain solver. What to do: run the "
               "time-domain simulation of the scenario (POST /api/v1/jobs), which models "
               "flange contact, or ask again with \"strict\": false for an estimate flagged as "
               "doubtful",
    "reason": "flange_contact"}

RESPONSES: dict[int | str, dict[str, Any]] = {
    200: {"description": "The estimate (EstimateOut), with 'sweep' the series over the "
          "values (SweepOut), or with refusal 'answer' for a scenario the linear estimate "
          "does not hold for applicable: false and the reasons (NotApplicableOut)"},
    401: {"model": ErrorResponse, "description": "Bearer token missing or wrong"},
    409: {"model": ErrorResponse, "description": "A flexible body whose FE model is not built "
          "yet: a job of the scenario or GET /fe/{kind} builds it"},
    422: {"model": ErrorResponse, "description": "Invalid scenario or option (field path and "
          "allowed range; a sweep value at ['sweep', 'values', i]), beyond the service's "
          "limits, or a scenario the linear estimate does not hold for (type "
          "LinearisationError, ctx.reason flange_contact, contact_loss, excitation, unstable or "
          "equilibrium, and what to do)",
          "content": {"application/json": {"examples": {
              "refused": {"summary": "Flange contact in steady curving (strict)",
                          "value": _REFUSED_EXAMPLE}}}}},
    503: {"model": ErrorResponse, "description": "Every estimate slot of the service is busy; "
          "ask again after Retry-After s",
          "headers": {"Retry-After": {"description": "Seconds", "schema": {"type": "integer"}}}},
}


@router.post("", response_model=EstimateOut | SweepOut | NotApplicableOut, dependencies=AUTH,
             responses=RESPONSES, summary="Frequency-domain comfort estimate")
def create_estimate(body: EstimateCreate, request: Request, svc: ServicesDep) -> Response:
    """The comfort indices of a scenario from its linearised vehicle–track model driven by the
    track spectra — what ``flexride estimate --json`` prints, in about 0.3–0.5 s for a rigid
    vehicle (docs/analysis.md, "Frequency-domain estimate"): per point the rms, ISO 2631
    weighted rms, Sperling, EN 12299 a_P95 / N_MV, the expected peak and the eigenmodes that
    carry the comfort-weighted variance.

    The scenario is given as for ``POST /jobs`` (``scenario``, or ``preset`` with
    ``overrides``) and checked as a job is (field paths and ranges, uploads only, FE bodies
    and recorded points within the service's limits). With ``sweep`` the scenario is
    estimated at each of up to {max_values} values of one field and the answer holds every
    index against the values (null where the linear estimate is refused, with the reason in
    ``refused``).

    With ``floor_map`` the answer also maps the comfort over the car body's floor grid
    (``floor_map``: axes, names, rms, ISO 2631 weighted rms and Sperling per direction, N_MV;
    422 at ``["floor_map", "spacing_m"]`` for a grid beyond the service's limit of recorded
    points).

    With real wheel and rail profiles the contact is quasi-linearised by default
    (``linearisation: "statistical"``: Gaussian-equivalent gains over each wheel's lateral
    motion on the rail, iterated to the response's own amplitude; ``"local"`` takes the slopes
    at the operating point); the model summary's ``linearisation`` says how it went.

    A scenario the linear model does not hold for (flange contact or lost contact at
    equilibrium, a transient excitation, hunting, a quasi-linearisation that does not settle)
    is refused with 422 unless ``strict`` is
    false; the time-domain job (``POST /jobs``) is the answer then. With ``refusal:
    "answer"`` the refusal is a 200 answer with ``applicable: false``, the reason and the
    located reasons (for a client that asks whether the estimate applies). A flexible body is
    estimated only when its FE model is built (409 otherwise). Answers are kept: the same
    request again is served from memory.
    """
    return svc_est.estimate_answer(request, svc, body)


if create_estimate.__doc__:
    create_estimate.__doc__ = create_estimate.__doc__.replace(
        "{max_values}", str(MAX_SWEEP_VALUES))
