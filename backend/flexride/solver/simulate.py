"""``simulate(scenario) -> Results``: assemble, find static equilibrium, check the time step,
integrate in chunks (progress and cancellation between chunks), collect the channels.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from contextlib import AbstractContextManager
from dataclasses import dataclass
from typing import Any

import numpy as np

from flexride.errors import SimulationCancelled, SimulationError
from flexride.results import Results
from flexride.scenario.fidelity import cutoff_notes
from flexride.scenario.scenario import Scenario
from flexride.scenario.solver import AUTO
from flexride.solver import system as S
from flexride.solver.assemble import (
    Assembly,
    assemble,
    flexible_body_facts,
    output_rate_for,
    with_step,
)
from flexride.solver.estimate import check_steps
from flexride.solver.kernel import (
    STATUS_CHATTER,
    STATUS_FULL,
    STATUS_NONFINITE,
    STATUS_OK,
    STATUS_RUNAWAY,
    run_chunk,
)
from flexride.solver.setup_cache import SetupCache, default_cache, run_setup
from flexride.solver.stability import OperatingPoint, combine, operating_points, resolve_step
from flexride.solver.static import initial_window_start
from flexride.solver.steady import smooth_assembly
from flexride.track.measured import LIBRARY, MeasuredSources
from flexride.vehicle.topology import VehicleModel

ProgressCallback = Callable[[float, str], None]
CancelCallback = Callable[[], bool]

CONTACT_TABLES: dict[str, Any] = {}
"""Contact tables kept between the runs of this process (``assemble(contact_tables=…)``: by
their inputs, at most :data:`~flexride.solver.assemble.MAX_KEPT_CONTACTS`)."""

_DEFAULT = object()


def _static_wheel_loads(asm: Assembly, X0: np.ndarray, s_win0: float) -> list[list[float]]:
    from flexride.solver.forces import evaluate
    from flexride.solver.linearise import workspace

    F, A, aux, sn, cst = workspace(asm.sys)
    evaluate(asm.sys, X0.copy(), np.zeros_like(X0), 0.0, s_win0, F, A, aux, sn, cst, 0.0)
    return [[float(aux[w, 0, S.AUX_FZ]), float(aux[w, 1, S.AUX_FZ])] for w in range(aux.shape[0])]


def small_dense_problems() -> AbstractContextManager[Any]:
    """One BLAS thread for the setup of a run (assembly, static equilibrium, stability check):
    dense problems of a few hundred unknowns gain nothing from threads, and on a loaded machine
    competing BLAS threads made each 461 × 461 solve 100 times slower (0.35 s against 3.5 ms;
    a whole preflight 1.24 s against 0.36 s).
    """
    from threadpoolctl import threadpool_limits

    return threadpool_limits(limits=1, user_api="blas")


def preflight(scenario: Scenario, vehicle: VehicleModel | None = None,
              sources: MeasuredSources = LIBRARY, setup_cache: Any = _DEFAULT) -> dict:
    """Check a scenario without running it: assembly, static equilibrium and the time-step
    stability limit (raises :class:`~flexride.errors.StabilityError` with a step that works).

    Returns
    -------
    dict
        ``n_dof``, ``n_steps``, ``output_rate`` (Hz), ``stability`` (see
        :func:`~flexride.solver.stability.stability_limit`) and ``static_wheel_loads`` (N).
        ``setup_cache`` as for :func:`simulate`.
    """
    with small_dense_problems():
        asm = assemble(scenario, vehicle=vehicle, sources=sources, contact_tables=CONTACT_TABLES)
        asm, ready = prepare_run(scenario, asm, _cache(setup_cache), check=True)
    X0, stab, s_win0 = ready.X0, ready.stability, ready.s_win0
    return {"n_dof": int(X0.size), "n_steps": int(asm.n_steps), "output_rate": asm.output_rate,
            "stability": stab, "static_wheel_loads": _static_wheel_loads(asm, X0, s_win0)}


def simulate(
    scenario: Scenario,
    progress: ProgressCallback | None = None,
    cancel: CancelCallback | None = None,
    vehicle: VehicleModel | None = None,
    sources: MeasuredSources = LIBRARY,
    setup_cache: Any = _DEFAULT,
    max_steps: int | None = None,
) -> Results:
    """Simulate the vehicle running over the track of ``scenario``.

    Parameters
    ----------
    scenario : Scenario
        Validated scenario.
    progress : callable(fraction, message), optional
        Called after every chunk of ``solver.progress_every_steps`` steps with the fraction done
        (0–1) and a short message.
    cancel : callable() -> bool, optional
        Polled after every chunk; returning True stops the run with
        :class:`~flexride.errors.SimulationCancelled`.
    vehicle : VehicleModel, optional
        Prebuilt vehicle (e.g. with flexible bodies) instead of the scenario's rigid one.
    sources : MeasuredSources
        Where measured irregularities may be read from (default: files by path; the service
        passes its upload store and forbids paths).
    setup_cache : SetupCache or None, optional
        Where the static equilibrium and the stability limit are kept by content
        (:mod:`flexride.solver.setup_cache`); default the process-wide cache
        (``$FLEXRIDE_SETUP_CACHE``), None computes them.
    max_steps : int, optional
        Refuse (:class:`~flexride.errors.ScenarioError`) a run of more steps, once the step is
        known (the service's bound; ``solver.dt: auto`` chooses it in the set-up).

    Returns
    -------
    Results
        Decimated channels (accelerations m/s², forces N, displacements m, rotations rad).

    Raises
    ------
    StabilityError
        The time step is beyond the explicit method's stability limit.
    SimulationError
        The run diverged (NaN, inf or runaway displacement), with the time and the quantity.
    SimulationCancelled
        ``cancel()`` returned True.
    """
    t_start = time.perf_counter()
    report = progress or (lambda f, m: None)
    report(0.0, "assembling")
    with small_dense_problems():
        asm = assemble(scenario, vehicle=vehicle, sources=sources, contact_tables=CONTACT_TABLES)
        report(0.0, "static equilibrium and time-step check")
        asm, ready = prepare_run(scenario, asm, _cache(setup_cache),
                                 check=scenario.solver.check_stability)
    if max_steps is not None:
        check_steps(scenario, float(asm.sys.par.dt), max_steps)
    t_ready = time.perf_counter()

    V0 = convected_rail_velocity(asm, ready.X0)
    return integrate(asm, ready.X0, V0, scenario, report, cancel, ready.stability, t_start,
                     t_ready, setup_source=ready.source)


@dataclass(frozen=True)
class ReadyRun:
    """What a run starts from, once its set-up is done.

    Attributes
    ----------
    X0 : numpy.ndarray
        Static equilibrium where the run starts (m, rad).
    s_win0 : float
        Rail-window start at t = 0 (m).
    stability : dict or None
        The step's stability record (:func:`~flexride.solver.stability.resolve_step`: the
        limit over the run's operating points, the step and its margin), None when neither
        checked nor needed.
    source : str
        Where the static equilibrium came from (``computed``, ``memory``, ``disk``).
    """

    X0: np.ndarray
    s_win0: float
    stability: dict | None
    source: str


def prepare_run(scenario: Scenario, asm: Assembly, cache: SetupCache | None, check: bool
                ) -> tuple[Assembly, ReadyRun]:
    """The set-up of a run: static equilibrium, the time-step limit over the run's operating
    points (:mod:`flexride.solver.stability`; when ``check`` or when ``solver.dt: auto`` needs
    it) and the step; returns ``asm`` running with that step.

    Raises
    ------
    StabilityError
        A given step beyond the limit.
    """
    s_win0 = initial_window_start(asm, 0.0)
    setup = run_setup(asm, 0.0, s_win0, False, cache)
    limit = None
    if check or scenario.solver.dt == AUTO:
        limit = combine([_point_limit(scenario, asm, point, cache)
                         for point in operating_points(scenario, float(asm.sys.par.s_start))])
    # the interval an automatic step divides (also for the step a refusal suggests)
    dt, info = resolve_step(scenario, limit, 1.0 / output_rate_for(scenario, AUTO))
    return with_step(asm, scenario, dt), ReadyRun(setup.X0, s_win0, info, setup.source)


def _point_limit(scenario: Scenario, asm: Assembly, point: OperatingPoint,
                 cache: SetupCache | None) -> dict:
    """The step limit at an operating point of the run, on smooth track."""
    smooth = smooth_assembly(asm, point.s, scenario.line,
                             scenario.track.rail_centre_half_distance)
    setup = run_setup(smooth, point.s, initial_window_start(smooth, point.s), True, cache,
                      steady=True, point=point)
    assert setup.stability is not None  # asked for
    return setup.stability


def _cache(setup_cache: Any) -> SetupCache | None:
    """The set-up cache a caller asked for (the process-wide one by default)."""
    return default_cache() if setup_cache is _DEFAULT else setup_cache


def convected_rail_velocity(asm: Assembly, X0: np.ndarray) -> np.ndarray:
    """Initial velocities for a vehicle already moving at the running speed: the static
    deflection basin of each rail travels with the wheels, w(x − Vt), so ẇ = −V·∂w/∂x.

    Projected on the rail modes through the fastener values (discrete sine transform).
    """
    sysarr = asm.sys
    V0 = np.zeros_like(X0)
    nv = sysarr.par.n_veh
    nm = sysarr.par.n_rail_modes
    kap = sysarr.rail_kap
    xj = np.arange(1, nm + 1) * asm.rail.spacing
    cosm = np.cos(np.outer(xj, kap))
    speed = sysarr.par.speed
    for blk in range(6):
        o = nv + blk * nm
        slope = cosm @ (kap * X0[o : o + nm])
        V0[o : o + nm] = (2.0 / (nm + 1)) * (sysarr.rail_dst.T @ (-speed * slope))
    return V0


@dataclass
class _Workspace:
    """State and scratch arrays of one run, in the argument order of :func:`run_chunk`.

    Units follow the DOF vector: X in m or rad, V in m/s or rad/s, A in m/s² or rad/s²,
    F in N or N·m; the recording buffers hold the channels in their own units, time in s and
    distance in m.
    """

    X: np.ndarray
    V: np.ndarray
    A: np.ndarray
    Ap: np.ndarray
    F: np.ndarray
    aux: np.ndarray
    sn: np.ndarray
    cst: np.ndarray
    facc: np.ndarray
    eacc: np.ndarray
    ptv: np.ndarray
    pscr: np.ndarray
    X_ref: np.ndarray
    u: np.ndarray
    q: np.ndarray
    tstate: np.ndarray
    rec: np.ndarray
    rec_t: np.ndarray
    rec_s: np.ndarray
    info: np.ndarray
    watch: np.ndarray


def _workspace(asm: Assembly, X0: np.ndarray, V0: np.ndarray, X_ref: np.ndarray,
               s_win0: float) -> _Workspace:
    """Allocate the run's arrays, starting from (X0, V0) with the rail window at ``s_win0``.

    Parameters
    ----------
    asm : Assembly
        Assembled model (sizes of the DOF vector, wheels, rail modes, points and channels).
    X0, V0 : numpy.ndarray
        Initial displacements (m, rad) and velocities (m/s, rad/s); copied.
    X_ref : numpy.ndarray
        Reference displacements (m, rad) for the displacement channels and runaway checks.
    s_win0 : float
        Start of the rail window at t = 0 (m).

    Returns
    -------
    _Workspace
        Zeroed scratch arrays and recording buffers for ``asm.n_steps // n_dec`` records.
    """
    sysarr = asm.sys
    n = X0.shape[0]
    nw = sysarr.ws_body.shape[0]
    nm = sysarr.rail_kap.shape[0]
    npnt = sysarr.pt_body.shape[0]
    tstate = np.zeros(S.N_TSTATE)
    tstate[S.T_WIN_S0] = s_win0
    n_rec = asm.n_steps // sysarr.par.n_dec
    nch = len(asm.channel_names)
    return _Workspace(
        X=X0.copy(),
        V=V0.copy(),
        A=np.zeros(n),
        Ap=np.zeros(n),
        F=np.zeros(n),
        aux=np.zeros((nw, 2, S.N_AUX)),
        sn=np.zeros(nm),
        cst=np.zeros((nw, 2, S.N_CST)),
        facc=np.zeros((nw, 2, S.N_FACC)),
        eacc=np.zeros((sysarr.el_force.shape[0], 3)),
        ptv=np.zeros((npnt, 2)),
        pscr=np.zeros((npnt, 2)),
        X_ref=X_ref,
        u=np.zeros(nm),
        q=np.zeros(nm),
        tstate=tstate,
        rec=np.zeros((n_rec, nch)),
        rec_t=np.zeros(n_rec),
        rec_s=np.zeros(n_rec),
        info=np.zeros(2, dtype=np.int64),
        watch=np.zeros((nw, 2, S.N_WATCH_Q, S.N_WATCH_F)),
    )


def _check_status(status: int, asm: Assembly, scenario: Scenario, ws: _Workspace) -> None:
    """Raise :class:`~flexride.errors.SimulationError` for a diverged or failed chunk.

    Parameters
    ----------
    status : int
        Status returned by :func:`run_chunk`.
    asm : Assembly
        Assembled model (DOF names for the message).
    scenario : Scenario
        The scenario (runaway limit in m for the message).
    ws : _Workspace
        The run's arrays (time in s and offending DOF index).
    """
    tstate = ws.tstate
    if status in (STATUS_NONFINITE, STATUS_RUNAWAY):
        what = asm.dof_names[int(ws.info[0])]
        kind = (
            "became NaN or infinite"
            if status == STATUS_NONFINITE
            else (
                f"exceeded {scenario.solver.runaway_displacement_m:g} m from static equilibrium"
            )
        )
        raise SimulationError(
            f"the run diverged at t = {tstate[S.T_TIME]:.4f} s: coordinate {what} {kind}; "
            f"try a smaller solver.dt or check the parameters"
        )
    if status == STATUS_CHATTER:
        raise SimulationError(_chatter_message(asm, ws))
    if status not in (STATUS_OK, STATUS_FULL):
        raise SimulationError(f"kernel returned unknown status {status}")


def _chatter_message(asm: Assembly, ws: _Workspace) -> str:
    """What the run-time watch saw (:func:`~flexride.solver.kernel._watch`), in one line."""
    w, side = divmod(int(ws.info[0]), 2)
    q = int(ws.info[1])
    wheelset = asm.vehicle.bodies[asm.vehicle.wheelsets[w]].name
    what = "lateral creep force" if q == S.W_CREEP_Y else "normal force"
    size = abs(float(ws.watch[w, side, q, S.W_CHANGE]))
    dt = float(asm.sys.par.dt)
    return (f"the run became numerically unstable at t = {ws.tstate[S.T_TIME]:.4f} s: the "
            f"{what} of the {('left', 'right')[side]} wheel of {wheelset} alternated from step "
            f"to step for {S.CHATTER_STEPS} steps (last change {size:.3g} N), a period-two "
            f"chatter the step does not integrate; use solver.dt = {dt / 2:.3g} s")


def _run_chunks(asm: Assembly, scenario: Scenario, ws: _Workspace, report: ProgressCallback,
                cancel: CancelCallback | None) -> int:
    """Step the kernel in chunks of ``solver.progress_every_steps`` until the run is done.

    Parameters
    ----------
    asm : Assembly
        Assembled model.
    scenario : Scenario
        The scenario (chunk size, duration in s).
    ws : _Workspace
        The run's arrays, advanced in place.
    report : callable(fraction, message)
        Progress callback, called after every chunk.
    cancel : callable() -> bool, optional
        Polled after every chunk.

    Returns
    -------
    int
        Number of time steps done.
    """
    chunk = int(scenario.solver.progress_every_steps)
    done = 0
    tstate = ws.tstate
    while done < asm.n_steps:
        steps = min(chunk, asm.n_steps - done)
        status = run_chunk(
            asm.sys,
            ws.X,
            ws.V,
            ws.A,
            ws.Ap,
            ws.F,
            ws.aux,
            ws.sn,
            ws.cst,
            ws.facc,
            ws.eacc,
            ws.ptv,
            ws.pscr,
            ws.X_ref,
            ws.u,
            ws.q,
            tstate,
            steps,
            ws.rec,
            ws.rec_t,
            ws.rec_s,
            ws.info,
            ws.watch,
        )
        done = int(tstate[S.T_STEP])
        _check_status(status, asm, scenario, ws)
        frac = done / asm.n_steps
        report(frac, f"t = {tstate[S.T_TIME]:.2f} s of {scenario.duration:.2f} s")
        if cancel is not None and cancel():
            raise SimulationCancelled(f"cancelled at t = {tstate[S.T_TIME]:.3f} s")
        if status == STATUS_FULL:
            break
    return done


def _collect(asm: Assembly, scenario: Scenario, ws: _Workspace, meta: dict) -> Results:
    """Package the recorded channels of a finished run.

    Parameters
    ----------
    asm : Assembly
        Assembled model (channel names and units, recorded points).
    scenario : Scenario
        The scenario (stored with the results).
    ws : _Workspace
        The run's arrays after the last chunk.
    meta : dict
        Run metadata (see :func:`integrate`).

    Returns
    -------
    Results
        The first ``T_NREC`` records: time (s), distance (m) and every channel.
    """
    k = int(ws.tstate[S.T_NREC])
    channels = {
        name: np.ascontiguousarray(ws.rec[:k, i]) for i, name in enumerate(asm.channel_names)
    }
    units = dict(zip(asm.channel_names, asm.channel_units, strict=True))
    return Results(
        time=ws.rec_t[:k].copy(),
        distance=ws.rec_s[:k].copy(),
        channels=channels,
        units=units,
        scenario=scenario.model_dump(mode="json"),
        meta=meta,
        points=[p.to_dict() for p in asm.vehicle.recorded],
    )


def integrate(
    asm: Assembly,
    X0: np.ndarray,
    V0: np.ndarray,
    scenario: Scenario,
    report: ProgressCallback,
    cancel: CancelCallback | None = None,
    stab: dict | None = None,
    t_start: float | None = None,
    t_ready: float | None = None,
    X_ref: np.ndarray | None = None,
    final_state: dict | None = None,
    setup_source: str | None = None,
) -> Results:
    """Integrate from the state (X0, V0) at t = 0 and collect the results.

    ``X_ref`` (default ``X0``) is the reference for displacement channels and runaway checks;
    ``final_state``, if given, receives the final ``X`` and ``V``; ``setup_source`` (where
    the static equilibrium and the stability limit came from, :class:`~flexride.solver.
    setup_cache.Setup`) goes into the metadata.
    """
    if not asm.step_chosen:
        raise ValueError("solver.dt: auto: choose the step first (prepare_run or with_step)")
    t_start = time.perf_counter() if t_start is None else t_start
    t_ready = time.perf_counter() if t_ready is None else t_ready
    s_win0 = initial_window_start(asm, 0.0)
    X_ref = X0.copy() if X_ref is None else X_ref
    ws = _workspace(asm, X0, V0, X_ref, s_win0)

    from flexride.solver.forces import evaluate

    evaluate(asm.sys, ws.X, ws.V, 0.0, s_win0, ws.F, ws.A, ws.aux, ws.sn, ws.cst, 0.0)
    t_loop = time.perf_counter()
    cpu_loop = time.process_time()
    done = _run_chunks(asm, scenario, ws, report, cancel)
    t_end = time.perf_counter()
    cpu_end = time.process_time()
    if final_state is not None:
        final_state["X"] = ws.X.copy()
        final_state["V"] = ws.V.copy()
    meta = {
        "speed_mps": scenario.speed_mps,
        "speed_kmh": scenario.speed_kmh,
        "dt": float(asm.sys.par.dt),
        "output_rate": asm.output_rate,
        "n_steps": done,
        "n_dof": int(X0.shape[0]),
        "rail_modes_per_direction": int(asm.sys.rail_kap.shape[0]),
        "rail_window_m": float(asm.rail.length),
        "static_wheel_loads": _static_wheel_loads(asm, X_ref, s_win0),
        "stability": stab,
        "wall_time_setup_s": t_ready - t_start,
        "setup_source": setup_source,
        "wall_time_solve_s": t_end - t_loop,
        "cpu_time_solve_s": cpu_end - cpu_loop,
        "output_points": [p[0] for p in asm.vehicle.points if p[1] == 0],
        "friction": scenario.contact.friction,
        "flange_angle_rad": None if asm.profiles is None else asm.profiles.flange_angle(),
        "notes": cutoff_notes(scenario),
        "flexible_bodies": flexible_body_facts(scenario, asm.vehicle),
    }
    report(1.0, "done")
    return _collect(asm, scenario, ws, meta)
