"""Database errors told apart by their codes (flexride.store.probe): a fault of the database
(503 in the API) or a defect (500). SQLite's errors are made by a real database; PostgreSQL's
come from the server in tests/api/test_database_faults.py and are checked here for every code
of the table."""

from __future__ import annotations

import sqlite3

import psycopg.errors
import pytest
from sqlalchemy import create_engine, text
from sqlalchemy.exc import DBAPIError

from flexride.store.probe import PG_FAULTS, classify, db_fault, retryable


def _wrapped(orig: Exception) -> DBAPIError:
    return DBAPIError("INSERT …", {}, orig)


@pytest.mark.parametrize("code", sorted(c for c in PG_FAULTS if len(c) == 5))
def test_every_postgresql_code_of_the_table_is_a_fault(code):
    exc = _wrapped(psycopg.errors.lookup(code)("from the server"))
    assert db_fault(exc) == f"database {PG_FAULTS[code].reason}"
    assert retryable(exc) == (code in ("40001", "40P01"))


@pytest.mark.parametrize(("code", "reason"), [
    ("53400", "out of resources"),  # configuration_limit_exceeded: its class
    ("08006", "connection lost"),
    ("57P03", "connection lost (ended by the server)"),
    ("58P01", "I/O error"),
])
def test_a_class_stands_for_its_codes(code, reason):
    assert db_fault(_wrapped(psycopg.errors.lookup(code)("x"))) == f"database {reason}"


@pytest.mark.parametrize("code", ["23505", "22P05", "42P01", "42601", "22003"])
def test_defects_are_not_storage_faults(code):
    # unique violation, NUL in text, missing table, syntax error, numeric out of range
    assert classify(_wrapped(psycopg.errors.lookup(code)("x"))) is None


def test_sqlite_faults_by_result_code(tmp_path):
    db = tmp_path / "x.db"
    engine = create_engine(f"sqlite:///{db}")
    with engine.begin() as conn:
        conn.execute(text("CREATE TABLE t (x INTEGER PRIMARY KEY)"))
        conn.execute(text("INSERT INTO t VALUES (1)"))
    with pytest.raises(DBAPIError) as dup, engine.begin() as conn:
        conn.execute(text("INSERT INTO t VALUES (1)"))
    assert classify(dup.value) is None  # a constraint: a defect, 500
    read_only = create_engine(f"sqlite:///file:{db}?mode=ro&uri=true")
    with pytest.raises(DBAPIError) as ro, read_only.begin() as conn:
        conn.execute(text("INSERT INTO t VALUES (2)"))
    assert db_fault(ro.value) == "database read-only"
    with pytest.raises(DBAPIError) as gone, engine.begin() as conn:
        conn.execute(text("SELECT * FROM nowhere"))
    assert classify(gone.value) is None  # no such table: SQLITE_ERROR, a defect
    assert isinstance(ro.value.orig, sqlite3.OperationalError)


def test_no_answer_from_the_server_and_no_free_connection():
    from sqlalchemy.exc import TimeoutError as PoolTimeout

    refused = psycopg.OperationalError("connection failed: Connection refused")
    assert db_fault(_wrapped(refused)) == "database unreachable"
    assert db_fault(PoolTimeout("QueuePool limit reached")) == "database busy (no free connection)"
    assert classify(ValueError("not a database error")) is None
