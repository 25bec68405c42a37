"""Study: the beam car body as a second reference for the FE car body, and the ride index at
the car-body centre against the first vertical bending frequency (issue 26, §2).

On the paper's vehicle and random straight case (``paper-random-straight-<speed>``, German
high disturbance, real profiles), with the frequency engine (:mod:`flexride.frequency`), it
prints as Markdown tables (docs/fem.md, "The beam car body against the FE body, and the trend
with first bending frequency"):

1. **stiff limit** — rigid car body against a beam bending first at 50 Hz (the scenario's
   largest, mode kept by a 60 Hz cut-off) and at 200 Hz (library): PC, PFB, PR vertical rms,
   Sperling and ISO Wk at 80 km/h, and the vertical rms of a 3 s time-domain run;
2. **FE against beam** — the default FE car body (``--element-size``, modes to 40 Hz): the
   share of each mode in a beam-shaped first bending (:func:`flexride.fem.bending.bending_shares`),
   the mode with the largest share against a one-mode beam at its frequency: shapes at PC and
   the air-spring seats, participation p (:func:`~flexride.fem.bending.secondary_participation`),
   and from the frequency engine at 50–80 km/h the coupled damping ratio and the PC vertical rms
   over 0.7–1.4 f_b of the rigid body, the FE body with that one mode, the same with its shapes
   cut to the vertical components (uz, ry: what the beam has), the beam, and the FE body with
   all its modes;
3. **trend** — PC vertical Sperling (spectral), ISO 2631 Wk and unweighted rms of the beam car
   body (modes to 80 Hz) against its first bending frequency (``--f-min`` … ``--f-max`` every
   ``--step`` Hz, then 20, 30, 50 Hz), relative to the rigid body, at 80 and 50 km/h, with the
   frequencies where the bogies' bounce drives the symmetric bending in phase (n V/s) or not at
   all ((n + ½) V/s), and the wheelbase's zeros ((2k + 1) V/(2a)).

``--html FILE`` also writes the trend as a Plotly figure (self-contained HTML, plotly.js from
the installed package; about 5 MB: not for the repository).

Usage::

    python tools/studies/beam_bending_sweep.py [--element-size 0.2] [--step 0.5] \
        [--html /tmp/beam_bending.html]

(about a minute on 2 cores with the FE body cached; building the 0.2 m body adds about a
minute.)
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import time
from collections.abc import Sequence

import numpy as np

from flexride.bodies import ModalBody
from flexride.fem.beam import beam_carbody
from flexride.fem.bending import bending_shares, secondary_participation
from flexride.fem.carbody import CarBodyParams
from flexride.fem.flexible import build_flexible_body
from flexride.fem.flexible_body import FlexibleBody
from flexride.fem.mode_types import match_rank, parse_mode_type
from flexride.fem.vehicle_models import build_fe_model
from flexride.frequency import estimate, sweep
from flexride.frequency.comfort import DirectionComfort
from flexride.frequency.modes import mode_of
from flexride.scenario.presets import load_preset
from flexride.scenario.scenario import Scenario
from flexride.solver.simulate import simulate
from flexride.vehicle.topology import VehicleModel, build_vehicle

POINTS = ("PC", "PFB", "PR")
ZETA = 0.02
LENGTH = CarBodyParams().length
FE_CUTOFF_HZ = 40.0
#: Beam modes kept in the trend: every one below the frequency engine's 80 Hz.
TREND_CUTOFF_HZ = 80.0
HIGH_HZ = (20.0, 30.0, 50.0)
QUANTITIES = (("sperling", "W"), ("Wk", "Wk"), ("rms", "rms"))


def case(speed: int, **overrides: object) -> Scenario:
    """The paper's random straight case at ``speed`` (km/h) with dotted-path overrides."""
    return load_preset(f"paper-random-straight-{speed}", dict(overrides))


def index(d: DirectionComfort, quantity: str) -> float:
    """Sperling, an ISO weighting's a_w (m/s²) or the rms (m/s²) of one direction."""
    return d.iso[quantity] if quantity in d.iso else float(getattr(d, quantity))


def vertical(sc: Scenario, vehicle: VehicleModel | None = None, points: Sequence[str] = POINTS
             ) -> dict[str, DirectionComfort]:
    """Vertical comfort of ``points`` by the frequency engine (``vehicle`` prebuilt)."""
    table = estimate(sc, points=list(points), vehicle=vehicle).comfort
    return {p: table.point(p).directions["z"] for p in points}


