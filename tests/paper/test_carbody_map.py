"""The car-body map in the paper report (flexride.paper.carbody_map): the stored map
(backend/flexride/paper/data/carbody_map.json, made by tools/studies/carbody_map_time_domain.py)
renders, names its producer, pairs every flexible run with the rigid run on the same track, and
holds the physics the map rests on; a missing or malformed map fails with the command that makes
it. No test re-runs the study."""

from __future__ import annotations

import copy
import importlib.util
import json
import math
import sys
from pathlib import Path

import pytest

from flexride.paper import carbody_map as cm

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def stored() -> cm.CarbodyMap:
    return cm.load_map()


def _script():
    path = ROOT / cm.PRODUCER
    spec = importlib.util.spec_from_file_location("carbody_map_time_domain", path)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod  # its dataclasses look their module up
    spec.loader.exec_module(mod)
    return mod


def test_the_stored_map_names_the_script_that_made_it(stored):
    prov = stored.data["provenance"]
    assert prov["script"] == cm.PRODUCER
    assert (ROOT / cm.PRODUCER).is_file()
    assert prov["command"].startswith("python " + cm.PRODUCER)
    cost = prov["cost"]
    assert cost["runs"] == (len(stored.corners) * len(stored.speeds)
                            * len(stored.data["settings"]["seeds"]))
    assert cost["wall_s"] > 0
    assert stored.path.stat().st_size < 200_000  # kept small


def test_the_scripts_corners_include_rigid_default_and_the_beam_at_5_and_15_hz(stored):
    mod = _script()
    corners = {c.key: c for c in mod.CORNERS}
    assert corners["rigid"].kind == "rigid"
    assert corners["default"].kind == "fe"
    beams = {(c.first_bending_hz, c.beam_mass) for c in mod.CORNERS if c.kind == "beam"}
    assert {(5.0, "pitch_inertia"), (15.0, "pitch_inertia")} <= beams
    # the stored map is of the script's current corner set
    assert [c["key"] for c in stored.corners] == [c.key for c in mod.CORNERS]
    assert mod.SCRIPT == cm.PRODUCER


def test_every_flexible_rigid_ratio_comes_from_matched_seeds(stored):
    for v in stored.speeds:
        rigid = stored.time(v, "rigid")
        assert len(set(rigid["seeds"])) == len(rigid["seeds"]) >= 3
        for c in stored.corners:
            body = stored.time(v, c["key"])
            assert body["seeds"] == rigid["seeds"], (v, c["key"])
    rows = cm.evidence(stored)
    for r in rows:
        if r["time"] is None or r["claim"] == "quietest":
            continue
        v = f"{r['speed_kmh']:g}"
        rigid, body = stored.time(v, "rigid"), stored.time(v, r["key"])
        q = next(c.quantity for c in cm.CLAIMS if c.key == r["claim"])
        by_seed = dict(zip(rigid["seeds"], rigid["values"]["PC"][q], strict=True))
        ratios = [x / by_seed[s] for s, x in zip(body["seeds"], body["values"]["PC"][q],
                                                 strict=True)]
        assert r["time"]["seeds"] == rigid["seeds"]
        assert r["time"]["value"] == pytest.approx(sum(ratios) / len(ratios) - 1.0, rel=1e-12)


def test_pairing_by_seed_not_by_position(stored):
    """A body whose seeds are stored in another order is still divided by the rigid run of
    the same seed: the ratio does not change."""
    data = copy.deepcopy(stored.data)
    v = stored.speeds[0]
    body = data["time_domain"][v]["default"]
    order = list(reversed(range(len(body["seeds"]))))
    body["seeds"] = [body["seeds"][i] for i in order]
    for p in body["values"]:
        for q in body["values"][p]:
            body["values"][p][q] = [body["values"][p][q][i] for i in order]
    shuffled = cm.CarbodyMap(data, stored.path)
    a, _ = stored.ratio(v, "default", "PC", "rms")
    b, _ = shuffled.ratio(v, "default", "PC", "rms")
    assert b.mean == pytest.approx(a.mean, rel=1e-12)


def test_a_stiff_beam_is_the_rigid_body_on_every_seed(stored):
    """The beam bending first at 15 Hz with the vehicle's pitch inertia: its nodes sit almost
    under the air springs and 15 Hz is far above the bounce and pitch modes, so PC's Sperling
    index stays within 1 % of the rigid body's on every track (the engine: +0.3 % or less)."""
    for v in stored.speeds:
        rigid = stored.time(v, "rigid")["values"]["PC"]["sperling"]
        beam = stored.time(v, "beam-15")["values"]["PC"]["sperling"]
        for r, b in zip(rigid, beam, strict=True):
            assert abs(b / r - 1.0) < 0.01, (v, r, b)


