"""Types and error bodies shared by the API's request and response models."""

from __future__ import annotations

from collections.abc import Iterator
from datetime import UTC, datetime
from typing import Annotated, Any, Literal

from pydantic import (
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    ValidationError,
    model_validator,
)
from pydantic_core import InitErrorDetails, PydanticCustomError

JobStatus = Literal["queued", "running", "succeeded", "failed", "cancelled"]
JobKind = Literal["simulation", "fe_export", "paper_report"]
BodyModelName = Literal["rigid", "flexible"]

_NAME_PATTERN = r"^[A-Za-z0-9][A-Za-z0-9 _.+-]{0,79}$"


NUL_RULE = "text must not contain the NUL character (U+0000)"
"""Why a request text with NUL is refused: the job store cannot keep it (PostgreSQL's text
cannot hold NUL), and no field of a scenario or study needs it."""


def _nul_paths(value: Any, path: tuple[str | int, ...] = ()) -> Iterator[tuple[str | int, ...]]:
    """Paths of the strings (keys included) in a parsed JSON value that contain NUL."""
    if isinstance(value, str):
        if "\x00" in value:
            yield path
    elif isinstance(value, dict):
        for key, item in value.items():
            if isinstance(key, str) and "\x00" in key:
                yield (*path, key)
            yield from _nul_paths(item, (*path, key))
    elif isinstance(value, list):
        for i, item in enumerate(value):
            if isinstance(item, str | dict | list):
                yield from _nul_paths(item, (*path, i))


class _Strict(BaseModel):
    """A request body: unknown fields and NUL characters in any text are refused (422 at
    the field).
    """

    model_config = ConfigDict(extra="forbid")

    @model_validator(mode="before")
    @classmethod
    def _no_nul(cls, data: Any) -> Any:
        paths = list(_nul_paths(data))
        if paths:
            raise ValidationError.from_exception_data(cls.__name__, [
                InitErrorDetails(type=PydanticCustomError("string_nul", NUL_RULE), loc=loc,
                                 input="") for loc in paths[:20]])
        return data


class ScenarioInput(_Strict):
    """Where a request's scenario comes from: a full scenario, or a preset, each with dotted-path
    overrides applied last (one loader resolves it: ``scenario.loading.resolve_scenario``).
    """

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

    @model_validator(mode="after")
    def _one_source(self) -> ScenarioInput:
        if (self.scenario is None) == (self.preset is None):
            raise ValueError("give either 'scenario' or 'preset' (not both)")
        return self


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


def _utc(t: Any) -> Any:
    """Epoch seconds (the store's times) as an aware UTC datetime; other values unchanged."""
    if isinstance(t, int | float) and not isinstance(t, bool):
        return datetime.fromtimestamp(float(t), tz=UTC)
    return t


Epoch = Annotated[datetime, BeforeValidator(_utc)]
"""A time stored as UTC epoch seconds, shown as ISO 8601."""
