"""Submission: turn validated scenarios into job records (or reuse stored results) and hand
the queued ones to the runner. Used by the API for single jobs, for studies and for the
builds of FE exports (jobs of kind ``fe_export``).
"""

from __future__ import annotations

import logging
import uuid
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from typing import TYPE_CHECKING, Any

from flexride.errors import StorageError
from flexride.jobs.base import JobRunner
from flexride.scenario.scenario import Scenario
from flexride.settings import Settings
from flexride.solver.estimate import RunEstimate
from flexride.store import Job, JobStore, ResultFiles, Study, now
from flexride.store.probe import dir_problem
from flexride.store.uploads import UploadStore
from flexride.study.admission import Limits, admit, check_auto_steps
from flexride.study.expand import StudyPlan
from flexride.study.scenarios import (
    PREFLIGHT,
    PreflightCache,
    check_installable,
    check_submission,
    scenario_hash,
)

if TYPE_CHECKING:
    from flexride.fem.export import ExportSpec

log = logging.getLogger(__name__)


def new_id() -> str:
    """A new job or study id (32 hex digits)."""
    return uuid.uuid4().hex


@dataclass
class Submitted:
    """A created job: its record, whether stored results were reused, the submission check."""

    job: Job
    reused: bool
    preflight: dict[str, Any] | None


