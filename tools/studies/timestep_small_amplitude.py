"""Study: why the explicit Zhai integration with real profiles (S1002/60E1, two slots) is not
converged at the presets' Δt = 1/12000 s for small track irregularities.

Subcommands (one process at a time; scratch in --out, default /tmp/tsa):

``run``    short solver runs of ``paper-random-straight-<speed>`` with the random irregularity
           scaled by ``--scale``, at each ``--dt`` (1/x given as x: 12000 24000 …); prints the
           rms and band rms of the lateral channels (car body, frames, wheelsets, wheel forces,
           rail-head displacement, flange-slot load) with the ratio to the last step given.
``map``    linearises the kernel's *discrete one-step map* (X, V, A_prev, creep state) by
           central differences about a settled run on a perfect track (scale 0) and prints the
           spectral radius and the least damped / unstable discrete modes, their equivalent
           continuous eigenvalue ln(μ)/Δt and the coordinates dominating them, per step.
``hf``     a short run with output at the step rate: spectra of the wheel forces, the
           wheelsets' lateral velocity and the rail heads above 500 Hz (chatter / limit cycle).
``modes``  the stability check's modal decomposition (solver/stability.py) with each mode's
           creep damping kept as the kernel's *discrete* relaxed creep state (4 × 4 map of
           x, v, F, a_prev with e = exp(−Δt/τ)) instead of the series spring c/τ: the critical
           step per mode by that law against the check's.

Findings (2026-12-02, paper-random-straight-80, S1002/60E1):

* At Δt = 1/12000 s the discrete map linearised at static equilibrium has four period-2
  roots μ ≈ −1.12 … −1.15 (rail torsion modes 57/60/64/17 under the wheels with the tread
  slots' lateral creep state); on a perfect track the lateral creep force chatters at 6 kHz
  (±800 N) within 2 ms and stays there, held by creep saturation (mean contact-frame Fy of
  the tread slot 1245 → ~330 N). Max |μ| of the period-2 roots: 1/12500 0.92, 1/13000 0.70,
  1/14000 0.20, 1/16000 0.016. The check estimates 1.11e-4 s (dt_max 1.0e-4); the relaxed
  per-mode law 7.96e-5 s (speed-independent, 50–80 km/h). Conical: check 1.39e-4 (dt_max
  1.25e-4), relaxed 9.99e-5, full map: 1e-4 stable (0.87), 1/9000 unstable (1.53).
* Scale 0.01, 45 s: car-body PC rms 0.001272 (1/12000) against 0.00162 at 1/13000, 1/14000,
  1/16000 and 1/24000 (all equal to 4 digits): the whole deficit is the chatter.

Usage::

    python tools/studies/timestep_small_amplitude.py run --scale 0.01 --seconds 60 --dt 12000 24000
    python tools/studies/timestep_small_amplitude.py map --dt 12000 16000 24000
    python tools/studies/timestep_small_amplitude.py hf --dt 12000 24000 --seconds 4
"""

from __future__ import annotations

import argparse
import os
import time
from typing import Any

import numpy as np
from scipy import signal

from flexride.scenario.presets import load_preset

POINTS = ("PC", "PFB", "PR")
BANDS = ((0.2, 2.0), (2.0, 5.0), (5.0, 10.0), (10.0, 30.0), (30.0, 100.0), (100.0, 500.0))
WS = ("wheelset1", "wheelset2", "wheelset3", "wheelset4")
SKIP_S = 5.0


KIND = "straight"
#: extra dotted-path overrides of every scenario (``--set key=value``, value as JSON)
OVERRIDES: dict[str, Any] = {}


def scenario(speed: int, scale: float, seconds: float, dt: float, extra: dict | None = None):
    ov: dict[str, Any] = {"duration_s": seconds, "distance_m": None,
                          "excitation.0.scale": scale, "solver.dt": dt}
    ov.update(OVERRIDES)
    ov.update(extra or {})
    return load_preset(f"paper-random-{KIND}-{speed}", ov)


