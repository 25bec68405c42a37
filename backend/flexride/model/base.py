"""Common base for every scenario schema.

Conventions (DESIGN §4): SI units inside; every numeric field states its unit in its
description and carries validation bounds; speeds in km/h only in fields named ``*_kmh``.
Unknown fields are rejected so that a typo in a scenario file is an error, not a silent default.
"""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict


class Schema(BaseModel):
    """Base class of all scenario and parameter schemas (strict about unknown keys)."""

    model_config = ConfigDict(extra="forbid", validate_assignment=True, populate_by_name=True)
