"""The paper report study through Celery (real Redis, real `flexride worker` processes,
PostgreSQL): its runs and then its report's build (a job of kind paper_report) are run by the
workers; the API serves the report. The plan is the tiny study of tests/paper (4 runs, a
0.5 m car body mesh), as in tests/api/test_studies_report.py. Fails, never skips, when Redis
or PostgreSQL is down.
"""

from __future__ import annotations

import pytest

from jobs.test_celery_e2e import API, running_cluster
from service.svc_testkit import wait_for

pytestmark = pytest.mark.filterwarnings("ignore:Using `httpx`")


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    with running_cluster(tmp_path_factory, "celery-report") as c:
        yield c


def test_report_study_on_celery_workers(cluster, monkeypatch):
    import flexride.study.report as report
    from api.test_studies_report import TINY

    monkeypatch.setattr(report, "report_options", lambda request: TINY.checked())
    c = cluster.client
    r = c.post(f"{API}/studies", json={"preset": "paper-report", "quick": True})
    assert r.status_code == 201, r.text
    sid = r.json()["id"]
    try:
        final = wait_for(lambda: (s := c.get(f"{API}/studies/{sid}").json())["report"]["state"]
                         in ("ready", "failed") and s, 600.0, 1.0, "the report")
    except AssertionError as exc:
        raise AssertionError(f"{exc}\n--- worker log ---\n{cluster.worker_log()}") from None
    assert final["report"]["state"] == "ready", (final["report"], cluster.worker_log())
    job = c.get(f"{API}/jobs/{final['report']['job_id']}").json()
    assert job["kind"] == "paper_report" and job["worker"].startswith("celery-")
    page = c.get(final["report"]["links"]["html"])
    assert page.status_code == 200 and "Dynamic evaluation on ride comfort" in page.text
    assert len(c.get(final["report"]["links"]["summary"]).json()) > 50
