"""The kernel itself as the judge of a time step: run it from an operating point of the
time-step check on a perfect track with a small perturbation and watch whether the
perturbation dies out.

The measure is the step-to-step change of the wheels' lateral creep and normal forces (the
run-time watch's record, :func:`flexride.solver.kernel._watch`), which a period-two
oscillation makes large: after the start (equilibrium and perturbation: a few hundred N) it
dies out to below 1 N at a stable step, with short spikes where the rail window shifts, while
at an unstable step it stays at the creep force's saturation or the watch stops the run. The
median over the last fifth of the run against the largest value over the first twentieth
separates the two by a factor of about 100 either side of :data:`GROWTH_RATIO`.

Used by the tests of the check (``tests/solver/test_step_limit.py``) and by the study that
bisects the kernel's own limit (``tools/studies/step_limit_vs_kernel.py``).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from flexride.scenario.scenario import Scenario
from flexride.solver import system as S
from flexride.solver.assemble import Assembly, with_step
from flexride.solver.forces import evaluate
from flexride.solver.kernel import STATUS_FULL, STATUS_OK, run_chunk
from flexride.solver.simulate import _workspace, convected_rail_velocity
from flexride.solver.stability import curving_position
from flexride.solver.static import initial_window_start, static_equilibrium
from flexride.solver.steady import smooth_assembly, steady_state

#: Random perturbation of every coordinate at the start (m or rad).
PERTURBATION = 1.0e-7
#: Steps per kernel call between two readings of the watch.
CHUNK = 64
#: A run grows when the median change at its end is at least this fraction of the largest
#: change at its start.
GROWTH_RATIO = 0.1


@dataclass(frozen=True)
class Probe:
    """What a probe run saw.

    Attributes
    ----------
    stopped : bool
        The kernel stopped the run (chatter, NaN or runaway).
    start : float
        Largest step-to-step change of a watched wheel force over the first 5 % (N).
    end : float
        Median of those changes over the last 20 % (N).
    """

    stopped: bool
    start: float
    end: float

    @property
    def grows(self) -> bool:
        """Whether the perturbation did not die out (module docs)."""
        return self.stopped or self.end >= GROWTH_RATIO * self.start


def operating_start(scenario: Scenario, asm: Assembly, curving: bool, seconds: float = 0.0
                    ) -> tuple[Assembly, float, float, np.ndarray, np.ndarray]:
    """An operating point of the check on smooth track as a start for a run of ``seconds`` (s)
    — the steady rolling state where the run starts, or (``curving``) steady curving at
    :func:`~flexride.solver.stability.curving_position`: (assembly starting there, position
    s and rail-window start s_win0 in m, X, V).
    """
    s = curving_position(scenario) if curving else 0.0
    if s is None:
        raise ValueError("the run meets no curve")
    smooth = smooth_assembly(asm, s, scenario.line, scenario.track.rail_centre_half_distance,
                             travel=scenario.speed_mps * seconds)
    s_win0 = initial_window_start(smooth, s)
    X, V = steady_state(smooth, s, s_win0, static_equilibrium(smooth, s, s_win0))
    par = smooth.sys.par._replace(s_start=s)
    return dataclasses.replace(smooth, sys=smooth.sys._replace(par=par)), s, s_win0, X, V


def probe(scenario: Scenario, asm: Assembly, dt: float, curving: bool = False,
          seconds: float = 2.0, seed: int = 1) -> Probe:
    """Run the kernel for ``seconds`` (s) with the step ``dt`` (s) from the operating point
    (:func:`operating_start`) with a small random perturbation (module docs).
    """
    start, s, s_win0, X, V = operating_start(scenario, asm, curving, seconds)
    start = with_step(start, scenario, dt)
    V = V + convected_rail_velocity(start, X)
    X = X + PERTURBATION * np.random.default_rng(seed).standard_normal(X.size)
    ws = _workspace(start, X, V, X.copy(), s_win0)
    evaluate(start.sys, ws.X, ws.V, s, s_win0, ws.F, ws.A, ws.aux, ws.sn, ws.cst, 0.0)
    changes = []
    for _ in range(round(seconds / dt) // CHUNK):
        status = run_chunk(start.sys, ws.X, ws.V, ws.A, ws.Ap, ws.F, ws.aux, ws.sn, ws.cst,
                           ws.facc, ws.eacc, ws.ptv, ws.pscr, ws.X_ref, ws.u, ws.q, ws.tstate,
                           CHUNK, ws.rec, ws.rec_t, ws.rec_s, ws.info, ws.watch)
        ws.tstate[S.T_NREC] = 0  # keep recording into the same buffer
        if status not in (STATUS_OK, STATUS_FULL):
            return Probe(True, np.nan, np.nan)
        changes.append(np.abs(ws.watch[..., S.W_CHANGE]).max())
    d = np.array(changes)
    return Probe(False, float(d[: max(1, d.size // 20)].max()),
                 float(np.median(d[-max(1, d.size // 5):])))


def kernel_limit(scenario: Scenario, asm: Assembly, lo: float, hi: float,
                 curving: bool = False, rtol: float = 0.005) -> tuple[float, float]:
    """The kernel's own limit bracketed by bisection on :func:`probe` between ``lo`` (s,
    stable) and ``hi`` (s, growing) to ``rtol``: (largest stable, smallest growing step).

    Raises
    ------
    ValueError
        ``lo`` grows or ``hi`` does not.
    """
    if probe(scenario, asm, lo, curving).grows or not probe(scenario, asm, hi, curving).grows:
        raise ValueError(f"[{lo:g}, {hi:g}] s does not bracket the kernel's limit")
    while hi - lo > rtol * hi:
        mid = 0.5 * (lo + hi)
        if probe(scenario, asm, mid, curving).grows:
            hi = mid
        else:
            lo = mid
    return lo, hi
