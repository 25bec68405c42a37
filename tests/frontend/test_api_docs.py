"""The API docs of a real ``flexride serve`` work offline, in Chromium and Firefox: /docs (Swagger
UI) and /redoc (ReDoc) opened with every request to another host aborted list the operations,
and neither page tries to reach another host.

The pages load their scripts from the service (the fastapi-offline package's files) and carry a
Content-Security-Policy that lets them load nothing from elsewhere: ReDoc's Redocly logo (an
image from cdn.redoc.ly) is refused by the browser, which it reports on the console.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from typing import Any
from urllib.parse import urlsplit

import pytest

try:
    from playwright.sync_api import expect
except ImportError:  # the browser fixture skips these tests (or fails them in CI)
    expect = None

LOOPBACK = {"127.0.0.1", "localhost", "::1", "[::1]"}
#: Operations checked by method, path and summary.
OPERATIONS = [("POST", "/api/v1/jobs", "Submit a simulation job"),
              ("POST", "/api/v1/studies", "Submit a study"),
              ("GET", "/api/v1/jobs/{job_id}/series", "Decimated time series"),
              ("GET", "/api/v1/health", "Health")]
#: The one console message expected: the browser refusing ReDoc's logo (CSP of the page).
REDOC_LOGO = re.compile(r"cdn\.redoc\.ly/redoc/logo-mini\.svg.*(Content Security Policy|img-src)")


class Offline:
    """A page in a browser context whose requests to any host but this machine are aborted;
    records those requests and the page's console errors."""

    def __init__(self, context: Any, browser_name: str) -> None:
        self.blocked: list[str] = []
        self.errors: list[str] = []
        context.route("**/*", self._route)
        self.page = context.new_page()
        self.page.browser_name = browser_name
        self.page.set_default_timeout(30_000)
        self.page.on("console",
                     lambda m: self.errors.append(m.text) if m.type == "error" else None)
        self.page.on("pageerror", lambda e: self.errors.append(f"uncaught: {e}"))

    def _route(self, route: Any) -> None:
        url = route.request.url
        if urlsplit(url).hostname in LOOPBACK:
            route.continue_()
        else:
            self.blocked.append(url)
            route.abort()


@pytest.fixture
def offline(browser: Any, browser_name: str, server: Any) -> Iterator[Offline]:
    """A fresh context on the test server, cut off from every other host."""
    context = browser.new_context(viewport={"width": 1280, "height": 800}, base_url=server.url)
    try:
        yield Offline(context, browser_name)
    finally:
        context.close()


def _operation_count(server: Any) -> int:
    spec = server.api("/openapi.json")
    return sum(len(ops) for ops in spec["paths"].values())


def test_swagger_ui_lists_the_operations_offline(offline, server, shot):
    page = offline.page
    page.goto("/docs")
    for method, path, summary in OPERATIONS:
        block = page.locator(f".opblock-{method.lower()}").filter(
            has=page.locator(f".opblock-summary-path[data-path='{path}']"))
        expect(block).to_have_count(1)
        expect(block.locator(".opblock-summary-method")).to_have_text(method)
        expect(block.locator(".opblock-summary-description")).to_have_text(summary)
    expect(page.locator(".opblock")).to_have_count(_operation_count(server))
    shot(page, "api-docs-swagger", full_page=False)
    assert offline.blocked == [], offline.blocked
    assert offline.errors == [], offline.errors


def test_redoc_lists_the_operations_offline(offline, server, shot):
    page = offline.page
    page.goto("/redoc")
    for method, path, summary in OPERATIONS:
        expect(page.get_by_role("heading", name=summary).first).to_be_visible()
        endpoint = page.locator("button").filter(
            has=page.locator(f".http-verb.{method.lower()}")).filter(
            has=page.get_by_text(path, exact=True))
        expect(endpoint.first).to_be_attached()
    menu = page.locator("[role=menuitem] .operation-type")
    expect(menu).to_have_count(_operation_count(server))
    shot(page, "api-docs-redoc", full_page=False)
    assert offline.blocked == [], offline.blocked  # the policy keeps the logo from leaving
    assert [e for e in offline.errors if not REDOC_LOGO.search(e)] == [], offline.errors
