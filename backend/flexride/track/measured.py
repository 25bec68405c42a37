"""Measured track irregularities: parsing, checking and where the data may come from.

A :class:`~flexride.scenario.excitation.MeasuredIrregularity` gives its data in one of three
ways: ``path`` (a CSV file on the machine that runs the simulation: CLI and library),
``upload`` (the SHA-256 content hash of a CSV stored by the service, see
:class:`flexride.store.uploads.UploadStore`) or ``columns`` + ``rows`` inline. All three end in
one :class:`MeasuredTable` after the same checks. Error messages name the source, the line or
row and the column, never the text of a cell or the directory of a file.

Where data may be read from is decided by the caller through :class:`MeasuredSources`: the
library and CLI read paths; the service reads only its content-addressed uploads.
"""

from __future__ import annotations

import csv
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from flexride.errors import ErrorItem, ScenarioError
from flexride.scenario.excitation import MeasuredIrregularity

__all__ = [
    "COMPONENT_COLUMNS",
    "MEASURED_COLUMNS",
    "MIN_SPACING_M",
    "RAIL_COLUMNS",
    "MeasuredSources",
    "MeasuredTable",
    "load_measured",
    "parse_measured_csv",
    "table_from_rows",
]

COMPONENT_COLUMNS = ("vertical", "alignment", "cross_level", "gauge")
"""Columns of irregularity components (m)."""
RAIL_COLUMNS = ("z_left", "z_right", "y_left", "y_right")
"""Columns of per-rail irregularities (m)."""
MEASURED_COLUMNS = COMPONENT_COLUMNS + RAIL_COLUMNS
"""Every column that carries irregularity data."""
MIN_SPACING_M = 1.0e-3
"""Smallest accepted median spacing of measured data (m): the profile grid follows the data,
and a finer grid would only resolve wavelengths the contact patch filters out."""

_UPLOAD_ID = re.compile(r"^[0-9a-f]{64}$")


@dataclass(frozen=True)
class MeasuredTable:
    """Checked measured data.

    Attributes
    ----------
    distance : numpy.ndarray
        Distance along the line (m), strictly increasing.
    columns : dict of str to numpy.ndarray
        Irregularity columns present (names of :data:`MEASURED_COLUMNS`), in m.
    """

    distance: np.ndarray
    columns: dict[str, np.ndarray]

    @property
    def median_spacing(self) -> float:
        """Median distance between measurement points (m)."""
        return float(np.median(np.diff(self.distance)))


@dataclass(frozen=True)
class MeasuredSources:
    """Where measured irregularities may be read from.

    Attributes
    ----------
    upload_dir : pathlib.Path or None
        Directory of content-addressed uploads (``<sha256>.csv``), the service's data.
    allow_paths : bool
        Whether ``path`` (a file named by the scenario) may be read: True for the library and
        CLI, False in the service, where a request must never name a server file.
    """

    upload_dir: Path | None = None
    allow_paths: bool = True


LIBRARY = MeasuredSources()
"""The library's and CLI's sources: files named by path."""


def _table(header: list[str], header_label: str, rows: Sequence[tuple[str, Sequence[object]]],
           source: str, distance_column: str) -> MeasuredTable:
    """Check a header and labelled rows of cells and convert them to a table."""
    where = f"{source}, {header_label}"
    duplicates = sorted({h for h in header if header.count(h) > 1 and h in MEASURED_COLUMNS})
    if duplicates or len(set(header)) != len(header):
        raise ScenarioError(f"{where}: duplicate column name(s)"
                            + (f" {', '.join(duplicates)}" if duplicates else ""))
    if distance_column not in header:
        raise ScenarioError(f"{where}: missing distance column {distance_column!r} (none of "
                            f"the {len(header)} column names matches)")
    wanted = [h for h in header if h in MEASURED_COLUMNS]
    if not wanted:
        raise ScenarioError(f"{where}: no irregularity column; expected one or more of "
                            f"{', '.join(MEASURED_COLUMNS)}")
    if len(rows) < 2:
        raise ScenarioError(f"{source}: need at least two data rows, found {len(rows)}")
    use = [distance_column, *wanted]
    index = [header.index(h) for h in use]
    data = np.empty((len(rows), len(use)))
    for r, (label, cells) in enumerate(rows):
        if len(cells) != len(header):
            raise ScenarioError(f"{source}, {label}: expected {len(header)} cells (as in the "
                                f"header), found {len(cells)}")
        for j, (col, ci) in enumerate(zip(use, index, strict=True)):
            data[r, j] = _number(cells[ci], f"{source}, {label}, column {col!r}")
    dist = data[:, 0]
    bad = np.flatnonzero(np.diff(dist) <= 0.0)
    if bad.size:
        i = int(bad[0])
        raise ScenarioError(
            f"{source}, {rows[i + 1][0]}, column {distance_column!r}: distance must be strictly "
            f"increasing, but {dist[i + 1]:g} m follows {dist[i]:g} m ({rows[i][0]})")
    table = MeasuredTable(dist, {h: data[:, j + 1] for j, h in enumerate(wanted)})
    if not table.median_spacing >= MIN_SPACING_M:
        raise ScenarioError(f"{source}: median spacing {table.median_spacing:g} m of the "
                            f"measurement points is below {MIN_SPACING_M:g} m")
    return table


