"""A real ``flexride serve`` on a free port, and the system's browsers: what the dashboard's
browser tests (``tests/frontend/conftest.py``) and its benchmark (``benchmarks/bench_dashboard.py``)
share.

The browsers are Debian's packages, never downloaded ones: ``chromium`` (``/usr/bin/chromium``,
or ``FLEXRIDE_CHROMIUM``), headless, driven by Playwright over the Chrome DevTools Protocol;
and ``firefox-esr`` (``/usr/bin/firefox-esr``, or ``FLEXRIDE_FIREFOX``), driven over WebDriver
BiDi (Playwright's ``moz-firefox`` channel: the stock Firefox, no ``playwright install``). The
Python package ``playwright`` is pinned in ``pyproject.toml`` to a release whose BiDi commands
Firefox ESR knows.

Headless Firefox has no WebGL (Mozilla bug 1375585), so Plotly's 3D plots (the flexible-body
view) cannot draw there; ``virtual_display`` starts a private Xvfb (Debian package ``xvfb``)
on which Firefox runs with a window and gets WebGL from Mesa's software renderer. Headless
Chromium has WebGL (SwiftShader).

Both importers put this directory on ``sys.path``.
"""

from __future__ import annotations

import json
import os
import select
import shutil
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
#: Flags of the headless system Chromium (no sandbox in containers, nothing fetched at start).
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
#: Preferences of the system Firefox (nothing checked or fetched at start).
FIREFOX_PREFS = {
    "app.update.enabled": False,
    "browser.shell.checkDefaultBrowser": False,
    "network.captive-portal-service.enabled": False,
    "network.connectivity-service.enabled": False,
}
#: The browsers the dashboard is tested in (Playwright's names), and their Debian packages.
BROWSERS = {"chromium": "chromium", "firefox": "firefox-esr"}


def chromium_path() -> str | None:
    """The system Chromium (``FLEXRIDE_CHROMIUM`` if set), or None."""
    env = os.environ.get("FLEXRIDE_CHROMIUM")
    if env:
        return env if Path(env).is_file() else None
    for name in ("/usr/bin/chromium", "/usr/bin/chromium-browser"):
        if Path(name).is_file():
            return name
    return shutil.which("chromium") or shutil.which("chromium-browser")


def firefox_path() -> str | None:
    """The system Firefox (``FLEXRIDE_FIREFOX`` if set; Debian's ESR first), or None."""
    env = os.environ.get("FLEXRIDE_FIREFOX")
    if env:
        return env if Path(env).is_file() else None
    for name in ("/usr/bin/firefox-esr", "/usr/bin/firefox"):
        if Path(name).is_file():
            return name
    return shutil.which("firefox-esr") or shutil.which("firefox")


def browser_path(name: str) -> str | None:
    """The binary of browser ``name`` (a key of ``BROWSERS``), or None when it is missing."""
    if name == "chromium":
        return chromium_path()
    if name == "firefox":
        return firefox_path()
    raise ValueError(f"unknown browser {name!r} (known: {', '.join(BROWSERS)})")


def xvfb_path() -> str | None:
    """The X virtual frame buffer ``Xvfb`` (Debian package ``xvfb``), or None."""
    return shutil.which("Xvfb")


@contextmanager
def virtual_display(width: int = 1920, height: int = 1200, timeout: float = 15.0) -> Iterator[str]:
    """A private X display (``Xvfb`` on the first free display number) for a browser with a
    window; stopped on exit.

    Yields
    ------
    str
        Its ``DISPLAY`` value (``":<n>"``).

    Raises
    ------
    FileNotFoundError
        Without ``Xvfb`` (``apt-get install xvfb``).
    """
    exe = xvfb_path()
    if exe is None:
        raise FileNotFoundError("no Xvfb (apt-get install xvfb)")
    rfd, wfd = os.pipe()
    cmd = [exe, "-displayfd", str(wfd), "-screen", "0", f"{width}x{height}x24", "-nolisten", "tcp"]
    try:
        proc = subprocess.Popen(
            cmd, pass_fds=(wfd,), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
        )
    finally:
        os.close(wfd)
    try:
        number = b""
        end = time.monotonic() + timeout
        while not number.endswith(b"\n"):  # Xvfb writes its display number when it is ready
            left = end - time.monotonic()
            if left <= 0 or not select.select([rfd], [], [], left)[0]:
                raise RuntimeError(f"Xvfb did not start within {timeout} s")
            chunk = os.read(rfd, 16)
            if not chunk:
                raise RuntimeError(f"Xvfb exited ({proc.wait()}) before it was ready")
            number += chunk
        yield f":{int(number)}"
    finally:
        os.close(rfd)
        proc.terminate()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait(timeout=5)


def launch_browser(playwright: Any, name: str, *, display: str | None = None) -> Any:
    """Launch the system browser ``name`` (``chromium`` or ``firefox``) with Playwright.

    Parameters
    ----------
    playwright : playwright.sync_api.Playwright
        A started Playwright (``sync_playwright().start()`` or its context manager).
    name : str
        A key of ``BROWSERS``.
    display : str, optional
        For Firefox: an X display (``virtual_display``) on which it runs with a window, which
        gives it WebGL; headless without. Chromium is always headless.

    Returns
    -------
    playwright.sync_api.Browser

    Raises
    ------
    FileNotFoundError
        When the browser is not installed (``apt-get install`` its ``BROWSERS`` package).
    """
    path = browser_path(name)
    if path is None:
        raise FileNotFoundError(f"no system {name} (apt-get install {BROWSERS[name]})")
    if name == "chromium":
        return playwright.chromium.launch(executable_path=path, args=CHROMIUM_ARGS, headless=True)
    return playwright.firefox.launch(
        channel="moz-firefox",  # WebDriver BiDi: the stock Firefox, not Playwright's build
        executable_path=path,
        headless=display is None,
        env={**os.environ, "DISPLAY": display} if display else None,
        firefox_user_prefs=FIREFOX_PREFS,
    )


