"""Pairing of model modes with calibration targets: by type, by shape (MAC), by frequency.

Every target is paired with one model mode, and every mode with at most one target, by an
optimal assignment (``scipy.optimize.linear_sum_assignment``, the Hungarian method) that
minimises the summed cost of the pairs, so no target takes a mode greedily that another needs
more. A pair is allowed only when the mode has the target's type (the classifier's name has it
as its dominant type, or as its beam-like part at an extra cost) and, for a target with a
reference shape, a MAC of at least ``min_mac`` at the sensors. The cost of an allowed pair is

``|ln(f_mode / f_target)|  +  (1 − MAC)  +  SECONDARY_TYPE_COST · [type only secondary]``

(a 10 % frequency distance costs about as much as a MAC of 0.9). Targets left without an
allowed mode are reported with the reason, never paired with a mode of another type.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from flexride.errors import FEModelError
from flexride.fem.mac import mac
from flexride.fem.mode_types import match_rank
from flexride.fem.targets import ModeTarget

#: Least MAC between a target's reference shape and a model mode for a pair.
MIN_MAC = 0.5
#: Extra cost when the wanted type is only the beam-like part of a mode's name.
SECONDARY_TYPE_COST = 0.2
_NOT_ALLOWED = 1.0e6


@dataclass(frozen=True, eq=False)
class ModelModes:
    """The model's elastic modes as the pairing sees them.

    Attributes
    ----------
    frequencies_hz : numpy.ndarray
        (n,) elastic frequencies (Hz), ascending.
    types : list of str
        The classifier's name of each mode.
    sensor_shapes : numpy.ndarray or None
        (n_sensor_dofs, n) shapes at the sensor DOFs, needed by targets with a shape.
    """

    frequencies_hz: np.ndarray
    types: list[str]
    sensor_shapes: np.ndarray | None = None


@dataclass(frozen=True)
class TargetPair:
    """A target and the model mode paired with it (or why none is).

    Attributes
    ----------
    target : ModeTarget
        The target.
    mode : int or None
        Index of the paired elastic mode (0 = first elastic mode); None when unpaired.
    frequency_hz : float or None
        The paired mode's frequency (Hz).
    mode_type : str or None
        The paired mode's type (classifier's name).
    mac : float or None
        MAC between the target's shape and the mode at the sensors (None without a shape).
    message : str
        Why the target is unpaired; empty when paired.
    """

    target: ModeTarget
    mode: int | None
    frequency_hz: float | None
    mode_type: str | None
    mac: float | None
    message: str = ""

    @property
    def error(self) -> float | None:
        """Relative frequency error ``f_mode / f_target − 1`` (-), None when unpaired."""
        if self.frequency_hz is None:
            return None
        return self.frequency_hz / self.target.frequency_hz - 1.0

    def to_dict(self) -> dict:
        """JSON-able dict (mode numbered from 1 as in the reports)."""
        return {
            "target_hz": self.target.frequency_hz,
            "target_type": self.target.mode_type,
            "label": self.target.label,
            "mode": None if self.mode is None else self.mode + 1,
            "model_hz": self.frequency_hz,
            "error": self.error,
            "model_type": self.mode_type,
            "mac": self.mac,
            "message": self.message,
        }


def pair_targets(targets: Sequence[ModeTarget], modes: ModelModes,
                 min_mac: float = MIN_MAC) -> list[TargetPair]:
    """Pair each target with a model mode (module docstring: rules and cost).

    Parameters
    ----------
    targets : sequence of ModeTarget
        Targets in any order; those with a shape need ``modes.sensor_shapes``.
    modes : ModelModes
        The model's elastic modes.
    min_mac : float
        Least MAC of a pair for a target with a shape (-).

    Returns
    -------
    list of TargetPair
        One per target, in the targets' order.

    Raises
    ------
    FEModelError
        If a target has a shape but the modes have no sensor shapes, or the shape's length
        differs from the number of sensor DOFs.
    """
    macs = target_macs(targets, modes)
    cost = pair_costs(targets, modes, macs, min_mac)
    rows, cols = linear_sum_assignment(cost)
    chosen = {int(r): int(c) for r, c in zip(rows, cols, strict=True) if cost[r, c] < _NOT_ALLOWED}
    out = []
    for i, t in enumerate(targets):
        j = chosen.get(i)
        if j is None:
            out.append(TargetPair(t, None, None, None, None,
                                  _why_unpaired(i, t, modes, macs, cost, min_mac)))
            continue
        m = None if np.isnan(macs[i, j]) else float(macs[i, j])
        out.append(TargetPair(t, j, float(modes.frequencies_hz[j]), modes.types[j], m))
    return out


def target_macs(targets: Sequence[ModeTarget], modes: ModelModes) -> np.ndarray:
    """(n_targets, n_modes) MAC between each target's shape and each mode at the sensors;
    NaN rows for targets without a shape.
    """
    out = np.full((len(targets), len(modes.types)), np.nan)
    for i, t in enumerate(targets):
        if t.shape is None:
            continue
        if modes.sensor_shapes is None:
            raise FEModelError(f"target {t.describe()} has a shape but no sensors were given")
        if t.shape.size != modes.sensor_shapes.shape[0]:
            raise FEModelError(
                f"target {t.describe()}: its shape has {t.shape.size} values but there are "
                f"{modes.sensor_shapes.shape[0]} sensor DOFs"
            )
        out[i] = mac(t.shape, modes.sensor_shapes)[0]
    return out


def pair_costs(targets: Sequence[ModeTarget], modes: ModelModes, macs: np.ndarray,
               min_mac: float = MIN_MAC) -> np.ndarray:
    """(n_targets, n_modes) cost of each pair (module docstring); pairs that are not allowed
    cost :data:`_NOT_ALLOWED`.
    """
    f = np.asarray(modes.frequencies_hz, dtype=float)
    cost = np.empty((len(targets), f.size))
    for i, t in enumerate(targets):
        cost[i] = np.abs(np.log(np.maximum(f, 1e-12) / t.frequency_hz))
        wanted = t.wanted
        if wanted is not None:
            ranks = [match_rank(wanted, name) for name in modes.types]
            cost[i] += [_NOT_ALLOWED if r is None else SECONDARY_TYPE_COST * r for r in ranks]
        if t.shape is not None:
            cost[i] += np.where(macs[i] >= min_mac, 1.0 - macs[i], _NOT_ALLOWED)
    return np.minimum(cost, _NOT_ALLOWED)


def _why_unpaired(i: int, t: ModeTarget, modes: ModelModes, macs: np.ndarray,
                  cost: np.ndarray, min_mac: float) -> str:
    """The reason target ``i`` got no mode: no computed mode of its type, none similar
    enough in shape, or every allowed mode taken by other targets.
    """
    f = modes.frequencies_hz
    span = (f"the {f.size} computed modes ({f[0]:.2f}–{f[-1]:.2f} Hz)" if f.size
            else "no computed modes")
    wanted = t.wanted
    typed = [j for j, n in enumerate(modes.types)
             if wanted is None or match_rank(wanted, n) is not None]
    if not typed:
        found = ", ".join(sorted(set(modes.types))) or "none"
        return (f"no mode of type '{t.mode_type}' among {span}: the model does not produce "
                f"this type there (its types: {found}); compute more modes if it may lie "
                "higher")
    allowed = [j for j in typed if cost[i, j] < _NOT_ALLOWED]
    if not allowed:
        best = max(typed, key=lambda j: macs[i, j])
        return (f"no {'mode of type ' + repr(t.mode_type) if wanted else 'mode'} among {span} "
                f"has MAC ≥ {min_mac:g} with the target's shape (best {macs[i, best]:.2f}: "
                f"mode {best + 1} at {f[best]:.2f} Hz)")
    listed = ", ".join(f"{j + 1} at {f[j]:.2f} Hz" for j in allowed)
    return f"the modes it could pair with (mode {listed}) are paired with other targets"