def band_rms(x: np.ndarray, fs: float, bands=BANDS) -> list[float]:
    f, p = signal.welch(x - x.mean(), fs=fs, nperseg=min(x.size, int(4 * fs)))
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (p[1:] + p[:-1]) * np.diff(f))])
    return [float(np.sqrt(max(np.interp(hi, f, cum) - np.interp(lo, f, cum), 0.0)))
            for lo, hi in bands]


def lateral_channels(names: list[str]) -> list[str]:
    keep = [f"carbody.{p}.acc.y" for p in POINTS] + ["frame1.centre.acc.y"]
    keep += [f"{w}.centre.acc.y" for w in WS[:2]]
    keep += [f"{w}.cg.disp.y" for w in WS[:2]] + [f"{w}.cg.rot.z" for w in WS[:2]]
    keep += [n for n in names if n.startswith("wheelset1.") and (
        n.endswith(".force.y") or n.endswith(".force.flange") or n.endswith(".rail_disp.y")
        or n.endswith(".contact_angle") or n.endswith(".force.z"))]
    return [k for k in keep if k in names]


def cmd_run(a) -> None:
    from flexride.solver.simulate import simulate
    res_all = {}
    for x in a.dt:
        dt = 1.0 / x
        sc = scenario(a.speed, a.scale, a.seconds, dt)
        t0 = time.perf_counter()
        res = simulate(sc)
        wall = time.perf_counter() - t0
        fs = float(res.sample_rate)
        skip = int(SKIP_S * fs)
        names = list(res.channels)
        if not res_all:
            chans = lateral_channels(names)
        rec = {n: np.asarray(res.channels[n])[skip:] for n in chans}
        np.savez_compressed(os.path.join(a.out, f"run_s{a.scale:g}_dt{x:g}.npz"), **rec)
        res_all[x] = {n: (float(np.std(v)), band_rms(v, fs)) for n, v in rec.items()}
        print(f"Δt = 1/{x:g} s: {wall:.1f} s wall, stability {res.meta.get('stability')}",
              flush=True)
    ref = a.dt[-1]
    print(f"\nscale {a.scale:g}, {a.seconds:g} s at {a.speed} km/h (first {SKIP_S:g} s skipped);"
          f" ratio = rms(Δt)/rms(1/{ref:g})")
    hdr = "channel".ljust(34) + "".join(f"{f'1/{x:g}':>12}" for x in a.dt) \
        + "  band ratios (first Δt / ref) " + " ".join(f"{lo:g}-{hi:g}" for lo, hi in BANDS)
    print(hdr)
    for n in chans:
        r = res_all[ref][n]
        row = n.ljust(34) + "".join(f"{res_all[x][n][0]:12.4g}" for x in a.dt)
        br = [res_all[a.dt[0]][n][1][k] / r[1][k] if r[1][k] > 0 else np.nan
              for k in range(len(BANDS))]
        print(row + "  " + " ".join(f"{v:6.3f}" for v in br))


def _setup(a, x: float, scale: float = 0.0, seconds: float = 1.0):
    from flexride.solver.assemble import assemble
    from flexride.solver.forces import evaluate
    from flexride.solver.setup_cache import run_setup
    from flexride.solver.simulate import _workspace, convected_rail_velocity
    from flexride.solver.static import initial_window_start
    sc = scenario(a.speed, scale, seconds, 1.0 / x)
    asm = assemble(sc)
    s_win0 = initial_window_start(asm, 0.0)
    setup = run_setup(asm, 0.0, s_win0, False, None)
    X0 = setup.X0
    V0 = convected_rail_velocity(asm, X0)
    ws = _workspace(asm, X0, V0, X0.copy(), s_win0)
    evaluate(asm.sys, ws.X, ws.V, 0.0, s_win0, ws.F, ws.A, ws.aux, ws.sn, ws.cst, 0.0)
    return sc, asm, ws


