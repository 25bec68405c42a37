"""Routes of studies: submit a job matrix, detail with tables, list, cancel, delete, presets."""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import APIRouter, Path, Query, Response
from fastapi.responses import FileResponse

from flexride.api.deps import AUTH, ServicesDep
from flexride.api.errors import NotFound
from flexride.api.params import StudyId
from flexride.api.schemas import StudyCreate, StudyDetail, StudyList, StudyPresetOut
from flexride.api.services import studies as svc_studies

router = APIRouter(tags=["studies"])

_AUTH_DOC: dict[int | str, dict[str, Any]] = {
    401: {"description": "Bearer token missing or wrong"}
}


@router.post("/studies", status_code=201, response_model=StudyDetail, dependencies=AUTH,
             summary="Submit a study", responses=_AUTH_DOC)
def submit_study(body: StudyCreate, svc: ServicesDep) -> StudyDetail:
    """Create the job matrix of a base scenario and its axes (conditions × speeds × body
    models × parameters) and queue every job. ``{"preset": "paper-table3"}`` runs the
    paper's 16 conditions.
    """
    return svc_studies.create_study(svc, body)


@router.get("/studies", response_model=StudyList, summary="List studies")
def list_studies(
    svc: ServicesDep,
    limit: Annotated[int, Query(ge=1, le=500)] = 50,
    offset: Annotated[int, Query(ge=0, le=1_000_000_000)] = 0,
) -> dict[str, Any]:
    """Studies newest first with their job counts."""
    return svc_studies.list_studies(svc, limit, offset)


@router.get("/studies/{study_id}", response_model=StudyDetail, summary="Study detail")
def get_study(study_id: StudyId, svc: ServicesDep) -> StudyDetail:
    """Jobs of the study and its tables: Sperling vs speed per condition and point, peak
    acceleration vs speed with linear fit and R², flexible vs rigid differences.
    """
    return svc_studies.study_detail(svc, study_id)


#: The report is self-contained (Plotly and its data inline): it may run its own inline
#: scripts and nothing else, and may not load or send anything.
REPORT_CSP = ("default-src 'none'; script-src 'unsafe-inline' 'unsafe-eval'; "
              "style-src 'unsafe-inline'; img-src data: blob:; font-src data:; "
              "connect-src 'none'; base-uri 'none'; form-action 'none'")

_REPORT_DOC: dict[int | str, dict[str, Any]] = {
    404: {"description": "No such study, or not a paper report study"},
    409: {"description": "The report is not ready yet (runs or build unfinished, or failed)"},
}


@router.get("/studies/{study_id}/report", response_class=FileResponse,
            summary="Report of a paper report study", responses={
                200: {"content": {"text/html": {}}, "description": "index.html"},
                **_REPORT_DOC})
def study_report(study_id: StudyId, svc: ServicesDep) -> FileResponse:
    """The report (``index.html``, self-contained) of a study made with the
    ``paper-report`` preset, once every run has finished and the report is built.
    """
    path = svc_studies.report_file(svc, study_id, "index.html")
    return FileResponse(path, media_type="text/html; charset=utf-8",
                        headers={"X-Content-Type-Options": "nosniff",
                                 "Content-Security-Policy": REPORT_CSP})


@router.get("/studies/{study_id}/report/summary", summary="Claims of a paper report study",
            responses=_REPORT_DOC)
def study_report_summary(study_id: StudyId, svc: ServicesDep) -> Any:
    """``summary.json`` of the report: one claim per table entry and stated finding,
    ``{"id", "source", "paper", "flexride", "verdict", "note", ...}`` (docs/paper.md).
    """
    return svc_studies.report_summary(svc, study_id)


@router.post("/studies/{study_id}/cancel", response_model=StudyDetail, dependencies=AUTH,
             summary="Cancel a study", responses=_AUTH_DOC)
def cancel_study(study_id: StudyId, svc: ServicesDep) -> StudyDetail:
    """Cancel every queued or running job of the study."""
    return svc_studies.cancel_study(svc, study_id)


@router.delete("/studies/{study_id}", status_code=204, dependencies=AUTH,
               summary="Delete a study", responses=_AUTH_DOC)
def delete_study(study_id: StudyId, svc: ServicesDep) -> Response:
    """Delete the study, its jobs and their result files."""
    svc_studies.delete_study(svc, study_id)
    return Response(status_code=204)


@router.get("/study-presets", response_model=list[StudyPresetOut], summary="Study presets")
def study_presets() -> list[dict[str, Any]]:
    """Built-in studies (the paper's Table 3 and Table 2) and the requests they stand for."""
    return svc_studies.study_presets()


@router.get("/study-presets/{name}", response_model=StudyPresetOut, summary="A study preset")
def study_preset(name: Annotated[str, Path(max_length=80)]) -> dict[str, Any]:
    """One built-in study."""
    for p in svc_studies.study_presets():
        if p["name"] == name:
            return p
    raise NotFound(f"no study preset {name!r}")
