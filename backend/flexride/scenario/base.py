"""Common base for every scenario schema.

Conventions (DESIGN §4): SI units inside; every numeric field is a :func:`quantity`: its unit is
data of the schema (``"unit"`` in the JSON schema, which the dashboard shows) and closes its
description; it carries validation bounds; speeds in km/h only in fields named ``*_kmh``.
Unknown fields are rejected so that a typo in a scenario file is an error, not a silent default.
"""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ConfigDict, Field
from pydantic_core import PydanticUndefined


class Schema(BaseModel):
    """Base class of all scenario and parameter schemas (strict about unknown keys)."""

    model_config = ConfigDict(extra="forbid", validate_assignment=True, populate_by_name=True)


def quantity(
    default: Any = PydanticUndefined, *, unit: str, description: str, **kwargs: Any
) -> Any:
    """A numeric schema field with its unit.

    Parameters
    ----------
    default : optional
        Default value (``...`` or omitted: required).
    unit : str
        SI unit (``"m"``, ``"N·s/m"``; ``"-"`` for dimensionless), stored as ``unit`` in the
        field's JSON schema.
    description : str
        What the field is, without the unit: the description becomes ``"<text> (<unit>)"``.
    **kwargs
        Further arguments of :func:`pydantic.Field` (bounds, ``default_factory``...).
    """
    return Field(
        default, description=f"{description} ({unit})", json_schema_extra={"unit": unit}, **kwargs
    )
