"""Result files: one HDF5 file per job under ``<data_dir>/results``, served read-only.

Names are built from job ids only (never from request text) and every path is resolved and
checked to lie inside the results directory, so no request can reach another file. Channel
reads take only the datasets asked for.
"""

from __future__ import annotations

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

_NAME = re.compile(r"^[0-9a-f]{32}\.h5$")


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


class ResultFiles:
    """The results directory of the service.

    Parameters
    ----------
    root : path-like
        ``<data_dir>/results``; created if missing.
    """

    def __init__(self, root: str | os.PathLike[str]):
        self.root = Path(root).resolve()
        self.root.mkdir(parents=True, exist_ok=True)

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

    def describe(self, name: str) -> dict[str, Any]:
        """Channel names and units, sample count, sample rate, duration and recorded points
        (``{"body", "name", "x", "y", "z"}`` in m, :func:`flexride.results.read_points`) of a
        file."""
        p = self.path(name)
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
        return {"channels": chans, "n_samples": n, "sample_rate_hz": fs, "t_start_s": t0,
                "t_end_s": t1, "meta": meta, "points": points}

    def read(self, name: str, channels: list[str], t_start: float | None = None,
             t_end: float | None = None) -> ChannelData:
        """Read ``channels`` (and the axes), optionally only t_start ≤ t ≤ t_end.

        Raises
        ------
        KeyError
            A channel is not in the file (message lists what is).
        ResultsFileError
            Unreadable file.
        """
        p = self.path(name)
        with _open(p) as f:
            grp = f["channels"]
            missing = [c for c in channels if c not in grp]
            if missing:
                raise KeyError(
                    f"no channel {', '.join(map(repr, missing))} in the results; channels are: "
                    f"{', '.join(sorted(grp))}"
                )
            t = f["time"][()]
            i0, i1 = 0, t.size
            if t_start is not None:
                i0 = int(np.searchsorted(t, t_start, side="left"))
            if t_end is not None:
                i1 = int(np.searchsorted(t, t_end, side="right"))
            i1 = max(i0, i1)
            data = {c: grp[c][i0:i1] for c in channels}
            units = {c: str(grp[c].attrs.get("unit", "")) for c in channels}
            dist = f["distance"][i0:i1]
            meta = json.loads(f.attrs.get("meta_json", "{}"))
            scen = json.loads(f.attrs.get("scenario_json", "{}"))
        fs = _rate(meta, p, float(t[0]) if t.size else 0.0, float(t[-1]) if t.size else 0.0,
                   t.size)
        return ChannelData(time=t[i0:i1], distance=dist, channels=data, units=units,
                           sample_rate=fs, meta=meta, scenario=scen)


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
