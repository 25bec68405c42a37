"""Study: which side is wrong when the quasi-linear estimate with real profiles is low?

Diagnoses the gap between the frequency-domain estimate with S1002/60E1 (statistical
linearisation, :mod:`flexride.frequency.quasilinear`) and the time-domain solver on
``paper-random-straight-{speed}`` (rigid bodies, as tests/frequency/test_against_time_domain.py:
``distance_m`` long runs, the first 10 s skipped). For each case (speed, amplitude factor
``scale`` of the random irregularity, all four components, distance) it

1. runs the solver and records the car-body, frame and wheelset lateral accelerations, the
   wheelsets' and frames' lateral displacement and yaw, and each wheel's lateral displacement
   on the rail head Δy = y_wheelset − (rail head's elastic y + lateral irregularity);
2. builds the local and the statistical (quasi-linear) model of the same scenario, and the
   estimate's spectral expectations (rms of the car-body points, σ of Δy per wheel);
3. drives both linear models with the *same* irregularity realisation as the solver
   (FFT through the models' FRFs, as :func:`flexride.frequency.linear_time_history`, extended
   to displacements and Δy): record-to-record ratios free of the realisation's scatter;
4. prints rms and band rms (Welch, 8 s Hann segments) of the lateral channels for
   solver / local / quasi-linear, and the solver's Δy statistics (σ, skewness, kurtosis,
   share beyond 2σ and 3σ, share of time with flange force) against the Gaussian's.

Further subcommands work on the saved records (npz) or on the estimate alone:

``print``        the tables of finished cases again (their json);
``psd``          band rms ratios local/solver and statistical/solver, the solver's gain on the
                 statistical record |S_qs|/S_qq and the share of the solver's power coherent
                 with it (what any linear filter of that record can explain);
``coherence``    multiple coherence of the solver's channels with the four rail inputs at the
                 leading wheelset (the share any linear time-invariant model can explain), the
                 statistical record's own as the estimator's reference (1 up to bias);
``gains``        empirical vs Gaussian-equivalent gains of the rigid-contact Δr(y), Δγ(y) over
                 the solver's and the model's Δy, the residual variance share and its spectrum;
``residual``     proposal check: the statistical record plus the model's response to the
                 Δr-residual of its own (Gaussian) Δy, fed back as a rail shift (no solver data);
``sigma-sweep``  the statistical model at prescribed σ (factors of the estimate's fixed point):
                 how the car-body rms depends on σ.

Usage::

    python tools/studies/quasilinear_diagnosis.py run 80:1:10000 80:0.01:5000 \
        [--set solver.dt=4.1666666666666665e-05] [--out /tmp/qld]
    python tools/studies/quasilinear_diagnosis.py psd /tmp/qld/v80_s1_d10000.npz
    python tools/studies/quasilinear_diagnosis.py coherence /tmp/qld/v80_s1_d10000.npz 80:1:10000
    python tools/studies/quasilinear_diagnosis.py gains /tmp/qld/v80_s1_d10000.npz 80:1:10000
    python tools/studies/quasilinear_diagnosis.py residual /tmp/qld/v80_s1_d10000.npz 80:1:10000
    python tools/studies/quasilinear_diagnosis.py sigma-sweep --speed 80 --factors 0.9 1 1.1

A 10 km case takes 0.5–1.5 min of solver (1/12000 s; twice that at half the step) and
≈ 30 s for the models and records; keep to one at a time on a shared machine.

Findings (2026-12-02, paper-random-straight-80/50, 10 km, same-realisation ratios):

* Δt: at the presets' 1/12000 s the solver is not converged for small irregularities
  (scale ≤ 0.02: car-body lateral rms 23–25 % low against 1/24000 s, which equals 1/48000 s;
  scale 0.1: 12 % low); at scale ≥ 0.3 and at the presets' amplitude it is (0.1443 both).
  At the converged step the local model matches the solver within 2.5–3.5 % at scale
  0.003–0.01 (Δy σ within 0.6 %): the linear model is right where the contact is linear.
* At scale 1 the solver's car-body lateral power is only 88–91 % (PC, PFB) and 94–96 % (PR)
  linearly coherent with the track input (multiple and single coherence agree): no
  mean-square-optimal linear model can exceed −4.7 … −6.1 % rms at PC/PFB, −2 … −3 % at PR. The
  statistical model adds −0.4 … −4 % from its linear part (solver gain 1.05–1.10 on it at
  2–3 Hz). The deficit starts at the wheelsets (yaw −22/−31/−48 % at 2–3/3–5/5–10 Hz) and is
  passed on unchanged by frames and secondary suspension.
* ``residual``: feeding the Δr residual of the model's own Gaussian Δy back as a rail shift
  brings the design-amplitude cases from −6 … −9 % to −2 … +7 % (1–2 Hz overshoots by 3–13 %),
  but the same residual made of the solver's Δy (``--source solver``; Δr or Δγ) adds only
  +1 … +3 % and leaves 2–5 Hz as it was (it does restore the wheelsets' yaw above 5 Hz): the
  Gaussian version's agreement comes from its flange tails, not from the mechanism of the
  solver's 2–5 Hz power, which a memoryless Δy residual does not carry.

Scratch output (npz of the records, json of the tables) goes to ``--out`` (/tmp/qld).
"""

