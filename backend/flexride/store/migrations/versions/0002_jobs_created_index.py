"""Index of the job list (newest first): (created_at, id) of flexride_jobs.

Revision ID: 0002
Revises: 0001
Create Date: 2026-12-01
"""

from __future__ import annotations

from alembic import op

revision = "0002"
down_revision = "0001"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_index("ix_flexride_jobs_created", "flexride_jobs", ["created_at", "id"])


def downgrade() -> None:
    op.drop_index("ix_flexride_jobs_created", table_name="flexride_jobs")
