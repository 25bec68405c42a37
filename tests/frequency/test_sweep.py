"""Parameter sweeps that reuse what a value does not change, against the oracle of a rebuild
from scratch (:func:`flexride.frequency.estimate`) — every comfort index within 1e-9 with
the local linearisation; with the statistical one (real profiles) within the quasi-linear
iteration's tolerance, since a sweep starts each value's σ iteration from the previous value's
— and the pieces of the reuse against their own oracles: the assembly against ``assemble``,
the partial Jacobian update against full Jacobians at the same point, the linearity of the
Jacobians in a suspension stiffness, the warm start against the cold steady state, the kept
and the adapted track condensation against fresh ones."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import CONICAL, preset
from flexride.frequency import linear_model, sweep
from flexride.frequency.comfort import ComfortTable
from flexride.frequency.model import linearise, smooth_scenario
from flexride.frequency.operating_point import solve_operating_point, warm_start
from flexride.frequency.quasilinear import (
    SIGMA_RTOL,
    WARM_START_RTOL,
    statistical_linearisation,
)
from flexride.frequency.rebuild import ModelRebuilder, same_assembly
from flexride.frequency.reduce import condensation, reduce_track
from flexride.solver.assemble import assemble

BASE = "paper-random-straight-80"
POINTS = ["PC", "PFB"]
RTOL = 1e-9
#: The spectral Sperling index merges lines into peaks greedily from the strongest: a weak line
#: between two peaks of nearly equal power goes to one or the other, so 1e-9 in a PSD can move
#: it by more (4e-8 seen with the presets' profiles)
RTOL_SPERLING = 1e-6


def _indices(table: ComfortTable) -> dict[tuple[str, ...], float]:
    """Every number of a comfort table but the dominant modes' shares, by name."""
    out: dict[tuple[str, ...], float] = {}
    for p in table.points:
        if p.nmv is not None:
            out[(p.name, "nmv")] = p.nmv
        for d, dc in p.directions.items():
            for q in ("rms", "sperling", "sperling_filter", "a_p95", "peak"):
                out[(p.name, d, q)] = getattr(dc, q)
            out.update({(p.name, d, w): v for w, v in dc.iso.items()})
            out.update({(p.name, d, "mode", str(i)): m["frequency_hz"]
                        for i, m in enumerate(dc.modes)})
    return out


def _assert_same(a: ComfortTable | None, b: ComfortTable | None, rtol: float = RTOL) -> None:
    assert a is not None and b is not None
    ia, ib = _indices(a), _indices(b)
    assert ia.keys() == ib.keys()
    tol = {k: max(RTOL_SPERLING if k[-1] == "sperling" else RTOL, rtol) for k in ia}
    bad = {k: (ia[k], ib[k]) for k in ia if abs(ia[k] - ib[k]) > tol[k] * abs(ib[k])}
    assert not bad, bad
    assert a.flags == b.flags


@pytest.mark.parametrize("path, values, jacobians", [
    ("vehicle.secondary.kz", [2.0e5, 2.6e5, 3.4e5, 5.0e5], "jacobians_partial"),
    ("vehicle.secondary.cz", [4.0e4, 7.0e4, 1.2e5], "jacobians_partial"),
    ("vehicle.primary.ky", [8.0e6, 1.2e7], "jacobians_partial"),
    ("speed_kmh", [55.0, 70.0, 80.0], "jacobians_full"),
])
def test_sweep_with_reuse_equals_rebuilds_from_scratch(path, values, jacobians):
    scenario = preset(BASE)
    fast = sweep(scenario, path, values, points=POINTS, linearisation="local")
    oracle = sweep(scenario, path, values, points=POINTS, reuse=False, linearisation="local")
    assert fast.errors == oracle.errors == [None] * len(values)
    for a, b in zip(fast.tables, oracle.tables, strict=True):
        _assert_same(a, b)
    n = len(values)
    assert fast.reuse[jacobians] == (n if jacobians == "jacobians_full" else n - 1)
    assert fast.reuse["cold_start"] == 1 and fast.reuse["contact_table_reused"] == n - 1
    if jacobians == "jacobians_partial":  # the rail is untouched: its condensation is kept
        assert fast.reuse["condensation_reused"] == n - 1


