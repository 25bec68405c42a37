"""Study tables from summaries: grouping, fits, flexible vs rigid."""

from __future__ import annotations

import pytest

from flexride.study.aggregate import study_tables, summary_value


def _summary(sperling, peak, a_w=0.1):
    d = {"peaks": {"max_abs": peak, "rms": peak / 3},
         "sperling": {"value": sperling} if sperling is not None else None,
         "iso2631": {"Wb": {"a_w": a_w}}}
    return {"points": {"PC": {"directions": {"z": d}}}}


def _job(i, speed, summary, status="succeeded", **axes):
    return {"id": f"j{i}", "speed_kmh": speed, "status": status, "summary": summary,
            "axes": {**axes, "speed_kmh": speed}}


def test_speed_series_per_group_with_fit():
    jobs = [_job(i, v, _summary(1 + v / 100, 2 * v + (1 if c == "b" else 0)), condition=c)
            for i, (c, v) in enumerate((c, v) for c in "ab" for v in (50, 60, 80))]
    jobs.append(_job(9, 70, None, status="running", condition="a"))
    t = study_tables(jobs)
    peaks = {r["group"]["condition"]: r for r in t["peak_vs_speed"]}
    assert peaks["b"]["speed_kmh"] == [50.0, 60.0, 80.0]
    assert peaks["b"]["fit"]["slope"] == pytest.approx(2.0)
    assert peaks["b"]["fit"]["intercept"] == pytest.approx(1.0)
    assert peaks["b"]["fit"]["r_squared"] == pytest.approx(1.0)
    sp = {r["group"]["condition"]: r for r in t["sperling_vs_speed"]}
    assert sp["a"]["value"] == pytest.approx([1.5, 1.6, 1.8]) and sp["a"]["fit"] is None
    assert any("not finished" in n for n in t["notes"])


def test_flexible_vs_rigid_rows():
    jobs = [_job(0, 80, _summary(1.71, 0.5), body_model="rigid", condition="c"),
            _job(1, 80, _summary(1.76, 0.6), body_model="flexible", condition="c"),
            _job(2, 60, _summary(1.5, 0.4), body_model="rigid", condition="c")]
    rows = study_tables(jobs)["flexible_vs_rigid"]
    sp = next(r for r in rows if r["quantity"] == "sperling")
    assert sp["rigid"] == 1.71 and sp["flexible"] == 1.76 and sp["speed_kmh"] == 80
    assert sp["relative"] == pytest.approx(0.05 / 1.71)
    assert {r["quantity"] for r in rows} == {"sperling", "a_w", "rms", "peak"}
    assert all(r["group"] == {"condition": "c", "speed_kmh": 80} for r in rows)


def test_missing_values_and_failed_jobs():
    s = _summary(None, 0.5)
    assert summary_value(s, "PC", "z", "sperling") is None
    assert summary_value(s, "PX", "z", "peak") is None
    assert summary_value({"points": {}}, "PC", "z", "peak") is None
    with pytest.raises(ValueError):
        summary_value(s, "PC", "z", "bogus")
    t = study_tables([_job(0, 50, {"error": "boom"}), _job(1, 60, s, status="failed")])
    assert t["peak_vs_speed"] == [] and "boom" in t["notes"][0]
