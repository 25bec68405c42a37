"""Assembly: a validated Scenario becomes SystemArrays plus the facts needed to read results.

Runs once per scenario in NumPy; nothing here is in the time loop.
"""

from __future__ import annotations

import dataclasses
from collections.abc import MutableMapping
from dataclasses import dataclass, field
from typing import Any, Literal, NamedTuple

import numpy as np

from flexride.contact.geometry import ContactTable, conical_table
from flexride.contact.hertz import hertz_constant
from flexride.contact.profile_table import ProfileContactTable
from flexride.errors import ScenarioError
from flexride.results import Channel
from flexride.scenario.scenario import Scenario
from flexride.solver import system as S
from flexride.track.excitation import build_profile
from flexride.track.line_geometry import GRAVITY, LineTable, build_line_table
from flexride.track.measured import LIBRARY, MeasuredSources
from flexride.track.profile import IrregularityProfile
from flexride.track.rail import RailModel, build_rail_model
from flexride.vehicle.topology import VehicleModel, build_vehicle

RIGID_NAMES = ("x", "y", "z", "roll", "pitch", "yaw")
#: A wheel force whose step-to-step change alternates in sign beyond this fraction of the
#: static wheel load for :data:`~flexride.solver.system.CHATTER_STEPS` steps in a row stops
#: the run (a period-two chatter of the integration, :func:`~flexride.solver.kernel.run_chunk`).
CHATTER_LOAD_FRACTION = 0.01
RAIL_DIRS = ("vertical", "lateral", "torsion")
SIDES = ("left", "right")
#: Suspension stages whose elements' translational forces are always recorded (channels
#: ``<stage>.<element>.force.<x|y|z>``, e.g. ``secondary.1L.force.z``): the air springs.
RECORDED_STAGES = ("secondary",)
FORCE_DIRECTIONS = ("x", "y", "z")
#: Speed below which creepages are referred to this value instead (m/s): keeps creep forces
#: finite at standstill (they saturate anyway).
CREEP_MIN_SPEED = 0.5
#: Natural frequency of the soft longitudinal link that keeps the running speed (Hz): far below
#: every suspension mode, so it only removes the drift from rolling resistance.
TRACTION_LINK_HZ = 0.05


@dataclass
class Assembly:
    """SystemArrays and what is needed to interpret them."""

    sys: S.SystemArrays
    vehicle: VehicleModel
    rail: RailModel
    contact: ContactTable
    line: LineTable
    irregularity: IrregularityProfile
    dof_names: list[str]
    channel_names: list[str]
    channel_units: list[str]
    n_steps: int
    output_rate: float
    static_dofs: np.ndarray
    meta: dict = field(default_factory=dict)
    #: the two-slot table of real profiles (``contact.geometry: profiles``), else None;
    #: ``contact`` is then its one-point table (rigid contact, jumping to the flange)
    profiles: ProfileContactTable | None = None
    #: whether ``sys.par.dt`` is the run's step: False for ``solver.dt: auto`` until the
    #: set-up has chosen it (:func:`with_step`); the kernel refuses to run before
    step_chosen: bool = True


def output_rate_for(scenario: Scenario, dt: float | str | None = None) -> float:
    """Output sample rate (Hz): the user's, else max(1 kHz, 20 samples per shortest excitation
    period V/λ_min), rounded so that it divides the step rate 1/dt of the step ``dt`` (s;
    default the scenario's). With ``auto`` (``dt`` or the scenario's) the rate is as wanted:
    the step is then chosen to divide the output interval
    (:func:`~flexride.solver.stability.auto_step`).
    """
    step = scenario.solver.dt if dt is None else dt
    wanted = scenario.output.rate_hz
    if wanted is None:
        lam_min = np.inf
        for exc in scenario.excitation:
            lam = getattr(exc, "wavelength_min_m", None) or getattr(exc, "wavelength_m", None)
            if lam:
                lam_min = min(lam_min, float(lam))
        wanted = 1000.0
        if np.isfinite(lam_min):
            wanted = max(wanted, 20.0 * scenario.speed_mps / lam_min)
    if isinstance(step, str):  # auto
        return float(wanted)
    step_rate = 1.0 / step
    ndec = max(1, int(np.floor(step_rate / wanted + 1e-9)))
    return step_rate / ndec


def provisional_step(scenario: Scenario) -> float:
    """The step (s) an assembly is made with: the scenario's, or for ``solver.dt: auto`` the
    output interval until the set-up has chosen it (:func:`with_step`).
    """
    dt = scenario.solver.dt
    return 1.0 / output_rate_for(scenario) if isinstance(dt, str) else float(dt)