from __future__ import annotations

import argparse
import itertools
import json
import os
import time
from typing import Any

import numpy as np
from scipy import signal, stats

from flexride.frequency import estimate
from flexride.frequency.model import OutputMap, model_from
from flexride.frequency.quasilinear import statistical_linearisation
from flexride.frequency.response import response
from flexride.frequency.timehistory import PAD_S, _frf_times_input
from flexride.scenario.presets import load_preset
from flexride.solver.assemble import assemble
from flexride.solver.simulate import simulate

SKIP_S = 10.0
POINTS = ("PC", "PFB", "PR")
BANDS = ((0.2, 1.0), (1.0, 2.0), (2.0, 3.0), (3.0, 5.0), (5.0, 10.0), (10.0, 25.0))
WHEELSETS = ("wheelset1", "wheelset2", "wheelset3", "wheelset4")
SIDES = ("left", "right")
#: lateral channels compared (acceleration channels as the solver names them, displacement
#: coordinates as ``<body>.y`` / ``<body>.yaw``)
ACC = [f"carbody.{p}.acc.y" for p in POINTS] + ["frame1.centre.acc.y", "frame2.centre.acc.y"] \
    + [f"{w}.centre.acc.y" for w in WHEELSETS]
DISP = ["frame1.y", "frame1.yaw", "frame2.y", "frame2.yaw"] \
    + [f"{w}.{q}" for w in WHEELSETS for q in ("y", "yaw")]
SOLVER_DISP = {f"{b}.y": f"{b}.cg.disp.y" for b in ("frame1", "frame2", *WHEELSETS)} | \
    {f"{b}.yaw": f"{b}.cg.rot.z" for b in ("frame1", "frame2", *WHEELSETS)}
DY = [f"{w}.{s}.rel_disp.y" for w in WHEELSETS for s in SIDES]


#: extra dotted-path overrides of every scenario (``--set``), e.g. the conical tread
OVERRIDES: dict[str, Any] = {}


def scenario(speed: int, scale: float, distance: float):
    return load_preset(f"paper-random-straight-{speed}",
                       {"distance_m": distance, "duration_s": None,
                        "excitation.0.scale": scale, **OVERRIDES})


def band_rms(x: np.ndarray, fs: float) -> list[float]:
    f, p = signal.welch(x, fs=fs, nperseg=int(8 * fs))
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (p[1:] + p[:-1]) * np.diff(f))])
    return [float(np.sqrt(max(np.interp(hi, f, cum) - np.interp(lo, f, cum), 0.0)))
            for lo, hi in BANDS]


def linear_records(model, profile, t: np.ndarray) -> dict[str, np.ndarray]:
    """The linear model over ``profile`` from rest (as linear_time_history) for the lateral
    accelerations of ACC, the coordinates of DISP and each wheel's Δy."""
    dt = float(t[1] - t[0])
    nfft = int(2 ** np.ceil(np.log2(t.size + PAD_S / dt)))
    tt = t[0] + dt * np.arange(nfft)
    u = np.zeros((model.system.m, nfft))
    for w, x in enumerate(model.wheelset_x):
        rails = profile.sample(model.speed * tt + x)
        for c in range(4):
            u[4 * w + c] = rails[c]
    u[:, t.size:] = 0.0
    U = np.fft.rfft(u, axis=-1)
    f = np.fft.rfftfreq(nfft, dt)
    acc = model.accelerations
    ia = [acc.names.index(n) for n in ACC]
    n = model.system.n
    G_d = np.zeros((len(DISP), n))
    for k, name in enumerate(DISP):
        G_d[k, model.dof_names.index(name)] = 1.0
    wh = model.wheels
    iw = [wh.names.index(n_) for n_ in DY]
    P = np.vstack([acc.P[ia], np.zeros((len(DISP), n)), wh.P[iw]])
    G = np.vstack([acc.G[ia], G_d, wh.G[iw]])
    D = np.vstack([acc.D[ia], np.zeros((len(DISP), acc.D.shape[1])), wh.D[iw]])
    out = OutputMap(ACC + DISP + DY, P, G, D)
    names = out.names
    Y = _frf_times_input(model, out.P, out.G, out.D, f, U)
    y = np.fft.irfft(Y, nfft, axis=-1)[:, : t.size]
    return dict(zip(names, y, strict=True))


