"""``flexride critical-speed``: the hunting (critical) speed of a scenario's vehicle, linear
(eigenvalues of the linearised model) and nonlinear (time-domain runs after a lateral
disturbance, :mod:`flexride.study.critical_speed`). User errors end with one line on standard
error and exit code 2.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated, NoReturn

import typer
from rich.console import Console

from flexride.errors import FlexrideError

_out = Console(highlight=False, soft_wrap=True)
_err = Console(stderr=True, highlight=False, soft_wrap=True)


def _fail(message: str) -> NoReturn:
    _err.print(f"error: {message}", markup=False)
    raise typer.Exit(2)


def _speed(v: float | None, v_max: float) -> str:
    return f"above {v_max:g} km/h (none found)" if v is None else f"{v:.1f} km/h"


def critical_speed(
    scenario_file: Annotated[Path | None, typer.Argument(help="Scenario YAML/JSON file")] = None,
    preset: Annotated[str | None, typer.Option("--preset", "-p", help="Preset name")] = None,
    set_: Annotated[list[str] | None, typer.Option(
        "--set", help="Override any field: PATH=VALUE, e.g. contact.geometry=profiles")] = None,
    v_min: Annotated[float, typer.Option("--v-min", help="Lowest speed searched (km/h)")] = 40.0,
    v_max: Annotated[float, typer.Option("--v-max", help="Highest speed searched (km/h)")] = 200.0,
    tolerance: Annotated[float, typer.Option(help="Bisection tolerance (km/h)")] = 2.0,
    disturbance_mm: Annotated[float, typer.Option(
        "--disturbance-mm",
        help="Initial lateral displacement of the leading wheelset (mm)")] = 3.0,
    distance: Annotated[float, typer.Option(help="Length of each run (m)")] = 400.0,
    linear: Annotated[bool, typer.Option("--linear/--no-linear",
                                         help="Also find the linear critical speed")] = True,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON")] = False,
) -> None:
    """Find the critical (hunting) speed on smooth straight track, linear and nonlinear."""
    from flexride.cli import _load, _parse_set
    from flexride.study.critical_speed import critical_speed as find

    try:
        if not (0 < v_min < v_max and tolerance > 0 and disturbance_mm > 0 and distance > 0):
            raise FlexrideError("need 0 < --v-min < --v-max and positive --tolerance, "
                                "--disturbance-mm and --distance")
        scenario = _load(scenario_file, preset, _parse_set(set_ or []))
        show = None if as_json else (lambda m: _out.print(f"  {m}"))
        result = find(scenario, v_min_kmh=v_min, v_max_kmh=v_max, tolerance_kmh=tolerance,
                      disturbance_m=disturbance_mm * 1e-3, distance_m=distance, linear=linear,
                      progress=show)
    except FlexrideError as exc:
        _fail(str(exc))
    if as_json:
        typer.echo(json.dumps(result.to_dict(), indent=2, default=float))
        return
    _out.print(f"nonlinear critical speed ({disturbance_mm:g} mm disturbance, {distance:g} m "
               f"runs, decay over the run): {_speed(result.nonlinear_kmh, v_max)}")
    if linear:
        _out.print(f"linear critical speed (first growing eigenmode): "
                   f"{_speed(result.linear_kmh, v_max)}")
    for note in result.notes:
        _out.print(f"note: {note}")