def step_layout(scenario: Scenario, dt: float) -> tuple[int, float, int]:
    """Steps of the run, output rate (Hz) and steps per output sample for the step ``dt`` (s)."""
    rate = output_rate_for(scenario, dt)
    return round(scenario.duration / dt), rate, round(1.0 / (dt * rate))


def with_step(asm: Assembly, scenario: Scenario, dt: float) -> Assembly:
    """``asm`` running with the step ``dt`` (s): the kernel's step, decimation and number of
    steps (nothing else of an assembly depends on the step).
    """
    n_steps, rate, n_dec = step_layout(scenario, dt)
    par = asm.sys.par._replace(dt=float(dt), n_dec=int(n_dec))
    return dataclasses.replace(asm, sys=asm.sys._replace(par=par), n_steps=n_steps,
                               output_rate=rate, step_chosen=True)


def _irregularity(scenario: Scenario, length: float, sources: MeasuredSources
                  ) -> IrregularityProfile:
    """Sum of the excitations' profiles, each on its own grid (:func:`build_profile` of one
    excitation, errors located at ``excitation[i]``); flat track without excitations.
    """
    b = scenario.track.rail_centre_half_distance
    profiles = []
    for i, exc in enumerate(scenario.excitation):
        try:
            profiles.append(build_profile([exc], length, half_gauge=b, sources=sources))
        except ScenarioError as err:
            raise err.located(("excitation", i)) from None
    if not profiles:
        return IrregularityProfile.zeros(length, 1.0)
    total = profiles[0]
    for prof in profiles[1:]:
        total = total + prof
    return total


def _flexible(kind: Literal["carbody", "frame"], scenario: Scenario, settings, name: str,
              x_ref: float):
    from flexride.fem.damping import RayleighThroughModes
    from flexride.fem.flexible import build_flexible_body

    zeta = settings.damping_ratio
    damping = RayleighThroughModes(zeta, zeta) if settings.damping_model == "rayleigh" else zeta
    fb = build_flexible_body(kind, scenario.vehicle, method=settings.reduction,
                             cutoff_hz=settings.cutoff_hz, damping_ratio=damping,
                             element_size=settings.element_size_m, name=name, x_ref=x_ref,
                             calibration=settings.calibration)
    return fb.body


def _beam(scenario: Scenario, settings):
    from flexride.fem.beam import beam_carbody
    from flexride.fem.carbody import CarBodyParams

    return beam_carbody(scenario.vehicle, settings.first_bending_hz, settings.cutoff_hz,
                        settings.damping_ratio, CarBodyParams().length, settings.beam_mass)


def vehicle_for(scenario: Scenario) -> VehicleModel:
    """The vehicle of ``scenario``: rigid bodies, or flexible car body and/or frames built from
    their reduced finite-element models (cached by content hash in :mod:`flexride.fem`), or a
    beam car body (:mod:`flexride.fem.beam`).
    """
    bm = scenario.bodies
    carbody = frames = None
    if bm.carbody.model == "flexible":
        carbody = _flexible("carbody", scenario, bm.carbody, "carbody", 0.0)
    elif bm.carbody.model == "beam":
        carbody = _beam(scenario, bm.carbody)
    if bm.frames.model == "flexible":
        lc = scenario.vehicle.geometry.bogie_centre_spacing / 2.0
        frames = (_flexible("frame", scenario, bm.frames, "frame1", lc),
                  _flexible("frame", scenario, bm.frames, "frame2", -lc))
    return build_vehicle(scenario.vehicle, scenario.output, carbody=carbody, frames=frames)


def flexible_body_facts(scenario: Scenario, veh: VehicleModel) -> dict[str, dict[str, Any]]:
    """What the run's flexible bodies are made of, JSON-compatible (``meta["flexible_bodies"]``).

    Parameters
    ----------
    scenario : Scenario
        The scenario (each body's model and element size).
    veh : VehicleModel
        The assembled vehicle: a body with elastic modes is flexible, whatever built it.

    Returns
    -------
    dict
        By body name (``carbody``, ``frame1``, ``frame2``; rigid bodies absent):
        ``model`` (``flexible``, ``beam``, or None for a body the scenario calls rigid, e.g. a
        prebuilt vehicle passed to the solver), ``element_size_m`` (m: the car body's shell
        elements, the frames' beam elements, i.e. ``frame_element_size`` of the setting; None
        for the beam car body and where the scenario does not say), ``elastic_frequencies_hz``
        (Hz, the retained elastic modes in the body's order) and ``damping_ratios`` (-); a
        calibrated car body (``bodies.carbody.calibration``) also its ``calibration``
        (targets, calibrated values, pairs: ``ModalBody.info["calibration"]``).
    """
    facts: dict[str, dict[str, Any]] = {}
    for body in veh.bodies:
        if body.n_elastic == 0:
            continue
        from flexride.fem.vehicle_models import frame_element_size  # FE stack: on use only

        settings = (scenario.bodies.carbody if body.name == "carbody"
                    else scenario.bodies.frames if body.name.startswith("frame") else None)
        model = settings.model if settings is not None and settings.model != "rigid" else None
        size: float | None = None
        if model == "flexible" and settings is not None:
            size = float(settings.element_size_m)
            if body.name != "carbody":
                size = float(frame_element_size(size))
        facts[body.name] = {
            "model": model,
            "element_size_m": size,
            "elastic_frequencies_hz": [float(f) for f in body.elastic_frequencies],
            "damping_ratios": [float(z) for z in body.elastic_damping],
        }
        if body.info.get("calibration") is not None:  # what the body was calibrated to
            facts[body.name]["calibration"] = body.info["calibration"]
    return facts


