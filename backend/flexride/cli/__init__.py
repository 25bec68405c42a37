"""Command-line interface: ``flexride run``, ``flexride presets``, ``flexride analyze``.

Every command that prints results also takes ``--json``. Errors of the user's making end the
program with exit code 2 and one readable line on standard error.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path
from typing import Annotated, Any, NoReturn

import numpy as np
import typer
from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn
from rich.table import Table

from flexride.cli.tables import fit_table, points_legend
from flexride.errors import FlexrideError, ScenarioError
from flexride.results import time_step_record, time_step_text
from flexride.scenario.loading import parse_text

app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    help="flexride: ride comfort of metro vehicles on flexible track.",
)
console = Console()
err_console = Console(stderr=True)


def _fail(message: str, code: int = 2) -> NoReturn:
    err_console.print(f"[bold red]error:[/] {message}", highlight=False, soft_wrap=True)
    raise typer.Exit(code)


def _parse_set(items: list[str]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for item in items:
        if "=" not in item:
            raise ScenarioError(f"--set expects PATH=VALUE, got {item!r}")
        key, value = item.split("=", 1)
        out[key.strip()] = parse_text(value, False, f"--set {key.strip()}")
    return out


def command_overrides(set_: list[str] | None, speed: float | None, body_model: str | None,
                      duration: float | None = None) -> dict[str, Any]:
    """The overrides of a command's ``--set PATH=VALUE`` options and its shortcuts
    ``--speed`` (km/h), ``--body-model`` (rigid or flexible: car body and both frames; beam:
    the car body as a beam, the frames rigid) and
    ``--duration`` (s, replacing a distance).
    """
    overrides = _parse_set(set_ or [])
    if duration is not None:
        overrides["duration_s"] = duration
        overrides["distance_m"] = None
    if speed is not None:
        overrides["speed_kmh"] = speed
    if body_model is not None:
        if body_model not in ("rigid", "flexible", "beam"):
            raise ScenarioError(f"--body-model must be rigid, flexible or beam, got "
                                f"{body_model!r}")
        overrides["bodies.carbody.model"] = body_model
        overrides["bodies.frames.model"] = "rigid" if body_model == "beam" else body_model
    return overrides


def _load(scenario_file: Path | None, preset: str | None, overrides: dict[str, Any]):
    from flexride.scenario.loading import read_scenario_file, resolve_scenario

    if (scenario_file is None) == (preset is None):
        raise ScenarioError("give either a scenario file or --preset NAME (not both)")
    if scenario_file is not None:
        return resolve_scenario(read_scenario_file(scenario_file), overrides=overrides,
                                source=scenario_file.name)
    return resolve_scenario(preset=preset, overrides=overrides)


def run_summary(results, write_s: float | None = None) -> dict[str, Any]:
    """Peaks and rms per output point and direction (car body, frames, wheelsets), comfort and
    safety, and the wall time of each phase (``timings``; ``write_s`` the results file's, s).
    """
    rows = []
    for ch in results.parsed():
        if ch.quantity != "acc":
            continue
        name, body, point, direction = ch.name, ch.body, ch.point, ch.direction
        x = results.channels[name]
        rows.append(
            {
                "channel": name,
                "body": body,
                "point": point,
                "direction": direction,
                "rms": float(np.sqrt(np.mean(x**2))) if x.size else float("nan"),
                "peak": float(np.max(np.abs(x))) if x.size else float("nan"),
                "unit": results.units.get(name, ""),
            }
        )
    comfort: dict[str, Any] = {}
    t_analyze = time.perf_counter()
    try:
        from flexride.analysis import analyze

        comfort = analyze(results).to_dict()
    except FlexrideError as exc:  # e.g. a run without car-body channels
        comfort = {"error": str(exc)}
    analyze_s = time.perf_counter() - t_analyze
    from flexride.results import run_timings

    return {
        "scenario": results.scenario.get("name"),
        "speed_kmh": results.meta.get("speed_kmh"),
        "duration_s": float(results.time[-1]) if results.time.size else 0.0,
        "output_rate_hz": results.meta.get("output_rate"),
        "time_step": time_step_record(results.meta),
        "wall_time_solve_s": results.meta.get("wall_time_solve_s"),
        "timings": run_timings(results.meta, write_s, analyze_s),
        "accelerations": rows,
        "comfort": comfort,
    }


def _print_summary(summary: dict[str, Any]) -> None:
    table = Table(
        title=f"{summary['scenario']} — {summary['speed_kmh']:g} km/h, "
        f"{summary['duration_s']:.2f} s, output {summary['output_rate_hz']:g} Hz, "
        f"{time_step_text(summary['time_step'])}"
    )
    table.add_column("body")
    table.add_column("point")
    table.add_column("dir")
    table.add_column("rms (m/s²)", justify="right")
    table.add_column("peak (m/s²)", justify="right")
    for r in summary["accelerations"]:
        table.add_row(r["body"], r["point"], r["direction"], f"{r['rms']:.4f}", f"{r['peak']:.4f}")
    console.print(fit_table(table, console))
    comfort = summary.get("comfort")
    suspension = comfort.get("suspension") if isinstance(comfort, dict) else None
    if suspension:
        console.print(fit_table(_suspension_table(suspension), console))


def _suspension_table(suspension: dict[str, Any]) -> Table:
    """The summary's suspension forces (kN), vertical and lateral, one row per element."""
    table = Table(title="suspension forces on the car body (kN; z up)")
    table.add_column("element")
    for d in ("z", "y"):
        table.add_column(f"{d} mean", justify="right")
        table.add_column(f"{d} rms dyn", justify="right")
        table.add_column(f"{d} peak dyn", justify="right")
    for element, dirs in suspension.items():
        cells = [element]
        for d in ("z", "y"):
            s = dirs.get(d) or {}
            cells += [_kn(s.get(k)) for k in ("mean", "rms_dynamic", "peak_dynamic")]
        table.add_row(*cells)
    return table


def _kn(value: float | None) -> str:
    """A force in N as kN text (``-`` when missing)."""
    return "-" if value is None else f"{value / 1000.0:.2f}"


def _print_analysis(comfort: Any, points: list[dict[str, Any]]) -> None:
    """The comfort table with the legend of its points, then the running-safety table."""
    from flexride.analysis import safety_table, summary_table

    console.print(fit_table(summary_table(comfort), console))
    names = list(comfort["points"] if isinstance(comfort, dict) else comfort.points)
    console.print(points_legend(points, names))
    safety = safety_table(comfort)
    if safety is not None:
        console.print(fit_table(safety, console))
    for note in comfort["notes"] if isinstance(comfort, dict) else comfort.notes:
        console.print(f"note: {note}", markup=False)


@app.command()
def run(
    scenario_file: Annotated[Path | None, typer.Argument(help="Scenario YAML/JSON file")] = None,
    preset: Annotated[str | None, typer.Option("--preset", "-p", help="Preset name")] = None,
    output: Annotated[Path, typer.Option("--output", "-o", help="HDF5 results file")] = Path(
        "results.h5"
    ),
    duration: Annotated[float | None, typer.Option(help="Override the simulated time (s)")] = None,
    speed: Annotated[float | None, typer.Option(help="Override the running speed (km/h)")] = None,
    set_: Annotated[
        list[str] | None,
        typer.Option("--set", help="Override any field: PATH=VALUE, e.g. solver.dt=5e-5"),
    ] = None,
    body_model: Annotated[str | None, typer.Option(
        "--body-model", help="rigid or flexible: switches the car body and both frames; beam: "
        "the car body as a free–free beam (bodies.carbody.first_bending_hz), frames "
        "rigid")] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print the summary as JSON")] = False,
) -> None:
    """Simulate a scenario or preset, write the HDF5 file and print a summary."""
    from flexride.solver.simulate import simulate

    try:
        scenario = _load(scenario_file, preset,
                         command_overrides(set_, speed, body_model, duration))
        if as_json or not sys.stderr.isatty():
            results = simulate(scenario)
        else:
            with Progress(
                TextColumn("[bold]{task.description}"),
                BarColumn(),
                TextColumn("{task.percentage:>5.1f}%"),
                TimeElapsedColumn(),
                TimeRemainingColumn(),
                TextColumn("{task.fields[msg]}"),
                console=err_console,
                transient=True,
            ) as bar:
                task = bar.add_task(scenario.name, total=1.0, msg="")
                results = simulate(
                    scenario, progress=lambda f, m: bar.update(task, completed=f, msg=m)
                )
        t_write = time.perf_counter()
        path = results.write_hdf5(output)
        write_s = time.perf_counter() - t_write
    except FlexrideError as exc:
        _fail(str(exc))
    summary = run_summary(results, write_s)
    summary["output_file"] = str(path)
    if as_json:
        typer.echo(json.dumps(summary, indent=2, default=float))
    else:
        _print_summary(summary)
        if summary["comfort"] and "error" not in summary["comfort"]:
            _print_analysis(summary["comfort"], results.recorded_points)
        console.print(
            f"results written to [bold]{path}[/] (solver {summary['wall_time_solve_s']:.2f} s wall)"
        )


@app.command()
def presets(as_json: Annotated[bool, typer.Option("--json")] = False) -> None:
    """List the named scenarios."""
    from flexride.scenario.presets import PRESETS

    rows = [
        {"name": k, "description": v.get("description", ""), "speed_kmh": v.get("speed_kmh")}
        for k, v in PRESETS.items()
    ]
    if as_json:
        typer.echo(json.dumps(rows, indent=2))
        return
    table = Table(title="flexride presets")
    table.add_column("name")
    table.add_column("km/h", justify="right")
    table.add_column("description")
    for r in rows:
        table.add_row(r["name"], f"{r['speed_kmh']:g}", r["description"])
    console.print(fit_table(table, console))


@app.command()
def schema() -> None:
    """Print the JSON schema of a scenario."""
    from flexride.scenario.scenario import Scenario

    typer.echo(json.dumps(Scenario.model_json_schema(), indent=2))


@app.command()
def analyze(
    results_file: Annotated[Path, typer.Argument(help="HDF5 results file")],
    as_json: Annotated[bool, typer.Option("--json")] = False,
) -> None:
    """Ride comfort and running safety of a results file."""
    from flexride.results import Results

    try:
        from flexride.analysis import analyze as analyze_results

        results = Results.read_hdf5(results_file)
        summary = analyze_results(results)
    except FlexrideError as exc:
        _fail(str(exc))
    if as_json:
        typer.echo(json.dumps(summary.to_dict(), indent=2, default=float))
    else:
        _print_analysis(summary, results.recorded_points)


def _register_subcommands() -> None:
    """Service commands (``serve``, ``worker``), the finite-element tools (``fe``) and the
    contact-geometry tools (``contact``).
    """
    from flexride.cli.contact import contact_app
    from flexride.cli.critical_speed import critical_speed
    from flexride.cli.estimate import estimate_app
    from flexride.cli.fe import fe_app
    from flexride.cli.paper import paper_app
    from flexride.cli.service import register

    register(app)
    app.add_typer(fe_app, name="fe")
    app.add_typer(contact_app, name="contact")
    app.add_typer(estimate_app, name="estimate")
    app.command("critical-speed")(critical_speed)
    app.add_typer(paper_app, name="paper")


_register_subcommands()


def main() -> None:
    """Entry point of the ``flexride`` command."""
    app()


if __name__ == "__main__":
    main()
