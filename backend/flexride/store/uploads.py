"""Uploaded data: measured track irregularities sent to the service as CSV, and wheel or rail
profiles in their file formats, stored by the SHA-256 of their content under
``<data_dir>/uploads`` and referenced by that id.

A request never names a server file: it sends the data, gets the id back and refers to it
(``{"kind": "measured", "upload": "<id>"}``, ``"wheel": {"upload": "<id>"}``). Names are
built from the hash only, so no request can reach another file. Files are written atomically
(temporary name, then rename); the same content uploaded twice is stored once.
"""

from __future__ import annotations

import hashlib
import os
import re
from dataclasses import dataclass
from pathlib import Path

from flexride.contact.profiles import Profile, read_profile_bytes
from flexride.contact.profiles.readers import profile_format
from flexride.contact.scenario_table import PROFILE_EXTENSIONS
from flexride.errors import ScenarioError, StorageError
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


@dataclass(frozen=True)
class ProfileUploadInfo:
    """What the service knows of an uploaded wheel or rail profile.

    Attributes
    ----------
    id : str
        SHA-256 of the content (64 hexadecimal digits).
    bytes : int
        Size of the content.
    format : str
        File format, by the extension it was uploaded as (``prw``, ``prr``, ``whl``, ``ban``,
        ``txt``, ``csv``).
    kind : str
        ``wheel`` or ``rail``, as it was read.
    points : int
        Points of the profile.
    y_mm, z_mm : list of float
        The profile in flexride's convention (mm; y toward the field side, z up), at most
        :data:`MAX_DRAWN_POINTS` points, for drawing.
    """

    id: str
    bytes: int
    format: str
    kind: str
    points: int
    y_mm: list[float]
    z_mm: list[float]


MAX_DRAWN_POINTS = 2000
"""Most points of a profile given back for drawing."""


def _profile_info(upload_id: str, size: int, fmt: str, profile: Profile) -> ProfileUploadInfo:
    step = max(1, -(-profile.y.size // MAX_DRAWN_POINTS))
    idx = list(range(0, profile.y.size, step))
    if idx[-1] != profile.y.size - 1:
        idx.append(profile.y.size - 1)
    return ProfileUploadInfo(id=upload_id, bytes=size, format=fmt, kind=profile.kind,
                             points=int(profile.y.size),
                             y_mm=[round(float(profile.y[i]) * 1e3, 6) for i in idx],
                             z_mm=[round(float(profile.z[i]) * 1e3, 6) for i in idx])


def profile_kind(fmt: str, kind: str | None) -> str:
    """The kind of a profile upload of format ``fmt``: the one its format implies, else
    ``kind`` (:class:`ScenarioError` located at ``kind`` when it is missing or contradicts
    the format).
    """
    implied = profile_format(f"x.{fmt}")[1]
    if implied is not None and kind not in (None, implied):
        raise ScenarioError.at(("kind",), f"a .{fmt} file holds a {implied} profile, "
                               f"not a {kind} profile")
    chosen = implied or kind
    if chosen is None:
        raise ScenarioError.at(("kind",), f"say whether the .{fmt} profile is a wheel or a rail "
                               "(kind=wheel or kind=rail)")
    return chosen


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

    def put_profile(self, data: bytes, fmt: str, kind: str | None = None) -> ProfileUploadInfo:
        """Check ``data`` as a wheel or rail profile file of format ``fmt`` (an extension of
        :data:`~flexride.contact.scenario_table.PROFILE_EXTENSIONS` without the dot) and store
        it as ``<id>.<fmt>``.

        Raises
        ------
        flexride.errors.ScenarioError
            An unknown format, a kind that is missing or contradicts the format (located at
            ``kind``), or a profile the readers refuse (message names the line).
        StorageError
            The store cannot be written (the API answers 503).
        """
        if f".{fmt}" not in PROFILE_EXTENSIONS:
            raise ScenarioError.at(("format",), f"unknown profile format {fmt!r}")
        chosen = profile_kind(fmt, kind)
        profile = read_profile_bytes(data, f"upload.{fmt}", chosen)  # type: ignore[arg-type]
        upload_id = hashlib.sha256(data).hexdigest()
        dest = self.root / f"{upload_id}.{fmt}"
        if not dest.is_file():
            self._write(dest, data)
        return _profile_info(upload_id, len(data), fmt, profile)

    def profile_info(self, upload_id: str, kind: str | None = None) -> ProfileUploadInfo:
        """Facts of a stored profile read as ``kind`` (the format's kind when it implies one;
        ``KeyError`` when there is no such upload, :class:`ScenarioError` as for
        :meth:`put_profile`).
        """
        self.path(upload_id)  # KeyError for a string that is not an id
        for ext in PROFILE_EXTENSIONS:
            f = self.root / f"{upload_id}{ext}"
            if f.is_file():
                fmt = ext[1:]
                data = f.read_bytes()
                profile = read_profile_bytes(data, f"upload{ext}", profile_kind(fmt, kind))  # type: ignore[arg-type]
                return _profile_info(upload_id, len(data), fmt, profile)
        raise KeyError(f"no profile upload {upload_id}")

    def read(self, upload_id: str) -> bytes:
        """The content of a stored upload (``KeyError`` when there is none)."""
        try:
            return self.path(upload_id).read_bytes()
        except FileNotFoundError:
            raise KeyError(f"no upload {upload_id}") from None