def channel_layout(veh: VehicleModel, profiles: bool = False
                   ) -> tuple[list[str], list[str], list[tuple[int, int, int]]]:
    """Names, units and kernel recipes ``(kind, a, b)`` of the recorded channels, in order:
    accelerations of every recorded point, wheel–rail forces and rail displacements of every
    wheel, the rigid coordinates of every body, and the forces of the suspension elements of
    :data:`RECORDED_STAGES`.

    A suspension element ``<stage>.<name>`` (e.g. ``secondary.1L``, the left air spring of
    bogie 1) records ``<stage>.<name>.force.<x|y|z>`` (N): the mean over the output interval of
    the force its translational spring and damper exert on its body A (the car body for the
    secondary suspension), in A's track frame — vertical positive up, so an air spring's static
    value is its share of the car body's weight.

    With ``profiles`` (real profile contact) every wheel also records the normal force of its
    flange contact point (``<wheelset>.<side>.force.flange``, N) and the track-frame contact
    angle of its more loaded point (``<wheelset>.<side>.contact_angle.x``, rad, positive when the
    normal force on the wheel points toward the track centre).
    """
    bodies = veh.bodies
    off = np.concatenate([[0], np.cumsum([b.n_dof for b in bodies])[:-1]]).astype(np.int64)
    names: list[str] = []
    units: list[str] = []
    kinds: list[tuple[int, int, int]] = []
    for p, (pname, bi, _m) in enumerate(veh.points):
        bname = bodies[bi].name
        for kind, d in ((S.CH_POINT_ACC_Y, "y"), (S.CH_POINT_ACC_Z, "z")):
            names.append(Channel(bname, pname, "acc", d).name)
            units.append("m/s^2")
            kinds.append((kind, p, 0))
    for w, bi in enumerate(veh.wheelsets):
        wname = bodies[bi].name
        for sd, side in enumerate(SIDES):
            for kind, quantity, d, u in (
                (S.CH_WHEEL_FZ, "force", "z", "N"),
                (S.CH_WHEEL_FY, "force", "y", "N"),
                (S.CH_WHEEL_N, "force", "n", "N"),
                (S.CH_RAIL_Z, "rail_disp", "z", "m"),
                (S.CH_RAIL_Y, "rail_disp", "y", "m"),
            ):
                names.append(Channel(wname, side, quantity, d).name)
                units.append(u)
                kinds.append((kind, w, sd))
            if profiles:
                for kind, quantity, d, u in (
                    (S.CH_WHEEL_N_FLANGE, "force", "flange", "N"),
                    (S.CH_WHEEL_ANGLE, "contact_angle", "x", "rad"),
                ):
                    names.append(Channel(wname, side, quantity, d).name)
                    units.append(u)
                    kinds.append((kind, w, sd))
    coord_channels = [
        ("disp", "x", 0, "m"),
        ("disp", "y", 1, "m"),
        ("disp", "z", 2, "m"),
        ("rot", "x", 3, "rad"),
        ("rot", "y", 4, "rad"),
        ("rot", "z", 5, "rad"),
    ]
    for bi, body in enumerate(bodies):
        for quantity, d, j, u in coord_channels:
            if body.is_wheelset and j == 4:
                quantity, u = "spin", "rad"
            names.append(Channel(body.name, "cg", quantity, d).name)
            units.append(u)
            kinds.append((S.CH_COORD, int(off[bi] + j), 0))
    for e, el in enumerate(veh.elements):
        stage, _, element = el.name.partition(".")
        if stage not in RECORDED_STAGES:
            continue
        for j, d in enumerate(FORCE_DIRECTIONS):
            names.append(Channel(stage, element, "force", d).name)
            units.append("N")
            kinds.append((S.CH_ELEMENT_FORCE, e, j))
    return names, units, kinds


