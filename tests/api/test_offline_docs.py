"""/docs (Swagger UI) and /redoc (ReDoc) work without internet: their pages name only URLs of
this service, and those answer (the scripts and styles of the installed fastapi-offline
package). tests/frontend/test_api_docs.py opens both in real browsers with the network cut."""

from __future__ import annotations

import re

import pytest

#: URLs in the pages: attributes and the spec URL given to Swagger UI.
_URLS = re.compile(r"""(?:src|href|spec-url)\s*=\s*["']([^"']+)["']|\burl:\s*["']([^"']+)["']""")
_TYPES = {".js": "javascript", ".css": "text/css", ".png": "image/png", ".json": "json"}


def _local_urls(html: str) -> list[str]:
    urls = [a or b for a, b in _URLS.findall(html)]
    assert urls, html
    return urls


@pytest.mark.parametrize("page, needs", [
    ("/docs", ("swagger-ui-bundle.js", "swagger-ui.css", "favicon.png", "openapi.json")),
    ("/redoc", ("redoc.standalone.js", "favicon.png", "openapi.json")),
])
def test_docs_pages_load_everything_from_the_service(sqlite_client, page, needs):
    r = sqlite_client.get(page)
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/html")
    html = r.text
    assert "://" not in html, "an absolute URL"
    for word in ("cdn", "jsdelivr", "unpkg", "googleapis", "tiangolo", "validator.swagger"):
        assert word not in html.lower(), word
    urls = _local_urls(html)
    for need in needs:
        assert any(u.endswith(need) for u in urls), (need, urls)
    for url in urls:
        assert url.startswith("/") and not url.startswith("//"), url
        got = sqlite_client.get(url)
        assert got.status_code == 200, (url, got.status_code)
        kind = next(v for k, v in _TYPES.items() if url.endswith(k))
        assert kind in got.headers["content-type"], (url, got.headers["content-type"])
        assert len(got.content) > 100, url


def test_swagger_ui_asks_no_online_validator(sqlite_client):
    assert '"validatorUrl": null' in sqlite_client.get("/docs").text


def test_docs_behind_a_path_prefix(make_client):
    """Behind a proxy that serves the app under a prefix (ASGI root_path), the pages point
    into that prefix."""
    from fastapi.testclient import TestClient

    client = TestClient(make_client().app, root_path="/flexride")  # lifespan already run
    for page in ("/docs", "/redoc"):
        urls = _local_urls(client.get(page).text)
        assert all(u.startswith("/flexride/") for u in urls), urls


@pytest.mark.parametrize("page", ["/docs", "/redoc"])
def test_docs_pages_may_load_nothing_from_elsewhere(sqlite_client, page):
    """Their Content-Security-Policy: nothing from another origin (ReDoc's script would load
    its logo from cdn.redoc.ly), inline scripts only by hash."""
    import base64
    import hashlib

    r = sqlite_client.get(page)
    header = r.headers["content-security-policy"]
    policy = dict(d.strip().split(" ", 1) for d in header.split(";"))
    assert policy["default-src"] == "'self'" and policy["img-src"] == "'self' data:"
    assert "unsafe" not in policy["script-src"] and "http" not in header
    for script in re.findall(r"<script>(.*?)</script>", r.text, re.S):
        digest = base64.b64encode(hashlib.sha256(script.encode()).digest()).decode()
        assert f"'sha256-{digest}'" in policy["script-src"]