def with_car_body(sc: Scenario, body: ModalBody) -> VehicleModel:
    """The vehicle of ``sc`` with ``body`` as its car body."""
    return build_vehicle(sc.vehicle, sc.output, carbody=body)


def one_mode_beam(sc: Scenario, f_hz: float) -> ModalBody:
    """A beam car body with its first bending mode alone, at ``f_hz`` (Hz)."""
    return beam_carbody(sc.vehicle, f_hz, f_hz * (1 + 1e-6), ZETA, LENGTH, "uniform")


def vertical_shapes_only(body: ModalBody) -> ModalBody:
    """``body`` with its elastic shapes cut to uz and ry (what a beam's markers have)."""
    keep = np.zeros((6, 1))
    keep[[2, 4]] = 1.0
    full = body.shape_at
    assert full is not None
    return dataclasses.replace(
        body, elastic_shapes={k: v * keep for k, v in body.elastic_shapes.items()},
        shape_at=lambda p: np.asarray(full(p)) * keep)


# --- 1. stiff limit -------------------------------------------------------------------------

def stiff_limit() -> None:
    """Rigid against stiff beams at 80 km/h: frequency engine and a 3 s solver run."""
    sc = case(80)
    beam50 = {"bodies.carbody.model": "beam", "bodies.carbody.first_bending_hz": 50.0,
              "bodies.carbody.cutoff_hz": 60.0, "bodies.carbody.beam_mass": "uniform"}
    rows = {"rigid": vertical(sc),
            "beam 50 Hz (scenario)": vertical(case(80, **beam50)),
            "beam 200 Hz (library)": vertical(sc, with_car_body(
                sc, beam_carbody(sc.vehicle, 200.0, 250.0, ZETA, LENGTH, "uniform")))}
    short = {"distance_m": None, "duration_s": 3.0}
    runs = {"rigid": simulate(case(80, **short)),
            "beam 50 Hz (scenario)": simulate(case(80, **short, **beam50))}
    print("\n### 1. Stiff limit (80 km/h; rms and Wk in m/s²; change against rigid)\n")
    print("| car body | " + " | ".join(f"{p} rms | {p} W | {p} Wk" for p in POINTS)
          + " | 3 s solver rms PC / PFB / PR |")
    print("| --- " * (2 + 3 * len(POINTS)) + "|")
    ref = rows["rigid"]
    for label, r in rows.items():
        cells = []
        for p in POINTS:
            for q in ("rms", "sperling", "Wk"):
                v, v0 = index(r[p], q), index(ref[p], q)
                cells.append(f"{v:.4f}" if label == "rigid" else f"{v:.4f} ({_pct(v, v0)})")
        td = ""
        if label in runs:
            rms = [_rms(runs[label].channels[f"carbody.{p}.acc.z"]) for p in POINTS]
            rms0 = [_rms(runs["rigid"].channels[f"carbody.{p}.acc.z"]) for p in POINTS]
            td = " / ".join(f"{a:.4f}" if label == "rigid" else _pct(a, b, 3)
                            for a, b in zip(rms, rms0, strict=True))
        print(f"| {label} | " + " | ".join(cells) + f" | {td} |")


def _rms(x: np.ndarray) -> float:
    return float(np.sqrt(np.mean(x**2)))


def _pct(v: float, ref: float, digits: int = 2) -> str:
    return f"{100 * (v / ref - 1):+.{digits}f} %"


# --- 2. FE against beam ---------------------------------------------------------------------

def fe_against_beam(element_size: float, speeds: Sequence[int]) -> None:
    """Where the FE body's first bending lives, and its mode of largest share against the
    one-mode beam at its frequency."""
    sc = case(80)
    fb = build_flexible_body("carbody", sc.vehicle, "modal", FE_CUTOFF_HZ, ZETA, element_size)
    model, _ = build_fe_model("carbody", sc.vehicle, element_size)
    shares = bending_shares(fb.modes.nodes, model.assemble()[1], fb.modes.shapes, LENGTH)
    names = fb.report.classification
    f = fb.body.elastic_frequencies
    print(f"\n### 2. FE car body ({element_size} m, modes to {FE_CUTOFF_HZ:.0f} Hz) against "
          "the beam\n")
    print(f"Share of each mode in a beam-shaped first bending (all {f.size} modes: "
          f"{shares.sum():.3f}); the largest:\n")
    print("| mode | Hz | share | classification |\n| --- | --- | --- | --- |")
    for k in np.argsort(-shares)[:6]:
        print(f"| {k + 1} | {f[k]:.3f} | {shares[k]:.3f} | {names[k]} |")
    named = _first_named_bending(names)
    k = int(np.argmax(shares))
    print("\nThe classifier's lowest '… first vertical bending': "
          + (f"mode {named + 1}, {f[named]:.3f} Hz, share {shares[named]:.3f}, "
             f"p = {_participation(sc, fb.body.with_modes([named]))[0] * 1e6:+.2f}e-6 /kg"
             if named is not None else "none"))
    _shapes_table(sc, fb, k)
    _mass_distribution(sc, fb.modes.nodes, model.assemble()[1])
    _engine_table(fb, k, speeds)


