"""The set-up cache (static equilibrium and stability limit by content): a cached set-up is the
uncached one bit for bit, every input that matters changes the key, what the key leaves out
changes neither the key nor the set-up, and the files are bounded, atomic and never trusted.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from conftest import preset
from flexride.solver import setup_cache as sc
from flexride.solver.assemble import assemble
from flexride.solver.setup_cache import NOT_READ, SetupCache, run_setup, setup_key
from flexride.solver.simulate import simulate
from flexride.solver.static import initial_window_start

SHORT = {"duration_s": 0.2, "distance_m": None}


def _asm(name: str = "paper-random-straight-80", **overrides):
    return assemble(preset(name, **{**SHORT, **overrides}))


def _setup(asm, cache=None):
    s0 = initial_window_start(asm, 0.0)
    return run_setup(asm, 0.0, s0, True, cache)


def _key(asm) -> str:
    return setup_key(asm, 0.0, initial_window_start(asm, 0.0))


def _same(a, b) -> None:
    assert np.array_equal(a.X0, b.X0)
    assert a.stability == b.stability


def _perturbed(sysarr, name: str):
    """``sysarr`` with one value of field ``name`` (or scalar ``par.name``) changed."""
    if name in sysarr.par._fields:
        v = getattr(sysarr.par, name)
        new = (v - 1 if v > 0 else v + 1) if isinstance(v, int) else v * 1.5 + 1.0
        return sysarr._replace(par=sysarr.par._replace(**{name: new}))
    a = np.array(getattr(sysarr, name), copy=True)
    if a.size == 0:
        return None
    flat = a.reshape(-1)
    i = flat.size // 2
    if np.issubdtype(a.dtype, np.integer):  # another valid index
        flat[i] = (flat[i] + 1) % (flat.max() + 1)
    else:
        flat[i] = flat[i] * 1.5 + 1
    return sysarr._replace(**{name: a})


def test_cached_runs_are_the_uncached_run_bit_for_bit(tmp_path):
    scen = preset("paper-random-straight-80", **SHORT)
    cache = SetupCache(directory=tmp_path)
    ref = simulate(scen, setup_cache=None)
    sources = []
    for clear in (False, False, True):  # computed, from memory, from the file
        if clear:
            cache.clear()
        res = simulate(scen, setup_cache=cache)
        sources.append(res.meta["setup_source"])
        assert res.meta["stability"] == ref.meta["stability"]
        for name, data in ref.channels.items():
            assert np.array_equal(data, res.channels[name]), name
    assert sources == ["computed", "memory", "disk"]
    # the run's start (static equilibrium on its track) and its operating point (steady
    # rolling on smooth track, with the step limit)
    assert len(list(tmp_path.glob("*.npz"))) == 2


def test_every_field_the_setup_reads_is_in_the_key():
    asm = _asm()
    key = _key(asm)
    fields = [f for f in asm.sys._fields if f != "par" and f not in NOT_READ["fields"]]
    scalars = [f for f in asm.sys.par._fields if f not in NOT_READ["par"]]
    assert len(fields) > 20 and len(scalars) > 30
    for name in fields + scalars:
        changed = _perturbed(asm.sys, name)
        if changed is None:
            continue
        assert _key(replace(asm, sys=changed)) != key, name


@pytest.mark.parametrize("overrides", [
    {"speed_kmh": 70.0},
    {"vehicle__carbody__mass": 36000.0},
    {"vehicle__primary__kz": 1.0e6},
    {"vehicle__secondary__cz": 3.0e4},
    {"track__rail__youngs_modulus": 2.0e11},
    {"track__fastener__kz": 6.0e7},
    {"contact__friction": 0.25},
    {"contact__poisson": 0.3},
    {"contact__geometry": "conical"},
    {"solver__psi": 0.45},
    {"solver__rail_margin_m": 14.0},
], ids=lambda o: next(iter(o)))
def test_each_group_of_inputs_changes_the_key(overrides):
    assert _key(_asm(**overrides)) != _key(_asm())


def test_the_route_enters_only_where_the_vehicle_stands():
    base = _asm("paper-metro")
    # a settlement under the front wheelset changes the key, one 100 m ahead does not
    near = [{"kind": "settlement", "wavelength_m": 20.0, "depth_m": 0.01, "position_m": 5.0}]
    far = [{"kind": "settlement", "wavelength_m": 20.0, "depth_m": 0.01, "position_m": 150.0}]
    assert _key(_asm("paper-metro", excitation=near)) != _key(base)
    assert _key(_asm("paper-metro", excitation=far)) == _key(base)
    # a curve starting under the vehicle changes it, one starting 100 m ahead does not
    curve = {"kind": "curve", "radius_m": 800.0, "superelevation_m": 0.1,
             "entry_transition_m": 20.0, "exit_transition_m": 20.0, "arc_length_m": 100.0}
    assert _key(_asm("paper-metro", line={**curve, "start_m": 0.0})) != _key(base)
    ahead = _asm("paper-metro", line={**curve, "start_m": 100.0})
    assert _key(ahead) == _key(base)
    _same(_setup(ahead), _setup(base))


def test_what_the_key_leaves_out_does_not_change_the_setup():
    asm = _asm()
    key, ref = _key(asm), _setup(asm)
    left_out = [f for f in NOT_READ["fields"] if f not in ("irr", "line")]
    for name in left_out + sorted(NOT_READ["par"] - {"irr_s0", "irr_ds", "ln_s0", "ln_ds"}):
        changed = _perturbed(asm.sys, name)
        if changed is None:
            continue
        other = replace(asm, sys=changed)
        assert _key(other) == key, name
        _same(_setup(other), ref)
    # route tables changed away from the vehicle: same inputs, same set-up
    irr, line = asm.sys.irr.copy(), asm.sys.line.copy()
    irr[:, -50:] += 0.01
    line[:, -50:] += 0.001
    other = replace(asm, sys=asm.sys._replace(irr=irr, line=line))
    assert _key(other) == key
    _same(_setup(other), ref)


def test_the_run_length_step_and_outputs_share_a_setup():
    base = _key(_asm("paper-metro"))
    assert _key(_asm("paper-metro", duration_s=0.4)) == base
    assert _key(_asm("paper-metro", solver__dt=5e-5)) == base
    assert _key(_asm("paper-metro", output__rate_hz=200.0)) == base


def test_files_are_bounded_validated_and_damaged_ones_ignored(tmp_path, monkeypatch):
    monkeypatch.setattr(sc, "DISK_ENTRIES", 3)
    cache = SetupCache(directory=tmp_path)
    X0 = np.arange(4.0)
    for k in range(5):
        cache.put(f"{k:064x}", X0 + k, {"dt_max": 1e-4 * k})
    assert len(list(tmp_path.glob("*.npz"))) == 3
    assert not list(tmp_path.glob("*.tmp"))
    fresh = SetupCache(directory=tmp_path)
    hit = fresh.get(f"{4:064x}", True)
    assert hit is not None and hit.source == "disk" and hit.stability == {"dt_max": 4e-4}
    assert np.array_equal(hit.X0, X0 + 4)
    (tmp_path / f"{4:064x}.npz").write_bytes(b"not a numpy file")
    assert SetupCache(directory=tmp_path).get(f"{4:064x}", False) is None
    with pytest.raises(ValueError):
        fresh.get("../../etc/passwd", False)
    # a set-up kept without the stability limit is not a hit for a run that needs it
    cache.put(f"{9:064x}", X0, None)
    assert cache.get(f"{9:064x}", True) is None and cache.get(f"{9:064x}", False) is not None


def test_memory_is_bounded(monkeypatch):
    monkeypatch.setattr(sc, "MEMORY_ENTRIES", 2)
    cache = SetupCache(disk=False)
    for k in range(4):
        cache.put(f"{k:064x}", np.zeros(2), None)
    assert cache.get(f"{0:064x}", False) is None
    assert cache.get(f"{3:064x}", False) is not None
