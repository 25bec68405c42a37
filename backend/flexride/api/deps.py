"""Dependencies of the routes: the service objects of the app and the bearer-token check."""

from __future__ import annotations

import secrets
from dataclasses import dataclass
from typing import Annotated, Any

from fastapi import Depends, HTTPException, Request, Security
from fastapi.security import HTTPAuthorizationCredentials, HTTPBearer
from fastapi.security.utils import get_authorization_scheme_param

from flexride.api.middleware import TOKEN_REQUIRED
from flexride.api.services.fe import FEExports
from flexride.jobs.base import JobRunner
from flexride.jobs.reaper import Reaper
from flexride.settings import Settings
from flexride.store import JobStore, ResultFiles
from flexride.store.uploads import UploadStore
from flexride.study.submit import Submitter


@dataclass(frozen=True)
class Kept:
    """A value made at ``at`` (``time.monotonic()``, s) from ``key``, kept for a while."""

    at: float
    key: Any
    value: Any


@dataclass
class Services:
    """Everything a request may need, created once per app (see :func:`.main.create_app`)."""

    settings: Settings
    store: JobStore
    files: ResultFiles
    runner: JobRunner
    submitter: Submitter
    reaper: Reaper
    fe: FEExports
    uploads: UploadStore
    #: The last health report and storage probe (:mod:`flexride.api.services.health`).
    health_report: Kept | None = None
    storage_probe: Kept | None = None


def services_of(request: Request) -> Services:
    """The app's :class:`Services`."""
    return request.app.state.services


async def get_services(request: Request) -> Services:
    """The app's :class:`Services` (a dependency; ``async``: FastAPI runs a synchronous one
    in a worker thread, a hop that cost more than the lookup).
    """
    return services_of(request)


ServicesDep = Annotated[Services, Depends(get_services)]

_bearer = HTTPBearer(
    auto_error=False,
    description="Required by every mutating endpoint when the service has FLEXRIDE_API_TOKEN",
)


def authorized(token: str | None, authorization: str | None) -> bool:
    """Whether a request with this ``Authorization`` header may change things: the service
    has no ``token``, or the header is ``Bearer <token>`` (compared in constant time).
    """
    if not token:
        return True
    scheme, credentials = get_authorization_scheme_param(authorization)
    given = credentials if scheme.lower() == "bearer" else ""
    return secrets.compare_digest(given.encode(), token.encode())


async def token_ok(
    request: Request,
    # declared for the OpenAPI document (the bearer scheme); the header is read below
    credentials: Annotated[HTTPAuthorizationCredentials | None, Security(_bearer)] = None,
) -> bool:
    """Whether the request may change things (and see operators' details): the service has
    no token, or the request carries it as ``Authorization: Bearer <token>``.
    """
    return authorized(services_of(request).settings.api_token,
                      request.headers.get("authorization"))


async def require_token(
    request: Request,
    credentials: Annotated[HTTPAuthorizationCredentials | None, Security(_bearer)] = None,
) -> None:
    """Check ``Authorization: Bearer <token>`` when the service has a token (401 otherwise).

    :class:`flexride.api.middleware.TokenGate` makes the same check before the request's body
    is read, for every route that has this dependency (:func:`needs_token`).
    """
    if not await token_ok(request, credentials):
        raise HTTPException(status_code=401, detail=TOKEN_REQUIRED,
                            headers={"WWW-Authenticate": "Bearer"})


def needs_token(route: Any) -> bool:
    """Whether a route (or a route context of FastAPI's router) needs the token: it has
    :func:`require_token` among its dependencies.
    """
    def has(dependant: Any) -> bool:
        return dependant.call is require_token or any(has(d) for d in dependant.dependencies)

    dependant = getattr(route, "dependant", None)
    return dependant is not None and has(dependant)


TokenOk = Annotated[bool, Depends(token_ok)]


AUTH = [Depends(require_token)]
"""Dependencies of mutating routes."""