def _first_named_bending(names: Sequence[str]) -> int | None:
    """The lowest mode whose classification includes first vertical bending."""
    wanted = parse_mode_type("first vertical bending")
    return next((i for i, n in enumerate(names) if n and match_rank(wanted, n) is not None),
                None)


def _participation(sc: Scenario, body: ModalBody) -> np.ndarray:
    return secondary_participation(with_car_body(sc, body), "PC")


def _shapes_table(sc: Scenario, fb: FlexibleBody, k: int) -> None:
    """Mode ``k`` of the FE body against the one-mode beam at its frequency: vertical shapes
    at PC, PR and the seat as1L, longitudinal shape at the seat, participation."""
    f_b = float(fb.body.elastic_frequencies[k])
    vehicles = {"FE mode": with_car_body(sc, fb.body.with_modes([k])),
                "beam": with_car_body(sc, one_mode_beam(sc, f_b))}
    print(f"\nMode {k + 1} ({f_b:.3f} Hz, {fb.report.classification[k]}) against the beam "
          "bending first at the same frequency (shapes in mm per unit modal coordinate, "
          "sign: PC up):\n")
    print("| body | uz PC | uz PR | uz as1L | ux as1L | p (1e-6/kg) |")
    print("| --- " * 6 + "|")
    p = {}
    for label, veh in vehicles.items():
        m = veh.bodies[0].markers
        sign = math.copysign(1.0, m["point.PC"][2, 6])
        p[label] = secondary_participation(veh, "PC")[0]
        print(f"| {label} | {sign * m['point.PC'][2, 6] * 1e3:+.3f} | "
              f"{sign * m['point.PR'][2, 6] * 1e3:+.3f} | {sign * m['as1L'][2, 6] * 1e3:+.3f} | "
              f"{sign * m['as1L'][0, 6] * 1e3:+.3f} | {p[label] * 1e6:+.2f} |")
    print(f"\nFE / beam: p {p['FE mode'] / p['beam']:.3f}")


def station_masses(nodes: np.ndarray, mass) -> tuple[np.ndarray, np.ndarray]:
    """The FE body's cross-sections (nodes sharing x, m) and their vertical masses (kg): the
    row sums of the mass matrix's uz–uz block, summed per section."""
    uz = 6 * np.arange(nodes.shape[0]) + 2
    m_z = np.asarray(mass[uz][:, uz].sum(axis=1)).ravel()
    xs, inv = np.unique(np.round(nodes[:, 0], 4), return_inverse=True)
    return xs, np.bincount(inv, weights=m_z)


def lumped_beam_first_bending(xs: np.ndarray, masses: np.ndarray) -> np.ndarray:
    """First free–free bending shape (mass-normalised, m per unit modal coordinate) of a beam
    of uniform bending stiffness with point ``masses`` (kg) at ``xs`` (m): cubic Hermite
    elements between the points, their rotations condensed out (no rotary inertia)."""
    import scipy.linalg as sla

    n = xs.size
    K = np.zeros((2 * n, 2 * n))
    for e, h in enumerate(np.diff(xs)):
        K[2 * e:2 * e + 4, 2 * e:2 * e + 4] += np.array(
            [[12, 6 * h, -12, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h],
             [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]]) / h**3
    t, r = np.arange(0, 2 * n, 2), np.arange(1, 2 * n, 2)
    k_tt = K[np.ix_(t, t)] - K[np.ix_(t, r)] @ np.linalg.solve(K[np.ix_(r, r)], K[np.ix_(r, t)])
    phi = sla.eigh(k_tt, np.diag(masses))[1][:, 2]  # two rigid modes first
    return phi / np.sqrt(phi @ (masses * phi))


