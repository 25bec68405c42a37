"""What health and the job records tell whom (SQLite and PostgreSQL): without the token only
the state of each component (no path, host name, process id, URL or job); with it the
details an operator needs, still without a password or a server path. Workers are listed as
the job records say: one that stopped reporting is gone, its job what the database says.
"""

from __future__ import annotations

import json
import os
import socket

from sqlalchemy import update
from sqlalchemy.engine import make_url

from flexride.jobs.presence import worker_name
from flexride.store import Job, now
from service.svc_testkit import TEST_TOKEN, insert_finished_job, services

API = "/api/v1"
AUTH = {"Authorization": f"Bearer {TEST_TOKEN}"}
PASSWORD = "pw-Not-Checked-by-trust-7c1f"
"""A password in the database URL (PostgreSQL's trust authentication ignores it)."""


def _with_password(url: str) -> str:
    if not url.startswith("postgresql"):
        return url
    return make_url(url).set(password=PASSWORD).render_as_string(hide_password=False)


def _disclosures(client, db_url: str) -> list[str]:
    """What an anonymous answer must not contain: paths, URLs, host names, process ids."""
    svc = services(client)
    plain = make_url(db_url)
    secrets = [str(svc.settings.data_dir), str(svc.files.root), "/tmp", socket.gethostname(),
               "127.0.0.1", "sqlite", "postgresql", PASSWORD, str(plain.database)]
    if plain.query:
        secrets.append(str(dict(plain.query)))
    return secrets


def _seen_workers(client) -> tuple[str, str, str, str]:
    """A live worker running a job, and a gone one whose last report named a job that has
    since succeeded; returns (live worker, its job, gone worker, the finished job)."""
    svc = services(client)
    store = svc.store
    running = client.post(f"{API}/jobs", headers=AUTH, json={
        "preset": "paper-metro", "overrides": {"duration_s": 0.5, "distance_m": None}}).json()["id"]
    live, gone = worker_name("embedded", os.getpid()), worker_name("celery", 999_999)
    with store.writing() as s, s.begin():
        s.execute(update(Job).where(Job.id == running).values(
            status="running", worker=live, started_at=now(), heartbeat_at=now()))
    finished = insert_finished_job(store, svc.files, worker=gone)
    store.worker_seen(live, "embedded", socket.gethostname(), os.getpid(), running)
    store.worker_seen(gone, "celery", socket.gethostname(), 999_999, finished)
    stale = now() - 20 * svc.settings.heartbeat_interval_s  # stopped reporting
    with store.writing() as s, s.begin():
        from flexride.store import WorkerSeen

        s.execute(update(WorkerSeen).where(WorkerSeen.name == gone).values(last_seen=stale))
    return live, running, gone, finished


def test_anonymous_health_says_states_only(make_client, db_url):
    client = make_client(database_url=_with_password(db_url), api_token=TEST_TOKEN)
    live, running, _, finished = _seen_workers(client)
    r = client.get(f"{API}/health")
    assert r.status_code == 200
    body = r.json()
    assert set(body) == {"status", "view", "components", "solver"}, body
    assert body["view"] == "public" and body["status"] == "ok"
    assert body["components"] == {"api": "ok", "database": "ok", "storage": "ok",
                                  "workers": "ok"}, body
    # nothing else: no number but the solver's estimate (a process id would be one)
    assert set(body["solver"]) == {"state", "estimate_s"}, body
    text = r.text
    for secret in [*_disclosures(client, db_url), live, running, finished]:
        assert secret not in text, (secret, text)
    # a wrong token is no token
    wrong = client.get(f"{API}/health", headers={"Authorization": "Bearer wrong-token-123456"})
    assert wrong.json()["view"] == "public" and set(wrong.json()) == set(body)


def test_operators_see_the_details_without_password_or_path(make_client, db_url):
    client = make_client(database_url=_with_password(db_url), api_token=TEST_TOKEN)
    live, running, gone, _ = _seen_workers(client)
    r = client.get(f"{API}/health", headers=AUTH)
    body = r.json()
    assert body["view"] == "operator" and body["status"] == "ok"
    db = body["database"]["data"]
    assert db["backend"] == make_url(db_url).get_backend_name() and db["latency_ms"] >= 0
    if db["backend"] == "sqlite":
        assert db["location"] == "sqlite:jobs.db"
    else:
        assert db["location"] == "postgresql://127.0.0.1:5432/test"
    assert PASSWORD not in r.text and str(services(client).settings.data_dir) not in r.text
    workers = {w["name"]: w for w in body["workers"]}
    assert workers[live]["state"] == "alive" and workers[live]["alive"]
    assert workers[live]["current_job"] == running  # what the job records say
    assert workers[live]["hostname"] == socket.gethostname()
    # stopped reporting: gone; its last report named a job that has since succeeded
    assert workers[gone]["state"] == "gone" and not workers[gone]["alive"]
    assert workers[gone]["current_job"] is None, workers[gone]
    assert body["jobs"] == {"running": 1, "succeeded": 1}


def test_job_records_name_their_worker_to_operators_only(make_client, db_url):
    client = make_client(database_url=db_url, api_token=TEST_TOKEN)
    live, running, _, _ = _seen_workers(client)
    for headers, shown in (({}, None), (AUTH, live)):
        assert client.get(f"{API}/jobs/{running}", headers=headers).json()["worker"] == shown
        page = client.get(f"{API}/jobs", headers=headers).json()
        assert {j["id"]: j["worker"] for j in page["items"]}[running] == shown
        text = json.dumps(page)
        assert (socket.gethostname() in text) == (headers == AUTH), text
    # without a token every caller is an operator (as for changes)
    open_client = make_client(database_url=db_url)
    assert open_client.get(f"{API}/jobs/{running}").json()["worker"] == live
    assert open_client.get(f"{API}/health").json()["view"] == "operator"


def test_a_queue_without_live_workers_is_degraded_for_everyone(make_client, db_url):
    client = make_client(database_url=db_url, api_token=TEST_TOKEN, runner="none")
    svc = services(client)
    # a runner that runs jobs (not "none") with a queued job and no worker seen
    svc.runner.kind = "embedded"  # type: ignore[misc]
    try:
        client.post(f"{API}/jobs", headers=AUTH, json={
            "preset": "paper-metro", "overrides": {"duration_s": 0.5, "distance_m": None}})
        body = client.get(f"{API}/health").json()
        assert body["status"] == "degraded" and body["components"]["workers"] == "degraded"
    finally:
        svc.runner.kind = "none"  # type: ignore[misc]
