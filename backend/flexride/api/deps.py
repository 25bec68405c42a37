"""Dependencies of the routes: the service objects of the app and the bearer-token check."""

from __future__ import annotations

import secrets
from dataclasses import dataclass
from typing import Annotated

from fastapi import Depends, HTTPException, Request, Security
from fastapi.security import HTTPAuthorizationCredentials, HTTPBearer

from flexride.api.services.fe import FEExports
from flexride.jobs.base import JobRunner
from flexride.jobs.reaper import Reaper
from flexride.settings import Settings
from flexride.store import JobStore, ResultFiles
from flexride.store.uploads import UploadStore
from flexride.study.submit import Submitter


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


def get_services(request: Request) -> Services:
    """The app's :class:`Services`."""
    return request.app.state.services


ServicesDep = Annotated[Services, Depends(get_services)]

_bearer = HTTPBearer(
    auto_error=False,
    description="Required by every mutating endpoint when the service has FLEXRIDE_API_TOKEN",
)


def token_ok(
    request: Request,
    credentials: Annotated[HTTPAuthorizationCredentials | None, Security(_bearer)] = None,
) -> bool:
    """Whether the request may change things: the service has no token, or the request carries
    it as ``Authorization: Bearer <token>``.
    """
    token = get_services(request).settings.api_token
    if not token:
        return True
    given = credentials.credentials if credentials is not None else ""
    return secrets.compare_digest(given.encode(), token.encode())


def require_token(
    request: Request,
    credentials: Annotated[HTTPAuthorizationCredentials | None, Security(_bearer)] = None,
) -> None:
    """Check ``Authorization: Bearer <token>`` when the service has a token (401 otherwise)."""
    if not token_ok(request, credentials):
        raise HTTPException(status_code=401, detail="a valid bearer token is required",
                            headers={"WWW-Authenticate": "Bearer"})


TokenOk = Annotated[bool, Depends(token_ok)]


AUTH = [Depends(require_token)]
"""Dependencies of mutating routes."""
