"""Mode classification on shapes constructed from their definitions (car-body geometry)."""

from __future__ import annotations

import numpy as np
import pytest

from flexride.fem.carbody import CarBodyParams, build_carbody
from flexride.fem.classify import classify_mode, section_shear_share

P = CarBodyParams()


@pytest.fixture(scope="module")
def body():
    """The bare car-body structure at 1 m elements (geometry and regions only)."""
    return build_carbody(P, None, 1.0)


def _section_offsets(nodes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(Δy, Δz) of every node from the centroid of its cross-section (nodes sharing x)."""
    dy, dz = np.empty(len(nodes)), np.empty(len(nodes))
    for x in np.unique(nodes[:, 0]):
        s = nodes[:, 0] == x
        dy[s] = nodes[s, 1] - nodes[s, 1].mean()
        dz[s] = nodes[s, 2] - nodes[s, 2].mean()
    return dy, dz


def _shape(model, uy: np.ndarray, uz: np.ndarray, ux: np.ndarray | None = None) -> np.ndarray:
    u = np.zeros((model.nodes.shape[0], 6))
    u[:, 1], u[:, 2] = uy, uz
    if ux is not None:
        u[:, 0] = ux
    return u.ravel()


def _name(model, phi: np.ndarray) -> str:
    _, M = model.assemble()
    return classify_mode(phi, M, model.nodes, model.node_region, model.region_names)


def test_in_plane_shear_of_the_sections_is_rhombic(body):
    """Pure shear of each section, u_y = γ Δz, u_z = γ Δy (the rectangle becomes a rhombus:
    one diagonal lengthens, the other shortens), varying along the body."""
    dy, dz = _section_offsets(body.nodes)
    gamma = np.cos(np.pi * body.nodes[:, 0] / P.length)
    phi = _shape(body, gamma * dz, gamma * dy)
    assert _name(body, phi) == "rhombic"
    u = phi.reshape(-1, 6)[:, :3]
    assert section_shear_share(u, body.nodes) == pytest.approx(1.0, abs=1e-9)


def test_twist_differs_from_shear_by_one_sign_and_is_torsion(body):
    """Rigid twist of each section, u_y = −θ Δz, u_z = θ Δy, antisymmetric along x."""
    dy, dz = _section_offsets(body.nodes)
    theta = body.nodes[:, 0] / P.length
    phi = _shape(body, -theta * dz, theta * dy)
    assert _name(body, phi) == "torsion"
    assert section_shear_share(phi.reshape(-1, 6)[:, :3], body.nodes) < 1e-12


def test_side_walls_moving_apart_are_breathing_not_rhombic(body):
    nodes = body.nodes
    walls = [body.region_names.index(r) for r in ("wall_left", "wall_right")]
    on_wall = np.isin(body.node_region, walls)
    bulge = np.sin(np.pi * (nodes[:, 2] - P.floor_height) / (P.eave_height - P.floor_height))
    uy = np.where(on_wall, np.sign(nodes[:, 1]) * bulge, 0.0)
    phi = _shape(body, uy, 0.0 * uy)
    assert _name(body, phi) == "breathing (side walls)"
    assert section_shear_share(phi.reshape(-1, 6)[:, :3], body.nodes) < 0.1


def test_rigid_sections_moving_vertically_in_one_wave_are_first_vertical_bending(body):
    w = np.cos(2 * np.pi * body.nodes[:, 0] / P.length)
    assert _name(body, _shape(body, 0.0 * w, w)) == "first vertical bending"


def test_every_name_of_the_car_bodys_modes_is_in_the_vocabulary(vehicle):
    """The classifier and the targets' parser share the names; the car body's own rhombic
    mode is shear-dominated (not merely named so)."""
    from flexride.fem.calibration import carbody_frequencies
    from flexride.fem.mode_types import name_types
    from flexride.fem.vehicle_models import carbody_params_for, carbody_target

    _, model, modes = carbody_frequencies(carbody_params_for(vehicle), carbody_target(vehicle),
                                          0.6, 20)
    names = [_name(model, modes.shapes[:, 6 + k]) for k in range(20)]
    assert all(name_types(n) for n in names), names
    phi = modes.shapes[:, 6 + names.index("rhombic")]
    assert section_shear_share(phi.reshape(-1, 6)[:, :3], model.nodes) > 0.8
