"""Measured modal data (a modal test of the car body) as calibration targets.

File format (CSV, UTF-8, comma-separated; documented in docs/fem.md)::

    # lines starting with '#' are comments; blank lines are skipped
    x_m,y_m,z_m,direction,mode_6.35Hz,mode_10.8Hz:torsion
    6.3,1.4,2.2,y,0.81,-0.42
    ...

* ``x_m``, ``y_m``, ``z_m``: the sensor position (m) in the car-body frame of the FE model: x
  from the body centre, forward; y to the left; z above the top of the rail.
* ``direction``: ``x``, ``y`` or ``z``, the measured translation at that position (a triaxial
  sensor is three rows).
* one column per measured mode, headed ``mode_<frequency>Hz`` (Hz), optionally followed by
  ``:<type>`` from :data:`flexride.fem.mode_types.MODE_TYPES`; its values are the mode shape
  (any units and scale: only the shape counts, through the MAC).

The model's shapes are taken at the FE node nearest to each sensor (no interpolation: the
sensors of a modal test sit on the structure, within about an element of a node), and a sensor
farther from every node than a given distance is an error.
"""

from __future__ import annotations

import csv
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from flexride.errors import FEModelError
from flexride.fem.targets import ModeTarget

#: The first columns of the header, in this order.
SENSOR_COLUMNS = ("x_m", "y_m", "z_m", "direction")
#: Measured directions and their DOF offset in a node's six DOFs.
DIRECTIONS = {"x": 0, "y": 1, "z": 2}
_MODE_HEADER = re.compile(r"^mode_(?P<f>[^:]*?)\s*hz\s*(?::(?P<type>.*))?$", re.IGNORECASE)


@dataclass(frozen=True, eq=False)
class Sensors:
    """Sensor DOFs of a modal test.

    Attributes
    ----------
    positions : numpy.ndarray
        (n, 3) sensor positions (m), car-body frame of the FE model.
    directions : numpy.ndarray
        (n,) measured direction of each row: 0 = x, 1 = y, 2 = z.
    lines : tuple of int
        Line of each row in its file (for messages).
    """

    positions: np.ndarray
    directions: np.ndarray
    lines: tuple[int, ...]

    @property
    def n_dofs(self) -> int:
        """Number of measured DOFs."""
        return int(self.directions.size)


@dataclass(frozen=True, eq=False)
class ModalTest:
    """A modal test read from a file.

    Attributes
    ----------
    sensors : Sensors
        The measured DOFs.
    targets : list of ModeTarget
        One per measured mode: frequency (Hz), type if the header gives one, the shape at the
        sensors, the column header as label.
    source : str
        Where it came from (file name).
    """

    sensors: Sensors
    targets: list[ModeTarget]
    source: str


@dataclass(frozen=True, eq=False)
class SensorNodes:
    """The model DOFs that stand for the sensors.

    Attributes
    ----------
    nodes : numpy.ndarray
        (n,) node nearest to each sensor.
    dofs : numpy.ndarray
        (n,) model DOF of each sensor (six per node: x, y, z, then rotations).
    distances : numpy.ndarray
        (n,) distance (m) from each sensor to its node.
    """

    nodes: np.ndarray
    dofs: np.ndarray
    distances: np.ndarray


def read_modal_test(path: str | Path) -> ModalTest:
    """Read and check a modal-test file (module docstring: format).

    Raises
    ------
    FEModelError
        If the file cannot be read or breaks the format; the message names the file, the line
        and the column.
    """
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise FEModelError(f"cannot read modal-test file {p}: {exc}") from None
    return parse_modal_test(text, source=p.name)


def parse_modal_test(text: str, source: str = "modal test") -> ModalTest:
    """Parse and check the text of a modal-test file (see :func:`read_modal_test`)."""
    rows = _csv_rows(text)
    if not rows:
        raise FEModelError(f"{source}: no header line (expected {','.join(SENSOR_COLUMNS)},"
                           " then one mode_<f>Hz column per mode)")
    (head_line, header), body = rows[0], rows[1:]
    modes = _mode_columns(header, head_line, source)
    values = np.array([_data_row(row, header, n, source) for n, row in body],
                      dtype=float).reshape(len(body), len(header))
    sensors = Sensors(values[:, :3], values[:, 3].astype(np.int64), tuple(n for n, _ in body))
    _check_sensors(sensors, len(modes), source)
    targets = [_mode_target(values[:, 4 + k], f, kind, header[4 + k], source)
               for k, (f, kind) in enumerate(modes)]
    return ModalTest(sensors=sensors, targets=targets, source=source)


