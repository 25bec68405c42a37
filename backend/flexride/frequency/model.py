"""``linear_model(scenario) -> LinearModel``: the coupled vehicle–track system linearised about
its steady state on smooth track, with the rail irregularities at every wheelset as inputs.

Steps (the costly part of an estimate, done once per scenario):

1. assemble the scenario as the time-domain solver does (:func:`flexride.solver.assemble`),
   with a zero irregularity table: the model is linearised about smooth track;
2. the operating point (:mod:`flexride.frequency.operating_point`): static equilibrium, or
   steady curving on an arc, with the rail window frozen there; refused with flange contact
   or a lost contact;
3. finite-difference Jacobians of the kernel's own force evaluation
   (:mod:`flexride.frequency.jacobians`): K = −∂A/∂X and C = −∂A/∂V (suspensions, elastic
   modes, tangent Hertz stiffness, Kalker creep as damping f/V, gravitational stiffness and
   conicity all come out of the kernel's forces), the input matrices B0 = ∂A/∂u and
   B1 = ∂A/∂u̇ for the four rail irregularities u at each wheelset (u̇ = V·du/ds), and the
   wheels' normal force and lateral position relative to the rail;
4. the track model (:mod:`flexride.frequency.reduce`): rail modes condensed (default), all
   kept, or rigid rails;
5. the eigendecomposition of the state matrix, refused if a mode is unstable (hunting);
6. with real profiles (``linearisation="statistical"``, the default), the contact's
   derivatives in each wheel's lateral displacement replaced by Gaussian-equivalent gains at
   the response's own σ, iterated (:mod:`flexride.frequency.quasilinear`).

Outputs are the accelerations of every recorded point, as the kernel records them: the second
derivative of the point's displacement plus, laterally, the gravity component g·φ_x the
accelerometer sees when the body rolls (on a curve the frame's specific force instead of g).
"""

from __future__ import annotations

import functools
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from flexride.frequency.errors import LinearisationError
from flexride.frequency.jacobians import irregularity_jacobians, refined_state_jacobians
from flexride.frequency.lti import Modes, OutputMap, SecondOrderSystem
from flexride.frequency.modes import ModeInfo, describe_modes
from flexride.frequency.operating_point import (
    OperatingPoint,
    WarmStart,
    check_contact,
    solve_operating_point,
)
from flexride.frequency.reduce import TRACK_MODELS, Reduced, TrackModel, reduce_track
from flexride.frequency.track_input import STATIONARY_KINDS, TrackSpectra, track_spectra
from flexride.results import Channel
from flexride.scenario.scenario import Scenario
from flexride.solver import system as S
from flexride.solver.assemble import Assembly, assemble
from flexride.solver.forces import frame_specific_force
from flexride.solver.simulate import small_dense_problems
from flexride.track.measured import LIBRARY, MeasuredSources
from flexride.vehicle.topology import RecordedPoint, VehicleModel

__all__ = ["LinearModel", "Linearisation", "linear_model", "linearise", "model_from"]

LinearisationMethod = Literal["statistical", "local"]
#: How the contact is linearised (:mod:`flexride.frequency.quasilinear`): Gaussian-equivalent
#: gains at the response's own amplitude (profile contact; the conical tread is linear and
#: stays local), or local slopes at the operating point everywhere.
LINEARISATIONS: tuple[LinearisationMethod, ...] = ("statistical", "local")
#: The default (checked against the time-domain solver with S1002/60E1: docs/analysis.md).
DEFAULT_LINEARISATION: LinearisationMethod = "statistical"

#: A mode whose eigenvalue has a real part above this (1/s) makes the model unstable.
UNSTABLE_RATE = 1e-3
SIDES = ("left", "right")


