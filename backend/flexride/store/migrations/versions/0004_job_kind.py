"""Job kinds: ``flexride_jobs.kind``, ``simulation`` (every existing job) or ``fe_export`` (the
browser export of an FE body, run by the job runner like a simulation).

Revision ID: 0004
Revises: 0003
Create Date: 2027-01-15
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = "0004"
down_revision = "0003"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.add_column("flexride_jobs", sa.Column("kind", sa.String(16), nullable=False,
                                             server_default=sa.text("'simulation'")))


def downgrade() -> None:
    with op.batch_alter_table("flexride_jobs") as batch:
        batch.drop_column("kind")
