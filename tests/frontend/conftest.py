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
import shutil
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

ARTIFACTS = Path(__file__).parent / "artifacts"
ROOT = Path(__file__).resolve().parents[2]
CHROMIUM_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
VIEWPORT = {"width": 1280, "height": 800}


def _required() -> bool:
    return os.environ.get("FLEXRIDE_BROWSER_TESTS", "").lower() in {"1", "required", "yes"}


def _unavailable(why: str) -> None:
    if _required():
        pytest.fail(f"browser tests required but {why}", pytrace=False)
    pytest.skip(why)


def chromium_path() -> str | None:
    """The system Chromium (never a downloaded one)."""
    env = os.environ.get("FLEXRIDE_CHROMIUM")
    if env:
        return env if Path(env).is_file() else None
    for name in ("/usr/bin/chromium", "/usr/bin/chromium-browser"):
        if Path(name).is_file():
            return name
    found = shutil.which("chromium") or shutil.which("chromium-browser")
    return found


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _get_json(url: str, timeout: float = 5.0) -> Any:
    with urllib.request.urlopen(url, timeout=timeout) as r:
        return json.loads(r.read().decode())


class Server:
    """A running ``flexride serve`` and helpers to talk to its API directly."""

    def __init__(self, url: str, proc: subprocess.Popen, data_dir: Path, log: Path) -> None:
        self.url = url
        self.proc = proc
        self.data_dir = data_dir
        self.log = log

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
    """``flexride serve`` on a free port with a temporary data directory."""
    data_dir = tmp_path_factory.mktemp("flexride-data")
    port = _free_port()
    exe = Path(sys.executable).with_name("flexride")
    cmd = [str(exe)] if exe.is_file() else [sys.executable, "-m", "flexride.cli"]
    cmd += ["serve", "--host", "127.0.0.1", "--port", str(port), "--data-dir", str(data_dir)]
    env = {
        **os.environ,
        "FLEXRIDE_DATA_DIR": str(data_dir),
        "FLEXRIDE_WORKERS": "2",
        "FLEXRIDE_FRONTEND_DIR": str(ROOT / "frontend"),
        "FLEXRIDE_LOG_LEVEL": "warning",
    }
    env.pop("FLEXRIDE_API_TOKEN", None)
    env.pop("FLEXRIDE_BROKER_URL", None)
    log = data_dir / "serve.log"
    with open(log, "wb") as fh:
        proc = subprocess.Popen(cmd, stdout=fh, stderr=subprocess.STDOUT, env=env, cwd=ROOT)
    url = f"http://127.0.0.1:{port}"
    try:
        end = time.monotonic() + 90
        while True:
            if proc.poll() is not None:
                raise RuntimeError(
                    f"flexride serve exited ({proc.returncode}):\n{log.read_text()[-3000:]}"
                )
            try:
                h = _get_json(f"{url}/api/v1/health", timeout=2)
                if h.get("status") == "ok":
                    break
            except (urllib.error.URLError, ConnectionError, TimeoutError, json.JSONDecodeError):
                pass
            if time.monotonic() > end:
                raise RuntimeError(
                    f"flexride serve did not become healthy:\n{log.read_text()[-3000:]}"
                )
            time.sleep(0.25)
        yield Server(url, proc, data_dir, log)
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait(timeout=5)


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
