"""Routes of uploaded wheel and rail profiles, stored by content hash.

A scenario refers to an upload by its id (``"contact": {"geometry": "profiles", "wheel":
{"upload": "<id>"}}``); over the API a profile never names a server file.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import APIRouter, Path, Query, Request, Response

from flexride.api.deps import AUTH, ServicesDep
from flexride.api.errors import NotFound
from flexride.api.schemas import ProfileUploadOut
from flexride.contact.scenario_table import PROFILE_EXTENSIONS
from flexride.errors import ErrorItem, ScenarioError
from flexride.settings import API_PREFIX
from flexride.store.uploads import ProfileUploadInfo

router = APIRouter(prefix="/profiles", tags=["uploads"])

UploadId = Annotated[str, Path(pattern=r"^[0-9a-f]{64}$",
                               description="Upload id: SHA-256 of the content")]
_FORMATS = [ext[1:] for ext in PROFILE_EXTENSIONS]
Format = Annotated[str, Query(
    pattern="^(" + "|".join(_FORMATS) + ")$", json_schema_extra={"enum": _FORMATS},
    description="File format by its extension: " + ", ".join(_FORMATS))]
Kind = Annotated[Literal["wheel", "rail"] | None, Query(
    description="wheel or rail; implied by prw/whl (wheel) and prr/ban (rail), needed for "
    "txt and csv")]

_PROFILE_BODY = {"requestBody": {"required": True, "description": "A wheel or rail profile "
                 "file as exported by SIMPACK (.prw/.prr), MiniProf (.whl/.ban) or as plain "
                 "text/CSV of y, z in mm (reference: docs/model.md, contact geometry)",
                 "content": {"application/octet-stream": {"schema": {"type": "string",
                                                                    "format": "binary"}}}}}


def _out(info: ProfileUploadInfo) -> dict[str, Any]:
    return {**info.__dict__, "links": {"self": f"{API_PREFIX}/profiles/{info.id}"}}


def _at_query(err: ScenarioError) -> ScenarioError:
    """The error located at the query parameter it names, or at the body."""
    items = [ErrorItem(("query", *i.loc) if i.loc and i.loc[0] in ("kind", "format")
                       else ("body",), i.msg) for i in err.items] or [
        ErrorItem(("body",), str(err))]
    return ScenarioError(str(err), items)


@router.post("", status_code=201, response_model=ProfileUploadOut, dependencies=AUTH,
             summary="Upload a wheel or rail profile", openapi_extra=_PROFILE_BODY,
             responses={401: {"description": "Bearer token missing or wrong"},
                        503: {"description": "Storage unavailable"}})
async def upload_profile(request: Request, response: Response, svc: ServicesDep,
                         format: Format, kind: Kind = None) -> dict[str, Any]:
    """Check a profile file (the body, at most the service's body size limit) with the same
    readers as the CLI and store it by the SHA-256 of its content; the same content gives
    the same id. Refer to it in a scenario as ``"wheel": {"upload": "<id>"}`` (or ``rail``).
    Bad data give 422 naming the line.
    """
    try:
        info = svc.uploads.put_profile(await request.body(), format, kind)
    except ScenarioError as err:
        raise _at_query(err) from None
    response.headers["Location"] = f"{API_PREFIX}/profiles/{info.id}"
    return _out(info)


@router.get("/{upload_id}", response_model=ProfileUploadOut, summary="An uploaded profile")
def get_profile(upload_id: UploadId, svc: ServicesDep, kind: Kind = None) -> dict[str, Any]:
    """Format, kind and points (for drawing) of a stored profile."""
    try:
        return _out(svc.uploads.profile_info(upload_id, kind))
    except KeyError:
        raise NotFound(f"no profile upload {upload_id}") from None
    except ScenarioError as err:
        raise _at_query(err) from None