@dataclass
class Linearisation:
    """The full frozen-window system at the operating point, with the derivatives of the
    wheel quantities: what a linear model is made from (and what a sweep reuses).

    Attributes
    ----------
    op : OperatingPoint
        The operating point.
    full : SecondOrderSystem
        Mass-normalised full system: K = −∂A/∂X (1/s²), C = −∂A/∂V (1/s), B0 = ∂A/∂u
        (1/s²), B1 = ∂A/∂(du/ds)/V (1/s), B2 = 0.
    mass : numpy.ndarray
        (n,) diagonal generalised masses (kg, kg·m²).
    daux_dX, daux_dV : numpy.ndarray
        (n_ws·2·N_AUX, n) derivatives of the wheel quantities with respect to the coordinates
        and the velocities.
    daux_du : numpy.ndarray
        (n_ws·2·N_AUX, 4·n_ws) the same with respect to the rail irregularities.
    methods_x, methods_v : numpy.ndarray
        (n,) how each column of ∂A/∂X and ∂A/∂V was differenced
        (:func:`~flexride.frequency.jacobians.refined_state_jacobians`).
    contact_op : OperatingPoint, optional
        Where the contact's derivatives were differenced when that is not ``op`` (a sweep
        that reused them, :mod:`flexride.frequency.rebuild`).
    """

    op: OperatingPoint
    full: SecondOrderSystem
    mass: np.ndarray
    daux_dX: np.ndarray
    daux_dV: np.ndarray
    daux_du: np.ndarray
    methods_x: np.ndarray
    methods_v: np.ndarray
    contact_op: OperatingPoint | None = None

    @property
    def contact_origin(self) -> OperatingPoint:
        """The operating point the contact's derivatives were differenced at."""
        return self.contact_op if self.contact_op is not None else self.op