class Submitter:
    """Creates jobs and studies.

    Parameters
    ----------
    store : JobStore
        Where records go.
    files : ResultFiles
        Results directory (to give a reusing job its own copy of the file).
    runner : JobRunner
        Who runs queued jobs.
    settings : Settings
        ``max_attempts``, ``reuse_results``, ``preflight``.
    cache : PreflightCache
        Submission checks by stability key.
    """

    def __init__(self, store: JobStore, files: ResultFiles, runner: JobRunner,
                 settings: Settings, cache: PreflightCache = PREFLIGHT):
        self.store, self.files, self.runner, self.settings = store, files, runner, settings
        self.cache = cache
        self.limits = Limits.from_settings(settings)
        self.uploads = UploadStore(settings.uploads_dir)

    def check_storage(self) -> None:
        """Refuse new jobs while the results directory takes no files (a job could not
        write its results): :class:`~flexride.errors.StorageError` (503).
        """
        problem = dir_problem(self.files.root)
        if problem:
            raise StorageError(f"results directory not writable: {problem}")

    def admit(self, scenario: Scenario) -> RunEstimate:
        """The checks every job passes before it is recorded (:func:`.admission.admit`):
        measured data from uploads or inline only, the run and its FE bodies within limits.
        """
        return admit(scenario, self.limits, self.uploads.sources)

    def check(self, scenario: Scenario) -> dict[str, Any]:
        """The submission check (:func:`~flexride.study.scenarios.check_submission`) when it
        can run without compiling the solver (:data:`flexride.jobs.warmup.SOLVER`); while the
        solver is being compiled, ``{"deferred": reason}``: the worker checks the time step
        before it runs (a step beyond the limit fails the job with the step to use).

        Raises
        ------
        ScenarioError, StabilityError
            The check refused the scenario.
        """
        from flexride.jobs.warmup import SOLVER

        if not SOLVER.usable():
            check_installable(scenario)
            return {"deferred": "the solver is being compiled: the time step is checked by "
                                "the worker before the run"}
        return check_submission(scenario, cache=self.cache, sources=self.uploads.sources)

    def _record(self, scenario: Scenario, *, name: str, preset: str | None, reuse: bool,
                study_id: str | None = None, index: int | None = None,
                axes: dict[str, Any] | None = None,
                section: dict[str, Any] | None = None) -> Submitted:
        self.admit(scenario)
        self.check_storage()
        t = now()
        job_id = new_id()
        digest = scenario_hash(scenario)
        common = dict(id=job_id, name=name[:120], created_at=t, updated_at=t,
                      runner=self.runner.kind, max_attempts=self.settings.max_attempts,
                      scenario_hash=digest, preset=preset, speed_kmh=scenario.speed_kmh,
                      duration_s=scenario.duration, study_id=study_id, study_index=index,
                      axes=axes or {}, scenario=scenario.model_dump(mode="json"),
                      cancel_requested=False, attempts=0)
        if reuse and self.settings.reuse_results:
            src = self.store.find_reusable(digest)
            if src is not None and src.result_file and self.files.exists(src.result_file) and (
                    (src.run_meta or {}).get("section") == section):
                file_name = self.files.copy(src.result_file, job_id)
                job = Job(**common, status="succeeded", progress=1.0,
                          message=f"results reused from job {src.id}", started_at=t,
                          finished_at=t, heartbeat_at=t, reused_from=src.id,
                          result_file=file_name, summary=src.summary, run_meta=src.run_meta,
                          wall_time_s=0.0)
                return Submitted(job, True, None)
        pre = self.check(scenario) if self.settings.preflight else None
        check_auto_steps(scenario, pre, self.limits)
        meta = {"section": section} if section else {}
        job = Job(**common, status="queued", progress=0.0, message="queued", run_meta=meta)
        return Submitted(job, False, pre)

    def _add(self, items: Sequence[Submitted], study: Study | None = None) -> None:
        try:
            self.store.add([s.job for s in items], study)
        except Exception:
            for s in items:
                if s.reused:
                    self.files.delete(s.job.result_file)
            raise
        queued = [s.job.id for s in items if not s.reused]
        if queued:
            self.runner.submit(queued)

    def submit_job(self, scenario: Scenario, *, name: str | None = None,
                   preset: str | None = None, reuse: bool = True) -> Submitted:
        """Create one job (checked, or finished at once from reused results) and queue it.

        Raises
        ------
        ScenarioError, StabilityError
            The submission check refused the scenario.
        """
        sub = self._record(scenario, name=name or scenario.name, preset=preset, reuse=reuse)
        self._add([sub])
        return sub

    def submit_study(self, plan: StudyPlan) -> tuple[Study, list[Submitted]]:
        """Create a study and all its jobs in one transaction, then queue them."""
        study_id = new_id()
        subs: list[Submitted] = []
        try:
            for pj in plan.jobs:
                subs.append(self._record(pj.scenario, name=pj.name, preset=None,
                                         reuse=plan.reuse, study_id=study_id, index=pj.index,
                                         axes=pj.axes, section=pj.section))
        except Exception:
            for s in subs:  # copies of reused results made before the refusal
                if s.reused:
                    self.files.delete(s.job.result_file)
            raise
        study = Study(id=study_id, name=plan.name[:120], description=plan.description,
                      preset=plan.preset, created_at=now(), n_jobs=len(subs),
                      axes=[ax.describe() for ax in plan.axes], spec=plan.request)
        self._add(subs, study)
        return study, subs

    def submit_report(self, study: Study) -> tuple[Job, bool]:
        """Queue the build of a paper report study's report (a job of kind ``paper_report``,
        :mod:`flexride.study.report`) unless one is already queued or running for it.

        Returns
        -------
        (Job, bool)
            The new job and True, or the active one and False.
        """
        from flexride.study.report import REPORT_KIND, report_key

        self.check_storage()
        t = now()
        job = Job(id=new_id(), kind=REPORT_KIND, name=f"Report of study {study.name}"[:120],
                  status="queued", progress=0.0, message="queued", created_at=t,
                  updated_at=t, runner=self.runner.kind,
                  max_attempts=self.settings.max_attempts, attempts=0,
                  cancel_requested=False, scenario_hash=report_key(study.id),
                  scenario={"study_id": study.id}, axes={}, run_meta={})
        job, created = self.store.add_unless_active(job)
        if created:
            self.runner.submit([job.id])
        return job, created

    def submit_fe_export(self, spec: ExportSpec) -> tuple[Job, bool]:
        """Queue the build of an FE export (a job of kind ``fe_export``) unless one for the
        same content key is already queued or running: one job per key however often (and
        from however many API processes) it is asked for.

        The job's ``scenario`` is the spec (``asdict(spec)``), its ``scenario_hash`` the
        spec's content key; the size limits of the build are the caller's to check
        (:func:`flexride.study.admission.check_fe_build`).

        Returns
        -------
        (Job, bool)
            The new job and True, or the queued or running job of that key and False.
        """
        from flexride.fem.export import BODY_LABELS

        t = now()
        name = (f"FE export: {BODY_LABELS[spec.kind]}, {spec.element_size_m:g} m elements, "
                f"{spec.cutoff_hz:g} Hz, {spec.reduction}")
        job = Job(id=new_id(), kind="fe_export", name=name[:120], status="queued",
                  progress=0.0, message="queued", created_at=t, updated_at=t,
                  runner=self.runner.kind, max_attempts=self.settings.max_attempts,
                  attempts=0, cancel_requested=False, scenario_hash=spec.key,
                  scenario=asdict(spec), axes={}, run_meta={})
        job, created = self.store.add_unless_active(job)
        if created:
            log.info("FE export %s: job %s queued (%s)", spec.key, job.id, spec.parameters())
            self.runner.submit([job.id])
        return job, created
