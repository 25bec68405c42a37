// Job result: state while queued / running (live progress), the failure reason, and for a
// finished job: summary cards, time histories, spectra, spectrogram, Sperling breakdown,
// cross-correlation, wheel–rail forces with running safety; downloads and exports.

import { api, cached, request } from "../api.js";
import {
  h, setChildren, badge, progressBar, duration, when, fmt, fixed, errorBox, notice, loading, tabs,
  dataTable, prettyUnit, DIRECTION_NAMES, channelLabel, channelName,
} from "../components/dom.js";
import { plotCard, baseLayout, COLORS } from "../components/plot.js";
import { seriesPlot, spectrumPlot } from "../components/series.js";
import { channelMultiSelect, channelSelect, simpleSelect, directionOptions, accPoints, headlinePoint } from "../components/channels.js";
import { loadPaperPoints, pointCatalogue, pointColor, pointTag, pointText, pointsCard } from "../components/points.js";
import { solverState, compilingText, waitNote } from "../components/waiting.js";
import { safetyPanel, safetyHeadline, governing } from "../components/safety.js";
import { confirmButton } from "./jobs.js";
import { go, replaceQuery } from "../components/nav.js";

const ACTIVE = new Set(["queued", "running"]);

// -- summary helpers (shape of flexride.analysis.Summary.to_dict) ------------------------------

export function sperlingOf(dir) {
  if (!dir) return { value: null, grade: null, form: null };
  if (dir.sperling && dir.sperling.value !== null && dir.sperling.value !== undefined) return { value: dir.sperling.value, grade: dir.sperling.grade, form: dir.sperling.form || "spectral" };
  if (dir.sperling_alternative && dir.sperling_alternative.value !== null && dir.sperling_alternative.value !== undefined) return { value: dir.sperling_alternative.value, grade: dir.sperling_alternative.grade, form: dir.sperling_alternative.form || "filter", fallback: true, why: dir.errors?.sperling };
  return { value: null, grade: null, form: null, why: dir.errors?.sperling };
}

export function awOf(dir) {
  if (!dir?.iso2631) return { value: null, weighting: null };
  const w = Object.keys(dir.iso2631)[0];
  return { value: dir.iso2631[w]?.a_w ?? null, weighting: w, comfort: dir.iso2631[w]?.comfort };
}

export function gradeChip(grade) {
  return grade ? h("span", { class: `grade grade-${grade}` }, grade) : null;
}

function metric(label, value, sub, extra) {
  return h("div", { class: "metric" }, h("div", { class: "label" }, label), h("div", { class: "value" }, value, extra || null), sub ? h("div", { class: "sub" }, sub) : null);
}

/** "flexible (modal reduction, 40 Hz, 0.2 m elements)" or "rigid" of a scenario's body model. */
function bodyModelText(b) {
  if (!b) return "–";
  if (b.model !== "flexible") return "rigid";
  return `flexible (${b.reduction} reduction, cut-off ${fmt(b.cutoff_hz)} Hz, ${fmt(b.element_size_m)} m elements)`;
}

/** The contact model of a scenario in one line: geometry, profiles, normal contact, friction. */
function contactText(c) {
  if (!c) return "–";
  const geometry = c.geometry === "profiles"
    ? `real profiles ${c.wheel?.builtin || c.wheel?.upload || "wheel"} on ${c.rail?.builtin || c.rail?.upload || "rail"} at ${c.inclination}`
    : `conical tread, conicity ${fmt(c.conicity)}`;
  return `${geometry}; ${c.normal === "hertz" ? "Hertz" : c.normal} normal contact, Kalker creep with Shen–Hedrick–Elkins saturation, μ = ${fmt(c.friction)}`;
}

function jobInfo(job, sc) {
  const rows = [
    ["Status", badge(job.status)],
    ["Preset", job.preset || (sc ? "none (a scenario of its own)" : "–")],
    ["Car body", bodyModelText(sc?.bodies?.carbody)],
    ["Bogie frames", bodyModelText(sc?.bodies?.frames)],
    ["Contact model", contactText(sc?.contact)],
    ["Speed", job.speed_kmh !== null ? `${fmt(job.speed_kmh)} km/h` : "–"],
    ["Simulated time", job.duration_s !== null ? `${fmt(job.duration_s)} s` : "–"],
    ["Created", when(job.created_at)],
    ["Waited", duration(job.queue_time_s)],
    ["Run time", duration(job.run_time_s)],
    ["Solver wall time", duration(job.solver_wall_time_s)],
    ["Runner / worker", `${job.runner}${job.worker ? ` / ${job.worker}` : ""}`],
    ["Attempts", `${job.attempts} of ${job.max_attempts}`],
  ];
  if (job.reused_from) rows.push(["Results reused from", h("a", { href: `#/jobs/${job.reused_from}` }, job.reused_from.slice(0, 8))]);
  if (job.study_id) rows.push(["Study", h("a", { href: `#/studies/${job.study_id}` }, job.study_id.slice(0, 8)), ...[]]);
  if (job.axes && Object.keys(job.axes).length) rows.push(["Study axes", Object.entries(job.axes).map(([k, v]) => `${k} = ${v}`).join(", ")]);
  return h("dl", { class: "kv" }, rows.flatMap(([k, v]) => [h("dt", {}, k), h("dd", {}, v)]));
}

