"""The paper report as a kind of study: ``POST /api/v1/studies`` with
``{"preset": "paper-report", "quick": true, "seeds": N}``.

* **Runs.** The runs are those of ``flexride paper report`` (:func:`flexride.paper.plan.
  build_plan` of the request's ``quick`` and ``seeds``), submitted as the study's simulation
  jobs; their number is fixed by the plan (and bounded by ``FLEXRIDE_MAX_STUDY_JOBS``), the
  other study fields (axes, base, overrides) are refused. The study keeps the options and the
  plan's runs in its record (``spec["report"]``), so the report is built from the runs the
  jobs ran.
* **Report.** When every job has finished, one job of kind ``paper_report``
  (:data:`REPORT_KIND`, content key :func:`report_key`) reads the jobs' result files, makes
  each run's record as the CLI does (:func:`flexride.paper.record.record_from_results`) and
  writes the report through :func:`flexride.paper.run_report` into a temporary directory,
  then renames it to :func:`report_dir` — ``<results>/reports/<study id>/`` — in one step.
"""

from __future__ import annotations

import os
import shutil
import time
import uuid
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from flexride.errors import FlexrideError, ScenarioError, SimulationCancelled
from flexride.paper.plan import ReportError, ReportOptions, RunSpec, build_plan
from flexride.study.expand import Axis, Level, PlannedJob, StudyPlan, StudyTooLarge
from flexride.study.mesh_convergence import CARBODY_MESH_AXIS as MESH_AXIS
from flexride.study.seeds import SEED_AXIS

if TYPE_CHECKING:
    from flexride.paper.runner import RunOutcome
    from flexride.store import Job

__all__ = ["REPORT_KIND", "REPORT_PRESET", "expand_report", "report_dir", "report_key",
           "report_options", "run_paper_report"]

REPORT_PRESET = "paper-report"
"""Study preset of the report kind of study."""
REPORT_KIND = "paper_report"
"""Job kind that builds a report study's report."""
REPORTS_DIR = "reports"
"""Directory of the reports under the results directory."""
REPORT_FILES = ("index.html", "summary.json")
"""The files the API serves (``report.json`` lies beside them)."""
_FIXED = ("base", "conditions", "speeds_kmh", "body_models", "parameters", "overrides",
          "section", "cutoff")


def report_key(study_id: str) -> str:
    """Content key (``scenario_hash``) of the report job of a study."""
    return f"report-{study_id}"


def report_dir(results_root: Path, study_id: str) -> Path:
    """Where the service keeps a study's report: ``<results>/reports/<study id>``.

    ``study_id`` is a study record's id (32 hex digits), never a path from a request.
    """
    if not study_id.isalnum():
        raise ValueError(f"not a study id: {study_id!r}")
    return Path(results_root) / REPORTS_DIR / study_id


def report_options(request: Mapping[str, Any]) -> ReportOptions:
    """The report's options from a study request (``quick``, ``seeds``), checked.

    Raises
    ------
    ScenarioError
        Options the report cannot run.
    """
    try:
        return ReportOptions(quick=bool(request.get("quick")),
                             seeds=request.get("seeds"), jobs=1).checked()
    except ReportError as exc:
        raise ScenarioError.at(("seeds",), str(exc), "study") from None


def _axes(specs: list[RunSpec]) -> list[Axis]:
    def axis(name: str, values: list[Any]) -> Axis:
        return Axis(name, [Level(v, {}) for v in dict.fromkeys(values)])

    axes = [axis("condition", [s.condition for s in specs]),
            axis("speed_kmh", sorted(s.speed_kmh for s in specs)),
            axis("body_model", [s.body for s in specs]),
            axis(SEED_AXIS, sorted(s.seed or 1 for s in specs))]
    sizes = [s.element_size_m for s in specs if s.element_size_m is not None]
    if sizes:
        axes.append(axis(MESH_AXIS, sorted(sizes)))
    return axes


def _job_axes(spec: RunSpec) -> dict[str, Any]:
    """A run's values of the study's axes (the pre-calculation's runs with their element
    size, so the study's tables show them against it).
    """
    axes: dict[str, Any] = {"condition": spec.condition, "speed_kmh": spec.speed_kmh,
                            "body_model": spec.body, SEED_AXIS: spec.seed or 1}
    if spec.element_size_m is not None:
        axes[MESH_AXIS] = spec.element_size_m
    return axes


def _section(spec: RunSpec) -> dict[str, Any] | None:
    """The run's evaluated stretch as its job's section (the study page's tables then show
    the report's numbers); None when it is the whole run.
    """
    start, end = spec.window_m
    if start <= 0.0 and end >= spec.distance_m:
        return None
    return {"rule": "report", "start_m": start, "end_m": end,
            "label": f"report (the paper report's section) {start:.1f}–{end:.1f} m"}


