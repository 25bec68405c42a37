#!/usr/bin/env python3
"""Write ``requirements.lock``: the exact Python packages of the service image.

Installs flexride (no extras) into a fresh virtual environment with this Python, then writes
``pip freeze`` of it (flexride itself left out). The Dockerfile installs the lock first, then
flexride with ``--no-deps``, so an image built later gets the same packages. Run it after a
change of the dependencies in ``pyproject.toml``; ``tests/service/test_lock.py`` checks that the
lock still satisfies them.

Usage: ``python3 tools/lock_image.py``
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
import venv
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LOCK = ROOT / "requirements.lock"


def main() -> int:
    with tempfile.TemporaryDirectory(prefix="flexride-lock-") as tmp:
        venv.EnvBuilder(with_pip=True).create(tmp)
        py = str(Path(tmp) / "bin" / "python")
        subprocess.run([py, "-m", "pip", "install", "-q", "--upgrade", "pip"], check=True)
        subprocess.run([py, "-m", "pip", "install", "-q", str(ROOT)], check=True)
        frozen = subprocess.run([py, "-m", "pip", "freeze", "--exclude", "flexride"],
                                check=True, capture_output=True, text=True).stdout
    version = ".".join(map(str, sys.version_info[:2]))
    LOCK.write_text(f"# flexride service image, Python {version}: written by "
                    "tools/lock_image.py from pyproject.toml; do not edit\n" + frozen)
    print(f"wrote {LOCK.relative_to(ROOT)} ({len(frozen.splitlines())} packages)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
