"""Calibration targets: a frequency, optionally a mode type and a reference shape.

The command-line spelling is a comma-separated list of ``frequency[:type]``, e.g.
``5.03:torsion,6.11:rhombic,8.84:first vertical bending`` (types from
:data:`flexride.fem.mode_types.MODE_TYPES`); a target without a type (``7.40``) is paired with
the model mode nearest in frequency among those no other target takes.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from flexride.errors import FEModelError
from flexride.fem.mode_types import ModeType, parse_mode_type


@dataclass(frozen=True, eq=False)
class ModeTarget:
    """One target of a calibration.

    Attributes
    ----------
    frequency_hz : float
        Target natural frequency (Hz), positive.
    mode_type : str or None
        Wanted mode type (a name of :data:`~flexride.fem.mode_types.MODE_TYPES`, optionally
        with an order: ``first vertical bending``); stored in its canonical spelling. None:
        any type.
    shape : numpy.ndarray or None
        Reference shape at the sensor DOFs of the calibration (e.g. a measured mode shape;
        any scale and sign); None: no shape.
    label : str
        Name used in reports (e.g. the column of a modal-test file); empty for none.

    Raises
    ------
    FEModelError
        If the frequency is not a positive finite number, the type is unknown or the shape is
        not a finite non-zero vector.
    """

    frequency_hz: float
    mode_type: str | None = None
    shape: np.ndarray | None = None
    label: str = ""

    def __post_init__(self) -> None:
        """Check the values; store the type in its canonical spelling."""
        f = float(self.frequency_hz)
        if not (np.isfinite(f) and f > 0):
            raise FEModelError(f"target frequency must be a positive number of Hz, got {f}")
        object.__setattr__(self, "frequency_hz", f)
        if self.mode_type is not None:
            object.__setattr__(self, "mode_type", str(parse_mode_type(self.mode_type)))
        if self.shape is not None:
            object.__setattr__(self, "shape", _checked_shape(self.shape, f))

    @property
    def wanted(self) -> ModeType | None:
        """The wanted type, parsed (None: any)."""
        return None if self.mode_type is None else parse_mode_type(self.mode_type)

    def describe(self) -> str:
        """Short text: ``6.110 Hz rhombic`` (or with the label)."""
        kind = self.mode_type or "any type"
        return f"{self.label + ' ' if self.label else ''}{self.frequency_hz:.3f} Hz {kind}"

    def to_dict(self) -> dict:
        """JSON-able dict (the shape's values as a list)."""
        return {
            "frequency_hz": self.frequency_hz,
            "mode_type": self.mode_type,
            "label": self.label,
            "shape": None if self.shape is None else [float(v) for v in self.shape],
        }


def _checked_shape(shape: np.ndarray, f: float) -> np.ndarray:
    """The reference shape as a read-only float vector (for the target at ``f`` Hz)."""
    arr = np.array(shape, dtype=float).ravel()
    if arr.size == 0 or not np.all(np.isfinite(arr)) or not np.any(arr):
        raise FEModelError(f"the shape of the {f:g} Hz target must be finite and not all zero")
    arr.flags.writeable = False
    return arr


def parse_targets(text: str) -> list[ModeTarget]:
    """Targets from their command-line spelling.

    Parameters
    ----------
    text : str
        Comma- (or semicolon-) separated ``frequency[:type]`` items, frequencies in Hz, e.g.
        ``5.03:torsion,6.11:rhombic,8.84:first vertical bending`` or ``5.03,6.11``.

    Returns
    -------
    list of ModeTarget
        In the given order (any order: pairing does not depend on it).

    Raises
    ------
    FEModelError
        For an empty list, a frequency that is not a positive number or an unknown type (the
        message names the item, and lists the types).
    """
    items = [item.strip() for item in text.replace(";", ",").split(",") if item.strip()]
    if not items:
        raise FEModelError("no targets: give frequencies in Hz, e.g. 5.03:torsion,6.11")
    return [_parse_item(item, k + 1) for k, item in enumerate(items)]


def _parse_item(item: str, number: int) -> ModeTarget:
    """One ``frequency[:type]`` item (the ``number``-th of its list)."""
    freq, sep, kind = item.partition(":")
    try:
        f = float(freq)
    except ValueError:
        raise FEModelError(
            f"target {number} {item!r}: {freq.strip()!r} is not a frequency in Hz"
        ) from None
    if sep and not kind.strip():
        raise FEModelError(f"target {number} {item!r}: a mode type must follow ':'")
    try:
        return ModeTarget(f, kind if sep else None)
    except FEModelError as exc:
        raise FEModelError(f"target {number} {item!r}: {exc}") from None


def as_targets(targets: Sequence[ModeTarget | float]) -> list[ModeTarget]:
    """Targets from ``ModeTarget`` s or bare frequencies in Hz (untyped targets).

    Raises
    ------
    FEModelError
        For an empty sequence or an invalid frequency.
    """
    out = [t if isinstance(t, ModeTarget) else ModeTarget(float(t)) for t in targets]
    if not out:
        raise FEModelError("no targets: give at least one target frequency")
    return out
