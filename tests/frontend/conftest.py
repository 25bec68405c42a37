"""Fixtures of the dashboard's browser tests: a real ``flexride serve`` (embedded runner, temporary
data directory, free port) and the system's browsers driven by Playwright.

Every test runs in Chromium and in Firefox (test ids ``[chromium]`` and ``[firefox]``): the
Debian packages ``chromium`` and ``firefox-esr``, never downloaded (``tools/live_server.py``
launches them; ``FLEXRIDE_CHROMIUM`` / ``FLEXRIDE_FIREFOX`` select other binaries). Chromium
runs headless; Firefox with a window on a private Xvfb display (package ``xvfb``), because
headless Firefox has no WebGL and the flexible-body view draws its mesh with WebGL.
``FLEXRIDE_BROWSERS=chromium`` (or ``firefox``, or both comma-separated) picks browsers. One
server serves both browsers; each browser is launched once per session. Without a browser (or
without the Python package ``playwright``) its tests are skipped, unless
``FLEXRIDE_BROWSER_TESTS=required`` (CI), which turns that into a failure.

Screenshots of every view go to ``tests/frontend/artifacts/<browser>/`` (git-ignored).
"""

from __future__ import annotations

import base64
import json
import os
import re
import sys
import time
import urllib.request
from collections.abc import Callable, Iterator
from contextlib import ExitStack
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
from live_server import (  # noqa: E402
    BROWSERS,
    LiveServer,
    browser_path,
    launch_browser,
    start_server,
    virtual_display,
    xvfb_path,
)

ARTIFACTS = Path(__file__).parent / "artifacts"
VIEWPORT = {"width": 1280, "height": 800}
#: Browsers whose downloads Playwright sees (``page.expect_download``). Under WebDriver BiDi,
#: Firefox ESR announces a download without the id Playwright needs, so there the exports are
#: checked through ``DOWNLOAD_RECORDER`` instead.
NATIVE_DOWNLOADS = {"chromium"}
#: Init script for the other browsers: records every click on an ``<a download>`` (the
#: dashboard's CSV export and Plotly's PNG/SVG export) with its file name, and starts reading a
#: ``blob:`` link's content at the click, before the page revokes the URL.
DOWNLOAD_RECORDER = """(() => {
  const click = HTMLAnchorElement.prototype.click;
  const downloads = [];
  Object.defineProperty(window, "__flexrideDownloads", { value: downloads });
  HTMLAnchorElement.prototype.click = function () {
    if (this.hasAttribute("download")) {
      const entry = { name: this.download, href: this.href, content: null };
      if (this.href.startsWith("blob:") || this.href.startsWith("data:")) {
        entry.content = fetch(this.href).then(r => r.blob()).then(b => new Promise(ok => {
          const fr = new FileReader();
          fr.onload = () => ok(fr.result);
          fr.onerror = () => ok(null);
          fr.readAsDataURL(b);
        })).catch(() => null);
      }
      downloads.push(entry);
    }
    return click.call(this);
  };
})();"""


def selected_browsers() -> list[str]:
    """The browsers to test: ``FLEXRIDE_BROWSERS`` (comma-separated) or all of ``BROWSERS``."""
    env = os.environ.get("FLEXRIDE_BROWSERS", "")
    names = [n.strip().lower() for n in env.split(",") if n.strip()] or list(BROWSERS)
    unknown = [n for n in names if n not in BROWSERS]
    if unknown:
        raise pytest.UsageError(
            f"FLEXRIDE_BROWSERS: unknown {', '.join(unknown)} (known: {', '.join(BROWSERS)})"
        )
    return list(dict.fromkeys(names))


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
    # a new FE build answers 202 at once, so the views' "building" state is always seen
    live = start_server(data_dir, workers=2, cache_dir=cache_dir, log=data_dir / "serve.log",
                        env={"FLEXRIDE_FE_WAIT_S": "0"})
    try:
        live.wait_for_solver()  # the views expect the submission check, not a queued job
        yield Server(live, cache_dir)
    finally:
        live.stop()


@pytest.fixture(scope="session")
def playwright_api() -> Iterator[Any]:
    """A started Playwright (sync API), shared by the browsers of the session."""
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        _unavailable("the Python package playwright is not installed")
    with sync_playwright() as p:
        yield p


@pytest.fixture(scope="session", params=selected_browsers())
def browser(request: pytest.FixtureRequest, playwright_api: Any) -> Iterator[Any]:
    """The system's Chromium (headless) or Firefox (with a window on a private Xvfb display:
    headless Firefox has no WebGL for the 3D plots); one launch per session and browser."""
    name = request.param
    if browser_path(name) is None:
        _unavailable(f"no system {name} (apt-get install {BROWSERS[name]})")
    with ExitStack() as stack:
        display = None
        if name == "firefox":
            if xvfb_path() is None:
                _unavailable("no Xvfb for Firefox (headless it has no WebGL): apt-get install xvfb")
            display = stack.enter_context(virtual_display())
        b = launch_browser(playwright_api, name, display=display)
        b.flexride_name = name
        try:
            yield b
        finally:
            b.close()