def expand_report(request: dict[str, Any], max_jobs: int) -> StudyPlan:
    """The study of the paper report: one simulation job per run of its plan.

    Raises
    ------
    ScenarioError
        A field the report fixes (axes, base, overrides), or impossible options.
    StudyTooLarge
        More runs than ``max_jobs``.
    """
    for key in _FIXED:
        if request.get(key):
            raise ScenarioError.at((key,), "the paper report's runs and sections are fixed by "
                                   "its plan (docs/paper.md): give only quick and seeds",
                                   "study")
    options = report_options(request)
    specs = build_plan(options)
    if len(specs) > max_jobs:
        raise StudyTooLarge(f"study: the paper report with seeds = {options.seed_count()} makes "
                            f"{len(specs)} jobs; at most {max_jobs} are allowed "
                            "(FLEXRIDE_MAX_STUDY_JOBS)")
    jobs = [PlannedJob(index=i, name=s.label, scenario=s.scenario(), axes=_job_axes(s),
                       section=_section(s))
            for i, s in enumerate(specs)]
    quick = " (quick)" if options.quick else ""
    description = request.get("description") or (
        f"The paper's study{quick} as `flexride paper report` runs it: {len(specs)} runs, "
        f"{options.seed_count()} realisation(s) per random condition; the report (index.html, "
        "summary.json) is built when every run has finished.")
    spec = {**request, "report": {"options": options.to_dict(),
                                  "runs": [s.to_dict() for s in specs]}}
    return StudyPlan(name=request.get("name") or REPORT_PRESET, description=description,
                     preset=REPORT_PRESET, reuse=bool(request.get("reuse", True)),
                     axes=_axes(specs), jobs=jobs, request=spec)


def expand_report_size(request: Mapping[str, Any]) -> int:
    """Number of jobs of a paper report study (the runs of its plan)."""
    return len(build_plan(report_options(request)))


def _outcome(specs: list[RunSpec], jobs: dict[int, Job], files: Any, rep: Any) -> RunOutcome:
    """Run records from the study's jobs' result files (plan index = job's study index)."""
    from flexride.paper.record import record_from_results
    from flexride.paper.runner import RunOutcome
    from flexride.results import Results

    out = RunOutcome()
    for i, spec in enumerate(specs):
        if rep.cancel():
            raise SimulationCancelled("report cancelled")
        job = jobs.get(i)
        if job is None or job.status != "succeeded" or not files.exists(job.result_file):
            why = "missing" if job is None else (job.error or job.status)
            out.failures.append({"spec": spec.to_dict(), "label": spec.label,
                                 "error": f"job {getattr(job, 'id', '?')}: {why}"})
            continue
        t0 = time.perf_counter()
        try:
            results = Results.read_hdf5(files.path(job.result_file))
            out.records.append(record_from_results(spec, results, t0))
            out.computed += 1
        except FlexrideError as exc:
            out.failures.append({"spec": spec.to_dict(), "label": spec.label,
                                 "error": f"{type(exc).__name__}: {exc}"})
        rep.progress(0.9 * (i + 1) / len(specs), f"{spec.label}: analysed")
    starts = [j.started_at for j in jobs.values() if j.started_at is not None]
    ends = [j.finished_at for j in jobs.values() if j.finished_at is not None]
    if starts and ends:
        out.runs_wall_time_s = max(ends) - min(starts)
    return out


def _publish(tmp: Path, final: Path) -> None:
    """Put the finished report directory ``tmp`` in place of ``final`` (one rename; a
    previous report is moved aside first and removed after).
    """
    old = None
    if final.exists():
        old = final.with_name(f".old-{final.name}-{uuid.uuid4().hex[:8]}")
        os.replace(final, old)
    os.replace(tmp, final)
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)


def run_paper_report(job: Job, ctx: Any, rep: Any) -> Any:
    """A ``paper_report`` job: the report of the study ``job.scenario["study_id"]``.

    Reads every job's result file, writes ``index.html``, ``summary.json`` and
    ``report.json`` through :func:`flexride.paper.run_report`, then publishes them
    atomically under :func:`report_dir`.
    """
    from flexride.paper.report import run_report
    from flexride.study.run_job import Outcome

    study_id = str((job.scenario or {}).get("study_id", ""))
    study = ctx.store.get_study(study_id, spec=True)
    if study is None or not isinstance((study.spec or {}).get("report"), dict):
        raise FlexrideError(f"study {study_id} is gone or is not a paper report study")
    saved = study.spec["report"]
    options = ReportOptions.from_dict(saved["options"])
    specs = [RunSpec.from_dict(d) for d in saved["runs"]]
    jobs = {j.study_index: j for j in ctx.store.study_jobs(study_id)}
    final = report_dir(ctx.files.root, study_id)
    tmp = final.with_name(f".tmp-{study_id}-{uuid.uuid4().hex[:8]}")
    rep.progress(0.0, "Table 1: modal analysis of the car body", force=True)
    try:
        result = run_report(
            tmp, options, lambda m, d, t: rep.progress(0.9 if t and d >= t else 0.05, m),
            plan=specs, runs=lambda plan, say: _outcome(plan, jobs, ctx.files, rep))
        if rep.cancel(immediately=True):
            raise SimulationCancelled("report cancelled before it was published")
        _publish(tmp, final)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return Outcome({"run_meta": {"report": study_id, "counts": result.counts,
                                 "runs": len(specs), "failed": len(result.outcome.failures),
                                 "wall_time_s": result.wall_time_s}})