def solver_records(sc, res, profile, wheelset_x) -> dict[str, np.ndarray]:
    ch = res.channels
    rec = {n: np.asarray(ch[n]) for n in ACC}
    rec |= {k: np.asarray(ch[v]) for k, v in SOLVER_DISP.items()}
    s = np.asarray(res.distance)
    for ws, x in zip(WHEELSETS, wheelset_x, strict=True):
        _zl, _zr, yl, yr = profile.sample(s + x)
        for side, y_irr in zip(SIDES, (yl, yr), strict=True):
            rec[f"{ws}.{side}.rel_disp.y"] = (np.asarray(ch[f"{ws}.cg.disp.y"])
                                              - np.asarray(ch[f"{ws}.{side}.rail_disp.y"])
                                              - y_irr)
            fl = ch.get(f"{ws}.{side}.force.flange")
            rec[f"{ws}.{side}.flange"] = np.zeros_like(s) if fl is None else np.asarray(fl)
    return rec


def spectral(est) -> dict[str, Any]:
    """The estimate's expectations: car-body lateral rms and band rms, σ of Δy per wheel."""
    resp = response(est.model, points=list(POINTS))
    f = resp.frequencies
    out: dict[str, Any] = {}
    for p in POINTS:
        ch = f"carbody.{p}.acc.y"
        psd = resp.psd[resp.index(ch)]
        cum = np.concatenate([[0.0], np.cumsum(0.5 * (psd[1:] + psd[:-1]) * np.diff(f))])
        out[ch] = {"rms": float(est.comfort.point(p).directions["y"].rms),
                   "bands": [float(np.sqrt(max(np.interp(hi, f, cum) - np.interp(lo, f, cum),
                                                0.0))) for lo, hi in BANDS]}
    var = resp.variance(resp.wheel_psd)
    for i, name in enumerate(resp.wheel_channels):
        if name.endswith(".rel_disp.y"):
            out[name] = {"rms": float(np.sqrt(max(var[i], 0.0)))}
    return out


def gauss_stats(x: np.ndarray, flange: np.ndarray | None = None) -> dict[str, float]:
    x = x - np.mean(x)
    sd = float(np.std(x))
    d = {"sigma_mm": 1e3 * sd, "skew": float(stats.skew(x)),
         "kurtosis": float(stats.kurtosis(x, fisher=False)),
         "beyond_2s": float(np.mean(np.abs(x) > 2 * sd)),
         "beyond_3s": float(np.mean(np.abs(x) > 3 * sd))}
    if flange is not None:
        d["flange_share"] = float(np.mean(np.abs(flange) > 1.0))
    return d


def run_case(speed: int, scale: float, distance: float, outdir: str) -> dict[str, Any]:
    tag = f"v{speed}_s{scale:g}_d{distance:g}" + "".join(
        f"_{k.split('.')[-1]}{v}" for k, v in OVERRIDES.items())
    sc = scenario(speed, scale, distance)
    t0 = time.perf_counter()
    res = simulate(sc)
    t_sim = time.perf_counter() - t0
    fs = float(res.sample_rate)
    t = np.asarray(res.time)
    profile = assemble(sc).irregularity
    ests = {m: estimate(sc, linearisation=m, strict=False) for m in ("local", "statistical")}
    skip = int(SKIP_S * fs)
    recs = {"solver": solver_records(sc, res, profile, ests["local"].model.wheelset_x)}
    for m, e in ests.items():
        recs[m] = linear_records(e.model, profile, t)
    recs = {k: {n: v[skip:] for n, v in r.items()} for k, r in recs.items()}
    np.savez_compressed(os.path.join(outdir, tag + ".npz"),
                        **{f"{k}|{n}": v.astype(np.float32) for k, r in recs.items()
                           for n, v in r.items()})
    table: dict[str, Any] = {"speed": speed, "scale": scale, "distance": distance,
                             "t_sim_s": t_sim, "fs": fs, "channels": {}, "dy": {},
                             "spectral": {m: spectral(e) for m, e in ests.items()},
                             "ql": ests["statistical"].model.quasi_linear.to_dict()}
    for name in ACC + DISP + DY:
        table["channels"][name] = {k: {"rms": float(np.std(r[name])),
                                       "bands": band_rms(r[name], fs)}
                                   for k, r in recs.items()}
    for name in DY:
        fl = recs["solver"][name.replace("rel_disp.y", "flange")]
        table["dy"][name] = {"solver": gauss_stats(recs["solver"][name], fl),
                             "local": gauss_stats(recs["local"][name]),
                             "statistical": gauss_stats(recs["statistical"][name])}
    with open(os.path.join(outdir, tag + ".json"), "w", encoding="utf-8") as fh:
        json.dump(table, fh, indent=1)
    return table


