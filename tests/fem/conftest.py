"""Fixtures of the FE tests: the paper's vehicle and a private cache directory."""

from __future__ import annotations

import pytest

from flexride.scenario.presets import load_preset


@pytest.fixture(scope="session")
def vehicle():
    """The paper-metro vehicle parameters."""
    return load_preset("paper-metro").vehicle


@pytest.fixture
def cache_dir(tmp_path, monkeypatch):
    """Point the FE cache at a temporary directory."""
    monkeypatch.setenv("FLEXRIDE_CACHE_DIR", str(tmp_path / "cache"))
    return tmp_path / "cache"
