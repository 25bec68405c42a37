"""Result files: one HDF5 file per job under ``<data_dir>/results``, served read-only.

Names are built from job ids only (never from request text) and every path is resolved and
checked to lie inside the results directory, so no request can reach another file. Channel
reads take only the datasets asked for.

The results of a finished job never change, so what is read from a file (its description,
time and distance axes, run facts and each channel asked for) is kept in memory in a bounded
LRU (:class:`~flexride.store.lru.ByteLRU`, ``cache_bytes``): repeated reads of a job do not
open the HDF5 file again. Entries are keyed by the file name *and* its identity (inode, size,
modification time, one ``stat`` per read), so a file that was deleted or replaced is never
answered from memory; :meth:`ResultFiles.forget` drops a file's entries at once. Cached arrays
are read-only (NumPy ``writeable = False``): readers must not change them in place.
"""

from __future__ import annotations

import copy
import json
import os
import re
import shutil
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from flexride.errors import ResultsFileError
from flexride.results import read_points
from flexride.store.lru import ByteLRU, CacheStats

_NAME = re.compile(r"^[0-9a-f]{32}\.h5$")

DEFAULT_CACHE_BYTES = 256 * 1024 * 1024
"""Default bound of the in-memory cache of file contents (bytes)."""
DEFAULT_CACHE_ENTRIES = 8192
"""Default bound of its number of entries (arrays, descriptions)."""

FileToken = tuple[int, int, int, int]
"""Identity of a file version: device, inode, size (bytes), modification time (ns)."""


