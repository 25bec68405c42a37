"""``run_report``: the paper's study in one call — plan the runs, run them (cached), the Table 1
modal analysis, judge every claim, draw the figures, and write ``index.html``,
``summary.json`` and ``report.json`` into the report directory (atomically).

No model parameter is changed: every run is a paper preset (``flexride.scenario.presets``)
with only its speed, run length, body model, irregularity seed and the flexible bodies' mode
cut-off set (see :mod:`flexride.paper.plan`).
"""

from __future__ import annotations

import json
import os
import time
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from flexride import __version__
from flexride.analysis.sperling import spectral_form_text
from flexride.fileio import write_bytes_atomic
from flexride.paper import carbody_map
from flexride.paper.claims import evaluate_all
from flexride.paper.data import StudyData
from flexride.paper.figures import build_figures
from flexride.paper.html import finite, render_html
from flexride.paper.judge import VERDICTS
from flexride.paper.modal import car_body_modes
from flexride.paper.plan import ReportError, ReportOptions, RunSpec, build_plan
from flexride.paper.runner import RunCache, RunOutcome, run_study

__all__ = ["PAPER_TITLE", "ReportResult", "run_report"]

PAPER_TITLE = ("Dynamic evaluation on ride comfort of metro vehicle considering structural "
               "flexibility")

Progress = Callable[[str, int, int], None]
Runs = Callable[[list[RunSpec], Progress], RunOutcome]
"""``runs(plan, progress)``: the records of the plan's runs (default: :func:`run_study` with
the report directory's cache; the service reads its jobs' result files)."""


@dataclass
class ReportResult:
    """What :func:`run_report` wrote and found.

    Attributes
    ----------
    directory : pathlib.Path
        The report directory.
    claims : list of dict
        The judged claims (``summary.json``).
    counts : dict of str to int
        Claims per verdict.
    outcome : RunOutcome
        The runs (computed, reused, failed).
    wall_time_s : float
        Wall time of the whole report (s).
    """

    directory: Path
    claims: list[dict[str, Any]]
    counts: dict[str, int]
    outcome: RunOutcome
    wall_time_s: float

    @property
    def index(self) -> Path:
        """The report page."""
        return self.directory / "index.html"

    @property
    def summary(self) -> Path:
        """The claims as JSON."""
        return self.directory / "summary.json"


def _check_directory(directory: Path) -> None:
    if directory.exists() and not directory.is_dir():
        raise ReportError(f"{directory} exists and is not a directory")
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ReportError(f"cannot create the report directory {directory}: "
                          f"{exc.strerror}") from None


def _settings(options: ReportOptions, plan: list[RunSpec], modal: dict[str, Any]) -> list[str]:
    """Lines of the report's "How the study was run" list."""
    lines = [
        "Each run is a paper preset (paper-<condition>-<speed>): vehicle and track of Tables 4–5,"
        " what the paper does not give from B-type metro values (flexride.scenario.presets); "
        "'flexible' = car body and both bogie frames flexible (modal reduction of flexride's "
        "FE models, 2 % modal damping), 'rigid' = all rigid. No parameter is tuned to the "
        "paper.",
        f"Table 1: the flexible car body's FE model, {modal['element_size_m']:g} m elements "
        f"({modal['n_full_dof']} DOFs), modes to {modal['cutoff_hz']:g} Hz.",
        f"Sperling index: {spectral_form_text()}, of the dynamic part (docs/analysis.md); "
        "peaks are max |a| of the raw record, rms of the raw record.",
        "Rigid and flexible runs of a condition and speed run over the same irregularity "
        "sample (same seed)"
        + (f"; {options.seed_count()} realisations per random condition, values are means "
           "± 95 % CI (Student t)." if options.seed_count() > 1
           else "; one realisation (seed 1)."),
    ]
    for cond in options.conditions or ():
        specs = [s for s in plan if s.condition == cond and s.body == "flexible"]
        if not specs:
            continue
        windows = "; ".join(f"{s.speed_kmh:g} km/h: run {s.distance_m:.0f} m, evaluated "
                            f"{s.window_m[0]:.1f}–{s.window_m[1]:.1f} m"
                            for s in {s.speed_kmh: s for s in specs}.values())
        lines.append(f"{cond}: {windows}; flexible modes to {specs[0].cutoff_hz:g} Hz.")
    return lines


