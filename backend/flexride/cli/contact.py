"""``flexride contact …``: wheel–rail contact geometry of real profiles from the command line.

Commands: ``conicity`` (EN 15302 equivalent conicity of a profile pair or of a Δr table),
``table`` (rolling-radius difference, contact-angle difference, roll and contact positions
against the wheelset's lateral displacement, printed or exported as CSV/JSON) and ``profile``
(a built-in profile or a converted file written as plain text in mm). Profiles are the
built-in ``s1002`` wheel and ``60e1`` rail or files (SIMPACK ``.prw``/``.prr``, MiniProf
``.whl``/``.ban``, plain two-column text in mm). Options are in mm as the standards give them;
the library works in m. User errors end with one line on standard error and exit code 2.
"""

from __future__ import annotations

import csv
import io
import json
import math
import sys
from pathlib import Path
from typing import Annotated, Any, Literal, NoReturn

import numpy as np
import typer
from rich import box
from rich.console import Console
from rich.table import Table

from flexride.contact.placement import (
    FLANGE_BACK_MM,
    GAUGE_HEIGHT_MM,
    GAUGE_MM,
    R0_MM,
    Placement,
)
from flexride.contact.table_rows import (
    CONICITY_STEP_MM,
    CONICITY_Y_MAX_MM,
    conicity_rows,
)
from flexride.contact.table_rows import TABLE_COLUMNS as _TABLE_COLUMNS
from flexride.contact.table_rows import table_rows as _table_rows
from flexride.errors import FlexrideError, ScenarioError

contact_app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    help="Wheel–rail contact geometry of real profiles: equivalent conicity and contact tables.",
)
_out = Console(highlight=False, soft_wrap=True)
_err = Console(stderr=True, highlight=False, soft_wrap=True)

WheelOpt = Annotated[str, typer.Option("--wheel", help="s1002 or a wheel profile file.")]
RailOpt = Annotated[str, typer.Option("--rail", help="60e1 or a rail profile file.")]
InclOpt = Annotated[str, typer.Option("--inclination", help="Rail inclination: 1:40, 1:20, none.")]
GaugeOpt = Annotated[float, typer.Option("--gauge-mm", help="Track gauge (mm).")]
GaugeHOpt = Annotated[
    float, typer.Option("--gauge-height-mm", help="Gauge point below the top of rail (mm).")
]
FlangeBackOpt = Annotated[
    float, typer.Option("--flange-back-mm", help="Flange-back distance of the wheelset (mm).")
]
R0Opt = Annotated[float, typer.Option("--r0-mm", help="Nominal rolling radius (mm).")]

RollOpt = Annotated[
    bool,
    typer.Option("--roll/--no-roll",
                 help="Solve the wheelset roll from both wheels touching (default) or keep it 0."),
]
YMaxOpt = Annotated[float, typer.Option("--y-max-mm", help="Half range of the Δy grid (mm).")]
StepOpt = Annotated[float, typer.Option("--step-mm", help="Step of the Δy grid (mm).")]
JsonOpt = Annotated[bool, typer.Option("--json", help="Print JSON instead of a table.")]


def _fail(message: str) -> NoReturn:
    _err.print(f"error: {message}", markup=False)
    raise typer.Exit(2)


def _profile(spec: str, kind: Literal["wheel", "rail"]):
    from flexride.contact.profiles import rail_60e1, read_profile, s1002

    key = spec.strip().lower()
    if kind == "wheel" and key == "s1002":
        return s1002()
    if kind == "rail" and key in ("60e1", "uic60"):
        return rail_60e1()
    path = Path(spec)
    if not path.is_file():
        builtin = "s1002" if kind == "wheel" else "60e1"
        raise ScenarioError(f"--{kind}: {path.name}: no such file (built-in: {builtin})")
    return read_profile(path, kind)