/** The comfort indices per point: vertical and lateral side by side under one heading each,
 * short column labels with their units, so the table fits a 1280 px screen. */
export function comfortTable(pts, catalogue) {
  const d = (ps, dir) => ps?.directions?.[dir];
  const rows = Object.entries(pts).map(([p, ps]) => {
    const z = d(ps, "z");
    const y = d(ps, "y");
    return {
      point: p, wz: sperlingOf(z), wy: sperlingOf(y), awz: awOf(z).value, awy: awOf(y).value,
      pz: z?.peaks?.max_abs ?? null, py: y?.peaks?.max_abs ?? null, rz: z?.peaks?.rms ?? null, ry: y?.peaks?.rms ?? null,
      fz: z?.dominant_peaks?.[0]?.frequency ?? null, fy: y?.dominant_peaks?.[0]?.frequency ?? null, nmv: ps.mean_comfort?.value ?? null,
    };
  });
  const spCell = (v) => (v.value === null ? "–" : h("span", { class: "nowrap" }, fixed(v.value), v.fallback ? h("sup", { title: "filter form: the record is shorter than the 5 s the spectral form needs" }, "f") : null, gradeChip(v.grade)));
  const dirCols = (k, sep) => [
    { key: `w${k}`, label: "W (–)", title: "Sperling index (GB 5599 grade)", num: true, sep, value: (r) => r[`w${k}`].value, format: (v, r) => spCell(r[`w${k}`]) },
    { key: `aw${k}`, label: "a_w (m/s²)", title: `ISO 2631 weighted rms (${k === "z" ? "Wb" : "Wd"})`, num: true },
    { key: `p${k}`, label: "peak (m/s²)", title: "largest |acceleration|", num: true },
    { key: `r${k}`, label: "rms (m/s²)", title: "rms of the acceleration", num: true },
    { key: `f${k}`, label: "f (Hz)", title: "frequency of the dominant spectral peak", num: true },
  ];
  return dataTable([
    { key: "point", label: "Point", format: (v) => pointTag(v, catalogue) },
    ...dirCols("z", true), ...dirCols("y", true),
    { key: "nmv", label: "N_MV (–)", title: "EN 12299 mean comfort, standard method", num: true, sep: true, format: (v) => fixed(v) },
  ], rows, {
    caption: "Comfort indices per point (W: Sperling index with its GB 5599 grade; a_w: ISO 2631 weighted rms, Wb vertical, Wd lateral; f: dominant frequency)",
    className: "comfort-table", groups: [{ label: "", span: 1 }, { label: "Vertical (z)", span: 5 }, { label: "Lateral (y)", span: 5 }, { label: "", span: 1 }],
  });
}

/**
 * The frequency-domain estimate (POST /estimates with `spectra`) of a job's own scenario drawn
 * over its Welch PSD: the expected one-sided acceleration PSD of each chosen car-body channel,
 * times the squared gain of the quasi-static split when the Welch PSD removes it. A refusal
 * (`refusal: "answer"`: applicable false), an FE model not built (409) or a busy service (503)
 * is a note, never an error.
 */
