"""Service settings from FLEXRIDE_* environment variables."""

from __future__ import annotations

from pathlib import Path

import pytest
from pydantic import ValidationError

from flexride.settings import Settings, get_settings, url_location


@pytest.fixture
def clean_env(monkeypatch):
    import os

    for key in [k for k in os.environ if k.startswith("FLEXRIDE_")]:
        monkeypatch.delenv(key)
    return monkeypatch


def test_defaults_need_no_configuration(clean_env, tmp_path):
    clean_env.setenv("HOME", str(tmp_path))
    clean_env.delenv("XDG_DATA_HOME", raising=False)
    s = Settings(_env_file=None)
    assert s.data_dir == (tmp_path / ".local" / "share" / "flexride").resolve()
    assert s.effective_database_url == f"sqlite:///{s.data_dir / 'flexride.db'}"
    assert s.results_dir == s.data_dir / "results"
    assert s.effective_runner == "embedded" and s.bind_host == "127.0.0.1"
    assert s.workers >= 1 and s.api_token is None and s.port == 8000


def test_environment_variables(clean_env, tmp_path):
    clean_env.setenv("FLEXRIDE_DATA_DIR", str(tmp_path / "d"))
    clean_env.setenv("FLEXRIDE_BROKER_URL", "redis://127.0.0.1:6379/0")
    clean_env.setenv("FLEXRIDE_DATABASE_URL", "postgresql+psycopg://u:pw@db/x")
    clean_env.setenv("FLEXRIDE_WORKERS", "3")
    clean_env.setenv("FLEXRIDE_API_TOKEN", "")  # empty = unset
    clean_env.setenv("FLEXRIDE_HOST", "0.0.0.0")
    get_settings.cache_clear()
    try:
        s = get_settings()
        assert s.data_dir == (tmp_path / "d").resolve() and s.workers == 3
        assert s.effective_runner == "celery" and s.api_token is None
        assert s.effective_database_url.startswith("postgresql+psycopg://")
        assert s.bind_host == "0.0.0.0"
    finally:
        get_settings.cache_clear()
    clean_env.setenv("FLEXRIDE_WORKERS", "0")
    with pytest.raises(ValidationError):
        Settings(_env_file=None)
    clean_env.delenv("FLEXRIDE_WORKERS")
    assert Settings(_env_file=None, runner="none", workers=1).effective_runner == "none"
    assert isinstance(Settings(_env_file=None, data_dir="~/x").data_dir, Path)


def test_url_location_has_no_credentials_query_or_path():
    assert url_location("postgresql+psycopg://u:secret@h:5432/db?options=-csearch_path%3Dx") \
        == "postgresql://h:5432/db"
    assert url_location("redis://:secret@h:6379/0") == "redis://h:6379/0"
    assert url_location("rediss://u:pw@[::1]:6380/2") == "rediss://[::1]:6380/2"
    assert url_location("sqlite:////srv/data/flexride.db") == "sqlite:flexride.db"
    assert url_location("sqlite://") == "sqlite::memory:"
    assert url_location(None) is None
