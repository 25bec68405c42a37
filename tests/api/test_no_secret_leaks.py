"""A real ``flexride serve`` with secrets in its environment: no answer to any request, well
formed or hostile, contains them (the measured-irregularity path that read
``/proc/self/environ`` is the regression this guards)."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import httpx
import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
from live_server import start_server  # noqa: E402

from api.bad_requests import hostile_requests  # noqa: E402

TOKEN = "leak-probe-TOKEN-7f3a9c1e5b2d"
OTHER = "leak-probe-ENV-0d9e8f7a6b5c"
API = "/api/v1"


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    data = tmp_path_factory.mktemp("leak")
    srv = start_server(data / "data", workers=1, cache_dir=data / "cache",
                       log=data / "serve.log",
                       env={"FLEXRIDE_API_TOKEN": TOKEN, "LEAK_PROBE_SECRET": OTHER,
                            "FLEXRIDE_ALLOWED_HOSTS": "127.0.0.1"})
    yield srv
    srv.stop()


def _get_endpoints(client: httpx.Client) -> list[str]:
    spec = client.get(f"{API}/openapi.json").json()
    out = []
    for path, ops in spec["paths"].items():
        if "get" in ops:
            out.append(path.replace("{job_id}", "0" * 32).replace("{study_id}", "0" * 32)
                       .replace("{kind}", "carbody").replace("{name}", "paper-metro")
                       .replace("{upload_id}", "0" * 64))
    return out


def test_no_answer_contains_a_secret(server):
    sent = 0
    auth = {"Authorization": f"Bearer {TOKEN}"}
    with httpx.Client(base_url=server.url, timeout=60) as client:
        requests = [(m, API + p, kw) for m, p, kw in hostile_requests(TOKEN)]
        requests += [("GET", p, {}) for p in _get_endpoints(client)]
        for method, path, kw in requests:
            for headers in ({}, auth):
                r = client.request(method, path, headers=headers, **kw)
                sent += 1
                assert r.status_code < 500, (method, path, r.status_code, r.text[:300])
                text = r.text + json.dumps(dict(r.headers))
                assert TOKEN not in text and OTHER not in text, (method, path)
                assert "root:x:0" not in text, (method, path)
    assert sent > 150


def test_paths_are_refused_with_the_field_and_validate_needs_the_token(server):
    body = {"preset": "paper-metro",
            "overrides": {"excitation": [{"kind": "measured", "path": "/proc/self/environ"}]}}
    with httpx.Client(base_url=server.url, timeout=60) as client:
        assert client.post(f"{API}/jobs/validate", json=body).status_code == 401
        r = client.post(f"{API}/jobs/validate", json=body,
                        headers={"Authorization": f"Bearer {TOKEN}"})
    assert r.status_code == 422
    assert r.json()["detail"][0]["loc"] == ["excitation", 0, "path"]
    assert "/proc" not in r.text
