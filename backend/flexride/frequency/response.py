"""``response(model, spectra, points) -> ResponseSpectra``: the response PSD of the linear model
to independent random irregularity components, with the wheelsets' delays.

For component c with one-sided temporal PSD G_c(f) and rail mapping t_c (rail irregularities per
unit component), every wheelset w sees the same profile τ_w later than the leading one, so the
output o responds with

    Y_oc(ω) = Σ_w H_ow(ω) t_c e^{−jωτ_w},   H_ow(ω) = (−ω² P_o + G_o) X_w(ω) + D_ow

and, the components being independent (as in the synthesis of the time-domain solver),

    S_o(f) = Σ_c |Y_oc(2πf)|² G_c(f)                ((m/s²)²/Hz, one-sided).

X_w(ω) comes in closed form from the eigendecomposition of the state matrix: modal
coordinates η_k(ω) = l_k (B0 + jωB1 − ω²B2) u(ω) / (jω − λ_k), all frequencies at once with
NumPy (no loop over frequencies).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from flexride.errors import ScenarioError
from flexride.frequency.grid import frequency_grid, integration_weights
from flexride.frequency.indices import dynamic_part_gain
from flexride.frequency.lti import OutputMap
from flexride.frequency.model import LinearModel
from flexride.frequency.track_input import TrackSpectra

__all__ = ["ResponseSpectra", "channel_frf", "modal_input", "output_response", "response",
           "select_channels", "wheel_variance"]


@dataclass
class ResponseSpectra:
    """Response PSDs of one linear model to one set of track spectra.

    Attributes
    ----------
    model : LinearModel
        The model.
    spectra : TrackSpectra
        The input spectra.
    frequencies : numpy.ndarray
        (n_f,) frequency grid (Hz).
    channels : list of str
        Output names (``carbody.PC.acc.z`` …).
    psd : numpy.ndarray
        (n_ch, n_f) one-sided PSD ((m/s²)²/Hz for accelerations).
    by_component : numpy.ndarray
        (n_comp, n_ch, n_f) the part of each irregularity component.
    input_psd : numpy.ndarray
        (n_comp, n_f) the components' temporal PSD (m²/Hz, rad²/Hz for cross level).
    wheel_channels : list of str
        Wheel outputs (``wheelset1.left.force.n`` in N, ``wheelset1.left.rel_disp.y`` in m).
    wheel_psd : numpy.ndarray
        (n_wheel_ch, n_f) their PSD (N²/Hz, m²/Hz).
    """

    model: LinearModel
    spectra: TrackSpectra
    frequencies: np.ndarray
    channels: list[str]
    psd: np.ndarray
    by_component: np.ndarray
    input_psd: np.ndarray
    wheel_channels: list[str]
    wheel_psd: np.ndarray
    _eta: np.ndarray = field(repr=False, default_factory=lambda: np.zeros(0))
    _rows: tuple[np.ndarray, np.ndarray] = field(repr=False,
                                                 default_factory=lambda: (np.zeros(0),) * 2)
    _Y: np.ndarray = field(repr=False, default_factory=lambda: np.zeros(0))

    @property
    def weights(self) -> np.ndarray:
        """Trapezoidal integration weights of the grid (Hz)."""
        return integration_weights(self.frequencies)

    def variance(self, psd: np.ndarray | None = None) -> np.ndarray:
        """∫ PSD df over the grid for every channel (units²)."""
        return (self.psd if psd is None else psd) @ self.weights

    def band_rms(self, channel: str, f_lo: float, f_hi: float) -> float:
        """Rms of ``channel`` over the band ``f_lo`` … ``f_hi`` (Hz): √∫ PSD df by the
        trapezoidal rule on the grid's points inside the band (m/s² for accelerations).
        """
        f = self.frequencies
        band = (f >= f_lo) & (f <= f_hi)
        return float(np.sqrt(np.trapezoid(self.psd[self.index(channel)][band], f[band])))

    def index(self, channel: str) -> int:
        """Row of ``channel`` in :attr:`psd`."""
        try:
            return self.channels.index(channel)
        except ValueError:
            raise ScenarioError(f"no output channel {channel!r}; available: "
                                f"{', '.join(self.channels)}") from None

    def mode_shares(self, weight2: np.ndarray) -> np.ndarray:
        """Share of each eigenmode in each channel's weighted variance.

        Parameters
        ----------
        weight2 : numpy.ndarray
            (n_ch, n_f) squared magnitude of the frequency weighting per channel (-).

        Returns
        -------
        numpy.ndarray
            (n_ch, n_modes) Re Σ conj(Y)·Y_k |W|² G df / Σ |Y|² |W|² G df: the shares of all
            eigenvalues add up to one (the direct input part aside); a conjugate pair counts
            twice (add the partner's share).
        """
        w = 2.0 * np.pi * self.frequencies
        nf, nc, no = self._Y.shape
        z = np.conj(self._Y) * (self.input_psd.T[:, :, None] * self.weights[:, None, None]
                                * weight2.T[:, None, :])
        om, gm = self._rows
        zf = z.reshape(nf * nc, no)
        eta = self._eta.reshape(nf * nc, -1)
        a = (zf * np.repeat(-(w**2), nc)[:, None]).T @ eta
        b = zf.T @ eta
        total = np.einsum("fco,fco->o", z, self._Y).real
        return (a * om + b * gm).real / np.maximum(total, 1e-300)[:, None]

    def to_dict(self, arrays: bool = False) -> dict[str, Any]:
        """JSON form: channels, rms per channel; with ``arrays`` the grid (Hz), the PSDs
        ((m/s²)²/Hz) and ``dynamic_part_gain`` (-), the squared gain of the analysis's
        quasi-static split on the grid: PSD × gain is the PSD of the dynamic part a job's
        spectra show by default.
        """
        out: dict[str, Any] = {
            "scenario": self.model.scenario.name, "track": self.model.track,
            "channels": list(self.channels),
            "rms": dict(zip(self.channels, np.sqrt(self.variance()).tolist(), strict=True)),
            "spectra": self.spectra.to_dict(), "unit": "(m/s^2)^2/Hz, one-sided"}
        if arrays:
            out["frequencies_hz"] = self.frequencies.tolist()
            out["psd"] = {c: self.psd[i].tolist() for i, c in enumerate(self.channels)}
            out["dynamic_part_gain"] = dynamic_part_gain(self.frequencies).tolist()
        return out


def select_channels(model: LinearModel, points: Sequence[str] | None) -> list[str]:
    """Acceleration channels of ``points`` (point names such as ``PC`` or ``frame1.centre``;
    default every car-body point), lateral and vertical.

    Raises
    ------
    ScenarioError
        An unknown point.
    """
    names = model.accelerations.names
    if points is None:
        return [n for n in names if n.startswith("carbody.")]
    out = []
    for p in points:
        key = p if "." in p else f"carbody.{p}"
        found = [n for n in names if n.rsplit(".", 2)[0] == key]
        if not found:
            known = sorted({n.rsplit(".", 2)[0] for n in names})
            raise ScenarioError(f"unknown output point {p!r}; known: {', '.join(known)}")
        out += found
    return out


def _power(Y: np.ndarray) -> np.ndarray:
    """|Y|² of a complex array."""
    return Y.real**2 + Y.imag**2


def _sub(out: OutputMap, names: list[str]) -> OutputMap:
    idx = [out.names.index(n) for n in names]
    return OutputMap(names, out.P[idx], out.G[idx], out.D[idx])


def modal_input(model: LinearModel, f: np.ndarray, rail_maps: np.ndarray) -> np.ndarray:
    """Modal coordinates per unit irregularity component, wheelset delays included:
    η_ck(ω) = l_k Σ_w B(ω) t_c e^{−jωτ_w} / (jω − λ_k).

    Parameters
    ----------
    model : LinearModel
        The model.
    f : numpy.ndarray
        (n_f,) frequencies (Hz).
    rail_maps : numpy.ndarray
        (n_comp, 4) rail irregularities per unit component.

    Returns
    -------
    numpy.ndarray
        (n_f, n_comp, n_modes) complex, read-only: kept on the model for the next call with
        the same grid and maps.
    """
    memo = getattr(model, "modal_inputs", None)  # a model-like stand-in may have none
    key = (np.asarray(f, dtype=float).tobytes(), np.asarray(rail_maps, dtype=float).tobytes())
    kept = memo.get(key) if memo is not None else None
    if kept is not None and kept[0] is model.modes:
        return kept[1]
    eta = _modal_input(model, f, rail_maps)
    eta.setflags(write=False)
    if memo is not None:
        memo.clear()  # one grid at a time: the last one asked for
        memo[key] = (model.modes, eta)
    return eta


def _modal_input(model: LinearModel, f: np.ndarray, rail_maps: np.ndarray) -> np.ndarray:
    """:func:`modal_input` computed."""
    sys, modes = model.system, model.modes
    n, nw, nc = sys.n, model.wheelset_x.size, rail_maps.shape[0]
    nk = modes.lam.size
    w = 2.0 * np.pi * np.asarray(f, dtype=float)
    E = np.exp(-1j * np.outer(w, model.delays()))
    lv = modes.left[:, n:]
    eta: np.ndarray | None = None  # (n_f, nc·nk), built in place: these arrays are megabytes
    for k, B in enumerate((sys.B0, sys.B1, sys.B2)):
        if not np.any(B):
            continue
        a = np.einsum("kwr,cr->wck", (lv @ B).reshape(-1, nw, 4), rail_maps).reshape(nw, -1)
        term = E @ a
        if k:
            term *= (1j * w[:, None]) ** k
        if eta is None:
            eta = term
        else:
            eta += term
    if eta is None:
        eta = np.zeros((w.size, nc * nk), dtype=complex)
    out = eta.reshape(w.size, nc, nk)
    out *= (1.0 / (1j * w[:, None] - modes.lam[None, :]))[:, None, :]
    return out


def output_response(model: LinearModel, out: OutputMap, f: np.ndarray, rail_maps: np.ndarray,
                    eta: np.ndarray) -> tuple[np.ndarray, tuple[np.ndarray, np.ndarray]]:
    """Outputs per unit irregularity component from the modal coordinates ``eta``
    (:func:`modal_input`).

    Returns
    -------
    Y : numpy.ndarray
        (n_f, n_comp, n_out) complex response per unit component.
    rows : (numpy.ndarray, numpy.ndarray)
        Modal output rows (n_out, n_modes) of the ω² term and of the displacement term.
    """
    modes, n, nw = model.modes, model.system.n, model.wheelset_x.size
    w = 2.0 * np.pi * np.asarray(f, dtype=float)
    om = out.P @ modes.right[:n]
    gm = out.G @ modes.right[:n]
    flat = eta.reshape(-1, eta.shape[2])
    Y = flat @ gm.T
    if np.any(out.P):
        Y -= np.repeat(w**2, eta.shape[1])[:, None] * (flat @ om.T)
    Y = Y.reshape(eta.shape[0], eta.shape[1], -1)
    if np.any(out.D):
        E = np.exp(-1j * np.outer(w, model.delays()))
        d = np.einsum("owr,cr->wco", out.D.reshape(len(out.names), nw, 4), rail_maps)
        Y += (E @ d.reshape(nw, -1)).reshape(Y.shape)
    return Y, (om, gm)


def channel_frf(model: LinearModel, out: OutputMap, f: np.ndarray, rail_maps: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray, tuple[np.ndarray, np.ndarray]]:
    """Outputs per unit irregularity component, wheelset delays included.

    Returns
    -------
    Y : numpy.ndarray
        (n_f, n_comp, n_out) complex response per unit component.
    eta : numpy.ndarray
        (n_f, n_comp, n_modes) modal coordinates.
    rows : (numpy.ndarray, numpy.ndarray)
        Modal output rows (n_out, n_modes) of the ω² term and of the displacement term.
    """
    eta = modal_input(model, f, rail_maps)
    Y, rows = output_response(model, out, f, rail_maps, eta)
    return Y, eta, rows


def response(model: LinearModel, spectra: TrackSpectra | None = None,
             points: Sequence[str] | None = None,
             frequencies: np.ndarray | None = None) -> ResponseSpectra:
    """Response PSDs of ``model`` to ``spectra`` (default: the scenario's random irregularity).

    Parameters
    ----------
    model : LinearModel
        The linearised model.
    spectra : TrackSpectra, optional
        Input spectra.
    points : sequence of str, optional
        Points (``PC``, ``frame1.centre`` …); default every car-body point.
    frequencies : numpy.ndarray, optional
        Grid (Hz); default :func:`~flexride.frequency.grid.frequency_grid` of the model's modes.

    Returns
    -------
    ResponseSpectra

    Raises
    ------
    ScenarioError
        No spectra (the scenario has no random irregularity and none was given), or an unknown
        point.
    """
    spectra = _spectra(model, spectra)
    f = frequency_grid(model.modes) if frequencies is None else np.asarray(frequencies, float)
    channels = select_channels(model, points)
    maps = spectra.rail_maps()
    g = spectra.psd(f, model.speed)
    eta = modal_input(model, f, maps)
    Y, rows = output_response(model, _sub(model.accelerations, channels), f, maps, eta)
    by_comp = _power(Y).transpose(1, 2, 0) * g[:, None, :]
    wheel = _wheel_psd(model, model.wheels, f, maps, eta, g)
    return ResponseSpectra(model, spectra, f, channels, by_comp.sum(axis=0), by_comp, g,
                           list(model.wheels.names), wheel, eta, rows, Y)


def wheel_variance(model: LinearModel, names: Sequence[str]) -> np.ndarray:
    """Variances of the wheel channels ``names`` in the response to the scenario's spectra on
    the default grid (units²): the values :func:`response`'s wheel PSD gives them, without
    computing the other channels.
    """
    spectra = _spectra(model, None)
    f = frequency_grid(model.modes)
    maps = spectra.rail_maps()
    eta = modal_input(model, f, maps)
    psd = _wheel_psd(model, _sub(model.wheels, list(names)), f, maps, eta,
                     spectra.psd(f, model.speed))
    return psd @ integration_weights(f)


def _spectra(model: LinearModel, spectra: TrackSpectra | None) -> TrackSpectra:
    """``spectra``, else the scenario's (ScenarioError when it has none)."""
    spectra = spectra or model.spectra
    if spectra is None:
        raise ScenarioError("no track spectra: the scenario has no random irregularity; pass "
                            "spectra")
    return spectra


def _wheel_psd(model: LinearModel, out: OutputMap, f: np.ndarray, maps: np.ndarray,
               eta: np.ndarray, g: np.ndarray) -> np.ndarray:
    """(n_out, n_f) PSDs of the wheel channels ``out``, the components' contributions summed."""
    Yw, _rows = output_response(model, out, f, maps, eta)
    return (_power(Yw).transpose(1, 2, 0) * g[:, None, :]).sum(axis=0)
