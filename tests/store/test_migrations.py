"""Alembic migrations of the job store, on SQLite and PostgreSQL: an empty database reaches the
models' layout exactly, a store made before Alembic is adopted with its rows, and migrating
is idempotent."""

from __future__ import annotations

import pytest
from alembic.autogenerate import compare_metadata
from alembic.runtime.migration import MigrationContext
from sqlalchemy import inspect, text

from flexride.store import create_store_engine, init_db
from flexride.store.db import VERSION_TABLE, current_revision, head_revision
from flexride.store.models import Base
from service.svc_testkit import pg_schema


@pytest.fixture(params=["sqlite", "postgresql"])
def engine(request, tmp_path):
    if request.param == "sqlite":
        eng = create_store_engine(f"sqlite:///{tmp_path / 'jobs.db'}")
        yield eng
        eng.dispose()
    else:
        with pg_schema() as url:
            eng = create_store_engine(url)
            yield eng
            eng.dispose()


def _differences(engine) -> list:
    with engine.connect() as conn:
        ctx = MigrationContext.configure(conn, opts={"version_table": VERSION_TABLE,
                                                     "compare_type": True})
        return compare_metadata(ctx, Base.metadata)


def test_an_empty_database_gets_exactly_the_models_layout(engine):
    assert current_revision(engine) is None
    init_db(engine)
    assert current_revision(engine) == head_revision()
    assert _differences(engine) == []
    names = set(inspect(engine).get_table_names())
    assert {"flexride_jobs", "flexride_studies", "flexride_workers", VERSION_TABLE} <= names
    assert "flexride_schema" not in names
    init_db(engine)  # idempotent
    assert current_revision(engine) == head_revision()


LEGACY_JOBS = """CREATE TABLE flexride_jobs (
    id VARCHAR(32) PRIMARY KEY, name VARCHAR(120) NOT NULL, status VARCHAR(16) NOT NULL,
    progress FLOAT NOT NULL, message VARCHAR(400) NOT NULL, error TEXT, created_at FLOAT NOT NULL,
    updated_at FLOAT NOT NULL, started_at FLOAT, finished_at FLOAT, heartbeat_at FLOAT,
    runner VARCHAR(16) NOT NULL, worker VARCHAR(200), attempts INTEGER NOT NULL,
    max_attempts INTEGER NOT NULL, cancel_requested BOOLEAN NOT NULL,
    scenario_hash VARCHAR(64) NOT NULL, preset VARCHAR(80), speed_kmh FLOAT, duration_s FLOAT,
    study_id VARCHAR(32), study_index INTEGER, axes JSON NOT NULL, reused_from VARCHAR(32),
    result_file VARCHAR(200), run_meta JSON NOT NULL, scenario JSON, summary JSON)"""


def test_a_store_made_before_alembic_is_adopted_with_its_rows(engine):
    """A store of flexride 0.1 without the later column wall_time_s, without the job-list
    index and with its schema row: the baseline adds the column, later revisions the index."""
    with engine.begin() as conn:
        conn.execute(text(LEGACY_JOBS))
        conn.execute(text("CREATE TABLE flexride_schema (id INTEGER PRIMARY KEY, "
                          "version INTEGER NOT NULL)"))
        conn.execute(text("INSERT INTO flexride_schema VALUES (1, 1)"))
        conn.execute(text(
            "INSERT INTO flexride_jobs (id, name, status, progress, message, created_at, "
            "updated_at, runner, attempts, max_attempts, cancel_requested, scenario_hash, axes, "
            "run_meta, scenario) VALUES ('a', 'old job', 'succeeded', 1.0, 'done', 1.0, 2.0, "
            "'embedded', 1, 2, false, 'h', '{}', '{}', '{}')"))
    init_db(engine)
    assert current_revision(engine) == head_revision()
    cols = {c["name"] for c in inspect(engine).get_columns("flexride_jobs")}
    assert "wall_time_s" in cols
    assert "ix_flexride_jobs_created" in {i["name"] for i in inspect(engine).get_indexes(
        "flexride_jobs")}
    with engine.connect() as conn:
        assert conn.execute(text("SELECT name FROM flexride_jobs")).scalar_one() == "old job"
    # the legacy table had no indexes of its own and no foreign key: those are the only
    # differences left (nothing the service relies on for correctness)
    diffs = [d if isinstance(d, tuple) else d[0] for d in _differences(engine)]
    assert {d[0] for d in diffs} <= {"add_index", "add_fk", "modify_nullable"}, diffs
    # (SQLite reports a VARCHAR primary key of hand-written DDL as nullable)
    assert all(d[3] in ("wall_time_s", "id") for d in diffs if d[0] == "modify_nullable"), diffs


def test_revision_0004_makes_every_existing_job_a_simulation(engine):
    """A store at revision 0003 with a job gets the ``kind`` column, ``simulation`` for the
    rows it has; new rows without a kind get it too (server default)."""
    from alembic import command

    from flexride.store.db import _alembic

    with engine.begin() as conn:
        command.upgrade(_alembic(conn), "0003")
    assert current_revision(engine) == "0003"
    columns = ("id, name, status, progress, message, created_at, updated_at, runner, attempts, "
               "max_attempts, cancel_requested, scenario_hash, axes, run_meta, scenario")
    row = ("'{id}', 'old job', 'succeeded', 1.0, 'done', 1.0, 2.0, 'embedded', 1, 2, false, "
           "'h', '{{}}', '{{}}', '{{}}'")
    with engine.begin() as conn:
        conn.execute(text(f"INSERT INTO flexride_jobs ({columns}) VALUES "
                          f"({row.format(id='a')})"))
    init_db(engine)
    assert current_revision(engine) == head_revision()
    assert _differences(engine) == []
    with engine.begin() as conn:
        conn.execute(text(f"INSERT INTO flexride_jobs ({columns}) VALUES "
                          f"({row.format(id='b')})"))
        kinds = dict(conn.execute(text("SELECT id, kind FROM flexride_jobs")).all())
    assert kinds == {"a": "simulation", "b": "simulation"}
