"""Bearer token on mutating endpoints, strong tokens only, Host header check (no DNS
rebinding), body-size limit, file access confined to the results directory, loopback by
default."""

from __future__ import annotations

import subprocess

import pytest
from pydantic import ValidationError
from typer.testing import CliRunner

from flexride.api.middleware import TrustedHosts, host_name
from flexride.errors import ResultsFileError
from flexride.settings import Settings, get_settings
from flexride.store import ResultFiles
from service.svc_testkit import (
    TEST_TOKEN,
    free_port,
    insert_finished_job,
    make_settings,
    service_command,
    service_env,
    services,
    synthetic_results,
)

API = "/api/v1"
JOB = {"preset": "paper-metro", "overrides": {"duration_s": 1.0}}
AUTH = {"Authorization": f"Bearer {TEST_TOKEN}"}
HINT = 'python3 -c "import secrets; print(secrets.token_urlsafe(32))"'


def test_token_guards_every_mutating_endpoint(make_client):
    client = make_client(api_token=TEST_TOKEN)
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
    ok = client.post(f"{API}/jobs", json=JOB, headers=AUTH)
    assert ok.status_code == 201, ok.text
    job_id = ok.json()["id"]
    assert client.delete(f"{API}/jobs/{job_id}", headers=AUTH).status_code == 204


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


# -- strong tokens ---------------------------------------------------------------------------

WEAK_TOKENS = {
    "short": "s3cret",
    "well-known": "changeme",
    "15 characters": "Qm7vR2xK9pLw4Zt",
    "whitespace only": " " * 20,
    "leading space": " " + TEST_TOKEN,
    "trailing newline": TEST_TOKEN + "\n",
    "inner space": "Qm7vR2xK9p Lw4ZtB-e3Nc",
    "not ASCII": "Qm7vR2xK9pLw4ZtB-ë3Nc",
    "repeated word": "passwordpassword",
    "repeated word, upper case": "PASSWORDPASSWORD",
    "words and separators": "secret-secret-secret",
    "word and digits": "Admin12345678901!",
    "several words": "test-token-123456",
    "digits": "1234567890123456",
    "one character": "a" * 24,
    "few characters": "ab" * 10,
    "alphabet": "abcdefghijklmnopq",
    "keyboard": "qwertyuiopasdfgh",
}
STRONG_TOKENS = [TEST_TOKEN, "z2wlVWRRUcMgZRhDDIv6dCtHXPBOn42wwpaGXAmjk2I",
                 "b55f7b45d986013c582fa81fea758b6c", "correct-horse-battery-staple"]


@pytest.mark.parametrize("token", WEAK_TOKENS.values(), ids=WEAK_TOKENS.keys())
def test_weak_tokens_are_refused_with_how_to_make_one(token, tmp_path):
    with pytest.raises(ValidationError) as info:
        Settings(_env_file=None, data_dir=tmp_path, api_token=token)
    (err,) = info.value.errors()
    assert err["loc"] == ("api_token",) and HINT in err["msg"] and "\n" not in err["msg"]
    assert not token.strip() or token.strip() not in str(info.value)  # never repeated


def test_strong_tokens_are_accepted(tmp_path):
    for token in STRONG_TOKENS:
        assert Settings(_env_file=None, data_dir=tmp_path, api_token=token).api_token == token
    # empty means no token, as FLEXRIDE_API_TOKEN= does
    assert Settings(_env_file=None, data_dir=tmp_path, api_token="").api_token is None


def test_create_app_refuses_a_weak_token_that_skipped_validation(tmp_path):
    from flexride.api import create_app

    settings = make_settings(tmp_path).model_copy(update={"api_token": "changeme"})
    with pytest.raises(ValueError, match="FLEXRIDE_API_TOKEN: the token is too short"):
        create_app(settings)


@pytest.mark.parametrize("token", ["changeme", "passwordpassword", "   x   "])
def test_serve_refuses_a_weak_token_in_one_line(token, monkeypatch):
    import typer
    import uvicorn

    from flexride.cli.service import register

    monkeypatch.setattr(uvicorn, "run", lambda *a, **k: pytest.fail("the server started"))
    app = typer.Typer()
    register(app)
    get_settings.cache_clear()
    try:
        result = CliRunner().invoke(app, ["serve"], env={"FLEXRIDE_API_TOKEN": token})
    finally:
        get_settings.cache_clear()
    assert result.exit_code == 2, result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: FLEXRIDE_API_TOKEN: the token")
    assert HINT in lines[0] and f" {token.strip()} " not in lines[0]


