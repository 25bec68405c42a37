"""The scenario: everything one simulation needs, loadable from YAML or JSON."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from pydantic import Field, ValidationError, model_validator

from flexride.errors import ErrorItem, ScenarioError
from flexride.scenario.base import Schema, quantity
from flexride.scenario.bodies import BodyModels
from flexride.scenario.contact import Contact
from flexride.scenario.excitation import Excitation
from flexride.scenario.line import Line, StraightLine
from flexride.scenario.solver import Output, Solver
from flexride.scenario.track import Track
from flexride.scenario.vehicle import Vehicle
from flexride.units import kmh_to_mps


class Scenario(Schema):
    """One simulation: vehicle, track, line, excitation, speed, length, numerics and outputs.

    Exactly one of ``duration_s`` and ``distance_m`` sets the length of the run.
    """

    name: str = Field("scenario", max_length=80, description="Scenario name")
    description: str = Field("", max_length=4000, description="Free text")
    vehicle: Vehicle
    track: Track = Field(default_factory=Track)
    line: Line = Field(default_factory=StraightLine)
    contact: Contact = Field(default_factory=Contact)
    excitation: list[Excitation] = Field(default_factory=list, description="Combined excitations")
    speed_kmh: float = quantity(..., gt=0.0, le=200.0, description="Running speed", unit="km/h")
    duration_s: float | None = quantity(
        None, gt=0.0, le=3600.0, description="Simulated time", unit="s"
    )
    distance_m: float | None = quantity(
        None, gt=0.0, le=1.0e5, description="Distance to run", unit="m"
    )
    bodies: BodyModels = Field(
        default_factory=BodyModels, description="Rigid or flexible car body and bogie frames"
    )
    solver: Solver = Field(default_factory=Solver)
    output: Output = Field(default_factory=Output)

    @model_validator(mode="after")
    def _one_length(self) -> Scenario:
        if (self.duration_s is None) == (self.distance_m is None):
            raise ValueError("give exactly one of duration_s (s) and distance_m (m)")
        return self

    @property
    def speed_mps(self) -> float:
        """Running speed (m/s)."""
        return kmh_to_mps(self.speed_kmh)

    @property
    def duration(self) -> float:
        """Simulated time (s)."""
        if self.duration_s is not None:
            return self.duration_s
        if self.distance_m is None:  # only if validation was bypassed (model_construct)
            raise ScenarioError.at((), "give exactly one of duration_s (s) and distance_m (m)")
        return self.distance_m / self.speed_mps


def allowed_range(ctx: dict[str, Any] | None) -> str:
    """`` (allowed: ≤ 500)`` from the bounds of a validation error's context, or ``""``."""
    bounds = [f"{sym} {ctx[key]}" for key, sym in (("gt", ">"), ("ge", "≥"), ("lt", "<"),
                                                  ("le", "≤")) if ctx and key in ctx]
    return f" (allowed: {', '.join(bounds)})" if bounds else ""


def _data_loc(loc: tuple[Any, ...], data: Any) -> tuple[str | int, ...]:
    """``loc`` without the tags pydantic inserts for discriminated unions (``measured`` in
    ``excitation.0.measured.rows``): the path of the field in the input data.
    """
    out: list[str | int] = []
    node = data
    for part in loc:
        if isinstance(node, dict) and part not in node and isinstance(part, str) and (
                node.get("kind") == part):
            continue  # a union tag, not a key of the input
        if data is not None and not isinstance(node, dict | list) and isinstance(part, str):
            continue  # the member of a union of scalars (solver.dt: a number or auto)
        out.append(part)
        node = node.get(part) if isinstance(node, dict) else (
            node[part] if isinstance(node, list) and isinstance(part, int)
            and 0 <= part < len(node) else None)
    return tuple(out)


