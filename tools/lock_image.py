#!/usr/bin/env python3
"""Write ``requirements.lock``: the exact Python packages of the service image.

Resolves flexride's dependencies (no extras) with the image's own interpreter: in a container
of the image's Debian base (the local debootstrap base of ``tools/docker_images.py``, or
``--base debian:bookworm-slim`` from a registry) it installs Debian's ``python3-venv``, then
flexride from this checkout into a fresh virtual environment (binary wheels only), and writes
``pip freeze`` of it, flexride itself left out. Debian's Python (3.11.2) needs packages a newer
3.11 does not (``redis`` wants ``async-timeout`` before 3.11.3), so the lock is made there.
The Dockerfile installs the lock with ``--no-deps`` and then flexride with ``--no-deps``: an
image built later has exactly these packages. Run it after a change of the dependencies in
``pyproject.toml``; ``tests/service/test_lock.py`` checks that the lock still satisfies them.
pip reaches the index as the host's pip does (``docker_images.pip_build_args``).

Usage: ``python3 tools/lock_image.py [--base IMAGE]`` (with a Docker engine at
``DOCKER_HOST``; as root when the local base must be made first). ``--here`` locks with the
Python running this script instead, for a machine without Docker.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import venv
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import docker_images

ROOT = Path(__file__).resolve().parents[1]
LOCK = ROOT / "requirements.lock"
#: Run in the container: Debian's venv, flexride from /src (read-only), the frozen set
_SCRIPT = r"""
set -e
export DEBIAN_FRONTEND=noninteractive PIP_CERT=/etc/ssl/certs/ca-certificates.crt
apt-get update -qq >/dev/null
apt-get install -y -qq --no-install-recommends python3-venv ca-certificates >/dev/null
if [ -n "$EXTRA_CA_CERTS" ]; then
    printf '%s\n' "$EXTRA_CA_CERTS" > /usr/local/share/ca-certificates/lock-extra.crt
    update-ca-certificates >/dev/null 2>&1
fi
python3 -m venv /tmp/lock
/tmp/lock/bin/pip install -q --no-cache-dir --upgrade pip >&2
cp -r /src /tmp/src
/tmp/lock/bin/pip install -q --no-cache-dir --only-binary=:all: --no-binary=flexride /tmp/src >&2
echo "python $(python3 -c 'import platform; print(platform.python_version())')"
/tmp/lock/bin/pip freeze --exclude flexride
"""


def _source_tree(tmp: Path) -> Path:
    """A copy of what installing flexride needs (no .venv, no results, no caches)."""
    src = tmp / "src"
    for name in ("pyproject.toml", "README.md"):
        (src / name).parent.mkdir(parents=True, exist_ok=True)
        (src / name).write_bytes((ROOT / name).read_bytes())
    for f in docker_images._files(ROOT, ["backend"]):
        dest = src / f.relative_to(ROOT)
        dest.parent.mkdir(parents=True, exist_ok=True)
        dest.write_bytes(f.read_bytes())
    return src


def freeze_in_container(base: str) -> tuple[str, str]:
    """``(python version, pip freeze)`` of flexride installed in a container of ``base``."""
    args = docker_images.pip_build_args()
    env_flags = [a for k, v in args.items() for a in ("-e", f"{k}={v}")]
    with tempfile.TemporaryDirectory(prefix="flexride-lock-") as tmp:
        src = _source_tree(Path(tmp))
        out = docker_images.docker("run", "--rm", "--network=host", *env_flags,
                                   "-v", f"{src}:/src:ro", base, "sh", "-c", _SCRIPT)
    first, _, frozen = out.partition("\n")
    return first.split()[1], frozen


def freeze_here() -> tuple[str, str]:
    """``(python version, pip freeze)`` of flexride installed with this Python."""
    with tempfile.TemporaryDirectory(prefix="flexride-lock-") as tmp:
        venv.EnvBuilder(with_pip=True).create(tmp)
        py = str(Path(tmp) / "bin" / "python")
        subprocess.run([py, "-m", "pip", "install", "-q", "--upgrade", "pip"], check=True)
        subprocess.run([py, "-m", "pip", "install", "-q", str(ROOT)], check=True)
        frozen = subprocess.run([py, "-m", "pip", "freeze", "--exclude", "flexride"],
                                check=True, capture_output=True, text=True).stdout
    return ".".join(map(str, sys.version_info[:3])), frozen


def main(argv: list[str]) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--base", help="base image (default: the local debootstrap base)")
    p.add_argument("--here", action="store_true", help="lock with this Python, no Docker")
    opts = p.parse_args(argv)
    if opts.here:
        version, frozen = freeze_here()
    else:
        base = opts.base or docker_images.make_base(docker_images.debian_mirrors()).tag
        version, frozen = freeze_in_container(base)
    LOCK.write_text(f"# flexride service image, Python {version}: written by "
                    "tools/lock_image.py from pyproject.toml; do not edit\n" + frozen)
    print(f"wrote {LOCK.relative_to(ROOT)} ({len(frozen.splitlines())} packages)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
