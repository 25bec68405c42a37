"""The time-step check of a run: the largest step for which the kernel's own one-step map
is stable at the operating points the run meets, and the step ``solver.dt: auto`` takes.

Operating points (:func:`operating_points`, on smooth track): the steady rolling state where
the run starts (every acceleration zero with the wheelsets' spin rates balancing their
longitudinal creep forces — not the static equilibrium at rest: the rolling state's creep
forces set the limit 1.3 % lower with S1002/60E1, as the kernel does) and, on a curve the run
reaches, the steady curving state with its contact points, flange contact included, at the
middle of the arc (:func:`curving_position`). A run has one speed, its lowest
and highest at once; the creep damping it sets (∝ 1/V) is in the map.

At each point the map's blocks are central differences of the kernel's force evaluation with
the step's creep relaxation (:func:`kernel_blocks`) and the limit is found as
:mod:`flexride.solver.step_map` describes: the first step at which an eigenvalue reaches −1,
then the whole map's eigenvalues checked at the step returned. The limit of the run is the
smallest over its points, :data:`LIMIT_MARGIN` below the crossing (the finite differences and
the linearisation of a nonlinear, time-varying system).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from flexride.errors import StabilityError
from flexride.scenario.line import CurvedLine
from flexride.scenario.scenario import Scenario
from flexride.scenario.solver import AUTO, AUTO_FRACTION
from flexride.solver import step_map as sm
from flexride.solver.assemble import Assembly
from flexride.solver.forces import evaluate
from flexride.solver.linearise import step_jacobian_columns, workspace
from flexride.solver.symmetry import Half, coordinate_partners, creep_partners, mirror_halves

#: The limit lies this fraction below the first crossing of the unit circle, by the kind of
#: operating point: what covers the spread of the kernel's own limit (bisected on the kernel,
#: ``tools/studies/step_limit_vs_kernel.py``) about the frozen linearisation — within 0.5 % in
#: steady rolling on straight track; −2.3 … +0.8 % in steady curving, where the wheels move
#: through the rail window and over the fasteners with the flange in contact.
LIMIT_MARGIN = {"rolling": 0.005, "curving": 0.015}
#: No step above this is considered (s): the schema's largest step.
STEP_CEILING = 1.0e-2
#: The step the map's blocks are differenced at and its limit's search starts from (s); only
#: the speed of the search depends on it.
TRIAL_STEP = 1.0e-4


class KernelBlocks:
    """The blocks of the kernel's one-step map at (X, V) (m, rad; m/s, rad/s) with the vehicle
    centre at ``s`` and the rail window at ``s_win0`` (m), as a function of the step (s).

    The creep state is the steady one at (X, V). The blocks are central differences at one step
    h (:data:`TRIAL_STEP`); for any other step they follow exactly from the structure of the
    relaxation (``forces._relax_creep_state``): with e = e^(−Δt/τ) per creep state, the new
    creep state is (1 − e)·f(X, V) + e·c_prev and the accelerations are linear in it, so

    * ∂c/∂c_prev = diag(e) (τ from e_h),
    * ∂c/∂X, ∂c/∂V scale with (1 − e)/(1 − e_h) and ∂A/∂c_prev with e/e_h,
    * ∂A/∂X and ∂A/∂V gain ∂A/∂c_prev(h)/e_h · diag(e_h − e) · ∂c/∂(X, V)(h)/(1 − e_h)

    (at the steady state the derivative of τ with the normal load multiplies c_prev − f = 0).
    Creep states that nothing depends on (a slot without contact, the unused second slot of
    the conical model) are left out: ``creep_index`` holds the flat indices (into the creep
    state of shape ``creep_shape``) of those kept.
    """

    def __init__(self, asm: Assembly, X: np.ndarray, V: np.ndarray, s: float, s_win0: float):
        sys = asm.sys
        n = X.shape[0]
        F, A, aux, sn, cst = workspace(sys)
        evaluate(sys, X.copy(), V.copy(), s, s_win0, F, A, aux, sn, cst, 0.0)  # steady
        out = np.empty((n + cst.size, 2 * n + cst.size))
        step_jacobian_columns(sys, X.copy(), V.copy(), cst.copy(), s, s_win0, TRIAL_STEP,
                              sm.H_STATE, sm.H_CREEP, out)
        self.creep_shape = cst.shape
        self.creep_index = k = _live_creep_states(out, n)
        self._h = sm.StepJacobian(out[:n, :n], out[:n, n:2 * n], out[:n, 2 * n:][:, k],
                                  out[n:, :n][k], out[n:, n:2 * n][k],
                                  out[n:, 2 * n:][np.ix_(k, k)])
        self._e_h = np.diag(self._h.cc).copy()
        self._tau = -TRIAL_STEP / np.log(self._e_h)

    def __call__(self, dt: float) -> sm.StepJacobian:
        """The blocks for the step ``dt`` (s)."""
        h, e_h = self._h, self._e_h
        if dt == TRIAL_STEP:
            return h
        e = np.exp(-dt / self._tau)
        grow = (1.0 - e) / (1.0 - e_h)
        extra = (h.ac * ((e_h - e) / (e_h * (1.0 - e_h)))[None, :])
        return sm.StepJacobian(h.ax + extra @ h.cx, h.av + extra @ h.cv, h.ac * (e / e_h),
                               h.cx * grow[:, None], h.cv * grow[:, None], np.diag(e))


def _live_creep_states(out: np.ndarray, n: int) -> np.ndarray:
    """Indices of the creep states that act on the accelerations or change with the state."""
    acts = np.any(out[:n, 2 * n:] != 0.0, axis=0)
    moves = np.any(out[n:, :2 * n] != 0.0, axis=1)
    return np.flatnonzero(acts | moves)


@dataclass(frozen=True)
class PointLimit:
    """The step limit at one operating point.

    Attributes
    ----------
    dt_max : float
        Largest step (s) the map is stable for (:data:`LIMIT_MARGIN` below the crossing).
    radius : float
        Largest |μ| of the unresolved eigenvalues at ``dt_max`` (-).
    frequency_hz : float
        Frequency of the mode that limits the step (Hz; 1/(2Δt) for a period-two mode).
    coordinate : str
        The coordinate with the largest share of that mode's kinetic energy.
    kind : str
        ``period-two`` (an eigenvalue reaching −1), ``complex`` (a pair leaving the unit
        circle elsewhere, found on the whole map) or ``ceiling`` (stable up to
        :data:`STEP_CEILING`).
    """

    dt_max: float
    radius: float
    frequency_hz: float
    coordinate: str
    kind: str


def point_limit(blocks_at: sm.BlocksAt, psi: float, phi: float,
                describe: Callable[[np.ndarray], str], margin: float = LIMIT_MARGIN["rolling"]
                ) -> PointLimit:
    """The largest stable step at one operating point (module docs of :mod:`step_map`),
    ``margin`` (fraction) below the crossing.

    ``describe`` names the coordinate that dominates a mode shape (coordinates, m or rad).
    """
    crossing = sm.first_period_two_step(blocks_at, psi, phi, TRIAL_STEP, STEP_CEILING)
    kind = "period-two" if crossing < STEP_CEILING else "ceiling"
    dt = crossing * (1.0 - margin) if kind == "period-two" else STEP_CEILING
    mu, _ = sm.map_eigen(blocks_at(dt), dt, psi, phi)
    radius, _k = sm.numerical_radius(mu)
    if radius > 1.0 + sm.RADIUS_TOL:
        return _bisect_whole_map(blocks_at, psi, phi, dt, describe)
    shape = _period_two_shape(blocks_at(dt), dt, psi, phi) if kind == "period-two" else None
    coordinate = describe(shape) if shape is not None else ""
    freq = 0.5 / dt if kind == "period-two" else 0.0
    return PointLimit(dt, radius, freq, coordinate, kind)


def _period_two_shape(jac: sm.StepJacobian, dt: float, psi: float, phi: float) -> np.ndarray:
    """The mode shape (coordinates) of the eigenvalue nearest −1: the vector T(−1; Δt) maps
    nearest to zero (three steps of inverse iteration).
    """
    import scipy.linalg as sla

    t = sm.period_two_matrix(jac, dt, psi, phi)
    lu = sla.lu_factor(t)
    v: np.ndarray = np.random.default_rng(0).standard_normal((t.shape[0],))
    for _ in range(3):
        w = np.asarray(sla.lu_solve(lu, v))
        v = w / np.linalg.norm(w)
    return v


def _bisect_whole_map(blocks_at: sm.BlocksAt, psi: float, phi: float, unstable: float,
                      describe: Callable[[np.ndarray], str]) -> PointLimit:
    """The limit by bisection on the whole map's eigenvalues below the step ``unstable``,
    where an eigenvalue has left the unit circle away from −1.
    """
    def radius(dt: float) -> float:
        return sm.numerical_radius(sm.map_eigen(blocks_at(dt), dt, psi, phi)[0])[0]

    lo = unstable
    while radius(lo) > 1.0 + sm.RADIUS_TOL:
        lo *= 0.5
    hi = 2.0 * lo if 2.0 * lo < unstable else unstable
    while hi - lo > sm.STEP_RTOL * hi:
        mid = 0.5 * (lo + hi)
        if radius(mid) > 1.0 + sm.RADIUS_TOL:
            hi = mid
        else:
            lo = mid
    mu, vec = sm.map_eigen(blocks_at(hi), hi, psi, phi, vectors=True)
    _r, k = sm.numerical_radius(mu)
    assert vec is not None
    n = blocks_at(hi).n
    shape = np.abs(vec[:n, k])
    freq = abs(math.atan2(mu[k].imag, mu[k].real)) / (2.0 * math.pi * hi)
    return PointLimit(lo, radius(lo), freq, describe(shape), "complex")


def _mirror_halves(asm: Assembly, blocks: KernelBlocks) -> tuple[Half, Half] | None:
    """The map's symmetric and antisymmetric halves where it is mirror-symmetric
    (:mod:`flexride.solver.symmetry`), else None.
    """
    return mirror_halves(blocks(TRIAL_STEP), coordinate_partners(asm.dof_names),
                         creep_partners(blocks.creep_index, blocks.creep_shape),
                         asm.dof_names.index(f"{asm.vehicle.bodies[0].name}.z"))


def _projected(blocks: sm.BlocksAt, half: Half) -> sm.BlocksAt:
    """``blocks`` in the basis of ``half``."""
    return lambda dt: half.project(blocks(dt))


def _expanded(describe: Callable[[np.ndarray], str], half: Half
              ) -> Callable[[np.ndarray], str]:
    """``describe`` of a mode shape given in the basis of ``half``."""
    return lambda shape: describe(half.expand(shape))


def dominant_coordinate(asm: Assembly) -> Callable[[np.ndarray], str]:
    """A function naming where a mode shape ``x`` (coordinates of ``asm``) has the largest
    kinetic-energy share m·x²: the vehicle coordinate, or a rail and direction (its modal
    coordinates summed) followed by the vehicle coordinate that moves most with it.
    """
    energy_of = 1.0 / asm.sys.minv
    nv = int(asm.sys.par.n_veh)
    nm = int(asm.sys.par.n_rail_modes)
    blocks = [f"{rail} rail {d}" for rail in ("left", "right")
              for d in ("vertical", "lateral", "torsion")]

    def name(shape: np.ndarray) -> str:
        energy = energy_of * np.abs(shape) ** 2
        vehicle = asm.dof_names[int(np.argmax(energy[:nv]))]
        rail = energy[nv:].reshape(6, nm).sum(axis=1)
        if rail.max() <= energy[:nv].max():
            return vehicle
        return f"{blocks[int(np.argmax(rail))]} with {vehicle}"

    return name


def stability_limit(asm: Assembly, X0: np.ndarray, s: float, s_win0: float,
                    V0: np.ndarray | None = None, point: str = "static equilibrium",
                    margin: float = LIMIT_MARGIN["rolling"]) -> dict:
    """The step limit of the kernel's one-step map linearised at (X0, V0), ``margin``
    (fraction) below the crossing (module docs).

    Returns
    -------
    dict
        ``dt_max`` (s), ``critical_dof`` (coordinate dominating the limiting mode),
        ``critical_frequency_hz``, ``kind``, ``radius`` (the map's largest unresolved |μ| at
        ``dt_max``) and ``point`` (the operating point), a JSON-ready dict (it is cached).
    """
    V = np.zeros_like(X0) if V0 is None else V0
    par = asm.sys.par
    blocks = KernelBlocks(asm, X0, V, s, s_win0)
    describe = dominant_coordinate(asm)
    halves = _mirror_halves(asm, blocks)
    if halves is None:
        lim = point_limit(blocks, par.psi, par.phi, describe, margin)
    else:
        lim = min((point_limit(_projected(blocks, h), par.psi, par.phi, _expanded(describe, h),
                               margin) for h in halves), key=lambda p: p.dt_max)
    return {"dt_max": lim.dt_max, "critical_dof": lim.coordinate,
            "critical_frequency_hz": lim.frequency_hz, "kind": lim.kind,
            "radius": lim.radius, "point": point, "method": "one-step map"}


def auto_step(dt_max: float, output_interval: float) -> float:
    """The step ``solver.dt: auto`` takes: the output interval (s) divided by the smallest
    whole number that brings it to :data:`AUTO_FRACTION` of ``dt_max`` (s) or below.
    """
    k = max(1, math.ceil(output_interval / (AUTO_FRACTION * dt_max) - 1e-9))
    return output_interval / k


def curving_position(scenario: Scenario, s_start: float = 0.0) -> float | None:
    """Where a run that meets a curve is linearised in steady curving: the middle of the arc
    (vehicle-centre position, m), the curve's full curvature and cant deficiency, also for a
    run that ends in the transition (conservative); None on straight track or when the run ends
    before the curve begins.
    """
    line = scenario.line
    if not isinstance(line, CurvedLine):
        return None
    if s_start + scenario.speed_mps * scenario.duration <= line.start_m:
        return None
    return float(line.start_m + line.entry_transition_m + 0.5 * line.arc_length_m)


@dataclass(frozen=True)
class OperatingPoint:
    """Where a run is linearised: the vehicle centre at ``s`` (m) on smooth track in steady
    rolling or, on a curve, steady ``curving``.
    """

    s: float
    curving: bool

    @property
    def label(self) -> str:
        """What the stability record calls it."""
        return f"steady {'curving' if self.curving else 'rolling'} at s = {self.s:g} m"

    @property
    def margin(self) -> float:
        """:data:`LIMIT_MARGIN` of its kind."""
        return LIMIT_MARGIN["curving" if self.curving else "rolling"]


def operating_points(scenario: Scenario, s_start: float = 0.0) -> list[OperatingPoint]:
    """The run's operating points: the steady rolling where it starts, and steady curving at
    :func:`curving_position` if it meets a curve. Each is taken on smooth track (the
    irregularities are the excitation, not the system), so the realisations of a condition
    share their limit.
    """
    points = [OperatingPoint(s_start, False)]
    s = curving_position(scenario, s_start)
    return points if s is None else [*points, OperatingPoint(s, True)]


def combine(limits: list[dict]) -> dict:
    """The run's limit: the operating point with the smallest ``dt_max``."""
    return dict(min(limits, key=lambda d: d["dt_max"]))