def validation_items(exc: ValidationError, data: Any = None) -> list[ErrorItem]:
    """One located problem per validation error: what is wrong, the allowed range and the
    value given (located in the input ``data``).
    """
    errors = [(_data_loc(tuple(err["loc"]), data), err) for err in exc.errors()]
    valued = {loc for loc, err in errors if err["type"] != "literal_error"}
    keywords = {loc: str((err.get("ctx") or {}).get("expected", "")) for loc, err in errors
                if err["type"] == "literal_error" and loc in valued}  # solver.dt: … or 'auto'
    items: dict[tuple[str | int, ...], str] = {}
    for loc, err in errors:
        if loc in keywords and err["type"] == "literal_error":
            continue
        got = err.get("input")
        got_txt = "" if isinstance(got, dict | list) else f", got {got!r}"
        items.setdefault(loc, f"{err['msg']}{allowed_range(err.get('ctx'))}{got_txt}")
    return [ErrorItem(loc, _or_keyword(msg, keywords.get(loc))) for loc, msg in items.items()]


def _or_keyword(msg: str, keyword: str | None) -> str:
    """``msg`` (``…, got 1.0``) with the keyword a field also accepts: ``… or 'auto', got 1.0``."""
    if not keyword:
        return msg
    head, sep, tail = msg.rpartition(", got ")
    return f"{head} or {keyword}{sep}{tail}" if sep else f"{msg} or {keyword}"


def located_error(items: list[ErrorItem], source: str) -> ScenarioError:
    """A :class:`ScenarioError` of ``items`` whose message reads ``source: path: msg; …``."""
    return ScenarioError("; ".join(f"{source}: {it.path}: {it.msg}" for it in items), items)


def deep_merge(base: dict[str, Any], update: dict[str, Any]) -> dict[str, Any]:
    """``base`` updated by ``update``, recursively for nested mappings (lists are replaced)."""
    out = dict(base)
    for key, value in update.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = deep_merge(out[key], value)
        else:
            out[key] = value
    return out


def resolve_preset_base(data: dict[str, Any]) -> dict[str, Any]:
    """A scenario mapping may start from a preset: ``preset: NAME`` plus the fields to change."""
    if "preset" not in data:
        return data
    from flexride.scenario.presets import preset_dict

    rest = {k: v for k, v in data.items() if k != "preset"}
    base = preset_dict(str(data["preset"]))
    if "duration_s" in rest or "distance_m" in rest:
        base = {k: v for k, v in base.items() if k not in ("duration_s", "distance_m")}
    return deep_merge(base, rest)


def scenario_from_dict(data: dict[str, Any], source: str = "scenario") -> Scenario:
    """Validate a mapping into a :class:`Scenario`, raising :class:`ScenarioError` on failure.

    The mapping may name a ``preset`` to start from (see :func:`resolve_preset_base`).
    """
    if not isinstance(data, dict):
        raise ScenarioError.at((), f"a scenario must be a mapping, got {type(data).__name__}",
                               source)
    data = resolve_preset_base(data)
    try:
        return Scenario.model_validate(data)
    except ValidationError as exc:
        raise located_error(validation_items(exc, data), source) from None


def load_scenario(path: str | Path) -> Scenario:
    """Load a scenario from a YAML (``.yaml``/``.yml``) or JSON (``.json``) file (bounded
    parsing, presets and located errors of :mod:`flexride.scenario.loading`).

    Raises
    ------
    ScenarioError
        If the file is missing, unparsable or invalid (message names the field and range).
    """
    from flexride.scenario.loading import read_scenario_file, resolve_scenario

    return resolve_scenario(read_scenario_file(path), source=Path(path).name)


def apply_overrides(data: dict[str, Any], overrides: dict[str, Any]) -> dict[str, Any]:
    """Return a copy of ``data`` with dotted-path overrides applied (``"solver.dt": 5e-5``)."""
    out = json.loads(json.dumps(data))
    for dotted, value in overrides.items():
        node = out
        parts = dotted.split(".")
        for part in parts[:-1]:
            if isinstance(node, list):
                node = node[int(part)]
            else:
                node = node.setdefault(part, {})
        last = parts[-1]
        if isinstance(node, list):
            node[int(last)] = value
        else:
            node[last] = value
    return out