@dataclass
class LinearModel:
    """The linearised vehicle–track model of one scenario.

    Attributes
    ----------
    scenario : Scenario
        The scenario (its random excitation is the default input spectrum).
    track : {"condensed", "modal", "rigid"}
        Track model.
    system : SecondOrderSystem
        Mass-normalised system of the kept coordinates; inputs ordered 4·w + c for wheelset w
        and rail channel c (0 z left, 1 z right, 2 y left, 3 y right), in m.
    dof_names : list of str
        Names of the kept coordinates.
    speed : float
        Running speed V (m/s).
    wheelset_x : numpy.ndarray
        Wheelset positions from the vehicle centre, forward positive (m).
    points : list of RecordedPoint
        Every recorded point (car body points first).
    accelerations : OutputMap
        Accelerations (m/s²) of every recorded point, ``<body>.<point>.acc.<y|z>``.
    wheels : OutputMap
        Per wheel the dynamic normal force (``<wheelset>.<side>.force.n``, N) and the lateral
        displacement relative to the rail head (``<wheelset>.<side>.rel_disp.y``, m).
    static_wheel : dict
        ``normal_force`` (N) and ``rel_disp_y`` (m) per wheel at the steady state, the flange
        clearance (m, conical tread) and the contact model.
    mode_solver : callable
        Makes :attr:`modes`, the eigendecomposition of the state matrix (on first use: a
        sweep's local models, checked for stability by their eigenvalues alone, never need it).
    mode_describer : callable
        Makes :attr:`mode_info` (on first use: a sweep's local models are never described).
    spectra : TrackSpectra or None
        The scenario's random irregularity (None when it has none).
    quasi_static : dict
        Specific force at each recorded point in the steady state (m/s², lateral and vertical
        minus g): the quasi-static acceleration on a curve, 0 on straight track.
    flags : list of str
        Reasons the estimate may not hold (only with ``strict=False``).
    info : dict
        Operating point, sizes and timings.
    linearisation : Linearisation, optional
        The full system it was reduced from (kept for parameter sweeps).
    reduced : Reduced, optional
        The track reduction (kept for parameter sweeps).
    quasi_linear : QuasiLinear, optional
        How the contact was linearised (:mod:`flexride.frequency.quasilinear`); with the
        statistical linearisation ``linearisation`` is still the local one (what sweeps reuse)
        and ``quasi_linear.linearisation`` the one ``system`` was reduced from.
    modal_inputs : dict
        Modal coordinates per unit irregularity already computed
        (:func:`~flexride.frequency.response.modal_input`), by grid and rail maps: a model's
        response is asked for more than once (the quasi-linear iteration's σ, the comfort).
    """

    scenario: Scenario
    track: TrackModel
    system: SecondOrderSystem
    dof_names: list[str]
    speed: float
    wheelset_x: np.ndarray
    points: list[RecordedPoint]
    accelerations: OutputMap
    wheels: OutputMap
    static_wheel: dict[str, Any]
    mode_solver: Callable[[], Modes] = field(repr=False, compare=False)
    mode_describer: Callable[[], list[ModeInfo]] = field(repr=False, compare=False)
    spectra: TrackSpectra | None
    quasi_static: dict[str, dict[str, float]]
    flags: list[str] = field(default_factory=list)
    info: dict[str, Any] = field(default_factory=dict)
    linearisation: Linearisation | None = field(default=None, repr=False, compare=False)
    reduced: Reduced | None = field(default=None, repr=False, compare=False)
    quasi_linear: Any = field(default=None, repr=False, compare=False)
    modal_inputs: dict[tuple[bytes, bytes], tuple[Any, np.ndarray]] = field(
        default_factory=dict, repr=False, compare=False)

    @functools.cached_property
    def modes(self) -> Modes:
        """Eigendecomposition of the state matrix."""
        return self.mode_solver()

    @functools.cached_property
    def mode_info(self) -> list[ModeInfo]:
        """One entry per eigenvalue: frequency, damping, dominant coordinates, label."""
        return self.mode_describer()

    @property
    def duration(self) -> float:
        """The scenario's run time (s), for peak estimates."""
        return float(self.scenario.duration)

    def delays(self) -> np.ndarray:
        """Time each wheelset runs behind the leading one (s), τ_w = (x_1 − x_w)/V."""
        return (self.wheelset_x.max() - self.wheelset_x) / self.speed

    def to_dict(self) -> dict[str, Any]:
        """JSON summary: track model, sizes, operating point, modes below 30 Hz, flags."""
        low = [m.to_dict() for m in self.mode_info
               if m.frequency_hz <= 30.0 and m.representative]
        return {"scenario": self.scenario.name, "speed_kmh": self.scenario.speed_kmh,
                "track": self.track, "n_dof": self.system.n, "n_inputs": self.system.m,
                "points": [p.to_dict() for p in self.points], "modes_below_30_hz": low,
                "static_wheel": self.static_wheel, "quasi_static": self.quasi_static,
                "flags": list(self.flags), "info": self.info,
                "linearisation": (self.quasi_linear.to_dict() if self.quasi_linear is not None
                                  else {"method": "local", "applied": False}),
                "spectra": self.spectra.to_dict() if self.spectra else None}


def linearise(op: OperatingPoint) -> Linearisation:
    """Finite-difference Jacobians of the kernel's forces at ``op``: the full frozen-window
    system and the derivatives of the wheel quantities.
    """
    sys, s, w0 = op.sys, op.s, op.s_win0
    dA_dX, daux_dX, methods_x = refined_state_jacobians(sys, op.X0, op.V0, s, w0)
    dA_dV, daux_dV, methods_v = refined_state_jacobians(sys, op.X0, op.V0, s, w0,
                                                        wrt_velocity=True)
    dA_du, daux_du = irregularity_jacobians(sys, op.X0, op.V0, s, w0)
    speed = float(sys.par.speed)
    full = SecondOrderSystem(K=-dA_dX, C=-dA_dV, B0=dA_du[:, 0::2].copy(),
                             B1=dA_du[:, 1::2] / speed, B2=np.zeros_like(dA_du[:, 0::2]))
    return Linearisation(op, full, 1.0 / sys.minv, daux_dX, daux_dV,
                         daux_du[:, 0::2].copy(), methods_x, methods_v)