def _pct(a: float, b: float) -> str:
    return f"{100 * (a / b - 1):+6.1f}%" if b else "   —  "


def print_case(tb: dict[str, Any]) -> None:
    print(f"\n=== {tb['speed']} km/h, scale {tb['scale']:g}, {tb['distance']:g} m "
          f"(solver {tb['t_sim_s']:.0f} s) ===")
    print("rms: solver | same-realisation local, statistical (vs solver) | spectral local, "
          "statistical (vs solver)")
    sp = tb["spectral"]
    for name in ACC + DISP + DY:
        c = tb["channels"][name]
        s, lo, st = c["solver"]["rms"], c["local"]["rms"], c["statistical"]["rms"]
        line = f"  {name:<28s} {s:10.4g} | {_pct(lo, s)} {_pct(st, s)}"
        if name in sp["statistical"]:
            line += (f" | {_pct(sp['local'][name]['rms'], s)} "
                     f"{_pct(sp['statistical'][name]['rms'], s)}")
        print(line)
    print("band rms, statistical (same realisation) vs solver; bands "
          + " ".join(f"{lo:g}-{hi:g}" for lo, hi in BANDS) + " Hz")
    for name in ACC + DISP:
        c = tb["channels"][name]
        r = [_pct(b, a) for a, b in zip(c["solver"]["bands"], c["statistical"]["bands"],
                                        strict=True)]
        print(f"  {name:<28s} " + " ".join(r))
    print("  (local)")
    for name in [*ACC[:3], "wheelset1.y", "wheelset1.yaw"]:
        c = tb["channels"][name]
        r = [_pct(b, a) for a, b in zip(c["solver"]["bands"], c["local"]["bands"],
                                        strict=True)]
        print(f"  {name:<28s} " + " ".join(r))
    print("solver band rms (abs) of car body PFB, PC: ")
    for name in ACC[:3]:
        print(f"  {name:<28s} " + " ".join(f"{b:7.4f}" for b in
                                           tb["channels"][name]["solver"]["bands"]))
    print("Δy: σ (mm) solver / statistical same-realisation / estimate's σ; solver skew, "
          "kurtosis, P(>2σ), P(>3σ) [Gauss 4.55 %, 0.27 %], flange share")
    sig = tb["ql"].get("sigma_m", {})
    print(f"  (quasi-linear iteration: converged {tb['ql'].get('converged')}, "
          f"{tb['ql'].get('iterations')} iterations, last changes "
          f"{[round(c, 4) for c in tb['ql'].get('sigma_change', [])[-3:]]})")
    for name in DY:
        d = tb["dy"][name]
        key = name.removesuffix(".rel_disp.y")
        s = d["solver"]
        print(f"  {key:<18s} {s['sigma_mm']:6.3f} / {d['statistical']['sigma_mm']:6.3f} / "
              f"{1e3 * sig.get(key, float('nan')):6.3f}   {s['skew']:+5.2f} {s['kurtosis']:5.2f} "
              f"{100 * s['beyond_2s']:5.2f}% {100 * s['beyond_3s']:5.2f}% "
              f"{100 * s['flange_share']:5.2f}%")


