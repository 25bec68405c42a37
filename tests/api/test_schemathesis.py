"""Property-based runs over the OpenAPI schema (schemathesis): generated requests, valid and
invalid, against the real app in-process on SQLite and on PostgreSQL (about 1,400 each, the
same requests) and against a live ``flexride serve`` with an API token (at least 500, over
HTTP, the token sent with each); none may produce a server error, and every response must
match the documented status codes, content types and schemas (405 with the complete ``Allow``
header for methods a path does not have).

Jobs are recorded, not run (``runner=none``): generated scenarios are checked at submission
(the stability check included) but no simulation starts. FE exports come from a stand-in build
in-process (tests/api/test_fe_api.py runs a real one) and are left out of the live run, where a
request with the token would start real builds (minutes of CPU each).
"""

from __future__ import annotations

import atexit
import contextlib
import shutil
import sys
import tempfile
from collections import Counter
from pathlib import Path
from typing import Any

import httpx
import pytest
import schemathesis
from hypothesis import HealthCheck, given, settings
from hypothesis.errors import Unsatisfiable
from schemathesis import GenerationMode
from schemathesis.checks import not_a_server_error
from schemathesis.specs.openapi.checks import (
    allow_header_conformance,
    content_type_conformance,
    response_schema_conformance,
    status_code_conformance,
    unsupported_method,
)

from flexride.api import create_app
from flexride.store import JobStore, ResultFiles
from service.svc_testkit import (
    REPO,
    TEST_TOKEN,
    insert_finished_job,
    make_settings,
    pg_schema,
    synthetic_results,
    use_fe_builds,
)

sys.path.insert(0, str(REPO / "tools"))
from live_server import start_server

SENT: dict[str, list[int]] = {"sqlite": [], "postgresql": []}
AUTH = {"Authorization": f"Bearer {TEST_TOKEN}"}
LIVE_SENT: list[int] = []
LIVE_SKIPPED: list[str] = []
LIVE_SECRET = "live-env-secret-5c1d9e7a"
"""A secret in the live server's environment that no answer may contain."""
LIVE_EXAMPLES = 15
"""Examples per operation and mode (valid, invalid data) in the live run."""


def _counter(db: str):
    def count(ctx, response, case):
        """Counts the generated requests (and their status codes)."""
        SENT[db].append(response.status_code)

    count.__name__ = f"count_{db}"
    return count


def _count_live(ctx, response, case):
    """Counts the requests of the live run (and their status codes); a request that carried
    the token must not get 401 (invalid cases may leave the token out: those must)."""
    LIVE_SENT.append(response.status_code)
    answer = response.text + " ".join(f"{k}: {v}" for k, v in response.headers.items())
    assert TEST_TOKEN not in answer and LIVE_SECRET not in answer, (case.method, case.path)
    sent = response.request.headers.get("authorization")
    assert (response.status_code == 401) == (sent != AUTH["Authorization"] and case.method in (
        "POST", "DELETE")), (response.status_code, case.method, case.path, sent)


CHECKS = [not_a_server_error, status_code_conformance, content_type_conformance,
          response_schema_conformance, unsupported_method, allow_header_conformance]

EXAMPLES = 9
"""Examples per operation of each in-process run (derandomized: the same on both stores)."""
_DATA = Path(tempfile.mkdtemp(prefix="flexride-st-"))
atexit.register(shutil.rmtree, _DATA, ignore_errors=True)
_PG = contextlib.ExitStack()
atexit.register(_PG.close)


def _app(db: str):
    """The app on ``db`` (a fresh PostgreSQL schema, or SQLite), FE exports from a quick
    stand-in (not real builds)."""
    url = _PG.enter_context(pg_schema()) if db == "postgresql" else None
    app = create_app(make_settings(_DATA / db, max_study_jobs=8, max_body_bytes=64 * 1024,
                                   database_url=url))
    use_fe_builds(app, wait_s=2.0)
    return app


APPS = {db: _app(db) for db in SENT}
schema = schemathesis.openapi.from_asgi("/api/v1/openapi.json", APPS["sqlite"])
schema_pg = schemathesis.openapi.from_asgi("/api/v1/openapi.json", APPS["postgresql"])


@pytest.fixture(scope="module", autouse=True)
def finished_job():
    for app in APPS.values():
        svc = app.state.services
        insert_finished_job(svc.store, svc.files, synthetic_results(duration=6.0))


@schema.parametrize()
@settings(max_examples=EXAMPLES, deadline=None, derandomize=True,
          suppress_health_check=list(HealthCheck))
