"""The summary's ``suspension`` block: the statistics of each recorded suspension force equal
NumPy's on the channel, over the record analysed (a window of a run as the paper's records cut
it)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from flexride.analysis import analyze
from flexride.paper.record import window_results

from .conftest import make_results

SPRINGS = ("1L", "1R", "2L", "2R")


@pytest.fixture(scope="module")
def run():
    res = make_results(duration=12.0)
    rng = np.random.default_rng(3)
    t = res.time
    for i, k in enumerate(SPRINGS):
        for d, static in (("x", 0.0), ("y", 50.0), ("z", 86.9e3)):
            name = f"secondary.{k}.force.{d}"
            res.channels[name] = (static + 2.0e3 * np.sin(2 * np.pi * (1.0 + i) * t)
                                  + 300.0 * rng.standard_normal(t.size))
            res.units[name] = "N"
    return res


def _numpy(f: np.ndarray) -> dict[str, float]:
    return {"mean": float(np.mean(f)), "rms_dynamic": float(np.std(f)),
            "peak_dynamic": float(np.max(np.abs(f - np.mean(f)))),
            "max_abs": float(np.max(np.abs(f)))}


def test_suspension_block_equals_numpy(run):
    block = json.loads(analyze(run).to_json())["suspension"]
    assert sorted(block) == [f"secondary.{k}" for k in SPRINGS]
    for k in SPRINGS:
        assert sorted(block[f"secondary.{k}"]) == ["x", "y", "z"]
        for d in "xyz":
            got = block[f"secondary.{k}"][d]
            want = _numpy(run.channels[f"secondary.{k}.force.{d}"])
            assert set(got) == set(want)
            for key, value in want.items():
                assert got[key] == pytest.approx(value, rel=1e-12, abs=1e-9), (k, d, key)


def test_suspension_block_uses_the_evaluated_window(run):
    s = np.asarray(run.distance)
    window = (float(s[0] + 40.0), float(s[0] + 120.0))
    part = window_results(run, window)
    assert part.time.size < run.time.size / 2
    got = analyze(part).to_dict()["suspension"]["secondary.2R"]["z"]
    keep = (s >= window[0] - 1e-9) & (s <= window[1] + 1e-9)
    want = _numpy(run.channels["secondary.2R.force.z"][keep])
    for key, value in want.items():
        assert got[key] == pytest.approx(value, rel=1e-12), key


def test_a_broken_force_channel_is_skipped_with_a_note(run):
    bad = window_results(run, (float(run.distance[0]), float(run.distance[-1])))
    bad.channels["secondary.1L.force.z"] = bad.channels["secondary.1L.force.z"].copy()
    bad.channels["secondary.1L.force.z"][5] = np.nan
    summary = analyze(bad)
    assert "z" not in summary.suspension["secondary.1L"]
    assert "y" in summary.suspension["secondary.1L"]
    assert any("secondary.1L.force.z" in n for n in summary.notes)


def test_runs_without_suspension_channels_have_an_empty_block():
    assert analyze(make_results(duration=6.0)).to_dict()["suspension"] == {}
