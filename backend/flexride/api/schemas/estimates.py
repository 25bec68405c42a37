"""Bodies of ``POST /estimates``: the frequency-domain comfort estimate of a scenario (or of a
sweep of one of its fields) and its answer.
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationInfo, field_validator

from flexride.api.schemas.common import ScenarioInput, _Strict
from flexride.frequency.model import DEFAULT_LINEARISATION, LinearisationMethod
from flexride.vehicle.topology import PAPER_POINT_NAMES

MAX_SWEEP_VALUES = 100
"""Most values of one sweep."""
MAX_POINTS = 200
"""Most points asked for in one estimate."""
MAX_SPECTRA_POINTS = 24
"""Most points of an estimate that returns its spectra (two PSDs of about 10³ values each)."""

TrackModelName = Literal["condensed", "modal", "rigid"]


class SweepSpec(_Strict):
    """One scenario field and the values to estimate it at."""

    parameter: str = Field(
        max_length=200, pattern=r"^[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z0-9_]+){0,15}$",
        description="Dotted path of a scenario field, as in 'overrides' "
        "(e.g. vehicle.secondary.kz, speed_kmh)")
    values: list[Any] = Field(
        min_length=1, max_length=MAX_SWEEP_VALUES,
        description=f"Its values (at most {MAX_SWEEP_VALUES}), each checked as an override of "
        "the scenario: a value that makes it invalid is a 422 at ['sweep', 'values', i]")


class FloorMapSpec(_Strict):
    """A comfort map over the car body's floor grid (the grid of
    ``output.floor_grid_spacing_m``).
    """

    spacing_m: float = Field(
        gt=0.0, description="Grid spacing (m), within the range of the scenario's "
        "output.floor_grid_spacing_m; the grid's points with the scenario's other car-body "
        "points within the service's limit of recorded points (FLEXRIDE_MAX_OUTPUT_POINTS)",
        json_schema_extra={"unit": "m"})


class EstimateCreate(ScenarioInput):
    """A frequency-domain estimate: the scenario input of ``POST /jobs`` (a full scenario, or a
    preset with dotted-path overrides) and the estimate's options.
    """

    model_config = ConfigDict(extra="forbid", json_schema_extra={"examples": [
        {"preset": "paper-random-straight-80", "points": ["PC", "PR"]},
        {"preset": "paper-random-straight-80", "points": ["PC"],
         "sweep": {"parameter": "vehicle.secondary.cz", "values": [40000, 80000, 120000]}},
        {"scenario": {"preset": "paper-random-curve-80"}, "points": ["PC"], "strict": False},
    ]})

    points: list[str] = Field(
        default_factory=lambda: list(PAPER_POINT_NAMES), min_length=1, max_length=MAX_POINTS,
        description="Recorded points to estimate: car-body point names (PC, PR …) or "
        "'<body>.<point>' (frame1.centre); default the paper's six points")
    track: TrackModelName = Field(
        "condensed", description="Track model: rail condensed onto the rail heads under the "
        "wheels (default), every rail mode of the frozen window (modal, slower), rigid rails")
    strict: bool = Field(
        True, description="Refuse (422) a scenario the linear model does not hold for (flange "
        "contact or lost contact at equilibrium, a non-random excitation); false: estimate it "
        "anyway with the reason in 'flags'")
    linearisation: LinearisationMethod = Field(
        DEFAULT_LINEARISATION, description="How the wheel-rail contact is linearised with real "
        "profiles: statistical (default: each wheel's contact forces by their "
        "Gaussian-equivalent gains over its lateral motion on the rail, at the response's own "
        "amplitude, iterated until it settles) or local (slopes at the operating point). "
        "The conical tread is linear and gives the same either way")
    sweep: SweepSpec | None = Field(
        None, description="Estimate the scenario at each of several values of one field "
        "instead (the answer is then the series of every index against the values)")
    spectra: bool = Field(
        False, description="Also return the frequency grid and the one-sided acceleration PSD "
        f"of every channel ((m/s²)²/Hz) in 'response' (not with a sweep; at most "
        f"{MAX_SPECTRA_POINTS} points), with 'dynamic_part_gain': the squared gain of the "
        "analysis's quasi-static split (multiply a PSD by it to compare with a job's PSD of the "
        "dynamic part)")
    floor_map: FloorMapSpec | None = Field(
        None, description="Also map the comfort over the car body's floor grid: 'floor_map' "
        "in the answer with the grid's x_m, y_m, names and per direction the rms, ISO 2631 "
        "weighted rms and Sperling index as [y][x] arrays, N_MV, and the floor points of the "
        "scenario to mark (not with a sweep)")
    refusal: Literal["error", "answer"] = Field(
        "error", description="How a scenario the linear estimate does not hold for is answered: "
        "'error' (default) 422 with the reason; 'answer' 200 with applicable: false, the reason "
        "and the located reasons (NotApplicableOut), for clients that ask whether an estimate "
        "applies (the dashboard's instant estimate)")

    @field_validator("spectra")
    @classmethod
    def _spectra_bounded(cls, v: bool, info: ValidationInfo) -> bool:
        if not v:
            return v
        if info.data.get("sweep") is not None:
            raise ValueError("spectra are returned for one scenario, not with a sweep")
        n = len(info.data.get("points") or PAPER_POINT_NAMES)
        if n > MAX_SPECTRA_POINTS:
            raise ValueError(f"spectra are returned for at most {MAX_SPECTRA_POINTS} points, "
                             f"got {n}")
        return v

    @field_validator("floor_map")
    @classmethod
    def _floor_map_alone(cls, v: FloorMapSpec | None, info: ValidationInfo
                         ) -> FloorMapSpec | None:
        if v is not None and info.data.get("sweep") is not None:
            raise ValueError("a floor map is made for one scenario, not with a sweep")
        return v


class EstimateOut(BaseModel):
    """The estimate of one scenario, as ``flexride estimate --json`` prints it."""

    comfort: dict[str, Any] = Field(description=(
        "Comfort table: per point and direction the rms, ISO 2631 weighted rms (iso2631), "
        "Sperling (spectral and filter form), EN 12299 a_P95 and N_MV, the expected peak (all "
        "m/s² but the indices) and the eigenmodes carrying the comfort-weighted variance; the "
        "method and the flags where the estimate may not hold"))
    model: dict[str, Any] = Field(description=(
        "The linearised model: track model, sizes, operating point, modes below 30 Hz, static "
        "wheel loads, quasi-static accelerations, flags, timings"))
    response: dict[str, Any] = Field(description="rms per channel and the input spectra; with "
                                     "'spectra' also frequencies_hz, psd per channel and "
                                     "dynamic_part_gain")
    floor_map: dict[str, Any] | None = Field(None, description="With 'floor_map': the comfort "
                                             "map over the floor grid")


class NotApplicableOut(BaseModel):
    """The answer with ``refusal: "answer"`` for a scenario the linear estimate does not hold
    for (what a 422 refusal says otherwise).
    """

    applicable: Literal[False] = Field(description="Always false: no estimate")
    reason: str = Field(description="flange_contact, contact_loss, excitation, unstable or "
                        "equilibrium")
    message: str = Field(description="Why, and what to do")
    reasons: list[dict[str, Any]] = Field(description="Located reasons: loc (where it points in "
                                          "the request), msg, type, ctx.reason")


class RefusedValue(BaseModel):
    """A sweep value the linear estimate does not hold for."""

    index: int = Field(description="Position in sweep.values")
    value: Any
    reason: str = Field(description="flange_contact, contact_loss, unstable, excitation, "
                        "equilibrium, or the error's kind")
    message: str


class SweepOut(BaseModel):
    """The estimates of a sweep: every index against the values."""

    parameter: str
    values: list[Any]
    points: list[str]
    track: TrackModelName
    strict: bool
    linearisation: LinearisationMethod
    series: dict[str, dict[str, dict[str, list[float | None]]]] = Field(description=(
        "point → direction (y, z) → index → one number per value (null where refused): rms, "
        "Wb/Wk/Wd (ISO 2631 weighted rms), sperling, sperling_filter, a_p95, peak (m/s² but "
        "the Sperling indices)"))
    nmv: dict[str, list[float | None]] = Field(
        description="EN 12299 N_MV per floor point and value")
    flags: list[list[str]] = Field(description="Per value, where the estimate may not hold")
    refused: list[RefusedValue]
    reuse: dict[str, int] = Field(description="What the rebuilds of the linear model reused")
    seconds: float = Field(description="Computing time of the sweep (s)")