def _mass_distribution(sc: Scenario, nodes: np.ndarray, mass) -> None:
    """The uniform beam against a beam with the FE body's mass distribution (same stiffness
    everywhere): first bending at PC and the air springs, participation, nodes."""
    xs, m = station_masses(nodes, mass)
    half = sc.vehicle.geometry.bogie_centre_spacing / 2
    uniform = beam_carbody(sc.vehicle, 10.0, 10.0, ZETA, LENGTH, "uniform")
    x_fine = np.linspace(-LENGTH / 2, LENGTH / 2, 1901)
    shapes = {"uniform mass": (x_fine, np.array([uniform.shape_at(np.array([x, 0.0, 0.0]))[2, 0]
                                                 for x in x_fine])),
              "FE body's mass": (xs, lumped_beam_first_bending(xs, m))}
    print(f"\nMass distribution (FE body: {m[np.abs(xs) > 5.7].sum() / 1e3:.1f} t of "
          f"{m.sum() / 1e3:.1f} t beyond |x| = 5.7 m, Σ m x² = {np.sum(m * xs**2) / 1e3:.0f} "
          f"t·m²; uniform beam: {m.sum() * (1 - 5.7 / (LENGTH / 2)) / 1e3:.1f} t, "
          f"{m.sum() * LENGTH**2 / 12 / 1e3:.0f} t·m²), first bending of an Euler–Bernoulli "
          "beam of uniform stiffness (mm per unit modal coordinate, sign: PC up):\n")
    print("| beam | uz PC | uz air spring | nodes at x (m) | p (1e-6/kg) |")
    print("| --- " * 5 + "|")
    for label, (x, phi) in shapes.items():
        phi = phi * math.copysign(1.0, float(np.interp(0.0, x, phi)))
        pc, seat = float(np.interp(0.0, x, phi)), float(np.interp(half, x, phi))
        print(f"| {label} | {pc * 1e3:+.3f} | {seat * 1e3:+.3f} | ±{_first_node(x, phi):.2f} | "
              f"{4 * pc * seat * 1e6:+.2f} |")


def _first_node(x: np.ndarray, phi: np.ndarray) -> float:
    """The first zero of ``phi`` at x > 0 (m), linearly interpolated."""
    xp, fp = x[x >= 0], phi[x >= 0]
    i = int(np.flatnonzero(np.sign(fp[1:]) != np.sign(fp[:-1]))[0])
    return float(xp[i] - fp[i] * (xp[i + 1] - xp[i]) / (fp[i + 1] - fp[i]))


def _engine_table(fb: FlexibleBody, k: int, speeds: Sequence[int]) -> None:
    """PC vertical rms over 0.7–1.4 f_b (m/s²) and coupled damping, per speed."""
    f_b = float(fb.body.elastic_frequencies[k])
    lo, hi = 0.7 * f_b, 1.4 * f_b
    print(f"\nFrequency engine, PC vertical rms over {lo:.2f}–{hi:.2f} Hz (m/s²); ζ of the "
          "coupled bending mode; predicted FE/beam = (p/ζ)_FE / (p/ζ)_beam:\n")
    print("| km/h | rigid | FE mode | FE mode, uz ry only | beam | FE all modes | ζ FE | ζ beam "
          "| FE/beam | uz ry/beam | predicted | W PC FE mode / beam / rigid |")
    print("| --- " * 13 + "|")
    for speed in speeds:
        sc = case(speed)
        bodies = {"rigid": None, "fe": fb.body.with_modes([k]),
                  "fez": vertical_shapes_only(fb.body.with_modes([k])),
                  "beam": one_mode_beam(sc, f_b),
                  "all": fb.body.with_modes(range(fb.body.n_elastic))}
        band, amp, zeta, w = {}, {}, {}, {}
        for label, body in bodies.items():
            veh = with_car_body(sc, body) if body is not None else None
            est = estimate(sc, points=["PC"], vehicle=veh)
            band[label] = est.response.band_rms("carbody.PC.acc.z", lo, hi)
            w[label] = est.comfort.point("PC").directions["z"].sperling
            if label in ("fe", "beam"):
                assert veh is not None
                zeta[label] = mode_of(est.model.mode_info, "carbody.mode1").damping_ratio
                amp[label] = secondary_participation(veh, "PC")[0] / zeta[label]
        print(f"| {speed} | {band['rigid']:.4f} | {band['fe']:.4f} | {band['fez']:.4f} | "
              f"{band['beam']:.4f} | {band['all']:.4f} | {zeta['fe']:.4f} | "
              f"{zeta['beam']:.4f} | {band['fe'] / band['beam']:.2f} | "
              f"{band['fez'] / band['beam']:.2f} | {amp['fe'] / amp['beam']:.2f} | "
              f"{w['fe']:.3f} / {w['beam']:.3f} / {w['rigid']:.3f} |")