def _acceleration_outputs(op: OperatingPoint, veh: VehicleModel, n: int) -> tuple[
        OutputMap, dict[str, dict[str, float]]]:
    """Rows of every recorded point's lateral and vertical acceleration, and the specific
    force there in the steady state.
    """
    sys = op.sys
    names: list[str] = []
    P = np.zeros((2 * len(veh.points), n))
    G = np.zeros_like(P)
    qs: dict[str, dict[str, float]] = {}
    for p, (pname, bi, _m) in enumerate(veh.points):
        o, nd = int(sys.body_off[bi]), int(sys.body_ndof[bi])
        base = int(sys.pt_phi[p])
        phi = sys.phi[base:base + 6 * nd].reshape(6, nd)
        f_y, f_z, _k, _r, _d = frame_specific_force(sys, op.s + sys.body_x[bi])
        body = veh.bodies[bi].name
        names += [Channel(body, pname, "acc", "y").name, Channel(body, pname, "acc", "z").name]
        P[2 * p, o:o + nd] = phi[1]
        P[2 * p + 1, o:o + nd] = phi[2]
        G[2 * p, o:o + nd] = f_z * phi[3]
        G[2 * p + 1, o:o + nd] = -f_y * phi[3]
        rx = float(phi[3] @ op.X0[o:o + nd])
        qs[f"{body}.{pname}"] = {"y": float(f_y + rx * f_z),
                                 "z": float(f_z - rx * f_y - sys.par.gravity)}
    return OutputMap(names, P, G, np.zeros((P.shape[0], 4 * len(veh.wheelsets)))), qs


def _wheel_outputs(op: OperatingPoint, veh: VehicleModel, daux_dX: np.ndarray,
                   daux_du: np.ndarray) -> tuple[OutputMap, dict[str, Any]]:
    """Rows of each wheel's normal force (N) and lateral displacement relative to the rail
    head (m), and their steady values.
    """
    sys = op.sys
    n = op.X0.shape[0]
    names: list[str] = []
    G_rows, D_rows = [], []
    static: dict[str, Any] = {"normal_force": {}, "rel_disp_y": {}}
    for w, b in enumerate(veh.wheelsets):
        wname = veh.bodies[b].name
        o = int(sys.body_off[b])
        for side, sname in enumerate(SIDES):
            row = (2 * w + side) * S.N_AUX
            names.append(Channel(wname, sname, "force", "n").name)
            G_rows.append(daux_dX[row + S.AUX_N])
            D_rows.append(daux_du[row + S.AUX_N])
            g = -daux_dX[row + S.AUX_RAIL_Y].copy()
            g[o + 1] += 1.0
            d = np.zeros(daux_du.shape[1])
            d[4 * w + 2 + side] = -1.0
            names.append(Channel(wname, sname, "rel_disp", "y").name)
            G_rows.append(g)
            D_rows.append(d)
            key = f"{wname}.{sname}"
            static["normal_force"][key] = float(op.aux[w, side, S.AUX_N])
            static["rel_disp_y"][key] = float(op.X0[o + 1] - op.aux[w, side, S.AUX_RAIL_Y])
    static["contact_model"] = ("profiles" if sys.par.contact_model == S.CONTACT_PROFILES
                               else "conical")
    static["flange_clearance_m"] = float(sys.par.flange_clearance)
    Gm = np.array(G_rows)
    return OutputMap(names, np.zeros((len(names), n)), Gm, np.array(D_rows)), static


