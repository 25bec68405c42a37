"""analyze(): every measure per output point from a Results, JSON and rich output."""

from __future__ import annotations

import io
import json

import numpy as np
import pytest
from rich.console import Console
from rich.table import Table

from flexride.analysis import (
    Summary,
    analyze,
    regress_summaries,
    safety_table,
    sperling_spectral,
    split_quasistatic,
    summary_table,
)
from flexride.errors import AnalysisError
from flexride.results import Results


@pytest.fixture(scope="module")
def summary(run) -> Summary:
    return analyze(run)


def test_points_and_measures(summary, run):
    assert list(summary.points) == ["PR", "PFB", "PC", "PRB", "PLA", "PRA"]
    assert summary.points["PR"].on_floor is False and summary.points["PC"].on_floor is True
    ds = summary.points["PC"].directions["z"]
    assert ds.channel == "carbody.PC.acc.z" and not ds.errors
    assert ds.sperling.form == "spectral" and ds.sperling_alternative.form == "filter"
    assert set(ds.iso2631) == {"Wb", "Wk"}
    assert set(summary.points["PC"].directions["y"].iso2631) == {"Wd"}
    assert ds.continuous_comfort.weighting == "Wb"
    assert summary.points["PC"].mean_comfort.short_run  # 30 s run
    # the Sperling index is taken from the dynamic part
    x = run.channels["carbody.PC.acc.z"]
    expected = sperling_spectral(split_quasistatic(x, run.sample_rate).dynamic,
                                 run.sample_rate, "z").value
    assert ds.sperling.value == pytest.approx(expected, rel=1e-12)
    # 6 Hz sine in z is the dominant spectral peak
    assert ds.dominant_peaks[0].frequency == pytest.approx(6.0, abs=0.13)
    assert ds.peaks.max_abs == pytest.approx(np.max(np.abs(x)))
    assert summary.value("PC", "z", "sperling") == pytest.approx(ds.sperling.value)
    assert summary.value("PC", "z", "n_mv") == summary.points["PC"].mean_comfort.value
    assert summary.other_channels["frame1.centre.acc.z"].n == x.size


def test_correlations_follow_the_paper_convention(summary):
    """Reference PRB (rear, lags the front points by 0.5 s): R(PRB, PR) peaks at −0.5 s."""
    corr = {(c.other, c.direction): c.result for c in summary.correlations}
    assert all(c.reference == "PRB" for c in summary.correlations)
    assert corr[("PR", "z")].lag_at_max == pytest.approx(-0.5, abs=0.005)
    assert corr[("PLA", "z")].lag_at_max == pytest.approx(0.0, abs=0.005)
    assert corr[("PC", "z")].lag_at_max == pytest.approx(-1.0 / 6.0, abs=0.005)
    assert ("PC", "y") in corr
    assert corr[("PLA", "z")].normalised_at_max == pytest.approx(1.0, abs=1e-6)
    assert len(corr[("PR", "z")].local_maxima) <= 5


def test_safety_in_summary(summary):
    assert summary.safety is not None and summary.safety.passed
    assert len(summary.safety.indices) == 10


def test_json_and_tables(summary):
    d = summary.to_dict()
    text = json.dumps(d, allow_nan=False)
    assert json.loads(text)["points"]["PC"]["directions"]["z"]["sperling"]["form"] == "spectral"
    assert d["settings"]["sperling"]["default_form"] == "spectral"
    assert d["settings"]["en12299"]["edition"] == "EN 12299:2009"
    assert "lags" not in d["correlations"][0]["result"]  # large arrays stay out of the JSON
    assert len(text) < 200_000
    table = summary_table(summary)
    assert isinstance(table, Table) and table.row_count == 12
    assert summary_table(d).row_count == 12  # the JSON dictionary works too
    assert safety_table(d).row_count == 10
    with pytest.raises(AnalysisError, match="Summary"):
        summary_table({"something": 1})
    st = safety_table(summary)
    assert isinstance(st, Table) and st.row_count == 10
    console = Console(width=160, record=True, file=io.StringIO())
    console.print(table)
    out = console.export_text()
    assert "PRB" in out and "excellent" in out


def test_arrays_for_the_dashboard(run):
    s = analyze(run, arrays=True, sperling_form="filter")
    ds = s.points["PR"].directions["z"]
    assert ds.sperling.form == "filter" and ds.sperling_alternative.form == "spectral"
    assert ds.psd is not None and ds.psd.frequencies[-1] <= 100.0
    assert ds.spectrogram is not None and ds.spectrogram.values.shape[0] == \
        ds.spectrogram.frequencies.size
    assert s.correlations[0].curve is not None
    assert s.safety.indices[0].series is not None
    json.dumps(s.to_dict(), allow_nan=False)


def test_regression_over_speeds(results_factory):
    runs = [analyze(results_factory(duration=12.0, speed_kmh=v, wheelsets=1))
            for v in (50.0, 60.0, 70.0, 80.0)]
    fit = regress_summaries(runs, "PR", "z", "peak")
    assert fit.r_squared == pytest.approx(1.0, abs=1e-9)  # peaks scale with the speed
    assert fit.slope > 0 and fit.x_unit == "km/h"


def test_short_run_and_bad_channels(results_factory):
    res = results_factory(duration=2.0, wheelsets=1)
    res.channels["carbody.PC.acc.z"] = res.channels["carbody.PC.acc.z"].copy()
    res.channels["carbody.PC.acc.z"][10] = np.nan
    s = analyze(res)
    assert any("carbody.PC.acc.z" in n and "NaN" in n for n in s.notes)
    assert "z" not in s.points["PC"].directions
    pr = s.points["PR"].directions["z"]
    assert pr.sperling is None and "too short" in pr.errors["sperling"]
    assert pr.peaks.n == 1000
    json.dumps(s.to_dict(), allow_nan=False)


def test_no_carbody_channel():
    t = np.arange(100) / 100.0
    res = Results(time=t, distance=t, channels={"frame1.centre.acc.z": t}, units={},
                  meta={"output_rate": 100.0})
    with pytest.raises(AnalysisError, match="no car-body"):
        analyze(res)


def test_hdf5_round_trip(tmp_path, results_factory):
    res = results_factory(duration=6.0, wheelsets=1)
    back = Results.read_hdf5(res.write_hdf5(tmp_path / "run.h5"))
    s = analyze(back)
    assert s.run["sample_rate_hz"] == 500.0 and s.run["speed_kmh"] == pytest.approx(80.0)
    assert s.points["PRB"].directions["y"].sperling is not None
