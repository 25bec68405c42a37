"""Natural frequencies against element size (fem/mesh_study.py): modes are followed by their
classification before their order, the three finest meshes give the estimate, and the command
prints it (the estimate itself is tested against closed forms in test_convergence.py)."""

from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

from flexride.cli.fe import fe_app
from flexride.errors import FEModelError
from flexride.fem.mesh_study import MeshModes, _follow, frequency_convergence
from flexride.scenario.presets import load_preset


def _mesh(size: float, freqs, types) -> MeshModes:
    return MeshModes(size, 100, tuple(freqs), tuple(types), 0.0)


def test_a_mode_is_followed_by_its_type_when_the_order_swaps():
    """Torsion lies below bending on the fine meshes and above it on the coarse one: each is
    followed to its own kind; its values give the three-mesh estimate."""
    meshes = [_mesh(0.4, [5.30, 5.45], ["vertical bending", "torsion"]),
              _mesh(0.2, [5.10, 5.20], ["torsion", "vertical bending"]),
              _mesh(0.1, [5.02, 5.15], ["torsion", "vertical bending"])]
    torsion, bending = _follow(meshes)
    assert torsion.type == "torsion" and torsion.frequencies_hz == (5.45, 5.10, 5.02)
    assert bending.frequencies_hz == (5.30, 5.20, 5.15)
    assert not any(torsion.renamed + bending.renamed)
    assert torsion.estimate is not None and torsion.estimate.values == (5.02, 5.10, 5.45)


def test_a_mode_without_its_kind_elsewhere_takes_the_nearest_renamed():
    meshes = [_mesh(0.4, [6.0], ["floor local"]), _mesh(0.2, [5.9], ["roof local"]),
              _mesh(0.1, [5.8], ["roof local"])]
    (mode,) = _follow(meshes)
    assert mode.frequencies_hz == (6.0, 5.9, 5.8) and mode.renamed == (True, False, False)


def test_the_study_needs_three_sizes_the_builder_admits():
    vehicle = load_preset("paper-metro").vehicle
    with pytest.raises(FEModelError, match="three distinct"):
        frequency_convergence("frame", vehicle, [0.1, 0.1, 0.05])
    with pytest.raises(FEModelError, match=r"0\.01–0\.5"):
        frequency_convergence("frame", vehicle, [0.9, 0.1, 0.05])


def test_the_command_follows_the_frames_modes(cache_dir):
    runner = CliRunner()
    res = runner.invoke(fe_app, ["convergence", "frame", "--sizes", "0.2,0.1,0.05",
                                 "--n-modes", "4", "--json"])
    assert res.exit_code == 0, res.output
    data = json.loads(res.stdout)
    assert data["element_sizes_m"] == [0.2, 0.1, 0.05]
    assert [m["element_size_m"] for m in data["meshes"]] == [0.2, 0.1, 0.05]
    finest = data["meshes"][-1]["frequencies_hz"]
    assert [m["frequencies_hz"][-1] for m in data["modes"]] == finest[:4]
    assert all(m["estimate"] is not None for m in data["modes"])
    res = runner.invoke(fe_app, ["convergence", "frame", "--sizes", "0.2,0.1"])
    assert res.exit_code == 2 and "three distinct" in res.output
    res = runner.invoke(fe_app, ["convergence", "frame", "--sizes", "0.2,x,0.1"])
    assert res.exit_code == 2 and "--sizes must be numbers" in res.output


def test_a_builds_own_estimate_is_the_two_mesh_band_against_its_companion():
    """The frame's 0.1 m beams against a 0.15 m companion: each mode's companion frequency is
    that mesh's own (followed), and its GCI Roache's two-mesh band at order 2."""
    from flexride.fem.mesh_study import build_estimate, mesh_modes

    vehicle = load_preset("paper-metro").vehicle
    est = build_estimate("frame", vehicle, 0.1, 4)
    assert est["companion_element_size_m"] == pytest.approx(0.15)
    companion = mesh_modes("frame", vehicle, 0.15, 8)
    fine = mesh_modes("frame", vehicle, 0.1, 4)
    for mode, f in zip(est["modes"], fine.frequencies_hz, strict=True):
        assert mode["frequency_hz"] == f and mode["companion_hz"] in companion.frequencies_hz
        band = 3.0 * abs(mode["companion_hz"] / f - 1) / (1.5**2 - 1)
        assert mode["gci"] == pytest.approx(band, rel=1e-12)
