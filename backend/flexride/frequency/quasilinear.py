"""Statistical (quasi-) linearisation of the wheel–rail contact with real profiles.

The contact geometry of real profiles is strongly nonlinear in the wheelset's lateral
displacement relative to the rail head Δy (S1002 on 60E1 at 1:40: local conicity 0.11 about
the centre, a contact-point jump at 0.2–0.5 mm, equivalent conicity 0.36 at ŷ = 1 mm and 0.18
at 3 mm). A linearisation by local slopes describes a wheelset that moves by micrometres; one
that moves by millimetres sees an average of the geometry over its motion.

The classical remedy for random vibration (Booton, Kazakov; in railway dynamics the
quasi-linearisation with the equivalent conicity at the wheelset's amplitude) replaces the
slope of every force with respect to the nonlinear argument by its Gaussian-equivalent gain

    k_eq = E[y·f(y)] / σ²,     y ~ N(0, σ²) about the operating point,

the least-squares slope of f over the distribution of y (for a linear f it is the slope). With
Gauss–Hermite nodes x_i and weights w_i (y_i = √2·σ·x_i) and the nodes in ± pairs it is a
weighted sum of central differences with steps h_i = √2·σ·x_i (x_i > 0):

    k_eq = Σ_i c_i·(f(h_i) − f(−h_i))/(2h_i),   c_i = 4·w_i·x_i²/√π,   Σ_i c_i = 1.

**What moves the contact along the profile.** The kernel looks up each wheel's profile table
at Δy = y_w − y_head (wheelset lateral coordinate minus the rail head's lateral position, the
latter from the rail's lateral and torsion modes and the lateral irregularity of that rail).
The vertical motion, roll and yaw of the wheelset enter the contact through the compression,
the contact angle γ + φ and the creepages, at the table values of Δy, not through the lookup
position: they do not move the contact along the profile and keep their local derivatives.
So each wheel w, side has one nonlinear argument Δy_ws, and the lateral irregularity of that
rail at that wheelset moves it alone (by −u).

**The path.** Holding the other coordinates while Δy moves by millimetres would press the
wheel into the rail or lift it off (the contact point climbs or drops with the profile, and
the Hertz spring is stiff): the wheelset's vertical coordinate and roll are moved with it
(by l/2 and ±l/(2·b0), which lifts this wheel by l and leaves the other) until the wheel's
vertical contact force is the operating point's — the wheelset riding on the rails, as the
rigid-contact geometry of the equivalent conicity assumes (keeping the compression instead
would drop the load by 40 % after the contact-point jump, where the Hertz constant changes).
From the forces along the path the local linear effect of that vertical and roll move is
subtracted (−K·move), so the statistical column is the Δy derivative "with the wheelset's
vertical and roll rows slaved": in the linear model the wheelset then rises and rolls with Δy
at the Gaussian-equivalent rates, and every other row sees the Gaussian-equivalent force.

**The columns.** Booton's gains for f(y, q): ∂/∂y → E[y·f]/σ², ∂/∂q → E[∂f/∂q] (q independent
of y). So (i) the Δy column of each wheel (forces and wheel quantities) is the
Gaussian-equivalent gain along the path, differenced by shifting that wheel's lateral
irregularity at the Gauss–Hermite offsets; every column j of the coordinates gets the change of
that column times ∂Δy_ws/∂X_j (1 for the wheelset's lateral coordinate, minus the rail head's
lateral derivative for the rail modes): a rank-one update per wheel, consistent between the
state and input matrices (a rigid lateral shift of wheelset and rail still gives no force).
(ii) The creep columns — the wheelset's yaw angle and its six velocities — are replaced by
their Gaussian means over the path (the creep coefficients, the contact patch and the load
sharing of the two slots change along the profile); the rail heads' lateral and vertical
velocity columns get the same change with the opposite sign through the rail head's modal
derivatives, since creep depends on the relative velocity. The wheelset's vertical and roll
columns (Hertz stiffness) keep their local values.

**σ** is the standard deviation of each wheel's ``<wheelset>.<side>.rel_disp.y`` in the
response, the channel the flags use. It depends on the gains, so they are iterated: local
linearisation, σ from its response, statistical columns at σ, response again … until no σ
changes by more than :data:`SIGMA_RTOL` (at most :data:`MAX_ITERATIONS`), each step relaxed
by the secant slope of the last two (:func:`_next_sigma`). The path is sampled at the σ of a
fixed ladder and the gains blended from the two rungs around σ (:func:`ladder`), so that they
are one continuous function of σ: the fixed point does not depend on where the iteration
starts (a sweep starts each value from the previous value's σ, :class:`QuasiStart`). The
operating point is not moved (the mean of the statistically linearised force, E[f(y)] − f(0),
is neglected: on straight track the two wheels' parts cancel by symmetry).

Only profile contact is treated: the conical tread is linear in Δy up to its flange (whose
contact the flags report), so its model is the local one, unchanged.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from flexride.frequency.errors import LinearisationError
from flexride.frequency.jacobians import STATE_STEP, state_jacobians
from flexride.frequency.lti import SecondOrderSystem
from flexride.frequency.model import (
    DEFAULT_LINEARISATION,
    LINEARISATIONS,
    Linearisation,
    LinearisationMethod,
    LinearModel,
    model_from,
)
from flexride.frequency.response import wheel_variance
from flexride.frequency.track_input import TrackSpectra
from flexride.scenario.scenario import Scenario
from flexride.solver import system as S
from flexride.solver.forces import evaluate
from flexride.solver.linearise import workspace

__all__ = ["DEFAULT_LINEARISATION", "LINEARISATIONS", "LinearisationMethod", "QuasiLinear",
           "applies", "check_linearisation", "gaussian_gain", "hermite_differences",
           "quasi_linear_model", "statistical_linearisation", "wheel_sigma",
           "with_linearisation"]

#: Gauss–Hermite nodes of the expectation (10 ± pairs). On S1002/60E1 (a Δr with a kink and a
#: jump) 40 nodes move the car-body lateral indices by < 1 % and the wheels' σ by 2 %.
N_NODES = 20
#: The iteration stops when no wheel's σ changes by more than this fraction. The model it
#: returns is then within about SIGMA_RTOL/(1 − g') ≈ 0.1 % of the fixed point's σ (g' ≈ −0.2
#: below), whatever the start: a sweep's warm-started value and its rebuild from scratch agree
#: within that (1 % left the lateral indices 0.5 % apart after a change of speed).
SIGMA_RTOL = 1e-3
#: A sweep value whose iteration started from the previous value's σ (:class:`QuasiStart`) and
#: its estimate from scratch agree within this fraction in every comfort index (both within
#: SIGMA_RTOL of the same fixed point; up to 5.4e-4 measured, tests/frequency/test_sweep.py).
WARM_START_RTOL = 1e-3
#: Under-relaxation of the first σ update (:func:`_next_sigma`): g(σ) falls slightly as σ rises
#: (slope ≈ −0.2 on S1002/60E1 at 50–80 km/h), so 0.8 nearly cancels it. Later updates take
#: the relaxation 1/(1 − g') from the secant slope of the last two iterates (the gains are
#: continuous in σ, :func:`ladder`): near the stability limit of the wheelsets (soft primary
#: lateral stiffness) g falls steeply, where a fixed relaxation cycled (σ changing by 40–100 %
#: after 8 iterations at k_y = 100–316 kN/m, 80 km/h; now converged in 10).
RELAXATION = 0.8
#: Bounds of the secant relaxation.
RELAXATION_RANGE = (0.05, 1.0)
#: The iteration starts from this fraction of the local model's σ (the quasi-linear contact is
#: stiffer: the fixed point lies at 0.68–0.73 of it on S1002/60E1 at 50–80 km/h; the fixed
#: point does not depend on the start, the number of iterations does).
START_FACTOR = 0.75
#: At most this many statistical linearisations.
MAX_ITERATIONS = 12


def check_linearisation(method: str) -> None:
    """Refuse an unknown linearisation (:class:`LinearisationError`, reason ``linearisation``)."""
    if method not in LINEARISATIONS:
        raise LinearisationError(f"unknown linearisation {method!r}; use one of "
                                 f"{', '.join(LINEARISATIONS)}", "linearisation")


def hermite_differences(sigma: float, n: int = N_NODES) -> tuple[np.ndarray, np.ndarray]:
    """Steps and weights that make the Gaussian-equivalent gain a sum of central differences.

    Parameters
    ----------
    sigma : float
        Standard deviation σ of the zero-mean Gaussian argument (m, or its unit).
    n : int
        Number of Gauss–Hermite nodes (even: the zero node carries no weight here).

    Returns
    -------
    steps : numpy.ndarray
        (n/2,) h_i = √2·σ·x_i for the positive nodes x_i (m).
    weights : numpy.ndarray
        (n/2,) c_i = 4·w_i·x_i²/√π (-), summing to one: k_eq = Σ c_i·(f(h_i) − f(−h_i))/(2h_i).
    """
    x, w = np.polynomial.hermite.hermgauss(n)
    pos = x > 0.0
    return math.sqrt(2.0) * sigma * x[pos], 4.0 * w[pos] * x[pos] ** 2 / math.sqrt(math.pi)


def gaussian_gain(f: Callable[[np.ndarray], np.ndarray], sigma: float, n: int = N_NODES,
                  center: float = 0.0) -> float:
    """Gaussian-equivalent gain k_eq = E[y·f(center + y)]/σ² of ``f`` for y ~ N(0, σ²).

    Parameters
    ----------
    f : callable
        Vectorised function of the argument (unit of the argument → unit of the result).
    sigma : float
        Standard deviation σ > 0 (unit of the argument).
    n : int
        Gauss–Hermite nodes.
    center : float
        The operating point the argument varies about.

    Returns
    -------
    float
        The gain (unit of f per unit of the argument), by the same central differences the
        contact columns use (:func:`hermite_differences`).
    """
    h, c = hermite_differences(sigma, n)
    fp = np.asarray(f(center + h), dtype=float)
    fm = np.asarray(f(center - h), dtype=float)
    return float(np.sum(c * (fp - fm) / (2.0 * h)))


def applies(lin: Linearisation) -> bool:
    """Whether the contact needs the statistical linearisation: real profiles (two-slot
    tables, nonlinear in Δy); the conical tread is linear in Δy.
    """
    return int(lin.op.sys.par.contact_model) == S.CONTACT_PROFILES


@dataclass
class QuasiStart:
    """Where a quasi-linear iteration starts instead of the local model's σ: a sweep's
    previous value.

    Attributes
    ----------
    sigma : numpy.ndarray
        (n_ws, 2) σ of each wheel's lateral displacement relative to the rail (m).
    samples : PathSamples or None
        Path samples that describe this model's contact (None: sampled anew).
    """

    sigma: np.ndarray
    samples: PathSamples | None = None


@dataclass
class QuasiLinear:
    """How the contact of a linear model was linearised.

    Attributes
    ----------
    method : {"statistical", "local"}
        Gaussian-equivalent gains, or local slopes.
    applied : bool
        Whether the statistical gains were used (profile contact only).
    converged : bool
        Whether σ settled within :data:`SIGMA_RTOL` (True when not applied).
    iterations : int
        Statistical linearisations made (0 when not applied).
    sigma : dict of str to float
        σ of each wheel's lateral displacement relative to the rail (m) the final gains were
        made at, ``<wheelset>.<side>``.
    sigma_local : dict of str to float or None
        The same from the local linearisation (m); None when the iteration started from a
        previous sweep value's σ (:class:`QuasiStart`) and did not need it.
    history : list of float
        Largest relative change of σ at each iteration (-).
    lateral_gain : dict of str to float
        Per wheelset, the statistical over the local lateral stiffness K_yy of the wheelset's
        own lateral coordinate (contact and primary suspension, -): how far the quasi-linear
        contact is from the local one.
    linearisation : Linearisation or None
        The statistical linearisation the model was reduced from (None when not applied).
    sigma_next : numpy.ndarray or None
        (n_ws, 2) the iteration's next σ (m): where a following sweep value starts.
    samples : PathSamples or None
        The wheels' path samples the gains were made from (reused by a following sweep value
        whose contact they still describe).
    """

    method: LinearisationMethod
    applied: bool = False
    converged: bool = True
    iterations: int = 0
    sigma: dict[str, float] = field(default_factory=dict)
    sigma_local: dict[str, float] | None = field(default_factory=dict)
    history: list[float] = field(default_factory=list)
    lateral_gain: dict[str, float] = field(default_factory=dict)
    linearisation: Linearisation | None = field(default=None, repr=False, compare=False)
    sigma_next: np.ndarray | None = field(default=None, repr=False, compare=False)
    samples: PathSamples | None = field(default=None, repr=False, compare=False)

    @property
    def warm(self) -> bool:
        """Whether the iteration started from a previous sweep value (:class:`QuasiStart`):
        it then had no local σ.
        """
        return self.applied and self.sigma_local is None

    def start(self, samples_hold: bool) -> QuasiStart | None:
        """Where the iteration of a following sweep value starts: this σ, and these path
        samples if ``samples_hold`` (that value's contact and the wheelsets' rows and columns
        are this model's). None when the statistical linearisation was not applied.
        """
        if not self.applied or self.sigma_next is None:
            return None
        return QuasiStart(self.sigma_next, self.samples if samples_hold else None)

    def to_dict(self) -> dict[str, Any]:
        """JSON form."""
        return {"method": self.method, "applied": self.applied, "converged": self.converged,
                "iterations": self.iterations, "sigma_m": dict(self.sigma),
                "sigma_local_m": (dict(self.sigma_local) if self.sigma_local is not None
                                  else None), "warm_start": self.warm,
                "sigma_change": list(self.history), "lateral_gain": dict(self.lateral_gain),
                "n_nodes": N_NODES, "sigma_rtol": SIGMA_RTOL}

    def describe(self) -> str:
        """One line for the method statement."""
        if not self.applied:
            return ("contact linearised by local slopes" if self.method == "local" else
                    "contact linear in the lateral displacement (conical tread): local slopes")
        state = (f"converged in {self.iterations} iterations" if self.converged else
                 f"NOT converged after {self.iterations} iterations")
        return ("contact quasi-linearised: Gaussian-equivalent gains in each wheel's lateral "
                f"displacement on the rail at the response's own σ ({state})")


#: The wheel channel whose σ the gains are made at (the lateral displacement on the rail head).
SIGMA_CHANNEL = ".rel_disp.y"


def _sigma_channels(names: list[str]) -> list[str]:
    """The ``<wheelset>.<side>`` + :data:`SIGMA_CHANNEL` channels of ``names``, in order."""
    return [n for n in names if n.endswith(SIGMA_CHANNEL)]


def wheel_sigma(names: list[str], variance: np.ndarray, n_ws: int) -> np.ndarray:
    """(n_ws, 2) σ of each wheel's ``rel_disp.y`` (m) from the wheel channels' variances,
    in the order of :attr:`LinearModel.wheels` (per wheelset left, right).
    """
    rows = [names.index(n) for n in _sigma_channels(names)]
    return np.sqrt(np.maximum(variance[rows], 0.0)).reshape(n_ws, 2)


def _response_sigma(model: LinearModel) -> np.ndarray:
    """σ of every wheel's lateral displacement relative to the rail in ``model``'s response
    (m), as :func:`~flexride.frequency.comfort` computes it for the flags.
    """
    names = _sigma_channels(model.wheels.names)
    return wheel_sigma(names, wheel_variance(model, names), len(model.wheelset_x))


#: The wheel's vertical contact force on the path is held within this fraction of its
#: operating value (secant iterations on the wheel's lift, at most :data:`LIFT_ITERATIONS`).
LOAD_RTOL = 1e-9
LIFT_ITERATIONS = 12


@dataclass
class _Path:
    """One point of a wheel's path: accelerations (1/s²) and wheel quantities minus the local
    effect of the wheelset's vertical and roll move, and the creep columns there
    (∂A/∂ψ, ∂aux/∂ψ of the wheelset's yaw; ∂A/∂V, ∂aux/∂V of its six velocities).
    """

    acc: np.ndarray
    wheel: np.ndarray
    yaw: tuple[np.ndarray, np.ndarray]
    rates: tuple[np.ndarray, np.ndarray]


def _creep_columns(lin: Linearisation, o: int, X: np.ndarray
                   ) -> tuple[tuple[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]:
    """Derivatives with respect to the yaw of the wheelset at offset ``o`` and to its six
    velocities at coordinates ``X`` (central differences with the state step).
    """
    op = lin.op
    yaw = state_jacobians(op.sys, X, op.V0, op.s, op.s_win0, False, STATE_STEP,
                          np.array([o + 5]))
    rates = state_jacobians(op.sys, X, op.V0, op.s, op.s_win0, True, STATE_STEP,
                            np.arange(o, o + 6))
    return yaw, rates


def _path_point(lin: Linearisation, w: int, side: int, u: float, ws: tuple) -> _Path:
    """The wheel's path at the lateral irregularity of rail ``side`` at wheelset ``w``
    shifted by ``u`` (m; the wheel's Δy by −u), with the wheelset sitting on the rails: its
    vertical coordinate and roll moved (by l/2 and ±l/(2·b0), so that only this wheel rises,
    by l) until the wheel's vertical contact force is the operating point's again, the other
    wheel untouched (module docstring).
    """
    op = lin.op
    sys = op.sys
    F, A, aux, sn, cst = ws
    o = int(sys.body_off[sys.ws_body[w]])
    sg = 1.0 if side == 0 else -1.0
    unit = np.array([0.5, sg * 0.5 / sys.par.b0])  # coordinates per unit lift (-, rad/m)
    row = (2 * w + side) * S.N_AUX
    fz0 = op.aux[w, side, S.AUX_FZ]
    slope = float(lin.daux_dX[row + S.AUX_FZ, o + 2:o + 4] @ unit)  # N/m of lift
    irr = sys.irr
    i = int((op.s + sys.body_x[sys.ws_body[w]] - sys.par.irr_s0) / sys.par.irr_ds)
    saved = irr[2 + side, i:i + 2].copy()
    X, V = op.X0.copy(), op.V0.copy()
    lift = 0.0
    try:
        irr[2 + side, i:i + 2] = saved + u
        evaluate(sys, X, V, op.s, op.s_win0, F, A, aux, sn, cst, 0.0)
        # first guess: the wheel's largest compression back at the operating point's
        prev = (lift, aux[w, side, S.AUX_FZ] - fz0)
        lift = aux[w, side, S.AUX_DELTA] - op.aux[w, side, S.AUX_DELTA]
        for _ in range(LIFT_ITERATIONS):
            X[o + 2:o + 4] = op.X0[o + 2:o + 4] + lift * unit
            evaluate(sys, X, V, op.s, op.s_win0, F, A, aux, sn, cst, 0.0)
            res = aux[w, side, S.AUX_FZ] - fz0
            if abs(res) <= LOAD_RTOL * abs(fz0):
                break
            if lift != prev[0] and res != prev[1]:
                slope = (res - prev[1]) / (lift - prev[0])
            prev, lift = (lift, res), lift - res / slope
        yaw, rates = _creep_columns(lin, o, X)
    finally:
        irr[2 + side, i:i + 2] = saved
    move = lift * unit
    return _Path(A + lin.full.K[:, o + 2:o + 4] @ move,  # K = −∂A/∂X: the local slave terms
                 aux.reshape(-1) - lin.daux_dX[:, o + 2:o + 4] @ move, yaw, rates)


@dataclass
class WheelSamples:
    """One wheel's path sampled at the ± Gauss–Hermite offsets of a reference σ: what its
    Gaussian-equivalent gains at any nearby σ are weighted sums of (:func:`_gains`).

    Attributes
    ----------
    sigma_ref : float
        The reference σ (m).
    steps : numpy.ndarray
        (n/2,) offsets h_i = √2·σ_ref·x_i (m).
    prob : numpy.ndarray
        (n/2,) Gauss–Hermite weights w_i/√π of the pairs (-).
    diff_acc, diff_wheel : numpy.ndarray
        (n/2, ·) central differences (f(h_i) − f(−h_i))/(2h_i) of the accelerations (1/s²)
        and wheel quantities along the path with respect to the irregularity (= −Δy).
    sum_yaw, sum_rates : (numpy.ndarray, numpy.ndarray)
        Per pair g(h_i) + g(−h_i) of the creep columns: (n/2, n, ·) accelerations and
        (n/2, n_aux, ·) wheel quantities, one column for the yaw, six for the rates.
    """

    sigma_ref: float
    steps: np.ndarray
    prob: np.ndarray
    diff_acc: np.ndarray
    diff_wheel: np.ndarray
    sum_yaw: tuple[np.ndarray, np.ndarray]
    sum_rates: tuple[np.ndarray, np.ndarray]


#: A wheel's path is sampled at the σ of a fixed geometric ladder, SAMPLE_BASE·SAMPLE_RATIO^k.
#: The gains at σ are those of the two rungs around it, each reweighted to σ (self-normalised
#: importance weights, exact for linear functions), blended linearly in log σ
#: (:func:`ladder`). They are then one continuous function of σ, whoever asks: an iteration
#: from the local model's σ and one from a sweep's previous value reach the same fixed point
#: (within :data:`SIGMA_RTOL`). With nodes at the σ of the first iteration the two differed by
#: up to 0.9 % in the lateral indices (the quadrature's ripple over the contact-point jump);
#: with the nearest rung alone the gains jump between rungs and the iteration can cycle. A
#: sweep keeps its samples while σ stays between the same rungs.
SAMPLE_BASE = 1.0e-3
SAMPLE_RATIO = 1.1


def ladder(sigma: float) -> tuple[int, float]:
    """The rung k below ``sigma`` (m) on the sampling ladder and the blend t ∈ [0, 1) towards
    rung k + 1 (linear in log σ).
    """
    x = math.log(sigma / SAMPLE_BASE) / math.log(SAMPLE_RATIO)
    k = math.floor(x)
    return k, x - k


def rung_sigma(k: int) -> float:
    """σ of rung ``k`` of the sampling ladder (m)."""
    return SAMPLE_BASE * SAMPLE_RATIO**k


def sample_wheel(lin: Linearisation, w: int, side: int, sigma: float) -> WheelSamples:
    """The path of wheel ``side`` of wheelset ``w`` (:func:`_path_point`) at the ± offsets of
    the Gauss–Hermite nodes of standard deviation ``sigma`` (m).
    """
    ws = workspace(lin.op.sys)
    x, wx = np.polynomial.hermite.hermgauss(N_NODES)
    steps = math.sqrt(2.0) * sigma * x[x > 0.0]
    diff_a, diff_x, yaw, rates = [], [], [], []
    for h in steps:
        p, q = _path_point(lin, w, side, h, ws), _path_point(lin, w, side, -h, ws)
        diff_a.append((p.acc - q.acc) / (2.0 * h))
        diff_x.append((p.wheel - q.wheel) / (2.0 * h))
        yaw.append((p.yaw[0] + q.yaw[0], p.yaw[1] + q.yaw[1]))
        rates.append((p.rates[0] + q.rates[0], p.rates[1] + q.rates[1]))
    return WheelSamples(sigma, steps, wx[x > 0.0] / math.sqrt(math.pi), np.array(diff_a),
                        np.array(diff_x), (np.array([y[0] for y in yaw]),
                                           np.array([y[1] for y in yaw])),
                        (np.array([r[0] for r in rates]), np.array([r[1] for r in rates])))


def _gains(smp: WheelSamples, sigma: float) -> tuple[np.ndarray, ...]:
    """Gaussian-equivalent derivative along the path (E[y·f]/σ², accelerations and wheel
    quantities) and Gaussian means of the creep columns at ``sigma`` (m), from the samples:
    the pairs' probabilities reweighted by p_σ/p_ref and normalised so that a linear
    function gets its slope and a constant its value. In this order: the derivative's
    accelerations and wheel quantities, then the same of the yaw column and of the six rates.
    """
    h, s0 = smp.steps, smp.sigma_ref
    rho = smp.prob * np.exp(-0.5 * h**2 * (1.0 / sigma**2 - 1.0 / s0**2))
    c = rho * h**2
    c /= c.sum()  # E[y·f]/σ² = Σ c_i·D(h_i) with Σ c_i = 1
    m = rho / (2.0 * rho.sum())  # E[g] = Σ m_i·(g(h_i) + g(−h_i))
    means = [np.tensordot(m, a, 1) for a in (*smp.sum_yaw, *smp.sum_rates)]
    return (c @ smp.diff_acc, c @ smp.diff_wheel, *means)


@dataclass
class PathSamples:
    """What the iteration keeps between statistical linearisations of one local model: each
    wheel's path samples by (wheelset, side, rung), and the creep columns at the operating
    point by wheelset.
    """

    wheels: dict[tuple[int, int, int], WheelSamples] = field(default_factory=dict)
    creep0: dict[int, Any] = field(default_factory=dict)

    def gains(self, lin: Linearisation, w: int, side: int, sigma: float
              ) -> tuple[np.ndarray, ...]:
        """The gains of wheel ``side`` of wheelset ``w`` at ``sigma`` (m) (:func:`_gains`, in
        its order), blended linearly in log σ from the two rungs of the sampling ladder around
        it (sampled when missing).
        """
        k, t = ladder(sigma)
        lo, hi = (_gains(self._rung(lin, w, side, j), sigma) for j in (k, k + 1))
        return tuple((1.0 - t) * a + t * b for a, b in zip(lo, hi, strict=True))

    def _rung(self, lin: Linearisation, w: int, side: int, k: int) -> WheelSamples:
        """The wheel's samples at rung ``k``, sampled on first use."""
        if (w, side, k) not in self.wheels:
            self.wheels[w, side, k] = sample_wheel(lin, w, side, rung_sigma(k))
        return self.wheels[w, side, k]


def statistical_linearisation(lin: Linearisation, sigma: np.ndarray,
                              samples: PathSamples | None = None) -> Linearisation:
    """``lin`` with the contact's derivatives in each wheel's Δy replaced by their
    Gaussian-equivalent gains at ``sigma``, and its creep columns by their Gaussian means
    (module docstring).

    Parameters
    ----------
    lin : Linearisation
        The local linearisation.
    sigma : numpy.ndarray
        (n_ws, 2) σ of each wheel's lateral displacement relative to the rail (m).
    samples : PathSamples, optional
        The wheels' path samples on the sampling ladder (:data:`SAMPLE_RATIO`), reused and
        completed in place; default: sampled anew.

    Returns
    -------
    Linearisation
        New K, C, B0 and the wheel quantities' derivatives (B1 unchanged).
    """
    op = lin.op
    sys = op.sys
    samples = PathSamples() if samples is None else samples
    K, C, B0 = lin.full.K.copy(), lin.full.C.copy(), lin.full.B0.copy()
    daux_dX, daux_dV, daux_du = lin.daux_dX.copy(), lin.daux_dV.copy(), lin.daux_du.copy()
    left_k, left_kx, right_k = [], [], []  # rank-one updates of K (and ∂aux/∂X) …
    left_c, left_cx, right_c = [], [], []  # … and of C (∂aux/∂V), applied at once
    for w in range(int(sys.ws_body.shape[0])):
        o = int(sys.body_off[sys.ws_body[w]])
        if w not in samples.creep0:
            samples.creep0[w] = _creep_columns(lin, o, op.X0)
        yaw0, rates0 = samples.creep0[w]
        for side in range(2):
            k = 4 * w + 2 + side
            row = (2 * w + side) * S.N_AUX
            g_a, g_x, yaw_a, yaw_x, rate_a, rate_x = samples.gains(lin, w, side,
                                                                   float(sigma[w, side]))
            d_a, d_x = g_a - lin.full.B0[:, k], g_x - lin.daux_du[:, k]
            grad = -lin.daux_dX[row + S.AUX_RAIL_Y].copy()
            grad[o + 1] += 1.0  # ∂Δy/∂X of this wheel
            # ∂A/∂X_j += −grad_j·(∂A/∂u stat − local)
            left_k.append(d_a)
            left_kx.append(d_x)
            right_k.append(grad)
            B0[:, k] += d_a
            daux_du[:, k] += d_x
            # creep columns: the wheelset's yaw and velocities, and the rail heads' velocities
            # by the same change of the relative lateral and vertical velocity
            K[:, o + 5] -= yaw_a[:, 0] - yaw0[0][:, 0]
            daux_dX[:, o + 5] += yaw_x[:, 0] - yaw0[1][:, 0]
            dv_a, dv_x = rate_a - rates0[0], rate_x - rates0[1]
            C[:, o:o + 6] -= dv_a
            daux_dV[:, o:o + 6] += dv_x
            for col, fld in ((1, S.AUX_RAIL_Y), (2, S.AUX_RAIL_Z)):
                left_c.append(dv_a[:, col])
                left_cx.append(dv_x[:, col])
                right_c.append(lin.daux_dX[row + fld])
    K += np.column_stack(left_k) @ np.array(right_k)
    daux_dX -= np.column_stack(left_kx) @ np.array(right_k)
    C += np.column_stack(left_c) @ np.array(right_c)
    daux_dV -= np.column_stack(left_cx) @ np.array(right_c)
    full = SecondOrderSystem(K=K, C=C, B0=B0, B1=lin.full.B1, B2=lin.full.B2)
    return replace(lin, full=full, daux_dX=daux_dX, daux_dV=daux_dV, daux_du=daux_du)


def _lateral_gains(lin: Linearisation, stat: Linearisation, names: list[str]
                   ) -> dict[str, float]:
    """Per wheelset, statistical over local ∂A_y/∂y_w of the wheelset's own lateral row."""
    sys = lin.op.sys
    out = {}
    for w, b in enumerate(sys.ws_body):
        j = int(sys.body_off[b]) + 1
        local = lin.full.K[j, j]
        out[names[w]] = float(stat.full.K[j, j] / local) if local != 0.0 else math.nan
    return out


def _sigma_dict(model: LinearModel, sigma: np.ndarray) -> dict[str, float]:
    """``<wheelset>.<side>`` → σ (m)."""
    keys = [n.removesuffix(SIGMA_CHANNEL) for n in _sigma_channels(model.wheels.names)]
    return {k: float(v) for k, v in zip(keys, sigma.reshape(-1), strict=True)}


def _next_sigma(sigma: np.ndarray, response: np.ndarray,
                previous: tuple[np.ndarray, np.ndarray] | None) -> np.ndarray:
    """The next σ of the fixed-point iteration σ = g(σ) (m): σ + ω·(g(σ) − σ) with
    ω = 1/(1 − g'), g' the secant slope of g along the last step from the ``previous``
    iterate (σ, g(σ)) — one slope for all wheels, projected on the step: their σ move
    together — bounded by :data:`RELAXATION_RANGE`; :data:`RELAXATION` on the first step.
    """
    omega = RELAXATION
    if previous is not None:
        step = (sigma - previous[0]).ravel()
        if np.linalg.norm(step) > 1e-9 * np.linalg.norm(sigma):
            slope = float((response - previous[1]).ravel() @ step / (step @ step))
            omega = float(np.clip(1.0 / max(1.0 - slope, 1e-12), *RELAXATION_RANGE))
    return sigma + omega * (response - sigma)


def with_linearisation(model: LinearModel, method: str = DEFAULT_LINEARISATION,
                       strict: bool = True, start: QuasiStart | None = None) -> LinearModel:
    """``model`` (a local linear model) linearised by ``method``.

    Parameters
    ----------
    model : LinearModel
        Made by :func:`~flexride.frequency.model.model_from` from a local linearisation.
    method : {"statistical", "local"}
        See :data:`LINEARISATIONS`.
    strict : bool
        See :func:`quasi_linear_model`.
    start : QuasiStart, optional
        See :func:`quasi_linear_model`.

    Returns
    -------
    LinearModel
        ``model`` itself (local, or a contact linear in Δy) or its quasi-linear model.
    """
    check_linearisation(method)
    if method == "local":
        model.quasi_linear = QuasiLinear("local")
        return model
    assert method == "statistical"
    return quasi_linear_model(model.scenario, model, model.spectra, model.flags, strict, start)


def quasi_linear_model(scenario: Scenario, local: LinearModel, spectra: TrackSpectra | None,
                       flags: list[str], strict: bool = True,
                       start: QuasiStart | None = None) -> LinearModel:
    """The statistically linearised model of ``scenario``, iterated from its local model.

    Parameters
    ----------
    scenario : Scenario
        The scenario.
    local : LinearModel
        Its local linear model (its ``linearisation`` is kept on the result: what sweeps
        reuse and the steady-state solver's Newton matrix come from).
    spectra : TrackSpectra or None
        Its random irregularity (None: nothing to respond to, the local model is returned).
    flags : list of str
        Reasons the estimate may not hold (a non-converged iteration adds one).
    strict : bool
        Refuse (:class:`LinearisationError`, reason ``quasi_linear``) when σ does not settle;
        False flags it.
    start : QuasiStart, optional
        Start from this σ (and these path samples) instead of :data:`START_FACTOR` times the
        local model's σ: a sweep's previous value, whose fixed point is near. The result is
        the same fixed point within the iteration's tolerance (:data:`SIGMA_RTOL`) and the
        same sampling ladder (:data:`SAMPLE_RATIO`), not to rounding.

    Returns
    -------
    LinearModel
        With ``quasi_linear`` describing the iteration.
    """
    lin = local.linearisation
    assert lin is not None
    if spectra is None or not applies(lin):
        local.quasi_linear = QuasiLinear("statistical")
        return local
    t0 = time.perf_counter()
    sigma0: np.ndarray | None = None
    if start is None:
        sigma0 = _response_sigma(local)
        sigma, samples = START_FACTOR * sigma0, PathSamples()
    else:
        sigma, samples = start.sigma.copy(), start.samples or PathSamples()
    history: list[float] = []
    previous: tuple[np.ndarray, np.ndarray] | None = None
    model, stat = local, lin
    for _ in range(MAX_ITERATIONS):
        stat = statistical_linearisation(lin, sigma, samples)
        model = model_from(scenario, stat, local.track, spectra, flags, (t0, t0),
                           previous=local)
        new = _response_sigma(model)
        history.append(float(np.max(np.abs(new / sigma - 1.0))))
        sigma_used, sigma = sigma, _next_sigma(sigma, new, previous)
        previous = (sigma_used, new)
        if history[-1] < SIGMA_RTOL:
            break
    converged = history[-1] < SIGMA_RTOL
    ws_names = [n.split(".")[0] for n in model.wheels.names[::4]]
    ql = QuasiLinear("statistical", True, converged, len(history),
                     _sigma_dict(model, sigma_used),
                     _sigma_dict(model, sigma0) if sigma0 is not None else None, history,
                     _lateral_gains(lin, stat, ws_names), stat, sigma, samples)
    if not converged:
        msg = (f"quasi-linearisation of the profile contact did not converge: σ of the "
               f"wheelsets' lateral motion still changed by {100 * history[-1]:.1f} % after "
               f"{len(history)} iterations; the lateral estimate is doubtful")
        if strict:
            raise LinearisationError(msg, "quasi_linear")
        flags.append(msg)
    model.linearisation = lin  # the local one: sweeps rebuild from it
    model.quasi_linear = ql
    model.info.update({k: local.info[k] for k in ("time_operating_point_s",
                                                  "time_linearise_s", "time_modes_s")})
    model.info["time_quasi_linear_s"] = time.perf_counter() - t0
    return model
