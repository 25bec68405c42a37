"""Results of a run: time and distance axes, named channels with units, and their HDF5 file.

Channel names follow ``<body>.<point>.<quantity>.<direction>`` (DESIGN §4), for example
``carbody.PR.acc.z`` (car-body vertical acceleration at the roof point, m/s²) or
``wheelset1.left.force.z`` (wheel-rail normal force of the left wheel of wheelset 1, N).

The HDF5 layout is one file per run::

    /time                 float64 [n]   s
    /distance             float64 [n]   m
    /channels/<name>      float64 [n]   attribute ``unit``
    root attributes: ``format`` = "flexride-results", ``format_version``,
                     ``flexride_version``, ``scenario_json``, ``meta_json``

Files are written atomically: to a temporary name in the target directory, then renamed.
"""

from __future__ import annotations

import json
import os
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from flexride.errors import ResultsFileError

FORMAT_NAME = "flexride-results"
FORMAT_VERSION = 1


@dataclass
class Results:
    """Recorded output of one simulation.

    Attributes
    ----------
    time : numpy.ndarray
        Output time axis in s, uniformly sampled at :attr:`sample_rate`.
    distance : numpy.ndarray
        Distance of the vehicle centre along the line in m, same length as ``time``.
    channels : dict of str to numpy.ndarray
        Channel data, each the same length as ``time``.
    units : dict of str to str
        SI unit of every channel (``"m/s^2"``, ``"N"``, ``"m"``, ...).
    scenario : dict
        The full scenario that produced the run (JSON-compatible).
    meta : dict
        Run facts: ``speed_mps``, ``dt`` (s), ``output_rate`` (Hz), wall times, etc.
    """

    time: np.ndarray
    distance: np.ndarray
    channels: dict[str, np.ndarray]
    units: dict[str, str]
    scenario: dict[str, Any] = field(default_factory=dict)
    meta: dict[str, Any] = field(default_factory=dict)

    @property
    def sample_rate(self) -> float:
        """Output sample rate in Hz."""
        if "output_rate" in self.meta:
            return float(self.meta["output_rate"])
        if self.time.size < 2:
            raise ResultsFileError("cannot infer the sample rate from fewer than two samples")
        return float(1.0 / (self.time[1] - self.time[0]))

    def channel(self, name: str) -> np.ndarray:
        """Return the data of channel ``name``; raise :class:`KeyError` naming close matches."""
        try:
            return self.channels[name]
        except KeyError:
            raise KeyError(
                f"no channel {name!r}; channels are: {', '.join(sorted(self.channels))}"
            ) from None

    def names(self, quantity: str | None = None, body: str | None = None) -> list[str]:
        """Channel names, optionally filtered by quantity (``acc``, ``force``...) and body."""
        out = []
        for name in self.channels:
            parts = name.split(".")
            if quantity is not None and (len(parts) < 3 or parts[2] != quantity):
                continue
            if body is not None and parts[0] != body:
                continue
            out.append(name)
        return out

    def write_hdf5(self, path: str | os.PathLike[str]) -> Path:
        """Write the results atomically to ``path`` (temporary file, then rename).

        Parameters
        ----------
        path : path-like
            Destination ``.h5`` file; parent directories are created.

        Returns
        -------
        pathlib.Path
            The written path.
        """
        from flexride import __version__

        dest = Path(path)
        dest.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp_name = tempfile.mkstemp(prefix=f".{dest.name}.", suffix=".tmp", dir=dest.parent)
        os.close(fd)
        try:
            with h5py.File(tmp_name, "w") as f:
                f.attrs["format"] = FORMAT_NAME
                f.attrs["format_version"] = FORMAT_VERSION
                f.attrs["flexride_version"] = __version__
                f.attrs["scenario_json"] = json.dumps(self.scenario)
                f.attrs["meta_json"] = json.dumps(self.meta)
                f.create_dataset("time", data=self.time).attrs["unit"] = "s"
                f.create_dataset("distance", data=self.distance).attrs["unit"] = "m"
                grp = f.create_group("channels")
                for name, data in self.channels.items():
                    ds = grp.create_dataset(
                        name, data=data, compression="gzip", compression_opts=4, shuffle=True
                    )
                    ds.attrs["unit"] = self.units.get(name, "")
            os.replace(tmp_name, dest)
        except BaseException:
            Path(tmp_name).unlink(missing_ok=True)
            raise
        return dest

    @classmethod
    def read_hdf5(cls, path: str | os.PathLike[str]) -> Results:
        """Read a results file written by :meth:`write_hdf5`.

        Raises
        ------
        ResultsFileError
            If the file is missing, unreadable or not a flexride results file.
        """
        p = Path(path)
        if not p.is_file():
            raise ResultsFileError(f"results file not found: {p}")
        try:
            with h5py.File(p, "r") as f:
                if f.attrs.get("format") != FORMAT_NAME:
                    raise ResultsFileError(f"{p} is not a flexride results file")
                channels = {}
                units = {}
                for name, ds in f["channels"].items():
                    channels[name] = ds[()]
                    units[name] = str(ds.attrs.get("unit", ""))
                return cls(
                    time=f["time"][()],
                    distance=f["distance"][()],
                    channels=channels,
                    units=units,
                    scenario=json.loads(f.attrs["scenario_json"]),
                    meta=json.loads(f.attrs["meta_json"]),
                )
        except ResultsFileError:
            raise
        except (OSError, KeyError, ValueError) as exc:
            raise ResultsFileError(f"cannot read results file {p}: {exc}") from exc
