"""The deployment test's figures in the terminal summary, where they are seen with ``-q`` and
captured output alike."""

from __future__ import annotations

import pytest

from deploy.figures import FIGURES


def pytest_terminal_summary(terminalreporter: pytest.TerminalReporter,
                            config: pytest.Config) -> None:
    lines = config.stash.get(FIGURES, [])
    if lines:
        terminalreporter.write_sep("-", "docker deployment figures")
        for line in lines:
            terminalreporter.write_line(line)
