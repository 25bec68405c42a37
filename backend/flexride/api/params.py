"""Path and query parameters shared by the routers: the ids of jobs and studies.

Jobs and studies are named by UUIDs (stored as 32 lower-case hexadecimal digits). An id is
parsed as a UUID before any query — by Pydantic's UUID type, so every spelling a client may
send is accepted: hyphenated or not, any case, in braces or as ``urn:uuid:`` — and handed to
the routes in the stored form. Anything else is 422 at its parameter (a NUL byte or a control
character never reaches the database or the log).
"""

from __future__ import annotations

from typing import Annotated, Any
from uuid import UUID

from fastapi import Path, Query
from pydantic import BeforeValidator, TypeAdapter, ValidationError, WithJsonSchema
from pydantic_core import PydanticCustomError

_UUID = TypeAdapter(UUID)
ID_RULE = ("a UUID: 32 hexadecimal digits, with or without hyphens, in any case "
           "(e.g. 0f8fad5b-d9cb-469f-a165-70867728950e)")
"""What an id must be (said by a refused one)."""


def record_id(value: Any) -> str:
    """The stored form (32 lower-case hexadecimal digits) of a job or study id.

    Raises
    ------
    pydantic_core.PydanticCustomError
        ``uuid_parsing`` when ``value`` is not a UUID (the message does not repeat it).

    Examples
    --------
    >>> record_id("0F8FAD5B-D9CB-469F-A165-70867728950E")
    '0f8fad5bd9cb469fa16570867728950e'
    """
    try:
        return _UUID.validate_python(value).hex
    except ValidationError:
        raise PydanticCustomError("uuid_parsing", "Input should be {rule}",
                                  {"rule": ID_RULE}) from None


RecordId = Annotated[str, BeforeValidator(record_id),
                     WithJsonSchema({"type": "string", "format": "uuid"})]
"""A job or study id, normalised to the stored form."""

JobId = Annotated[RecordId, Path(description=f"Job id: {ID_RULE}")]
StudyId = Annotated[RecordId, Path(description=f"Study id: {ID_RULE}")]
StudyFilter = Annotated[RecordId | None, Query(description=f"Only this study ({ID_RULE})")]
