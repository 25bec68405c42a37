"""SQLAlchemy 2 models of the job store: jobs, studies, workers seen. Their tables are made
and changed by the Alembic migrations in :mod:`flexride.store.migrations` (a model change
needs a new revision there).

Times are UTC seconds since the epoch (``float``): the same in SQLite and PostgreSQL, easy to
compare in SQL (stale heartbeats) and converted to ISO 8601 by the API.
"""

from __future__ import annotations

from typing import Any, ClassVar

from sqlalchemy import JSON, Boolean, Float, ForeignKey, Index, Integer, String, Text, text
from sqlalchemy.orm import DeclarativeBase, Mapped, deferred, mapped_column

JOB_STATUSES = ("queued", "running", "succeeded", "failed", "cancelled")
FINAL_STATUSES = ("succeeded", "failed", "cancelled")
JOB_KINDS = ("simulation", "fe_export", "paper_report")
"""What a job does: run a scenario (``simulation``), or build the browser export of an FE body
(``fe_export``: its :class:`~flexride.fem.export.ExportSpec` is the job's ``scenario``, its
content key the ``scenario_hash``), or build the report of a paper report study
(``paper_report``: ``scenario`` ``{"study_id"}``, :mod:`flexride.study.report`)."""


class Base(DeclarativeBase):
    """Declarative base of the flexride tables."""

    type_annotation_map: ClassVar[dict[Any, Any]] = {dict[str, Any]: JSON, list[Any]: JSON}


class Study(Base):
    """A study: a base scenario and the axes varied; its jobs point back to it."""

    __tablename__ = "flexride_studies"

    id: Mapped[str] = mapped_column(String(32), primary_key=True)
    name: Mapped[str] = mapped_column(String(120))
    description: Mapped[str] = mapped_column(Text, default="")
    preset: Mapped[str | None] = mapped_column(String(80), nullable=True)
    created_at: Mapped[float] = mapped_column(Float, index=True)
    n_jobs: Mapped[int] = mapped_column(Integer, default=0)
    axes: Mapped[list[Any]] = mapped_column(JSON, default=list)
    spec: Mapped[dict[str, Any]] = deferred(mapped_column(JSON, default=dict))


class Job(Base):
    """One job: its kind (:data:`JOB_KINDS`), scenario, state, progress, timings, summary and
    result file.
    """

    __tablename__ = "flexride_jobs"
    __table_args__ = (
        Index("ix_flexride_jobs_status_created", "status", "created_at"),
        # the job list, newest first: without it every page sorts the whole table
        Index("ix_flexride_jobs_created", "created_at", "id"),
        Index("ix_flexride_jobs_study", "study_id", "study_index"),
        # result reuse and the duplicate check: the newest job of a kind, hash and status
        # from the index's end, however often the scenario was submitted
        Index("ix_flexride_jobs_reuse", "kind", "scenario_hash", "status", "finished_at"),
    )

    id: Mapped[str] = mapped_column(String(32), primary_key=True)
    kind: Mapped[str] = mapped_column(String(16), default="simulation",
                                      server_default=text("'simulation'"))
    name: Mapped[str] = mapped_column(String(120))
    status: Mapped[str] = mapped_column(String(16), index=True)
    progress: Mapped[float] = mapped_column(Float, default=0.0)
    message: Mapped[str] = mapped_column(String(400), default="")
    error: Mapped[str | None] = mapped_column(Text, nullable=True)
    created_at: Mapped[float] = mapped_column(Float)
    updated_at: Mapped[float] = mapped_column(Float)
    started_at: Mapped[float | None] = mapped_column(Float, nullable=True)
    finished_at: Mapped[float | None] = mapped_column(Float, nullable=True)
    heartbeat_at: Mapped[float | None] = mapped_column(Float, nullable=True)
    runner: Mapped[str] = mapped_column(String(16), default="embedded")
    worker: Mapped[str | None] = mapped_column(String(200), nullable=True)
    attempts: Mapped[int] = mapped_column(Integer, default=0)
    max_attempts: Mapped[int] = mapped_column(Integer, default=2)
    cancel_requested: Mapped[bool] = mapped_column(Boolean, default=False)
    scenario_hash: Mapped[str] = mapped_column(String(64), index=True)
    preset: Mapped[str | None] = mapped_column(String(80), nullable=True)
    speed_kmh: Mapped[float | None] = mapped_column(Float, nullable=True)
    duration_s: Mapped[float | None] = mapped_column(Float, nullable=True)
    study_id: Mapped[str | None] = mapped_column(
        String(32), ForeignKey("flexride_studies.id", ondelete="SET NULL"), nullable=True
    )
    study_index: Mapped[int | None] = mapped_column(Integer, nullable=True)
    axes: Mapped[dict[str, Any]] = mapped_column(JSON, default=dict)
    reused_from: Mapped[str | None] = mapped_column(String(32), nullable=True)
    result_file: Mapped[str | None] = mapped_column(String(200), nullable=True)
    wall_time_s: Mapped[float | None] = mapped_column(Float, nullable=True)
    run_meta: Mapped[dict[str, Any]] = mapped_column(JSON, default=dict)
    scenario: Mapped[dict[str, Any]] = deferred(mapped_column(JSON))
    summary: Mapped[dict[str, Any] | None] = deferred(mapped_column(JSON, nullable=True))


class WorkerSeen(Base):
    """A worker process that reported itself (embedded pool process or Celery child)."""

    __tablename__ = "flexride_workers"

    name: Mapped[str] = mapped_column(String(200), primary_key=True)
    kind: Mapped[str] = mapped_column(String(16))
    hostname: Mapped[str] = mapped_column(String(120))
    pid: Mapped[int] = mapped_column(Integer)
    started_at: Mapped[float] = mapped_column(Float)
    last_seen: Mapped[float] = mapped_column(Float, index=True)
    current_job: Mapped[str | None] = mapped_column(String(32), nullable=True)

