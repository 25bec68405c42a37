"""Is the storage writable? Probes of directories and of the database, and the readable
reasons of storage faults (a read-only or full disk, a database that refuses writes).

Database errors are told apart by their codes, never by their text: PostgreSQL's SQLSTATE
(psycopg's ``Error.sqlstate``) and SQLite's result code (``sqlite3.Error.sqlite_errorcode``).
A code listed here means *the database cannot take this write now* (read-only, no privilege,
full, connection lost, too busy): the API answers 503 ``storage unavailable: <reason>``. Any
other database error is a defect of the request handling (500).

Messages name the fault and the storage part (``results directory``, ``database``), never a
server path, so they can go into API answers.
"""

from __future__ import annotations

import errno
import os
import sqlite3
import tempfile
import uuid
from pathlib import Path
from typing import NamedTuple

from sqlalchemy import delete, false, insert, inspect, update
from sqlalchemy.engine import Engine
from sqlalchemy.exc import DBAPIError, DisconnectionError, SQLAlchemyError
from sqlalchemy.exc import TimeoutError as PoolTimeout

from flexride.store.models import Base, Job, Study, WorkerSeen

STORE_MODELS: tuple[type[Base], ...] = (WorkerSeen, Job, Study)
"""The tables the store writes (the database probe needs writes on each)."""
STORAGE_ERRNOS = frozenset({errno.EROFS, errno.ENOSPC, errno.EDQUOT, errno.EACCES,
                            errno.EPERM, errno.EIO})
"""``OSError`` numbers that mean the storage itself is at fault (not the request)."""


class Fault(NamedTuple):
    """A database fault: what the answer says, and whether the transaction may be tried again
    (the server rolled it back and a second attempt may well pass).
    """

    reason: str
    retry: bool = False


PG_FAULTS: dict[str, Fault] = {
    # SQLSTATE, or its class (first two characters) or prefix, → fault; longest match wins
    "25006": Fault("read-only"),                          # read_only_sql_transaction
    "42501": Fault("refuses writes (insufficient privilege)"),
    "53100": Fault("full"),                               # disk_full
    "53200": Fault("out of memory"),
    "53300": Fault("has too many connections"),
    "53": Fault("out of resources"),                      # insufficient resources
    "40001": Fault("busy (serialization failure)", retry=True),
    "40P01": Fault("busy (deadlock)", retry=True),
    "55P03": Fault("busy (lock not available)"),
    "57014": Fault("busy (statement cancelled)"),
    "08": Fault("connection lost"),                       # connection exceptions
    "57P": Fault("connection lost (ended by the server)"),  # admin/crash shutdown…
    "58": Fault("I/O error"),                             # system errors (io_error)
}
"""PostgreSQL errors that mean the database cannot take writes now."""

SQLITE_FAULTS: dict[int, Fault] = {
    sqlite3.SQLITE_PERM: Fault("refuses writes (permission)"),
    sqlite3.SQLITE_BUSY: Fault("locked by another writer"),
    sqlite3.SQLITE_LOCKED: Fault("locked by another writer"),
    sqlite3.SQLITE_READONLY: Fault("read-only"),
    sqlite3.SQLITE_IOERR: Fault("I/O error"),
    sqlite3.SQLITE_CORRUPT: Fault("damaged"),
    sqlite3.SQLITE_FULL: Fault("full"),
    sqlite3.SQLITE_CANTOPEN: Fault("cannot be opened"),
    sqlite3.SQLITE_NOTADB: Fault("damaged"),
}
"""SQLite primary result codes that mean the database cannot take writes now."""

UNREACHABLE = Fault("unreachable")
"""A connection that could not be made or was lost, without a server's error code."""
POOL_EXHAUSTED = Fault("busy (no free connection)")
"""Every connection of the pool stayed in use for the pool's timeout."""


