"""A tiny paper study shared by the report and CLI tests: two conditions, one speed, runs of
about 6 s of evaluated track, a coarse FE mesh (0.5 m, modes to 30 Hz: built in seconds or
taken from the FE cache), an element-size pre-calculation on three coarse meshes, two worker
processes."""

from __future__ import annotations

from pathlib import Path

import pytest

from flexride.paper import ReportOptions

TINY_OVERRIDES = (("bodies.carbody.element_size_m", 0.5), ("bodies.carbody.cutoff_hz", 30.0),
                  ("bodies.frames.cutoff_hz", 30.0))
TINY_MESH = (0.7, 0.6, 0.5)
"""The tiny study's element-size pre-calculation: three coarse meshes (built in seconds)."""


def tiny_options(**changes) -> ReportOptions:
    """Options of the tiny study (keyword arguments change fields)."""
    base = dict(conditions=("random-straight", "settlement"), speeds=(50.0,), seeds=1,
                distance_scale=0.01, jobs=2, overrides=TINY_OVERRIDES, mesh_sizes=TINY_MESH)
    base.update(changes)
    return ReportOptions(**base)


@pytest.fixture(scope="session")
def tiny_report(tmp_path_factory) -> tuple[Path, object]:
    """(directory, ReportResult) of the tiny study, run once per session."""
    from flexride.paper import run_report

    directory = tmp_path_factory.mktemp("paper") / "report"
    return directory, run_report(directory, tiny_options())
