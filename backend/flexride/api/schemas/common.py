"""Types and error bodies shared by the API's request and response models."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Annotated, Any, Literal

from pydantic import (
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
)

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


def _utc(t: Any) -> Any:
    """Epoch seconds (the store's times) as an aware UTC datetime; other values unchanged."""
    if isinstance(t, int | float) and not isinstance(t, bool):
        return datetime.fromtimestamp(float(t), tz=UTC)
    return t


Epoch = Annotated[datetime, BeforeValidator(_utc)]
"""A time stored as UTC epoch seconds, shown as ISO 8601."""
