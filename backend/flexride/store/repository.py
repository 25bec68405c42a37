"""The job store: every read and write of job, study and worker records goes through here.

State changes that several processes may attempt at once (claiming a job, finishing it,
declaring its worker lost) are single conditional transactions, so a job is run by one worker
at a time and a late worker cannot overwrite the record of a job that was taken over, cancelled
or deleted meanwhile.
"""

from __future__ import annotations

import functools
import hashlib
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, ParamSpec, TypeVar, cast

from sqlalchemy import (
    CursorResult,
    Engine,
    Result,
    and_,
    bindparam,
    delete,
    func,
    select,
    text,
    update,
)
from sqlalchemy.exc import DBAPIError
from sqlalchemy.orm import Session, defer, sessionmaker, undefer

from flexride.store.data_version import DataVersion
from flexride.store.db import get_engine, init_db, writer
from flexride.store.models import FINAL_STATUSES, Job, Study, WorkerSeen
from flexride.store.probe import retryable

DeadWorker = Callable[[str], bool]
P = ParamSpec("P")
R = TypeVar("R")

WRITE_ATTEMPTS = 3
"""Runs of a writing transaction that the database rolled back as a serialization failure or
a deadlock (:func:`flexride.store.probe.retryable`) before the error is raised."""
_RETRY_PAUSE_S = 0.05

ACTIVE_STATUSES = ("queued", "running")
"""States of a job that is still to run or running."""
_PG_KEY_LOCKS = 0x464C5853  # "FLXS": advisory locks of add_unless_active (one per content key)

LIST_COLUMNS = tuple(c for c in Job.__table__.c if c.name not in ("scenario", "summary"))
"""Columns of a job in lists: all but the large JSON scenario and summary."""


def now() -> float:
    """Current UTC time in seconds since the epoch (the store's time unit)."""
    return time.time()


def _never_dead(_name: str) -> bool:
    return False


@dataclass(frozen=True)
class Claim:
    """Outcome of an attempt to start a job.

    Attributes
    ----------
    claimed : bool
        True if the caller now runs the job.
    reason : str
        Why not (``missing``, ``succeeded``, ``cancelled``, ``running elsewhere``, ``failed``...)
        or ``claimed``.
    job : Job or None
        The record after the attempt (with its scenario when claimed).
    """

    claimed: bool
    reason: str
    job: Job | None = None



_PING = select(1)
_COUNTS = select(Job.status, func.count()).group_by(Job.status)
_WORKERS_AND_JOBS = (
    select(*WorkerSeen.__table__.c, Job.id.label("job_id"))
    .outerjoin(Job, and_(Job.worker == WorkerSeen.name, Job.status == "running"))
    .where(WorkerSeen.last_seen >= bindparam("seen_after"))
    .order_by(WorkerSeen.last_seen.desc(), WorkerSeen.name))
"""The statements of :meth:`JobStore.overview`, built once (health is polled often)."""


@dataclass(frozen=True)
class Overview:
    """The store at a glance (:meth:`JobStore.overview`)."""

    latency_s: float
    counts: dict[str, int]
    workers: list[Any]
    """Rows with the columns of :class:`WorkerSeen` and ``job_id``."""


def _rows(result: Result[Any]) -> int:
    """Rows an UPDATE or DELETE touched (``Session.execute`` returns a CursorResult for them)."""
    return int(cast(CursorResult[Any], result).rowcount)


def _key_int32(key: str) -> int:
    """A signed 32-bit number from a content key (a PostgreSQL advisory lock's second key)."""
    return int.from_bytes(hashlib.sha256(key.encode()).digest()[:4], "big", signed=True)


