"""``flexride estimate``: the frequency-domain comfort estimate of a scenario or preset (the
linearised vehicle–track model driven by the track spectra, :mod:`flexride.frequency`).

Prints, per car-body point, the rms and ISO 2631 weighted rms accelerations, the Sperling
indices and EN 12299 N_MV, then the eigenmodes carrying most of each point's comfort-weighted
variance, and any reason the linear estimate may not hold. ``--json`` prints the same as JSON.
User errors end with one line on standard error and exit code 2.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated, Any, NoReturn

import typer
from rich import box
from rich.console import Console
from rich.table import Table

from flexride.errors import FlexrideError, ScenarioError

estimate_app = typer.Typer(add_completion=False, help="Frequency-domain ride-comfort estimate.")
_out = Console(highlight=False, soft_wrap=True)
_err = Console(stderr=True, highlight=False, soft_wrap=True)

TRACK_HELP = ("Track model: condensed (rail condensed onto its heads, default), modal (every "
              "rail mode of the frozen window) or rigid")


def _fail(message: str) -> NoReturn:
    _err.print(f"error: {message}", markup=False)
    raise typer.Exit(2)


def _f(v: float | None, fmt: str = ".3f") -> str:
    return "–" if v is None else format(v, fmt)


def comfort_table(data: dict[str, Any]) -> Table:
    """Rich table of a comfort estimate's ``to_dict()``."""
    t = Table(title=f"{data['scenario']} — {data['speed_kmh']:g} km/h, frequency-domain "
                    f"estimate ({data['track']} track)", box=box.SIMPLE_HEAD)
    for col in ("point", "rms z", "rms y", "a_w Wb z", "a_w Wk z", "a_w Wd y", "W z", "W y",
                "N_MV"):
        t.add_column(col, justify="left" if col == "point" else "right")
    for p in data["points"]:
        z, y = p["directions"].get("z", {}), p["directions"].get("y", {})
        t.add_row(p["name"], _f(z.get("rms")), _f(y.get("rms")),
                  _f(z.get("iso2631", {}).get("Wb")), _f(z.get("iso2631", {}).get("Wk")),
                  _f(y.get("iso2631", {}).get("Wd")), _f(z.get("sperling"), ".2f"),
                  _f(y.get("sperling"), ".2f"), _f(p.get("nmv"), ".2f"))
    t.caption = ("accelerations in m/s² (0.1–80 Hz); W = Sperling index, spectral form "
                 "(expected, 5 s lines); N_MV EN 12299 (Gaussian P95 of 5 s rms, x = 0)")
    return t


def modes_table(data: dict[str, Any]) -> Table:
    """Rich table of the dominant eigenmodes per point and direction."""
    t = Table(title="modes carrying the comfort-weighted variance (Wb z, Wd y)",
              box=box.SIMPLE_HEAD)
    for col in ("point", "dir", "f (Hz)", "ζ", "share", "mode"):
        t.add_column(col, justify="left" if col in ("point", "dir", "mode") else "right")
    for p in data["points"]:
        for d, dv in p["directions"].items():
            for m in dv["dominant_modes"]:
                t.add_row(p["name"], d, f"{m['frequency_hz']:.2f}", f"{m['damping_ratio']:.2f}",
                          f"{100 * m['share']:.0f} %", m["label"])
    return t


@estimate_app.callback(invoke_without_command=True)
def estimate(
    scenario_file: Annotated[Path | None, typer.Argument(help="Scenario YAML/JSON file")] = None,
    preset: Annotated[str | None, typer.Option("--preset", "-p", help="Preset name")] = None,
    speed: Annotated[float | None, typer.Option(help="Override the running speed (km/h)")] = None,
    set_: Annotated[list[str] | None, typer.Option(
        "--set", help="Override any field: PATH=VALUE, e.g. vehicle.secondary.kz=3e5")] = None,
    body_model: Annotated[str | None, typer.Option(
        "--body-model", help="rigid or flexible: switches the car body and both frames")] = None,
    track: Annotated[str, typer.Option("--track", help=TRACK_HELP)] = "condensed",
    points: Annotated[str | None, typer.Option(
        "--points", help="Comma-separated points (default every car-body point)")] = None,
    strict: Annotated[bool, typer.Option(
        "--strict/--no-strict",
        help="Refuse (default) or only flag a scenario the linear model does not hold for "
             "(flange contact at equilibrium, non-random excitation)")] = True,
    linearisation: Annotated[str | None, typer.Option(
        "--linearisation",
        help="Contact linearisation with real profiles: statistical (Gaussian-equivalent "
             "gains at the response's own amplitude, iterated; the default) or local (slopes "
             "at the operating point)")] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of tables")] = False,
) -> None:
    """Estimate ride comfort in the frequency domain (linearised model, track spectra)."""
    from flexride.cli import _load, command_overrides
    from flexride.frequency import estimate as run_estimate
    from flexride.frequency.model import DEFAULT_LINEARISATION, LINEARISATIONS

    try:
        scenario = _load(scenario_file, preset, command_overrides(set_, speed, body_model))
        if track not in ("condensed", "modal", "rigid"):
            raise ScenarioError(f"--track must be condensed, modal or rigid, got {track!r}")
        method = linearisation or DEFAULT_LINEARISATION
        if method not in LINEARISATIONS:
            raise ScenarioError(f"--linearisation must be {' or '.join(LINEARISATIONS)}, got "
                                f"{method!r}")
        pts = [p.strip() for p in points.split(",") if p.strip()] if points else None
        est = run_estimate(scenario, pts, track, strict=strict,  # type: ignore[arg-type]
                           linearisation=method)
    except FlexrideError as exc:
        _fail(str(exc))
    data = est.comfort.to_dict()
    if as_json:
        typer.echo(json.dumps(est.to_dict(), indent=2, default=float))
        return
    _out.print(f"method: {data['method']}")
    _out.print(comfort_table(data))
    _out.print(modes_table(data))
    for flag in data["flags"]:
        _out.print(f"note: {flag}")
    info = est.model.info
    built = sum(info[k] for k in ("time_operating_point_s", "time_linearise_s", "time_modes_s"))
    _out.print(f"model: {info['n_dof']} coordinates ({info['n_dof_full']} before the track "
               f"reduction), built in {built:.2f} s")
