"""Every 422 of a request names its field in ``loc`` (the ones that said ``loc: []``)."""

from __future__ import annotations

import pytest

API = "/api/v1"


@pytest.mark.parametrize(("endpoint", "body", "loc"), [
    ("/jobs", {"preset": "nope"}, ["preset"]),
    ("/jobs/validate", {"scenario": {"preset": "nope"}}, ["preset"]),
    ("/jobs", {"preset": "paper-metro", "overrides": {"excitation.9.seed": 3}},
     ["overrides", "excitation.9.seed"]),
    ("/jobs", {"preset": "paper-metro", "overrides": {"excitation.x.seed": 3}},
     ["overrides", "excitation.x.seed"]),
    ("/jobs", {"preset": "paper-metro", "overrides": {"excitation": [
        {"kind": "measured", "columns": ["distance_m", "vertical"],
         "rows": [[0, 0], [1, 0], [0.5, 0]]}]}}, ["excitation", 0, "rows"]),
    ("/studies", {"name": "s", "base": {"preset": "paper-metro",
                                        "overrides": {"excitation.4.seed": 1}},
                  "speeds_kmh": [60]}, ["base", "overrides", "excitation.4.seed"]),
])
def test_422_names_the_field(sqlite_client, endpoint, body, loc):
    r = sqlite_client.post(API + endpoint, json=body)
    assert r.status_code == 422, r.text
    assert r.json()["detail"][0]["loc"] == loc, r.text