def retried(method: Callable[P, R]) -> Callable[P, R]:
    """Run a method that is one writing transaction again (up to :data:`WRITE_ATTEMPTS`
    times, pausing 0.05, then 0.1 s) when the database rolled it back as a serialization
    failure or a deadlock; other errors, and the last one, are raised.
    """
    @functools.wraps(method)
    def run(*args: P.args, **kwargs: P.kwargs) -> R:
        for attempt in range(1, WRITE_ATTEMPTS + 1):
            try:
                return method(*args, **kwargs)
            except DBAPIError as exc:
                if attempt == WRITE_ATTEMPTS or not retryable(exc):
                    raise
            time.sleep(_RETRY_PAUSE_S * 2 ** (attempt - 1))  # back-off, not synchronisation
        raise AssertionError("unreachable")  # pragma: no cover

    return run

class JobStore:
    """Job, study and worker records in a SQL database.

    Parameters
    ----------
    engine : sqlalchemy.Engine
        Engine from :func:`flexride.store.db.create_store_engine` / ``get_engine``.
    """

    def __init__(self, engine: Engine):
        self.engine = engine
        self._read = sessionmaker(engine, expire_on_commit=False)
        self._write = sessionmaker(writer(engine), expire_on_commit=False)
        self._version = DataVersion(engine)

    @classmethod
    def from_url(cls, url: str, *, create: bool = True) -> JobStore:
        """Store of the database at ``url`` (schema created or migrated when ``create``)."""
        engine = get_engine(url)
        if create:
            init_db(engine)
        return cls(engine)

    def data_version(self) -> int | None:
        """A number that changes whenever anyone commits a change to the database, or None
        when the database cannot tell (see :mod:`flexride.store.data_version`).
        """
        return self._version.current()

    # -- sessions ---------------------------------------------------------------------------

    def reading(self) -> Session:
        """A session for reads (deferred transaction)."""
        return self._read()

    def writing(self) -> Session:
        """A session for writes (``BEGIN IMMEDIATE`` on SQLite)."""
        return self._write()

    def ping(self) -> float:
        """Round-trip a trivial query; return its duration in s."""
        t0 = time.perf_counter()
        with self.reading() as s:
            s.execute(select(1)).scalar_one()
        return time.perf_counter() - t0

    # -- jobs: creation and reads ------------------------------------------------------------

    @retried
    def add(self, jobs: Sequence[Job], study: Study | None = None) -> None:
        """Insert new jobs (and their study) in one transaction."""
        with self.writing() as s, s.begin():
            if study is not None:
                s.add(study)
                s.flush()
            s.add_all(list(jobs))

    def get_job(self, job_id: str, *, scenario: bool = False, summary: bool = False) -> Job | None:
        """The job ``job_id`` or None; ``scenario``/``summary`` also load those columns."""
        opts = []
        if scenario:
            opts.append(undefer(Job.scenario))
        if summary:
            opts.append(undefer(Job.summary))
        with self.reading() as s:
            return s.get(Job, job_id, options=opts)

    def result_file_of(self, job_id: str) -> str | None:
        """Result file name of job ``job_id`` if it has succeeded and has one, else None.

        One indexed query of one column (no ORM object): the check every results request
        makes before it is answered, possibly from memory.
        """
        q = select(Job.result_file).where(Job.id == job_id, Job.status == "succeeded")
        with self.engine.connect() as conn:
            return conn.execute(q).scalar_one_or_none()

    @retried
    def add_unless_active(self, job: Job) -> tuple[Job, bool]:
        """Insert ``job`` unless a job of its kind and ``scenario_hash`` is queued or running;
        in one transaction, so concurrent callers (threads, API processes) add one job per
        key however often they ask.

        Returns
        -------
        (Job, bool)
            The new job and True, or the active job found and False.
        """
        with self.writing() as s, s.begin():
            if s.get_bind().dialect.name == "postgresql":  # SQLite: BEGIN IMMEDIATE serialises
                s.execute(text("SELECT pg_advisory_xact_lock(:a, :b)"),
                          {"a": _PG_KEY_LOCKS, "b": _key_int32(job.scenario_hash)})
            q = (select(Job)
                 .where(Job.kind == job.kind, Job.scenario_hash == job.scenario_hash,
                        Job.status.in_(ACTIVE_STATUSES))
                 .order_by(Job.created_at)
                 .limit(1))
            active = s.scalars(q).first()
            if active is not None:
                return active, False
            s.add(job)
            return job, True

    def latest_job(self, kind: str, scenario_hash: str) -> Job | None:
        """The newest job of ``kind`` with this ``scenario_hash`` (any status), or None."""
        q = (select(Job)
             .where(Job.kind == kind, Job.scenario_hash == scenario_hash)
             .order_by(Job.created_at.desc(), Job.id)
             .limit(1))
        with self.reading() as s:
            return s.scalars(q).first()

    def count_active(self, kind: str) -> int:
        """Number of queued or running jobs of ``kind``."""
        q = (select(func.count()).select_from(Job)
             .where(Job.kind == kind, Job.status.in_(ACTIVE_STATUSES)))
        with self.engine.connect() as conn:
            return int(conn.execute(q).scalar_one())

    def list_jobs(
        self,
        *,
        status: str | None = None,
        study_id: str | None = None,
        kind: str | None = "simulation",
        limit: int = 50,
        offset: int = 0,
    ) -> tuple[list[Any], int]:
        """Jobs newest first with optional filters (``kind`` None: every kind), and the total
        count matching them.

        The page is read as plain rows (no ORM objects) of the columns of :class:`Job` other
        than the large JSON ``scenario`` and ``summary`` (:data:`LIST_COLUMNS`), with the
        attributes of a :class:`Job` of those names; page and count share one connection.
        """
        q = select(*LIST_COLUMNS)
        cq = select(func.count()).select_from(Job)
        if status is not None:
            q, cq = q.where(Job.status == status), cq.where(Job.status == status)
        if study_id is not None:
            q, cq = q.where(Job.study_id == study_id), cq.where(Job.study_id == study_id)
        if kind is not None:
            q, cq = q.where(Job.kind == kind), cq.where(Job.kind == kind)
        q = q.order_by(Job.created_at.desc(), Job.id).limit(limit).offset(offset)
        with self.engine.connect() as conn:
            items = list(conn.execute(q))
            total = int(conn.execute(cq).scalar_one())
        return items, total

    def study_jobs(self, study_id: str, *, summary: bool = False) -> list[Job]:
        """Jobs of a study in matrix order (with their summaries when asked)."""
        q = select(Job).where(Job.study_id == study_id).order_by(Job.study_index)
        if summary:
            q = q.options(undefer(Job.summary))
        with self.reading() as s:
            return list(s.scalars(q))

    def find_reusable(self, scenario_hash: str, kind: str = "simulation") -> Job | None:
        """The newest succeeded job of ``kind`` with this scenario hash and a result file."""
        q = (
            select(Job)
            .options(undefer(Job.summary))
            .where(Job.kind == kind, Job.scenario_hash == scenario_hash,
                   Job.status == "succeeded", Job.result_file.is_not(None))
            .order_by(Job.finished_at.desc())
            .limit(1)
        )
        with self.reading() as s:
            return s.scalars(q).first()

    def queued_ids(self, runner: str | None = None) -> list[str]:
        """Ids of queued jobs, oldest first."""
        q = select(Job.id).where(Job.status == "queued").order_by(Job.created_at)
        if runner is not None:
            q = q.where(Job.runner == runner)
        with self.reading() as s:
            return list(s.scalars(q))

    def counts(self) -> dict[str, int]:
        """Number of jobs per status."""
        with self.reading() as s:
            rows = s.execute(_COUNTS).all()
        return {status: int(n) for status, n in rows}

    def overview(self, workers_seen_after: float) -> Overview:
        """What health reports of the store, read on one connection: a round trip's time,
        the jobs per status and the workers seen after ``workers_seen_after`` (most recent
        first), each with the job that the job records say it runs (``job_id``, None when
        no running job names it: not the worker's own last report, which a worker that died
        or stopped reporting never corrects).
        """
        with self.engine.connect() as conn:
            t0 = time.perf_counter()
            conn.execute(_PING).scalar_one()
            latency = time.perf_counter() - t0
            counts = conn.execute(_COUNTS).all()
            seen: dict[str, Any] = {}
            for row in conn.execute(_WORKERS_AND_JOBS, {"seen_after": workers_seen_after}):
                seen.setdefault(row.name, row)  # one row per worker
        return Overview(latency, {status: int(n) for status, n in counts}, list(seen.values()))

    # -- jobs: running ------------------------------------------------------------------------

    def _claim_row(self, s: Session, job: Job | None, worker: str, stale_before: float,
                   dead: DeadWorker) -> Claim:
        if job is None:
            return Claim(False, "missing")
        if job.status in FINAL_STATUSES:
            return Claim(False, job.status, job)
        t = now()
        if job.cancel_requested:
            job.status, job.finished_at, job.updated_at = "cancelled", t, t
            job.message = "cancelled before it ran"
            return Claim(False, "cancelled", job)
        note = ""
        if job.status == "running":
            stale = job.heartbeat_at is None or job.heartbeat_at < stale_before
            if not (stale or (job.worker is not None and dead(job.worker))):
                return Claim(False, "running elsewhere", job)
            note = "previous attempt lost (its worker stopped reporting); "
        if job.attempts >= job.max_attempts:
            job.status, job.finished_at, job.updated_at = "failed", t, t
            job.error = (f"{note}the job's worker was lost {job.attempts} time(s) "
                         f"(max_attempts = {job.max_attempts})")
            job.message = "failed: worker lost"
            return Claim(False, "failed", job)
        job.status = "running"
        job.attempts += 1
        job.worker = worker
        job.started_at = job.heartbeat_at = job.updated_at = t
        job.progress = 0.0
        job.message = f"{note}started (attempt {job.attempts} of {job.max_attempts})"
        job.error = None
        return Claim(True, "claimed", job)

    @retried
    def claim(self, job_id: str, worker: str, *, stale_before: float,
              dead: DeadWorker = _never_dead) -> Claim:
        """Start job ``job_id`` on ``worker`` if it is queued, or running on a lost worker.

        Parameters
        ----------
        job_id : str
            The job.
        worker : str
            Name of the claiming worker (``kind-pid@host``).
        stale_before : float
            A running job whose last heartbeat is older than this (epoch s) has lost its
            worker and may be taken over.
        dead : callable(worker name) -> bool
            Tells whether a recorded worker is known to be dead (same host, no such process).

        Returns
        -------
        Claim
            ``claimed`` is True when the caller must run the job (attempts incremented). A job
            whose attempts are used up is marked failed instead.
        """
        with self.writing() as s, s.begin():
            job = s.get(Job, job_id, options=[undefer(Job.scenario)], with_for_update=True)
            return self._claim_row(s, job, worker, stale_before, dead)

    @retried
    def claim_next(self, runner: str, worker: str, *, stale_before: float,
                   dead: DeadWorker = _never_dead) -> Claim | None:
        """Claim the oldest queued job of ``runner``; None when there is none."""
        q = (
            select(Job)
            .options(undefer(Job.scenario))
            .where(Job.status == "queued", Job.runner == runner)
            .order_by(Job.created_at, Job.study_index)
            .limit(1)
            .with_for_update(skip_locked=True)
        )
        with self.writing() as s, s.begin():
            job = s.scalars(q).first()
            if job is None:
                return None
            return self._claim_row(s, job, worker, stale_before, dead)

    @retried
    def _update_running(self, job_id: str, worker: str, **values: Any) -> bool:
        stmt = (
            update(Job)
            .where(Job.id == job_id, Job.status == "running", Job.worker == worker)
            .values(**values)
        )
        with self.writing() as s, s.begin():
            return _rows(s.execute(stmt)) == 1

    def report_progress(self, job_id: str, worker: str, fraction: float, message: str) -> bool:
        """Record progress (and a heartbeat); False if the job is no longer ``worker``'s."""
        t = now()
        return self._update_running(
            job_id, worker, progress=max(0.0, min(1.0, float(fraction))),
            message=message[:400], heartbeat_at=t, updated_at=t,
        )

    def heartbeat(self, job_id: str, worker: str) -> bool:
        """Record that ``worker`` still runs the job; False if it is no longer its job."""
        return self._update_running(job_id, worker, heartbeat_at=now())

    def should_stop(self, job_id: str, worker: str) -> bool:
        """True if the run must stop: cancel requested, job deleted or taken over."""
        with self.reading() as s:
            row = s.execute(
                select(Job.status, Job.worker, Job.cancel_requested).where(Job.id == job_id)
            ).first()
        if row is None:
            return True
        status, owner, cancel = row
        return bool(cancel) or status != "running" or owner != worker

    def finish(self, job_id: str, worker: str, status: str, **values: Any) -> bool:
        """Set the final state of a job run by ``worker``; False if it is no longer its job."""
        if status not in FINAL_STATUSES:
            raise ValueError(f"not a final status: {status!r}")
        t = now()
        values.setdefault("message", status)
        return self._update_running(job_id, worker, status=status, finished_at=t, updated_at=t,
                                    heartbeat_at=t, **values)

    @retried
    def request_cancel(self, job_id: str) -> Job | None:
        """Cancel a job: a queued one at once, a running one at its next cancellation check."""
        with self.writing() as s, s.begin():
            job = s.get(Job, job_id, with_for_update=True)
            if job is None:
                return None
            t = now()
            if job.status == "queued":
                job.status, job.finished_at = "cancelled", t
                job.message = "cancelled before it ran"
                job.cancel_requested = True
            elif job.status == "running":
                job.cancel_requested = True
                job.message = "cancel requested"
            job.updated_at = t
            return job

    @retried
    def delete_job(self, job_id: str) -> Job | None:
        """Delete a job record; return it (its result file is the caller's to remove)."""
        with self.writing() as s, s.begin():
            job = s.get(Job, job_id)
            if job is None:
                return None
            s.delete(job)
            return job

    @retried
    def worker_lost(self, job_id: str, worker: str, reason: str) -> str | None:
        """Declare ``worker`` lost while running the job: requeue it, or fail it when its
        attempts are used up. Returns the new status, or None if the job was not ``worker``'s.
        """
        with self.writing() as s, s.begin():
            job = s.get(Job, job_id, with_for_update=True)
            if job is None or job.status != "running" or job.worker != worker:
                return None
            t = now()
            job.updated_at = t
            if job.cancel_requested:
                job.status, job.finished_at, job.message = "cancelled", t, f"cancelled ({reason})"
            elif job.attempts < job.max_attempts:
                job.status, job.progress, job.heartbeat_at = "queued", 0.0, None
                job.message = f"requeued after attempt {job.attempts}: {reason}"
            else:
                job.status, job.finished_at = "failed", t
                job.error = f"{reason}; gave up after {job.attempts} attempt(s)"
                job.message = "failed: worker lost"
            return job.status

    def stale_running(self, stale_before: float) -> list[Job]:
        """Running jobs whose last heartbeat is older than ``stale_before``."""
        q = select(Job).where(Job.status == "running", Job.heartbeat_at < stale_before)
        with self.reading() as s:
            return list(s.scalars(q))

    def running_jobs(self, runner: str | None = None) -> list[Job]:
        """Running jobs (of one runner kind when given)."""
        q = select(Job).where(Job.status == "running")
        if runner is not None:
            q = q.where(Job.runner == runner)
        with self.reading() as s:
            return list(s.scalars(q))

    def running_on(self, workers: Sequence[str]) -> list[Job]:
        """Running jobs of the named workers."""
        if not workers:
            return []
        q = select(Job).where(Job.status == "running", Job.worker.in_(list(workers)))
        with self.reading() as s:
            return list(s.scalars(q))

    @retried
    def requeue_interrupted(self, worker: str, reason: str) -> bool:
        """Put a job interrupted by a service shutdown back in the queue (attempt not counted)."""
        stmt = (
            update(Job)
            .where(Job.status == "running", Job.worker == worker)
            .values(status="queued", attempts=Job.attempts - 1, progress=0.0, heartbeat_at=None,
                    message=f"requeued: {reason}", updated_at=now())
        )
        with self.writing() as s, s.begin():
            return _rows(s.execute(stmt)) > 0

    # -- studies ------------------------------------------------------------------------------

    def get_study(self, study_id: str, *, spec: bool = False) -> Study | None:
        """The study ``study_id`` or None."""
        opts = [undefer(Study.spec)] if spec else []
        with self.reading() as s:
            return s.get(Study, study_id, options=opts)

    def list_studies(self, *, limit: int = 50, offset: int = 0) -> tuple[list[Study], int]:
        """Studies newest first and their total count."""
        q = select(Study).order_by(Study.created_at.desc(), Study.id).limit(limit).offset(offset)
        with self.reading() as s:
            items = list(s.scalars(q))
            total = int(s.execute(select(func.count()).select_from(Study)).scalar_one())
        return items, total

    def study_status_counts(self, study_ids: Sequence[str]) -> dict[str, dict[str, int]]:
        """Per study, the number of its jobs in each status."""
        if not study_ids:
            return {}
        q = (
            select(Job.study_id, Job.status, func.count())
            .where(Job.study_id.in_(list(study_ids)))
            .group_by(Job.study_id, Job.status)
        )
        out: dict[str, dict[str, int]] = {sid: {} for sid in study_ids}
        with self.reading() as s:
            for sid, status, n in s.execute(q):
                if sid is not None:
                    out[sid][status] = int(n)
        return out

    @retried
    def delete_study(self, study_id: str) -> tuple[Study | None, list[Job]]:
        """Delete a study and its jobs; return them (result files are the caller's)."""
        with self.writing() as s, s.begin():
            study = s.get(Study, study_id)
            if study is None:
                return None, []
            jobs = list(s.scalars(select(Job).options(defer(Job.scenario))
                                  .where(Job.study_id == study_id)))
            s.execute(delete(Job).where(Job.study_id == study_id))
            s.delete(study)
            return study, jobs

    # -- workers ------------------------------------------------------------------------------

    @retried
    def worker_seen(self, name: str, kind: str, hostname: str, pid: int,
                    current_job: str | None = None) -> None:
        """Record that a worker process is alive (insert or update its row)."""
        t = now()
        with self.writing() as s, s.begin():
            row = s.get(WorkerSeen, name)
            if row is None:
                s.add(WorkerSeen(name=name, kind=kind, hostname=hostname, pid=pid, started_at=t,
                                 last_seen=t, current_job=current_job))
            else:
                row.last_seen, row.current_job = t, current_job

    @retried
    def worker_gone(self, name: str) -> None:
        """Remove a worker that stopped cleanly."""
        with self.writing() as s, s.begin():
            s.execute(delete(WorkerSeen).where(WorkerSeen.name == name))

    def workers(self, seen_after: float | None = None) -> list[WorkerSeen]:
        """Workers seen after ``seen_after`` (all when None), most recent first."""
        q = select(WorkerSeen).order_by(WorkerSeen.last_seen.desc())
        if seen_after is not None:
            q = q.where(WorkerSeen.last_seen >= seen_after)
        with self.reading() as s:
            return list(s.scalars(q))

    @retried
    def forget_workers(self, seen_before: float) -> int:
        """Delete worker rows not seen since ``seen_before``."""
        with self.writing() as s, s.begin():
            return _rows(s.execute(delete(WorkerSeen).where(WorkerSeen.last_seen < seen_before)))