def _check_stable(lam: np.ndarray, modes: Callable[[], Modes],
                  describe: Callable[[], list[ModeInfo]]) -> None:
    """Refuse a linearised system with a growing mode (hunting above its critical speed):
    ``lam`` its eigenvalues (1/s); ``modes`` and ``describe`` give the eigendecomposition and
    the modes' names to say which one grows.
    """
    if np.any(lam.real > UNSTABLE_RATE):
        full = modes()
        k = int(np.argmax(full.lam.real))
        raise LinearisationError(
            f"the linearised system is unstable: a mode at {full.damped_frequency_hz[k]:.2f} Hz "
            f"({describe()[k].label}) grows at {full.lam.real[k]:.3g} 1/s (hunting?); a "
            "stationary response does not exist", "unstable")


def linear_model(scenario: Scenario, track: TrackModel = "condensed", *,
                 vehicle: VehicleModel | None = None, strict: bool = True,
                 sources: MeasuredSources = LIBRARY,
                 linearisation: LinearisationMethod = DEFAULT_LINEARISATION) -> LinearModel:
    """Linearise ``scenario`` about its steady state on smooth track.

    Parameters
    ----------
    scenario : Scenario
        Validated scenario (rigid or flexible bodies, conical or profile contact, straight or
        curved line; its excitations must be random irregularities).
    track : {"condensed", "modal", "rigid"}
        Track model (:mod:`flexride.frequency.reduce`).
    vehicle : VehicleModel, optional
        A prebuilt vehicle (e.g. flexible bodies already built).
    strict : bool
        Raise :class:`LinearisationError` where the linearisation does not hold (flange
        contact at equilibrium, a non-random excitation); with False those become ``flags``
        and the model is built anyway (an unstable system always raises).
    sources : MeasuredSources
        Where uploaded wheel and rail profiles are read from (default: files by path).
    linearisation : {"statistical", "local"}
        How the contact is linearised (:mod:`flexride.frequency.quasilinear`): with real
        profiles, Gaussian-equivalent gains in each wheel's lateral displacement at the
        response's own σ, iterated (default, :data:`DEFAULT_LINEARISATION`; the conical tread
        is linear and stays local); or local slopes at the operating point.

    Returns
    -------
    LinearModel

    Raises
    ------
    LinearisationError
        See ``strict``; also when no steady state exists, the system is unstable or the
        quasi-linearisation does not converge (``strict``; else a flag).

    Notes
    -----
    BLAS runs on one thread meanwhile (dense problems of a few hundred unknowns: threads
    competing on a loaded machine made them several times slower).
    """
    from flexride.frequency.quasilinear import check_linearisation, with_linearisation

    check_track_model(track)
    check_linearisation(linearisation)
    with small_dense_problems():
        t0 = time.perf_counter()
        flags: list[str] = []
        spectra = spectra_or_flag(scenario, strict, flags, sources)
        asm = assemble(smooth_scenario(scenario), vehicle=vehicle, sources=sources)
        op = operating_point_or_flag(scenario, asm, strict, flags)
        t1 = time.perf_counter()
        model = model_from(scenario, linearise(op), track, spectra, flags, (t0, t1))
        return with_linearisation(model, linearisation, strict)


def check_track_model(track: str) -> None:
    """Refuse an unknown track model (:class:`LinearisationError`, reason ``track``)."""
    if track not in TRACK_MODELS:
        raise LinearisationError(f"unknown track model {track!r}; use one of "
                                 f"{', '.join(TRACK_MODELS)}", "track")


def smooth_scenario(scenario: Scenario) -> Scenario:
    """``scenario`` without its excitations: what is assembled for the linearisation."""
    return scenario.model_copy(update={"excitation": []})


