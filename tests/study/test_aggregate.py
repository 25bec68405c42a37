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


def _t_ci(values):
    """Hand computation of the 95 % CI half width: t_{0.975, n-1} · s / √n."""
    import math

    from scipy import stats

    n = len(values)
    mean = sum(values) / n
    s = math.sqrt(sum((v - mean) ** 2 for v in values) / (n - 1))
    return mean, stats.t.ppf(0.975, n - 1) * s / math.sqrt(n)


def test_seeds_mean_and_confidence_interval_against_student_t():
    sp80 = [1.70, 1.82, 1.76]  # three realisations at 80 km/h
    pk80 = [0.50, 0.61, 0.47]
    jobs = [_job(k, 80, _summary(sp80[k - 1], pk80[k - 1]), seed=k, condition="c")
            for k in (1, 2, 3)]
    jobs += [_job(10 + k, 60, _summary(1.5, 0.4), seed=k, condition="c") for k in (1, 2)]
    t = study_tables(jobs)
    (sp,) = t["sperling_vs_speed"]
    assert sp["speed_kmh"] == [60.0, 80.0] and sp["n"] == [2, 3]
    mean, half = _t_ci(sp80)
    assert sp["value"][1] == pytest.approx(mean) and sp["ci95"][1] == pytest.approx(half)
    assert half == pytest.approx(4.303 * 0.06 / 3 ** 0.5, rel=1e-3)  # t(0.975, 2) = 4.303
    assert sp["ci95"][0] == pytest.approx(0.0)  # two equal values
    assert sp["jobs"][1] == ["j1", "j2", "j3"] and sp["job_ids"] == ["j11", "j1"]
    assert sp["job_values"]["j2"] == 1.82
    (pk,) = t["peak_vs_speed"]
    m60, m80 = 0.4, sum(pk80) / 3
    assert pk["fit"]["slope"] == pytest.approx((m80 - m60) / 20)  # the line through the means


def test_seeds_flexible_vs_rigid_paired_by_realisation():
    rigid, flex = [1.0, 2.0, 4.0], [1.1, 2.4, 4.4]
    jobs = [_job(k, 80, _summary(rigid[k - 1], 1.0), body_model="rigid", seed=k)
            for k in (1, 2, 3)]
    jobs += [_job(10 + k, 80, _summary(flex[k - 1], 1.0), body_model="flexible", seed=k)
             for k in (1, 2, 3)]
    rows = study_tables(jobs)["flexible_vs_rigid"]
    sp = next(r for r in rows if r["quantity"] == "sperling")
    assert sp["group"] == {"speed_kmh": 80} and sp["n"] == 3
    rel = [f / r - 1 for r, f in zip(rigid, flex, strict=True)]  # 0.1, 0.2, 0.1
    assert sp["relative"] == pytest.approx(_t_ci(rel)[0])
    assert sp["relative_ci95"] == pytest.approx(_t_ci(rel)[1])
    assert sp["rigid_ci95"] == pytest.approx(_t_ci(rigid)[1])
    assert sp["difference"] == pytest.approx(_t_ci([0.1, 0.4, 0.4])[0])
    assert sp["rigid_job"] == "j1" and sp["flexible_job"] == "j11"