@pytest.fixture(scope="session")
def browser_name(browser: Any) -> str:
    """``chromium`` or ``firefox``: the browser of the running test."""
    return browser.flexride_name


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


def _allow_busy_estimate(log: ConsoleLog, response: Any) -> None:
    """The new-job form's instant estimate answered 503 (every estimate slot of the process
    busy, shown as a note in its panel by design): the browser's own "Failed to load resource …
    503" line for it is not an error of the page."""
    if response.status == 503 and "/api/v1/estimates" in response.url:
        log.allow(r"status of 503")


@pytest.fixture(scope="session")
def browser_context(browser: Any, server: Server) -> Iterator[Any]:
    """One browser context for all tests: its HTTP cache keeps Plotly (4.6 MB) between them."""
    ctx = browser.new_context(viewport=VIEWPORT, base_url=server.url, accept_downloads=True)
    if browser.flexride_name not in NATIVE_DOWNLOADS:
        ctx.add_init_script(DOWNLOAD_RECORDER)
    try:
        yield ctx
    finally:
        ctx.close()


@pytest.fixture
def page(
    browser_context: Any, browser_name: str, request: pytest.FixtureRequest
) -> Iterator[Any]:
    """A fresh page at 1280×800 on the test server; fails the test on unexpected console errors.
    ``page.browser_name`` is the browser's name (``chromium`` or ``firefox``)."""
    pg = browser_context.new_page()
    pg.browser_name = browser_name
    pg.set_default_timeout(20_000)
    log = ConsoleLog()
    pg.on("console", lambda m: log.errors.append(m.text) if m.type == "error" else None)
    pg.on("pageerror", lambda e: log.errors.append(f"uncaught: {e}"))
    pg.on("response", lambda r: _allow_busy_estimate(log, r))
    pg.console_log = log
    try:
        yield pg
    finally:
        pg.close()
    bad = log.unexpected()
    assert not bad, f"console errors in {request.node.name}: {bad}"


def shot(page: Any, name: str, full_page: bool = True) -> Path:
    """Save a screenshot under tests/frontend/artifacts/<browser>/."""
    folder = ARTIFACTS / page.browser_name
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{name}.png"
    page.screenshot(path=str(path), full_page=full_page)
    return path


def wait_plot(page: Any, selector: str, timeout: float = 30_000) -> int:
    """Wait until the plot in ``selector`` (a plot card) has drawn data; return its point count."""
    page.wait_for_selector(f"{selector} .plot[data-state=ready]", timeout=timeout)
    n = int(page.get_attribute(f"{selector} .plot", "data-points") or 0)
    traces = page.eval_on_selector(f"{selector} .plot", "e => (e.data || []).length")
    assert traces > 0 and n > 0, f"{selector}: {traces} traces, {n} points"
    return n


def download(page: Any, click: Callable[[], None]) -> tuple[str, bytes]:
    """Run ``click`` (which makes the page save a file) and return the file's name and content.

    Chromium: the download as Playwright sees it. Firefox: the ``<a download>`` click that
    ``DOWNLOAD_RECORDER`` saw and the content of its link, read from the moment of the click
    (Plotly revokes its ``blob:`` URL right after clicking).
    """
    if page.browser_name in NATIVE_DOWNLOADS:
        with page.expect_download() as dl:
            click()
        return dl.value.suggested_filename, Path(dl.value.path()).read_bytes()
    before = page.evaluate("() => window.__flexrideDownloads.length")
    click()
    page.wait_for_function(f"() => window.__flexrideDownloads.length > {before}")
    name, content = page.evaluate(
        "async () => { const d = window.__flexrideDownloads.at(-1);"
        " return [d.name, await d.content]; }"
    )
    assert content, f"{name}: the content of its link could not be read"
    return name, base64.b64decode(content.split(",", 1)[1])


@pytest.fixture(name="shot")
def shot_fixture():
    """``shot(page, name)``: save a screenshot under tests/frontend/artifacts/<browser>/."""
    return shot


@pytest.fixture(name="download")
def download_fixture():
    """``download(page, click)``: the name and content of the file that ``click`` saves."""
    return download


@pytest.fixture(name="wait_plot")
def wait_plot_fixture():
    """``wait_plot(page, selector)``: wait for a plot card to show data; its point count."""
    return wait_plot