def resolve_step(scenario: Scenario, info: dict | None, output_interval: float
                 ) -> tuple[float, dict | None]:
    """The run's step (s) and its stability record: ``solver.dt: auto`` takes
    :func:`auto_step` of the limit ``info`` (which it needs), a given step is checked against
    it (:func:`check_step`) when there is one.
    """
    dt = scenario.solver.dt
    if info is None:
        if dt == AUTO:
            raise ValueError("solver.dt: auto needs the stability limit")
        return float(dt), None
    info = {**info, "dt_suggested": auto_step(info["dt_max"], output_interval)}
    if dt == AUTO:
        step = info["dt_suggested"]
        return step, {**info, "dt": step, "margin": info["dt_max"] / step, "auto": True}
    return float(dt), {**check_step(info, float(dt)), "auto": False}


def check_step(info: dict, dt: float) -> dict:
    """Raise :class:`StabilityError` if the step ``dt`` (s) exceeds the limit ``info`` of
    :func:`stability_limit` (with ``dt_suggested``, the step auto would take); return
    ``info`` with the step's margin ``dt_max / dt``.
    """
    if dt > info["dt_max"]:
        mode = (f"a period-two ({info['critical_frequency_hz'] / 1000:.1f} kHz) oscillation "
                if info.get("kind") == "period-two" else
                f"a {info['critical_frequency_hz']:.0f} Hz mode ")
        raise StabilityError(
            f"time step solver.dt = {dt:g} s is beyond the stability limit of the solver's "
            f"one-step map: the largest stable step is {info['dt_max']:.3g} s "
            f"({info.get('point', 'static equilibrium')}), set by {mode}of the "
            f"{info['critical_dof']}; use solver.dt = auto or {info['dt_suggested']:g} s",
            dt=dt,
            dt_max=info["dt_max"],
            dt_suggested=info["dt_suggested"],
        )
    return {**info, "dt": dt, "margin": info["dt_max"] / dt}