@pytest.mark.parametrize("path, values", [
    ("vehicle.secondary.kz", [2.0e5, 2.6e5, 3.4e5, 5.0e5]),
    ("vehicle.primary.ky", [8.0e6, 1.2e7]),
    ("speed_kmh", [70.0, 80.0]),
])
def test_statistical_sweep_equals_rebuilds_within_the_iteration_tolerance(path, values):
    scenario = preset(BASE)
    fast = sweep(scenario, path, values, points=POINTS)
    oracle = sweep(scenario, path, values, points=POINTS, reuse=False)
    assert fast.errors == oracle.errors == [None] * len(values)
    for a, b in zip(fast.tables, oracle.tables, strict=True):
        _assert_same(a, b, WARM_START_RTOL)
    n = len(values)
    assert fast.reuse["quasi_linear_cold"] == 1 and fast.reuse["quasi_linear_warm"] == n - 1


def test_a_warm_started_value_lands_on_the_cold_fixed_point_in_fewer_iterations():
    """Started at the previous value's σ, the iteration needs fewer steps than from the local
    model's σ, and both σ are within the iteration's tolerance of each other."""
    rb = ModelRebuilder()
    rb.model(preset(BASE, vehicle__secondary__kz=3.0e5))
    warm = rb.model(preset(BASE, vehicle__secondary__kz=3.4e5)).quasi_linear
    cold = linear_model(preset(BASE, vehicle__secondary__kz=3.4e5)).quasi_linear
    assert warm.warm and not cold.warm and warm.converged and cold.converged
    assert warm.iterations < cold.iterations
    assert warm.sigma_local is None and cold.sigma_local
    for key, value in cold.sigma.items():
        assert warm.sigma[key] == pytest.approx(value, rel=2 * SIGMA_RTOL), key


def test_a_refused_value_keeps_the_sweep_going():
    """The paper's curve (R 800 m) puts the leading wheelsets on their flanges: refused, with
    its reason; a wider curve is estimated as a rebuild would. Conical tread: with the presets'
    S1002/60E1 a wide curve's equilibrium lies in the contact-point jump at 0.2–0.5 mm, where
    the local linearisation is meaningless (docs/analysis.md)."""
    scenario = preset("paper-random-curve-80", **CONICAL)
    values = [800.0, 3000.0, 3100.0]
    res = sweep(scenario, "line.radius_m", values, points=["PC"])
    oracle = sweep(scenario, "line.radius_m", values, points=["PC"], reuse=False)
    assert res.tables[0] is None and res.errors[0] == oracle.errors[0]
    assert "flange contact" in (res.errors[0] or "")
    for a, b in zip(res.tables[1:], oracle.tables[1:], strict=True):
        _assert_same(a, b)
    assert res.reuse["warm_start"] == 1  # 3100 m from 3000 m


def test_the_assembly_that_reuses_contact_tables_equals_assemble():
    contacts: dict = {}
    for name, over in [(BASE, {}), ("paper-random-curve-60", {}),
                       (BASE, {"vehicle__secondary__kz": 4.0e5}),
                       (BASE, {"contact__conicity": 0.1})]:
        sc = smooth_scenario(preset(name, **over))
        assert same_assembly(assemble(sc), assemble(sc, contact_tables=contacts))
    # one table for the conical contact of the paper's vehicle, one for conicity 0.1
    assert len(contacts) == 2


def _op_and_lin(kz: float):
    sc = preset(BASE, vehicle__secondary__kz=kz)
    op = solve_operating_point(sc, assemble(smooth_scenario(sc)))
    return op, linearise(op)


def test_jacobians_are_affine_in_a_suspension_stiffness():
    """K(k) = K(k0) + (k − k0)·∂K/∂k: the second difference over equal steps vanishes to the
    rounding of the differences, although the car body sits lower as k falls."""
    lins = [_op_and_lin(kz)[1] for kz in (2.0e5, 3.0e5, 4.0e5)]
    K0, K1, K2 = (lin.full.K * lin.mass[:, None] for lin in lins)
    scale = np.abs(K1 - K0).max()
    assert scale > 1e4  # the secondary springs' entries (N/m)
    assert np.abs(K2 - 2.0 * K1 + K0).max() <= 1e-9 * np.abs(K1).max()
    assert np.abs(lins[0].op.X0[2] - lins[2].op.X0[2]) > 1e-2  # car body z moved (m)


