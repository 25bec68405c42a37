"""The numba cache directory's key (:mod:`flexride._numba_env`): it follows the sources of the
modules that use numba, so that an edited callee is never loaded from a stale caller's cache."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from flexride._numba_env import kernel_sources_digest


def _package(root: Path) -> Path:
    (root / "solver").mkdir(parents=True)
    (root / "solver" / "kernel.py").write_text("import numba\n\n@numba.njit\ndef f(x):\n"
                                               "    return x + 1\n")
    (root / "api.py").write_text("def route():\n    return 1\n")
    return root


def test_digest_follows_the_kernels_sources_only(tmp_path):
    pkg = _package(tmp_path / "pkg")
    first = kernel_sources_digest(pkg)
    assert kernel_sources_digest(pkg) == first and len(first) == 12
    (pkg / "api.py").write_text("def route():\n    return 2\n")  # no numba: same cache
    assert kernel_sources_digest(pkg) == first
    (pkg / "solver" / "kernel.py").write_text("import numba\n\n@numba.njit\ndef f(x):\n"
                                              "    return x + 2\n")
    assert kernel_sources_digest(pkg) != first


def test_the_package_cache_directory_carries_the_digest(tmp_path):
    """Without a directory of the user's choosing, a fresh process caches its kernels under
    the cache root in a directory named after the versions and the digest."""
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env["FLEXRIDE_CACHE_DIR"] = str(tmp_path)
    out = subprocess.run([sys.executable, "-c", "import os, flexride; "
                          "print(os.environ['NUMBA_CACHE_DIR'])"], env=env, check=True,
                         capture_output=True, text=True).stdout.strip()
    path = Path(out)
    assert path.parent == tmp_path
    assert path.name.startswith("numba-") and path.name.endswith(f"-{kernel_sources_digest()}")
