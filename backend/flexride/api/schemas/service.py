"""Bodies of presets, health, version and uploads."""

from __future__ import annotations

from datetime import datetime
from typing import Any, Literal

from pydantic import (
    BaseModel,
    Field,
)

# -- presets, health, version -----------------------------------------------------------------


class PresetOut(BaseModel):
    """A named scenario."""

    name: str
    description: str
    speed_kmh: float | None = None


class ComponentHealth(BaseModel):
    """Health of one component."""

    ok: bool
    detail: str = ""
    data: dict[str, Any] = Field(default_factory=dict)


class WorkerOut(BaseModel):
    """A worker process seen recently (operators only)."""

    name: str
    kind: str
    hostname: str
    pid: int
    started_at: datetime
    last_seen: datetime
    alive: bool = Field(description="Reported within three heartbeat intervals")
    state: Literal["alive", "gone"] = Field(
        description="alive, or gone: it stopped reporting (stopped, killed or cut off)")
    current_job: str | None = Field(
        description="The job the job records say this worker runs (null when none)")


class SolverHealth(BaseModel):
    """Whether the solver's compiled kernels are ready (jobs run at full speed, submissions are
    checked for time-step stability at once) or still being compiled.
    """

    state: Literal["ready", "compiling"]
    estimate_s: float | None = Field(
        None, description="Seconds until the compilation is expected to end (null when "
        "ready) (s)")


ComponentState = Literal["ok", "degraded", "down"]


class HealthOut(BaseModel):
    """Health of the service. Anyone sees ``status``, the state of each component and the
    solver's compile state (``view: public``); with the API token (or on a service without
    one) the details too (``view: operator``): where the database and broker are, the
    workers with their hosts, processes and jobs, the job counts.
    """

    status: Literal["ok", "degraded", "down"]
    view: Literal["public", "operator"] = Field(
        description="public: states only (send the API token for the details); operator")
    components: dict[str, ComponentState] = Field(
        description="State of each component: api, database, storage, workers and (Celery "
        "runner) broker")
    solver: SolverHealth | None = Field(
        None, description="Compilation state of the solver's kernels")
    version: str | None = Field(None, description="Operators only")
    runner: str | None = Field(None, description="Operators only")
    api: ComponentHealth | None = Field(None, description="Operators only")
    database: ComponentHealth | None = Field(
        None, description="Operators only: backend, location (host, port, database; no "
        "password or path), latency")
    storage: ComponentHealth | None = Field(
        None, description="Operators only: whether the results and upload directories and "
        "the database take writes (status degraded when not)")
    broker: ComponentHealth | None = Field(None, description="Operators only (Celery runner)")
    workers: list[WorkerOut] | None = Field(None, description="Operators only")
    jobs: dict[str, int] | None = Field(None, description="Operators only: jobs per status")


class VersionOut(BaseModel):
    """Versions of flexride and the main libraries."""

    flexride: str
    api: str
    python: str
    libraries: dict[str, str]
    runner: str


class ProfileUploadOut(BaseModel):
    """A stored wheel or rail profile (refer to it as ``{"upload": id}`` in a scenario's
    ``contact.wheel`` or ``contact.rail``).
    """

    id: str = Field(description="SHA-256 of the content (64 hexadecimal digits)")
    bytes: int = Field(description="Size of the content (bytes)")
    format: str = Field(description="File format by extension: prw, prr, whl, ban, txt, csv")
    kind: Literal["wheel", "rail"] = Field(description="What the profile describes")
    points: int = Field(description="Points of the profile")
    y_mm: list[float] = Field(description="Lateral coordinate, toward the field side, of at "
                              "most 2000 points for drawing (mm)")
    z_mm: list[float] = Field(description="Vertical coordinate, up, of the same points (mm)")
    links: dict[str, str] = Field(description="URLs of the upload's resources")


class UploadOut(BaseModel):
    """A stored upload of measured irregularities (refer to it as
    ``{"kind": "measured", "upload": id}`` in a scenario).
    """

    id: str = Field(description="SHA-256 of the content (64 hexadecimal digits)")
    bytes: int = Field(description="Size of the content (bytes)")
    rows: int = Field(description="Measurement points")
    columns: list[str] = Field(description="Irregularity columns found (m)")
    distance_start_m: float = Field(description="Start of the measured stretch (m)")
    distance_end_m: float = Field(description="End of the measured stretch (m)")
    median_spacing_m: float = Field(description="Median distance between points (m)")
    links: dict[str, str] = Field(description="URLs of the upload's resources")
