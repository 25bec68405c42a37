"""Model updating: typed targets and measured modes recover known parameters; the default is
calibrated."""

from __future__ import annotations

import numpy as np
import pytest

from flexride.fem.calibration import calibrate_carbody, carbody_frequencies
from flexride.fem.classify import classify_mode
from flexride.fem.defaults import PAPER_TABLE1_HZ, default_carbody_params
from flexride.fem.modal_test import parse_modal_test
from flexride.fem.targets import parse_targets
from flexride.fem.vehicle_models import carbody_params_for, carbody_target


def _modes(params, vehicle, size: float, n: int):
    """Frequencies (Hz), classification and (model, modes) of a car body: the 'truth'."""
    f, model, modes = carbody_frequencies(params, carbody_target(vehicle), size, n)
    _, M = model.assemble()
    names = [classify_mode(modes.shapes[:, 6 + k], M, model.nodes, model.node_region,
                           model.region_names) for k in range(n)]
    return f, names, model, modes


def test_typed_targets_out_of_order_recover_a_known_floor_depth(vehicle):
    """The truth (floor 25 % deeper) has its first vertical bending (as part of mode 1), its
    rhombic mode and its torsion mode (the twelfth); the targets list them in another order,
    and by rank or by nearest frequency the torsion target would meet a roof mode of the
    starting model."""
    base = carbody_params_for(vehicle)
    truth = base.with_values(floor_depth=base.floor_depth * 1.25)
    f, names, _, _ = _modes(truth, vehicle, 0.5, 16)
    i_t, i_r = names.index("torsion"), names.index("rhombic")
    assert "first vertical bending" in names[0] and i_t > 8
    targets = parse_targets(f"{f[i_t]}:torsion,{f[i_r]}:rhombic,{f[0]}:first vertical bending")
    f0, names0, _, _ = _modes(base, vehicle, 0.5, 16)
    nearest = int(np.argmin(np.abs(f0 - f[i_t])))
    assert names0[nearest] != "torsion"  # frequency alone would pair the wrong mode
    res = calibrate_carbody(targets, carbody_target(vehicle), base=base,
                            variables=("floor_depth",), element_size=0.5, regularisation=0.0,
                            max_evaluations=20, tolerance=0.01, n_modes=16)
    assert res.success, res.table()
    assert [p.mode for p in res.pairs] == [i_t, i_r, 0]
    assert res.classification[:2] == ["torsion", "rhombic"]
    assert res.values["floor_depth"] == pytest.approx(truth.floor_depth, rel=0.01)
    assert "torsion" in res.table() and res.to_dict()["pairs"][0]["mode"] == i_t + 1


def test_a_type_beyond_the_computed_modes_is_reported_not_mismatched(vehicle):
    res = calibrate_carbody(parse_targets("6.5:rhombic,11.0:torsion"), carbody_target(vehicle),
                            base=carbody_params_for(vehicle), variables=("floor_depth",),
                            element_size=0.6, max_evaluations=2, n_modes=8)
    rhombic, torsion = res.pairs
    assert rhombic.mode_type == "rhombic" and torsion.mode is None
    assert not res.success and res.frequencies_hz[1] is None
    assert "no mode of type 'torsion' among the 8 computed modes" in res.unpaired[0]
    assert "NOT PAIRED: target 2 (11.000 Hz torsion)" in res.table()


def test_untyped_targets_pair_by_nearest_frequency(vehicle):
    """A small change (floor 5 % deeper) keeps the nearest modes the same ones."""
    target = carbody_target(vehicle)
    base = carbody_params_for(vehicle)
    truth = base.with_values(floor_depth=base.floor_depth * 1.05)
    f_true, _, _ = carbody_frequencies(truth, target, 1.0, 2)
    res = calibrate_carbody(list(f_true[::-1]), target, base=base, variables=("floor_depth",),
                            element_size=1.0, regularisation=0.0, max_evaluations=20,
                            tolerance=0.005)
    assert res.success, res.table()
    assert [p.mode for p in res.pairs] == [1, 0]
    assert res.values["floor_depth"] == pytest.approx(truth.floor_depth, rel=0.02)


#: Sensors of the synthetic modal test: floor, roof and both walls at five stations.
_STATIONS = (-6.3, -3.0, 0.0, 3.0, 6.3)
_SENSORS = [((x, y, z), d) for x in _STATIONS for (y, z, d) in (
    (0.0, 1.1, "z"), (0.95, 1.1, "z"), (1.4, 2.2, "y"), (-1.4, 2.2, "y"), (0.0, 3.8, "z"),
    (0.0, 3.8, "y"))]


def _modal_test_csv(model, modes, freqs, picked: list[int]) -> str:
    """A modal-test file of the modes ``picked`` of a model (shapes at the nodes nearest to
    the sensors, scaled to a largest value of 1)."""
    dofs = [6 * model.nearest_node(np.array(p)) + "xyz".index(d) for p, d in _SENSORS]
    shapes = modes.shapes[np.array(dofs)][:, [6 + k for k in picked]]
    shapes = shapes / np.abs(shapes).max(axis=0)
    head = "x_m,y_m,z_m,direction," + ",".join(f"mode_{freqs[k]:.4f}Hz" for k in picked)
    rows = [f"{p[0]},{p[1]},{p[2]},{d}," + ",".join(f"{v:.5f}" for v in vals)
            for (p, d), vals in zip(_SENSORS, shapes, strict=True)]
    return "\n".join(["# synthetic modal test", head, *rows]) + "\n"


def test_a_synthetic_modal_test_of_a_known_body_is_recovered(vehicle):
    """Measured = the modes 4, 1, 5, 2 (in that order, untyped) of a body with a 20 % deeper
    floor and a 15 % thinner roof, at 30 sensor DOFs; the calibration pairs them by MAC and
    finds both depths."""
    base = carbody_params_for(vehicle)
    truth = base.with_values(floor_depth=base.floor_depth * 1.2,
                             roof_depth=base.roof_depth * 0.85)
    f, _, model, modes = _modes(truth, vehicle, 0.6, 6)
    picked = [3, 0, 4, 1]
    test = parse_modal_test(_modal_test_csv(model, modes, f, picked), source="synthetic")
    res = calibrate_carbody(test.targets, carbody_target(vehicle), base=base,
                            variables=("floor_depth", "roof_depth"), element_size=0.6,
                            regularisation=0.0, max_evaluations=40, tolerance=0.005,
                            sensors=test.sensors)
    assert res.success, res.table()
    assert [p.mode for p in res.pairs] == picked
    assert all(p.mac is not None and p.mac > 0.99 for p in res.pairs)
    assert res.values["floor_depth"] == pytest.approx(truth.floor_depth, rel=0.01)
    assert res.values["roof_depth"] == pytest.approx(truth.roof_depth, rel=0.01)
    assert res.sensors is not None and res.sensors["n_dofs"] == len(_SENSORS)
    assert res.sensors["max_distance_m"] <= 0.6


@pytest.mark.slow
def test_default_carbody_matches_paper_table1(vehicle):
    """The stored calibration: first six elastic modes of the 0.2 m model within ±5 %."""
    f, _, _ = carbody_frequencies(
        carbody_params_for(vehicle, default_carbody_params()), carbody_target(vehicle), 0.2, 6
    )
    err = f / np.asarray(PAPER_TABLE1_HZ) - 1.0
    assert np.all(np.abs(err) < 0.05), (f, err)
