"""``flexride fe …``: finite-element car body and bogie frame from the command line.

Commands: ``modes`` (modal table and mass properties of a default model), ``reduce`` (reduction
report), ``calibrate`` (model updating against typed target frequencies or measured modes),
``convergence`` (natural frequencies against element size, with the observed order and GCI)
and ``export`` (mesh and mode shapes as JSON). Every command takes ``--json``. User errors end with
one line on standard error and exit code 2.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, NoReturn

import numpy as np
import typer
from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

from flexride.errors import FlexrideError

if TYPE_CHECKING:
    from flexride.fem.reduce import Method
    from flexride.fem.vehicle_models import Kind

fe_app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    help="Finite-element models of the car body and bogie frame: modes, reductions, calibration.",
)
_out = Console(highlight=False, soft_wrap=True)
_err = Console(stderr=True, highlight=False, soft_wrap=True)

KindArg = Annotated[str, typer.Argument(help="carbody or frame")]
JsonOpt = Annotated[bool, typer.Option("--json", help="Print JSON instead of a table.")]
SizeOpt = Annotated[
    float,
    typer.Option("--element-size", help="Car-body shell element size (m).", min=0.05, max=1.0),
]
PresetOpt = Annotated[str, typer.Option("--preset", help="Preset whose vehicle is used.")]


def _fail(message: str) -> NoReturn:
    _err.print(f"error: {message}", markup=False)
    raise typer.Exit(2)


def _vehicle(preset: str):
    from flexride.scenario.presets import load_preset

    return load_preset(preset).vehicle


def _build_body(kind: str, preset: str, method: str, cutoff: float, element_size: float,
                use_cache: bool = True, calibration=None):
    """The reduced default body (or the car body calibrated to ``calibration``) for the
    ``reduce`` and ``export`` commands: options checked first, any flexride error as one
    line and a non-zero exit.
    """
    try:
        from flexride.fem.flexible import build_flexible_body

        reduction = _method(method)
        if not (cutoff > 0 and np.isfinite(cutoff)):
            _fail(f"--cutoff must be a positive frequency in Hz, got {cutoff}")

        def progress(n: int, f) -> None:
            _err.print(f"  calibration evaluation {n}: "
                       + ", ".join("-" if np.isnan(v) else f"{v:.3f}" for v in f) + " Hz")

        return build_flexible_body(_kind(kind), _vehicle(preset), method=reduction,
                                   cutoff_hz=cutoff, element_size=element_size, name=kind,
                                   use_cache=use_cache, calibration=calibration,
                                   calibration_progress=progress)
    except FlexrideError as exc:
        _fail(str(exc))


def _calibration(kind: str, targets: str | None, variables: str, max_evaluations: int):
    """The car-body calibration of ``--calibration-targets`` … (the schema of a scenario's
    ``bodies.carbody.calibration``; its errors as one line), or None without targets.
    """
    from pydantic import ValidationError

    from flexride.scenario.bodies import CarBodyCalibration

    if targets is None:
        return None
    if kind != "carbody":
        _fail("--calibration-targets: a calibration is the car body's; the frame has none")
    data: dict = {"targets": targets, "max_evaluations": max_evaluations}
    names = [v.strip() for v in variables.split(",") if v.strip()]
    if names:
        data["variables"] = names
    try:
        return CarBodyCalibration.model_validate(data)
    except ValidationError as exc:
        err = exc.errors()[0]
        where = ".".join(str(p) for p in err["loc"]) or "calibration"
        _fail(f"--calibration-{where.split('.')[0].replace('_', '-')}: "
              f"{str(err['msg']).removeprefix('Value error, ')}")


CalTargetsOpt = Annotated[str | None, typer.Option(
    "--calibration-targets", help="Car body: calibrate it first to targets FREQ[:TYPE],… "
    "(Hz; the spelling of calibrate --targets and of bodies.carbody.calibration.targets).",
    show_default=False)]
CalVariablesOpt = Annotated[str, typer.Option(
    "--calibration-variables", help="Comma-separated calibration variables (default: those "
    "of the default body's calibration).")]
CalBudgetOpt = Annotated[int, typer.Option(
    "--calibration-max-evaluations", help="Budget of FE evaluations of the calibration.")]


_KINDS: tuple[Kind, ...] = ("carbody", "frame")


def _kind(kind: str) -> Kind:
    for k in _KINDS:
        if k == kind:
            return k
    _fail(f"unknown body {kind!r}: use carbody or frame")


def _method(method: str) -> Method:
    from flexride.fem.reduce import METHODS

    for m in METHODS:
        if m == method:
            return m
    _fail(f"unknown method {method!r}: use one of {', '.join(METHODS)}")


def _print_json(data) -> None:
    sys.stdout.write(json.dumps(data, indent=1) + "\n")


@fe_app.command("modes")
def modes_cmd(
    kind: KindArg,
    as_json: JsonOpt = False,
    element_size: SizeOpt = 0.2,
    n_modes: Annotated[int, typer.Option("--n-modes", min=1, max=200)] = 12,
    preset: PresetOpt = "paper-metro",
) -> None:
    """Free–free modes (frequency, classification) and mass properties of a default model."""
    try:
        from flexride.fem.classify import classify_mode, classify_plane_frame_mode
        from flexride.fem.eigen import free_free_modes
        from flexride.fem.report import mass_summary
        from flexride.fem.rigid import rigid_body_vectors
        from flexride.fem.vehicle_models import build_fe_model

        model, target = build_fe_model(_kind(kind), _vehicle(preset), element_size)
        K, M = model.assemble()
        modes = free_free_modes(K, M, rigid_body_vectors(model.nodes), n_elastic=n_modes)
        rows = []
        for k in range(6, modes.frequencies.size):
            phi = modes.shapes[:, k]
            if kind == "frame":
                c = classify_plane_frame_mode(phi, M, model.nodes)
            else:
                c = classify_mode(phi, M, model.nodes, model.node_region, model.region_names)
            rows.append({"mode": k - 5, "frequency_hz": float(modes.frequencies[k]), "type": c})
        mass = mass_summary(model.mass_properties(), target)
    except FlexrideError as exc:
        _fail(str(exc))
    data = {
        "body": kind,
        "element_size_m": element_size if kind == "carbody" else model.info["element_size"],
        "n_nodes": int(model.mesh.n_nodes),
        "n_dof": int(model.n_dof),
        "rigid_frequencies_hz": [float(v) for v in modes.frequencies[:6]],
        "modes": rows,
        "mass": mass,
        "mass_groups_kg": model.info.get("mass_groups_kg", {}),
    }
    if as_json:
        _print_json(data)
        return
    _out.print(
        f"{kind}: {data['n_nodes']} nodes, {data['n_dof']} DOFs, element size "
        f"{data['element_size_m']:g} m"
    )
    _print_mass(mass)
    _out.print(f"{'mode':>4} {'f (Hz)':>9}  type")
    for r in rows:
        _out.print(f"{r['mode']:4d} {r['frequency_hz']:9.3f}  {r['type']}")


def _print_mass(m: dict) -> None:
    _out.print(
        f"mass {m['mass_kg']:.1f} kg; CG ({m['cg_m'][0]:.3f}, {m['cg_m'][1]:.3f}, "
        f"{m['cg_m'][2]:.3f}) m; Ixx/Iyy/Izz "
        + " / ".join(f"{v:.1f}" for v in m["inertia_diag_kgm2"])
        + " kg·m²"
    )
    if "errors" in m:
        e = m["errors"]
        _out.print(
            f"vs vehicle parameters: mass {100 * e['mass']:+.2f} %, Ixx {100 * e['ixx']:+.2f} %, "
            f"Iyy {100 * e['iyy']:+.2f} %, Izz {100 * e['izz']:+.2f} %, "
            f"CG height {1000 * e['cg_m'][2]:+.1f} mm"
        )


def _calibration_lines(cal: dict) -> str:
    """The calibration of a built body: targets, pairs with their errors, values."""
    state = "from the FE cache" if cal.get("from_cache") else f"{cal['seconds']:.0f} s"
    lines = [f"calibrated to {cal['targets']} ({cal['n_evaluations']} of at most "
             f"{cal['max_evaluations']} FE evaluations, {state}; "
             f"{'all' if cal['success'] else 'NOT all'} within ±{100 * cal['tolerance']:g} %):"]
    for p in cal["pairs"]:
        lines.append(f"  {p['target_hz']:7.3f} Hz {p['target_type'] or '(any)':<24} -> mode "
                     f"{p['mode']:>2} {p['model_hz']:7.3f} Hz {100 * p['error']:+6.2f} %  "
                     f"{p['model_type']}")
    lines.append("  values: " + ", ".join(f"{k} {v:.5g}" for k, v in cal["values"].items()))
    return "\n".join(lines)


@fe_app.command("reduce")
def reduce_cmd(
    kind: KindArg,
    method: Annotated[
        str, typer.Option("--method", help="guyan, craig-bampton or modal")
    ] = "modal",
    cutoff: Annotated[float, typer.Option("--cutoff", help="Cut-off frequency (Hz).")] = 100.0,
    as_json: JsonOpt = False,
    element_size: SizeOpt = 0.2,
    preset: PresetOpt = "paper-metro",
    max_rows: Annotated[int, typer.Option("--rows", min=1)] = 40,
    no_cache: Annotated[
        bool, typer.Option("--no-cache", help="Rebuild, do not use the cache.")
    ] = False,
    calibration_targets: CalTargetsOpt = None,
    calibration_variables: CalVariablesOpt = "",
    calibration_max_evaluations: CalBudgetOpt = 30,
) -> None:
    """Reduce a default (or calibrated) model and print the reduction report."""
    cal = _calibration(kind, calibration_targets, calibration_variables,
                       calibration_max_evaluations)
    fb = _build_body(kind, preset, method, cutoff, element_size, use_cache=not no_cache,
                     calibration=cal)
    if as_json:
        d = fb.report.to_dict()
        d["build_seconds"] = fb.build_seconds
        d["from_cache"] = fb.from_cache
        d["calibration"] = fb.calibration
        _print_json(d)
        return
    if fb.calibration is not None:
        _out.print(_calibration_lines(fb.calibration), markup=False)
    _out.print(fb.report.table(max_rows=max_rows), markup=False)
    _out.print(
        f"({'loaded from cache' if fb.from_cache else 'built'} in {fb.build_seconds:.2f} s)",
        markup=False,
    )


def _calibration_targets(targets: str | None, measured: Path | None):
    """The targets (and sensors) of ``calibrate``: typed or untyped frequencies, a modal-test
    file, or paper Table 1 (untyped) when neither is given.
    """
    from flexride.fem.defaults import PAPER_TABLE1_HZ
    from flexride.fem.modal_test import read_modal_test
    from flexride.fem.targets import ModeTarget, parse_targets

    if targets is not None and measured is not None:
        _fail("give --targets or --measured, not both")
    if measured is not None:
        test = read_modal_test(measured)
        return test.targets, test.sensors
    if targets is None:
        return [ModeTarget(f) for f in PAPER_TABLE1_HZ], None
    return parse_targets(targets), None


def _calibrate_help() -> str:
    from flexride.fem.mode_types import MODE_TYPES

    types = "; ".join(f"'{k}'" for k in MODE_TYPES)
    return (
        "Update car-body panel sections and mass split so that the model modes paired with the "
        "targets hit their frequencies.\n\n"
        "Targets: --targets FREQ[:TYPE],… (Hz, any order), e.g. "
        "'5.03:torsion,6.11:rhombic,8.84:first vertical bending'; a typed target is paired "
        "only with a model mode of its type, an untyped one with the nearest free mode in "
        f"frequency. Types: {types}; bending and torsion may start with an order (first, "
        "second …). Or --measured FILE: a modal-test CSV (x_m,y_m,z_m,direction, then one "
        "mode_<f>Hz column per mode; docs/fem.md), paired by MAC at the sensors. Without "
        "either: paper Table 1, untyped. Targets whose type no computed mode has are reported "
        "as NOT PAIRED."
    )


@fe_app.command("calibrate", help=_calibrate_help())
def calibrate_cmd(
    targets: Annotated[str | None, typer.Option(
        "--targets", help="Targets FREQ[:TYPE],… in Hz, e.g. '6.11:rhombic,8.84:first vertical "
        "bending' (default: paper Table 1, untyped).", show_default=False)] = None,
    measured: Annotated[Path | None, typer.Option(
        "--measured", help="Modal-test CSV: sensors and measured mode shapes (docs/fem.md).")
    ] = None,
    as_json: JsonOpt = False,
    element_size: SizeOpt = 0.2,
    max_evaluations: Annotated[int, typer.Option("--max-evaluations", min=1, max=2000)] = 90,
    variables: Annotated[
        str, typer.Option("--variables", help="Comma-separated calibration variables.")
    ] = "",
    n_modes: Annotated[int | None, typer.Option(
        "--n-modes", min=1, max=200, help="Model modes computed and classified per evaluation "
        "(default: 3 × targets, at least targets + 6).", show_default=False)] = None,
    min_mac: Annotated[float, typer.Option(
        "--min-mac", min=0.0, max=1.0, help="Least MAC of a pair with a measured mode.")] = 0.5,
    preset: PresetOpt = "paper-metro",
) -> None:
    """Calibrate the car body against typed targets or measured modes (help: above)."""
    from flexride.fem.calibration import DEFAULT_VARIABLES, calibrate_carbody
    from flexride.fem.vehicle_models import carbody_params_for, carbody_target

    names = tuple(v.strip() for v in variables.split(",") if v.strip()) or DEFAULT_VARIABLES
    try:
        goals, sensors = _calibration_targets(targets, measured)
        vehicle = _vehicle(preset)

        def progress(n: int, f) -> None:
            if not as_json:
                _err.print(f"  evaluation {n}: "
                           + ", ".join("-" if np.isnan(v) else f"{v:.3f}" for v in f) + " Hz")

        res = calibrate_carbody(
            goals,
            carbody_target(vehicle),
            base=carbody_params_for(vehicle),
            variables=names,
            element_size=element_size,
            max_evaluations=max_evaluations,
            progress=progress,
            n_modes=n_modes,
            sensors=sensors,
            min_mac=min_mac,
        )
    except FlexrideError as exc:
        _fail(str(exc))
    if as_json:
        _print_json(res.to_dict())
        return
    _out.print(res.table(), markup=False)
    _out.print("calibrated values (paste into flexride/fem/defaults.py CARBODY_CALIBRATED):")
    _out.print(json.dumps({k: round(v, 6) for k, v in res.values.items()}), markup=False)
    if res.unpaired:
        _err.print(f"warning: {len(res.unpaired)} target(s) NOT PAIRED with a model mode "
                   "(reasons above)", markup=False)


@fe_app.command("convergence")
def convergence_cmd(
    kind: KindArg,
    sizes: Annotated[str, typer.Option(
        "--sizes", help="Element sizes in m, comma-separated, at least three (default: car "
        "body 0.5,0.4,0.3,0.2 and with --response 0.5,0.4,0.3,0.2,0.15,0.1; frame "
        "0.2,0.1,0.05).", show_default=False)] = "",
    n_modes: Annotated[int, typer.Option("--n-modes", min=1, max=60,
                                         help="Elastic modes of the finest mesh followed.")] = 8,
    response: Annotated[bool, typer.Option(
        "--response", help="Run the flexible vehicle at each size (the study preset "
        "mesh-convergence: the paper's Fig. 4) and judge the air-spring forces, first "
        "frequencies and comfort indices instead of the natural frequencies alone.")] = False,
    conditions: Annotated[str, typer.Option(
        "--conditions", help="With --response: conditions, comma-separated "
        "(smooth-straight and the paper's).")] = "smooth-straight,random-straight",
    speed: Annotated[float, typer.Option("--speed", min=1.0, max=400.0,
                                         help="With --response: speed (km/h).")] = 80.0,
    as_json: JsonOpt = False,
    preset: PresetOpt = "paper-metro",
) -> None:
    """Natural frequencies against element size: each mode of the finest mesh followed to the
    coarser ones, with its observed order, extrapolated frequency and GCI (three finest).
    """
    body = _kind(kind)
    default = ("0.5,0.4,0.3,0.2,0.15,0.1" if response else "0.5,0.4,0.3,0.2") \
        if body == "carbody" else "0.2,0.1,0.05"
    try:
        values = [float(v) for v in (sizes or default).split(",") if v.strip()]
    except ValueError:
        _fail(f"--sizes must be numbers in m separated by commas, got {sizes!r}")
    try:
        if response:
            _response_convergence(body, values, conditions, speed, preset, as_json)
        else:
            _frequency_convergence(body, values, n_modes, preset, as_json)
    except FlexrideError as exc:
        _fail(str(exc))


def _progress_bar(as_json: bool) -> Progress:
    return Progress(TextColumn("[bold]{task.description}"), BarColumn(),
                    TextColumn("{task.fields[msg]}"), TimeElapsedColumn(), console=_err,
                    transient=True, disable=as_json)


def _frequency_convergence(body: Kind, sizes: list[float], n_modes: int, preset: str,
                           as_json: bool) -> None:
    from flexride.fem.mesh_study import frequency_convergence

    with _progress_bar(as_json) as bar:
        task = bar.add_task(f"{body} meshes", total=len(set(sizes)), msg="")

        def progress(done: int, total: int, size: float) -> None:
            bar.update(task, completed=done, msg=f"{size:g} m done")

        res = frequency_convergence(body, _vehicle(preset), sizes, n_modes, progress)
    if as_json:
        _print_json(res.to_dict())
        return
    dofs = ", ".join(f"{m.element_size:g} m: {m.n_dof} DOFs {m.seconds:.1f} s"
                     for m in res.meshes)
    _out.print(f"{body} natural frequencies against element size ({dofs})", markup=False)
    _out.print(res.table(), markup=False)


def _response_convergence(body: Kind, sizes: list[float], conditions: str, speed: float,
                          preset: str, as_json: bool) -> None:
    from flexride.study.aggregate import study_tables
    from flexride.study.expand import expand_study
    from flexride.study.local_run import run_plan
    from flexride.study.mesh_convergence import study_request
    from flexride.study.mesh_verdict import format_table

    names = [c.strip() for c in conditions.split(",") if c.strip()]
    request = study_request("carbody" if body == "carbody" else "frames", sizes, names, speed)
    request["base"] = {"preset": preset}
    plan = expand_study(request, max_jobs=200)
    with _progress_bar(as_json) as bar:
        task = bar.add_task("runs", total=len(plan.jobs), msg="")

        def progress(i: int, n: int, fraction: float, message: str) -> None:
            job = plan.jobs[i]
            bar.update(task, completed=i + fraction, msg=f"{job.name}: {message}")

        jobs = run_plan(plan, progress)
    tables = study_tables(jobs)
    if as_json:
        _print_json({"request": request, "mesh_convergence": tables["mesh_convergence"],
                     "notes": tables["notes"]})
        return
    for table in tables["mesh_convergence"]:
        _out.print(format_table(table), markup=False)
        _out.print("")
    for note in tables["notes"]:
        _err.print(f"note: {note}", markup=False)


@fe_app.command("export")
def export_cmd(
    kind: KindArg,
    out: Annotated[Path, typer.Option("--out", help="Output JSON file ('-' for stdout).")] = Path(
        "-"
    ),
    method: Annotated[str, typer.Option("--method")] = "modal",
    cutoff: Annotated[float, typer.Option(
        "--cutoff", help="Cut-off frequency (Hz); the default is a scenario body's.")] = 40.0,
    n_modes: Annotated[int, typer.Option("--n-modes", min=0, max=500)] = 12,
    element_size: SizeOpt = 0.2,
    preset: PresetOpt = "paper-metro",
    calibration_targets: CalTargetsOpt = None,
    calibration_variables: CalVariablesOpt = "",
    calibration_max_evaluations: CalBudgetOpt = 30,
) -> None:
    """Mesh and mode shapes as JSON for a browser (of the calibrated car body with
    --calibration-targets: then ``calibration`` holds the calibrated values and the pairing).
    """
    cal = _calibration(kind, calibration_targets, calibration_variables,
                       calibration_max_evaluations)
    fb = _build_body(kind, preset, method, cutoff, element_size, calibration=cal)
    data = fb.export(max_modes=n_modes)
    if fb.calibration is not None:
        data["calibration"] = fb.calibration
    text = json.dumps(data)
    if str(out) == "-":
        sys.stdout.write(text + "\n")
    else:
        try:
            out.write_text(text, encoding="utf-8")
        except OSError as exc:
            _fail(f"cannot write {out}: {exc}")
        _out.print(f"wrote {out} ({len(text) / 1e6:.1f} MB)")