def test_the_linear_engine_and_the_solver_agree_on_the_rigid_body(stored):
    """The rigid car body on the random straight case is nearly linear: the solver's seed
    mean of PC's vertical rms lies within 15 % of the frequency engine's expectation."""
    for v in stored.speeds:
        t = stored.time(v, "rigid")["values"]["PC"]["rms"]
        e = stored.engine(v, "rigid")["PC"]["rms"]
        assert abs(sum(t) / len(t) / e - 1.0) < 0.15, (v, sum(t) / len(t), e)


def test_the_section_renders_every_input_and_claim_from_the_stored_json(stored):
    page = cm.section_html(stored)
    assert f"id='{cm.ANCHOR}'" in page
    for c in cm.CLAIMS:
        assert c.text.replace("'", "&#x27;") in page
    for c in stored.corners:
        assert c["label"] in page
    # a number of the table, recomputed from the per-seed values
    est, _ = stored.ratio(stored.speeds[0], "default", "PC", "sperling")
    assert f"{100.0 * (est.mean - 1.0):+.1f} ± {100.0 * est.ci95:.1f} % (" in page
    figs = cm.figures(stored)
    panels = figs[0]["panels"]
    assert len(panels) == 3 * len(stored.speeds)
    assert all(f"id='{cm.ANCHOR}-{i}'" in page for i in range(len(panels)))
    json.dumps(figs, allow_nan=False)  # goes into the page's figure data as strict JSON


def test_annotate_adds_the_map_to_the_notes_and_keeps_the_verdicts(stored):
    claims = [{"id": "table2.sperling_z.difference", "verdict": "not reproduced", "note": "n"},
              {"id": "s8.fig24.pc-smallest", "verdict": "not reproduced", "note": "m"},
              {"id": "table1.mode1", "verdict": "reproduced", "note": "x"}]
    out = cm.annotate(claims, stored)
    assert [c["verdict"] for c in out] == [c["verdict"] for c in claims]
    assert out[0]["note"].startswith("n ") and "car-body map" in out[0]["note"]
    assert "car-body map" in out[1]["note"]
    assert out[2] == claims[2]


def test_a_missing_map_fails_with_the_command_that_makes_it(tmp_path):
    with pytest.raises(cm.CarbodyMapError, match="is missing.*python " + cm.PRODUCER):
        cm.load_map(tmp_path / "nothing.json")


@pytest.mark.parametrize("damage", ["not json", "other script", "seed missing", "no rigid",
                                    "old format"])
def test_a_malformed_map_fails_clearly(stored, tmp_path, damage):
    path = tmp_path / "map.json"
    data = copy.deepcopy(stored.data)
    v = stored.speeds[0]
    if damage == "not json":
        path.write_text("{not json")
        with pytest.raises(cm.CarbodyMapError, match="cannot be read as JSON"):
            cm.load_map(path)
        return
    if damage == "other script":
        data["provenance"]["script"] = "tools/studies/elsewhere.py"
        match = "names 'tools/studies/elsewhere.py' as its producer"
    elif damage == "seed missing":
        data["time_domain"][v]["default"]["values"]["PC"]["rms"].pop()
        match = "malformed.*default.*PC rms"
    elif damage == "no rigid":
        data["corners"] = [c for c in data["corners"] if c["key"] != "rigid"]
        match = "malformed.*no rigid corner"
    else:
        data["format"] = 0
        match = "format 0"
    path.write_text(json.dumps(data))
    with pytest.raises(cm.CarbodyMapError, match=match):
        cm.load_map(path)


def test_the_map_rules_follow_the_paper_numbers():
    assert cm.agrees(0.035, 0.035) and cm.agrees(0.0175, 0.035) and cm.agrees(0.07, 0.035)
    assert not cm.agrees(0.071, 0.035) and not cm.agrees(0.017, 0.035)
    assert not cm.agrees(-0.035, 0.035)
    # the report's own rule is looser: a stiff body's +0.3 % passes it
    assert cm.report_rule(0.003, 0.035) and not cm.report_rule(0.09, 0.035)
    assert math.isclose(next(c.paper for c in cm.CLAIMS if c.key == "sperling") or 0, 0.035)
