"""Baseline: the job store as flexride 0.1 created it (studies, jobs, workers, schema row).

Creates the tables on an empty database. A store made before migrations were run by Alembic
(tables created by ``create_all`` and columns added by the old column migrator) is brought to
this layout instead: missing tables are created and missing columns added (nullable).

Revision ID: 0001
Revises:
Create Date: 2026-12-01
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = "0001"
down_revision = None
branch_labels = None
depends_on = None


def _tables(meta: sa.MetaData) -> list[sa.Table]:
    """The layout of this revision (a snapshot: later model changes go in later revisions)."""
    studies = sa.Table(
        "flexride_studies", meta,
        sa.Column("id", sa.String(32), primary_key=True),
        sa.Column("name", sa.String(120), nullable=False),
        sa.Column("description", sa.Text, nullable=False),
        sa.Column("preset", sa.String(80), nullable=True),
        sa.Column("created_at", sa.Float, nullable=False, index=True),
        sa.Column("n_jobs", sa.Integer, nullable=False),
        sa.Column("axes", sa.JSON, nullable=False),
        sa.Column("spec", sa.JSON, nullable=True),
    )
    jobs = sa.Table(
        "flexride_jobs", meta,
        sa.Column("id", sa.String(32), primary_key=True),
        sa.Column("name", sa.String(120), nullable=False),
        sa.Column("status", sa.String(16), nullable=False, index=True),
        sa.Column("progress", sa.Float, nullable=False),
        sa.Column("message", sa.String(400), nullable=False),
        sa.Column("error", sa.Text, nullable=True),
        sa.Column("created_at", sa.Float, nullable=False),
        sa.Column("updated_at", sa.Float, nullable=False),
        sa.Column("started_at", sa.Float, nullable=True),
        sa.Column("finished_at", sa.Float, nullable=True),
        sa.Column("heartbeat_at", sa.Float, nullable=True),
        sa.Column("runner", sa.String(16), nullable=False),
        sa.Column("worker", sa.String(200), nullable=True),
        sa.Column("attempts", sa.Integer, nullable=False),
        sa.Column("max_attempts", sa.Integer, nullable=False),
        sa.Column("cancel_requested", sa.Boolean, nullable=False),
        sa.Column("scenario_hash", sa.String(64), nullable=False, index=True),
        sa.Column("preset", sa.String(80), nullable=True),
        sa.Column("speed_kmh", sa.Float, nullable=True),
        sa.Column("duration_s", sa.Float, nullable=True),
        sa.Column("study_id", sa.String(32),
                  sa.ForeignKey("flexride_studies.id", ondelete="SET NULL"), nullable=True),
        sa.Column("study_index", sa.Integer, nullable=True),
        sa.Column("axes", sa.JSON, nullable=False),
        sa.Column("reused_from", sa.String(32), nullable=True),
        sa.Column("result_file", sa.String(200), nullable=True),
        sa.Column("wall_time_s", sa.Float, nullable=True),
        sa.Column("run_meta", sa.JSON, nullable=False),
        sa.Column("scenario", sa.JSON, nullable=True),
        sa.Column("summary", sa.JSON, nullable=True),
        sa.Index("ix_flexride_jobs_status_created", "status", "created_at"),
        sa.Index("ix_flexride_jobs_study", "study_id", "study_index"),
    )
    workers = sa.Table(
        "flexride_workers", meta,
        sa.Column("name", sa.String(200), primary_key=True),
        sa.Column("kind", sa.String(16), nullable=False),
        sa.Column("hostname", sa.String(120), nullable=False),
        sa.Column("pid", sa.Integer, nullable=False),
        sa.Column("started_at", sa.Float, nullable=False),
        sa.Column("last_seen", sa.Float, nullable=False, index=True),
        sa.Column("current_job", sa.String(32), nullable=True),
    )
    schema = sa.Table(
        "flexride_schema", meta,
        sa.Column("id", sa.Integer, primary_key=True),
        sa.Column("version", sa.Integer, nullable=False),
    )
    return [studies, jobs, workers, schema]


def upgrade() -> None:
    bind = op.get_bind()
    insp = sa.inspect(bind)
    present = set(insp.get_table_names())
    for table in _tables(sa.MetaData()):
        if table.name not in present:
            table.create(bind)
            continue
        have = {c["name"] for c in insp.get_columns(table.name)}
        for column in table.columns:
            if column.name not in have:  # an older store: the column is added nullable
                op.add_column(table.name, sa.Column(column.name, column.type, nullable=True))


def downgrade() -> None:
    for name in ("flexride_jobs", "flexride_studies", "flexride_workers", "flexride_schema"):
        op.drop_table(name)
