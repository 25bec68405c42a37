"""HDF5 results file: round trip, attributes, atomic write."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from flexride.errors import ResultsFileError
from flexride.results import Results


def _results():
    t = np.arange(100) / 1000.0
    return Results(time=t, distance=t * 20, channels={"carbody.PC.acc.z": np.sin(t)},
                   units={"carbody.PC.acc.z": "m/s^2"}, scenario={"name": "x"},
                   meta={"output_rate": 1000.0})


def test_round_trip(tmp_path):
    r = _results()
    p = r.write_hdf5(tmp_path / "sub" / "r.h5")
    back = Results.read_hdf5(p)
    assert np.array_equal(back.channels["carbody.PC.acc.z"], r.channels["carbody.PC.acc.z"])
    assert back.units["carbody.PC.acc.z"] == "m/s^2"
    assert back.scenario == {"name": "x"} and back.sample_rate == 1000.0
    with h5py.File(p) as f:
        assert f["time"].attrs["unit"] == "s"


def test_failed_write_leaves_nothing(tmp_path, monkeypatch):
    r = _results()
    r.channels["bad"] = object()  # not storable
    with pytest.raises(TypeError):
        r.write_hdf5(tmp_path / "r.h5")
    assert list(tmp_path.iterdir()) == []


def test_not_a_results_file(tmp_path):
    p = tmp_path / "x.h5"
    with h5py.File(p, "w") as f:
        f["a"] = 1
    with pytest.raises(ResultsFileError, match="not a flexride results file"):
        Results.read_hdf5(p)
    with pytest.raises(ResultsFileError, match="not found"):
        Results.read_hdf5(tmp_path / "missing.h5")


def test_points_are_written_with_the_file_and_read_back(tmp_path):
    from flexride.scenario.presets import load_preset

    r = _results()
    r.scenario = load_preset("paper-metro", {"output.floor_grid_spacing_m": 3.0}).model_dump(
        mode="json")
    p = r.write_hdf5(tmp_path / "r.h5")
    with h5py.File(p) as f:
        assert f.attrs["format_version"] == 3
        assert f["points/position"].attrs["unit"] == "m"
        assert f["points/position"].shape == (len(r.recorded_points), 3)
    back = Results.read_hdf5(p)
    assert back.points == r.recorded_points
    pr = next(q for q in back.points if q["name"] == "PR")
    assert (pr["body"], pr["x"], pr["y"], pr["z"]) == ("carbody", 6.3, 0.0, 3.8)
    # a file without a vehicle (no scenario) has an empty list, not an error
    assert Results.read_hdf5(_results().write_hdf5(tmp_path / "s.h5")).points == []


def test_recorded_points_are_where_the_solver_puts_its_markers():
    """The rule that results files store is the one build_vehicle follows: every recorded
    point, in channel order, at its marker (CG position + marker offset)."""
    from flexride.scenario.presets import load_preset
    from flexride.vehicle.topology import build_vehicle, recorded_points

    sc = load_preset("paper-metro", {"output.floor_grid_spacing_m": 1.5, "output.points": [
        {"name": "SEAT", "x": -4.2, "y": 0.8, "z": 1.6}]})
    veh = build_vehicle(sc.vehicle, sc.output)
    pts = recorded_points(sc.vehicle, sc.output)
    assert [(p.body, p.name) for p in pts] == [(veh.bodies[b].name, n) for n, b, _ in veh.points]
    for p, (_, b, marker) in zip(pts, veh.points, strict=True):
        body = veh.bodies[b]
        off = body.marker_positions[marker]
        assert (p.x, p.y, p.z) == pytest.approx(
            (body.x_ref + off[0], off[1], body.cg_height + off[2]), abs=1e-12)


def test_recorded_points_say_what_they_are_and_whether_they_are_on_the_floor(tmp_path):
    from flexride.scenario.presets import load_preset
    from flexride.vehicle.topology import PAPER_POINTS, recorded_points

    sc = load_preset("paper-metro", {"output.floor_grid_spacing_m": 3.0, "output.points": [
        {"name": "SEAT", "x": -4.2, "y": 0.8, "z": 1.6},
        {"name": "FLOOR1", "x": 2.0, "y": 0.0, "z": 1.12}]})
    pts = {p.name if p.body == "carbody" else p.body: p
           for p in recorded_points(sc.vehicle, sc.output)}
    for paper in PAPER_POINTS:
        assert pts[paper.name].description.startswith(f"{paper.name}: ")
        assert pts[paper.name].on_floor is (paper.level == "floor")
    assert "PB" in pts["PFB"].description  # the paper's name of the point
    assert pts["SEAT"].on_floor is False and "user point" in pts["SEAT"].description
    assert pts["FLOOR1"].on_floor is True  # within 5 cm of the floor height
    assert pts["F0_0"].on_floor is True and "grid" in pts["F0_0"].description
    assert pts["frame1"].on_floor is None and pts["wheelset4"].on_floor is None


def test_files_of_format_2_get_descriptions_from_their_scenario(tmp_path):
    from flexride.scenario.presets import load_preset

    r = _results()
    r.scenario = load_preset("paper-metro").model_dump(mode="json")
    p = r.write_hdf5(tmp_path / "old.h5")
    with h5py.File(p, "r+") as f:  # as written before format 3
        del f["points/description"], f["points/on_floor"]
        f.attrs["format_version"] = 2
    back = Results.read_hdf5(p)
    pc = next(q for q in back.points if q["name"] == "PC")
    assert pc["on_floor"] is True and pc["description"].startswith("PC: ")


def test_points_know_their_kind():
    from flexride.scenario.presets import load_preset
    from flexride.vehicle.topology import recorded_points

    sc = load_preset("paper-metro", {"output.floor_grid_spacing_m": 3.0, "output.points": [
        {"name": "SEAT", "x": -4.2, "y": 0.8, "z": 1.6}]})
    kinds = [p.kind for p in recorded_points(sc.vehicle, sc.output)]
    n_grid = kinds.count("grid")
    assert kinds == ["paper"] * 6 + ["user"] + ["grid"] * n_grid + ["body"] * 6 and n_grid == 7
