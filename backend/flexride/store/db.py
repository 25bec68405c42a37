"""Database engines and schema creation for the job store (SQLite by default, PostgreSQL by URL).

SQLite is used from several processes at once (the API and the worker processes), so every
connection runs in WAL mode with a busy timeout, and writing transactions start with
``BEGIN IMMEDIATE`` (taking the write lock up front instead of failing on a lock upgrade).
Engines are cached per process: a forked worker gets its own engine and never touches the
parent's connections.
"""

from __future__ import annotations

import logging
import os
import threading
from pathlib import Path

from sqlalchemy import Engine, create_engine, event, insert, inspect, text, update
from sqlalchemy.engine import make_url

from flexride.store.models import SCHEMA_VERSION, Base, SchemaInfo

log = logging.getLogger(__name__)

_ENGINES: dict[tuple[int, str], Engine] = {}
_LOCK = threading.Lock()
_PG_LOCK_KEY = 0x464C5852  # "FLXR": advisory lock serialising schema creation


def _sqlite_events(engine: Engine) -> None:
    @event.listens_for(engine, "connect")
    def _on_connect(dbapi_conn, _record):  # pragma: no cover - exercised through SQLite
        dbapi_conn.isolation_level = None  # transactions are begun below, not by the driver
        cur = dbapi_conn.cursor()
        cur.execute("PRAGMA journal_mode=WAL")
        cur.execute("PRAGMA busy_timeout=30000")
        cur.execute("PRAGMA synchronous=NORMAL")
        cur.execute("PRAGMA foreign_keys=ON")
        cur.close()

    @event.listens_for(engine, "begin")
    def _on_begin(conn):  # pragma: no cover - exercised through SQLite
        mode = conn.get_execution_options().get("sqlite_begin", "DEFERRED")
        conn.exec_driver_sql(f"BEGIN {mode}")


def create_store_engine(url: str) -> Engine:
    """A new engine for ``url`` configured for the job store.

    Parameters
    ----------
    url : str
        SQLAlchemy URL: ``sqlite:///path.db`` or ``postgresql+psycopg://...``
        (``postgresql://`` is taken as psycopg 3).
    """
    u = make_url(url)
    if u.drivername in ("postgresql", "postgres"):
        u = u.set(drivername="postgresql+psycopg")
    if u.get_backend_name() == "sqlite":
        if u.database and u.database != ":memory:":
            Path(u.database).expanduser().parent.mkdir(parents=True, exist_ok=True)
        engine = create_engine(
            u, connect_args={"check_same_thread": False, "timeout": 30.0}, pool_pre_ping=True
        )
        _sqlite_events(engine)
        return engine
    return create_engine(u, pool_pre_ping=True, pool_size=5, max_overflow=10,
                         pool_recycle=1800)


def get_engine(url: str) -> Engine:
    """The engine of this process for ``url`` (created on first use, again after a fork)."""
    key = (os.getpid(), url)
    with _LOCK:
        engine = _ENGINES.get(key)
        if engine is None:
            for old_key in [k for k in _ENGINES if k[0] != key[0]]:
                _ENGINES.pop(old_key).dispose(close=False)  # inherited from the parent
            engine = _ENGINES[key] = create_store_engine(url)
        return engine


def writer(engine: Engine) -> Engine:
    """``engine`` with writing transactions (``BEGIN IMMEDIATE`` on SQLite)."""
    return engine.execution_options(sqlite_begin="IMMEDIATE")


def _add_missing_columns(conn) -> list[str]:
    """Add columns that the models have and the tables lack (forward migration)."""
    added = []
    insp = inspect(conn)
    for table in Base.metadata.sorted_tables:
        existing = {c["name"] for c in insp.get_columns(table.name)}
        for column in table.columns:
            if column.name in existing:
                continue
            # added as nullable: existing rows have no value for it
            name = conn.dialect.identifier_preparer.quote(column.name)
            kind = column.type.compile(dialect=conn.dialect)
            conn.execute(text(f"ALTER TABLE {table.name} ADD COLUMN {name} {kind}"))
            added.append(f"{table.name}.{column.name}")
    return added


def init_db(engine: Engine) -> None:
    """Create the tables, add columns missing from an older store and record the version.

    Safe to call from several processes at once (an advisory lock on PostgreSQL, the write
    lock on SQLite).
    """
    with writer(engine).begin() as conn:
        if conn.dialect.name == "postgresql":
            conn.execute(text("SELECT pg_advisory_xact_lock(:k)"), {"k": _PG_LOCK_KEY})
        Base.metadata.create_all(conn, checkfirst=True)
        added = _add_missing_columns(conn)
        if added:
            log.info("job store migrated: added %s", ", ".join(added))
        row = conn.execute(text("SELECT version FROM flexride_schema WHERE id = 1")).first()
        if row is None:
            conn.execute(insert(SchemaInfo).values(id=1, version=SCHEMA_VERSION))
        elif row[0] < SCHEMA_VERSION:
            conn.execute(
                update(SchemaInfo).where(SchemaInfo.id == 1).values(version=SCHEMA_VERSION)
            )
