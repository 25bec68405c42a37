"""Presets, schemas, health, version and static files."""

from __future__ import annotations

API = "/api/v1"


def test_presets_and_schemas(sqlite_client):
    c = sqlite_client
    names = [p["name"] for p in c.get(f"{API}/presets").json()]
    assert "paper-metro" in names and "paper-settlement-60" in names and len(names) >= 18
    full = c.get(f"{API}/presets/paper-corrugation-70").json()
    dt = full["solver"]["dt"]  # defaults filled in
    assert full["speed_kmh"] == 70.0 and (dt == "auto" or dt > 0)
    assert c.get(f"{API}/presets/nope").status_code == 404
    schema = c.get(f"{API}/schemas/scenario").json()
    assert "speed_kmh" in schema["properties"]
    assert "speeds_kmh" in c.get(f"{API}/schemas/study").json()["properties"]
    openapi = c.get(f"{API}/openapi.json").json()
    assert "/api/v1/jobs/{job_id}/series" in openapi["paths"]
    assert c.get("/docs").status_code == 200


def test_health_and_version(client):
    h = client.get(f"{API}/health")
    assert h.status_code == 200
    body = h.json()
    assert body["status"] == "ok" and body["database"]["ok"]
    assert body["runner"] == "none" and body["broker"] is None
    assert body["database"]["data"]["latency_ms"] >= 0
    solver = body["solver"]  # the dashboard's contract: state and an estimate while compiling
    assert solver["state"] in ("ready", "compiling")
    assert (solver["estimate_s"] is None) == (solver["state"] == "ready")
    v = client.get(f"{API}/version").json()
    assert v["api"] == "v1" and "numba" in v["libraries"]


def test_static_files_and_frontend_hook(make_client, tmp_path):
    c = make_client()
    js = c.get("/static/plotly.min.js")
    assert js.status_code == 200 and "javascript" in js.headers["content-type"]
    assert len(js.content) > 100_000
    r = c.get("/", follow_redirects=False)
    assert r.status_code in (302, 307) and r.headers["location"] == "/docs"
    front = tmp_path / "frontend"
    front.mkdir()
    (front / "index.html").write_text("<h1>flexride dashboard</h1>")
    c2 = make_client(frontend_dir=front)
    assert "dashboard" in c2.get("/").text
    assert c2.get(f"{API}/presets").status_code == 200  # the API still wins
    assert c2.get("/static/plotly.min.js").status_code == 200


def test_the_paper_points_and_where_they_sit(sqlite_client):
    pts = sqlite_client.get("/api/v1/schemas/points").json()
    assert [p["name"] for p in pts] == ["PR", "PFB", "PC", "PRB", "PLA", "PRA"]
    by = {p["name"]: p for p in pts}
    assert (by["PR"]["along"], by["PR"]["level"]) == ("front", "roof")
    assert (by["PLA"]["along"], by["PLA"]["across"], by["PLA"]["level"]) == (
        "rear", "left", "floor")
    assert all(p["description"] for p in pts)
