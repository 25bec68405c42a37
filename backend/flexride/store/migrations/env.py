"""Alembic environment of the job store: runs on the connection that
:func:`flexride.store.db.init_db` passes (``config.attributes["connection"]``), or, for
developers running ``alembic`` by hand, on ``FLEXRIDE_DATABASE_URL`` (default: the service's
SQLite file)."""

from __future__ import annotations

from alembic import context

from flexride.store.models import Base

VERSION_TABLE = "flexride_alembic_version"


def _run(connection) -> None:
    context.configure(connection=connection, target_metadata=Base.metadata,
                      version_table=VERSION_TABLE, render_as_batch=True,
                      compare_type=True)
    with context.begin_transaction():
        context.run_migrations()


def main() -> None:
    connection = context.config.attributes.get("connection")
    if connection is not None:
        _run(connection)
        return
    from flexride.settings import get_settings
    from flexride.store.db import create_store_engine

    engine = create_store_engine(get_settings().effective_database_url)
    with engine.begin() as conn:
        _run(conn)


main()