def _setup(wheel: str, rail: str, inclination: str, gauge_mm: float, gauge_height_mm: float,
           flange_back_mm: float, r0_mm: float, roll: bool, y_max_mm: float, step_mm: float):
    from flexride.contact.placement import parse_inclination
    from flexride.contact.search import SearchSettings

    for name, value in (("--gauge-mm", gauge_mm), ("--gauge-height-mm", gauge_height_mm),
                        ("--flange-back-mm", flange_back_mm), ("--r0-mm", r0_mm),
                        ("--y-max-mm", y_max_mm), ("--step-mm", step_mm)):
        if not math.isfinite(value):
            raise ScenarioError(f"{name} must be a finite number, got {value!r}")
    placement = Placement(inclination=parse_inclination(inclination), gauge=gauge_mm * 1e-3,
                          gauge_height=gauge_height_mm * 1e-3,
                          flange_back=flange_back_mm * 1e-3, r0=r0_mm * 1e-3)
    settings = SearchSettings(y_max=y_max_mm * 1e-3, step=step_mm * 1e-3, roll=roll)
    return _profile(wheel, "wheel"), _profile(rail, "rail"), placement, settings


def _amplitudes(text: str | None) -> np.ndarray:
    from flexride.contact.conicity import DEFAULT_AMPLITUDES

    if not text:
        return DEFAULT_AMPLITUDES
    try:
        vals = [float(v) for v in text.replace(";", ",").split(",") if v.strip()]
    except ValueError as exc:
        raise ScenarioError(f"--amplitudes-mm must be comma-separated numbers, got {text!r}") \
            from exc
    if not vals or any(not (math.isfinite(v) and v > 0.0) for v in vals):
        raise ScenarioError(f"--amplitudes-mm must be positive amplitudes in mm, got {text!r}")
    return np.array(vals) * 1e-3


@contact_app.command("conicity")
def conicity_cmd(
    wheel: WheelOpt = "s1002",
    rail: RailOpt = "60e1",
    inclination: InclOpt = "1:40",
    gauge_mm: GaugeOpt = GAUGE_MM,
    gauge_height_mm: GaugeHOpt = GAUGE_HEIGHT_MM,
    flange_back_mm: FlangeBackOpt = FLANGE_BACK_MM,
    r0_mm: R0Opt = R0_MM,
    roll: RollOpt = True,
    delta_r: Annotated[
        Path | None,
        typer.Option("--delta-r", help="Δr table (CSV with header y_mm,delta_r_mm) instead of "
                                       "profiles."),
    ] = None,
    method: Annotated[
        str, typer.Option("--method", help="integration (EN 15302) or harmonic.")
    ] = "integration",
    amplitudes_mm: Annotated[
        str | None,
        typer.Option("--amplitudes-mm", help="Amplitudes (mm), comma-separated; default 1 … 7.5 "
                                             "in 0.5 steps."),
    ] = None,
    as_json: JsonOpt = False,
) -> None:
    """Equivalent conicity tan γe against the amplitude of the wheelset's lateral motion."""
    from flexride.contact.conicity import equivalent_conicity, read_delta_r_csv
    from flexride.contact.search import search_contact

    try:
        if method not in ("integration", "harmonic"):
            raise ScenarioError(f"--method must be integration or harmonic, got {method!r}")
        amps = _amplitudes(amplitudes_mm)
        if delta_r is not None:
            try:
                text = delta_r.read_text(encoding="utf-8-sig")
            except (OSError, UnicodeDecodeError) as exc:
                raise ScenarioError(f"--delta-r: {delta_r.name}: cannot read the file") from exc
            y, dr = read_delta_r_csv(text, delta_r.name)
            source = delta_r.name
        else:
            w, r, placement, settings = _setup(wheel, rail, inclination, gauge_mm,
                                               gauge_height_mm, flange_back_mm, r0_mm, roll,
                                               CONICITY_Y_MAX_MM, CONICITY_STEP_MM)
            geo = search_contact(w, r, placement, settings)
            y, dr = geo.y, geo.delta_r
            source = f"{w.name} on {r.name}"
        tan_ge = equivalent_conicity(y, dr, amps, method=method)  # type: ignore[arg-type]
    except FlexrideError as exc:
        _fail(str(exc))
    rows = conicity_rows(amps, tan_ge)
    if as_json:
        sys.stdout.write(json.dumps(rows, indent=1) + "\n")
        return
    table = Table(title=f"Equivalent conicity ({method}), {source}")
    table.add_column("amplitude (mm)", justify="right")
    table.add_column("tan γe", justify="right")
    for row in rows:
        t = row["tan_gamma_e"]
        table.add_row(f"{row['amplitude_mm']:g}", "—" if t is None else f"{t:.4f}")
    _out.print(table)


