#!/usr/bin/env python3
"""Set up a local virtual environment and run flexride's main job or its tests.

Usage (from the repository root, with nothing but python3 installed)::

    python3 tools/dev.py serve    # create .venv, install flexride, start the service + dashboard
    python3 tools/dev.py run      # create .venv, install flexride, run the paper's 80 km/h case
    python3 tools/dev.py test     # create .venv, install flexride with test extras, run pytest

Extra arguments go to ``flexride serve``, ``flexride run`` or pytest respectively.
"""

from __future__ import annotations

import hashlib
import os
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


def main(argv: list[str]) -> int:
    if not argv or argv[0] not in {"serve", "run", "test"}:
        print(__doc__)
        return 2
    cmd, rest = argv[0], argv[1:]
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
    return subprocess.call([str(BIN / "python"), "-m", "pytest", *rest], cwd=ROOT)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
