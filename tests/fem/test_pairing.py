"""Pairing of model modes with targets: by type, by MAC, by frequency; optimal, not greedy."""

from __future__ import annotations

import numpy as np
import pytest

from flexride.errors import FEModelError
from flexride.fem.pairing import ModelModes, pair_targets
from flexride.fem.targets import ModeTarget, parse_targets

#: A model whose frequency order differs from the order of the targets' types below.
MODES = ModelModes(
    frequencies_hz=np.array([5.0, 6.1, 6.4, 7.4, 8.1, 9.0]),
    types=["roof–floor breathing", "floor local", "rhombic", "roof local",
           "floor local + first vertical bending", "torsion"],
)


def _modes(pairs) -> list[int | None]:
    return [p.mode for p in pairs]


def test_typed_targets_pair_by_type_not_by_order_or_frequency():
    pairs = pair_targets(parse_targets("5.03:torsion,6.11:rhombic,8.84:roof-floor breathing"),
                         MODES)
    assert _modes(pairs) == [5, 2, 0]
    assert [p.mode_type for p in pairs] == ["torsion", "rhombic", "roof–floor breathing"]
    assert pairs[0].error == pytest.approx(9.0 / 5.03 - 1.0)
    assert all(p.mac is None and p.message == "" for p in pairs)


def test_untyped_targets_take_the_nearest_free_modes():
    assert _modes(pair_targets(parse_targets("9.1,6.2"), MODES)) == [5, 1]


def test_the_assignment_is_optimal_not_greedy():
    # greedy in the targets' order would give 5.6 the 6.0 Hz mode and leave 6.5 with 5.0 Hz
    two = ModelModes(np.array([5.0, 6.0]), ["floor local", "floor local"])
    assert _modes(pair_targets(parse_targets("5.6,6.5"), two)) == [0, 1]
    # an untyped target does not take the only mode a typed one can have
    pair = ModelModes(np.array([6.0, 6.5]), ["rhombic", "roof local"])
    assert _modes(pair_targets(parse_targets("6.05,6.4:rhombic"), pair)) == [1, 0]


def test_a_secondary_type_counts_less_than_a_dominant_one():
    modes = ModelModes(np.array([8.1, 9.5]),
                       ["floor local + first vertical bending", "first vertical bending"])
    assert _modes(pair_targets(parse_targets("8.2:first vertical bending"), modes)) == [1]
    only = ModelModes(np.array([8.1]), ["floor local + first vertical bending"])
    assert _modes(pair_targets(parse_targets("8.2:first vertical bending"), only)) == [0]


def test_a_type_the_model_does_not_have_is_reported_not_mismatched():
    (p,) = pair_targets(parse_targets("6.0:lateral bending"), MODES)
    assert p.mode is None and p.frequency_hz is None and p.error is None
    assert "no mode of type 'lateral bending' among the 6 computed modes (5.00–9.00 Hz)" in (
        p.message)
    a, b = pair_targets(parse_targets("6.35:rhombic,6.6:rhombic"), MODES)
    assert a.mode == 2 and b.mode is None
    assert "(mode 3 at 6.40 Hz) are paired with other targets" in b.message


def _shapes(n_dof: int, n_modes: int) -> np.ndarray:
    q, _ = np.linalg.qr(np.random.default_rng(5).standard_normal((n_dof, n_modes)))
    return q


def test_shapes_pair_by_mac_whatever_the_frequency():
    shapes = _shapes(10, 6)
    modes = ModelModes(MODES.frequencies_hz, MODES.types, shapes)
    noisy = -2.0 * shapes[:, 3] + 0.05 * shapes[:, 0]
    (p,) = pair_targets([ModeTarget(5.0, shape=noisy)], modes)
    assert p.mode == 3 and p.mac == pytest.approx(1.0, abs=0.01)


def test_a_shape_like_no_mode_is_reported():
    shapes = _shapes(10, 7)
    modes = ModelModes(MODES.frequencies_hz, MODES.types, shapes[:, :6])
    (p,) = pair_targets([ModeTarget(5.0, shape=shapes[:, 6])], modes)  # orthogonal to all
    assert p.mode is None and "has MAC ≥ 0.5 with the target's shape" in p.message
    (q,) = pair_targets([ModeTarget(5.0, "torsion", shape=shapes[:, 1])], modes)
    assert q.mode is None and "no mode of type 'torsion'" in q.message  # MAC says mode 2


def test_shapes_need_sensor_shapes_of_their_length():
    with pytest.raises(FEModelError, match="no sensors"):
        pair_targets([ModeTarget(5.0, shape=np.ones(3))], MODES)
    modes = ModelModes(MODES.frequencies_hz, MODES.types, _shapes(10, 6))
    with pytest.raises(FEModelError, match="3 values but there are 10 sensor DOFs"):
        pair_targets([ModeTarget(5.0, shape=np.ones(3))], modes)
