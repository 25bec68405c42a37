"""From what a user gives to a validated :class:`~flexride.scenario.scenario.Scenario`: a file
(YAML or JSON), a mapping (which may start from ``preset: NAME``) or a preset name, plus dotted
overrides. One loader for the CLI, the API and studies, so the same input gives the same
answer everywhere, and every failure is a :class:`~flexride.errors.ScenarioError` located at
its field (``preset``, ``overrides.<path>``, the scenario field).

Text is parsed with bounds: nesting deeper than :data:`MAX_NESTING` or more than
:data:`MAX_NODES` values (YAML aliases can expand a small file) are refused.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import yaml

from flexride.errors import ErrorItem, ScenarioError, UnknownPresetError
from flexride.scenario.scenario import (
    Scenario,
    apply_overrides,
    resolve_preset_base,
    scenario_from_dict,
)

MAX_NESTING = 64
"""Deepest nesting of mappings and lists accepted in a scenario (scenarios need < 10)."""
MAX_NODES = 2_000_000
"""Most values (mappings, lists and scalars, aliases counted each time) in a scenario."""
MAX_PATH_DEPTH = 12
"""Most parts of a dotted override path."""

Loc = tuple[str | int, ...]


def check_shape(data: Any, source: str) -> None:
    """Refuse data nested deeper than :data:`MAX_NESTING` or with more than :data:`MAX_NODES`
    values.
    """
    stack, nodes = [(data, 1)], 0
    while stack:
        node, depth = stack.pop()
        nodes += 1
        if depth > MAX_NESTING:
            raise ScenarioError(f"{source}: nested more than {MAX_NESTING} levels deep")
        if nodes > MAX_NODES:
            raise ScenarioError(f"{source}: more than {MAX_NODES:,} values")
        children = (
            node.values() if isinstance(node, dict) else node if isinstance(node, list) else ()
        )
        stack.extend((child, depth + 1) for child in children)


def parse_text(text: str, as_json: bool, source: str) -> Any:
    """Parse YAML (or JSON) text into plain data, with one-line errors for syntax errors and
    for data nested too deeply or too large.
    """
    try:
        data = json.loads(text) if as_json else yaml.safe_load(text)
    except (json.JSONDecodeError, yaml.YAMLError) as exc:
        raise ScenarioError(f"{source}: cannot parse: {str(exc).splitlines()[0]}") from None
    except RecursionError:  # the parsers recurse per level of nesting
        raise ScenarioError(f"{source}: nested more than {MAX_NESTING} levels deep") from None
    check_shape(data, source)
    return data


def read_scenario_file(path: str | Path) -> dict[str, Any]:
    """The mapping of a YAML (``.yaml``/``.yml``) or JSON (``.json``) scenario file.

    Raises
    ------
    ScenarioError
        Missing file, not UTF-8, unparsable, too deep or too large, not a mapping.
    """
    p = Path(path)
    if not p.is_file():
        raise ScenarioError(f"scenario file not found: {p}")
    try:
        text = p.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise ScenarioError(f"{p}: not UTF-8 text (byte {exc.start})") from None
    data = parse_text(text, p.suffix.lower() == ".json", str(p))
    if not isinstance(data, dict):
        raise ScenarioError(f"{p}: a scenario must be a mapping")
    return data


def safe_overrides(
    data: dict[str, Any],
    overrides: dict[str, Any] | None,
    source: str = "overrides",
    loc: Loc = ("overrides",),
) -> dict[str, Any]:
    """Apply dotted-path overrides; a failure is a :class:`ScenarioError` at ``loc + (path,)``.

    Parameters
    ----------
    data : dict
        Scenario mapping (presets already resolved).
    overrides : dict, optional
        ``{"solver.dt": 5e-5, "excitation.0.seed": 3}``.
    source : str
        Prefix of error messages.
    loc : tuple
        Location of the overrides in the request.
    """
    if not overrides:
        return data
    if not isinstance(overrides, dict):
        raise ScenarioError.at(loc, "must be a mapping of dotted paths to values", source)
    for path in overrides:
        parts = path.split(".") if isinstance(path, str) else []
        if not parts or any(not p.strip() for p in parts) or len(parts) > MAX_PATH_DEPTH:
            raise ScenarioError.at(
                (*loc, str(path)), f"{path!r} is not a dotted field path like 'solver.dt'", source
            )
    out = data
    for path, value in overrides.items():
        try:
            out = apply_overrides(out, {path: value})
        except (KeyError, IndexError, ValueError, TypeError, AttributeError) as exc:
            raise ScenarioError.at(
                (*loc, path), f"cannot set {path!r}: {_why(exc)}", source
            ) from None
    return out


def _why(exc: Exception) -> str:
    if isinstance(exc, IndexError):
        return "no such list item"
    if isinstance(exc, ValueError):
        return "a list index must be a whole number"
    return f"{type(exc).__name__}: {exc}"


def check_finite(value: Any, path: str = "") -> None:
    """Refuse NaN and infinite numbers anywhere in plain data (fields without bounds too)."""
    if isinstance(value, float) and not math.isfinite(value):
        loc = tuple(int(p) if p.isdigit() else p for p in path.split(".")) if path else ()
        raise ScenarioError.at(loc, f"must be a finite number, got {value}")
    if isinstance(value, dict):
        for k, v in value.items():
            check_finite(v, f"{path}.{k}" if path else str(k))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            check_finite(v, f"{path}.{i}" if path else str(i))


def _preset(name: str, loc: Loc) -> dict[str, Any]:
    from flexride.scenario.presets import preset_dict

    try:
        return preset_dict(name)
    except UnknownPresetError as exc:
        raise ScenarioError(str(exc), [ErrorItem(loc, str(exc))]) from None


def resolve_scenario(
    scenario: dict[str, Any] | None = None,
    preset: str | None = None,
    overrides: dict[str, Any] | None = None,
    source: str | None = None,
) -> Scenario:
    """Validated scenario from a full mapping (which may start from ``preset: NAME``) or from a
    preset name, with optional dotted-path overrides.

    Parameters
    ----------
    scenario : dict, optional
        Scenario mapping (e.g. from :func:`read_scenario_file` or a request body).
    preset : str, optional
        Preset name instead of ``scenario``.
    overrides : dict, optional
        Dotted-path overrides.
    source : str, optional
        How messages name the input (default ``scenario`` or ``preset NAME``).

    Raises
    ------
    ScenarioError
        Neither or both given, unknown preset (at ``preset``), bad override path (at
        ``overrides.<path>``), or an invalid field (the field path and the allowed range).
    """
    if (scenario is None) == (preset is None):
        raise ScenarioError("give either 'scenario' or 'preset' (not both)")
    if preset is not None:
        data = _preset(preset, ("preset",))
        source = source or f"preset {preset}"
    else:
        if not isinstance(scenario, dict):
            raise ScenarioError.at(("scenario",), "must be a mapping", "request")
        if "preset" in scenario:
            _preset(str(scenario["preset"]), ("preset",))  # located error for a bad name
        data = resolve_preset_base(scenario) if "preset" in scenario else scenario
        source = source or "scenario"
    data = safe_overrides(data, overrides)
    result = scenario_from_dict(data, source=source)
    check_finite(result.model_dump(mode="json"))
    return result
