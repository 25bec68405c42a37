"""Request and response bodies of the API (pydantic), as documented in the OpenAPI schema."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Annotated, Any, Literal

from pydantic import (
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    computed_field,
    field_validator,
    model_validator,
)

from flexride.settings import API_PREFIX

JobStatus = Literal["queued", "running", "succeeded", "failed", "cancelled"]
JobKind = Literal["simulation", "fe_export"]
BodyModelName = Literal["rigid", "flexible"]

_NAME_PATTERN = r"^[A-Za-z0-9][A-Za-z0-9 _.+-]{0,79}$"


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")


# -- errors ----------------------------------------------------------------------------------


class ErrorItem(BaseModel):
    """One problem with a request: where (``loc``), what (``msg``) and its kind."""

    loc: list[str | int] = Field(default_factory=list, description="Path of the field")
    msg: str
    type: str
    ctx: dict[str, Any] | None = None


class ErrorResponse(BaseModel):
    """Error body: ``detail`` is a list of problems (422) or one message (other codes)."""

    detail: list[ErrorItem] | str
    message: str | None = Field(None, description="The whole error as one line")
    dt_suggested: float | None = Field(
        None, description="For an unstable time step: a solver.dt that works (s)"
    )


# -- jobs ------------------------------------------------------------------------------------


class JobCreate(_Strict):
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

    scenario: dict[str, Any] | None = Field(
        None,
        description="Full scenario, see GET /api/v1/schemas/scenario; may start from "
        "'preset: NAME' and give only what differs",
    )
    preset: str | None = Field(None, max_length=80, description="Preset name (GET /presets)")
    overrides: dict[str, Any] = Field(
        default_factory=dict,
        max_length=200,
        description="Dotted path → value, applied last, e.g. {\"speed_kmh\": 60, "
        "\"solver.dt\": 5e-5}",
    )
    name: str | None = Field(None, pattern=_NAME_PATTERN, description="Job name")
    reuse: bool = Field(
        True, description="Reuse the stored results of an identical scenario (content hash)"
    )

    @model_validator(mode="after")
    def _one_source(self) -> JobCreate:
        if (self.scenario is None) == (self.preset is None):
            raise ValueError("give either 'scenario' or 'preset' (not both)")
        return self


def _utc(t: Any) -> Any:
    """Epoch seconds (the store's times) as an aware UTC datetime; other values unchanged."""
    if isinstance(t, int | float) and not isinstance(t, bool):
        return datetime.fromtimestamp(float(t), tz=UTC)
    return t


Epoch = Annotated[datetime, BeforeValidator(_utc)]
"""A time stored as UTC epoch seconds, shown as ISO 8601."""


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


# -- results ---------------------------------------------------------------------------------


class ChannelInfo(BaseModel):
    """A recorded channel ``<body>.<point>.<quantity>.<direction>``."""

    name: str
    unit: str
    body: str | None = None
    point: str | None = None
    quantity: str | None = None
    direction: str | None = None
    position: list[float] | None = Field(
        None, description="x, y, z of the channel's recorded point (m, see point_frame); "
        "null for channels that are not at a recorded point (wheel forces, body coordinates)")


class PointInfo(BaseModel):
    """A recorded point: its body, name, description, position (m, see ``point_frame``) and
    whether it is on the car-body floor.
    """

    body: str = Field(description="Body the point is on: carbody, frame1, wheelset3...")
    name: str = Field(description="Point name: PR, PC, F3_2 (floor grid), centre...")
    description: str = Field("", description="What the point is, for people")
    x: float = Field(description="Longitudinal position from the car-body centre, forward (m)")
    y: float = Field(description="Lateral position, left positive (m)")
    z: float = Field(description="Height above top of rail (m)")
    on_floor: bool | None = Field(None, description="On the car-body floor (ISO 2631 floor "
                                  "measurement); null off the car body")
    kind: str = Field("", description="paper (one of the paper's points), user, grid (floor "
                      "grid of comfort maps) or body (centre of a frame or wheelset); empty in "
                      "old result files")


class PaperPointOut(BaseModel):
    """One of the paper's car-body measurement points and where it sits."""

    name: str
    description: str
    along: Literal["front", "centre", "rear"] = Field(
        description="Above the front bogie centre, at the body centre or above the rear bogie")
    across: Literal["centre", "left", "right"] = Field(
        description="On the centre line or above the left/right air spring")
    level: Literal["floor", "roof"]


class ChannelList(BaseModel):
    """The channels of a job's results, its sampling and its recorded points."""

    job_id: str
    sample_rate_hz: float
    n_samples: int
    t_start_s: float
    t_end_s: float
    channels: list[ChannelInfo]
    points: list[PointInfo] = Field(
        default_factory=list, description="Recorded points in channel order (m)")
    point_frame: str = Field(description="Coordinates of the point positions")


class SeriesChannel(BaseModel):
    """One channel, decimated: sample times (s) and values."""

    name: str
    unit: str
    time: list[float]
    values: list[float | None]
    distance: list[float] | None = Field(None, description="Distance (m), if asked for")


class SeriesOut(BaseModel):
    """Decimated time series of chosen channels."""

    job_id: str
    method: Literal["minmax", "lttb", "none"]
    max_points: int
    n_samples: int = Field(description="Samples in the requested time range")
    decimated: bool
    sample_rate_hz: float
    channels: list[SeriesChannel]


class PeakOut(BaseModel):
    """A spectral peak."""

    frequency: float
    amplitude: float | None
    value: float | None
    prominence: float | None


class SpectrumChannel(BaseModel):
    """Spectrum values of one channel (on the shared frequency axis)."""

    name: str
    unit: str
    values: list[float | None]
    peaks: list[PeakOut] = Field(default_factory=list)


class SpectrumOut(BaseModel):
    """Amplitude spectrum or PSD of chosen channels."""

    job_id: str
    kind: Literal["amplitude", "psd"]
    frequencies: list[float]
    resolution_hz: float
    window: str
    n_averages: int
    scaling: str
    dynamic: bool = Field(description="Quasi-static part (< 0.3 Hz) removed first")
    decimated: bool
    channels: list[SpectrumChannel]


class SpectrogramOut(BaseModel):
    """Short-time spectrum of one channel: ``values[i_frequency][i_time]``."""

    job_id: str
    channel: str
    unit: str
    times: list[float]
    frequencies: list[float]
    values: list[list[float | None]]
    scaling: str
    window_s: float
    hop_s: float
    resolution_hz: float
    method: str
    dynamic: bool


class SperlingBand(BaseModel):
    """Contribution of a frequency band to the Sperling index."""

    f_low_hz: float
    f_high_hz: float
    w: float | None = Field(description="(Σ W_i^10)^(1/10) over the band's lines")


class SperlingChannel(BaseModel):
    """Sperling index of one channel and its breakdown over frequency."""

    name: str
    direction: Literal["vertical", "lateral"]
    value: float | None = Field(description="Spectral form (default), as in the summary")
    grade: str
    filter_value: float | None = Field(None, description="Filter form, for comparison")
    frequencies: list[float] = Field(description="Spectral lines used (Hz)")
    line_amplitudes: list[float | None] = Field(description="Peak amplitude per line (m/s²)")
    line_w: list[float | None] = Field(description="W_i per line")
    bands: list[SperlingBand]
    segment_values: list[float | None]
    method: str


class SperlingOut(BaseModel):
    """Sperling breakdown of chosen channels."""

    job_id: str
    dynamic: bool
    channels: list[SperlingChannel]


class CorrelationChannel(BaseModel):
    """Cross-correlation of the reference with one channel."""

    name: str
    lag_at_max_s: float | None
    lag_at_max_interpolated_s: float | None
    value_at_max: float | None
    normalised_at_max: float | None
    local_maxima: list[dict[str, float | None]]
    lags_s: list[float]
    normalised: list[float | None]


class CorrelationOut(BaseModel):
    """Cross-correlations; a maximum at lag > 0 means the channel lags the reference."""

    job_id: str
    reference: str
    max_lag_s: float
    convention: str
    dynamic: bool
    channels: list[CorrelationChannel]


# -- studies ---------------------------------------------------------------------------------


class ScenarioSource(_Strict):
    """The base scenario of a study: a full scenario or a preset, with overrides."""

    scenario: dict[str, Any] | None = None
    preset: str | None = Field(None, max_length=80)
    overrides: dict[str, Any] = Field(default_factory=dict, max_length=200)

    @model_validator(mode="after")
    def _one_source(self) -> ScenarioSource:
        if (self.scenario is None) == (self.preset is None):
            raise ValueError("give either 'scenario' or 'preset' (not both)")
        return self


class Condition(_Strict):
    """A named line/excitation condition: dotted-path values set together."""

    name: str = Field(pattern=r"^[A-Za-z0-9][A-Za-z0-9_.+-]{0,39}$")
    set: dict[str, Any] = Field(default_factory=dict, max_length=50,
                                description="Dotted path → value")


class ParameterAxis(_Strict):
    """Any scenario parameter varied by its dotted path."""

    path: str = Field(min_length=1, max_length=200, description="e.g. vehicle.carbody.mass")
    values: list[Any] = Field(min_length=1, max_length=100)


class StudyCreate(_Strict):
    """A study: a base scenario and the axes to vary; the job matrix is their product.

    Give ``preset`` (a study preset, GET /study-presets) or ``base``; axes given here replace
    the preset's. ``overrides`` apply to every job, last (e.g. a shorter ``duration_s``).
    """

    # No null values in examples (see JobCreate); every example is submitted by
    # tests/api/test_conformance.py.
    model_config = ConfigDict(extra="forbid", json_schema_extra={"examples": [
        {"name": "speeds",
         "base": {"scenario": {"preset": "paper-random-straight-80", "duration_s": 6.0}},
         "speeds_kmh": [60, 80]},
        {"preset": "paper-table3", "overrides": {"distance_m": 150.0}},
    ]})

    name: str | None = Field(None, pattern=_NAME_PATTERN)
    description: str = Field("", max_length=4000)
    preset: str | None = Field(None, max_length=80, description="Study preset name")
    base: ScenarioSource | None = None
    speeds_kmh: list[float] | None = Field(None, min_length=1, max_length=100)
    conditions: list[str | Condition] | None = Field(
        None, min_length=1, max_length=100,
        description="Paper conditions by name (random-straight, random-curve, corrugation, "
        "settlement) or custom conditions",
    )
    body_models: list[BodyModelName] | None = Field(
        None, min_length=1, max_length=2,
        description="Car body and frames rigid and/or flexible",
    )
    parameters: list[ParameterAxis] | None = Field(None, max_length=10)
    overrides: dict[str, Any] = Field(default_factory=dict, max_length=200)
    reuse: bool = True

    @model_validator(mode="after")
    def _base_or_preset(self) -> StudyCreate:
        if self.preset is None and self.base is None:
            raise ValueError("give a study 'preset' or a 'base' scenario")
        return self


class StudyJobOut(BaseModel):
    """A job of a study: its place in the matrix and its state."""

    id: str
    index: int | None
    name: str
    axes: dict[str, Any]
    status: JobStatus
    progress: float
    speed_kmh: float | None
    error: str | None = None
    reused_from: str | None = None


class LinearFitOut(BaseModel):
    """Least-squares line y = slope·x + intercept with R²."""

    slope: float | None
    intercept: float | None
    r_squared: float | None
    n: int
    stderr_slope: float | None = None
    stderr_intercept: float | None = None
    x_unit: str = "km/h"
    y_unit: str = ""


class SpeedSeries(BaseModel):
    """A quantity against speed for one group (other axes fixed), point and direction."""

    group: dict[str, Any]
    point: str
    direction: str
    quantity: str
    unit: str
    speed_kmh: list[float]
    value: list[float | None]
    job_ids: list[str]
    fit: LinearFitOut | None = None


class FlexRigidRow(BaseModel):
    """Flexible against rigid model for one case, point, direction and quantity."""

    group: dict[str, Any]
    speed_kmh: float | None
    point: str
    direction: str
    quantity: str
    rigid: float | None
    flexible: float | None
    difference: float | None = Field(description="flexible − rigid")
    relative: float | None = Field(description="(flexible − rigid) / rigid")
    rigid_job: str
    flexible_job: str


class StudyTables(BaseModel):
    """Study results ready to plot."""

    sperling_vs_speed: list[SpeedSeries] = Field(default_factory=list)
    peak_vs_speed: list[SpeedSeries] = Field(default_factory=list)
    flexible_vs_rigid: list[FlexRigidRow] = Field(default_factory=list)
    notes: list[str] = Field(default_factory=list)


class StudyOut(BaseModel):
    """State of a study."""

    id: str
    name: str
    description: str
    preset: str | None
    created_at: datetime
    status: Literal["queued", "running", "succeeded", "failed", "cancelled", "partial", "empty"]
    progress: float
    n_jobs: int
    counts: dict[str, int]
    axes: list[dict[str, Any]]
    links: dict[str, str] = Field(default_factory=dict)


class StudyDetail(StudyOut):
    """A study with its jobs and its aggregated tables."""

    jobs: list[StudyJobOut]
    tables: StudyTables


class StudyList(BaseModel):
    """A page of studies, newest first."""

    items: list[StudyOut]
    total: int
    limit: int
    offset: int


class StudyPresetOut(BaseModel):
    """A built-in study and the request it stands for."""

    name: str
    description: str
    request: dict[str, Any]
    n_jobs: int


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
    """A worker process seen recently."""

    name: str
    kind: str
    hostname: str
    pid: int
    started_at: datetime
    last_seen: datetime
    alive: bool
    current_job: str | None


class HealthOut(BaseModel):
    """Health of the API, the database, the broker and the workers."""

    status: Literal["ok", "degraded", "down"]
    version: str
    runner: str
    api: ComponentHealth
    database: ComponentHealth
    storage: ComponentHealth | None = Field(
        None, description="Whether the results and upload directories and the database take "
        "writes (status degraded when not)")
    broker: ComponentHealth | None = None
    workers: list[WorkerOut]
    jobs: dict[str, int]


class VersionOut(BaseModel):
    """Versions of flexride and the main libraries."""

    flexride: str
    api: str
    python: str
    libraries: dict[str, str]
    runner: str


# -- FE meshes and mode shapes ---------------------------------------------------------------


class FEMode(BaseModel):
    """One elastic mode shape of an FE export."""

    index: int = Field(description="Mode number (1 = lowest elastic mode)")
    frequency_hz: float = Field(description="Natural frequency (Hz)")
    classification: str = Field(description="Kind of mode (bending, torsion...) or empty")
    scale_m: float = Field(description="Largest nodal translation of the mass-normalised "
                           "shape (m); the displacements are divided by it")
    displacements: list[list[float]] = Field(
        description="Per node [dx, dy, dz], scaled to a largest translation of 1")


class FEModelInfo(BaseModel):
    """What an FE export was built from."""

    kind: Literal["carbody", "frame"]
    reduction: str
    cutoff_hz: float = Field(description="Highest elastic mode frequency kept (Hz)")
    element_size_m: float = Field(description="Car-body shell element size (m)")
    max_modes: int = Field(description="Mode shapes exported at most")
    key: str = Field(description="Content key of the export")
    n_nodes: int
    n_elastic_modes: int = Field(description="Elastic modes retained below the cut-off")
    frequencies_hz: list[float] = Field(description="Frequencies of all retained modes (Hz)")
    from_cache: bool = Field(description="The reduced body came from the FE cache")
    build_seconds: float = Field(description="Time to build or load the body (s)")


class FEExport(BaseModel):
    """FE mesh and mode shapes (the JSON of ``flexride fe export``, plus ``model``)."""

    units: dict[str, str]
    nodes: list[list[float]] = Field(description="Node coordinates [x, y, z] (m): x from the "
                                     "body centre forward, y left, z above top of rail")
    quads: list[list[int]] = Field(description="Shell elements (four node indices)")
    beams: list[list[int]] = Field(description="Beam elements (two node indices)")
    named_nodes: dict[str, int] = Field(description="Attachment and output nodes by name")
    regions: dict[str, Any] | None = Field(None, description="Region names and each node's")
    modes: list[FEMode]
    model: FEModelInfo


class FEBuildStatus(BaseModel):
    """An FE export that is not ready yet (202)."""

    status: Literal["queued", "building"] = Field(
        description="queued: the build job waits for a worker; building: it runs")
    key: str = Field(description="Content key of the export")
    parameters: dict[str, Any] = Field(description="kind, reduction, cutoff_hz, "
                                       "element_size_m, max_modes")
    job_id: str | None = Field(None, description="The build job (kind fe_export): GET "
                               "/jobs/{id} follows it, POST /jobs/{id}/cancel cancels it")
    progress: float = Field(0.0, description="Fraction of the build done (0–1)")
    elapsed_s: float = Field(description="Seconds since the build was requested")
    retry_after_s: int = Field(description="Ask again after this many seconds "
                               "(also the Retry-After header)")
    message: str


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