def psd_table(npz: str, channels: list[str], f_lo: float, f_hi: float, df: float,
              fs: float = 1000.0) -> None:
    """PSD of ``channels`` in the saved records (Welch, 16 s segments) in bands of ``df``:
    solver's band rms and the ratio local/solver, statistical/solver, and the coherence-based
    transfer |H| = |S_model,solver| / S_solver,solver (same realisation)."""
    data = np.load(npz)
    edges = np.arange(f_lo, f_hi + 1e-9, df)
    for ch in channels:
        x = {k: data[f"{k}|{ch}"].astype(float) for k in ("solver", "local", "statistical")}
        nper = int(16 * fs)
        f, ps = signal.welch(x["solver"], fs=fs, nperseg=nper)
        print(f"\n{ch} ({npz.rsplit('/', 1)[-1]}): band, solver rms, local/solver, "
              "statistical/solver (rms ratios), gain |S_qs|/S_qq of the solver on the "
              "statistical model's record, solver power share coherent with it")
        for k in ("local", "statistical"):
            _f, p = signal.welch(x[k], fs=fs, nperseg=nper)
            x[k + "_p"] = p
        _f, cs = signal.csd(x["statistical"], x["solver"], fs=fs, nperseg=nper)
        tot = {k: 0.0 for k in ("s", "l", "q", "coh")}
        for lo, hi in itertools.pairwise(edges):
            m = (f >= lo) & (f < hi)
            a = ps[m].sum()
            # power of the solver record linearly coherent with the statistical model's record
            # (per bin |S_sq|²/S_qq, summed): the part any linear filter of it can explain
            coh = float(np.sum(np.abs(cs[m]) ** 2 / x["statistical_p"][m]))
            for k, v in (("s", a), ("l", x["local_p"][m].sum()),
                         ("q", x["statistical_p"][m].sum()), ("coh", coh)):
                tot[k] += v
            print(f"  {lo:5.2f}-{hi:5.2f} {np.sqrt(a * (f[1] - f[0])):9.3g} "
                  f"{np.sqrt(x['local_p'][m].sum() / a):6.3f} "
                  f"{np.sqrt(x['statistical_p'][m].sum() / a):6.3f} "
                  f"{abs(cs[m].sum()) / x['statistical_p'][m].sum():6.3f}  "
                  f"coherent share {coh / a:6.3f}")
        print(f"  {'total':11s} {np.sqrt(tot['s'] * (f[1] - f[0])):9.3g} "
              f"{np.sqrt(tot['l'] / tot['s']):6.3f} {np.sqrt(tot['q'] / tot['s']):6.3f} "
              f"{'':6s}  coherent share {tot['coh'] / tot['s']:6.3f}")


def multiple_coherence(npz: str, speed: int, scale: float, distance: float,
                       channels: list[str], f_lo: float, f_hi: float, df: float,
                       fs: float = 1000.0, segment_s: float = 8.0) -> None:
    """Share of each solver channel's power that ANY linear time-invariant model of the track
    input can explain: the multiple coherence γ²(f) = S_yu S_uu⁻¹ S_uy / S_yy with the four
    rail irregularities (z left, z right, y left, y right) at the leading wheelset as inputs
    (the other wheelsets see them delayed: a linear filter), band-averaged as power; beside it
    the same for the statistical model's record (1 for a linear record, up to the estimator's
    bias ≈ 4/n_averages) and the share coherent with the statistical record alone."""
    data = np.load(npz)
    sc = scenario(speed, scale, distance)
    profile = assemble(sc).irregularity
    n = data[f"solver|{channels[0]}"].size
    t = SKIP_S + np.arange(n) / fs
    x1 = float(max(abs(x) for x in (7.4,)))  # leading wheelset: x = +7.4 m (model.wheelset_x)
    u = np.array(profile.sample(sc.speed_mps * t + x1))
    nper = int(segment_s * fs)
    n_avg = 2 * n // nper - 1
    f, _ = signal.welch(u[0], fs=fs, nperseg=nper)
    Suu = np.empty((f.size, 4, 4), complex)
    for i in range(4):
        for j in range(4):
            Suu[:, i, j] = signal.csd(u[i], u[j], fs=fs, nperseg=nper)[1]
    edges = np.arange(f_lo, f_hi + 1e-9, df)
    print(f"\nmultiple coherence with the 4 rail inputs ({npz.rsplit('/', 1)[-1]}, "
          f"{n_avg} Welch averages of {segment_s:g} s: bias ≈ {4 / n_avg:.3f})")
    for ch in channels:
        print(f"  {ch}: band, solver rms, γ²_multi solver, γ²_multi statistical record, "
              "statistical/solver power")
        res = {}
        for k in ("solver", "statistical"):
            y = data[f"{k}|{ch}"].astype(float)
            Syy = signal.welch(y, fs=fs, nperseg=nper)[1]
            Suy = np.stack([signal.csd(u[i], y, fs=fs, nperseg=nper)[1] for i in range(4)], -1)
            # coherent power per bin: S_yu S_uu^-1 S_uy
            sol = np.linalg.solve(Suu + 1e-30 * np.eye(4), Suy[..., None])[..., 0]
            coh = np.real(np.einsum("fi,fi->f", Suy.conj(), sol))
            res[k] = (Syy, coh)
        tot = np.zeros(4)
        for lo, hi in itertools.pairwise(edges):
            m = (f >= lo) & (f < hi)
            ps, cs = res["solver"][0][m].sum(), res["solver"][1][m].sum()
            pq, cq = res["statistical"][0][m].sum(), res["statistical"][1][m].sum()
            tot += (ps, cs, pq, cq)
            print(f"    {lo:5.2f}-{hi:5.2f} {np.sqrt(ps * (f[1] - f[0])):9.3g} {cs / ps:6.3f} "
                  f"{cq / pq:6.3f} {pq / ps:6.3f}")
        print(f"    {'total':11s} {np.sqrt(tot[0] * (f[1] - f[0])):9.3g} {tot[1] / tot[0]:6.3f} "
              f"{tot[3] / tot[2]:6.3f} {tot[2] / tot[0]:6.3f}")