function psdOverlay(jobId, signal) {
  const answers = new Map(); // points → answer (the service keeps them too)
  const note = h("p", { class: "small muted", id: "psd-overlay-note", "aria-live": "polite" });
  const say = (text, state) => { note.textContent = text; note.dataset.state = state; };

  async function answer(points) {
    const key = points.join(",");
    if (!answers.has(key)) {
      const scenario = await cached(`scenario:${jobId}`, () => api.jobScenario(jobId));
      const body = { scenario, points, spectra: true, refusal: "answer" };
      answers.set(key, request("/estimates", { method: "POST", body, signal, timeout: 60000 }));
    }
    try {
      return await answers.get(key);
    } catch (err) {
      answers.delete(key); // ask again next time (busy, not built yet)
      throw err;
    }
  }

  function trace(res, channel, p) {
    const r = res.response;
    const gain = p.dynamic ? r.dynamic_part_gain : null;
    const keep = r.frequencies_hz.map((f, i) => i).filter((i) => r.frequencies_hz[i] <= (p.fmax ?? 50));
    const y = keep.map((i) => r.psd[channel][i] * (gain ? gain[i] : 1)).map((v) => (v > 0 ? v : null));
    const point = channel.split(".")[1];
    return {
      type: "scatter", mode: "lines", name: `${channelLabel(channel)} – frequency-domain estimate`,
      x: keep.map((i) => r.frequencies_hz[i]), y, line: { width: 2, color: pointColor(point), dash: "dot" },
      meta: { unit: "(m/s²)²/Hz" }, hovertemplate: "%{x:.3g} Hz: %{y:.4g} (m/s²)²/Hz<extra>%{fullData.name}</extra>",
    };
  }

  /** Traces of the estimate for the chosen channels (none, with the reason in the note). */
  async function traces(channels, p) {
    const acc = channels.filter((c) => /^carbody\.[^.]+\.acc\.[yz]$/.test(c));
    if (!acc.length) {
      say("The estimate covers car-body accelerations (lateral y, vertical z): choose one.", "none");
      return [];
    }
    say("Estimating in the frequency domain…", "loading");
    let res;
    try {
      res = await answer([...new Set(acc.map((c) => c.split(".")[1]))]);
    } catch (err) {
      if (signal.aborted || err?.name === "AbortError") return [];
      say(`No frequency-domain estimate${err.status === 503 ? " now" : ""}: ${err.message}`, "refused");
      return [];
    }
    if (res.applicable === false) {
      say(`No frequency-domain estimate: ${res.message}`, "refused");
      return [];
    }
    const c = res.comfort;
    const flags = c.flags.length ? ` ${c.flags.length} flag(s) where it may not hold: ${c.flags.join(" ")}` : "";
    say(`Dotted: the expected PSD of the same channel for this job's scenario (${c.speed_kmh} km/h), one-sided like the Welch PSD${p.dynamic ? ", quasi-static part removed the same way" : ""}. Method: ${c.method}.${flags}`, "ready");
    return acc.map((ch) => trace(res, ch, p));
  }
  return { note, traces, clear: () => say("", "off") };
}

