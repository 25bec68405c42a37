"""Numba configuration shared by every compiled kernel.

Kernels are compiled with ``cache=True`` into a directory keyed by the flexride and numba
versions and by the kernels' sources, so neither an upgrade nor an edit loads a stale cache
(numba checks only the file of the function it loads: a cached caller keeps the code of a
callee in another file that has changed since). ``FASTMATH`` is LLVM's fast-math flag set
*without* ``nnan`` and ``ninf``: the kernels check for NaN/inf to stop diverging runs, and those
checks must not be optimised away.
"""

from __future__ import annotations

import hashlib
import os
from importlib import metadata
from pathlib import Path

from flexride.fileio import cache_root

FASTMATH = set({"nsz", "arcp", "contract", "afn", "reassoc"})


def _numba_version() -> str:
    try:
        return metadata.version("numba")
    except metadata.PackageNotFoundError:  # pragma: no cover - numba is a hard dependency
        return "unknown"


def configure_numba_cache(flexride_version: str) -> Path:
    """Point numba's on-disk cache at a version-keyed directory (unless the user chose one).

    Parameters
    ----------
    flexride_version : str
        Version of this package; part of the cache key.

    Returns
    -------
    pathlib.Path
        The cache directory in use.
    """
    if "NUMBA_CACHE_DIR" not in os.environ:
        path = cache_root() / (f"numba-{flexride_version}-{_numba_version()}-"
                               f"{kernel_sources_digest()}")
        os.environ["NUMBA_CACHE_DIR"] = str(path)
    return Path(os.environ["NUMBA_CACHE_DIR"])


def kernel_sources_digest(package: Path | None = None) -> str:
    """Short SHA-256 of the package's modules that use numba (path and content, -).

    Parameters
    ----------
    package : pathlib.Path, optional
        The package directory (default: flexride's).
    """
    root = package or Path(__file__).parent
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        data = path.read_bytes()
        if b"numba" in data:
            digest.update(path.relative_to(root).as_posix().encode() + b"\0" + data)
    return digest.hexdigest()[:12]