class _DofLayout(NamedTuple):
    """Where each body's and the rails' coordinates sit in the state vector."""

    ndof: np.ndarray  # coordinates per body, int64
    off: np.ndarray  # first state index of each body, int64
    n_veh: int  # vehicle coordinates (the rails' modal coordinates follow)
    n_rail_modes: int  # modes per rail direction

    @property
    def n(self) -> int:
        """Length of the state vector: vehicle plus 2 rails × 3 directions × modes."""
        return self.n_veh + 6 * self.n_rail_modes


class _Suspension(NamedTuple):
    """Suspension elements, recorded points and the flat marker matrices they refer to."""

    el_a: np.ndarray  # body A of each element, int64
    el_b: np.ndarray  # body B of each element, int64
    el_phia: np.ndarray  # offset in ``phi`` of the marker matrix on A, int64
    el_phib: np.ndarray  # offset in ``phi`` of the marker matrix on B, int64
    el_k: np.ndarray  # (ne, 6) stiffnesses, N/m and N·m/rad
    el_c: np.ndarray  # (ne, 6) dampings, N·s/m and N·m·s/rad
    el_pb: np.ndarray  # (ne, 3) marker B position from B's track-frame origin, m
    pt_body: np.ndarray  # body of each recorded point, int64
    pt_phi: np.ndarray  # offset in ``phi`` of each recorded point's marker matrix, int64
    phi: np.ndarray  # all marker matrices, flat


class _Contact(NamedTuple):
    """Wheel–rail contact tables and the scalars that go with them."""

    table: ContactTable  # one-point table (conical, or the profiles' rigid single table)
    profiles: ProfileContactTable | None  # two-slot table of real profiles, else None
    ct: np.ndarray  # one-point table data, [side, field, Δy sample]
    ct2: np.ndarray  # two-slot table [side, slot, field, Δy sample]; zeros for conical contact
    ct_grid: np.ndarray  # one-point table parameters: [0] y0 m, [1] dy m, … (TABLE_PARAMS)
    ct2_grid: np.ndarray  # two-slot grid: [0] y0 m, [1] dy m
    b0: float  # rolling-circle half distance, m
    hertz_g: float  # Hertz constant G of the centred tread contact, m/N^(2/3)
    model: int  # S.CONTACT_CONICAL or S.CONTACT_PROFILES


def _dof_layout(veh: VehicleModel, rail: RailModel) -> _DofLayout:
    """State-vector layout: per-body coordinate counts and offsets, then the rail modes.

    Parameters
    ----------
    veh : VehicleModel
        The vehicle.
    rail : RailModel
        The rail window model (its mode count).

    Returns
    -------
    _DofLayout
        Counts and offsets (dimensionless indices).
    """
    ndof = np.array([b.n_dof for b in veh.bodies], dtype=np.int64)
    off = np.concatenate([[0], np.cumsum(ndof)[:-1]]).astype(np.int64)
    return _DofLayout(ndof, off, int(ndof.sum()), rail.n_modes)


def _rail_window(scenario: Scenario, veh: VehicleModel) -> tuple[RailModel, int]:
    """Modal rail model of the moving window that covers every wheelset plus margins.

    Parameters
    ----------
    scenario : Scenario
        Validated scenario (track, fastener spacing, solver margins).
    veh : VehicleModel
        The vehicle (wheelset positions set the span, m).

    Returns
    -------
    rail : RailModel
        Rail model of window length span + margins, shifted by whole bays.
    shift_bays : int
        Fastener bays (each ``fastener.spacing`` m) the window moves by at a shift.
    """
    sol = scenario.solver
    ws_x = np.array([veh.bodies[i].x_ref for i in veh.wheelsets])
    span = float(ws_x.max() - ws_x.min())
    fas = scenario.track.fastener
    nshift = max(1, round(sol.rail_shift_m / fas.spacing))
    rail = build_rail_model(scenario.track, span, sol.rail_margin_m, nshift * fas.spacing)
    return rail, nshift