export default async function render(main, ctx) {
  const id = ctx.params.id;
  ctx.title(`Job ${id.slice(0, 8)}`);
  const head = h("div");
  const body = h("div", {}, loading("Loading the job…"));
  main.append(head, body);
  let timer = null;
  let shownFinal = false;
  let solverAsked = 0;
  let solverLast = { compiling: false, estimate_s: null };
  let scenario = null;
  cached(`scenario:${id}`, () => api.jobScenario(id)).then((sc) => { scenario = sc; }).catch(() => {});

  /** The solver's state, asked at most every 3 s while the job waits or runs. */
  async function solverNow() {
    if (Date.now() - solverAsked > 3000) {
      solverAsked = Date.now();
      solverLast = await solverState(ctx.signal);
    }
    return solverLast;
  }

  async function poll() {
    let job;
    try {
      job = await api.job(id, { signal: ctx.signal });
    } catch (err) {
      if (ctx.signal.aborted) return;
      if (err.status === 404) {
        setChildren(head, h("h1", {}, "Job not found"));
        setChildren(body, notice("error", null, `There is no job ${id}. It may have been deleted. `, h("a", { href: "#/" }, "Back to the jobs.")));
        return;
      }
      setChildren(body, errorBox(err, "Could not load the job"));
      timer = setTimeout(poll, 5000);
      return;
    }
    if (ctx.signal.aborted) return;
    ctx.title(job.name);
    renderHead(job);
    if (ACTIVE.has(job.status)) {
      const solver = await solverNow();
      if (ctx.signal.aborted) return;
      const queuedS = job.status === "queued" && job.created_at ? (Date.now() - new Date(job.created_at).getTime()) / 1000 : null;
      setChildren(body, h("section", { class: "card", "aria-labelledby": "progress-title" },
        h("h2", { id: "progress-title" }, job.status === "queued" ? "Waiting for a worker" : "Running"),
        progressBar(job.progress, "Job progress", job.status),
        h("p", { class: "muted", id: "job-message" }, job.message || (job.status === "queued" ? "queued: every worker is busy" : "")),
        solver.compiling ? waitNote({ id: "solver-compiling", title: "The service is compiling the solver – first run only",
          text: `The workers are ${compilingText(solver)}: the numerical kernels are compiled once after installation and kept on disk, so later jobs start at once. This job starts when a worker is ready`,
          elapsed_s: queuedS ?? undefined, estimate_s: solver.estimate_s, remaining: true }) : null,
        h("p", { class: "small muted" }, "This page follows the job and shows the results when it has finished.")));
      timer = setTimeout(poll, 1000);
      return;
    }
    if (shownFinal) return;
    shownFinal = true;
    if (job.status === "failed") {
      setChildren(body, notice("error", "The job failed", h("p", { id: "job-error" }, job.error || job.message || "No reason was recorded."),
        h("p", {}, h("a", { href: `#/new?from=${id}` }, "Edit its scenario and submit it again"), ".")));
      return;
    }
    if (job.status === "cancelled") {
      setChildren(body, notice("warn", "The job was cancelled", job.message || "", job.has_results ? null : " It has no results."));
      if (!job.has_results) return;
    }
    if (!job.has_results) {
      setChildren(body, notice("warn", "No results", "The job finished without a results file."));
      return;
    }
    await renderResults(job);
  }

  function renderHead(job) {
    const actions = [
      job.has_results ? h("a", { class: "btn", href: api.downloadUrl(id), download: "" }, "Download HDF5") : null,
      job.has_results ? h("a", { class: "btn", href: `#/compare?jobs=${id}` }, "Compare…") : null,
      h("a", { class: "btn", href: `#/new?from=${id}` }, "New job from this"),
      ACTIVE.has(job.status) ? h("button", { type: "button", class: "btn", onclick: async () => {
        try {
          await api.cancelJob(id);
        } catch (err) {
          setChildren(body, errorBox(err, "Could not cancel"));
        }
      } }, "Cancel job") : null,
      confirmButton("Delete", "Confirm delete", async () => {
        try {
          await api.deleteJob(id);
          go("/");
        } catch (err) {
          setChildren(body, errorBox(err, "Could not delete"));
        }
      }),
    ];
    const wasOpen = !!head.querySelector("#job-details")?.open;
    setChildren(head,
      h("div", { class: "crumbs" }, h("a", { href: "#/" }, "Jobs"), job.study_id ? [" › ", h("a", { href: `#/studies/${job.study_id}` }, "study")] : null, " › ", id.slice(0, 8)),
      h("div", { class: "page-head" }, h("h1", {}, job.name, " ", badge(job.status)), h("div", { class: "actions" }, actions)),
      h("details", { class: "card small", id: "job-details", open: wasOpen }, h("summary", {}, "Job details"), jobInfo(job, scenario)));
    if (!scenario) {
      cached(`scenario:${id}`, () => api.jobScenario(id)).then((sc) => {
        scenario = sc;
        const det = head.querySelector("#job-details");
        if (det && !ctx.signal.aborted) det.replaceChildren(h("summary", {}, "Job details"), jobInfo(job, sc));
      }).catch(() => {});
    }
  }

  async function renderResults(job) {
    setChildren(body, loading("Loading the results…"));
    let summary;
    let chans;
    try {
      [summary, chans] = await Promise.all([
        cached(`summary:${id}`, () => api.summary(id)).catch((e) => ({ error: e })),
        cached(`channels:${id}`, () => api.channels(id)),
        loadPaperPoints().catch(() => []),
      ]);
    } catch (err) {
      setChildren(body, errorBox(err, "Could not load the results"));
      return;
    }
    if (ctx.signal.aborted) return;
    const s = summary?.summary || null;
    const channels = chans.channels;
    const has = (n) => channels.some((c) => c.name === n);
    const pointInfo = accPoints(channels, chans.points);
    const points = pointInfo.map((p) => p.name);
    const floorGrid = pointInfo.some((p) => p.kind === "grid");
    const catalogue = pointCatalogue(chans.points);
    const pointOption = (p) => [p, pointText(p, catalogue)];
    const t = tabs([
      { id: "summary", label: "Summary" },
      { id: "time", label: "Time histories" },
      { id: "spectra", label: "Spectra" },
      { id: "spectrogram", label: "Spectrogram" },
      { id: "sperling", label: "Sperling" },
      { id: "correlation", label: "Correlation" },
      { id: "forces", label: "Forces & safety" },
    ], (tab, panel) => {
      const r = { summary: () => summaryPanel(panel, s, summary?.error, chans, floorGrid, catalogue), time: () => timePanel(panel), spectra: () => spectraPanel(panel), spectrogram: () => spectrogramPanel(panel), sperling: () => sperlingPanel(panel), correlation: () => correlationPanel(panel, s), forces: () => forcesPanel(panel, s) }[tab];
      r();
    }, { label: "Results", initial: ctx.query.tab || "summary" });
    t.onSelect = (tab) => replaceQuery({ tab });
    setChildren(body, t.el);

    /** Series sources of channels: a car-body point in its own colour (dashed: lateral). */
    function sourcesOf(names) {
      return names.map((c, i) => {
        const m = c.match(/^carbody\.([^.]+)\.acc\.([xyz])$/);
        return m ? { job: id, channel: c, color: pointColor(m[1]), dash: { z: "solid", y: "dash", x: "dot" }[m[2]] }
          : { job: id, channel: c, color: COLORS[(i + 6) % COLORS.length] };
      });
    }

    // ---- panels ----
    function timePanel(panel) {
      const def = ["carbody.PC.acc.z", "carbody.PRB.acc.z", "carbody.PR.acc.z"].filter(has);
      const plot = seriesPlot({ title: "Time histories", id: "plot-time", description: "Time histories of the chosen channels", height: 420 });
      let chosen = (ctx.query.ch ? ctx.query.ch.split(",").filter(has) : def);
      panel.append(h("div", { class: "three" },
        h("div", { class: "controls" }, channelMultiSelect({ id: "time-channels", label: "Channels", channels, selected: chosen, max: 8, size: 16, describe: (c) => pointText(c.point, catalogue), onChange: (names) => {
          chosen = names;
          plot.set(sourcesOf(chosen));
        } })),
        plot.el));
      plot.set(sourcesOf(chosen));
    }

    function spectraPanel(panel) {
      let chosen = ["carbody.PC.acc.z", "carbody.PR.acc.z"].filter(has);
      const p = { fmax: 30, segment_s: 8, dynamic: true, logx: false };
      const amp = spectrumPlot({ title: "Amplitude spectrum", id: "plot-spectrum", kind: "amplitude", description: "Amplitude spectrum with dominant peaks" });
      const psd = spectrumPlot({ title: "Power spectral density", id: "plot-psd", kind: "psd", description: "Welch PSD with dominant peaks" });
      const overlay = psdOverlay(id, ctx.signal);
      let overlayOn = false;
      let seq = 0;
      const drawPsd = async () => {
        const my = ++seq;
        const extra = overlayOn ? await overlay.traces(chosen, p) : [];
        if (my === seq && !ctx.signal.aborted) await psd.set(sourcesOf(chosen), { ...p, extra });
      };
      const draw = () => {
        amp.set(sourcesOf(chosen), p);
        drawPsd();
      };
      psd.el.append(overlay.note);
      psd.card.setControls(h("div", { class: "controls" }, h("label", { class: "check" },
        h("input", { type: "checkbox", id: "psd-overlay", onchange: (e) => {
          overlayOn = e.target.checked;
          if (!overlayOn) overlay.clear();
          drawPsd();
        } }), "Overlay frequency-domain estimate")));
      const num = (key, label, unit, attrs) => {
        const inp = h("input", { type: "number", id: `spec-${key}`, value: String(p[key]), ...attrs, style: { width: "6em" }, onchange: () => {
          const v = Number(inp.value);
          if (Number.isFinite(v) && v > 0) {
            p[key] = v;
            draw();
          }
        } });
        return h("label", { for: `spec-${key}` }, `${label} (${unit})`, inp);
      };
      panel.append(h("div", { class: "three" },
        h("div", { class: "controls stack" },
          channelMultiSelect({ id: "spec-channels", label: "Channels", channels, selected: chosen, max: 6, size: 12, filter: (c) => c.quantity !== "rot", describe: (c) => pointText(c.point, catalogue), onChange: (n) => { chosen = n; draw(); } }),
          num("fmax", "Up to", "Hz", { min: "1", max: "500", step: "1" }),
          num("segment_s", "PSD segment", "s", { min: "0.5", max: "60", step: "0.5" }),
          h("label", { class: "check" }, h("input", { type: "checkbox", checked: true, onchange: (e) => { p.dynamic = e.target.checked; draw(); } }), "Remove the quasi-static part (< 0.3 Hz)"),
          h("label", { class: "check" }, h("input", { type: "checkbox", onchange: (e) => { p.logx = e.target.checked; draw(); } }), "Logarithmic frequency axis")),
        h("div", {}, amp.el, psd.el)));
      draw();
    }

    function spectrogramPanel(panel) {
      const p = { channel: has("carbody.PC.acc.z") ? "carbody.PC.acc.z" : channels[0].name, window_s: 1, overlap: 0.75, fmax: 30, log: true };
      const card = plotCard({ title: "Spectrogram", id: "plot-spectrogram", description: "Spectrogram: frequency against time, colour = power spectral density", height: 420,
        csv: () => last && ({ header: ["time (s)", ...last.frequencies.map((f) => `${f} Hz`)], rows: last.times.map((tt, j) => [tt, ...last.values.map((row) => row[j])]) }) });
      let last = null;
      const draw = async () => {
        card.loading("Computing the spectrogram on the server…");
        try {
          const win = Math.min(p.window_s, Math.max(0.06, (chans.t_end_s - chans.t_start_s) / 2));
          const sg = await api.spectrogram(id, { channel: p.channel, window_s: win, overlap: p.overlap, fmax: p.fmax });
          last = sg;
          const z = p.log ? sg.values.map((row) => row.map((v) => (v > 0 ? Math.log10(v) : null))) : sg.values;
          const unit = prettyUnit(sg.unit);
          await card.draw([{
            type: "heatmap", x: sg.times, y: sg.frequencies, z, colorscale: "Viridis",
            colorbar: { title: { text: p.log ? `log₁₀ PSD<br>(${unit})` : `PSD (${unit})`, side: "right" } },
            hovertemplate: `t = %{x:.2f} s<br>f = %{y:.2f} Hz<br>${p.log ? "log₁₀ " : ""}PSD = %{z:.3g}<extra></extra>`,
          }], baseLayout("Time (s)", "Frequency (Hz)", { margin: { l: 64, r: 24, t: 16, b: 52 } }));
          card.setNote(`${channelLabel(sg.channel)} – ${sg.method}.`);
        } catch (err) {
          card.error(err);
        }
      };
      const num = (key, label, attrs) => {
        const inp = h("input", { type: "number", id: `sg-${key}`, value: String(p[key]), style: { width: "6em" }, ...attrs, onchange: () => {
          const v = Number(inp.value);
          if (Number.isFinite(v)) { p[key] = v; draw(); }
        } });
        return h("label", { for: `sg-${key}` }, label, inp);
      };
      card.setControls(h("div", { class: "controls" },
        channelSelect({ id: "sg-channel", label: "Channel", channels, selected: p.channel, filter: (c) => c.quantity === "acc" || c.quantity === "force", describe: (c) => pointText(c.point, catalogue), onChange: (v) => { p.channel = v; draw(); } }),
        num("window_s", "Window (s)", { min: "0.1", max: "30", step: "0.1" }),
        num("overlap", "Overlap (0–0.95)", { min: "0", max: "0.95", step: "0.05" }),
        num("fmax", "Up to (Hz)", { min: "1", max: "500", step: "1" }),
        h("label", { class: "check" }, h("input", { type: "checkbox", checked: true, onchange: (e) => { p.log = e.target.checked; draw(); } }), "Logarithmic colour scale")));
      panel.append(card.el);
      draw();
    }

    function sperlingPanel(panel) {
      let point = headlinePoint(pointInfo)?.name || points[0];
      const card = plotCard({ title: "Sperling index by third-octave band", id: "plot-sperling", description: "Contribution of each third-octave band to the Sperling index",
        csv: () => last && ({ header: ["channel", "band low (Hz)", "band high (Hz)", "W"], rows: last.channels.flatMap((c) => c.bands.map((b) => [c.name, b.f_low_hz, b.f_high_hz, b.w])) }) });
      let last = null;
      const recordS = chans.t_end_s - chans.t_start_s + 1 / chans.sample_rate_hz;
      const draw = async () => {
        if (recordS < 5 - 1e-6) {
          card.empty(`The spectral Sperling index needs at least 5 s of record (5 s segments); this run has ${fmt(recordS, 3)} s. The summary shows the filter form instead.`);
          return;
        }
        card.loading("Computing the Sperling breakdown…");
        const names = ["z", "y"].map((d) => channelName({ body: "carbody", point, quantity: "acc", direction: d })).filter(has);
        try {
          const res = await api.sperling(id, { channels: names });
          last = res;
          const traces = res.channels.map((c, i) => ({
            type: "bar", name: `${DIRECTION_NAMES[c.name.slice(-1)]}: W = ${fixed(c.value)} (${c.grade})`,
            x: c.bands.map((b) => `${fmt(Math.sqrt(b.f_low_hz * b.f_high_hz), 2)}`), y: c.bands.map((b) => b.w),
            marker: { color: COLORS[i] }, hovertemplate: "%{x} Hz band: W = %{y:.2f}<extra>%{fullData.name}</extra>",
          }));
          await card.draw(traces, baseLayout("Third-octave band centre (Hz)", "Band Sperling value W (–)", { barmode: "group", xaxis: { type: "category" } }));
          card.setNote(res.channels.map((c) => `${channelLabel(c.name)}: W = ${fixed(c.value)} (${c.grade}), filter form ${fixed(c.filter_value)}. ${c.method}`).join(" "));
        } catch (err) {
          card.error(err, "No Sperling breakdown");
        }
      };
      card.setControls(h("div", { class: "controls" }, simpleSelect("sp-point", "Point", points.filter((x) => catalogue.get(x)?.kind !== "grid").map(pointOption), point, (v) => { point = v; draw(); })));
      panel.append(card.el);
      draw();
    }

    function correlationPanel(panel, sum) {
      // the paper's pair (Fig. 20): the floor above the rear bogie against the roof above the
      // front one, found by where the points sit rather than by name
      const paper = pointInfo.filter((p) => p.kind === "paper");
      const rearFloor = paper.filter((p) => p.on_floor && p.x < 0).sort((a, b) => Math.abs(a.y) - Math.abs(b.y))[0];
      const roof = paper.find((p) => p.on_floor === false);
      let ref = rearFloor?.name || points[0];
      let other = roof?.name || points.find((p) => p !== ref);
      let dir = "z";
      let maxLag = 3;
      const card = plotCard({ title: "Cross-correlation", id: "plot-correlation", description: "Normalised cross-correlation against the lag, maximum marked",
        csv: () => last && ({ header: ["lag (s)", "normalised R"], rows: last.lags_s.map((l, i) => [l, last.normalised[i]]) }) });
      let last = null;
      const draw = async () => {
        if (ref === other) {
          card.empty("Choose two different points.");
          return;
        }
        card.loading("Correlating on the server…");
        try {
          const lagCap = Math.max(0.05, 0.95 * (chans.t_end_s - chans.t_start_s));
          const acc = (point) => channelName({ body: "carbody", point, quantity: "acc", direction: dir });
          const res = await api.correlation(id, { reference: acc(ref), channels: [acc(other)], max_lag_s: Math.min(maxLag, lagCap) });
          const c = res.channels[0];
          last = c;
          const lag = c.lag_at_max_interpolated_s ?? c.lag_at_max_s;
          const traces = [
            { type: "scatter", mode: "lines", name: `R(τ) ${ref} → ${other}`, x: c.lags_s, y: c.normalised, line: { color: COLORS[0], width: 1.4 }, hovertemplate: "τ = %{x:.3f} s: %{y:.3f}<extra></extra>" },
            { type: "scatter", mode: "markers", name: "local maxima", x: c.local_maxima.map((m) => m.lag), y: c.local_maxima.map((m) => m.normalised), marker: { color: COLORS[2], size: 7, symbol: "circle-open" }, hovertemplate: "τ = %{x:.3f} s: %{y:.3f}<extra>local maximum</extra>" },
            { type: "scatter", mode: "markers", name: "maximum", x: [c.lag_at_max_s], y: [c.normalised_at_max], marker: { color: COLORS[1], size: 11, symbol: "diamond" }, hovertemplate: "maximum at τ = %{x:.3f} s: %{y:.3f}<extra></extra>" },
          ];
          await card.draw(traces, baseLayout("Lag τ (s)", "Normalised cross-correlation (–)", {
            shapes: [{ type: "line", x0: c.lag_at_max_s, x1: c.lag_at_max_s, yref: "paper", y0: 0, y1: 1, line: { color: COLORS[1], dash: "dash", width: 1.5 } }],
            annotations: [{ x: c.lag_at_max_s, y: 1, yref: "paper", text: `max at τ = ${fmt(lag, 3)} s`, showarrow: false, yanchor: "bottom", font: { color: COLORS[1] }, bgcolor: "rgba(255,255,255,.85)" }],
            yaxis: { range: [-1.05, 1.15] },
          }));
          card.setNote(`Reference a = ${pointText(ref, catalogue)}, b = ${pointText(other, catalogue)}, ${DIRECTION_NAMES[dir]}. Maximum ${fmt(c.normalised_at_max, 3)} at τ = ${fmt(lag, 4)} s (${lag > 0 ? `${other} lags ${ref}` : lag < 0 ? `${other} leads ${ref}` : "no delay"}). ${res.convention}.`);
        } catch (err) {
          card.error(err);
        }
      };
      const pts = pointInfo.filter((p) => p.kind !== "grid").map((p) => pointOption(p.name));
      const lagIn = h("input", { id: "corr-lag", type: "number", min: "0.1", max: "30", step: "0.1", value: "3", style: { width: "6em" }, onchange: () => { const v = Number(lagIn.value); if (v > 0) { maxLag = v; draw(); } } });
      card.setControls(h("div", { class: "controls" },
        simpleSelect("corr-ref", "Reference point (a)", pts, ref, (v) => { ref = v; draw(); }),
        simpleSelect("corr-other", "Other point (b)", pts, other, (v) => { other = v; draw(); }),
        simpleSelect("corr-dir", "Direction", directionOptions(["z", "y"]), dir, (v) => { dir = v; draw(); }),
        h("label", { for: "corr-lag" }, "Largest lag (s)", lagIn)));
      panel.append(card.el);
      draw();
      if (sum?.correlations?.length) {
        panel.append(h("section", { class: "card" }, dataTable([
          { key: "pair", label: "Pair (a → b)", format: (v, r) => h("span", {}, pointTag(r.a, catalogue), " → ", pointTag(r.b, catalogue)) },
          { key: "direction", label: "Direction", format: (v) => DIRECTION_NAMES[v] || v },
          { key: "lag", label: "Lag of the maximum (s)", num: true, format: (v) => fmt(v, 4) },
          { key: "value", label: "Normalised maximum", num: true, format: (v) => fmt(v, 3) },
        ], sum.correlations.map((c) => ({ pair: `${c.reference} → ${c.other}`, a: c.reference, b: c.other, direction: c.direction, lag: c.result?.lag_at_max_interpolated ?? c.result?.lag_at_max, value: c.result?.normalised_at_max })),
        { caption: "Cross-correlations of the summary (reference point against every other)" })));
      }
    }

    function forcesPanel(panel, sum) {
      const wheelsets = [...new Set(channels.filter((c) => c.quantity === "force").map((c) => c.body))].sort();
      const gov = governing(sum?.safety?.indices)?.location?.split(".")[0];
      let ws = wheelsets.includes(gov) ? gov : wheelsets[0];
      let dir = "z";
      const FORCE = { z: "vertical wheel force Q", y: "lateral wheel force Y", n: "normal force N" };
      const plot = seriesPlot({ title: "Wheel–rail forces", id: "plot-forces", description: "Wheel–rail contact forces of the chosen wheelset", height: 380 });
      const draw = () => plot.set(["left", "right"].map((side) => ({ side, name: channelName({ body: ws, point: side, quantity: "force", direction: dir }) })).filter((c) => has(c.name))
        .map((c, i) => ({ job: id, channel: c.name, label: `${ws.replace("wheelset", "wheelset ")} ${c.side} wheel, ${FORCE[dir]}`, scale: 1e-3, unit: "kN", color: COLORS[i] })));
      panel.append(safetyPanel(sum, {
        onWheelset: (w) => {
          if (!wheelsets.includes(w)) return;
          ws = w;
          const sel = panel.querySelector("#force-ws");
          if (sel) sel.value = w;
          draw();
        },
      }));
      if (!wheelsets.length) panel.append(notice("empty", null, "This run recorded no wheel–rail forces."));
      else {
        plot.card.setControls(h("div", { class: "controls" },
          simpleSelect("force-ws", "Wheelset", wheelsets.map((w) => [w, w.replace("wheelset", "wheelset ")]), ws, (v) => { ws = v; draw(); }),
          simpleSelect("force-dir", "Force", [["z", "vertical Q (z)"], ["y", "lateral Y (y)"], ["n", "normal N (n)"]].filter(([d]) => has(`${ws}.left.force.${d}`)), dir, (v) => { dir = v; draw(); })));
        panel.append(plot.el);
        draw();
      }
    }
  }

  // -- summary panel ------------------------------------------------------------------------------
  function summaryPanel(panel, s, error, chans, floorGrid, catalogue) {
    if (!s) {
      panel.append(error ? errorBox(error, "No analysis summary") : notice("empty", null, "This job has no analysis summary."));
      return;
    }
    const pts = s.points || {};
    const head = headlinePoint(accPoints(chans.channels, chans.points).filter((p) => pts[p.name]))?.name || Object.keys(pts)[0];
    const d = (p, dir) => pts[p]?.directions?.[dir];
    const tag = (p) => pointTag(p, catalogue);
    const cards = [];
    if (head) {
      for (const [dir, name] of [["z", "vertical"], ["y", "lateral"]]) {
        const sp = sperlingOf(d(head, dir));
        cards.push(metric(h("span", {}, `Sperling ${name} `, h("span", { class: "nowrap" }, "(", tag(head), ")")), sp.value === null ? "–" : fixed(sp.value), sp.form ? `${sp.form} form${sp.fallback ? " (record shorter than 5 s)" : ""}` : sp.why || "", gradeChip(sp.grade)));
      }
      for (const [dir, name] of [["z", "vertical"], ["y", "lateral"]]) {
        const aw = awOf(d(head, dir));
        cards.push(metric(h("span", {}, `Weighted rms ${name} `, h("span", { class: "nowrap" }, "(", tag(head), ")")), aw.value === null ? "–" : fmt(aw.value, 3), aw.weighting ? `a_w (${aw.weighting}) in m/s²${aw.comfort ? ` – ${aw.comfort}` : ""}` : ""));
      }
      let best = null;
      for (const [p, ps] of Object.entries(pts)) {
        for (const [dir, dd] of Object.entries(ps.directions || {})) {
          const v = dd.peaks?.max_abs;
          if (typeof v === "number" && (!best || v > best.v)) best = { v, p, dir, t: dd.peaks.time_of_max_abs };
        }
      }
      if (best) cards.push(metric("Largest |acceleration|", fmt(best.v, 3), h("span", {}, "m/s² at ", tag(best.p), ` ${DIRECTION_NAMES[best.dir]}, t = ${fmt(best.t, 3)} s`)));
      const nmv = pts[head]?.mean_comfort;
      if (nmv?.value !== undefined && nmv?.value !== null) cards.push(metric(h("span", {}, "Mean comfort N_MV (", tag(head), ")"), fixed(nmv.value), `EN 12299 – ${nmv.scale}${nmv.short_run ? " (short run)" : ""}`));
    }
    const safe = safetyHeadline(s);
    if (safe) cards.push(metric("Running safety", h("span", { class: safe.passed ? "pass" : "fail" }, safe.passed ? "passed" : "exceeded"), safe.text));
    panel.append(h("div", { class: "cards", id: "summary-cards" }, cards));
    panel.append(h("section", { class: "card" }, comfortTable(pts, catalogue)));
    panel.append(pointsCard(catalogue, { id: "points-card" }));
    const notes = [...(s.notes || [])];
    const errs = new Set();
    for (const ps of Object.values(pts)) for (const dd of Object.values(ps.directions || {})) for (const e of Object.values(dd.errors || {})) errs.add(e.replace(/^\w+Error: /, ""));
    if (notes.length || errs.size) panel.append(notice("info", "Notes", h("ul", {}, [...notes, ...errs].map((n) => h("li", {}, n)))));
    if (floorGrid) panel.append(notice("info", null, "This run recorded the floor grid: ", h("a", { href: `#/flex?job=${id}` }, "see the comfort map over the floor"), "."));
    panel.append(h("p", { class: "small muted" }, `Record: ${fmt(chans.t_start_s, 4)}–${fmt(chans.t_end_s, 4)} s, ${chans.n_samples.toLocaleString("en-GB")} samples at ${fmt(chans.sample_rate_hz)} Hz, ${chans.channels.length} channels. ${s.settings?.sperling?.grades || ""}`));
  }

  await poll();
  return () => clearTimeout(timer);
}