def _csv_text(rows: list[dict[str, Any]]) -> str:
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=[c for c, _ in _TABLE_COLUMNS], lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: ("" if v is None else v) for k, v in row.items()})
    return buf.getvalue()


@contact_app.command("table")
def table_cmd(
    wheel: WheelOpt = "s1002",
    rail: RailOpt = "60e1",
    inclination: InclOpt = "1:40",
    gauge_mm: GaugeOpt = GAUGE_MM,
    gauge_height_mm: GaugeHOpt = GAUGE_HEIGHT_MM,
    flange_back_mm: FlangeBackOpt = FLANGE_BACK_MM,
    r0_mm: R0Opt = R0_MM,
    roll: RollOpt = True,
    y_max_mm: YMaxOpt = 12.0,
    step_mm: StepOpt = 0.05,
    every_mm: Annotated[
        float | None,
        typer.Option("--every-mm", help="Row spacing (mm); default 0.5 on the terminal, every "
                                        "grid point in CSV/JSON."),
    ] = None,
    fmt: Annotated[
        str, typer.Option("--format", help="table, csv or json (default: from --output, else "
                                           "table).")
    ] = "",
    output: Annotated[
        Path | None, typer.Option("--output", help="Write CSV or JSON to this file.")
    ] = None,
    as_json: JsonOpt = False,
) -> None:
    """Contact geometry against the wheelset's lateral displacement (rigid contact points)."""
    from flexride.contact.search import search_contact

    try:
        kind = _table_format(fmt, as_json, output, every_mm)
        w, r, placement, settings = _setup(wheel, rail, inclination, gauge_mm, gauge_height_mm,
                                           flange_back_mm, r0_mm, roll, y_max_mm, step_mm)
        geo = search_contact(w, r, placement, settings)
    except FlexrideError as exc:
        _fail(str(exc))
    every = every_mm * 1e-3 if every_mm is not None else (5e-4 if kind == "table" else None)
    rows = _table_rows(geo, every)
    if kind == "table":
        _print_table(rows, f"Contact geometry, {w.name} on {r.name}{'' if roll else ' (no roll)'}")
        return
    if kind == "csv":
        text = _csv_text(rows)
    else:
        text = json.dumps({"columns": dict(_TABLE_COLUMNS), "rows": rows}, indent=1) + "\n"
    if output is None:
        sys.stdout.write(text)
        return
    _write_output(output, text, len(rows))


def _table_format(fmt: str, as_json: bool, output: Path | None, every_mm: float | None) -> str:
    """Output format of ``contact table`` from its options, checking them.

    Parameters
    ----------
    fmt : str
        ``--format`` ("" when not given).
    as_json : bool
        ``--json``.
    output : Path or None
        ``--output`` file (its suffix picks the format when none is given).
    every_mm : float or None
        ``--every-mm`` row spacing (mm), checked to be positive.

    Returns
    -------
    str
        ``"table"``, ``"csv"`` or ``"json"``.
    """
    kind = fmt or ("json" if as_json else "")
    if not kind and output is not None:
        kind = {".csv": "csv", ".json": "json"}.get(output.suffix.lower(), "")
        if not kind:
            raise ScenarioError(f"--output {output.name}: use a .csv or .json file or give "
                                "--format")
    kind = kind or "table"
    if kind not in ("table", "csv", "json"):
        raise ScenarioError(f"--format must be table, csv or json, got {fmt!r}")
    if kind == "table" and output is not None:
        raise ScenarioError("--output needs --format csv or json")
    if every_mm is not None and not (math.isfinite(every_mm) and every_mm > 0.0):
        raise ScenarioError(f"--every-mm must be positive, got {every_mm!r}")
    return kind