@dataclass
class ChannelData:
    """Some channels of a result file.

    Attributes
    ----------
    time, distance : numpy.ndarray
        Axes (s, m) of the selected samples.
    channels : dict of str to numpy.ndarray
        Selected channels.
    units : dict of str to str
        Unit of each selected channel.
    sample_rate : float
        Output sample rate in Hz.
    meta, scenario : dict
        Run facts and the scenario of the file.
    """

    time: np.ndarray
    distance: np.ndarray
    channels: dict[str, np.ndarray]
    units: dict[str, str]
    sample_rate: float
    meta: dict[str, Any] = field(default_factory=dict)
    scenario: dict[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class _FileInfo:
    """What every read of a file needs: channel units, the time axis, run facts, scenario."""

    units: dict[str, str]
    time: np.ndarray
    sample_rate: float
    meta: dict[str, Any]
    scenario: dict[str, Any]


class ResultFiles:
    """The results directory of the service.

    Parameters
    ----------
    root : path-like
        ``<data_dir>/results``; created if missing.
    cache_bytes : int
        Bound (bytes) of the in-memory cache of file contents; 0 disables it.
    cache_entries : int
        Bound of its number of entries.
    """

    def __init__(self, root: str | os.PathLike[str], cache_bytes: int = DEFAULT_CACHE_BYTES,
                 cache_entries: int = DEFAULT_CACHE_ENTRIES):
        self.root = Path(root).resolve()
        self.root.mkdir(parents=True, exist_ok=True)
        self.cache = ByteLRU(cache_bytes, cache_entries)

    @staticmethod
    def name_for(job_id: str) -> str:
        """File name of a job's results."""
        name = f"{job_id}.h5"
        if not _NAME.match(name):
            raise ResultsFileError(f"not a job id: {job_id!r}")
        return name

    def path(self, name: str) -> Path:
        """Absolute path of result file ``name``, refusing anything outside the directory."""
        if not isinstance(name, str) or not _NAME.match(name):
            raise ResultsFileError(f"not a result file name: {name!r}")
        p = (self.root / name).resolve()
        if p.parent != self.root or not p.is_relative_to(self.root):
            raise ResultsFileError(f"result file {name!r} is outside the results directory")
        return p

    def exists(self, name: str | None) -> bool:
        """Whether result file ``name`` exists."""
        if not name:
            return False
        try:
            return self.path(name).is_file()
        except ResultsFileError:
            return False

    def delete(self, name: str | None) -> bool:
        """Remove result file ``name`` if present; True if a file was removed."""
        if not name:
            return False
        try:
            p = self.path(name)
        except ResultsFileError:
            return False
        try:
            p.unlink()
            return True
        except FileNotFoundError:
            return False

    def copy(self, source: str, target_job_id: str) -> str:
        """Give job ``target_job_id`` its own copy (hard link if possible) of ``source``."""
        src = self.path(source)
        name = self.name_for(target_job_id)
        dst = self.path(name)
        tmp = dst.with_name(f".{name}.tmp")
        try:
            os.link(src, tmp)
        except OSError:
            shutil.copyfile(src, tmp)
        os.replace(tmp, dst)
        return name

    # -- reads (cached) ---------------------------------------------------------------------

    def token(self, name: str) -> FileToken:
        """Identity of the current version of file ``name`` (device, inode, size,
        modification time): it changes when the file is replaced.

        Raises
        ------
        ResultsFileError
            Not a result file name, or no such file.
        """
        return _token(self.path(name))

    def forget(self, name: str | None) -> int:
        """Drop the cached contents of file ``name`` (e.g. when its job is deleted); return
        the number of entries dropped.
        """
        if not name:
            return 0
        return self.cache.discard(lambda key: key[1] == name)

    def cache_stats(self) -> CacheStats:
        """Size, bounds and counters of the cache of file contents."""
        return self.cache.stats()

    def describe(self, name: str) -> dict[str, Any]:
        """Channel names and units, sample count, sample rate, duration and recorded points
        (``{"body", "name", "x", "y", "z"}`` in m, :func:`flexride.results.read_points`) of a
        file. The answer is a fresh copy (callers may change it).
        """
        p = self.path(name)
        tok = _token(p)
        d = self.cache.get_or_make(("describe", name, tok), lambda: self._describe(p))
        return copy.deepcopy(d)

    def _describe(self, p: Path) -> tuple[dict[str, Any], int]:
        with _open(p) as f:
            chans = {k: str(ds.attrs.get("unit", "")) for k, ds in f["channels"].items()}
            n = int(f["time"].shape[0])
            meta = json.loads(f.attrs.get("meta_json", "{}"))
            t = f["time"]
            t0 = float(t[0]) if n else 0.0
            t1 = float(t[-1]) if n else 0.0
            try:
                points = read_points(f)
            except (KeyError, ValueError, OSError) as exc:
                raise ResultsFileError(f"{p.name}: unreadable /points: {exc}") from None
        fs = _rate(meta, p, t0, t1, n)
        d = {"channels": chans, "n_samples": n, "sample_rate_hz": fs, "t_start_s": t0,
             "t_end_s": t1, "meta": meta, "points": points}
        return d, 512 + 96 * (len(chans) + len(points)) + len(json.dumps(meta))

    def read(self, name: str, channels: list[str], t_start: float | None = None,
             t_end: float | None = None) -> ChannelData:
        """Read ``channels`` (and the axes), optionally only t_start ≤ t ≤ t_end.

        Arrays come from the cache when this version of the file was read before; they are
        read-only views.

        Raises
        ------
        KeyError
            A channel is not in the file (message lists what is).
        ResultsFileError
            Unreadable file.
        """
        p = self.path(name)
        tok = _token(p)
        info = self.cache.get_or_make(("info", name, tok), lambda: _read_info(p))
        missing = [c for c in channels if c not in info.units]
        if missing:
            raise KeyError(
                f"no channel {', '.join(map(repr, missing))} in the results; channels are: "
                f"{', '.join(sorted(info.units))}"
            )
        t = info.time
        i0, i1 = 0, t.size
        if t_start is not None:
            i0 = int(np.searchsorted(t, t_start, side="left"))
        if t_end is not None:
            i1 = int(np.searchsorted(t, t_end, side="right"))
        i1 = max(i0, i1)
        data = {c: self._dataset(p, tok, f"channels/{c}", t.size, i0, i1) for c in channels}
        return ChannelData(time=t[i0:i1], distance=self._dataset(p, tok, "distance", t.size,
                                                                  i0, i1),
                           channels=data, units={c: info.units[c] for c in channels},
                           sample_rate=info.sample_rate, meta=copy.deepcopy(info.meta),
                           scenario=copy.deepcopy(info.scenario))

    def _dataset(self, p: Path, tok: FileToken, dataset: str, n: int, i0: int,
                 i1: int) -> np.ndarray:
        """Samples ``i0:i1`` of a 1-D dataset of ``n`` samples: from the cached whole dataset,
        or read from the file alone when the whole one is too large to cache.
        """
        key = ("dataset", p.name, tok, dataset)
        if n * 8 > self.cache.max_entry_bytes:
            with _open(p) as f:
                return _read_only(f[dataset][i0:i1])
        return self.cache.get_or_make(key, lambda: _read_dataset(p, dataset))[i0:i1]


def _token(p: Path) -> FileToken:
    try:
        st = p.stat()
    except FileNotFoundError:
        raise ResultsFileError(f"results file not found: {p.name}") from None
    return st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns


def _read_only(a: np.ndarray) -> np.ndarray:
    a.flags.writeable = False
    return a


def _read_info(p: Path) -> tuple[_FileInfo, int]:
    """Units, time axis, sample rate, run facts and scenario of a file, and their size."""
    with _open(p) as f:
        units = {c: str(ds.attrs.get("unit", "")) for c, ds in f["channels"].items()}
        t = _read_only(f["time"][()])
        meta_json = f.attrs.get("meta_json", "{}")
        scen_json = f.attrs.get("scenario_json", "{}")
    fs = _rate(json.loads(meta_json), p, float(t[0]) if t.size else 0.0,
               float(t[-1]) if t.size else 0.0, t.size)
    nbytes = t.nbytes + 4 * (len(meta_json) + len(scen_json)) + 96 * len(units)
    return _FileInfo(units=units, time=t, sample_rate=fs, meta=json.loads(meta_json),
                     scenario=json.loads(scen_json)), nbytes


def _read_dataset(p: Path, dataset: str) -> tuple[np.ndarray, int]:
    with _open(p) as f:
        a = _read_only(f[dataset][()])
    return a, a.nbytes


def _rate(meta: dict[str, Any], p: Path, t0: float, t1: float, n: int) -> float:
    if "output_rate" in meta:
        return float(meta["output_rate"])
    if n < 2 or t1 <= t0:
        raise ResultsFileError(f"{p.name}: cannot infer the sample rate")
    return (n - 1) / (t1 - t0)


class _open:
    """``h5py.File`` read-only, with errors turned into :class:`ResultsFileError`."""

    def __init__(self, path: Path):
        self.path = path

    def __enter__(self) -> h5py.File:
        if not self.path.is_file():
            raise ResultsFileError(f"results file not found: {self.path.name}")
        try:
            self.f = h5py.File(self.path, "r")
        except OSError as exc:
            raise ResultsFileError(f"cannot read results file {self.path.name}: {exc}") from None
        if "channels" not in self.f or "time" not in self.f:
            self.f.close()
            raise ResultsFileError(f"{self.path.name} is not a flexride results file")
        return self.f

    def __exit__(self, *exc: object) -> None:
        self.f.close()
