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

from alembic import command
from alembic.config import Config as AlembicConfig
from alembic.runtime.migration import MigrationContext
from alembic.script import ScriptDirectory
from sqlalchemy import Connection, Engine, create_engine, event, text
from sqlalchemy.engine import make_url

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
        # no pre-ping: a SQLite connection is a file handle, it does not go stale
        engine = create_engine(u, connect_args={"check_same_thread": False, "timeout": 30.0})
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


MIGRATIONS = Path(__file__).parent / "migrations"
"""The Alembic scripts of the job store."""
VERSION_TABLE = "flexride_alembic_version"
"""Alembic's revision table of the job store (its own name: the database may hold others)."""


def _alembic(conn: Connection) -> AlembicConfig:
    cfg = AlembicConfig()
    cfg.set_main_option("script_location", str(MIGRATIONS))
    cfg.set_main_option("version_table", VERSION_TABLE)
    cfg.attributes["connection"] = conn
    return cfg


def head_revision() -> str:
    """The newest revision of the migrations."""
    head = ScriptDirectory(str(MIGRATIONS)).get_current_head()
    if head is None:  # pragma: no cover - the package ships its revisions
        raise RuntimeError("no migrations found")
    return head


def current_revision(engine: Engine) -> str | None:
    """The revision of the store behind ``engine`` (None for an empty database)."""
    with engine.connect() as conn:
        return MigrationContext.configure(
            conn, opts={"version_table": VERSION_TABLE}).get_current_revision()


def init_db(engine: Engine) -> None:
    """Bring the store to the newest revision of its Alembic migrations (creating the tables
    on an empty database; a store made before Alembic is adopted by the baseline revision).

    Safe to call from several processes at once (an advisory lock on PostgreSQL, the write
    lock on SQLite).
    """
    with writer(engine).begin() as conn:
        if conn.dialect.name == "postgresql":
            conn.execute(text("SELECT pg_advisory_xact_lock(:k)"), {"k": _PG_LOCK_KEY})
        before = MigrationContext.configure(
            conn, opts={"version_table": VERSION_TABLE}).get_current_revision()
        if before != head_revision():
            command.upgrade(_alembic(conn), "head")
            log.info("job store migrated from %s to %s", before or "nothing", head_revision())