def _number(cell: object, where: str) -> float:
    """A finite float from a CSV cell or a JSON value (message without the cell's text)."""
    if isinstance(cell, bool):
        raise ScenarioError(f"{where}: not a number")
    try:
        value = float(cell.strip() if isinstance(cell, str) else cell)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        empty = isinstance(cell, str) and not cell.strip()
        raise ScenarioError(f"{where}: {'empty cell' if empty else 'not a number'}") from None
    if not math.isfinite(value):
        raise ScenarioError(f"{where}: not a finite number")
    return value


def parse_measured_csv(data: bytes, source: str, distance_column: str = "distance_m"
                       ) -> MeasuredTable:
    """Parse and check measured irregularities in CSV form.

    Parameters
    ----------
    data : bytes
        The file's content: UTF-8 text (a BOM is allowed), comma separated, one header row,
        then one row per measurement point; blank lines and lines starting with ``#`` are
        skipped. Format of the columns: :class:`~flexride.scenario.excitation.MeasuredIrregularity`.
    source : str
        How messages name the data (a file name or ``upload <id>``; never a directory).
    distance_column : str
        Name of the distance column (m).

    Returns
    -------
    MeasuredTable

    Raises
    ------
    ScenarioError
        Not UTF-8, empty, no distance or irregularity column, fewer than two rows, a row with
        the wrong number of cells, a cell that is not a finite number, distance not strictly
        increasing, spacing below :data:`MIN_SPACING_M`; the message names line and column.
    """
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ScenarioError(f"{source}: not UTF-8 text (invalid byte at offset {exc.start}); "
                            "save the file as UTF-8 CSV") from None
    lines = [(i, line) for i, line in enumerate(text.splitlines(), start=1)
             if line.strip() and not line.lstrip().startswith("#")]
    if not lines:
        raise ScenarioError(f"{source}: file is empty (expected a header row and data rows)")
    header = [h.strip() for h in next(csv.reader([lines[0][1]]))]
    rows = [(f"line {i}", next(csv.reader([line]))) for i, line in lines[1:]]
    return _table(header, f"line {lines[0][0]}", rows, source, distance_column)


def table_from_rows(columns: Sequence[str], rows: Sequence[Sequence[float]],
                    distance_column: str = "distance_m", source: str = "rows") -> MeasuredTable:
    """Check measured irregularities given inline as column names and rows of values (m).

    Parameters
    ----------
    columns : sequence of str
        Column names, as a CSV header.
    rows : sequence of sequence of float
        One row per measurement point, one value per column.
    distance_column : str
        Name of the distance column (m).
    source : str
        How messages name the data.

    Returns
    -------
    MeasuredTable
    """
    labelled = [(f"row {i}", list(r)) for i, r in enumerate(rows)]
    return _table([c.strip() for c in columns], "columns", labelled, source, distance_column)


def _upload_file(upload: str, sources: MeasuredSources) -> Path:
    if sources.upload_dir is None:
        raise ScenarioError("uploaded measured irregularities are only available in the "
                            "service (no upload store here); give 'path' or 'rows'")
    if not _UPLOAD_ID.match(upload):
        raise ScenarioError("not an upload id (64 hexadecimal digits)")
    return sources.upload_dir / f"{upload}.csv"


def load_measured(exc: MeasuredIrregularity, sources: MeasuredSources = LIBRARY
                  ) -> MeasuredTable:
    """The checked data of a measured-irregularity excitation from its source.

    Parameters
    ----------
    exc : MeasuredIrregularity
        The excitation (exactly one of ``path``, ``upload``, ``rows`` set).
    sources : MeasuredSources
        Which sources may be read.

    Raises
    ------
    ScenarioError
        Located at the excitation's source field (``path``, ``upload`` or ``rows``): a source
        that is not allowed here, a missing file or upload, or data that fail the checks.
    """
    field = "path" if exc.path is not None else "upload" if exc.upload is not None else "rows"
    try:
        if exc.rows is not None:
            return table_from_rows(exc.columns or [], exc.rows, exc.distance_column)
        if exc.upload is not None:
            name = f"upload {exc.upload[:12]}"
            return parse_measured_csv(_read(_upload_file(exc.upload, sources), name), name,
                                      exc.distance_column)
        if not sources.allow_paths:
            raise ScenarioError("file paths are not accepted here; upload the CSV "
                                "(POST /api/v1/irregularities) and give its id as 'upload', "
                                "or give the data inline as 'columns' and 'rows'")
        path = Path(str(exc.path))
        return parse_measured_csv(_read(path, str(path)), path.name, exc.distance_column)
    except ScenarioError as err:
        raise ScenarioError(str(err), [ErrorItem((field,), str(err))]) from None


def _read(path: Path, name: str) -> bytes:
    """The bytes of a measured-data file (a missing file named as ``name``)."""
    try:
        return path.read_bytes()
    except FileNotFoundError:
        raise ScenarioError(f"{name}: no such file") from None
    except OSError as exc:
        raise ScenarioError(f"{name}: cannot read ({exc.strerror or type(exc).__name__})"
                            ) from None
