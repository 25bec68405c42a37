"""``comfort(response) -> ComfortTable``: ride-comfort indices per point from the response
spectra (formulas in :mod:`flexride.frequency.indices`), the eigenmodes that carry the weighted
variance, and flags where the Gaussian linear estimate is doubtful (wheel unloading, flange
contact).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from flexride.analysis.summary import ISO_WEIGHTINGS
from flexride.analysis.weighting import weighting_response
from flexride.contact.conicity import equivalent_conicity
from flexride.contact.profile_table import ProfileContactTable
from flexride.frequency import indices as ix
from flexride.frequency.response import ResponseSpectra

__all__ = ["METHOD", "ComfortTable", "DirectionComfort", "PointComfort", "comfort"]

METHOD = ("frequency domain: vehicle-track model linearised about its steady state on smooth "
          "track (rail window frozen, {track} track), driven by the German track spectra at "
          "the running speed with the wheelsets' delays; indices are the expectations of the "
          "time-domain definitions for a stationary Gaussian response; {contact}")
#: Number of standard deviations of the dynamic wheel load or lateral displacement that must
#: stay within the static load / flange clearance.
N_SIGMA = 3.0
#: Dominant modes listed per point and direction.
N_MODES = 3


@dataclass
class DirectionComfort:
    """Comfort indices of one point and direction (accelerations in m/s²).

    Attributes
    ----------
    rms : float
        Unweighted rms over 0.1–80 Hz.
    iso : dict of str to float
        Weighted rms by weighting (Wb, Wk for z; Wd for y).
    sperling : float
        Sperling index, spectral form (expected, 5 s segments).
    sperling_filter : float
        Sperling index, filter form.
    a_p95 : float
        EN 12299 95th percentile of the 5 s comfort-weighted rms.
    peak : float
        Expected largest |a| over the scenario's duration (Gaussian).
    modes : list of dict
        Eigenmodes with the largest share of the comfort-weighted variance: frequency (Hz),
        damping ratio, label, share (-).
    """

    rms: float
    iso: dict[str, float]
    sperling: float
    sperling_filter: float
    a_p95: float
    peak: float
    modes: list[dict[str, Any]] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        """JSON form."""
        return {"rms": self.rms, "iso2631": self.iso, "sperling": self.sperling,
                "sperling_filter": self.sperling_filter, "a_p95": self.a_p95,
                "peak": self.peak, "dominant_modes": self.modes}


@dataclass
class PointComfort:
    """Comfort of one point.

    Attributes
    ----------
    name : str
        Point (``PC``, ``frame1.centre`` …).
    on_floor : bool or None
        Whether it is on the car-body floor.
    directions : dict of str to DirectionComfort
        ``"y"`` and ``"z"``.
    nmv : float or None
        EN 12299 mean comfort N_MV (x counts as 0, as in the time-domain analysis).
    """

    name: str
    on_floor: bool | None
    directions: dict[str, DirectionComfort]
    nmv: float | None

    def to_dict(self) -> dict[str, Any]:
        """JSON form."""
        return {"name": self.name, "on_floor": self.on_floor, "nmv": self.nmv,
                "directions": {d: v.to_dict() for d, v in self.directions.items()}}


@dataclass
class ComfortTable:
    """The comfort estimate of one scenario.

    Attributes
    ----------
    scenario : str
        Scenario name.
    speed_kmh : float
        Running speed (km/h).
    track : str
        Track model.
    method : str
        How the numbers were made.
    points : list of PointComfort
        One per point.
    flags : list of str
        Where the estimate may not hold.
    settings : dict
        Grid, segment length, duration of the peak estimate, Sperling band.
    """

    scenario: str
    speed_kmh: float
    track: str
    method: str
    points: list[PointComfort]
    flags: list[str]
    settings: dict[str, Any]

    def point(self, name: str) -> PointComfort:
        """The row of point ``name``."""
        return next(p for p in self.points if p.name == name)

    def to_dict(self) -> dict[str, Any]:
        """JSON form (plain floats, lists and dicts)."""
        return {"scenario": self.scenario, "speed_kmh": self.speed_kmh, "track": self.track,
                "method": self.method, "points": [p.to_dict() for p in self.points],
                "flags": list(self.flags), "settings": self.settings}


def _point_key(channel: str) -> tuple[str, str]:
    body, point, _q, d = channel.split(".")
    return (point if body == "carbody" else f"{body}.{point}"), d


def _dominant(resp: ResponseSpectra, shares: np.ndarray, row: int) -> list[dict[str, Any]]:
    """The :data:`N_MODES` modes (conjugate pairs combined) with the largest shares."""
    info = resp.model.mode_info
    pair = {m.index: shares[row, m.index] + (shares[row, m.partner] if m.partner != m.index
                                              else 0.0) for m in info if m.representative}
    top = sorted(pair, key=lambda k: -pair[k])[:N_MODES]
    return [{"frequency_hz": info[k].damped_frequency_hz, "damping_ratio":
             info[k].damping_ratio, "label": info[k].label, "share": float(pair[k])}
            for k in top]


#: Relative difference between local and equivalent conicity beyond which the estimate is
#: flagged (the lateral car-body rms is then 17–29 % off the solver's, docs/analysis.md)
CONICITY_MISMATCH = 0.25


def _normal_tail(x: float) -> float:
    """P(Z > x) of a standard normal variable."""
    return 0.5 * math.erfc(x / math.sqrt(2.0))


def _flags(resp: ResponseSpectra) -> list[str]:
    """Wheel unloading or flange contact within :data:`N_SIGMA` standard deviations; with real
    profiles, a contact geometry that is not linear over the wheelsets' motion.
    """
    static = resp.model.static_wheel
    sigma = np.sqrt(resp.variance(resp.wheel_psd))
    flags = []
    for name, s in zip(resp.wheel_channels, sigma, strict=True):
        key, kind = ".".join(name.split(".")[:2]), name.split(".")[2]
        if kind == "force":
            n0 = static["normal_force"][key]
            if N_SIGMA * s > n0:
                flags.append(f"{key}: dynamic wheel load σ = {s / 1e3:.1f} kN against a static "
                             f"{n0 / 1e3:.1f} kN: contact loss likely, the linear estimate is "
                             "doubtful")
        elif static["contact_model"] == "conical":
            dy0 = abs(static["rel_disp_y"][key])
            clear = static["flange_clearance_m"]
            if dy0 + N_SIGMA * s > clear:
                p = _normal_tail((clear - dy0) / s) + _normal_tail((clear + dy0) / s)
                flags.append(f"{key}: lateral displacement relative to the rail "
                             f"{dy0 * 1e3:.1f} mm, σ = {s * 1e3:.1f} mm, reaches the flange "
                             f"clearance {clear * 1e3:.0f} mm {100 * p:.1f} % of the time "
                             "(Gaussian): flange contact likely, the linear estimate is "
                             "doubtful")
    return flags + _profile_flags(resp, dict(zip(resp.wheel_channels, sigma, strict=True)))


def _contact_method(model: Any) -> str:
    """How the contact was linearised, for the method statement."""
    ql = model.quasi_linear
    return ql.describe() if ql is not None else "contact linearised by local slopes"


def _profile_flags(resp: ResponseSpectra, sigma: dict[str, float]) -> list[str]:
    """Per wheelset, where the profiles' local conicity at the steady state and their
    equivalent conicity (EN 15302, first harmonic) at the amplitude ŷ = √2·σ of the wheelset's
    lateral motion on the rail differ by more than :data:`CONICITY_MISMATCH`: the estimate
    linearises the first, the wheelset sees the second. Not when the contact was
    quasi-linearised at that σ and the iteration converged (its non-convergence is a flag of
    its own).
    """
    ql = resp.model.quasi_linear
    if ql is not None and ql.applied and ql.converged:
        return []
    lin = resp.model.linearisation
    table = None if lin is None else lin.op.asm.profiles
    if resp.model.static_wheel["contact_model"] != "profiles" or not isinstance(
            table, ProfileContactTable):
        return []
    y, dr = table.y_grid, table.rigid_delta_r()
    flags = []
    rel = resp.model.static_wheel["rel_disp_y"]
    for key in [k for k in rel if k.endswith(".left")]:
        right = key.removesuffix(".left") + ".right"
        y0 = 0.5 * (rel[key] + rel[right])  # from the track centre: the rails' mean
        s = sigma[f"{key}.rel_disp.y"]
        amp = max(math.sqrt(2.0) * s, table.dy)
        h = 2.0 * table.dy
        local = float(np.interp(y0 + h, y, dr) - np.interp(y0 - h, y, dr)) / (4.0 * h)
        equiv = float(equivalent_conicity(y, dr, np.array([amp]), method="harmonic")[0])
        if not math.isfinite(equiv) or abs(equiv - local) > CONICITY_MISMATCH * max(
                abs(equiv), abs(local)):
            flags.append(f"{key.rsplit('.', 1)[0]}: contact geometry not linear over the "
                         f"wheelset's motion: local conicity {local:.3f} at Δy = "
                         f"{round(y0 * 1e3, 2) + 0.0:.2f} mm, equivalent conicity "
                         f"{equiv:.3f} at ŷ = √2·σ = "
                         f"{amp * 1e3:.1f} mm (EN 15302, first harmonic): the lateral estimate "
                         "is doubtful")
    return flags


def comfort(resp: ResponseSpectra) -> ComfortTable:
    """Comfort indices of every point of ``resp`` (see the module docstring).

    Returns
    -------
    ComfortTable
    """
    f, df, psd = resp.frequencies, resp.weights, resp.psd
    model = resp.model
    keys = [_point_key(c) for c in resp.channels]
    dirs = np.array([d for _p, d in keys])
    comfort_w = np.array([ISO_WEIGHTINGS[d][0] for d in dirs])
    w2 = np.array([np.abs(weighting_response(w, f)) ** 2 for w in comfort_w])
    shares = resp.mode_shares(w2)
    rms = np.sqrt(psd @ df)
    peak = ix.expected_peak(f, df, psd, model.duration)
    values: dict[str, dict[str, DirectionComfort]] = {}
    for d in ("y", "z"):
        rows = np.flatnonzero(dirs == d)
        if rows.size == 0:
            continue
        iso = {w: ix.weighted_rms(f, df, psd[rows], w) for w in ISO_WEIGHTINGS[d]}
        spec = ix.sperling_spectral_from_psd(f, psd[rows], d)
        filt = ix.sperling_filter_from_psd(f, df, psd[rows], d)
        p95 = ix.nmv_block_p95(f, df, psd[rows], ISO_WEIGHTINGS[d][0])
        for j, r in enumerate(rows):
            values.setdefault(keys[r][0], {})[d] = DirectionComfort(
                float(rms[r]), {w: float(v[j]) for w, v in iso.items()}, float(spec[j]),
                float(filt[j]), float(p95[j]), float(peak[r]), _dominant(resp, shares, int(r)))
    on_floor = {(p.name if p.body == "carbody" else f"{p.body}.{p.name}"): p.on_floor
                for p in model.points}
    points = []
    for name, dv in values.items():
        nmv = (6.0 * float(np.sqrt(sum(v.a_p95**2 for v in dv.values())))
               if on_floor.get(name) is not None else None)
        points.append(PointComfort(name, on_floor.get(name), dv, nmv))
    return ComfortTable(
        scenario=model.scenario.name, speed_kmh=float(model.scenario.speed_kmh),
        track=model.track, method=METHOD.format(track=model.track, contact=_contact_method(model)),
        points=points,
        flags=list(model.flags) + _flags(resp),
        settings={"frequency_hz": [float(f[0]), float(f[-1])], "n_frequencies": int(f.size),
                  "sperling": "spectral form: expected line power of 5 s rectangular segments "
                              "(Fejér kernel), lines 0.5-40 Hz, quasi-static part removed",
                  "peak_duration_s": model.duration,
                  "nmv": "Gaussian: 5 s mean square as scaled chi-square, 95th percentile; "
                         "x counts as 0", "iso": {k: list(v) for k, v in ISO_WEIGHTINGS.items()}})
