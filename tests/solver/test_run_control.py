"""Progress reports, cooperative cancellation, divergence detection, output rate, options."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import preset
from flexride.errors import SimulationCancelled, SimulationError
from flexride.solver.assemble import assemble, output_rate_for
from flexride.solver.linearise import jacobian
from flexride.solver.setup_cache import default_cache
from flexride.solver.simulate import integrate, prepare_run, simulate
from flexride.solver.static import initial_window_start, static_equilibrium


def test_progress_is_reported_and_monotonic():
    seen = []
    simulate(preset(duration_s=0.5, **{"solver.progress_every_steps": 1000}),
             progress=lambda f, m: seen.append(f))
    fracs = [f for f in seen if f > 0]
    assert len(fracs) >= 5 and fracs == sorted(fracs) and fracs[-1] == 1.0


def test_cancel_stops_between_chunks():
    calls = []

    def cancel():
        calls.append(1)
        return len(calls) >= 2

    with pytest.raises(SimulationCancelled, match="cancelled at t ="):
        simulate(preset(duration_s=5.0, **{"solver.progress_every_steps": 1000}), cancel=cancel)
    assert len(calls) == 2


def test_divergence_names_time_and_coordinate():
    """Start a wheelset 2 m off the track: the runaway check stops the run at once."""
    sc = preset(duration_s=0.5, **{"solver.runaway_displacement_m": 0.5})
    asm, ready = prepare_run(sc, assemble(sc), default_cache(), check=False)
    X0 = ready.X0
    Xi = X0.copy()
    Xi[asm.sys.body_off[3] + 1] = 2.0
    with pytest.raises(SimulationError, match=r"diverged at t = .* wheelset1\.y"):
        integrate(asm, Xi, np.zeros_like(Xi), sc, lambda f, m: None, X_ref=X0)


def test_nan_is_detected():
    sc = preset(duration_s=0.1)
    asm, ready = prepare_run(sc, assemble(sc), default_cache(), check=False)
    X0 = ready.X0
    Xi = X0.copy()
    Xi[asm.sys.body_off[0] + 2] = np.nan
    # the NaN spreads through the coupling within a step; the message names the time and the
    # first non-finite coordinate found at the check (every output interval)
    pattern = r"at t = 0\.0010 s: coordinate carbody\.\w+ became NaN"
    with pytest.raises(SimulationError, match=pattern):
        integrate(asm, Xi, np.zeros_like(Xi), sc, lambda f, m: None, X_ref=X0)


def test_output_rate_rule():
    assert output_rate_for(preset()) == 1000.0
    # 50 mm corrugation at 80 km/h: 444 Hz passing frequency → ≥ 20 samples per period
    sc = preset(excitation=[{"kind": "corrugation", "wavelength_m": 0.05, "depth_m": 1e-4}])
    rate = output_rate_for(sc)  # solver.dt auto: the step will divide the interval
    assert rate == pytest.approx(20 * (80 / 3.6) / 0.05)
    fixed = preset(excitation=sc.model_dump()["excitation"], **{"solver.dt": 5e-5})
    rate = output_rate_for(fixed)
    assert rate >= 20 * (80 / 3.6) / 0.05 and (1 / fixed.solver.dt) % rate == 0


def _roll_frequency(sc):
    asm = assemble(sc)
    s0 = initial_window_start(asm)
    X0 = static_equilibrium(asm, 0.0, s0)
    n = X0.size
    K = -jacobian(asm.sys, X0, np.zeros(n), 0.0, s0, np.arange(n))
    i = asm.dof_names.index("carbody.roll")
    return K[i, i]  # (roll moment per roll angle) / Ixx, 1/s²


def test_anti_roll_bar_adds_its_stiffness_to_the_car_body_roll():
    base = preset()
    k_arb = 2.0e6
    with_bar = preset(**{"vehicle.optional.anti_roll_bar_stiffness": k_arb})
    added = (_roll_frequency(with_bar) - _roll_frequency(base)) * base.vehicle.carbody.ixx
    assert added == pytest.approx(2 * k_arb, rel=1e-6)  # one bar per bogie


def test_secondary_lateral_damper_damps_car_body_lateral_motion():
    def lateral_damping(sc):
        asm = assemble(sc)
        n = asm.sys.minv.size
        C = -jacobian(asm.sys, np.zeros(n), np.zeros(n), 0.0, -1000.0, np.arange(n),
                      wrt_velocity=True)
        i = asm.dof_names.index("carbody.y")
        return C[i, i] * sc.vehicle.carbody.mass

    c = 3.0e4
    extra = lateral_damping(preset(**{"vehicle.optional.secondary_lateral_damper": c})) - \
        lateral_damping(preset())
    assert extra == pytest.approx(2 * c, rel=1e-6)


def test_a_chattering_step_stops_the_run_with_a_step_that_works():
    """Beyond the limit of the one-step map (S1002/60E1, 1/12000 s, check switched off) the
    lateral creep force alternates from step to step on a perfect track within milliseconds
    (the presets' former step): the run-time watch stops the run naming the time, the wheel
    and a step; that step runs through."""
    over = {"distance_m": None, "duration_s": 0.3, "excitation": [],
            "solver.check_stability": False}
    sc = preset("paper-random-straight-80", **{**over, "solver.dt": 1.0 / 12000.0})
    with pytest.raises(SimulationError, match=r"numerically unstable at t = 0\.0\d+ s: the "
                       r"lateral creep force of the (left|right) wheel of wheelset\d "
                       r"alternated .* use solver\.dt = ") as err:
        simulate(sc)
    step = float(str(err.value).rsplit("= ", 1)[1].split()[0])
    simulate(preset("paper-random-straight-80", **{**over, "solver.dt": step}))
