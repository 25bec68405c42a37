"""Uploaded data: measured track irregularities sent to the service as CSV, stored by the
SHA-256 of their content under ``<data_dir>/uploads`` and referenced by that id.

A request never names a server file: it sends the data, gets the id back and refers to it
(``{"kind": "measured", "upload": "<id>"}``). Names are built from the hash only, so no
request can reach another file. Files are written atomically (temporary name, then rename);
the same content uploaded twice is stored once.
"""

from __future__ import annotations

import hashlib
import os
import re
from dataclasses import dataclass
from pathlib import Path

from flexride.errors import StorageError
from flexride.fileio import write_bytes_atomic
from flexride.store.probe import os_fault
from flexride.track.measured import MeasuredSources, MeasuredTable, parse_measured_csv

_ID = re.compile(r"^[0-9a-f]{64}$")


@dataclass(frozen=True)
class UploadInfo:
    """What the service knows of an upload.

    Attributes
    ----------
    id : str
        SHA-256 of the content (64 hexadecimal digits).
    bytes : int
        Size of the content.
    rows : int
        Measurement points.
    columns : list of str
        Irregularity columns found (besides the distance column).
    distance_start_m, distance_end_m : float
        Measured stretch (m).
    median_spacing_m : float
        Median distance between measurement points (m).
    """

    id: str
    bytes: int
    rows: int
    columns: list[str]
    distance_start_m: float
    distance_end_m: float
    median_spacing_m: float


def _info(upload_id: str, size: int, table: MeasuredTable) -> UploadInfo:
    return UploadInfo(id=upload_id, bytes=size, rows=int(table.distance.size),
                      columns=list(table.columns), distance_start_m=float(table.distance[0]),
                      distance_end_m=float(table.distance[-1]),
                      median_spacing_m=table.median_spacing)


class UploadStore:
    """Content-addressed store of uploaded measured irregularities.

    Parameters
    ----------
    root : path-like
        ``<data_dir>/uploads``; created when the first upload is stored.
    """

    def __init__(self, root: str | os.PathLike[str]):
        self.root = Path(root).resolve()

    @property
    def sources(self) -> MeasuredSources:
        """Measured-data sources of the service: these uploads, never a path."""
        return MeasuredSources(upload_dir=self.root, allow_paths=False)

    def path(self, upload_id: str) -> Path:
        """File of upload ``upload_id`` (``KeyError`` for a string that is not an id)."""
        if not isinstance(upload_id, str) or not _ID.match(upload_id):
            raise KeyError("not an upload id (64 hexadecimal digits)")
        return self.root / f"{upload_id}.csv"

    def put(self, data: bytes, distance_column: str = "distance_m") -> UploadInfo:
        """Check ``data`` as measured irregularities (CSV) and store it.

        Raises
        ------
        flexride.errors.ScenarioError
            The data fail the checks of :func:`~flexride.track.measured.parse_measured_csv`
            (message names line and column, never a cell's text).
        StorageError
            The store cannot be written (the API answers 503).
        """
        upload_id = hashlib.sha256(data).hexdigest()
        table = parse_measured_csv(data, "upload", distance_column)
        dest = self.path(upload_id)
        if not dest.is_file():
            self._write(dest, data)
        return _info(upload_id, len(data), table)

    def _write(self, dest: Path, data: bytes) -> None:
        """Write ``data`` to ``dest`` atomically (:class:`StorageError` when it cannot)."""
        try:
            write_bytes_atomic(dest, data, fsync=True)
        except OSError as exc:
            raise StorageError(f"upload store not writable: {os_fault(exc)}") from None

    def info(self, upload_id: str, distance_column: str = "distance_m") -> UploadInfo:
        """Facts of a stored upload (``KeyError`` when there is none)."""
        path = self.path(upload_id)
        try:
            data = path.read_bytes()
        except FileNotFoundError:
            raise KeyError(f"no upload {upload_id}") from None
        table = parse_measured_csv(data, f"upload {upload_id[:12]}", distance_column)
        return _info(upload_id, len(data), table)

    def read(self, upload_id: str) -> bytes:
        """The content of a stored upload (``KeyError`` when there is none)."""
        try:
            return self.path(upload_id).read_bytes()
        except FileNotFoundError:
            raise KeyError(f"no upload {upload_id}") from None
