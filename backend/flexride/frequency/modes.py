"""Names for the eigenmodes of the linear model: frequency, damping and the coordinates that
carry most of the mode's kinetic energy (m_i·|φ_i|², shares of the total).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from flexride.frequency.lti import Modes
from flexride.vehicle.topology import VehicleModel

__all__ = ["ModeInfo", "coordinate_label", "describe_modes", "mode_of"]

_RIGID = {"x": "longitudinal", "y": "lateral", "z": "bounce", "roll": "roll", "pitch": "pitch",
          "yaw": "yaw"}
_BODY = {"carbody": "car-body", "frame": "bogie frame ", "wheelset": "wheelset "}
#: Shares below this are not listed among a mode's dominant coordinates.
MIN_SHARE = 0.1


def coordinate_label(name: str, vehicle: VehicleModel | None = None) -> str:
    """People's name of a coordinate: ``carbody.z`` → ``car-body bounce``, ``carbody.mode1`` →
    ``car-body elastic mode 1 (5.03 Hz free)``, ``wheelset2.pitch`` → ``wheelset 2 spin``.
    """
    body, _, coord = name.partition(".")
    if body == "rail":
        return "rail head" if coord.startswith("head") else name.replace(".", " ")
    who = body
    for key, text in _BODY.items():
        if body.startswith(key):
            who = text + body[len(key):]
            break
    if coord.startswith("mode"):
        k = int(coord[4:])
        freq = ""
        if vehicle is not None:
            b = next((b for b in vehicle.bodies if b.name == body), None)
            if b is not None and k <= b.n_elastic:
                freq = f" ({b.elastic_frequencies[k - 1]:.2f} Hz free)"
        return f"{who} elastic mode {k}{freq}"
    if body.startswith("wheelset") and coord == "pitch":
        return f"{who} spin"
    return f"{who} {_RIGID.get(coord, coord)}"


@dataclass
class ModeInfo:
    """One eigenvalue of the linear model.

    Attributes
    ----------
    index : int
        Index of the eigenvalue in :attr:`Modes.lam`.
    frequency_hz : float
        Undamped natural frequency |λ|/2π (Hz).
    damped_frequency_hz : float
        |Im λ|/2π (Hz).
    damping_ratio : float
        −Re λ/|λ| (-).
    dominant : list of (str, float)
        Coordinates with at least 10 % of the kinetic energy and their shares (-).
    label : str
        People's name from the dominant coordinates.
    representative : bool
        True for one eigenvalue of each complex-conjugate pair (Im λ ≥ 0) and for real ones.
    partner : int
        Index of the conjugate eigenvalue (itself for real eigenvalues).
    """

    index: int
    frequency_hz: float
    damped_frequency_hz: float
    damping_ratio: float
    dominant: list[tuple[str, float]] = field(default_factory=list)
    label: str = ""
    representative: bool = True
    partner: int = -1

    def to_dict(self) -> dict[str, Any]:
        """JSON form."""
        return {"frequency_hz": self.frequency_hz,
                "damped_frequency_hz": self.damped_frequency_hz,
                "damping_ratio": self.damping_ratio, "label": self.label,
                "dominant": [{"coordinate": c, "share": s} for c, s in self.dominant]}


def describe_modes(modes: Modes, mass: np.ndarray, names: list[str],
                   vehicle: VehicleModel | None = None) -> list[ModeInfo]:
    """A :class:`ModeInfo` per eigenvalue.

    Parameters
    ----------
    modes : Modes
        Eigendecomposition of the state matrix.
    mass : numpy.ndarray
        (n,) diagonal masses of the coordinates (kg, kg·m²), for the energy shares.
    names : list of str
        Coordinate names.
    vehicle : VehicleModel, optional
        For the free frequencies of elastic modes in labels.
    """
    n = len(names)
    phi = modes.right[:n]
    energy = mass[:, None] * np.abs(phi) ** 2
    share = energy / np.maximum(energy.sum(axis=0, keepdims=True), 1e-300)
    lam = modes.lam
    freq, fd, zeta = modes.frequency_hz, modes.damped_frequency_hz, modes.damping_ratio
    partners = _partners(lam)
    order = np.argsort(-share, axis=0, kind="stable")[:3]
    labels: dict[str, str] = {}
    out = []
    for k in range(lam.size):
        top = order[:, k]
        dom = [(names[i], float(share[i, k])) for i in top if share[i, k] >= MIN_SHARE]
        if not dom:
            dom = [(names[top[0]], float(share[top[0], k]))]
        label = " + ".join(_label(c, vehicle, labels) for c, _ in dom[:2])
        out.append(ModeInfo(k, float(freq[k]), float(fd[k]), float(zeta[k]), dom, label,
                            representative=bool(lam[k].imag >= 0.0), partner=int(partners[k])))
    return out


def mode_of(info: Sequence[ModeInfo], coordinate: str) -> ModeInfo:
    """The representative eigenmode of ``info`` in which ``coordinate`` (``carbody.mode1`` …)
    has the largest share of the kinetic energy.

    Raises
    ------
    ValueError
        If the coordinate dominates no eigenmode (it has less than 10 % of every mode's
        kinetic energy).
    """
    shares = [(dict(m.dominant).get(coordinate, 0.0), m) for m in info if m.representative]
    share, mode = max(shares, key=lambda sm: sm[0], default=(0.0, None))
    if mode is None or share <= 0.0:
        raise ValueError(f"coordinate {coordinate!r} dominates no eigenmode")
    return mode


def _partners(lam: np.ndarray) -> np.ndarray:
    """Index of each eigenvalue's complex conjugate (itself for a real eigenvalue)."""
    dist = np.abs(lam[:, None] - np.conj(lam)[None, :])
    return np.where(lam.imag != 0, np.argmin(dist, axis=1), np.arange(lam.size))


def _label(name: str, vehicle: VehicleModel | None, cache: dict[str, str]) -> str:
    """:func:`coordinate_label`, once per name."""
    if name not in cache:
        cache[name] = coordinate_label(name, vehicle)
    return cache[name]
