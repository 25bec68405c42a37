"""A study run in this process (flexride.study.local_run) on three coarse car-body meshes: the
air springs carry the car body's weight on every mesh, each run's first elastic frequency is the
FE model's own at that size, and the mesh table follows them; the CLI prints the table."""

from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

from flexride.scenario.presets import load_preset
from flexride.study.aggregate import study_tables
from flexride.study.expand import expand_study
from flexride.study.local_run import run_plan
from flexride.study.mesh_convergence import study_request

SIZES = [0.7, 0.6, 0.5]
G = 9.81


@pytest.fixture(scope="module")
def smooth_jobs():
    request = study_request("carbody", SIZES, ["smooth-straight"])
    request["overrides"] = {"distance_m": 45.0, "bodies.carbody.cutoff_hz": 20.0,
                            "bodies.frames.model": "rigid"}
    plan = expand_study(request, max_jobs=10)
    seen = []
    jobs = run_plan(plan, lambda i, n, f, m: seen.append((i, n, f)))
    assert {i for i, _, f in seen if f == 1.0} == {0, 1, 2}
    return jobs


def test_every_mesh_carries_the_car_body_on_its_air_springs(smooth_jobs):
    vehicle = load_preset("paper-metro").vehicle
    weight = vehicle.carbody.mass * G
    for job in smooth_jobs:
        forces = job["summary"]["suspension"]
        springs = [e for e in forces if e.startswith("secondary.")]
        assert len(springs) == 4
        total = sum(forces[e]["z"]["mean"] for e in springs)
        assert total == pytest.approx(weight, rel=5e-3), job["name"]


def test_each_runs_first_frequency_is_its_fe_models(smooth_jobs):
    from flexride.fem.mesh_study import mesh_modes

    vehicle = load_preset("paper-metro").vehicle
    for job, size in zip(smooth_jobs, SIZES, strict=True):
        body = job["run_meta"]["flexible_bodies"]["carbody"]
        assert body["element_size_m"] == size
        fe = mesh_modes("carbody", vehicle, size, 1)
        assert body["elastic_frequencies_hz"][0] == pytest.approx(fe.frequencies_hz[0],
                                                                  rel=1e-6)


def test_the_mesh_table_follows_the_runs(smooth_jobs):
    (table,) = study_tables(smooth_jobs)["mesh_convergence"]
    assert table["sizes_m"] == sorted(SIZES) and table["group"]["condition"] == "smooth-straight"
    f1 = next(r for r in table["rows"] if r["key"] == "frequency.1")
    assert f1["values"] == [j["run_meta"]["flexible_bodies"]["carbody"][
        "elastic_frequencies_hz"][0] for j in sorted(smooth_jobs, key=lambda j: j["axes"][
            "bodies.carbody.element_size_m"])]
    assert f1["estimate"] is not None and table["claim"]["reference_within"]["all"] is None


def test_the_cli_prints_the_tables_of_the_runs(monkeypatch, smooth_jobs):
    import flexride.study.local_run as local_run
    from flexride.cli import app

    planned = []

    def fake_run_plan(plan, progress=None):  # the runs above, not again
        planned.append(plan)
        return smooth_jobs

    monkeypatch.setattr(local_run, "run_plan", fake_run_plan)
    runner = CliRunner()
    res = runner.invoke(app, ["fe", "convergence", "carbody", "--response", "--sizes",
                              "0.7,0.6,0.5", "--conditions", "smooth-straight"])
    assert res.exit_code == 0, res.output
    assert "air spring 1L z: rms of the dynamic part" in res.output and "verdict:" in res.output
    assert [j.axes["bodies.carbody.element_size_m"] for j in planned[0].jobs] == SIZES
    res = runner.invoke(app, ["fe", "convergence", "carbody", "--response", "--json",
                              "--sizes", "0.7,0.6,0.5", "--conditions", "smooth-straight"])
    assert res.exit_code == 0
    data = json.loads(res.stdout)
    assert data["mesh_convergence"][0]["sizes_m"] == sorted(SIZES)
    bad = runner.invoke(app, ["fe", "convergence", "carbody", "--response", "--conditions",
                              "tunnel"])
    assert bad.exit_code == 2 and "unknown condition 'tunnel'" in bad.output