# --- 3. trend -------------------------------------------------------------------------------

def trend(speeds: Sequence[int], values: Sequence[float]) -> dict[int, dict[str, list[float]]]:
    """Excess (-) of the PC vertical indices over the rigid body's, per speed and quantity,
    against the beam's first bending frequency ``values`` (Hz)."""
    out: dict[int, dict[str, list[float]]] = {}
    for speed in speeds:
        rigid = vertical(case(speed), points=["PC"])["PC"]
        beam = case(speed, **{"bodies.carbody.model": "beam",
                              "bodies.carbody.cutoff_hz": TREND_CUTOFF_HZ,
                              "bodies.carbody.beam_mass": "uniform"})
        res = sweep(beam, "bodies.carbody.first_bending_hz", list(values), points=["PC"])
        out[speed] = {}
        for q, _ in QUANTITIES:
            ref = index(rigid, q)
            series = res.series("PC", "z", q)
            out[speed][q] = [float(v) / ref - 1.0 if v is not None else math.nan
                             for v in series]
        out[speed]["rigid"] = [index(rigid, q) for q, _ in QUANTITIES]
    return out


def print_trend(speeds: Sequence[int], values: Sequence[float],
                data: dict[int, dict[str, list[float]]]) -> None:
    """The trend as a Markdown table, with the geometric-filter frequencies."""
    sc = case(speeds[0])
    s, a = sc.vehicle.geometry.bogie_centre_spacing, sc.vehicle.geometry.wheelbase
    print("\n### 3. PC vertical indices of the beam car body against its first bending "
          "frequency (change against the rigid body)\n")
    for speed in speeds:
        v = speed / 3.6
        print(f"{speed} km/h: bogies in phase at {_list(n * v / s for n in range(1, 20))} Hz, "
              f"in anti-phase at {_list((n + 0.5) * v / s for n in range(1, 20))} Hz; "
              f"wheelbase zeros at {_list((2 * k + 1) * v / (2 * a) for k in range(4))} Hz")
    print("\n| f_b (Hz) | " + " | ".join(f"{sp} km/h {lab}" for sp in speeds
                                       for _, lab in QUANTITIES) + " |")
    print("| --- " * (1 + len(speeds) * len(QUANTITIES)) + "|")
    for i, fv in enumerate(values):
        cells = [f"{100 * data[sp][q][i]:+.1f} %" for sp in speeds for q, _ in QUANTITIES]
        print(f"| {fv:g} | " + " | ".join(cells) + " |")
    rigid = [f"{x:.3f}" if q == "sperling" else f"{x:.4f} m/s²"
             for sp in speeds for (q, _), x in zip(QUANTITIES, data[sp]["rigid"], strict=True)]
    print("| rigid | " + " | ".join(rigid) + " |")


def _list(freqs) -> str:
    return ", ".join(f"{f:.2f}" for f in freqs if 4.0 <= f <= 16.0)


def mass_distributed_beam(sc: Scenario, xs: np.ndarray, phi: np.ndarray, f_hz: float
                          ) -> ModalBody:
    """The beam car body with one bending mode of shape ``phi`` (mass-normalised, at the
    sections ``xs``, m: :func:`lumped_beam_first_bending` of the FE body's masses) at
    ``f_hz`` (Hz): a marker at x moves vertically by φ(x) and pitches by −φ'(x), as on the
    uniform beam."""
    cb = sc.vehicle.carbody
    dphi = np.gradient(phi, xs)

    def shape_at(position: np.ndarray) -> np.ndarray:
        out = np.zeros((6, 1))
        out[2, 0] = np.interp(position[0], xs, phi)
        out[4, 0] = -np.interp(position[0], xs, dphi)
        return out

    return ModalBody(name="carbody", mass=cb.mass, inertia=np.array([cb.ixx, cb.iyy, cb.izz]),
                     x_ref=0.0, cg_height=cb.cg_height, elastic_frequencies=np.array([f_hz]),
                     elastic_damping=np.array([ZETA]), shape_at=shape_at)


