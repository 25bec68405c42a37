"""The image's entry point and health check (docker/entrypoint.py, docker/healthcheck.py) as
plain Python: secrets from files, the wait for the database and the broker (this machine's
Redis and PostgreSQL, as the other service tests use them), the one line when they stay
away. No Docker engine needed."""

from __future__ import annotations

import importlib.util
import socket
from pathlib import Path
from types import ModuleType

import pytest
from sqlalchemy.engine import make_url

REPO = Path(__file__).resolve().parents[2]


def _load(name: str) -> ModuleType:
    spec = importlib.util.spec_from_file_location(f"flexride_docker_{name}",
                                                  REPO / "docker" / f"{name}.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


entrypoint = _load("entrypoint")
healthcheck = _load("healthcheck")


def _closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def test_secrets_from_files(tmp_path):
    (tmp_path / "token").write_text("k9Fq2-ZxT7_wLp3Rv8Ys\n")
    (tmp_path / "pw").write_text("p@ss/wörd:1\n")
    env = {"FLEXRIDE_API_TOKEN": "", "FLEXRIDE_API_TOKEN_FILE": str(tmp_path / "token"),
           "FLEXRIDE_DATABASE_PASSWORD_FILE": str(tmp_path / "pw"),
           "FLEXRIDE_DATABASE_URL": "postgresql+psycopg://flexride:flexride@postgres:5432/fx"}
    entrypoint.read_secret_files(env)
    assert env["FLEXRIDE_API_TOKEN"] == "k9Fq2-ZxT7_wLp3Rv8Ys"
    url = make_url(env["FLEXRIDE_DATABASE_URL"])
    assert url.password == "p@ss/wörd:1" and url.host == "postgres" and url.database == "fx"
    assert not any(k.endswith("_FILE") for k in env)  # nothing passed on to flexride


def test_a_secret_set_both_ways_is_refused(tmp_path):
    (tmp_path / "token").write_text("x")
    env = {"FLEXRIDE_API_TOKEN": "abc", "FLEXRIDE_API_TOKEN_FILE": str(tmp_path / "token")}
    with pytest.raises(SystemExit, match="not both"):
        entrypoint.read_secret_files(env)


def test_waits_for_this_machines_redis_and_postgresql():
    env = {"FLEXRIDE_BROKER_URL": "redis://127.0.0.1:6379/0", "FLEXRIDE_WAIT_S": "10",
           "FLEXRIDE_DATABASE_URL": "postgresql+psycopg://postgres@127.0.0.1:5432/test"}
    entrypoint.wait_for_services(env)  # returns: both answer


def test_gives_up_with_one_line_when_a_service_stays_away(capsys):
    env = {"FLEXRIDE_BROKER_URL": f"redis://127.0.0.1:{_closed_port()}/0",
           "FLEXRIDE_WAIT_S": "1.5"}
    with pytest.raises(SystemExit) as exc:
        entrypoint.wait_for_services(env)
    message = str(exc.value)
    assert message.startswith("flexride-entrypoint: Redis is not reachable after 1.5 s")
    assert "\n" not in message and "waiting for Redis" in capsys.readouterr().err


def test_no_wait_for_sqlite_or_when_told_not_to():
    entrypoint.wait_for_services({"FLEXRIDE_DATABASE_URL": "sqlite:////data/flexride.db"})
    entrypoint.wait_for_services({"FLEXRIDE_BROKER_URL": f"redis://127.0.0.1:{_closed_port()}",
                                  "FLEXRIDE_WAIT_S": "0"})


def test_healthcheck_usage_and_an_api_that_is_down(monkeypatch, capsys):
    assert healthcheck.main([]) == 2
    monkeypatch.setenv("FLEXRIDE_PORT", str(_closed_port()))
    assert healthcheck.main(["api"]) == 1
    assert capsys.readouterr().out.startswith("health:")
    monkeypatch.delenv("FLEXRIDE_BROKER_URL", raising=False)
    assert healthcheck.worker_problem() == "FLEXRIDE_BROKER_URL is not set"