def _step(asm, ws, n):
    from flexride.solver.kernel import run_chunk
    return run_chunk(asm.sys, ws.X, ws.V, ws.A, ws.Ap, ws.F, ws.aux, ws.sn, ws.cst, ws.facc,
                     ws.eacc, ws.ptv, ws.pscr, ws.X_ref, ws.u, ws.q, ws.tstate, n, ws.rec,
                     ws.rec_t, ws.rec_s, ws.info, ws.watch)


def _pack(ws):
    return np.concatenate([ws.X, ws.V, ws.A, ws.Ap, ws.cst.ravel()])


def _unpack(ws, z, n):
    ws.X[:] = z[:n]
    ws.V[:] = z[n:2 * n]
    ws.A[:] = z[2 * n:3 * n]
    ws.Ap[:] = z[3 * n:4 * n]
    ws.cst[...] = z[4 * n:].reshape(ws.cst.shape)


def state_names(asm) -> list[str]:
    nc = asm.sys.ws_body.shape[0] * 2 * 6
    cn = [f"cst.ws{w + 1}.{'LR'[s]}.slot{k // 3}.{('Fx', 'Fy', 'Mz')[k % 3]}"
          for w in range(nc // 12) for s in range(2) for k in range(6)]
    return ([f"X:{d}" for d in asm.dof_names] + [f"V:{d}" for d in asm.dof_names]
            + [f"A:{d}" for d in asm.dof_names] + [f"Ap:{d}" for d in asm.dof_names] + cn)


def one_step_map(asm, ws, settle_steps: int):
    """Jacobian of the kernel's one-step map at the state after ``settle_steps`` steps."""
    from flexride.solver import system as S
    _step(asm, ws, settle_steps)
    n = ws.X.shape[0]
    # avoid a rail-window shift inside the differenced step
    for _ in range(100000):
        snap = {k: getattr(ws, k).copy() for k in ("X", "V", "A", "Ap", "cst", "tstate", "facc",
                                                    "ptv", "F", "aux")}
        _step(asm, ws, 1)
        shifted = ws.tstate[S.T_WIN_S0] != snap["tstate"][S.T_WIN_S0]
        for k, v in snap.items():
            getattr(ws, k)[...] = v
        if not shifted:
            break
        _step(asm, ws, 1)
    base = {k: getattr(ws, k).copy() for k in ("X", "V", "A", "Ap", "cst", "tstate", "facc",
                                                "ptv", "F", "aux")}
    z0 = _pack(ws)
    m = z0.size
    scal = np.concatenate([np.full(n, 1e-8), np.full(n, 1e-6), np.full(n, 1e-3),
                           np.full(n, 1e-3), np.full(ws.cst.size, 1e-2)])
    J = np.zeros((m, m))

    def fwd(z):
        for k, v in base.items():
            getattr(ws, k)[...] = v
        _unpack(ws, z, n)
        # state of the step: X_n, V_n, A_n (evaluated at the end of the last step),
        # A_{n-1} and the relaxed creep forces cst_n
        _step(asm, ws, 1)
        return _pack(ws)

    for j in range(m):
        h = scal[j]
        zp = z0.copy()
        zp[j] += h
        zm = z0.copy()
        zm[j] -= h
        J[:, j] = (fwd(zp) - fwd(zm)) / (2 * h)
    for k, v in base.items():
        getattr(ws, k)[...] = v
    return J


def _dominant(vec, names, k=3):
    w = np.abs(vec)
    w = w / w.max()
    idx = np.argsort(w)[::-1][:k]
    return ", ".join(f"{names[i]}({w[i]:.2f})" for i in idx)


def cmd_map(a) -> None:
    for x in a.dt:
        dt = 1.0 / x
        _sc, asm, ws = _setup(a, x, 0.0, 2.0)
        settle = round(a.settle / dt)
        t0 = time.perf_counter()
        J = one_step_map(asm, ws, settle)
        names = state_names(asm)
        n = ws.X.shape[0]
        mu, vec = np.linalg.eig(J)
        # scale the eigenvector components by typical magnitudes for the dominance measure:
        # compare only displacement (X) and creep-state parts
        ok = np.abs(mu) > 1e-6
        lam = np.full(mu.shape, np.nan, complex)
        lam[ok] = np.log(mu[ok]) / dt
        np.savez_compressed(os.path.join(a.out, f"map_dt{x:g}.npz"), mu=mu, J=J,
                            names=np.array(names))
        print(f"\nΔt = 1/{x:g} s: state {J.shape[0]}, map {time.perf_counter() - t0:.1f} s, "
              f"spectral radius {np.abs(mu).max():.6f}")
        order = np.argsort(-np.abs(mu))
        print("  least damped discrete modes: |μ|, f (Hz), σ = Re ln μ/Δt (1/s), dominant X/cst")
        shown = 0
        for i in order:
            if mu[i].imag < -1e-12:
                continue
            v = vec[:, i]
            print(f"   |μ|={abs(mu[i]):.6f} μ={mu[i]:.4f} f={lam[i].imag / 2 / np.pi:8.1f} "
                  f"σ={lam[i].real:10.2f}\n      X: {_dominant(v[:n], names[:n])}"
                  f"\n      V: {_dominant(v[n:2 * n], names[n:2 * n])}"
                  f"\n      creep state: {_dominant(v[4 * n:], names[4 * n:], 4)}")
            shown += 1
            if shown >= a.top:
                break
        # most negative real parts with |λ|Δt large
        big = np.where(ok & (np.abs(lam) * dt > a.ldt))[0]
        print(f"  modes with |ln μ| > {a.ldt}: {big.size}")
        for i in big[np.argsort(-np.abs(lam[big]))][: a.top]:
            if mu[i].imag < -1e-12:
                continue
            v = vec[:, i].copy()
            v[n:4 * n] = 0.0
            v[4 * n:] *= 1e-7
            print(f"   μ={mu[i]:.4f} |λ|Δt={abs(lam[i]) * dt:.3f} f={lam[i].imag / 2 / np.pi:8.1f}"
                  f" σ={lam[i].real:11.1f}  {_dominant(v, names)}")


def cmd_hf(a) -> None:
    from flexride.solver.simulate import simulate
    for x in a.dt:
        dt = 1.0 / x
        rate = min(x, 12000.0)
        sc = scenario(a.speed, a.scale, a.seconds, dt, {"output.rate_hz": rate})
        res = simulate(sc)
        fs = float(res.sample_rate)
        skip = int(1.0 * fs)
        names = [n for n in res.channels if n.startswith("wheelset1.") and (
            n.endswith(".force.y") or n.endswith(".force.z") or n.endswith(".rail_disp.y")
            or n.endswith(".force.flange"))] + ["wheelset1.centre.acc.y", "wheelset1.cg.disp.y"]
        names = [n for n in names if n in res.channels]
        hb = ((0, 50), (50, 200), (200, 500), (500, 1500), (1500, 3000), (3000, fs / 2))
        print(f"\nΔt = 1/{x:g}, output {fs:g} Hz, scale {a.scale:g}: band rms")
        print("channel".ljust(34) + "".join(f"{f'{b[0]:g}-{b[1]:g}':>12}" for b in hb)
              + "        mean")
        for n in names:
            v = np.asarray(res.channels[n])[skip:]
            br = band_rms(v, fs, hb)
            print(n.ljust(34) + "".join(f"{b:12.4g}" for b in br) + f"{v.mean():12.5g}")
        np.savez_compressed(os.path.join(a.out, f"hf_s{a.scale:g}_dt{x:g}.npz"),
                            **{n: np.asarray(res.channels[n]) for n in names})


def relaxed_amplification(omega, c0, ccr, tau, dt, psi=0.5, phi=0.5):
    """The kernel's discrete map for one mode (unit modal mass) with the creep force as a
    relaxed state: a_n = −ω²x_n − c0·v_n + F_n, Zhai's update of (x, v), then
    F_{n+1} = e·F_n − (1 − e)·ccr·v_{n+1}, e = exp(−Δt/τ) (as forces._relax_creep_state).
    State (x, v, F, a_prev); returns the 4 × 4 matrix."""
    e = np.exp(-dt / tau)
    w2 = omega ** 2
    # a = [-w2, -c0, 1, 0] · z
    arow = np.array([-w2, -c0, 1.0, 0.0])
    xr = np.array([1.0, dt, 0.0, 0.0]) + (0.5 + psi) * dt ** 2 * arow \
        - psi * dt ** 2 * np.array([0, 0, 0, 1.0])
    vr = np.array([0.0, 1.0, 0.0, 0.0]) + (1 + phi) * dt * arow \
        - phi * dt * np.array([0, 0, 0, 1.0])
    fr = e * np.array([0, 0, 1.0, 0]) - (1 - e) * ccr * vr
    return np.vstack([xr, vr, fr, arow])


def relaxed_radius(omega, c0, ccr, tau, dt, psi=0.5, phi=0.5):
    return float(np.abs(np.linalg.eigvals(relaxed_amplification(omega, c0, ccr, tau, dt,
                                                                 psi, phi))).max())


def relaxed_critical_step(omega, c0, ccr, tau, psi=0.5, phi=0.5, hi=1e-3):
    """Smallest Δt at which the relaxed scalar map becomes unstable (scan, then bisection)."""
    grid = np.geomspace(1e-7, hi, 400)
    bad = [dt for dt in grid if relaxed_radius(omega, c0, ccr, tau, dt, psi, phi) > 1 + 1e-9]
    if not bad:
        return hi
    b = bad[0]
    lo = grid[max(np.searchsorted(grid, b) - 1, 0)]
    for _ in range(50):
        mid = 0.5 * (lo + b)
        if relaxed_radius(omega, c0, ccr, tau, mid, psi, phi) > 1 + 1e-9:
            b = mid
        else:
            lo = mid
    return lo


def cmd_modes(a) -> None:
    """The stability check's modal decomposition, with the creep damping kept as a relaxed
    state (the kernel's discrete law) instead of the series spring c/τ."""
    from flexride.solver.linearise import jacobian
    from flexride.solver.stability import creep_relaxation_time, critical_step, stability_limit
    x = a.dt[0]
    _sc, asm, ws = _setup(a, x, 0.0, 1.0)
    sys = asm.sys
    X0 = ws.X_ref.copy()
    from flexride.solver.static import initial_window_start
    s_win0 = initial_window_start(asm, 0.0)
    n = X0.size
    V0 = np.zeros(n)
    cols = np.arange(n)
    K = -jacobian(sys, X0, V0, 0.0, s_win0, cols)
    C = -jacobian(sys, X0, V0, 0.0, s_win0, cols, wrt_velocity=True)
    nf = sys._replace(par=sys.par._replace(mu=0.0))
    C0 = -jacobian(nf, X0, V0, 0.0, s_win0, cols, wrt_velocity=True)
    tau = creep_relaxation_time(asm)
    sq = np.sqrt(1.0 / sys.minv)
    isq = 1.0 / sq

    def sym(Mx):
        Ms = sq[:, None] * Mx * isq[None, :]
        return 0.5 * (Ms + Ms.T)
    Ccr = sym(C - C0)
    Ks_check = sym(K + (C - C0) / tau)
    lam, vec = np.linalg.eigh(Ks_check)          # the check's modes
    Kp = sym(K)
    om_chk = np.sqrt(np.clip(lam, 0, None))
    c0m = np.clip(np.sum(vec * (sym(C0) @ vec), axis=0), 0, None)
    ccm = np.clip(np.sum(vec * (Ccr @ vec), axis=0), 0, None)
    om_k = np.sqrt(np.clip(np.sum(vec * (Kp @ vec), axis=0), 0, None))
    dchk = critical_step(om_chk, c0m, sys.par.psi, sys.par.phi)
    info = stability_limit(asm, X0, 0.0, s_win0)
    print(f"creep relaxation time τ = {tau * 1e6:.1f} µs (Δt/τ: 1/12000 → {1 / 12000 / tau:.3f},"
          f" 1/24000 → {1 / 24000 / tau:.3f}); the check: dt_max {info['dt_max']:.4g} s, "
          f"critical {info['critical_dof']} at {info['critical_frequency_hz']:.0f} Hz")
    order = np.argsort(dchk)[: a.top * 4]
    rows = []
    for j in order:
        drel = relaxed_critical_step(om_k[j], c0m[j], ccm[j], tau)
        rows.append((j, drel))
    rows.sort(key=lambda r: r[1])
    print("mode  dominant coordinate              f_K(Hz)  f_chk(Hz)  c0(1/s)  c_creep(1/s) "
          " c_cr·Δt(1/12000)  Δt_chk(s)  Δt_relaxed(s)  ρ(1/12000)  ρ(1/13000)")
    for j, drel in rows[: a.top]:
        dof = asm.dof_names[int(np.argmax(np.abs(vec[:, j])))]
        r12 = relaxed_radius(om_k[j], c0m[j], ccm[j], tau, 1 / 12000)
        r13 = relaxed_radius(om_k[j], c0m[j], ccm[j], tau, 1 / 13000)
        print(f"{j:4d}  {dof:32s} {om_k[j] / 2 / np.pi:8.0f} {om_chk[j] / 2 / np.pi:9.0f} "
              f"{c0m[j]:8.1f} {ccm[j]:12.0f} {ccm[j] / 12000:14.3f} {dchk[j]:11.4g} "
              f"{drel:13.4g} {r12:10.4f} {r13:10.4f}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__.split("\n\n", 1)[1])
    ap.add_argument("--out", default="/tmp/tsa")
    ap.add_argument("--speed", type=int, default=80)
    ap.add_argument("--kind", choices=("straight", "curve"), default="straight",
                    help="paper-random-<kind>-<speed>")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="scenario override, e.g. contact.geometry=\"conical\"")
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run", help="solver runs at several steps")
    r.add_argument("--dt", type=float, nargs="+", default=[12000, 24000], help="1/Δt values")
    r.add_argument("--scale", type=float, default=0.01)
    r.add_argument("--seconds", type=float, default=60.0)
    m = sub.add_parser("map", help="eigenvalues of the kernel's discrete one-step map")
    m.add_argument("--dt", type=float, nargs="+", default=[12000, 24000])
    m.add_argument("--settle", type=float, default=0.5, help="s on a perfect track first")
    m.add_argument("--top", type=int, default=12)
    m.add_argument("--ldt", type=float, default=0.3)
    h = sub.add_parser("hf", help="output at step rate, spectra above 500 Hz")
    h.add_argument("--dt", type=float, nargs="+", default=[12000, 24000])
    h.add_argument("--scale", type=float, default=0.01)
    h.add_argument("--seconds", type=float, default=4.0)
    o = sub.add_parser("modes", help="the stability check's modes with relaxed creep damping")
    o.add_argument("--dt", type=float, nargs="+", default=[12000])
    o.add_argument("--top", type=int, default=10)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    global KIND
    KIND = a.kind
    import json
    for kv in a.set:
        k, v = kv.split("=", 1)
        try:
            OVERRIDES[k] = json.loads(v)
        except json.JSONDecodeError:
            OVERRIDES[k] = v
    {"run": cmd_run, "map": cmd_map, "hf": cmd_hf, "modes": cmd_modes}[a.cmd](a)


if __name__ == "__main__":
    main()