def print_mass_distribution_trend(speeds: Sequence[int], element_size: float) -> None:
    """PC vertical indices of a one-mode beam of uniform mass against one with the FE body's
    mass distribution and one with the vehicle's pitch inertia (end masses; uniform stiffness
    in all three), at the bogies' in-phase frequencies in 5–15 Hz."""
    sc = case(speeds[0])
    model, _ = build_fe_model("carbody", sc.vehicle, element_size)
    xs, m = station_masses(model.nodes, model.assemble()[1])
    phi = lumped_beam_first_bending(xs, m)
    spacing = sc.vehicle.geometry.bogie_centre_spacing
    print("\nOne bending mode, uniform mass against the FE body's mass distribution and the "
          "beam with the vehicle's pitch inertia (bodies.carbody.beam_mass: pitch_inertia), "
          "at the frequencies where the bogies move in phase (change against rigid):\n")
    groups = ("uniform", "FE mass", "pitch Iyy")
    print("| km/h | f_b (Hz) | " + " | ".join(f"{g} {lab}" for g in groups
                                              for _, lab in QUANTITIES) + " |")
    print("| --- " * (2 + len(groups) * len(QUANTITIES)) + "|")
    for speed in speeds:
        sc = case(speed)
        rigid = vertical(sc, points=["PC"])["PC"]
        period = speed / 3.6 / spacing
        for f_b in (n * period for n in range(1, 30) if 5.0 <= n * period <= 15.0):
            cells = []
            pitch = beam_carbody(sc.vehicle, f_b, f_b * (1 + 1e-6), ZETA, LENGTH)
            for body in (one_mode_beam(sc, f_b), mass_distributed_beam(sc, xs, phi, f_b), pitch):
                d = vertical(sc, with_car_body(sc, body), ["PC"])["PC"]
                cells += [_pct(index(d, q), index(rigid, q), 1) for q, _ in QUANTITIES]
            print(f"| {speed} | {f_b:.2f} | " + " | ".join(cells) + " |")


def write_html(path: str, speeds: Sequence[int], values: Sequence[float],
               data: dict[int, dict[str, list[float]]]) -> None:
    """The trend as a Plotly figure: one panel per index, one line per speed."""
    from plotly.subplots import make_subplots

    fig = make_subplots(rows=1, cols=len(QUANTITIES), shared_xaxes=True,
                        subplot_titles=[f"PC vertical {lab}: change against rigid (%)"
                                        for _, lab in QUANTITIES])
    for c, (q, _) in enumerate(QUANTITIES, start=1):
        for speed in speeds:
            fig.add_scatter(x=list(values), y=[100 * x for x in data[speed][q]], row=1, col=c,
                            name=f"{speed} km/h", legendgroup=str(speed), showlegend=c == 1,
                            mode="lines+markers")
        fig.add_hline(y=0.0, line_dash="dot", row=1, col=c)
        fig.update_xaxes(title_text="first bending frequency f_b (Hz)", type="log", row=1, col=c)
    fig.update_layout(title="Beam car body, paper-random-straight: ride index at the car-body "
                            "centre against first bending frequency (rigid = 0)")
    fig.write_html(path, include_plotlyjs=True)
    print(f"\nwrote {path}")


def main() -> None:
    """Run the three parts and print their tables."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--element-size", type=float, default=0.2, help="FE shell size (m)")
    ap.add_argument("--f-min", type=float, default=5.0, help="lowest first bending (Hz)")
    ap.add_argument("--f-max", type=float, default=15.0, help="highest swept (Hz)")
    ap.add_argument("--step", type=float, default=0.5, help="sweep step (Hz)")
    ap.add_argument("--html", help="also write the trend figure to this HTML file")
    ap.add_argument("--skip", nargs="*", default=[], choices=["stiff", "fe", "trend"],
                    help="parts to leave out")
    args = ap.parse_args()
    t0 = time.perf_counter()
    if "stiff" not in args.skip:
        stiff_limit()
    if "fe" not in args.skip:
        fe_against_beam(args.element_size, (50, 60, 70, 80))
    if "trend" not in args.skip:
        values = [float(x) for x in np.arange(args.f_min, args.f_max + 1e-9, args.step)]
        values += [f for f in HIGH_HZ if f > args.f_max]
        data = trend((80, 50), values)
        print_trend((80, 50), values, data)
        print_mass_distribution_trend((80, 50), args.element_size)
        if args.html:
            write_html(args.html, (80, 50), values, data)
    print(f"\n({time.perf_counter() - t0:.0f} s)")


if __name__ == "__main__":
    main()