def contact_gains(npz: str, speed: int, scale: float, distance: float) -> None:
    """Gaussian-equivalent vs empirical gains of the rigid-contact Δr(y) and Δγ(y) (left minus
    right rolling radius and contact angle against the wheelset's displacement on the track,
    y = (Δy_left + Δy_right)/2): k = E[y·f(y)]/E[y²] over the solver's samples of y, over a
    Gaussian of the solver's σ, and over a Gaussian of the statistical record's σ; and the
    share of f's variance the linear term leaves (the distortion a linear model drops)."""
    data = np.load(npz)
    sc = scenario(speed, scale, distance)
    tab = assemble(sc).profiles
    grid = tab.y_grid
    idx = tab.rigid_slot[:, None, :].astype(np.intp)
    funcs = {}
    for name in ("r", "gamma"):
        v = np.take_along_axis(tab.field(name), idx, axis=1)[:, 0, :]
        funcs["Δ" + name] = v[0] - v[1]
    rng = np.random.default_rng(0)
    z = rng.standard_normal(2_000_000)
    print(f"\ncontact gains ({npz.rsplit('/', 1)[-1]}): wheelset, function: σ solver / "
          "statistical record (mm), kurtosis; k empirical, k Gauss(σ solver), "
          "k Gauss(σ stat) (per m); residual variance share empirical, Gauss")
    for ws in WHEELSETS:
        ys = {k: 0.5 * (data[f"{k}|{ws}.left.rel_disp.y"].astype(float)
                        + data[f"{k}|{ws}.right.rel_disp.y"].astype(float))
              for k in ("solver", "statistical")}
        ys = {k: v - v.mean() for k, v in ys.items()}
        sd = {k: float(np.std(v)) for k, v in ys.items()}
        for fname, fv in funcs.items():
            def gain(y, fv=fv):
                f = np.interp(y, grid, fv)
                f = f - f.mean()
                k = float(np.mean(y * f) / np.mean(y * y))
                return k, float(np.var(f - k * y) / np.var(f))
            ke, re_ = gain(ys["solver"])
            kg, rg = gain(sd["solver"] * z)
            kq, _ = gain(sd["statistical"] * z)
            print(f"  {ws} {fname:<7s} {1e3 * sd['solver']:.3f} / {1e3 * sd['statistical']:.3f}"
                  f"  {stats.kurtosis(ys['solver'], fisher=False):.2f}   {ke:8.4f} {kg:8.4f} "
                  f"{kq:8.4f}   {re_:.3f} {rg:.3f}")
            if ws == "wheelset1" and fname == "Δr":
                y = ys["solver"]
                f = np.interp(y, grid, fv)
                f = f - f.mean()
                e = f - ke * y
                fr, py = signal.welch(ke * y, fs=1000.0, nperseg=16000)
                _, pe = signal.welch(e, fs=1000.0, nperseg=16000)
                bands = ((0.0, 1.0), (1.0, 2.0), (2.0, 3.0), (3.0, 4.0), (4.0, 6.0), (6.0, 10.0),
                         (10.0, 25.0), (25.0, 100.0))
                print("    wheelset1 Δr: PSD of the residual Δr(y) − k·y against k·y per band "
                      "(residual/linear power; residual's share of its total):")
                parts = []
                for lo, hi in bands:
                    m = (fr >= lo) & (fr < hi)
                    parts.append(f"{lo:g}-{hi:g} Hz {pe[m].sum() / py[m].sum():.2f} "
                                 f"({pe[m].sum() / pe.sum():.2f})")
                print("    " + "  ".join(parts))


