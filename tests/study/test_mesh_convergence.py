"""Quantities against element size (flexride.study.mesh_convergence): the estimates against
exact power laws, the grouping of a study's jobs, the paper's Fig. 4 claim judged."""

from __future__ import annotations

import math

import pytest

from flexride.errors import ScenarioError
from flexride.study.aggregate import study_tables
from flexride.study.expand import expand_study
from flexride.study.mesh_convergence import mesh_convergence_tables, size_estimate, study_request
from flexride.study.mesh_verdict import REFERENCE_SIZE_M, format_table

AXIS = "bodies.carbody.element_size_m"
SIZES = [0.1, 0.15, 0.2, 0.3, 0.4]


def test_three_finest_meshes_recover_a_second_order_law_exactly():
    # v(h) = 10 + 40 h^2: order 2, extrapolated 10, each mesh 4 h^2 above it
    est = size_estimate(SIZES[::-1], [10 + 40 * h**2 for h in SIZES[::-1]])
    assert est["sizes_m"] == [0.1, 0.15, 0.2]
    assert est["order"] == pytest.approx(2.0, rel=1e-8)
    assert est["extrapolated"] == pytest.approx(10.0, rel=1e-10)
    assert not est["oscillatory"] and not est["order_assumed"] and est["reliable"]
    assert est["converged"] == pytest.approx(10.0, rel=1e-10)
    assert est["band"] == est["gci_fine"]
    for h, dev in est["deviation"]:
        assert dev == pytest.approx(4 * h**2, rel=1e-8)
    # Celik's GCI of the finest mesh: 1.25 |e21/phi1| / (r^p - 1)
    phi1, phi2 = 10 + 40 * 0.01, 10 + 40 * 0.0225
    assert est["gci_fine"] == pytest.approx(1.25 * (phi2 - phi1) / phi1 / (1.5**2 - 1))


def test_two_meshes_assume_the_elements_order_and_missing_values_are_left_out():
    est = size_estimate([0.2, 0.1, 0.3], [10 + 40 * 0.04, 10 + 40 * 0.01, None])
    assert est["order_assumed"] and est["order"] == 2.0
    assert est["extrapolated"] == pytest.approx(10.0)
    assert size_estimate([0.2, 0.1], [None, 3.0]) is None


def test_oscillating_or_barely_converging_meshes_fall_back_to_the_finest_and_the_spread():
    osc = size_estimate([0.1, 0.15, 0.2], [10.0, 10.2, 10.1])
    assert osc["oscillatory"] and not osc["reliable"]
    assert osc["converged"] == 10.0 and osc["band"] == pytest.approx(0.02)
    # differences shrinking by a factor 0.98 per refinement of 1.5: order 0.05
    slow = size_estimate([0.1, 0.15, 0.225], [10.0, 10.0 + 1.0, 10.0 + 1.0 + 1.0 / 0.98])
    assert slow["order"] < 0.5 and not slow["reliable"] and slow["converged"] == 10.0


def _job(size: float, condition: str, seed: int, force: float, freq: float,
         sperling: float) -> dict:
    point = {"directions": {"z": {"sperling": {"value": sperling},
                                  "peaks": {"rms": 0.1, "max_abs": 0.3}}}}
    suspension = {e: {"z": {"mean": 1e3, "rms_dynamic": force, "peak_dynamic": 3 * force,
                            "max_abs": 5 * force}}
                  for e in ("secondary.1L", "secondary.2R")}
    return {"id": f"{condition}-{size}-{seed}", "status": "succeeded", "speed_kmh": 80.0,
            "axes": {"condition": condition, "speed_kmh": 80.0, AXIS: size, "seed": seed},
            "summary": {"points": {"PC": point}, "suspension": suspension},
            "run_meta": {"flexible_bodies": {"carbody": {
                "element_size_m": size, "elastic_frequencies_hz": [freq, 2 * freq, 3 * freq]}}}}


def _study(force_law, freq_law) -> list[dict]:
    jobs = []
    for h in SIZES:
        for seed, spread in ((1, -1.0), (2, 1.0)):  # realisations average to the law
            jobs.append(_job(h, "random", seed, force_law(h) + spread, freq_law(h),
                             1.5 + h**2 + 0.01 * spread))
        jobs.append(_job(h, "smooth", 1, force_law(h) / 10, freq_law(h), 1.0))
    return jobs