def _diagonals(veh: VehicleModel, rail: RailModel, dofs: _DofLayout
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Inverse generalised mass of every coordinate, and the bodies' modal stiffness and damping.

    Parameters
    ----------
    veh : VehicleModel
        The vehicle.
    rail : RailModel
        The rail window (modal mass kg, roll inertia kg·m²).
    dofs : _DofLayout
        State-vector layout.

    Returns
    -------
    minv : ndarray
        (n,) inverse masses, 1/kg or 1/(kg·m²); vehicle then rails (left, right; vertical,
        lateral, torsion).
    kdiag : ndarray
        (n_veh,) modal stiffness, N/m (zero for rigid coordinates).
    cdiag : ndarray
        (n_veh,) modal damping, N·s/m (zero for rigid coordinates).
    """
    n_veh, nm = dofs.n_veh, dofs.n_rail_modes
    minv = np.empty(dofs.n)
    kdiag = np.zeros(n_veh)
    cdiag = np.zeros(n_veh)
    for b, o in zip(veh.bodies, dofs.off, strict=True):
        minv[o : o + b.n_dof] = 1.0 / b.mass_diagonal()
        kdiag[o : o + b.n_dof] = b.modal_stiffness()
        cdiag[o : o + b.n_dof] = b.modal_damping()
    for r in range(2):
        o = n_veh + 3 * r * nm
        minv[o : o + nm] = 1.0 / rail.mass
        minv[o + nm : o + 2 * nm] = 1.0 / rail.mass
        minv[o + 2 * nm : o + 3 * nm] = 1.0 / rail.roll_inertia
    return minv, kdiag, cdiag


def _suspension(veh: VehicleModel) -> _Suspension:
    """Suspension element arrays and recorded points, with their marker matrices stored once
    each in one flat array (elements' markers first, then the points').

    Parameters
    ----------
    veh : VehicleModel
        The vehicle.

    Returns
    -------
    _Suspension
        Element bodies, marker offsets, stiffness (N/m, N·m/rad), damping (N·s/m, N·m·s/rad)
        and marker B position (m, from B's track-frame origin); recorded points' bodies
        and marker offsets; the flat marker matrices.
    """
    bodies = veh.bodies
    phi_chunks: list[np.ndarray] = []
    phi_off: dict[tuple[int, str], int] = {}
    pos = 0

    def marker_offset(bi: int, name: str) -> int:
        nonlocal pos
        key = (bi, name)
        if key not in phi_off:
            m = np.ascontiguousarray(bodies[bi].markers[name], dtype=float)
            phi_off[key] = pos
            phi_chunks.append(m.ravel())
            pos += m.size
        return phi_off[key]

    ne = len(veh.elements)
    el_a = np.empty(ne, np.int64)
    el_b = np.empty(ne, np.int64)
    el_pa = np.empty(ne, np.int64)
    el_pb_off = np.empty(ne, np.int64)
    el_k = np.empty((ne, 6))
    el_c = np.empty((ne, 6))
    el_pb = np.empty((ne, 3))
    for e, el in enumerate(veh.elements):
        el_a[e], el_b[e] = el.body_a, el.body_b
        el_pa[e] = marker_offset(el.body_a, el.marker_a)
        el_pb_off[e] = marker_offset(el.body_b, el.marker_b)
        el_k[e], el_c[e] = el.stiffness, el.damping
        p = bodies[el.body_b].marker_positions[el.marker_b]
        el_pb[e] = (p[0], p[1], p[2] + bodies[el.body_b].cg_height)

    pt_body = np.array([p[1] for p in veh.points], dtype=np.int64)
    pt_phi = np.array([marker_offset(p[1], p[2]) for p in veh.points], dtype=np.int64)
    phi = np.concatenate(phi_chunks) if phi_chunks else np.zeros(1)
    return _Suspension(el_a, el_b, el_pa, el_pb_off, el_k, el_c, el_pb, pt_body, pt_phi, phi)


def _contact(scenario: Scenario, veh: VehicleModel, sources: MeasuredSources) -> _Contact:
    """Contact tables: the conical one-point table, or the real-profile two-slot table.

    Parameters
    ----------
    scenario : Scenario
        Validated scenario (its ``contact`` section and rail Young's modulus, Pa).
    veh : VehicleModel
        The vehicle (wheel radius and rolling-circle half distance, m).
    sources : MeasuredSources
        Where measured profiles may be read from.

    Returns
    -------
    _Contact
        Tables sampled on the wheelset's lateral displacement Δy (m), their grids, the
        rolling-circle half distance b0 (m) and the Hertz constant G (m/N^(2/3)).

    Raises
    ------
    ScenarioError
        The profiles cannot be built, located at ``contact``.
    """
    c = scenario.contact
    r0 = veh.wheel_radius
    b0 = veh.rolling_circle_half_distance
    E_rail = scenario.track.rail.youngs_modulus
    ptable: ProfileContactTable | None = None
    if c.geometry == "profiles":
        from flexride.contact.scenario_table import scenario_contact_table

        try:
            ptable = scenario_contact_table(c, r0, b0, E_rail, sources)
        except ScenarioError as err:
            raise err.located(("contact",)) from None
        table = ptable.single_table()
        p2, ct2 = ptable.as_arrays()
        ct2 = np.ascontiguousarray(ct2)
        b0 = ptable.b0
        i_mid = round(-ptable.y0 / ptable.dy)
        hertz_g = float(ct2[0, 0, S.PT_GH, i_mid])
        contact_model = S.CONTACT_PROFILES
    else:
        table = conical_table(
            r0=r0,
            conicity=c.conicity,
            b0=b0,
            flange_clearance=c.flange_clearance,
            flange_stiffness=c.flange_stiffness,
            rail_head_radius=c.rail_head_radius,
            E=E_rail,
            nu=c.poisson,
        )
        p2 = np.array([0.0, 1.0])
        ct2 = np.zeros((2, 2, S.N_PT, 2))
        hertz_g = hertz_constant(r0, c.hertz_tread)
        contact_model = S.CONTACT_CONICAL
    tparams, tdata = table.as_arrays()
    ct = np.ascontiguousarray(tdata.transpose(1, 0, 2))
    return _Contact(table, ptable, ct, ct2, tparams, p2, b0, hertz_g, contact_model)


def _route(scenario: Scenario, veh: VehicleModel, sources: MeasuredSources
           ) -> tuple[LineTable, IrregularityProfile]:
    """Line-geometry and irregularity tables along the route. The vehicle centre runs from
    0 to speed × duration (m); the line table reaches 25 m beyond the outermost bodies at
    both ends of the run, the irregularity grid runs from 0 to that far end.

    Parameters
    ----------
    scenario : Scenario
        Validated scenario (line, excitations, speed m/s, duration s).
    veh : VehicleModel
        The vehicle (body positions x_ref, m).
    sources : MeasuredSources
        Where measured irregularities may be read from.

    Returns
    -------
    line : LineTable
        Curvature, cant and gradient along the route, sampled in distance (m).
    irregularity : IrregularityProfile
        Sum of the excitations' rail irregularities (m) from 0 to the route's far end.
    """
    dist = scenario.speed_mps * scenario.duration
    x_lo = min(b.x_ref for b in veh.bodies) - 20.0
    x_hi = max(b.x_ref for b in veh.bodies) + 20.0
    b_rail = scenario.track.rail_centre_half_distance
    line = build_line_table(scenario.line, x_lo - 5.0, dist + x_hi + 5.0, b_rail)
    irr = _irregularity(scenario, dist + x_hi + 5.0, sources)
    return line, irr


def _dof_names(veh: VehicleModel, dofs: _DofLayout) -> tuple[list[str], np.ndarray]:
    """Names of all coordinates, and the subset solved in statics: z and roll of every body,
    pitch of every body but the wheelsets (theirs is the spin), elastic modes, all rail modes.

    Parameters
    ----------
    veh : VehicleModel
        The vehicle.
    dofs : _DofLayout
        State-vector layout.

    Returns
    -------
    dof_names : list of str
        ``<body>.<x|y|z|roll|pitch|yaw|modeK>`` then ``rail.<side>.<direction>.modeK``.
    static_dofs : ndarray
        int64 state indices of the static subset.
    """
    dof_names: list[str] = []
    static = []
    for bi, body in enumerate(veh.bodies):
        for j in range(body.n_dof):
            nm_ = RIGID_NAMES[j] if j < 6 else f"mode{j - 5}"
            dof_names.append(f"{body.name}.{nm_}")
            if j in (2, 3) or j >= 6 or (j == 4 and not body.is_wheelset):
                static.append(int(dofs.off[bi] + j))
    for side in SIDES:
        for d in RAIL_DIRS:
            dof_names.extend(f"rail.{side}.{d}.mode{k + 1}" for k in range(dofs.n_rail_modes))
    static.extend(range(dofs.n_veh, dofs.n))
    return dof_names, np.array(static, dtype=np.int64)


def _scalars(scenario: Scenario, veh: VehicleModel, rail: RailModel, shift_bays: int,
             dofs: _DofLayout, contact: _Contact, line: LineTable, irr: IrregularityProfile,
             n_dec: int, n_ch: int) -> S.Scalars:
    """The kernel's named scalars (``par``).

    Includes the time step (s), speed (m/s), rail foundation properties per metre (N/m²,
    N·s/m²), friction, shear modulus (Pa), table grids (m), and the soft traction link
    (:data:`TRACTION_LINK_HZ`, critically damped on the whole vehicle mass: N/m, N·s/m).

    Parameters
    ----------
    scenario : Scenario
        Validated scenario.
    veh : VehicleModel
        The vehicle.
    rail : RailModel
        The rail window.
    shift_bays : int
        Fastener bays per window shift.
    dofs : _DofLayout
        State-vector layout.
    contact : _Contact
        Contact tables.
    line : LineTable
        Line-geometry table.
    irr : IrregularityProfile
        Irregularity table.
    n_dec : int
        Time steps per output sample.
    n_ch : int
        Number of recorded channels.

    Returns
    -------
    Scalars
        Each value cast to its field's type.
    """
    sol = scenario.solver
    c = scenario.contact
    w_tr = 2.0 * np.pi * TRACTION_LINK_HZ
    return S.make_scalars(
        dt=provisional_step(scenario),
        psi=sol.psi,
        phi=sol.phi,
        speed=scenario.speed_mps,
        gravity=GRAVITY,
        b0=contact.b0,
        r0=veh.wheel_radius,
        win_len=rail.length,
        spacing=rail.spacing,
        h_foot=rail.h_foot,
        h_head=rail.h_head,
        cz_d=rail.cz / rail.spacing,
        ky_d=rail.ky / rail.spacing,
        cy_d=rail.cy / rail.spacing,
        kr_d=rail.k_roll / rail.spacing,
        cr_d=rail.c_roll / rail.spacing,
        mu=c.friction,
        g_shear=c.shear_modulus_for(scenario.track.rail.youngs_modulus),
        hertz_g=contact.hertz_g,
        flange_clearance=c.flange_clearance,
        flange_k=c.flange_stiffness if contact.profiles is None else 0.0,
        runaway=sol.runaway_displacement_m,
        chatter_force=CHATTER_LOAD_FRACTION * veh.total_mass * GRAVITY / (2 * len(veh.wheelsets)),
        v_min=CREEP_MIN_SPEED,
        ct_y0=contact.ct_grid[0],
        ct_dy=contact.ct_grid[1],
        ct2_y0=contact.ct2_grid[0],
        ct2_dy=contact.ct2_grid[1],
        contact_model=contact.model,
        irr_s0=irr.s0,
        irr_ds=irr.ds,
        ln_s0=line.s0,
        ln_ds=line.ds,
        s_start=0.0,
        margin=sol.rail_margin_m,
        k_traction=veh.total_mass * w_tr**2,
        c_traction=2.0 * veh.total_mass * w_tr,
        n_veh=dofs.n_veh,
        n_rail_modes=dofs.n_rail_modes,
        n_bodies=len(veh.bodies),
        n_elem=len(veh.elements),
        n_ws=len(veh.wheelsets),
        n_dec=n_dec,
        shift_bays=shift_bays,
        n_points=len(veh.points),
        n_ch=n_ch,
    )


def _system_arrays(par: S.Scalars, veh: VehicleModel, rail: RailModel, dofs: _DofLayout,
                   diagonals: tuple[np.ndarray, np.ndarray, np.ndarray], susp: _Suspension,
                   contact: _Contact, line: LineTable, irr: IrregularityProfile,
                   kinds: list[tuple[int, int, int]]) -> S.SystemArrays:
    """The kernel's SystemArrays, gathered from the assembled parts.

    Parameters
    ----------
    par : Scalars
        Named scalars.
    veh : VehicleModel
        The vehicle (body positions m, cg heights m, masses kg, inertias kg·m²).
    rail : RailModel
        The rail window (modal stiffnesses, wavenumbers rad/m, sine matrix).
    dofs : _DofLayout
        State-vector layout.
    diagonals : tuple of ndarray
        Inverse masses, modal stiffness and modal damping (:func:`_diagonals`).
    susp : _Suspension
        Suspension elements, recorded points and marker matrices.
    contact : _Contact
        Contact tables.
    line : LineTable
        Line-geometry table.
    irr : IrregularityProfile
        Irregularities (m), stacked as z left, z right, y left, y right.
    kinds : list of (int, int, int)
        Kernel recipes of the recorded channels (:func:`channel_layout`).

    Returns
    -------
    SystemArrays
        Contiguous arrays for the kernel.
    """
    bodies = veh.bodies
    minv, kdiag, cdiag = diagonals
    ch = np.array(kinds, dtype=np.int64).reshape(-1, 3)
    return S.SystemArrays(
        par=par,
        minv=minv,
        kdiag=kdiag,
        cdiag=cdiag,
        body_off=dofs.off,
        body_ndof=dofs.ndof,
        body_x=np.array([b.x_ref for b in bodies]),
        body_h=np.array([b.cg_height for b in bodies]),
        body_mass=np.array([b.mass for b in bodies]),
        body_inertia=np.ascontiguousarray(np.array([b.inertia for b in bodies], dtype=float)),
        body_ws=np.array([1 if b.is_wheelset else 0 for b in bodies], dtype=np.int64),
        phi=susp.phi,
        el_a=susp.el_a,
        el_b=susp.el_b,
        el_phia=susp.el_phia,
        el_phib=susp.el_phib,
        el_k=susp.el_k,
        el_c=susp.el_c,
        el_pb=susp.el_pb,
        ws_body=np.array(veh.wheelsets, dtype=np.int64),
        rail_kz=rail.vertical_stiffness(),
        rail_kyb=rail.lateral_bending_stiffness(),
        rail_ktb=rail.torsional_stiffness(),
        rail_kap=rail.wavenumbers(),
        rail_dst=np.ascontiguousarray(rail.sine_matrix()),
        ct=contact.ct,
        ct2=contact.ct2,
        irr=np.ascontiguousarray(np.vstack([irr.z_left, irr.z_right, irr.y_left, irr.y_right])),
        line=line.as_array(),
        pt_body=susp.pt_body,
        pt_phi=susp.pt_phi,
        ch=np.ascontiguousarray(ch),
        body_line=np.zeros((len(bodies), S.N_BL)),
        el_force=np.zeros((len(veh.elements), 3)),
    )


def contact_key(scenario: Scenario, veh: VehicleModel) -> str:
    """What the contact tables of an assembly are made from (:func:`_contact`): the
    ``contact`` section, the wheel radius, the rolling-circle distance and the rail's Young's
    modulus.
    """
    return "|".join([scenario.contact.model_dump_json(), repr(float(veh.wheel_radius)),
                     repr(float(veh.rolling_circle_half_distance)),
                     repr(float(scenario.track.rail.youngs_modulus))])


#: Contact tables a caller's ``contact_tables`` mapping keeps at most.
MAX_KEPT_CONTACTS = 4


def _kept_contact(scenario: Scenario, veh: VehicleModel, sources: MeasuredSources,
                  kept: MutableMapping[str, Any] | None) -> _Contact:
    """The contact tables of ``scenario``: from ``kept`` when made from the same inputs
    (:func:`contact_key`), else made (and kept, oldest out beyond :data:`MAX_KEPT_CONTACTS`).
    """
    if kept is None:
        return _contact(scenario, veh, sources)
    key = contact_key(scenario, veh)
    contact = kept.get(key)
    if contact is None:
        contact = _contact(scenario, veh, sources)
        while len(kept) >= MAX_KEPT_CONTACTS:
            kept.pop(next(iter(kept)))
        kept[key] = contact
    return contact


def assemble(scenario: Scenario, vehicle: VehicleModel | None = None,
             sources: MeasuredSources = LIBRARY,
             contact_tables: MutableMapping[str, Any] | None = None) -> Assembly:
    """Build the SystemArrays of ``scenario``.

    Parameters
    ----------
    scenario : Scenario
        Validated scenario.
    vehicle : VehicleModel, optional
        A prebuilt vehicle (e.g. with flexible bodies); built from the scenario otherwise.
    sources : MeasuredSources
        Where measured irregularities may be read from (default: files by path).
    contact_tables : mutable mapping, optional
        Contact tables kept between assemblies by the caller (e.g. the runs of a parameter
        sweep): a table made from the same inputs is taken from it, a new one is put in.

    Returns
    -------
    Assembly
        The kernel's arrays and what is needed to read its results.
    """
    veh = vehicle or vehicle_for(scenario)
    rail, shift_bays = _rail_window(scenario, veh)
    dofs = _dof_layout(veh, rail)
    diagonals = _diagonals(veh, rail, dofs)
    susp = _suspension(veh)
    contact = _kept_contact(scenario, veh, sources, contact_tables)
    line, irr = _route(scenario, veh, sources)

    dt = provisional_step(scenario)
    n_steps, rate, n_dec = step_layout(scenario, dt)
    names, units, kinds = channel_layout(veh, profiles=contact.profiles is not None)
    dof_names, static_dofs = _dof_names(veh, dofs)

    par = _scalars(scenario, veh, rail, shift_bays, dofs, contact, line, irr, n_dec, len(names))
    sysarr = _system_arrays(par, veh, rail, dofs, diagonals, susp, contact, line, irr, kinds)
    return Assembly(
        sys=sysarr,
        vehicle=veh,
        rail=rail,
        contact=contact.table,
        line=line,
        irregularity=irr,
        dof_names=dof_names,
        channel_names=names,
        channel_units=units,
        n_steps=n_steps,
        output_rate=rate,
        static_dofs=static_dofs,
        profiles=contact.profiles,
        step_chosen=not isinstance(scenario.solver.dt, str),
    )
