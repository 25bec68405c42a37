"""The API does what its OpenAPI document says: the published request examples are accepted as
they are, a known path asked with another method answers 405 with the complete ``Allow``
header, and query values the code refuses are refused by the schema too."""

from __future__ import annotations

import re
from typing import Any

import pytest

from service.svc_testkit import REPO, insert_finished_job, services, synthetic_results

API = "/api/v1"
METHODS = ("GET", "HEAD", "POST", "PUT", "PATCH", "DELETE", "OPTIONS")
#: Routes outside the OpenAPI document, with the methods they answer.
OTHER_ROUTES = {"/docs": {"GET", "HEAD"}, "/redoc": {"GET", "HEAD"},
                f"{API}/openapi.json": {"GET", "HEAD"}, "/static/plotly.min.js": {"GET"}}
#: Paths served by static files (the docs' assets, the dashboard mounted at /).
STATIC_PATHS = ("/static/docs/swagger-ui.css", "/static/docs/redoc.standalone.js",
                "/index.html", "/")


def _examples(spec: dict[str, Any], path: str) -> list[Any]:
    """Every example of the JSON body of ``POST path``: the operation's own and its
    schema's (``example``, ``examples``)."""
    content = spec["paths"][path]["post"]["requestBody"]["content"]["application/json"]
    found = [content["example"]] if "example" in content else []
    found += [e["value"] for e in content.get("examples", {}).values() if "value" in e]
    schema = content["schema"]
    if "$ref" in schema:
        schema = spec["components"]["schemas"][schema["$ref"].rsplit("/", 1)[1]]
    found += ([schema["example"]] if "example" in schema else []) + schema.get("examples", [])
    return found


@pytest.mark.parametrize("path", ["/jobs", "/studies"])
def test_published_examples_are_accepted(make_client, path):
    client = make_client()
    spec = client.get(f"{API}/openapi.json").json()
    examples = _examples(spec, f"{API}{path}")
    assert len(examples) >= 2, examples
    for i, example in enumerate(examples):
        r = client.post(f"{API}{path}", json=example)
        assert r.status_code == 201, (i, example, r.text)


def _template_regex(template: str) -> re.Pattern[str]:
    return re.compile("^" + re.sub(r"\{[^}]+\}", "[^/]+", template) + "$")


def _routes(spec: dict[str, Any]) -> dict[str, tuple[set[str], set[str]]]:
    """Every route's path with its parameters filled in: the methods of its own template, and
    those of every template that matches it (``/jobs/validate`` also matches
    ``/jobs/{job_id}``, whose GET and DELETE therefore answer there, with 404)."""
    templates = {path: {m.upper() for m in ops} for path, ops in spec["paths"].items()}
    templates.update(OTHER_ROUTES)
    routes = {}
    for template, methods in templates.items():
        path = re.sub(r"\{[^}]+\}", "x", template)
        matching = [m for t, m in templates.items() if _template_regex(t).match(path)]
        routes[path] = (methods, set().union(*matching))
    return routes


def _allow(response: Any) -> set[str]:
    return {m.strip() for m in response.headers.get("allow", "").split(",") if m.strip()}


def test_405_names_every_allowed_method(make_client):
    """On every route (with the dashboard mounted at /, as `flexride serve` has it): each
    method that no route has for the path gives 405, JSON, and Allow listing exactly the
    methods the OpenAPI document gives the path."""
    client = make_client(frontend_dir=REPO / "frontend")
    routes = _routes(client.get(f"{API}/openapi.json").json())
    assert routes[f"{API}/jobs"] == ({"GET", "POST"},) * 2
    assert routes[f"{API}/jobs/x"] == ({"GET", "DELETE"},) * 2
    assert routes[f"{API}/jobs/validate"] == ({"POST"}, {"POST", "GET", "DELETE"})
    for path, (allowed, routed) in sorted(routes.items()):
        for method in sorted(set(METHODS) - routed):
            r = client.request(method, path)
            assert r.status_code == 405, (method, path, r.status_code, r.text)
            assert _allow(r) == allowed, (method, path, r.headers.get("allow"))
            if method != "HEAD":
                assert r.json()["detail"] == "Method Not Allowed"
    for path in STATIC_PATHS:
        assert client.get(path).status_code == 200, path
        r = client.post(path)
        assert r.status_code == 405 and _allow(r) == {"GET", "HEAD"}, (path, r.headers)


def test_allowed_methods_still_reach_their_route(make_client):
    client = make_client(frontend_dir=REPO / "frontend")
    assert client.get(f"{API}/presets").status_code == 200
    assert client.delete(f"{API}/jobs/{'0' * 32}").status_code == 404
    assert client.post(f"{API}/jobs/{'0' * 32}/cancel").status_code == 404
    assert client.get(f"{API}/jobs/{'0' * 32}/cancel").status_code == 405


def test_empty_channel_names_are_refused_by_the_schema(make_client):
    client = make_client()
    spec = client.get(f"{API}/openapi.json").json()
    for op in ("series", "spectrum", "psd", "sperling", "correlation"):
        params = spec["paths"][f"{API}/jobs/{{job_id}}/{op}"]["get"]["parameters"]
        (channels,) = [p for p in params if p["name"] == "channels"]
        assert channels["schema"]["items"]["minLength"] == 1, op
    svc = services(client)
    job_id = insert_finished_job(svc.store, svc.files, synthetic_results(duration=6.0))
    for query in ("channels=", "channels=carbody.PR.acc.z&channels="):
        r = client.get(f"{API}/jobs/{job_id}/series?{query}")
        assert r.status_code == 422, r.text
        assert r.json()["detail"][0]["loc"][:2] == ["query", "channels"]
    r = client.get(f"{API}/jobs/{job_id}/series?channels=carbody.PR.acc.z")
    assert r.status_code == 200, r.text
