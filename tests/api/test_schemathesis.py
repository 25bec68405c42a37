"""Property-based run over the OpenAPI schema (schemathesis): a few hundred generated requests,
valid and invalid, against the real app; none may produce a server error, and every response
must match the documented status codes, content types and schemas.

Jobs are recorded, not run (``runner=none``): generated scenarios are checked at submission
(the stability check included) but no simulation starts. FE exports come from a stand-in build
(tests/api/test_fe_api.py runs a real one).
"""

from __future__ import annotations

import atexit
import shutil
import tempfile
from pathlib import Path

import pytest
import schemathesis
from hypothesis import HealthCheck, settings
from schemathesis.checks import not_a_server_error
from schemathesis.specs.openapi.checks import (
    content_type_conformance,
    response_schema_conformance,
    status_code_conformance,
)

from flexride.api import create_app
from service.svc_testkit import (
    insert_finished_job,
    make_settings,
    synthetic_results,
    use_fe_builds,
)

SENT: list[int] = []


def _count(ctx, response, case):
    """Counts the generated requests (and their status codes)."""
    SENT.append(response.status_code)


CHECKS = [not_a_server_error, status_code_conformance, content_type_conformance,
          response_schema_conformance, _count]

_DATA = Path(tempfile.mkdtemp(prefix="flexride-st-"))
atexit.register(shutil.rmtree, _DATA, ignore_errors=True)
APP = create_app(make_settings(_DATA, max_study_jobs=8, max_body_bytes=64 * 1024))
use_fe_builds(APP, wait_s=2.0)  # FE exports from a quick stand-in, not real builds
schema = schemathesis.openapi.from_asgi("/api/v1/openapi.json", APP)


@pytest.fixture(scope="module", autouse=True)
def finished_job():
    svc = APP.state.services
    return insert_finished_job(svc.store, svc.files, synthetic_results(duration=6.0))


@schema.parametrize()
@settings(max_examples=12, deadline=None, derandomize=True,
          suppress_health_check=list(HealthCheck))
@pytest.mark.filterwarnings("ignore")
def test_no_request_fails_the_api(case):
    case.call_and_validate(checks=CHECKS)


def test_a_few_hundred_requests_were_sent():
    from collections import Counter

    assert len(SENT) >= 200, len(SENT)
    codes = Counter(SENT)
    print(f"schemathesis: {len(SENT)} requests, status codes {dict(codes)}")
    assert not [c for c in codes if c >= 500], codes
    assert codes[200] and codes[201] and codes[422] and codes[404], codes