def residual_forcing(npz: str, speed: int, scale: float, distance: float,
                     fs: float = 1000.0, source: str = "statistical",
                     function: str = "r") -> None:
    """Proposal check: the statistical model plus the response to the residual of its own
    linearisation. From the statistical model's (Gaussian) Δy record of each wheelset,
    y = (Δy_left + Δy_right)/2, the residual of the rolling-radius difference
    e = (Δr(y) − k·y)/k (k its gain E[y·Δr]/E[y²]; e in metres of Δy) is fed back into the same
    model as a lateral shift −e of both rails at that wheelset (so every contact quantity sees
    e through its equivalent gain, Δr sees its residual), and the response added to the model's
    record. No solver data enter the correction; the solver's record is only compared
    (``source="solver"``, a diagnostic: the residual of the solver's own Δy instead)."""
    data = np.load(npz)
    sc = scenario(speed, scale, distance)
    tab = assemble(sc).profiles
    grid = tab.y_grid
    idx = tab.rigid_slot[:, None, :].astype(np.intp)
    r = np.take_along_axis(tab.field(function), idx, axis=1)[:, 0, :]
    dr = r[0] - r[1]
    model = estimate(sc, strict=False).model
    n = data["solver|" + ACC[0]].size
    nfft = int(2 ** np.ceil(np.log2(n + PAD_S * fs)))
    u = np.zeros((model.system.m, nfft))
    for w, ws in enumerate(WHEELSETS):
        y = 0.5 * (data[f"{source}|{ws}.left.rel_disp.y"].astype(float)
                   + data[f"{source}|{ws}.right.rel_disp.y"].astype(float))
        y = y - y.mean()
        f_ = np.interp(y, grid, dr)
        f_ = f_ - f_.mean()
        k = float(np.mean(y * f_) / np.mean(y * y))
        e = (f_ - k * y) / k
        print(f"  {ws}: σ_y {1e3 * np.std(y):.3f} mm, k {k:.4f}, σ_e {1e3 * np.std(e):.3f} mm "
              f"(residual share of Δr variance {np.var(k * e) / np.var(f_):.3f})")
        u[4 * w + 2, :n] = -e
        u[4 * w + 3, :n] = -e
    U = np.fft.rfft(u, axis=-1)
    f = np.fft.rfftfreq(nfft, 1.0 / fs)
    acc = model.accelerations
    names = [f"carbody.{p}.acc.y" for p in POINTS]
    ia = [acc.names.index(nm) for nm in names]
    disp = ["frame1.y", "wheelset1.y", "wheelset1.yaw"]
    G_d = np.zeros((len(disp), model.system.n))
    for k_, nm in enumerate(disp):
        G_d[k_, model.dof_names.index(nm)] = 1.0
    P = np.vstack([acc.P[ia], np.zeros_like(G_d)])
    G = np.vstack([acc.G[ia], G_d])
    D = np.vstack([acc.D[ia], np.zeros((len(disp), acc.D.shape[1]))])
    names = names + disp
    Y = _frf_times_input(model, P, G, D, f, U)
    extra = np.fft.irfft(Y, nfft, axis=-1)[:, :n]
    print(f"  {'channel':<20s} {'solver':>8s} {'stat':>8s} {'stat+res':>9s}  band rms vs solver "
          + " ".join(f"{lo:g}-{hi:g}" for lo, hi in BANDS) + " Hz (stat | stat+res)")
    for nm, ex in zip(names, extra, strict=True):
        s_ = data[f"solver|{nm}"].astype(float)
        q = data[f"statistical|{nm}"].astype(float)
        qr = q + ex
        bs, bq, bqr = band_rms(s_, fs), band_rms(q, fs), band_rms(qr, fs)
        print(f"  {nm:<20s} {np.std(s_):8.4f} {_pct(np.std(q), np.std(s_))} "
              f"{_pct(np.std(qr), np.std(s_))}   "
              + " ".join(f"{_pct(b, a)}|{_pct(c, a)}" for a, b, c in zip(bs, bq, bqr,
                                                                       strict=True)))
        shares = []
        for rec in (q, qr):
            ff, pss = signal.welch(s_, fs=fs, nperseg=int(16 * fs))
            _, prr = signal.welch(rec, fs=fs, nperseg=int(16 * fs))
            _, csr = signal.csd(rec, s_, fs=fs, nperseg=int(16 * fs))
            m = (ff >= 0.5) & (ff <= 25.0)
            shares.append(float(np.sum(np.abs(csr[m]) ** 2 / prr[m]) / np.sum(pss[m])))
        print(f"  {'':<20s} solver power (0.5-25 Hz) coherent with stat {shares[0]:.3f}, "
              f"with stat+res {shares[1]:.3f}")


