"""Routes of health and version."""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter, Request

from flexride.api.deps import ServicesDep, TokenOk
from flexride.api.errors import SafeJSONResponse, recent_storage_fault
from flexride.api.schemas import HealthOut, VersionOut
from flexride.api.services import health as svc_health

router = APIRouter(tags=["service"])


@router.get("/health", response_model=HealthOut, summary="Health",
            responses={503: {"model": HealthOut, "description": "The database is down"}})
def health(svc: ServicesDep, request: Request, operator: TokenOk) -> Any:
    """The state of each component (API, database, storage, workers, broker of the Celery
    runner) and of the solver's compilation; ``degraded`` while the storage takes no writes
    or queued jobs have no live worker. With the API token (or on a service without one):
    where the database and broker are, the workers seen in the last hour and the job counts.
    """
    from fastapi.encoders import jsonable_encoder

    status, body = svc_health.health(svc, recent_storage_fault(request.app),
                                     operator=operator)
    return SafeJSONResponse(jsonable_encoder(body), status_code=status)


@router.get("/version", response_model=VersionOut, summary="Version")
def version(svc: ServicesDep) -> dict[str, Any]:
    """flexride, API and library versions, and the runner in use."""
    return svc_health.version(svc)
