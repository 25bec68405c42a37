"""The database change counter (flexride.store.data_version): it changes with every commit by
any connection or process, not with reads, and PostgreSQL has none."""

from __future__ import annotations

import subprocess
import sys

from sqlalchemy import text

from flexride.store import JobStore
from service.svc_testkit import pg_schema

COMMIT_IN_CHILD = """
import sys
from sqlalchemy import text
from flexride.store.db import create_store_engine
engine = create_store_engine(sys.argv[1])
with engine.begin() as conn:
    conn.execute(text("INSERT INTO scratch VALUES (1)"))
"""


def test_sqlite_counter_changes_with_commits_of_any_process(tmp_path):
    url = f"sqlite:///{tmp_path / 'store.db'}"
    store = JobStore.from_url(url)
    v0 = store.data_version()
    assert isinstance(v0, int)
    store.list_jobs()  # reads change nothing
    assert store.data_version() == v0
    with store.engine.begin() as conn:  # a pooled connection of this process
        conn.execute(text("CREATE TABLE scratch (a INTEGER)"))
    v1 = store.data_version()
    assert v1 != v0
    subprocess.run([sys.executable, "-c", COMMIT_IN_CHILD, url], check=True, timeout=120)
    assert store.data_version() not in (v0, v1)


def test_postgresql_has_no_counter():
    with pg_schema() as url:
        assert JobStore.from_url(url).data_version() is None
