"""Where flexride keeps files, and how it writes them: the cache directory and atomic writes.

Kept free of heavy imports: :mod:`flexride._numba_env` uses it before numba is loaded.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

CACHE_ENV = "FLEXRIDE_CACHE_DIR"
"""Environment variable that moves the cache directory."""


def cache_root() -> Path:
    """The cache directory: ``$FLEXRIDE_CACHE_DIR``, default ``~/.cache/flexride`` (numba
    kernels, reduced FE bodies, their browser exports).
    """
    return Path(os.environ.get(CACHE_ENV) or Path.home() / ".cache" / "flexride")


@contextmanager
def atomic_path(dest: str | os.PathLike[str], *, fsync: bool = False) -> Iterator[Path]:
    """A temporary path beside ``dest`` that becomes ``dest`` when the block ends without an
    exception (rename, atomic on one file system); removed otherwise.

    Parameters
    ----------
    dest : path-like
        Final file; its parent directories are created.
    fsync : bool
        Flush the file to disk before the rename (for data that must survive a crash).

    Yields
    ------
    pathlib.Path
        Where to write.
    """
    path = Path(dest)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    tmp = Path(name)
    try:
        yield tmp
        if fsync:
            with open(tmp, "rb+") as fh:
                os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def write_bytes_atomic(dest: str | os.PathLike[str], data: bytes, *, fsync: bool = False) -> Path:
    """Write ``data`` to ``dest`` atomically (:func:`atomic_path`); return ``dest``."""
    with atomic_path(dest, fsync=fsync) as tmp:
        tmp.write_bytes(data)
    return Path(dest)
