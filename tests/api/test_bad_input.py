"""Hand-made bad requests (tests/api/bad_requests.py) against the real app on SQLite and on
PostgreSQL, with the API token: no answer is a server error. Job and study ids are read as
UUIDs in every spelling a client may send, and anything else is 422 at the parameter before
any query (a NUL byte made PostgreSQL answer 500); NUL in a request's text is 422 at its field;
control characters never reach the log raw.
"""

from __future__ import annotations

import logging

import pytest

from api.bad_requests import (
    BAD_IDS,
    hostile_requests,
    id_routes,
    id_spellings,
    malformed_bodies,
    nul_bodies,
    query_families,
)
from flexride.api.logs import SafeFormatter
from service.svc_testkit import TEST_TOKEN, insert_finished_job, services

API = "/api/v1"
AUTH = {"Authorization": f"Bearer {TEST_TOKEN}"}


@pytest.fixture
def authed(make_client, db_url):
    """The app on SQLite and PostgreSQL with an API token, and a finished job in its store."""
    client = make_client(database_url=db_url, api_token=TEST_TOKEN)
    svc = services(client)
    return client, insert_finished_job(svc.store, svc.files)


def _no_server_error(client, method, path, headers=None, **kw):
    r = client.request(method, API + path, headers={**AUTH, **(headers or {})}, **kw)
    assert r.status_code < 500, (method, path, r.status_code, r.text[:300])
    return r


def test_ids_in_any_spelling_name_the_same_job(authed):
    client, job_id = authed
    for spelling in id_spellings(job_id):
        r = client.get(f"{API}/jobs/{spelling}", headers=AUTH)
        assert r.status_code == 200 and r.json()["id"] == job_id, (spelling, r.text)
        assert client.get(f"{API}/jobs/{spelling}/summary").status_code == 200, spelling
    study = client.post(f"{API}/studies", headers=AUTH, json={
        "name": "s", "base": {"preset": "paper-metro"}, "speeds_kmh": [60],
        "overrides": {"duration_s": 0.5, "distance_m": None}}).json()["id"]
    for spelling in id_spellings(study):
        assert client.get(f"{API}/studies/{spelling}").json()["id"] == study, spelling
        page = client.get(f"{API}/jobs", params={"study_id": spelling.replace("%7B", "{")
                                                 .replace("%7D", "}")}).json()
        assert page["total"] == 1, spelling


def test_anything_else_is_422_at_the_id_before_any_query(authed):
    client, _ = authed
    routes = id_routes(client.get(f"{API}/openapi.json").json())
    assert len(routes) >= 15, routes  # every job and study route (19 today)
    for method, template, name in routes:
        for bad in BAD_IDS:
            path = template.replace("{" + name + "}", bad)
            r = _no_server_error(client, method, path)
            # 404: "%2F" decodes to "/", and the path is no longer the route's
            assert r.status_code == (404 if "%2F" in bad else 422), (method, path, r.text[:200])
            if r.status_code == 422:
                assert r.json()["detail"][0]["loc"] == ["path", name], (method, path)
    for bad in BAD_IDS:
        r = _no_server_error(client, "GET", f"/jobs?study_id={bad}")
        assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["query", "study_id"]


def test_nul_in_any_request_text_is_422_at_its_field(authed):
    client, _ = authed
    for path, body, loc in nul_bodies():
        r = _no_server_error(client, "POST", path, json=body)
        assert r.status_code == 422, (path, body, r.text[:300])
        assert loc in [item["loc"] for item in r.json()["detail"]], (path, r.json()["detail"])


@pytest.mark.parametrize("family", [query_families, malformed_bodies,
                                    lambda: hostile_requests("not-a-secret")])
def test_no_bad_request_is_a_server_error(authed, family):
    client, _ = authed
    requests = family()
    assert len(requests) > 20
    for method, path, kw in requests:
        _no_server_error(client, method, path, **kw)


def test_control_characters_never_reach_the_log_raw(make_client, caplog):
    client = make_client()
    record = logging.LogRecord("flexride.test", logging.ERROR, __file__, 1,
                               "on GET /jobs/%s", ("\x00\x1b[31m\r\nFAKE 200 OK\x7f\x9b",), None)
    line = SafeFormatter("%(message)s").format(record)
    assert line == "on GET /jobs/\\x00\\x1b[31m\\x0d\\nFAKE 200 OK\\x7f\\x9b", line
    # what the service logs of a request: its path percent-encoded (a storage fault here)
    from starlette.requests import Request

    from flexride.api.logs import request_line

    scope = {"type": "http", "method": "DELETE", "path": "/api/v1/jobs/\x00\x1b\n",
             "root_path": "", "headers": [], "query_string": b""}
    assert request_line(Request(scope)) == "DELETE /api/v1/jobs/%00%1B%0A"
    assert client.get(f"{API}/jobs/%00%1b%0a").status_code == 422
