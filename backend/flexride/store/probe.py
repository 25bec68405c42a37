"""Is the storage writable? Probes of directories and of the database, and the readable
reasons of storage faults (a read-only or full disk, a database that refuses writes).

Messages name the fault and the storage part (``results directory``, ``database``), never a
server path, so they can go into API answers (503 ``storage unavailable: …``).
"""

from __future__ import annotations

import errno
import os
import tempfile
from pathlib import Path

from sqlalchemy import text
from sqlalchemy.engine import Engine
from sqlalchemy.exc import DBAPIError

STORAGE_ERRNOS = frozenset({errno.EROFS, errno.ENOSPC, errno.EDQUOT, errno.EACCES,
                            errno.EPERM, errno.EIO})
"""``OSError`` numbers that mean the storage itself is at fault (not the request)."""

_DB_FAULTS = (
    ("readonly", "read-only"), ("read-only", "read-only"), ("read only", "read-only"),
    ("disk is full", "full"), ("no space left", "full"), ("disk full", "full"),
    ("could not extend file", "full"), ("unable to open", "cannot be opened"),
    ("connection", "unreachable"), ("could not connect", "unreachable"),
    ("server closed", "unreachable"), ("locked", "locked by another writer"),
)


def os_fault(exc: OSError) -> str:
    """A short reason of a storage ``OSError`` (its ``strerror``, lower case, no path)."""
    return (exc.strerror or errno.errorcode.get(exc.errno or 0, type(exc).__name__)).lower()


def is_storage_oserror(exc: BaseException) -> bool:
    """Whether ``exc`` is an ``OSError`` of the storage (read-only, full, no permission)."""
    return isinstance(exc, OSError) and exc.errno in STORAGE_ERRNOS


def db_fault(exc: DBAPIError) -> str:
    """A short reason of a database error: read-only, full, unreachable… (no SQL, no path)."""
    msg = str(getattr(exc, "orig", exc)).lower()
    for needle, reason in _DB_FAULTS:
        if needle in msg:
            return f"database {reason}"
    return f"database error ({type(getattr(exc, 'orig', exc)).__name__})"


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
    """Why the database refuses writes, or None: a table is created in a transaction that is
    rolled back, so nothing stays behind.
    """
    try:
        with engine.connect() as conn:
            tx = conn.begin()
            try:
                conn.execute(text("CREATE TABLE flexride_write_probe (x INTEGER)"))
                conn.execute(text("INSERT INTO flexride_write_probe (x) VALUES (1)"))
            finally:
                tx.rollback()
    except DBAPIError as exc:
        return db_fault(exc)
    return None
