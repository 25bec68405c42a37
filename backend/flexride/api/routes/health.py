"""Routes of health and version."""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter, Request

from flexride.api.deps import ServicesDep
from flexride.api.errors import SafeJSONResponse, recent_storage_fault
from flexride.api.schemas import HealthOut, VersionOut
from flexride.api.services import health as svc_health

router = APIRouter(tags=["service"])


@router.get("/health", response_model=HealthOut, summary="Health",
            responses={503: {"model": HealthOut, "description": "The database is down"}})
def health(svc: ServicesDep, request: Request) -> Any:
    """API, database, storage (writable?), broker (Celery runner) and the workers seen in the
    last hour; ``degraded`` while the storage takes no writes.
    """
    from fastapi.encoders import jsonable_encoder

    status, body = svc_health.health(svc, recent_storage_fault(request.app))
    return SafeJSONResponse(jsonable_encoder(body), status_code=status)


@router.get("/version", response_model=VersionOut, summary="Version")
def version(svc: ServicesDep) -> dict[str, Any]:
    """flexride, API and library versions, and the runner in use."""
    return svc_health.version(svc)
