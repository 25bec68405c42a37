"""Bearer token on mutating endpoints, body-size limit, file access confined to the results
directory, loopback by default."""

from __future__ import annotations

import pytest

from flexride.errors import ResultsFileError
from flexride.settings import Settings
from flexride.store import ResultFiles
from service.svc_testkit import insert_finished_job, services, synthetic_results

API = "/api/v1"
JOB = {"preset": "paper-metro", "overrides": {"duration_s": 1.0}}


def test_token_guards_every_mutating_endpoint(make_client):
    client = make_client(api_token="s3cret")
    assert client.get(f"{API}/jobs").status_code == 200  # reads stay open
    assert client.get(f"{API}/health").status_code == 200
    for method, path, body in (("post", "/jobs", JOB), ("post", "/jobs/x/cancel", None),
                               ("delete", "/jobs/x", None), ("post", "/studies", {}),
                               ("post", "/studies/x/cancel", None), ("delete", "/studies/x",
                                                                     None)):
        kw = {"json": body} if body is not None else {}
        r = getattr(client, method)(f"{API}{path}", **kw)
        assert r.status_code == 401, (method, path, r.text)
        assert r.headers["www-authenticate"] == "Bearer"
        r = getattr(client, method)(f"{API}{path}", headers={"Authorization": "Bearer nope"},
                                    **kw)
        assert r.status_code == 401
    ok = client.post(f"{API}/jobs", json=JOB, headers={"Authorization": "Bearer s3cret"})
    assert ok.status_code == 201, ok.text
    job_id = ok.json()["id"]
    assert client.delete(f"{API}/jobs/{job_id}",
                         headers={"Authorization": "Bearer s3cret"}).status_code == 204


def test_oversized_bodies_are_413(make_client):
    client = make_client(max_body_bytes=2048)
    big = {"preset": "paper-metro", "overrides": {"description": "x" * 5000}}
    r = client.post(f"{API}/jobs", json=big)
    assert r.status_code == 413 and "limit" in r.json()["detail"]

    def chunks():  # no Content-Length: the limit applies while streaming
        for _ in range(10):
            yield b" " * 1000

    r = client.post(f"{API}/jobs", content=chunks(), headers={"content-type":
                                                               "application/json"})
    assert r.status_code == 413
    assert client.post(f"{API}/jobs", json=JOB).status_code == 201


def test_malformed_json_is_422_not_500(sqlite_client):
    r = sqlite_client.post(f"{API}/jobs", content=b"{not json",
                           headers={"content-type": "application/json"})
    assert r.status_code == 422
    r = sqlite_client.post(f"{API}/jobs", content=b'{"preset": "paper-metro", '
                           b'"overrides": {"speed_kmh": NaN}}',
                           headers={"content-type": "application/json"})
    assert r.status_code == 422


def test_files_cannot_escape_the_results_directory(tmp_path, sqlite_client):
    files = ResultFiles(tmp_path / "results")
    (tmp_path / "secret.h5").write_bytes(b"x")
    for name in ("../secret.h5", "/etc/passwd", "..", "a/b.h5", "0" * 32 + ".h5/../x",
                 "", None, "0" * 31 + "g.h5"):
        with pytest.raises(ResultsFileError):
            files.path(name)
    link = files.root / ("a" * 32 + ".h5")
    link.symlink_to(tmp_path / "secret.h5")
    with pytest.raises(ResultsFileError):
        files.path(link.name)
    # through the API: a record pointing outside gives 404, never the file
    svc = services(sqlite_client)
    job_id = insert_finished_job(svc.store, svc.files, synthetic_results(duration=6.0),
                                 result_file="../../secret.h5")
    for path in ("download", "channels", "series?channels=carbody.PR.acc.z"):
        r = sqlite_client.get(f"{API}/jobs/{job_id}/{path}")
        assert r.status_code == 404, (path, r.text)
    for bad in ("..%2F..%2Fetc%2Fpasswd", "%2e%2e", "x" * 65):
        assert sqlite_client.get(f"{API}/jobs/{bad}/download").status_code in (404, 422)


def test_binds_to_loopback_without_configuration(tmp_path, monkeypatch):
    monkeypatch.delenv("FLEXRIDE_HOST", raising=False)
    assert Settings(_env_file=None, data_dir=tmp_path).bind_host == "127.0.0.1"
