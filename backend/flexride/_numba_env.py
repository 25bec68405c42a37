"""Numba configuration shared by every compiled kernel.

Kernels are compiled with ``cache=True`` into a directory keyed by the flexride and numba
versions, so an upgrade never loads a stale cache. ``FASTMATH`` is LLVM's fast-math flag set
*without* ``nnan`` and ``ninf``: the kernels check for NaN/inf to stop diverging runs, and those
checks must not be optimised away.
"""

from __future__ import annotations

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
        path = cache_root() / f"numba-{flexride_version}-{_numba_version()}"
        os.environ["NUMBA_CACHE_DIR"] = str(path)
    return Path(os.environ["NUMBA_CACHE_DIR"])