def test_tables_group_by_condition_average_realisations_and_judge_the_claim():
    force = lambda h: 200.0 + 1000.0 * h**2  # noqa: E731 - grows with the element
    freq = lambda h: 5.0 - 2.0 * h**2  # noqa: E731
    tables = study_tables(_study(force, freq))["mesh_convergence"]
    assert [t["group"]["condition"] for t in tables] == ["random", "smooth"]
    random = tables[0]
    assert random["sizes_m"] == SIZES and random["realisations"] == [2] * 5
    rows = {r["key"]: r for r in random["rows"]}
    rms = rows["secondary.1L.z.rms_dynamic"]
    assert rms["values"] == pytest.approx([force(h) for h in SIZES])
    assert rms["estimate"]["extrapolated"] == pytest.approx(200.0)
    assert rms["at_reference"] == pytest.approx(1000.0 * REFERENCE_SIZE_M**2 / 200.0)
    f1 = rows["frequency.1"]
    assert f1["estimate"]["extrapolated"] == pytest.approx(5.0)
    assert rows["frequency.3"]["values"][0] == pytest.approx(3 * freq(0.1))
    assert rows["PC.z.sperling"]["estimate"]["extrapolated"] == pytest.approx(1.5)
    claim = random["claim"]
    # 2 air springs x (rms, peak, largest), z only in the summaries
    assert claim["grows"] == [6, 6] and claim["grows_holds"]
    assert claim["coarsest_over_reference"] == pytest.approx(force(0.4) / force(0.2))
    assert claim["reference_within"]["force"] == pytest.approx(0.2)
    assert claim["adequate"] is False  # 20 % from the converged force
    assert "grows with the element size in 6 of 6 judged rows" in claim["text"]
    text = format_table(random)
    assert "air spring 1L z: rms of the dynamic part" in text and "verdict:" in text


def test_a_force_that_falls_with_the_element_does_not_grow():
    tables = mesh_convergence_tables(_study(lambda h: 500.0 - 300.0 * h, lambda h: 5.0))
    assert tables[0]["claim"]["grows"] == [0, 6] and tables[0]["claim"]["grows_holds"] is False
    # constant frequencies: no order, the finest value stands, no deviation
    f1 = next(r for r in tables[0]["rows"] if r["key"] == "frequency.1")
    assert f1["estimate"]["extrapolated"] == pytest.approx(5.0)
    assert f1["at_reference"] == pytest.approx(0.0)


def test_a_group_with_one_size_and_jobs_without_the_axis_give_no_table():
    jobs = [_job(0.2, "random", 1, 100.0, 5.0, 1.5)]
    jobs.append({**_job(0.3, "random", 1, 100.0, 5.0, 1.5), "axes": {"condition": "random"}})
    assert mesh_convergence_tables(jobs) == []


def test_the_preset_expands_to_sizes_times_conditions_and_rejects_unknown_bodies():
    plan = expand_study(study_request("carbody", [0.5, 0.4, 0.3], ["smooth-straight"]), 50)
    assert [j.axes[AXIS] for j in plan.jobs] == [0.5, 0.4, 0.3]
    assert all(not j.scenario.excitation for j in plan.jobs)
    assert all(j.scenario.bodies.carbody.model == "flexible" for j in plan.jobs)
    frames = expand_study(study_request("frames", [0.2, 0.1], ["random-straight"], 50.0), 50)
    assert [j.scenario.bodies.frames.element_size_m for j in frames.jobs] == [0.2, 0.1]
    assert {j.scenario.speed_kmh for j in frames.jobs} == {50.0}
    with pytest.raises(ScenarioError, match="carbody, frames"):
        study_request("bogie", [0.2, 0.1])
    assert math.isclose(REFERENCE_SIZE_M, 0.2)


def test_forces_and_accelerations_below_the_resolution_are_not_judged():
    """A smooth track: static loads of 10 kN with a dynamic part of 0.1 N (noise, 1e-5) and
    accelerations of micro-g are reported, not judged; the frequencies still are."""
    jobs = _study(lambda h: 0.01 + 0.1 * h, lambda h: 5.0 + h)
    for j in jobs:
        for e in j["summary"]["suspension"].values():
            e["z"]["max_abs"] = 1e4
        pc = j["summary"]["points"]["PC"]["directions"]["z"]
        pc["peaks"]["rms"], pc["sperling"]["value"] = 1e-5, 0.05
    table = mesh_convergence_tables(jobs)[0]
    rows = {r["key"]: r for r in table["rows"]}
    assert rows["secondary.1L.z.rms_dynamic"]["negligible"].startswith("below 0.001 of")
    assert rows["secondary.1L.z.max_abs"]["negligible"] is None
    assert rows["PC.z.rms"]["negligible"] and rows["PC.z.sperling"]["negligible"]
    assert rows["frequency.1"]["negligible"] is None
    claim = table["claim"]
    assert claim["grows"] == [0, 2] and not claim["grows_holds"]  # 10 kN at every mesh
    assert "rows below the resolution, not judged" in claim["text"]


def test_growth_needs_meshes_coarser_than_the_reference():
    fine = [j for j in _study(lambda h: 200.0 + 1000.0 * h**2, lambda h: 5.0)
            if j["axes"][AXIS] <= 0.2]
    claim = mesh_convergence_tables(fine)[0]["claim"]
    assert claim["grows"] == [0, 0] and claim["grows_holds"] is None
    assert "no mesh coarser than 0.2 m: growth not judged" in claim["text"]
