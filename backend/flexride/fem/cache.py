"""On-disk cache of reduced bodies, keyed by a content hash of their inputs.

Location: ``$FLEXRIDE_CACHE_DIR`` (default ``~/.cache/flexride``) / ``fem-<flexride version>``,
as for the numba cache (:mod:`flexride._numba_env`), so an upgrade never loads a stale body.
Each entry is an uncompressed ``.npz`` of the small arrays, one ``.npy`` per large array (the
nodal mode shapes, memory-mapped on load so a hit costs milliseconds whatever the number of
modes) and a ``.json`` of everything else, each written atomically (temporary file, then
rename; the ``.json`` last, and a load needs all files) so concurrent processes never read half
an entry.
"""

from __future__ import annotations

import hashlib
import json
from contextlib import ExitStack
from pathlib import Path
from typing import Any

import numpy as np

from flexride.fileio import atomic_path, cache_root

#: Bump when the content or layout of cached entries changes.
CACHE_SCHEMA = 2
#: Arrays stored as separate ``.npy`` files and memory-mapped when loaded.
MAPPED = ("shapes",)


def _version() -> str:
    from flexride import __version__

    return __version__


def cache_dir() -> Path:
    """The cache directory for FE bodies (created on first write)."""
    return cache_root() / f"fem-{_version()}"


def _canonical(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {str(k): _canonical(v) for k, v in sorted(obj.items(), key=lambda kv: str(kv[0]))}
    if isinstance(obj, (list, tuple)):
        return [_canonical(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _canonical(obj.tolist())
    if isinstance(obj, (np.floating, float)):
        return float(repr(float(obj))) if np.isfinite(obj) else str(obj)
    if isinstance(obj, (np.integer,)):
        return int(obj)
    return obj


def content_hash(inputs: dict) -> str:
    """SHA-256 of the canonical JSON of ``inputs`` plus the versions and cache schema."""
    from flexride.fem.pyfe3d_adapter import PYFE3D_VERSION

    payload = {
        "inputs": _canonical(inputs),
        "flexride": _version(),
        "pyfe3d": PYFE3D_VERSION,
        "numpy_major": np.__version__.split(".")[0],
        "schema": CACHE_SCHEMA,
    }
    text = json.dumps(payload, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:32]


def load(key: str) -> tuple[dict[str, np.ndarray], dict] | None:
    """Arrays and metadata of entry ``key``, or None when absent or unreadable.

    Large arrays (:data:`MAPPED`) are read-only memory maps.
    """
    d = cache_dir()
    npz, meta = d / f"{key}.npz", d / f"{key}.json"
    if not (npz.is_file() and meta.is_file()):
        return None
    try:
        info = json.loads(meta.read_text(encoding="utf-8"))
        with np.load(npz, allow_pickle=False) as data:
            arrays = {k: data[k] for k in data.files}
        for name in info.get("_mapped", []):
            arrays[name] = np.load(d / f"{key}.{name}.npy", mmap_mode="r", allow_pickle=False)
    except (OSError, ValueError, json.JSONDecodeError):
        return None
    return arrays, info


def store(key: str, arrays: dict[str, np.ndarray], info: dict) -> Path | None:
    """Write entry ``key``; returns its path, or None when the directory is not writable."""
    d = cache_dir()
    mapped = [k for k in arrays if k in MAPPED]
    small = {k: v for k, v in arrays.items() if k not in MAPPED}
    try:
        # every file renamed into place only when all are written (metadata last written,
        # first renamed: a reader that finds it also needs the arrays, see load)
        with ExitStack() as files:
            for name in mapped:
                with open(files.enter_context(atomic_path(d / f"{key}.{name}.npy")), "wb") as fh:
                    np.save(fh, np.ascontiguousarray(arrays[name]), allow_pickle=False)
            with open(files.enter_context(atomic_path(d / f"{key}.npz")), "wb") as fh:
                np.savez(fh, allow_pickle=False, **small)  # numeric arrays; load refuses pickles
            meta = files.enter_context(atomic_path(d / f"{key}.json"))
            meta.write_text(json.dumps(_canonical({**info, "_mapped": mapped})),
                            encoding="utf-8")
    except OSError:
        return None
    return d / f"{key}.npz"
