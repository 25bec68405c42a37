"""Bodies of the job routes: submission, state, list."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    computed_field,
    field_validator,
)

from flexride.api.schemas.common import (
    _NAME_PATTERN,
    Epoch,
    JobKind,
    JobStatus,
    ScenarioInput,
)
from flexride.settings import API_PREFIX

# -- jobs ------------------------------------------------------------------------------------


class JobCreate(ScenarioInput):
    """A simulation job: a full scenario, or a preset with dotted-path overrides."""

    # Examples are published without null values (FastAPI drops None from the OpenAPI
    # document): a preset's run length is changed by giving its own field (distance_m here),
    # or duration_s in a scenario that starts from the preset (which then drops distance_m).
    # tests/api/test_conformance.py submits every example.
    model_config = ConfigDict(extra="forbid", json_schema_extra={"examples": [
        {"preset": "paper-random-straight-80", "overrides": {"distance_m": 40.0}},
        {"scenario": {"preset": "paper-metro", "speed_kmh": 60, "duration_s": 2.0},
         "name": "metro-60", "reuse": False},
    ]})

    name: str | None = Field(None, pattern=_NAME_PATTERN, description="Job name")
    reuse: bool = Field(
        True, description="Reuse the stored results of an identical scenario (content hash)"
    )



TIMINGS_DOC = ("Wall time of each phase of the run (s): setup_s (assembly, static equilibrium, "
               "stability check), solve_s (time loop), write_s (results file), analyze_s "
               "(comfort and safety); null before the run finished")


class JobOut(BaseModel):
    """State of a job, read from its record (``JobOut.model_validate(job)``)."""

    model_config = ConfigDict(from_attributes=True)

    id: str
    kind: JobKind = Field("simulation", description="simulation, or fe_export (the build of "
                          "an FE mesh and mode-shape export served by GET /fe/{kind})")
    name: str
    status: JobStatus
    progress: float = Field(description="Fraction done (0–1)")
    message: str = Field(description="Last progress message")
    error: str | None = Field(None, description="Why the job failed")
    created_at: Epoch
    started_at: Epoch | None = None
    finished_at: Epoch | None = None
    updated_at: Epoch
    attempts: int = Field(description="Times a worker started the job")
    max_attempts: int
    runner: str
    worker: str | None = None
    cancel_requested: bool
    preset: str | None = None
    speed_kmh: float | None = None
    duration_s: float | None = Field(None, description="Simulated time (s)")
    scenario_hash: str
    reused_from: str | None = Field(None, description="Job whose results were reused")
    study_id: str | None = None
    study_index: int | None = None
    axes: dict[str, Any] = Field(default_factory=dict, description="Study axis values")
    run_meta: dict[str, Any] | None = Field(None, exclude=True)
    result_file: str | None = Field(None, exclude=True)

    @field_validator("axes", mode="before")
    @classmethod
    def _no_axes(cls, value: Any) -> Any:
        return value or {}

    @computed_field(description="Time waiting for a worker (s)")  # type: ignore[prop-decorator]
    @property
    def queue_time_s(self) -> float | None:
        """Seconds from creation to start (or to now while queued)."""
        if self.started_at is not None:
            return max(0.0, (self.started_at - self.created_at).total_seconds())
        if self.status == "queued":
            return max(0.0, (datetime.now(UTC) - self.created_at).total_seconds())
        return None

    @computed_field(description="Time running so far or in all (s)")  # type: ignore[prop-decorator]
    @property
    def run_time_s(self) -> float | None:
        """Seconds from start to finish (or to now while running)."""
        if self.started_at is None:
            return None
        end = self.finished_at or datetime.now(UTC)
        return max(0.0, (end - self.started_at).total_seconds())

    @computed_field(description="Solver loop wall time (s)")  # type: ignore[prop-decorator]
    @property
    def solver_wall_time_s(self) -> float | None:
        """Wall time of the solver loop from the run facts (s)."""
        value = (self.run_meta or {}).get("wall_time_solve_s")
        return None if value is None else float(value)

    @computed_field(description=TIMINGS_DOC)  # type: ignore[prop-decorator]
    @property
    def timings(self) -> dict[str, float | None] | None:
        """The run's ``timings`` from its facts (s), None before it finished."""
        value = (self.run_meta or {}).get("timings")
        return dict(value) if isinstance(value, dict) else None

    @computed_field(description="The job has results to read")  # type: ignore[prop-decorator]
    @property
    def has_results(self) -> bool:
        """Whether the job succeeded with a result file."""
        return self.status == "succeeded" and self.result_file is not None

    @computed_field(description="URLs of the job's resources")  # type: ignore[prop-decorator]
    @property
    def links(self) -> dict[str, str]:
        """URLs of the job's resources."""
        base = f"{API_PREFIX}/jobs/{self.id}"
        return {"self": base, "summary": f"{base}/summary", "channels": f"{base}/channels",
                "series": f"{base}/series", "spectrum": f"{base}/spectrum",
                "download": f"{base}/download"}


class JobSubmitted(JobOut):
    """A job just created (``reused``: finished at once from stored results)."""

    reused: bool = False
    preflight: dict[str, Any] | None = Field(
        None, description="Submission check: stability limit and suggested step"
    )


class JobList(BaseModel):
    """A page of jobs, newest first."""

    items: list[JobOut]
    total: int
    limit: int
    offset: int