def sigma_sweep(speed: int, factors: list[float], scale: float) -> None:
    sc = scenario(speed, scale, 10_000.0)
    est = estimate(sc)
    model = est.model
    ql = model.quasi_linear
    keys = list(ql.to_dict()["sigma_m"].keys())
    sig0 = np.array([ql.to_dict()["sigma_m"][k] for k in keys]).reshape(-1, 2)
    lin = model.linearisation
    print(f"{speed} km/h scale {scale:g}: fixed point σ (mm) "
          + " ".join(f"{1e3 * s:.3f}" for s in sig0[:, 0]))
    print(f"{'factor':>7s} " + " ".join(f"{p + ' rms':>10s}" for p in POINTS)
          + "   σ_out/σ_in (ws1..4)")
    for fac in factors:
        stat = statistical_linearisation(lin, fac * sig0)
        m = model_from(sc, stat, model.track, model.spectra, [], (0.0, 0.0))
        resp = response(m, points=list(POINTS))
        var = resp.variance(resp.psd)
        rms = [float(np.sqrt(var[resp.index(f"carbody.{p}.acc.y")])) for p in POINTS]
        wv = resp.variance(resp.wheel_psd)
        sg = np.array([np.sqrt(wv[i]) for i, nm in enumerate(resp.wheel_channels)
                       if nm.endswith(".rel_disp.y")]).reshape(-1, 2)
        print(f"{fac:7.2f} " + " ".join(f"{r:10.4f}" for r in rms) + "   "
              + " ".join(f"{a:.3f}" for a in (sg[:, 0] / (fac * sig0[:, 0]))))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__.split("\n\n", 1)[1])
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run", help="solver vs local and quasi-linear models, per case")
    r.add_argument("cases", nargs="+", help="speed:scale:distance, e.g. 80:1:10000")
    r.add_argument("--out", default="/tmp/qld")
    r.add_argument("--set", nargs="*", default=[], metavar="KEY=VALUE",
                   help="dotted-path overrides (JSON values), e.g. contact.geometry=\"conical\"")
    p = sub.add_parser("print", help="print the tables of finished cases (json files)")
    p.add_argument("files", nargs="+")
    q = sub.add_parser("psd", help="band PSD ratios of saved records (npz)")
    q.add_argument("npz")
    q.add_argument("--channels", nargs="+", default=["carbody.PFB.acc.y", "wheelset1.yaw"])
    q.add_argument("--band", type=float, nargs=3, default=[0.5, 8.0, 0.5],
                   metavar=("F_LO", "F_HI", "DF"))
    c = sub.add_parser("coherence", help="multiple coherence of saved records with the input")
    c.add_argument("npz")
    c.add_argument("case", help="speed:scale:distance of the npz (to rebuild its input)")
    c.add_argument("--channels", nargs="+",
                   default=["carbody.PFB.acc.y", "carbody.PC.acc.y", "wheelset1.yaw"])
    c.add_argument("--band", type=float, nargs=3, default=[0.5, 10.0, 0.5],
                   metavar=("F_LO", "F_HI", "DF"))
    c.add_argument("--set", nargs="*", default=[], metavar="KEY=VALUE")
    g = sub.add_parser("gains", help="empirical vs Gaussian gains of Δr, Δγ on saved records")
    g.add_argument("npz")
    g.add_argument("case", help="speed:scale:distance of the npz")
    rr = sub.add_parser("residual", help="statistical model + response to its Δr residual")
    rr.add_argument("npz")
    rr.add_argument("case", help="speed:scale:distance of the npz")
    rr.add_argument("--set", nargs="*", default=[], metavar="KEY=VALUE")
    rr.add_argument("--source", choices=["statistical", "solver"], default="statistical",
                    help="whose Δy the residual is made of (solver: a diagnostic only)")
    rr.add_argument("--function", choices=["r", "gamma"], default="r",
                    help="left-minus-right rolling radius (Δr) or contact angle (Δγ)")
    s = sub.add_parser("sigma-sweep", help="statistical model at prescribed σ")
    s.add_argument("--speed", type=int, default=80)
    s.add_argument("--scale", type=float, default=1.0)
    s.add_argument("--factors", type=float, nargs="+", default=[0.8, 0.9, 1.0, 1.05, 1.1, 1.2])
    args = ap.parse_args()
    if args.cmd == "run":
        for kv in args.set:
            k, v = kv.split("=", 1)
            OVERRIDES[k] = json.loads(v)
        os.makedirs(args.out, exist_ok=True)
        for case in args.cases:
            v, sc, d = case.split(":")
            print_case(run_case(int(v), float(sc), float(d), args.out))
    elif args.cmd == "print":
        for fn in args.files:
            with open(fn, encoding="utf-8") as fh:
                print_case(json.load(fh))
    elif args.cmd == "coherence":
        for kv in args.set:
            k, v = kv.split("=", 1)
            OVERRIDES[k] = json.loads(v)
        v, sc, d = args.case.split(":")
        multiple_coherence(args.npz, int(v), float(sc), float(d), args.channels, *args.band)
    elif args.cmd == "gains":
        v, sc, d = args.case.split(":")
        contact_gains(args.npz, int(v), float(sc), float(d))
    elif args.cmd == "residual":
        for kv in args.set:
            k, v = kv.split("=", 1)
            OVERRIDES[k] = json.loads(v)
        v, sc, d = args.case.split(":")
        residual_forcing(args.npz, int(v), float(sc), float(d), source=args.source,
                         function=args.function)
    elif args.cmd == "psd":
        psd_table(args.npz, args.channels, *args.band)
    else:
        sigma_sweep(args.speed, args.factors, args.scale)


if __name__ == "__main__":
    main()
