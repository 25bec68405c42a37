"""Fixtures of the dashboard's browser tests: a real ``flexride serve`` (embedded runner, temporary
data directory, free port) and the system's headless Chromium driven by Playwright.

The browser is the Debian package ``chromium`` (``/usr/bin/chromium``); it is never downloaded.
Set ``FLEXRIDE_CHROMIUM`` to use another binary. Without a browser (or without the Python
package ``playwright``) the tests are skipped, unless ``FLEXRIDE_BROWSER_TESTS=required`` (CI),
which turns that into a failure.

Screenshots of every view go to ``tests/frontend/artifacts/`` (git-ignored).
"""

from __future__ import annotations

import json
import os
import re
import sys
import time
import urllib.request
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
from live_server import CHROMIUM_ARGS, LiveServer, chromium_path, start_server  # noqa: E402

ARTIFACTS = Path(__file__).parent / "artifacts"
VIEWPORT = {"width": 1280, "height": 800}


def _required() -> bool:
    return os.environ.get("FLEXRIDE_BROWSER_TESTS", "").lower() in {"1", "required", "yes"}


def _unavailable(why: str) -> None:
    if _required():
        pytest.fail(f"browser tests required but {why}", pytrace=False)
    pytest.skip(why)


class Server:
    """A running ``flexride serve`` and helpers to talk to its API directly."""

    def __init__(self, live: LiveServer, cache_dir: Path) -> None:
        self.url = live.url
        self.proc = live.proc
        self.data_dir = live.data_dir
        self.log = live.log
        self.cache_dir = cache_dir

    def api(self, path: str, body: dict | None = None, method: str | None = None) -> Any:
        data = json.dumps(body).encode() if body is not None else None
        req = urllib.request.Request(
            f"{self.url}/api/v1{path}",
            data=data,
            method=method or ("POST" if data else "GET"),
            headers={"Content-Type": "application/json"} if data else {},
        )
        with urllib.request.urlopen(req, timeout=30) as r:
            text = r.read().decode()
            return json.loads(text) if text else None

    def wait_job(self, job_id: str, timeout: float = 120.0) -> dict:
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            job = self.api(f"/jobs/{job_id}")
            if job["status"] not in ("queued", "running"):
                return job
            time.sleep(0.3)
        raise AssertionError(f"job {job_id} did not finish in {timeout} s")


@pytest.fixture(scope="session")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    """``flexride serve`` on a free port with a temporary data directory and a temporary FE
    cache (FE models are built by the session that asks for them)."""
    data_dir = tmp_path_factory.mktemp("flexride-data")
    cache_dir = tmp_path_factory.mktemp("flexride-cache")
    live = start_server(data_dir, workers=2, cache_dir=cache_dir, log=data_dir / "serve.log")
    try:
        yield Server(live, cache_dir)
    finally:
        live.stop()


@pytest.fixture(scope="session")
def browser() -> Iterator[Any]:
    """The system's headless Chromium."""
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        _unavailable("the Python package playwright is not installed")
    path = chromium_path()
    if path is None:
        _unavailable("no system Chromium (apt-get install chromium)")
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=path, args=CHROMIUM_ARGS, headless=True)
        try:
            yield b
        finally:
            b.close()


class ConsoleLog:
    """Console errors and uncaught exceptions of a page."""

    def __init__(self) -> None:
        self.errors: list[str] = []
        self.allowed: list[re.Pattern[str]] = []

    def allow(self, pattern: str) -> None:
        """Accept console errors matching ``pattern`` (e.g. an expected 422 response)."""
        self.allowed.append(re.compile(pattern))

    def unexpected(self) -> list[str]:
        return [e for e in self.errors if not any(p.search(e) for p in self.allowed)]


@pytest.fixture(scope="session")
def browser_context(browser: Any, server: Server) -> Iterator[Any]:
    """One browser context for all tests: its HTTP cache keeps Plotly (4.6 MB) between them."""
    ctx = browser.new_context(viewport=VIEWPORT, base_url=server.url, accept_downloads=True)
    try:
        yield ctx
    finally:
        ctx.close()


@pytest.fixture
def page(browser_context: Any, request: pytest.FixtureRequest) -> Iterator[Any]:
    """A fresh page at 1280×800 on the test server; fails the test on unexpected console errors."""
    pg = browser_context.new_page()
    pg.set_default_timeout(20_000)
    log = ConsoleLog()
    pg.on("console", lambda m: log.errors.append(m.text) if m.type == "error" else None)
    pg.on("pageerror", lambda e: log.errors.append(f"uncaught: {e}"))
    pg.console_log = log
    try:
        yield pg
    finally:
        pg.close()
    bad = log.unexpected()
    assert not bad, f"console errors in {request.node.name}: {bad}"


def shot(page: Any, name: str, full_page: bool = True) -> Path:
    """Save a screenshot under tests/frontend/artifacts/."""
    ARTIFACTS.mkdir(exist_ok=True)
    path = ARTIFACTS / f"{name}.png"
    page.screenshot(path=str(path), full_page=full_page)
    return path


def wait_plot(page: Any, selector: str, timeout: float = 30_000) -> int:
    """Wait until the plot in ``selector`` (a plot card) has drawn data; return its point count."""
    page.wait_for_selector(f"{selector} .plot[data-state=ready]", timeout=timeout)
    n = int(page.get_attribute(f"{selector} .plot", "data-points") or 0)
    traces = page.eval_on_selector(f"{selector} .plot", "e => (e.data || []).length")
    assert traces > 0 and n > 0, f"{selector}: {traces} traces, {n} points"
    return n


@pytest.fixture(name="shot")
def shot_fixture():
    """``shot(page, name)``: save a screenshot under tests/frontend/artifacts/."""
    return shot


@pytest.fixture(name="wait_plot")
def wait_plot_fixture():
    """``wait_plot(page, selector)``: wait for a plot card to show data; its point count."""
    return wait_plot
