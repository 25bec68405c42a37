"""The study's runs: conditions × speeds × models × seeds, windows, cut-offs, options."""

from __future__ import annotations

import pytest

from flexride.paper.plan import ReportError, ReportOptions, build_plan, full_window


def test_full_study_is_table3_times_two_models():
    plan = build_plan(ReportOptions(seeds=1, mesh_sizes=()).checked())
    assert len(plan) == 32
    assert {s.condition for s in plan} == {"random-straight", "random-curve", "corrugation",
                                           "settlement"}
    assert {s.speed_kmh for s in plan} == {50.0, 60.0, 70.0, 80.0}
    assert all(s.distance_m in (400.0, 410.0, 200.0, 120.0) for s in plan)


def test_the_full_report_runs_five_realisations_of_the_random_conditions_the_quick_one():
    """Issue 14: the full report gives every random condition's index as a mean with its CI
    over at least five realisations; --quick is a first look with one."""
    full = build_plan(ReportOptions(mesh_sizes=()).checked())
    random = {"random-straight", "random-curve"}
    assert {s.seed for s in full if s.condition in random} == {1, 2, 3, 4, 5}
    assert len(full) == 16 + 16 * 5  # defects once, random conditions five times
    quick = build_plan(ReportOptions(quick=True, mesh_sizes=()).checked())
    assert {s.seed for s in quick if s.condition in random} == {1} and len(quick) == 16


def test_rigid_and_flexible_share_the_track_and_seeds_multiply_random_conditions():
    plan = build_plan(ReportOptions(quick=True, seeds=3, mesh_sizes=()).checked())
    random = [s for s in plan if s.condition.startswith("random")]
    assert len(random) == 2 * 2 * 3 * 2 and len(plan) - len(random) == 2 * 2 * 2
    for s in random:
        twin = [t for t in random if (t.condition, t.speed_kmh, t.seed) ==
                (s.condition, s.speed_kmh, s.seed) and t.body != s.body]
        assert len(twin) == 1
        rigid, flex = sorted([s, twin[0]], key=lambda x: x.body != "rigid")
        a, b = rigid.scenario(), flex.scenario()
        assert a.excitation == b.excitation and a.distance_m == b.distance_m
        assert a.bodies.carbody.model == "rigid" and b.bodies.frames.model == "flexible"


def test_curve_is_evaluated_with_every_wheelset_on_the_arc():
    start, end, _ = full_window("random-curve")
    assert start == pytest.approx(40.0 + 55.0 + 7.4) and end == pytest.approx(295.0 - 7.4)


def test_quick_runs_keep_a_sperling_segment_and_the_settlement_dip():
    for s in build_plan(ReportOptions(quick=True).checked()):
        length_s = (s.window_m[1] - s.window_m[0]) / (s.speed_kmh / 3.6)
        assert length_s >= 5.0 or s.distance_m == 120.0, s.label
        if s.condition == "settlement":
            assert s.window_m[1] >= 40.0 + 20.0 + 7.4 + 20.0 - 1e-9


def test_flexible_cutoff_follows_the_excitation():
    cut = {s.condition: s.cutoff_hz for s in build_plan(ReportOptions(mesh_sizes=()).checked())
           if s.body == "flexible"}
    assert cut == {"random-straight": 40.0, "random-curve": 40.0, "corrugation": 70.0,
                   "settlement": 40.0}


@pytest.mark.parametrize(("options", "words"), [
    (ReportOptions(seeds=0), "--seeds"), (ReportOptions(jobs=0), "--jobs"),
    (ReportOptions(distance_scale=1.5), "--distance-scale"),
    (ReportOptions(speeds=(50.0, 250.0)), "speeds"),
    (ReportOptions(conditions=("tunnel",)), "tunnel")])
def test_impossible_options_are_refused(options, words):
    with pytest.raises(ReportError, match=words):
        options.checked()


def test_the_element_size_precalculation_runs_the_flexible_vehicle_at_each_size():
    """Fig. 4: smooth and random straight track at 80 km/h, the car body at each size (the
    full report: the study preset's sizes; quick: the three finest that cost no more than
    0.2 m), the same modes on both tracks, records of their own even at 0.2 m."""
    from flexride.study.presets import MESH_SIZES_M

    full = build_plan(ReportOptions(seeds=1).checked())
    mesh = [s for s in full if s.element_size_m is not None]
    assert len(full) == 32 + len(mesh) and len(mesh) == 2 * len(MESH_SIZES_M)
    assert {(s.condition, s.speed_kmh, s.body) for s in mesh} == {
        ("smooth-straight", 80.0, "flexible"), ("random-straight", 80.0, "flexible")}
    table3_frames = next(s for s in full if s.body == "flexible").scenario().bodies.frames
    for s in mesh:
        scen = s.scenario()
        assert scen.bodies.carbody.element_size_m == s.element_size_m
        assert scen.bodies.frames == table3_frames  # the frames keep their mesh
        assert s.cutoff_hz == 40.0
        assert bool(scen.excitation) == (s.condition == "random-straight")
    table3 = next(s for s in full if s.label == "random-straight 80 km/h flexible seed 1")
    twin = next(s for s in mesh if s.condition == "random-straight" and s.element_size_m == 0.2)
    assert twin.scenario() == table3.scenario() and twin.key() != table3.key()
    quick = build_plan(ReportOptions(quick=True).checked())
    assert sorted({s.element_size_m for s in quick} - {None}) == [0.2, 0.3, 0.4]
    with pytest.raises(ReportError, match="mesh sizes"):
        ReportOptions(mesh_sizes=(0.2,)).checked()