def test_serve_process_with_a_weak_token_exits_2_without_traceback(tmp_path):
    p = subprocess.run([*service_command(), "serve", "--port", str(free_port())],
                       env=service_env(FLEXRIDE_API_TOKEN="passwordpassword",
                                       FLEXRIDE_DATA_DIR=str(tmp_path)),
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 2, (p.stdout, p.stderr)
    assert p.stdout == "" and len(p.stderr.strip().splitlines()) == 1, p.stderr
    assert "Traceback" not in p.stderr and HINT in p.stderr


# -- Host header (DNS rebinding) ---------------------------------------------------------------


def test_requests_for_another_host_are_400(make_client):
    client = make_client()
    for method, path in (("get", f"{API}/health"), ("get", "/docs"), ("get", "/"),
                         ("post", f"{API}/jobs"), ("get", f"{API}/openapi.json")):
        r = client.request(method, path, headers={"Host": "evil.example"},
                           **({"json": JOB} if method == "post" else {}))
        assert r.status_code == 400, (path, r.text)
        assert r.headers["content-type"] == "application/json"
        assert "Host" in r.json()["detail"] and "evil.example" in r.json()["message"]
    assert client.get(f"{API}/jobs").json()["total"] == 0  # the POST did nothing
    for host in ("localhost", "localhost:8000", "127.0.0.1", "127.0.0.1:8000", "[::1]:8000",
                 "LOCALHOST.", "testserver"):
        r = client.get(f"{API}/health", headers={"Host": host})
        assert r.status_code == 200, (host, r.text)


def test_allowed_hosts_setting(make_client):
    client = make_client(allowed_hosts="api.example.org, *.lab.example")
    for host in ("api.example.org", "API.example.org:443", "x.lab.example", "a.b.lab.example",
                 "localhost:8000"):
        assert client.get(f"{API}/health", headers={"Host": host}).status_code == 200, host
    for host in ("testserver", "example.org", "evilapi.example.org", "lab.example.evil.com",
                 "lab.example", "api.example.org.evil.com"):
        assert client.get(f"{API}/health", headers={"Host": host}).status_code == 400, host
    anything = make_client(allowed_hosts="*")
    assert anything.get(f"{API}/health", headers={"Host": "evil.example"}).status_code == 200
    bound = make_client(host="10.1.2.3")  # the bind address is a host name of the service
    assert bound.get(f"{API}/health", headers={"Host": "10.1.2.3:8000"}).status_code == 200


def test_allowed_hosts_entries_are_checked(tmp_path):
    for bad in ("http://api.example.org", "api.example.org/x", "a.org,two words"):
        with pytest.raises(ValidationError, match="is not a host name"):
            Settings(_env_file=None, data_dir=tmp_path, allowed_hosts=bad)
    s = Settings(_env_file=None, data_dir=tmp_path, host="0.0.0.0", allowed_hosts="A.org, b.org")
    assert s.trusted_hosts == ["localhost", "127.0.0.1", "::1", "a.org", "b.org"]
    s = Settings(_env_file=None, data_dir=tmp_path, host="flexride.lan")
    assert s.trusted_hosts == ["localhost", "127.0.0.1", "::1", "flexride.lan"]


def test_host_header_parsing():
    assert host_name("LocalHost:8000") == "localhost" and host_name("[::1]:8000") == "::1"
    assert host_name("example.org.") == "example.org" and host_name("[::1") == ""
    hosts = TrustedHosts(None, ["localhost", "::1", "[fe80::1]:80", "*.lab.example"])
    for good in ("[::1]", "[fe80::1]:8000", "x.lab.example", "LOCALHOST:1"):
        assert hosts.allows(good), good
    for bad in ("", ":8000", "[::2]", "lab.example", "localhost.evil", "xlab.example"):
        assert not hosts.allows(bad), bad