def os_fault(exc: OSError) -> str:
    """A short reason of a storage ``OSError`` (its ``strerror``, lower case, no path)."""
    return (exc.strerror or errno.errorcode.get(exc.errno or 0, type(exc).__name__)).lower()


def is_storage_oserror(exc: BaseException) -> bool:
    """Whether ``exc`` is an ``OSError`` of the storage (read-only, full, no permission)."""
    return isinstance(exc, OSError) and exc.errno in STORAGE_ERRNOS


def _pg_fault(sqlstate: str) -> Fault | None:
    for length in (5, 3, 2):
        fault = PG_FAULTS.get(sqlstate[:length])
        if fault is not None:
            return fault
    return None


def classify(exc: BaseException) -> Fault | None:
    """The storage fault behind a database error, or None when the error is not one (a
    defect: invalid SQL, a constraint, a value the column cannot hold).

    Parameters
    ----------
    exc : BaseException
        An error raised by SQLAlchemy (``DBAPIError`` wraps the driver's error in ``orig``,
        the pool raises ``TimeoutError``) or by a driver.
    """
    if isinstance(exc, PoolTimeout):
        return POOL_EXHAUSTED
    if isinstance(exc, DisconnectionError):
        return UNREACHABLE
    orig = exc.orig if isinstance(exc, DBAPIError) else exc
    if isinstance(orig, sqlite3.Error):
        code = getattr(orig, "sqlite_errorcode", None)
        return None if code is None else SQLITE_FAULTS.get(code & 0xFF)
    sqlstate = getattr(orig, "sqlstate", None)
    if sqlstate:
        return _pg_fault(str(sqlstate))
    if isinstance(exc, DBAPIError) and (
            exc.connection_invalidated or type(orig).__name__ in ("OperationalError",
                                                                  "InterfaceError")):
        return UNREACHABLE  # psycopg: no server answer (refused, reset, closed)
    return None


def db_fault(exc: BaseException) -> str | None:
    """``database <reason>`` of a database error that means the database cannot take writes
    now (read-only, full, unreachable…; no SQL, no path), or None for any other error.
    """
    fault = classify(exc)
    return None if fault is None else f"database {fault.reason}"


def retryable(exc: BaseException) -> bool:
    """Whether a failed transaction may simply be run again (serialization failure,
    deadlock: the server rolled it back).
    """
    fault = classify(exc)
    return fault is not None and fault.retry


def dir_problem(path: Path) -> str | None:
    """Why files cannot be written in ``path`` (created if missing), or None when a small
    file can be written, synced and removed there.
    """
    try:
        path.mkdir(parents=True, exist_ok=True)
        fd, name = tempfile.mkstemp(dir=path, prefix=".probe-", suffix=".tmp")
        try:
            os.write(fd, b"flexride write probe\n" * 8)
            os.fsync(fd)
        finally:
            os.close(fd)
            Path(name).unlink(missing_ok=True)
    except OSError as exc:
        return os_fault(exc)
    return None


def db_problem(engine: Engine) -> str | None:
    """Why the database refuses the store's writes, or None.

    One transaction, rolled back (nothing stays): a row inserted into the worker table, and
    in every table of the store an update and a delete that match no row — statements that
    still need the privileges the store's writes need (INSERT, UPDATE, DELETE) and a
    transaction that may write.
    """
    probe = {"name": f"write-probe-{uuid.uuid4().hex}", "kind": "probe", "hostname": "",
             "pid": 0, "started_at": 0.0, "last_seen": 0.0}
    try:
        with engine.connect() as conn:
            tx = conn.begin()
            try:
                conn.execute(insert(WorkerSeen).values(**probe))
                for model in STORE_MODELS:
                    key = inspect(model).primary_key[0]
                    conn.execute(update(model).where(false()).values({key: key}))
                    conn.execute(delete(model).where(false()))
            finally:
                tx.rollback()
    except SQLAlchemyError as exc:
        return db_fault(exc) or f"database error ({type(getattr(exc, 'orig', exc)).__name__})"
    return None
