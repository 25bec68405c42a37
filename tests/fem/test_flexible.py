"""build_flexible_body: the solver-facing entry point, its cache and its exports."""

from __future__ import annotations

import json

import numpy as np
import pytest

from flexride.bodies import ModalBody
from flexride.errors import FEModelError
from flexride.fem.damping import RayleighDamping
from flexride.fem.flexible import build_flexible_body


@pytest.fixture(scope="module")
def module_cache(tmp_path_factory):
    path = tmp_path_factory.mktemp("fem-cache")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("FLEXRIDE_CACHE_DIR", str(path))
        yield path


@pytest.fixture(scope="module")
def carbody(vehicle, module_cache):
    return build_flexible_body(
        "carbody",
        vehicle,
        method="modal",
        cutoff_hz=15.0,
        element_size=0.5,
        extra_points={"SEAT1": (3.0, 1.0, 1.6)},
    )


def test_carbody_modal_body(carbody, vehicle):
    b = carbody.body
    assert isinstance(b, ModalBody)
    assert b.name == "carbody" and b.x_ref == 0.0
    assert b.mass == pytest.approx(vehicle.carbody.mass, rel=0.01)
    np.testing.assert_allclose(
        b.inertia, [vehicle.carbody.ixx, vehicle.carbody.iyy, vehicle.carbody.izz], rtol=0.01
    )
    assert b.cg_height == pytest.approx(vehicle.carbody.cg_height, abs=0.01)
    assert b.n_elastic > 6 and np.all(np.diff(b.elastic_frequencies) >= 0)
    assert b.elastic_frequencies[0] > 2.0 and b.elastic_frequencies[-1] <= 15.0
    assert np.all(b.elastic_damping == 0.02)
    for name in ("as1L", "as1R", "as2L", "as2R", "bogie1", "bogie2", "PR", "PC", "SEAT1"):
        assert b.elastic_shapes[name].shape == (6, b.n_elastic)


def test_shape_at_and_markers(carbody, vehicle):
    b = carbody.body
    g = vehicle.geometry
    rel = np.array(
        [
            g.bogie_centre_spacing / 2,
            g.secondary_lateral_half_spacing,
            g.secondary_height - b.cg_height,
        ]
    )
    np.testing.assert_allclose(carbody.shape_at(rel), b.elastic_shapes["as1L"])
    b.add_marker("as1L_solver", rel, elastic=carbody.shape_at(rel))
    assert b.markers["as1L_solver"].shape == (6, b.n_dof)
    names, pos = carbody.floor_grid_nodes()
    assert len(names) == pos.shape[0] == 95
    assert np.allclose(pos[:, 2], 1.10 - b.cg_height, atol=1e-6)


def test_cache_hit_is_fast_and_identical(carbody, vehicle, module_cache):
    again = build_flexible_body(
        "carbody",
        vehicle,
        method="modal",
        cutoff_hz=15.0,
        element_size=0.5,
        extra_points={"SEAT1": (3.0, 1.0, 1.6)},
        name="cb2",
        x_ref=1.0,
        damping_ratio=0.05,
    )
    assert again.from_cache and not carbody.from_cache
    assert again.build_seconds < 0.5
    np.testing.assert_array_equal(again.body.elastic_frequencies, carbody.body.elastic_frequencies)
    np.testing.assert_array_equal(again.modes.shapes, carbody.modes.shapes)
    assert again.body.name == "cb2" and again.body.x_ref == 1.0
    assert np.all(again.body.elastic_damping == 0.05)
    assert list(module_cache.glob("fem-*/*.npz"))


def test_rayleigh_damping_option(vehicle, module_cache):
    ray = RayleighDamping(5.0, 10.0, 0.02, 0.03)
    fb = build_flexible_body(
        "frame", vehicle, cutoff_hz=80.0, damping_ratio=ray, name="frame1", x_ref=6.3
    )
    np.testing.assert_allclose(fb.body.elastic_damping, ray.ratios(fb.body.elastic_frequencies))
    assert fb.body.cg_height == pytest.approx(0.65, abs=1e-3)
    assert fb.body.elastic_shapes["ab1L"].shape == (6, fb.body.n_elastic)


def test_mesh_export_is_json(carbody):
    d = carbody.export(max_modes=3)
    text = json.dumps(d)
    assert len(d["modes"]) == 3 and len(d["nodes"]) == carbody.modes.nodes.shape[0]
    assert len(d["modes"][0]["displacements"]) == len(d["nodes"])
    assert max(abs(v) for row in d["modes"][0]["displacements"] for v in row) == pytest.approx(1.0)
    assert "floor" in d["regions"]["names"] and len(text) > 1000


def test_report_of_the_body(carbody):
    r = carbody.report
    assert r.method == "modal" and r.reduced_frequencies == r.full_frequencies
    assert all(abs(e) < 1e-12 for e in r.frequency_errors())
    assert abs(r.mass["errors"]["iyy"]) < 0.01
    assert "modal reduction" in r.table()
    assert r.classification[0]


@pytest.mark.parametrize(
    "kwargs",
    [{"kind": "bogie"}, {"method": "ritz"}, {"cutoff_hz": -1.0}, {"element_size": 5.0}],
)
def test_bad_arguments(vehicle, module_cache, kwargs):
    args = {"kind": "frame", "method": "modal", "cutoff_hz": 50.0, "element_size": 0.2} | kwargs
    kind = args.pop("kind")
    if kind == "frame" and "element_size" in kwargs:
        kind = "carbody"
    with pytest.raises(FEModelError):
        build_flexible_body(kind, vehicle, **args)


def test_scenario_rayleigh_damping_reaches_the_solver(module_cache):
    """`bodies.frames.damping_model: rayleigh` gives each frame mode ζ = α/(2ω) + βω/2 with
    ζ = damping_ratio at the first two elastic modes; the assembled system carries c = 2ζω."""
    from flexride.scenario.presets import load_preset
    from flexride.solver.assemble import assemble

    sc = load_preset("paper-metro", {"duration_s": 0.1, "bodies.frames.model": "flexible",
                                     "bodies.frames.element_size_m": 0.5,
                                     "bodies.frames.cutoff_hz": 150.0,
                                     "bodies.frames.damping_ratio": 0.03,
                                     "bodies.frames.damping_model": "rayleigh"})
    asm = assemble(sc)
    frame = asm.vehicle.bodies[1]
    f = frame.elastic_frequencies
    assert f.size >= 3
    expect = RayleighDamping(f[0], f[1], 0.03, 0.03).ratios(f)
    np.testing.assert_allclose(frame.elastic_damping, expect, rtol=1e-12)
    assert frame.elastic_damping[-1] > 0.03  # grows above the second mode
    o, nd = asm.sys.body_off[1], asm.sys.body_ndof[1]
    w = 2 * np.pi * f
    np.testing.assert_allclose(asm.sys.cdiag[o + 6:o + nd], 2 * expect * w, rtol=1e-9)