def model_from(scenario: Scenario, lin: Linearisation, track: TrackModel,
               spectra: TrackSpectra | None, flags: list[str], times: tuple[float, float],
               previous: LinearModel | None = None, lazy_modes: bool = False) -> LinearModel:
    """The linear model of ``scenario`` from its linearisation: outputs, track reduction,
    eigenmodes and their names, the stability check.

    Parameters
    ----------
    scenario : Scenario
        The scenario.
    lin : Linearisation
        Its full system at the operating point.
    track : {"condensed", "modal", "rigid"}
        Track model.
    spectra : TrackSpectra or None
        Its random irregularity.
    flags : list of str
        Reasons the estimate may not hold.
    times : (float, float)
        ``time.perf_counter()`` at the start and after the operating point (s).
    previous : LinearModel, optional
        The model of a scenario with the same rail rows and columns (parameter sweeps): its
        track condensation is reused when it fits.
    lazy_modes : bool
        Check the stability on the eigenvalues alone and solve the eigenvectors on first use
        (a model that may never need them: a sweep's local model under the statistical
        linearisation).

    Raises
    ------
    LinearisationError
        The system is unstable.
    """
    op, full = lin.op, lin.full
    veh = op.asm.vehicle
    acc, qs = _acceleration_outputs(op, veh, full.n)
    wheels, static = _wheel_outputs(op, veh, lin.daux_dX, lin.daux_du)
    red: Reduced = reduce_track(full, lin.mass, int(op.sys.par.n_veh), track,
                                previous.reduced if previous is not None else None)
    t2 = time.perf_counter()
    names = [op.asm.dof_names[i] if i >= 0 else f"rail.head{-i}" for i in red.keep]
    modes = functools.cache(red.system.modes)

    def describe() -> list[ModeInfo]:
        return describe_modes(modes(), red.mass, names, veh)

    lam = np.linalg.eigvals(red.system.state_matrix()) if lazy_modes else modes().lam
    _check_stable(lam, modes, describe)
    t3 = time.perf_counter()
    ws_x = np.array([veh.bodies[b].x_ref for b in veh.wheelsets])
    return LinearModel(
        scenario=scenario, track=track, system=red.system, dof_names=names,
        speed=float(scenario.speed_mps), wheelset_x=ws_x, points=list(veh.recorded),
        accelerations=red.outputs(acc), wheels=red.outputs(wheels), static_wheel=static,
        mode_solver=modes, mode_describer=describe, spectra=spectra, quasi_static=qs,
        flags=flags,
        info={"position_m": op.s, "on_arc": op.on_arc, "rail_window_start_m": op.s_win0,
              "n_dof_full": full.n, "n_dof": red.system.n,
              "time_operating_point_s": times[1] - times[0],
              "time_linearise_s": t2 - times[1], "time_modes_s": t3 - t2},
        linearisation=lin, reduced=red)


def spectra_or_flag(scenario: Scenario, strict: bool, flags: list[str],
                    sources: MeasuredSources = LIBRARY) -> TrackSpectra | None:
    """The scenario's stationary irregularities (random, measured: ``sources`` says where
    uploads are read from); a transient excitation raises or is flagged.
    """
    try:
        return track_spectra(scenario, sources=sources)
    except LinearisationError as err:
        if strict and err.reason == "excitation" and scenario.excitation:
            raise
        flags.append(str(err))
        stationary = scenario.model_copy(update={"excitation": [
            e for e in scenario.excitation if e.kind in STATIONARY_KINDS]})
        try:
            return track_spectra(stationary, sources=sources) if stationary.excitation else None
        except LinearisationError as again:  # e.g. a measured record too short for spectra
            flags.append(str(again))
            return None


def operating_point_or_flag(scenario: Scenario, asm: Assembly, strict: bool, flags: list[str],
                            warm: WarmStart | None = None) -> OperatingPoint:
    """The operating point (from ``warm`` when given); with ``strict=False`` flange contact or
    a lost contact there is a flag instead of an error.
    """
    op = solve_operating_point(scenario, asm, warm)
    try:
        check_contact(op.asm, op.X0, op.aux)
    except LinearisationError as err:
        if strict or err.reason not in ("flange_contact", "contact_loss"):
            raise
        flags.append(str(err))
    return op
