"""Fixtures of the API tests: the real app on SQLite and on PostgreSQL (no runner: jobs are
recorded, not run; the end-to-end tests in tests/jobs run them)."""

from __future__ import annotations

import pytest

from service.svc_testkit import make_settings, pg_schema


def pytest_configure(config):
    config.addinivalue_line("filterwarnings", "ignore:Using `httpx`")


@pytest.fixture(params=["sqlite", "postgresql"])
def db_url(request, tmp_path):
    """Database URL: a SQLite file under tmp_path, or a fresh PostgreSQL schema."""
    if request.param == "sqlite":
        yield f"sqlite:///{tmp_path / 'jobs.db'}"
    else:
        with pg_schema() as url:
            yield url


@pytest.fixture
def make_client(tmp_path):
    """Factory: a started TestClient of the real app with the given settings."""
    from fastapi.testclient import TestClient

    from flexride.api import create_app

    clients = []

    def make(**kw):
        settings = make_settings(tmp_path / "data", **kw)
        client = TestClient(create_app(settings), raise_server_exceptions=False)
        client.__enter__()
        clients.append(client)
        return client

    yield make
    for c in clients:
        c.__exit__(None, None, None)


@pytest.fixture
def client(make_client, db_url):
    """The app on SQLite and on PostgreSQL."""
    return make_client(database_url=db_url)


@pytest.fixture
def sqlite_client(make_client):
    """The app on its default SQLite store."""
    return make_client()