def _csv_rows(text: str) -> list[tuple[int, list[str]]]:
    """(line number, stripped fields) of the lines that are neither blank nor comments."""
    out = []
    for n, line in enumerate(text.splitlines(), start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        out.append((n, [field.strip() for field in next(csv.reader([line]))]))
    return out


def _mode_columns(header: list[str], line: int, source: str) -> list[tuple[float, str | None]]:
    """(frequency in Hz, type or None) of each mode column of the header."""
    if [h.lower() for h in header[:4]] != list(SENSOR_COLUMNS):
        raise FEModelError(
            f"{source} line {line}: the header must start with {','.join(SENSOR_COLUMNS)}, "
            f"got {','.join(header[:4])!r}")
    if len(header) < 5:
        raise FEModelError(f"{source} line {line}: no mode columns (mode_<frequency>Hz)")
    out = []
    for col, name in enumerate(header[4:], start=5):
        m = _MODE_HEADER.match(name)
        f = _number(m.group("f")) if m else None
        if m is None or f is None or not f > 0:
            raise FEModelError(
                f"{source} line {line}, column {col} {name!r}: a mode column is headed "
                "mode_<frequency>Hz with a positive frequency, optionally :<type> "
                "(e.g. mode_6.11Hz or mode_8.84Hz:first vertical bending)")
        kind = m.group("type")
        out.append((f, kind.strip() if kind is not None else None))
    return out


def _number(text: str) -> float | None:
    """``text`` as a finite float, None if it is not one."""
    try:
        v = float(text)
    except ValueError:
        return None
    return v if np.isfinite(v) else None


def _data_row(row: list[str], header: list[str], line: int, source: str) -> list[float]:
    """One sensor row as numbers (direction as 0, 1, 2)."""
    if len(row) != len(header):
        raise FEModelError(
            f"{source} line {line}: {len(row)} fields, the header has {len(header)}")
    out = []
    for col, (name, field) in enumerate(zip(header, row, strict=True), start=1):
        if col == 4:
            d = DIRECTIONS.get(field.lower())
            if d is None:
                raise FEModelError(f"{source} line {line}, column {col} {name!r}: "
                                   f"direction must be x, y or z, got {field!r}")
            out.append(float(d))
            continue
        v = _number(field)
        if v is None:
            raise FEModelError(f"{source} line {line}, column {col} {name!r}: "
                               f"{field!r} is not a finite number")
        out.append(v)
    return out


def _check_sensors(sensors: Sensors, n_modes: int, source: str) -> None:
    """Enough sensor DOFs to tell the modes apart, and no DOF measured twice."""
    if sensors.n_dofs < max(n_modes, 2):
        raise FEModelError(
            f"{source}: {sensors.n_dofs} sensor rows for {n_modes} modes: the MAC cannot tell "
            "mode shapes apart with fewer measured DOFs than modes (and at least two)")
    seen: dict[tuple, int] = {}
    for pos, d, line in zip(sensors.positions, sensors.directions, sensors.lines, strict=True):
        key = (*np.round(pos, 3), int(d))
        if key in seen:
            raise FEModelError(f"{source} line {line}: the same position and direction as "
                               f"line {seen[key]}")
        seen[key] = line


def _mode_target(shape: np.ndarray, f: float, kind: str | None, name: str,
                 source: str) -> ModeTarget:
    """The target of one mode column (its shape checked)."""
    if not np.any(shape):
        raise FEModelError(f"{source}, column {name!r}: every value is zero (no shape)")
    try:
        return ModeTarget(f, kind, shape=shape, label=name)
    except FEModelError as exc:
        raise FEModelError(f"{source}, column {name!r}: {exc}") from None


def sensor_nodes(nodes: np.ndarray, sensors: Sensors, max_distance: float) -> SensorNodes:
    """The FE node nearest to each sensor and the DOF of its measured direction.

    Parameters
    ----------
    nodes : numpy.ndarray
        (n_nodes, 3) node coordinates (m).
    sensors : Sensors
        The sensors (same frame as the nodes).
    max_distance : float
        Largest accepted distance (m) from a sensor to its node.

    Raises
    ------
    FEModelError
        If a sensor is farther than ``max_distance`` from every node (the message names its
        line and position).
    """
    d2 = np.sum((sensors.positions[:, None, :] - nodes[None, :, :]) ** 2, axis=2)
    near = np.argmin(d2, axis=1)
    dist = np.sqrt(d2[np.arange(near.size), near])
    far = np.flatnonzero(dist > max_distance)
    if far.size:
        k = int(far[0])
        raise FEModelError(
            f"sensor on line {sensors.lines[k]} at {tuple(map(float, sensors.positions[k]))} m "
            f"is {dist[k]:.2f} m from the nearest node (more than {max_distance:g} m): check "
            "its coordinates (car-body frame: x from the body centre forward, y to the left, "
            f"z above the top of the rail); {far.size} sensor(s) are that far")
    return SensorNodes(nodes=near, dofs=6 * near + sensors.directions, distances=dist)
