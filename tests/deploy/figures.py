"""Figures of the deployment test (image build times and sizes, the stack's start, the restart),
shown in the terminal summary by tests/deploy/conftest.py."""

from __future__ import annotations

import pytest

FIGURES = pytest.StashKey[list[str]]()


def record(config: pytest.Config, line: str) -> None:
    """Add ``line`` to the figures shown at the end of the session."""
    config.stash.setdefault(FIGURES, []).append(line)
