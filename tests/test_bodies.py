"""ModalBody.with_modes: a body with its rigid coordinates and a subset of its elastic modes."""

from __future__ import annotations

import numpy as np
import pytest

from flexride.bodies import ModalBody


def _body() -> ModalBody:
    """A body with three elastic modes whose shapes at x are (row + 1)·(mode + 1) + x, a named
    shape (PC) and one marker."""
    n = 3

    def shape_at(position: np.ndarray) -> np.ndarray:
        return np.arange(1, 7)[:, None] * (np.arange(n)[None, :] + 1.0) + position[0]

    body = ModalBody(name="carbody", mass=1000.0, inertia=np.array([1.0, 2.0, 3.0]), x_ref=0.0,
                     cg_height=1.5, elastic_frequencies=np.array([5.0, 7.0, 9.0]),
                     elastic_damping=np.array([0.01, 0.02, 0.03]),
                     elastic_shapes={"PC": shape_at(np.zeros(3)) * 10.0}, shape_at=shape_at)
    body.add_marker("m", (2.0, 0.5, -0.6))
    return body


def test_with_modes_keeps_the_rigid_coordinates_and_the_chosen_modes_in_order():
    body = _body()
    sub = body.with_modes([2, 0])
    assert sub.n_elastic == 2 and sub.n_dof == 8
    assert sub.elastic_frequencies.tolist() == [9.0, 5.0]
    assert sub.elastic_damping.tolist() == [0.03, 0.01]
    assert sub.mass == body.mass and sub.inertia.tolist() == body.inertia.tolist()
    np.testing.assert_array_equal(sub.elastic_shapes["PC"], body.elastic_shapes["PC"][:, [2, 0]])
    np.testing.assert_array_equal(sub.markers["m"][:, :6], body.markers["m"][:, :6])
    np.testing.assert_array_equal(sub.markers["m"][:, 6:], body.markers["m"][:, [8, 6]])
    p = np.array([1.0, 0.0, 0.0])
    assert sub.shape_at is not None and body.shape_at is not None
    np.testing.assert_array_equal(sub.shape_at(p), body.shape_at(p)[:, [2, 0]])
    assert sub.modal_stiffness()[6:] == pytest.approx((2 * np.pi * np.array([9.0, 5.0])) ** 2)


def test_with_modes_copies_and_checks_the_indices():
    body = _body()
    sub = body.with_modes([1])
    sub.elastic_shapes["PC"][:] = 0.0
    sub.add_marker("n", (0.0, 0.0, 0.0))
    assert body.elastic_shapes["PC"].any() and "n" not in body.markers
    assert body.with_modes([]).n_elastic == 0
    with pytest.raises(ValueError, match="out of range"):
        body.with_modes([3])
