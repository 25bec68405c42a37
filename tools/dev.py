#!/usr/bin/env python3
"""Set up a local virtual environment and run flexride's main job or its tests.

Usage (from the repository root, with nothing but python3 installed)::

    python3 tools/dev.py serve    # create .venv, install flexride, start the service + dashboard
    python3 tools/dev.py run      # create .venv, install flexride, run the paper's 80 km/h case
    python3 tools/dev.py test     # create .venv, install flexride with test extras, install or
                                  # start what the tests need, run pytest
    python3 tools/dev.py coverage # the same, and print the line coverage of flexride
    python3 tools/dev.py flexride ARGS  # create .venv, install flexride, run `flexride ARGS`

Extra arguments go to ``flexride serve``, ``flexride run`` or pytest respectively. Before the
tests, ``test`` installs Debian's chromium, firefox-esr, xvfb, docker.io, debootstrap and a
Compose CLI with apt-get when they are missing, and starts (or installs) Redis and PostgreSQL
(``tools/ensure_services.sh``); it stops with one line naming what is missing when it cannot.
``FLEXRIDE_TEST_SETUP=skip`` leaves the machine as it is.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import sys
import venv
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
VENV = Path(os.environ.get("FLEXRIDE_VENV", ROOT / ".venv"))
BIN = VENV / ("Scripts" if os.name == "nt" else "bin")


#: Test-only packages installed without their dependencies: ansys-mapdl-reader's .full reader
#: needs only NumPy/SciPy, but its package metadata would pull pyvista and VTK (~725 MB).
NO_DEPS_TEST_PACKAGES = ("ansys-mapdl-reader==0.56.0",)


def _stamp_key(extras: str) -> str:
    text = (ROOT / "pyproject.toml").read_bytes() + extras.encode()
    if extras == "dev":
        text += " ".join(NO_DEPS_TEST_PACKAGES).encode()
    return hashlib.sha256(text).hexdigest()


def ensure_venv(extras: str = "") -> None:
    """Create ``.venv`` and install flexride (editable) unless the install is current."""
    if not (BIN / "python").exists():
        print(f"creating virtual environment in {VENV}", flush=True)
        venv.EnvBuilder(with_pip=True, clear=False).create(VENV)
    stamp = VENV / ".flexride-install-stamp"
    key = _stamp_key(extras)
    if stamp.exists() and stamp.read_text() == key:
        return
    py = str(BIN / "python")
    subprocess.run([py, "-m", "pip", "install", "-q", "--upgrade", "pip"], check=True)
    target = f".[{extras}]" if extras else "."
    subprocess.run([py, "-m", "pip", "install", "-q", "-e", target], check=True, cwd=ROOT)
    if extras == "dev":
        subprocess.run([py, "-m", "pip", "install", "-q", "--no-deps", *NO_DEPS_TEST_PACKAGES],
                       check=True, cwd=ROOT)
    stamp.write_text(key)


#: Debian packages the tests need, by the command that shows each is installed: the dashboard's
#: browsers (never a browser download), a virtual display for Firefox's WebGL, and for the
#: deployment test (tests/deploy) a Docker engine and client and debootstrap, which makes the
#: images' Debian base without a registry; a Compose CLI is checked below.
TEST_PACKAGES = {"chromium": "chromium", "firefox-esr": "firefox-esr", "Xvfb": "xvfb",
                 "dockerd": "docker.io", "docker": "docker.io", "debootstrap": "debootstrap"}
#: Where Debian puts dockerd and debootstrap (not on every user's PATH)
_SBIN = ("/usr/local/sbin", "/usr/sbin", "/sbin")


def _installed(cmd: str) -> bool:
    return shutil.which(cmd) is not None or any(
        os.access(os.path.join(d, cmd), os.X_OK) for d in _SBIN)


def _missing_packages() -> list[str]:
    missing = list(dict.fromkeys(pkg for cmd, pkg in TEST_PACKAGES.items()
                                 if not _installed(cmd)))
    compose = shutil.which("docker-compose") or (
        shutil.which("docker") and subprocess.call(
            ["docker", "compose", "version"], stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL) == 0)
    if not compose:
        missing.append("docker-compose")
    return missing


def _as_root(cmd: list[str]) -> list[str]:
    if os.geteuid() == 0:
        return cmd
    return ["sudo", "-n", *cmd] if shutil.which("sudo") else cmd


def prepare_test_machine() -> str | None:
    """Install or start what the tests need (Debian's browsers, Xvfb, Docker, debootstrap, a
    Compose CLI; Redis and PostgreSQL via tools/ensure_services.sh); return why that failed,
    or None. The deployment test starts its own Docker daemon (tests/deploy/engine.py)."""
    missing = _missing_packages()
    if missing:
        print(f"installing {', '.join(missing)} with apt-get", flush=True)
        env = {**os.environ, "DEBIAN_FRONTEND": "noninteractive"}
        ok = (subprocess.call(_as_root(["apt-get", "update", "-qq"]), env=env) == 0 and
              subprocess.call(_as_root(["apt-get", "install", "-y", "-qq", *missing]),
                              env=env) == 0)
        still = _missing_packages()
        if not ok or still:
            return (f"cannot install {', '.join(still or missing)} (needs apt-get as root); "
                    "install them and run the tests again")
    if subprocess.call(["bash", str(ROOT / "tools" / "ensure_services.sh")]) != 0:
        return ("Redis (127.0.0.1:6379) or PostgreSQL (127.0.0.1:5432, database test) is not "
                "reachable and could not be started; see the lines above")
    return None


def main(argv: list[str]) -> int:
    if not argv or argv[0] not in {"serve", "run", "test", "coverage", "flexride"}:
        print(__doc__)
        return 2
    cmd, rest = argv[0], argv[1:]
    if cmd == "flexride":  # any command of the CLI, without activating .venv
        ensure_venv()
        return subprocess.call([str(BIN / "flexride"), *rest])
    if cmd == "serve":
        ensure_venv()
        return subprocess.call([str(BIN / "flexride"), "serve", *rest], cwd=ROOT)
    if cmd == "run":
        ensure_venv()
        args = rest or [
            "--preset",
            "paper-random-straight-80",
            "-o",
            str(ROOT / "results" / "paper-random-straight-80.h5"),
        ]
        return subprocess.call([str(BIN / "flexride"), "run", *args], cwd=ROOT)
    ensure_venv("dev")
    if os.environ.get("FLEXRIDE_TEST_SETUP", "").lower() != "skip":
        problem = prepare_test_machine()
        if problem:
            print(f"flexride tests: {problem}", file=sys.stderr)
            return 2
    # the browser tests fail, not skip, without a browser (FLEXRIDE_BROWSER_TESTS=optional
    # lets them skip on a machine set up by hand)
    env = {"FLEXRIDE_BROWSER_TESTS": "required", **os.environ}
    if cmd == "coverage":  # the same run under coverage (about twice as slow in Python code)
        rest = ["--cov=flexride", "--cov-report=term:skip-covered", *rest]
    return subprocess.call([str(BIN / "python"), "-m", "pytest", *rest], cwd=ROOT, env=env)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
