"""A cheap test of whether anything in the database changed: SQLite's ``PRAGMA data_version``.

Read caches of job records (the job list, a job's detail) key their answers by this number,
so a request that finds nothing changed costs one pragma instead of a query, ORM rows and
validation. The pragma's value, read on a connection of its own that never writes, changes
whenever any other connection commits a change: the pooled connections of this process, the
embedded runner's worker processes, Celery workers, other API processes. PostgreSQL has no
such number; there the answer is None and callers do not cache.
"""

from __future__ import annotations

import os
import sqlite3
import threading
from typing import Any

from sqlalchemy import Engine


class DataVersion:
    """The change counter of one engine's database, for this process.

    Parameters
    ----------
    engine : sqlalchemy.Engine
        The store's engine; only SQLite has a counter.
    """

    def __init__(self, engine: Engine):
        self.engine = engine
        self.supported = engine.dialect.name == "sqlite" and engine.url.database not in (
            None, "", ":memory:")
        self._lock = threading.Lock()
        self._conn: Any = None
        self._pid = -1

    def current(self) -> int | None:
        """A number that differs from every earlier one after any committed change, or None
        when the database cannot tell (PostgreSQL, in-memory SQLite, a failed read).
        """
        if not self.supported:
            return None
        with self._lock:
            try:
                conn = self._connection()
                return int(conn.execute("PRAGMA data_version").fetchone()[0])
            except (sqlite3.Error, OSError):
                self._close()
                return None

    def _connection(self) -> Any:
        if self._conn is None or self._pid != os.getpid():  # a forked child opens its own
            self._conn = None
            raw = self.engine.raw_connection()
            conn = raw.driver_connection
            raw.detach()  # private to this counter, never returned to the pool
            self._conn, self._pid = conn, os.getpid()
        return self._conn

    def _close(self) -> None:
        if self._conn is not None and self._pid == os.getpid():
            try:
                self._conn.close()
            except sqlite3.Error:
                pass
        self._conn = None
