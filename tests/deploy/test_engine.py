"""How the deployment test gets its Docker engine, and the one line it fails with when there is
none (tests/deploy/engine.py). No engine needed."""

from __future__ import annotations

import pytest

from deploy import engine


def test_the_daemons_own_words_are_the_reason(tmp_path):
    log = tmp_path / "dockerd.log"
    log.write_text(
        'time="2026-12-01T22:37:10Z" level=info msg="Starting up"\n'
        'time="2026-12-01T22:37:11Z" level=error msg="iptables failed: no chain DOCKER"\n'
        'failed to start daemon: Error initializing network controller: iptables failed\n')
    assert engine._why_not(log) == ("failed to start daemon: Error initializing network "
                                    "controller: iptables failed")
    log.write_text('time="x" level=fatal msg="could not open the data root"\n')
    assert engine._why_not(log) == "could not open the data root"
    assert engine._why_not(tmp_path / "missing.log") == "no output"


def test_a_given_engine_that_does_not_answer_is_one_line(monkeypatch, tmp_path):
    monkeypatch.setenv("FLEXRIDE_DOCKER_HOST", f"unix://{tmp_path / 'none.sock'}")
    with pytest.raises(engine.EngineUnavailable) as exc:
        engine.get_engine()
    assert "\n" not in str(exc.value) and "FLEXRIDE_DOCKER_HOST" in str(exc.value)


def test_without_root_it_says_so(monkeypatch):
    monkeypatch.delenv("FLEXRIDE_DOCKER_HOST", raising=False)
    monkeypatch.setattr(engine.os, "geteuid", lambda: 1000)
    with pytest.raises(engine.EngineUnavailable, match="needs root"):
        engine.get_engine()