def test_partial_jacobian_update_equals_full_jacobians_at_the_same_point():
    rb = ModelRebuilder()
    rb.model(preset(BASE, vehicle__secondary__kz=3.0e5))
    model = rb.model(preset(BASE, vehicle__secondary__kz=3.3e5))
    assert rb.stats["jacobians_partial"] == 1
    lin = model.linearisation
    assert lin is not None
    full = linearise(lin.op)
    for name in ("K", "C", "B0"):
        a, b = getattr(lin.full, name), getattr(full.full, name)
        tol = 1e-10 * np.abs(b).max(axis=0, keepdims=True) + 1e-300
        assert np.all(np.abs(a - b) <= tol), name


def test_warm_start_lands_on_the_cold_steady_state():
    op0, lin0 = _op_and_lin(3.0e5)
    cold, _ = _op_and_lin(3.1e5)
    sc = preset(BASE, vehicle__secondary__kz=3.1e5)
    warm = solve_operating_point(sc, assemble(smooth_scenario(sc)),
                                 warm_start(op0, -lin0.full.K, -lin0.full.C))
    assert warm.chord_iterations > 0
    np.testing.assert_allclose(warm.X0, cold.X0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(warm.V0, cold.V0, rtol=0, atol=1e-12)


def test_a_kept_condensation_gives_the_fresh_one():
    _op, lin = _op_and_lin(3.0e5)
    n_veh = int(lin.op.sys.par.n_veh)
    first = reduce_track(lin.full, lin.mass, n_veh, "condensed")
    K = lin.full.K.copy()
    K[:6, :6] *= 1.01  # a change of the car body's block only
    other = type(lin.full)(K, lin.full.C, lin.full.B0, lin.full.B1, lin.full.B2)
    assert first.condensation is not None and first.condensation.fits(other, lin.mass)
    kept = reduce_track(other, lin.mass, n_veh, "condensed", previous=first)
    fresh = reduce_track(other, lin.mass, n_veh, "condensed")
    assert kept.condensation is first.condensation
    for name in ("K", "C", "B0", "B1"):
        np.testing.assert_array_equal(getattr(kept.system, name), getattr(fresh.system, name))
    K[50, 3] += 1.0  # a rail row changed: the condensation does not fit any more
    assert not first.condensation.fits(type(lin.full)(K, lin.full.C, lin.full.B0, lin.full.B1,
                                                       lin.full.B2), lin.mass)
    assert condensation(other, lin.mass, n_veh).Tr.shape == first.condensation.Tr.shape


def _eigenvalues(red) -> np.ndarray:
    lam = red.system.modes().lam
    return lam[np.lexsort((lam.imag, lam.real))]


def test_an_adapted_condensation_gives_the_fresh_one():
    """A statistical linearisation of the profile contact changes the rail rows and columns
    only in and through the rail heads: the local model's static modes serve it (new parts
    only), with the eigenvalues of a fresh condensation; a change of the rail's interior (a
    rail mode's stiffness) does not pass."""
    _op, lin = _op_and_lin(3.0e5)
    n_veh = int(lin.op.sys.par.n_veh)
    local = reduce_track(lin.full, lin.mass, n_veh, "condensed")
    sigma = np.full((lin.op.sys.ws_body.shape[0], 2), 1.5e-3)
    stat = statistical_linearisation(lin, sigma).full
    assert local.condensation is not None
    assert not local.condensation.fits(stat, lin.mass)
    assert local.condensation.interface_only(stat, lin.mass)
    adapted = reduce_track(stat, lin.mass, n_veh, "condensed", previous=local)
    fresh = reduce_track(stat, lin.mass, n_veh, "condensed")
    assert adapted.condensation is not None and adapted.condensation.Tr is local.condensation.Tr
    a, b = _eigenvalues(adapted), _eigenvalues(fresh)
    np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-9 * np.abs(b).max())
    K = stat.K.copy()
    rail = n_veh + 7
    K[rail, rail] *= 1.01
    inner = type(stat)(K, stat.C, stat.B0, stat.B1, stat.B2)
    assert not local.condensation.interface_only(inner, lin.mass)
    assert local.condensation.adapt(inner, lin.mass) is None
