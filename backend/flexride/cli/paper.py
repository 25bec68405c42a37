"""``flexride paper report``: the paper's study in one command, with every table, figure and
stated finding of the paper beside flexride's result (:mod:`flexride.paper`). User errors end
with one line on standard error and exit code 2.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Annotated, NoReturn

import typer
from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

from flexride.errors import FlexrideError

paper_app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    help="The paper reproduced: its study, tables, figures and findings beside flexride's.",
)
_out = Console(highlight=False, soft_wrap=True)
_err = Console(stderr=True, highlight=False, soft_wrap=True)


def _fail(message: str) -> NoReturn:
    _err.print(f"error: {message}", markup=False)
    raise typer.Exit(2)


def _floats(text: str | None, what: str) -> tuple[float, ...] | None:
    if text is None:
        return None
    try:
        return tuple(float(v) for v in text.split(",") if v.strip())
    except ValueError:
        _fail(f"{what} must be comma-separated numbers, got {text!r}")


def _words(text: str | None) -> tuple[str, ...] | None:
    return None if text is None else tuple(v.strip() for v in text.split(",") if v.strip())


def _run(output: Path, options, quiet: bool):
    from flexride.paper import report as paper_report

    if quiet:
        return paper_report.run_report(output, options)
    with Progress(TextColumn("[bold]{task.description}"), BarColumn(),
                  TextColumn("{task.fields[count]}"), TimeElapsedColumn(),
                  TextColumn("{task.fields[msg]}"), console=_err, transient=True) as bar:
        task = bar.add_task("paper study", total=None, msg="", count="")

        def progress(message: str, done: int, total: int) -> None:
            bar.update(task, completed=done, total=total or None, msg=message,
                       count=f"{done}/{total} runs" if total else "")
            if done and total:
                _err.print(f"  {message}", markup=False)

        return paper_report.run_report(output, options, progress=progress)


@paper_app.command("report")
def report(
    output: Annotated[Path, typer.Option("--output", "-o", help="Report directory")],
    quick: Annotated[bool, typer.Option(
        "--quick", help="Shortened study: 50 and 80 km/h, 1/4 of each evaluated stretch")] = False,
    seeds: Annotated[int | None, typer.Option(
        help="Irregularity realisations per random condition (mean ± 95 % CI); "
        "default 5, 1 with --quick")] = None,
    jobs: Annotated[int | None, typer.Option(
        help="Worker processes (default: the number of cores)")] = None,
    distance_scale: Annotated[float | None, typer.Option(
        "--distance-scale", hidden=True, help="Factor on the evaluated stretches")] = None,
    speeds: Annotated[str | None, typer.Option(
        hidden=True, help="Comma-separated speeds (km/h)")] = None,
    conditions: Annotated[str | None, typer.Option(
        hidden=True, help="Comma-separated conditions of Table 3")] = None,
    min_eval_s: Annotated[float, typer.Option(
        "--min-eval-s", hidden=True, help="Shortest evaluated stretch (s)")] = 6.0,
    mesh_sizes: Annotated[str | None, typer.Option(
        "--mesh-sizes", help="Car-body element sizes (m) of the element-size pre-calculation "
        "(Fig. 4), comma-separated, or 'none'; default 0.5,0.4,0.3,0.2,0.15,0.1 "
        "(0.4,0.3,0.2 with --quick)")] = None,
) -> None:
    """Run the paper's study and write DIR/index.html (the report), DIR/summary.json (the
    claims and their verdicts) and DIR/report.json; run records are cached in DIR/runs.
    """
    from flexride.paper.plan import ReportOptions

    options = ReportOptions(quick=quick, seeds=seeds, jobs=jobs, distance_scale=distance_scale,
                            speeds=_floats(speeds, "--speeds"), conditions=_words(conditions),
                            min_eval_s=min_eval_s,
                            mesh_sizes=() if mesh_sizes == "none" else _floats(mesh_sizes,
                                                                               "--mesh-sizes"))
    try:
        result = _run(output, options, quiet=not sys.stderr.isatty())
    except FlexrideError as exc:
        _fail(str(exc))
    counts = ", ".join(f"{n} {k}" for k, n in result.counts.items())
    runs = result.outcome
    _out.print(f"{len(result.claims)} claims: {counts}")
    _out.print(f"runs: {runs.computed} computed, {runs.reused} from the cache, "
               f"{len(runs.failures)} failed; {result.wall_time_s:.0f} s")
    _out.print(f"report: {result.index}")
    _out.print(f"claims: {result.summary}")