def free_port() -> int:
    """A free TCP port on 127.0.0.1."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def get_json(url: str, timeout: float = 5.0) -> Any:
    """GET ``url`` and parse its JSON body."""
    with urllib.request.urlopen(url, timeout=timeout) as r:
        return json.loads(r.read().decode())


@dataclass
class LiveServer:
    """A running ``flexride serve``.

    Attributes
    ----------
    url : str
        Base URL (``http://127.0.0.1:<port>``).
    proc : subprocess.Popen
        The server process.
    data_dir : pathlib.Path
        Its data directory (database and results).
    log : pathlib.Path or None
        File with its output, if kept.
    """

    url: str
    proc: subprocess.Popen
    data_dir: Path
    log: Path | None = None

    def wait_for_solver(self, timeout: float = 900.0) -> None:
        """Wait until the service's solver kernels are compiled (health ``solver.state``
        ``ready``): before, the service queues jobs without the submission check. A few
        seconds when numba's cache holds them; a cold compile otherwise (once per change of
        the solver's sources).
        """
        end = time.monotonic() + timeout
        while True:
            try:
                health = get_json(f"{self.url}/api/v1/health", timeout=5)
                if (health.get("solver") or {}).get("state") == "ready":
                    return
            except (urllib.error.URLError, ConnectionError, TimeoutError, json.JSONDecodeError):
                pass
            if self.proc.poll() is not None or time.monotonic() > end:
                raise RuntimeError(f"the service's solver did not become ready:\n"
                                   f"{_tail(self.log)}")
            time.sleep(0.5)

    def stop(self, timeout: float = 15.0) -> None:
        """Terminate the server (kill it if it does not stop within ``timeout`` s)."""
        self.proc.terminate()
        try:
            self.proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait(timeout=5)


def _tail(log: Path | None) -> str:
    return log.read_text(errors="replace")[-3000:] if log is not None and log.is_file() else ""


def start_server(data_dir: Path, *, workers: int | None = None, cache_dir: Path | None = None,
                 log: Path | None = None, timeout: float = 90.0,
                 env: dict[str, str] | None = None) -> LiveServer:
    """Start ``flexride serve`` (embedded runner, dashboard from ``frontend/``) and wait until
    its health is ``ok``.

    Parameters
    ----------
    data_dir : pathlib.Path
        Data directory of the service (database, results).
    workers : int, optional
        Embedded worker processes (default: the service's, one per core).
    cache_dir : pathlib.Path, optional
        ``FLEXRIDE_CACHE_DIR`` of the service (FE models and their exports); the numba kernel
        cache stays where it is, so the kernels are not compiled again.
    log : pathlib.Path, optional
        File for the server's output (discarded otherwise).
    timeout : float
        Seconds to wait for the server to become healthy.
    env : dict of str to str, optional
        More environment variables of the server (e.g. ``FLEXRIDE_API_TOKEN``); by default
        it has neither a token nor a broker.

    Returns
    -------
    LiveServer
    """
    import flexride  # noqa: F401  (sets NUMBA_CACHE_DIR in this process's environment)

    port = free_port()
    exe = Path(sys.executable).with_name("flexride")
    cmd = [str(exe)] if exe.is_file() else [sys.executable, "-m", "flexride.cli"]
    cmd += ["serve", "--host", "127.0.0.1", "--port", str(port), "--data-dir", str(data_dir)]
    extra = env or {}
    env = {
        **os.environ,
        "FLEXRIDE_DATA_DIR": str(data_dir),
        "FLEXRIDE_FRONTEND_DIR": str(ROOT / "frontend"),
        "FLEXRIDE_LOG_LEVEL": "warning",
    }
    if workers is not None:
        env["FLEXRIDE_WORKERS"] = str(workers)
    if cache_dir is not None:
        env["FLEXRIDE_CACHE_DIR"] = str(cache_dir)
    env.pop("FLEXRIDE_API_TOKEN", None)
    env.pop("FLEXRIDE_BROKER_URL", None)
    env.update(extra)
    out = open(log, "wb") if log is not None else subprocess.DEVNULL
    try:
        proc = subprocess.Popen(cmd, stdout=out, stderr=subprocess.STDOUT, env=env, cwd=ROOT)
    finally:
        if log is not None:
            out.close()  # type: ignore[union-attr]
    url = f"http://127.0.0.1:{port}"
    server = LiveServer(url, proc, data_dir, log)
    end = time.monotonic() + timeout
    while True:
        if proc.poll() is not None:
            raise RuntimeError(f"flexride serve exited ({proc.returncode}):\n{_tail(log)}")
        try:
            if get_json(f"{url}/api/v1/health", timeout=2).get("status") == "ok":
                return server
        except (urllib.error.URLError, ConnectionError, TimeoutError, json.JSONDecodeError):
            pass
        if time.monotonic() > end:
            server.stop()
            raise RuntimeError(f"flexride serve did not become healthy:\n{_tail(log)}")
        time.sleep(0.25)