def _print_table(rows: list[dict[str, Any]], title: str) -> None:
    """Print the rows of ``contact table`` as a terminal table.

    Parameters
    ----------
    rows : list of dict
        Rows from :func:`_table_rows` (lengths in mm, angles in rad; roll shown in mrad).
    title : str
        Table title.
    """
    t = Table(title=title,
              caption="Δy, Δr, wheel s, track y in mm; Δγ in rad; roll in mrad; "
                      "2-pt: two-point contact (L, R)",
              box=box.SIMPLE_HEAD, pad_edge=False)
    for head in ("Δy", "Δr", "Δγ", "roll", "wheel L", "wheel R", "track L", "track R",
                 "2-pt"):
        t.add_column(head, justify="right", no_wrap=True)

    def f(v: Any, spec: str, scale: float = 1.0) -> str:
        return "—" if v is None else format(v * scale, spec)

    for row in rows:
        two = ("L" if row["two_point_left"] else "") + ("R" if row["two_point_right"] else "")
        t.add_row(f(row["dy_mm"], ".2f"), f(row["dr_mm"], ".4f"), f(row["dgamma_rad"], ".4f"),
                  f(row["roll_rad"], ".4f", 1e3), f(row["wheel_left_mm"], ".2f"),
                  f(row["wheel_right_mm"], ".2f"), f(row["track_left_mm"], ".2f"),
                  f(row["track_right_mm"], ".2f"), two)
    Console(highlight=False, width=max(_out.width, 100)).print(t)


def _write_output(output: Path, text: str, n_rows: int, what: str = "rows") -> None:
    """Write the text of ``contact table`` or ``contact profile`` to ``output`` atomically.

    Parameters
    ----------
    output : Path
        Destination file.
    text : str
        File content.
    n_rows : int
        Number of rows, for the confirmation line.
    what : str
        What the rows are, for the confirmation line.
    """
    try:
        from flexride.fileio import atomic_path

        with atomic_path(output) as tmp:
            tmp.write_text(text, encoding="utf-8")
    except OSError as exc:
        _fail(f"--output {output.name}: cannot write ({exc.strerror or exc})")
    _out.print(f"wrote {n_rows} {what} to {output.name}")


@contact_app.command("profile")
def profile_cmd(
    kind: Annotated[Literal["wheel", "rail"], typer.Argument(help="wheel or rail.")],
    source: Annotated[str, typer.Argument(
        help="s1002 (wheel), 60e1 (rail) or a profile file to convert.")],
    output: Annotated[Path, typer.Option("--output", "-o", help="Text file to write.")],
    every_mm: Annotated[float, typer.Option(
        "--every-mm", help="Least lateral distance between written points (mm).")] = 0.5,
) -> None:
    """Write a profile as plain text (y, z in mm; flexride's convention: y toward the field
    side, z up; a wheel's taping line at y = 0): a built-in profile to look at, edit (e.g.
    as a worn variant) or upload to the service, or a SIMPACK/MiniProf file converted.
    """
    try:
        if not (math.isfinite(every_mm) and every_mm > 0):
            raise ScenarioError(f"--every-mm must be a positive number, got {every_mm!r}")
        prof = _profile(source, kind)
    except FlexrideError as err:
        _fail(str(err))
    y_mm, z_mm = prof.y * 1e3, prof.z * 1e3
    keep = [0]
    for i in range(1, y_mm.size - 1):
        if y_mm[i] - y_mm[keep[-1]] >= every_mm:
            keep.append(i)
    keep.append(y_mm.size - 1)
    lines = [f"# {prof.name}: {kind} profile, y z in mm (y toward the field side, z up)"]
    lines += [f"{y_mm[i]:.6f} {z_mm[i]:.6f}" for i in keep]
    _write_output(output, "\n".join(lines) + "\n", len(keep), "points")
