"""Bodies of the study routes: requests, jobs, tables."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Literal, Self, TypeVar

from pydantic import (
    AliasChoices,
    BaseModel,
    ConfigDict,
    Field,
    computed_field,
    field_validator,
    model_validator,
)

from flexride.api.schemas.common import (
    _NAME_PATTERN,
    BodyModelName,
    Epoch,
    JobStatus,
    ScenarioInput,
    _Strict,
)
from flexride.scenario.fidelity import CUTOFF_RULE_LABELS, DEFAULT_CUTOFF_RULE, CutoffRule
from flexride.settings import API_PREFIX
from flexride.study.sections import DEFAULT_SECTION_RULE, SECTION_RULE_LABELS, SectionRule
from flexride.study.seeds import MAX_SERVICE_SEEDS

# -- studies ---------------------------------------------------------------------------------


class ScenarioSource(ScenarioInput):
    """The base scenario of a study: a full scenario or a preset, with overrides."""


class Condition(_Strict):
    """A named line/excitation condition: dotted-path values set together."""

    name: str = Field(pattern=r"^[A-Za-z0-9][A-Za-z0-9_.+-]{0,39}$")
    set: dict[str, Any] = Field(default_factory=dict, max_length=50,
                                description="Dotted path → value")


class ParameterAxis(_Strict):
    """Any scenario parameter varied by its dotted path."""

    path: str = Field(min_length=1, max_length=200, description="e.g. vehicle.carbody.mass")
    values: list[Any] = Field(min_length=1, max_length=100)


_Choice = TypeVar("_Choice", bound=str)


def _choice(default: _Choice, labels: Mapping[_Choice, str], description: str) -> Any:
    """A field of one of the keys of ``labels``, which the schema shows as ``x-enum-labels``
    (the dashboard labels its choices with them).
    """
    return Field(default, description=description,
                 json_schema_extra={"x-enum-labels": {str(k): v for k, v in labels.items()}})


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
        {"preset": "paper-report", "quick": True, "seeds": 1},
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
    seeds: int | None = Field(
        None, ge=1, le=MAX_SERVICE_SEEDS,
        description=f"Irregularity realisations per condition (1–{MAX_SERVICE_SEEDS}): "
        "realisation k sets every random irregularity's seed to its own + k − 1; the tables "
        "give each index as the mean with its 95 % confidence interval (Student t). Jobs "
        "without a random irregularity run once.",
    )
    section: SectionRule = _choice(
        DEFAULT_SECTION_RULE, SECTION_RULE_LABELS, "Stretch each job's indices are evaluated "
        "on: paper (the report's rules: on a curve the circular arc, on straight track from "
        "30 m on, a settlement the whole run), curve (the whole curve with its transitions, "
        "otherwise as paper) or run (the whole run). A section shorter than 6 s of the run "
        "falls back to the whole run; the tables state each index's section.")
    cutoff: CutoffRule = _choice(
        DEFAULT_CUTOFF_RULE, CUTOFF_RULE_LABELS, "Elastic-mode cut-off of flexible bodies: "
        "follow (raise each job's cut-off to at least 1.5 × its highest excitation frequency "
        "V/λ_min, rounded up to 10 Hz: 70 Hz for 0.5 m corrugation at 80 km/h) or as_given "
        "(the scenario's; a job that keeps fewer modes than its excitation drives says so "
        "in its notes)")
    quick: bool | None = Field(
        None, description="paper-report preset only: the shortened study of `flexride paper "
        "report --quick` (2 speeds, 1/4 of every evaluated stretch)")
    overrides: dict[str, Any] = Field(default_factory=dict, max_length=200)
    reuse: bool = True

    @model_validator(mode="after")
    def _base_or_preset(self) -> StudyCreate:
        if self.preset is None and self.base is None:
            raise ValueError("give a study 'preset' or a 'base' scenario")
        return self


class StudyJobOut(BaseModel):
    """A job of a study: its place in the matrix and its state (read from its record)."""

    model_config = ConfigDict(from_attributes=True, populate_by_name=True)

    id: str
    index: int | None = Field(validation_alias=AliasChoices("index", "study_index"))
    name: str
    axes: dict[str, Any]
    status: JobStatus
    progress: float
    speed_kmh: float | None
    error: str | None = None
    reused_from: str | None = None

    @field_validator("axes", mode="before")
    @classmethod
    def _no_axes(cls, value: Any) -> Any:
        return value or {}


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
    """A quantity against speed for one group (other axes but the realisations fixed), point
    and direction. With a ``seed`` axis ``value`` is the mean over the realisations.
    """

    group: dict[str, Any]
    point: str
    direction: str
    quantity: str
    unit: str
    speed_kmh: list[float]
    value: list[float | None] = Field(description="Per speed: mean over the realisations")
    ci95: list[float | None] = Field(
        default_factory=list, description="Per speed: half width of the 95 % confidence "
        "interval of the mean (Student t over the realisations; null for one)")
    n: list[int] = Field(default_factory=list, description="Per speed: realisations averaged")
    sections: list[str] = Field(default_factory=list, description="Per speed: the section "
                                "the values are evaluated on (m along the line)")
    job_ids: list[str] = Field(description="Per speed: the job of the first realisation")
    jobs: list[list[str]] = Field(default_factory=list,
                                  description="Per speed: every job averaged")
    job_values: dict[str, float | None] = Field(default_factory=dict,
                                                description="Each job's own value")
    fit: LinearFitOut | None = Field(None, description="Least-squares line through the means")


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
    rigid_ci95: float | None = Field(None, description="95 % CI half width of rigid")
    flexible_ci95: float | None = Field(None, description="95 % CI half width of flexible")
    difference_ci95: float | None = Field(None, description="95 % CI half width of difference")
    relative_ci95: float | None = Field(None, description="95 % CI half width of relative")
    n: int = Field(1, description="Realisations (pairs on the same track) averaged")
    section: str | None = Field(None, description="The section the values are evaluated on")
    rigid_job: str = Field(description="Rigid job of the first realisation")
    flexible_job: str = Field(description="Flexible job of the first realisation")


class ConvergenceEstimateOut(BaseModel):
    """A quantity's discretisation estimate from its finest meshes (Celik et al. 2008; two
    meshes: Roache 1994 at the elements' order).
    """

    sizes_m: list[float] = Field(description="Element sizes used, fine to coarse (m)")
    values: list[float] = Field(description="The quantity on them (the row's unit)")
    order: float | None = Field(description="Observed order of convergence (-), or the "
                                "assumed one (order_assumed)")
    order_assumed: bool = Field(description="Two meshes only: the order is the elements' 2")
    extrapolated: float | None = Field(description="Richardson-extrapolated value")
    gci_fine: float | None = Field(description="Grid convergence index of the finest mesh (-, "
                                   "relative)")
    error_fine: float | None = Field(description="Finest value against the extrapolated (-)")
    oscillatory: bool = Field(description="The differences change sign: the spread, not an "
                              "asymptote, bounds the error")
    reliable: bool = Field(description="The extrapolation can be used: two meshes, or three "
                           "converging monotonically at an order of at least 0.5")
    converged: float | None = Field(description="Best estimate of the converged value: the "
                                    "extrapolated one where reliable, else the finest mesh's")
    band: float | None = Field(description="Its relative uncertainty (-): the GCI where "
                               "reliable, else the spread of the fine meshes")
    deviation: list[list[float | None]] = Field(
        description="[element size (m), relative distance from the converged estimate (-)] "
        "for every mesh, fine to coarse")


class MeshConvergenceRow(BaseModel):
    """One quantity against element size."""

    key: str = Field(description="e.g. secondary.1L.z.rms_dynamic, frequency.1, PC.z.sperling")
    group: Literal["force", "frequency", "comfort"]
    label: str
    unit: str
    values: list[float | None] = Field(description="Per element size (sizes_m): the mean "
                                       "over the realisations")
    estimate: ConvergenceEstimateOut | None
    at_reference: float | None = Field(description="The reference mesh's relative distance "
                                       "from the converged estimate (-)")
    negligible: str | None = Field(None, description="Why the row is below the resolution and "
                                   "not judged (null: judged)")


class MeshClaimOut(BaseModel):
    """The paper's Fig. 4 claim judged on one table's rows above the resolution."""

    grows: list[int] = Field(description="[force rows growing with element size from the "
                             "reference size on, force rows judged]")
    grows_holds: bool | None = Field(description="Every judged force row grows (null: none "
                                     "judged)")
    coarsest_over_reference: float | None = Field(description="Largest ratio of the coarsest "
                                                  "mesh's force to the reference's (-)")
    reference_within: dict[str, float | None] = Field(
        description="Largest |distance| of the reference mesh from the converged estimates "
        "(-): force rows and all judged rows")
    adequate: bool | None = Field(description="The reference mesh within 5 % for every judged "
                                  "row (null: not judged)")
    negligible: list[str] = Field(default_factory=list, description="Keys of the rows below "
                                  "the resolution")
    text: str


class MeshConvergenceTable(BaseModel):
    """A study's quantities against one body's element size, for one group of the other axes
    (the paper's element-size pre-calculation, Fig. 4).
    """

    body: Literal["carbody", "frames"]
    axis: str = Field(description="The element-size axis")
    group: dict[str, Any] = Field(description="The other axes' values")
    sizes_m: list[float] = Field(description="Element sizes, fine to coarse (m)")
    realisations: list[int] = Field(description="Jobs averaged per size")
    reference_size_m: float = Field(description="The size judged (the paper's 0.2 m)")
    rows: list[MeshConvergenceRow]
    claim: MeshClaimOut


class StudyTables(BaseModel):
    """Study results ready to plot."""

    sperling_vs_speed: list[SpeedSeries] = Field(default_factory=list)
    peak_vs_speed: list[SpeedSeries] = Field(default_factory=list)
    flexible_vs_rigid: list[FlexRigidRow] = Field(default_factory=list)
    mesh_convergence: list[MeshConvergenceTable] = Field(
        default_factory=list, description="Quantities against element size, for a study with "
        "an element-size axis (bodies.carbody.element_size_m or bodies.frames.element_size_m)")
    notes: list[str] = Field(default_factory=list)


class StudyOut(BaseModel):
    """State of a study: its record (``StudyOut.model_validate(study)``) and the state of its
    jobs (:meth:`with_jobs_state`).
    """

    model_config = ConfigDict(from_attributes=True)

    id: str
    name: str
    description: str
    preset: str | None
    created_at: Epoch
    status: Literal["queued", "running", "succeeded", "failed", "cancelled", "partial",
                    "empty"] = "empty"
    progress: float = 0.0
    n_jobs: int
    counts: dict[str, int] = Field(default_factory=dict)
    axes: list[dict[str, Any]]

    @field_validator("axes", mode="before")
    @classmethod
    def _no_axes(cls, value: Any) -> Any:
        return value or []

    @computed_field(description="URLs of the study's resources")  # type: ignore[prop-decorator]
    @property
    def links(self) -> dict[str, str]:
        """URLs of the study and of its jobs."""
        return {"self": f"{API_PREFIX}/studies/{self.id}",
                "jobs": f"{API_PREFIX}/jobs?study_id={self.id}"}

    def with_jobs_state(self, status: str, progress: float, counts: dict[str, int]) -> Self:
        """The same study with the state of its jobs (status word, fraction done, counts)."""
        return self.model_copy(update={"status": status, "progress": progress,
                                       "counts": counts})


class StudyReportOut(BaseModel):
    """The report of a paper report study (preset ``paper-report``)."""

    state: Literal["waiting", "queued", "running", "ready", "failed"] = Field(
        description="waiting: runs not finished; queued/running: the report is being built; "
        "ready: GET links.html and links.summary; failed: see error")
    message: str = ""
    progress: float = Field(0.0, description="Of the report's build (0–1)")
    job_id: str | None = Field(None, description="The job (kind paper_report) that builds it")
    error: str | None = None
    counts: dict[str, int] = Field(default_factory=dict,
                                   description="Claims per verdict (when ready)")
    links: dict[str, str] = Field(default_factory=dict)


class StudyDetail(StudyOut):
    """A study with its jobs and its aggregated tables (and, for a paper report study, the
    state of its report).
    """

    jobs: list[StudyJobOut] = Field(default_factory=list)
    tables: StudyTables = Field(default_factory=StudyTables)
    report: StudyReportOut | None = None


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
