"""Routes of uploaded data: measured track irregularities as CSV, stored by content hash.

A scenario refers to an upload by its id (``{"kind": "measured", "upload": "<id>"}``); over the
API a measured irregularity never names a server file.
"""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import APIRouter, Path, Query, Request, Response

from flexride.api.deps import AUTH, ServicesDep
from flexride.api.errors import NotFound
from flexride.api.schemas import UploadOut
from flexride.errors import ErrorItem, ScenarioError
from flexride.settings import API_PREFIX
from flexride.store.uploads import UploadInfo

router = APIRouter(prefix="/irregularities", tags=["uploads"])

UploadId = Annotated[str, Path(pattern=r"^[0-9a-f]{64}$",
                               description="Upload id: SHA-256 of the content")]
DistanceColumn = Annotated[str, Query(min_length=1, max_length=64,
                                      description="Name of the distance column (m)")]

_CSV_BODY = {"requestBody": {"required": True, "description": "Measured irregularities, CSV "
             "(UTF-8): a header row with the distance column and any of vertical, alignment, "
             "cross_level, gauge, z_left, z_right, y_left, y_right (m)",
             "content": {"text/csv": {"schema": {"type": "string"},
                                      "example": "distance_m,vertical\n0,0\n0.25,0.0004\n"
                                      "0.5,0.0007\n"}}}}


def _out(info: UploadInfo) -> dict[str, Any]:
    base = f"{API_PREFIX}/irregularities/{info.id}"
    return {**info.__dict__, "links": {"self": base, "csv": f"{base}/csv"}}


@router.post("", status_code=201, response_model=UploadOut, dependencies=AUTH,
             summary="Upload measured irregularities", openapi_extra=_CSV_BODY,
             responses={401: {"description": "Bearer token missing or wrong"},
                        503: {"description": "Storage unavailable"}})
async def upload_irregularities(request: Request, response: Response, svc: ServicesDep,
                                distance_column: DistanceColumn = "distance_m"
                                ) -> dict[str, Any]:
    """Check a CSV of measured irregularities (the body, at most the service's body size
    limit) and store it by the SHA-256 of its content; the same content gives the same id.
    Refer to it in a scenario as ``{"kind": "measured", "upload": "<id>"}``. Bad data give
    422 naming line and column.
    """
    try:
        info = svc.uploads.put(await request.body(), distance_column)
    except ScenarioError as err:
        raise ScenarioError(str(err), [ErrorItem(("body",), str(err))]) from None
    response.headers["Location"] = f"{API_PREFIX}/irregularities/{info.id}"
    return _out(info)


@router.get("/{upload_id}", response_model=UploadOut, summary="An upload's facts")
def get_upload(upload_id: UploadId, svc: ServicesDep,
               distance_column: DistanceColumn = "distance_m") -> dict[str, Any]:
    """Rows, columns and measured stretch of a stored upload."""
    try:
        return _out(svc.uploads.info(upload_id, distance_column))
    except KeyError:
        raise NotFound(f"no upload {upload_id}") from None


@router.get("/{upload_id}/csv", summary="An upload's content",
            response_class=Response,
            responses={200: {"content": {"text/csv": {"schema": {"type": "string"}}}}})
def get_upload_csv(upload_id: UploadId, svc: ServicesDep) -> Response:
    """The stored CSV as it was uploaded."""
    try:
        data = svc.uploads.read(upload_id)
    except KeyError:
        raise NotFound(f"no upload {upload_id}") from None
    return Response(data, media_type="text/csv",
                    headers={"Cache-Control": "public, max-age=31536000, immutable"})