@pytest.mark.filterwarnings("ignore")
def test_no_request_fails_the_api(case):
    case.call_and_validate(checks=[*CHECKS, _counter("sqlite")])


@schema_pg.parametrize()
@settings(max_examples=EXAMPLES, deadline=None, derandomize=True,
          suppress_health_check=list(HealthCheck))
@pytest.mark.filterwarnings("ignore")
def test_no_request_fails_the_api_on_postgresql(case):
    case.call_and_validate(checks=[*CHECKS, _counter("postgresql")])


@pytest.mark.parametrize("db", list(SENT))
def test_a_few_hundred_requests_were_sent(db):
    sent = SENT[db]
    assert len(sent) >= 200, len(sent)
    codes = Counter(sent)
    print(f"schemathesis on {db}: {len(sent)} requests, status codes {dict(codes)}")
    assert not [c for c in codes if c >= 500], codes
    assert codes[200] and codes[201] and codes[422] and codes[404], codes


# -- a live `flexride serve` with an API token ---------------------------------------------------
# Run with hypothesis directly over each operation's strategies (valid and invalid data):
# schemathesis.pytest.from_fixture, which would load the schema from a fixture, fails under
# pytest 9 (it reads the removed ``Node._nodeid``).


@pytest.fixture(scope="module")
def live_url(tmp_path_factory):
    """API URL of a ``flexride serve`` process (tools/live_server.py) with a token, no runner
    (generated jobs are recorded, not run) and a finished job in its store."""
    data = tmp_path_factory.mktemp("flexride-live")
    store = JobStore.from_url(f"sqlite:///{data / 'flexride.db'}", create=True)
    insert_finished_job(store, ResultFiles(data / "results"), synthetic_results(duration=6.0))
    store.engine.dispose()
    server = start_server(data, cache_dir=data / "cache", log=data / "serve.log",
                          env={"FLEXRIDE_API_TOKEN": TEST_TOKEN, "FLEXRIDE_RUNNER": "none",
                               "LIVE_PROBE_SECRET": LIVE_SECRET,
                               "FLEXRIDE_MAX_STUDY_JOBS": "8",
                               "FLEXRIDE_MAX_BODY_BYTES": str(64 * 1024)})
    try:
        yield f"{server.url}/api/v1"
    finally:
        server.stop()


def _fuzz(operation: Any, mode: GenerationMode) -> None:
    """Send up to ``LIVE_EXAMPLES`` generated requests of ``operation`` (with the token) and
    check each response; the first failing case fails the test."""

    @given(case=operation.as_strategy(generation_mode=mode))
    @settings(max_examples=LIVE_EXAMPLES, deadline=None, derandomize=True, database=None,
              suppress_health_check=list(HealthCheck))
    def run(case: Any) -> None:
        case.call_and_validate(headers=AUTH, timeout=60, checks=[*CHECKS, _count_live])

    try:
        run()
    except Unsatisfiable:  # no invalid request exists (an operation without parameters)
        LIVE_SKIPPED.append(f"{operation.label} ({mode.value})")


@pytest.mark.filterwarnings("ignore")
def test_no_request_fails_the_live_service(live_url):
    schema = schemathesis.openapi.from_url(f"{live_url}/openapi.json").exclude(
        path_regex="/fe/")
    operations = [result.ok() for result in schema.get_all_operations()]
    assert len(operations) >= 25, [op.label for op in operations]
    for operation in operations:
        for mode in (GenerationMode.POSITIVE, GenerationMode.NEGATIVE):
            _fuzz(operation, mode)
    codes = Counter(LIVE_SENT)
    print(f"schemathesis, live: {len(LIVE_SENT)} requests, status codes {dict(codes)}; "
          f"not generated: {LIVE_SKIPPED}")
    assert len(LIVE_SENT) >= 500, codes
    assert not [c for c in codes if c >= 500], codes
    assert codes[201] and codes[200] and codes[422], codes  # the token let changes through


def test_the_live_service_answers_only_its_own_host_names(live_url):
    assert httpx.get(f"{live_url}/health", headers={"Host": "evil.example"}).status_code == 400
    port = live_url.split(":")[2].split("/")[0]
    for host in ("localhost", f"localhost:{port}", f"127.0.0.1:{port}"):
        assert httpx.get(f"{live_url}/health", headers={"Host": host}).status_code == 200
    r = httpx.post(f"{live_url}/jobs", json={"preset": "paper-metro"})
    assert r.status_code == 401  # the token is needed