def _meta(options: ReportOptions, plan: list[RunSpec], modal: dict[str, Any],
          outcome: RunOutcome, counts: dict[str, int], wall: float) -> dict[str, Any]:
    return {"paper": PAPER_TITLE, "flexride_version": __version__,
            "generated": datetime.now(UTC).strftime("%Y-%m-%d %H:%M UTC"),
            "wall_time_s": wall, "runs_wall_time_s": outcome.runs_wall_time_s,
            "options": options.to_dict(),
            "runs": {"total": len(plan), "computed": outcome.computed,
                     "reused": outcome.reused, "failed": len(outcome.failures)},
            "failures": outcome.failures, "counts": counts,
            "settings": _settings(options, plan, modal), "modal": modal}


def _write(path: Path, data: bytes) -> None:
    """Write atomically, readable by others as an ordinary file would be (umask applies)."""
    write_bytes_atomic(path, data)
    mask = os.umask(0)
    os.umask(mask)
    path.chmod(0o666 & ~mask)


def _write_json(path: Path, data: Any) -> None:
    text = json.dumps(finite(data), indent=1, ensure_ascii=False, allow_nan=False)
    _write(path, (text + "\n").encode("utf-8"))


def run_report(directory: str | Path, options: ReportOptions | None = None,
               progress: Progress | None = None, *, plan: list[RunSpec] | None = None,
               runs: Runs | None = None) -> ReportResult:
    """Run the paper's study and write its report into ``directory``.

    Parameters
    ----------
    directory : str or pathlib.Path
        Report directory (created); run records are cached in ``directory/runs``.
    options : ReportOptions, optional
        What to run (default: the full study, one seed, one job per core).
    progress : callable(message, done, total), optional
        Called at each step and after every run.
    plan : list of RunSpec, optional
        The runs (default :func:`build_plan` of ``options``; the service passes the plan its
        study was made with).
    runs : callable(plan, progress) -> RunOutcome, optional
        Where the run records come from (default: simulated here, cached in
        ``directory/runs``).

    Returns
    -------
    ReportResult

    Raises
    ------
    ReportError
        Impossible options or an unusable directory.
    """
    from plotly.offline import get_plotlyjs

    t0 = time.perf_counter()
    say = progress or (lambda m, d, t: None)
    options = (options or ReportOptions()).checked()
    out = Path(directory)
    _check_directory(out)
    plan = build_plan(options) if plan is None else plan
    cmap = carbody_map.load_map()  # stored evidence on the car-body inputs: fail before the runs
    say("Table 1: modal analysis of the car body", 0, len(plan))
    modal = car_body_modes(options)
    if runs is None:
        outcome = run_study(plan, RunCache(out / "runs"), options.jobs or 1, say)
    else:
        outcome = runs(plan, say)
    data = StudyData(outcome.records, modal)
    say("judging the claims and drawing the figures", len(plan), len(plan))
    claims = carbody_map.annotate([r.to_dict() for r in evaluate_all(data)], cmap)
    tally = Counter(c["verdict"] for c in claims)
    counts = {v: tally.get(v, 0) for v in VERDICTS}
    figures = [*build_figures(data), *carbody_map.figures(cmap)]
    wall = time.perf_counter() - t0
    meta = _meta(options, plan, modal, outcome, counts, wall)
    _write_json(out / "summary.json", claims)
    _write_json(out / "report.json", meta)
    page = render_html(meta, claims, figures, get_plotlyjs(),
                       appendix=[carbody_map.section_html(cmap)])
    _write(out / "index.html", page.encode("utf-8"))
    return ReportResult(out, claims, counts, outcome, wall)
