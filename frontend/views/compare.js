// Compare: the same channel from two or more jobs overlaid in time and frequency (e.g. flexible
// against rigid, paper Figs. 6 and 7), with their indices side by side.

import { api, cached } from "../api.js";
import { h, setChildren, notice, errorBox, loading, fmt, fixed, pct, dataTable, channelLabel } from "../components/dom.js";
import { seriesPlot, spectrumPlot } from "../components/series.js";
import { channelSelect, simpleSelect } from "../components/channels.js";
import { COLORS, DASHES, loadPlotly } from "../components/plot.js";
import { replaceQuery } from "../components/nav.js";
import { sperlingOf, awOf, gradeChip } from "./job.js";
import { loadPaperPoints, pointCatalogue, pointText } from "../components/points.js";

const MAX_JOBS = 6;

function jobLabel(job, all) {
  const axes = Object.entries(job.axes || {}).filter(([, v]) => !job.name.includes(String(v)))
    .map(([k, v]) => (k === "speed_kmh" ? `${v} km/h` : String(v))).join(", ");
  const same = all.filter((j) => j.name === job.name).length > 1;
  return `${job.name}${axes ? ` (${axes})` : ""}${same ? ` [${job.id.slice(0, 6)}]` : ""}`;
}

export default async function render(main, ctx) {
  loadPlotly().catch(() => {}); // in parallel with the data
  ctx.title("Compare jobs");
  main.append(h("h1", {}, "Compare jobs"), loading("Loading finished jobs…"));
  let jobs;
  try {
    const page = await api.jobs({ status: "succeeded", limit: 200 }, { signal: ctx.signal });
    jobs = page.items.filter((j) => j.has_results);
    const wanted = (ctx.query.jobs || "").split(",").filter(Boolean);
    for (const id of wanted) {
      if (!jobs.some((j) => j.id === id)) {
        try {
          const j = await api.job(id);
          if (j.has_results) jobs.push(j);
        } catch { /* a deleted job: ignore */ }
      }
    }
  } catch (err) {
    if (ctx.signal.aborted) return undefined;
    setChildren(main, h("h1", {}, "Compare jobs"), errorBox(err, "Could not load the jobs"));
    return undefined;
  }
  if (ctx.signal.aborted) return undefined;
  if (!jobs.length) {
    setChildren(main, h("h1", {}, "Compare jobs"), notice("empty", "Nothing to compare yet", h("span", {}, "Finished jobs appear here. Submit one from ", h("a", { href: "#/new" }, "New job"), " or run the rigid-against-flexible ", h("a", { href: "#/studies/new?preset=paper-table2" }, "study"), ".")));
    return undefined;
  }

  const state = {
    selected: (ctx.query.jobs || "").split(",").filter((id) => jobs.some((j) => j.id === id)).slice(0, MAX_JOBS),
    channel: ctx.query.channel || "carbody.PC.acc.z",
    ref: ctx.query.ref || "",
    fmax: 30,
    logx: false,
  };
  if (!state.selected.length) state.selected = jobs.slice(0, Math.min(2, jobs.length)).map((j) => j.id);
  const refBox = h("div");
  const saveQuery = () => replaceQuery({ jobs: state.selected.join(","), channel: state.channel, ref: state.ref });

  /** The reference job: the one chosen (GET ref=…) while it is selected, else the first. */
  function reference() {
    if (!state.selected.includes(state.ref)) state.ref = state.selected[0] || "";
    return state.ref;
  }

  function refControl() {
    const sel = state.selected.map((id) => jobs.find((j) => j.id === id)).filter(Boolean);
    setChildren(refBox, sel.length > 1 ? simpleSelect("cmp-ref", "Reference (differences relative to it)", sel.map((j) => [j.id, jobLabel(j, sel)]), reference(), (v) => { state.ref = v; saveQuery(); draw(); }) : null);
  }

  const msg = h("div", { "aria-live": "polite" });
  const chanBox = h("div");
  const time = seriesPlot({ title: "Time history overlay", id: "plot-compare-time", description: "The chosen channel of each job against time", height: 380 });
  const amp = spectrumPlot({ title: "Amplitude spectrum overlay", id: "plot-compare-spectrum", kind: "amplitude", description: "Amplitude spectra of the chosen channel of each job" });
  const psd = spectrumPlot({ title: "PSD overlay", id: "plot-compare-psd", kind: "psd", description: "Power spectral densities of the chosen channel of each job" });
  const table = h("div");

  const boxes = jobs.map((j) => h("label", { class: "check", style: { display: "flex" } },
    h("input", { type: "checkbox", value: j.id, checked: state.selected.includes(j.id), onchange: (e) => {
      if (e.target.checked) {
        if (state.selected.length >= MAX_JOBS) {
          e.target.checked = false;
          setChildren(msg, notice("warn", null, `At most ${MAX_JOBS} jobs at once.`));
          return;
        }
        state.selected.push(j.id);
      } else state.selected = state.selected.filter((x) => x !== j.id);
      setChildren(msg);
      refresh();
    } }), jobLabel(j, jobs)));
  const fmaxIn = h("input", { id: "cmp-fmax", type: "number", min: "1", max: "500", value: String(state.fmax), style: { width: "6em" }, onchange: () => { const v = Number(fmaxIn.value); if (v > 0) { state.fmax = v; draw(); } } });

  async function refresh() {
    reference();
    saveQuery();
    refControl();
    if (state.selected.length < 1) {
      setChildren(chanBox);
      time.card.empty("Choose at least one job (two or more to compare).");
      amp.card.empty("Choose jobs to compare.");
      psd.card.empty("Choose jobs to compare.");
      setChildren(table);
      return;
    }
    let lists;
    try {
      [lists] = await Promise.all([Promise.all(state.selected.map((id) => cached(`channels:${id}`, () => api.channels(id)))), loadPaperPoints().catch(() => [])]);
    } catch (err) {
      setChildren(msg, errorBox(err, "Could not load the channels"));
      return;
    }
    // channels every selected job has
    const common = lists[0].channels.filter((c) => lists.every((l) => l.channels.some((x) => x.name === c.name)));
    if (!common.some((c) => c.name === state.channel)) state.channel = (common.find((c) => c.name === "carbody.PC.acc.z") || common[0])?.name;
    const catalogue = pointCatalogue(lists[0].points);
    setChildren(chanBox, common.length ? channelSelect({ id: "cmp-channel", label: "Channel (common to the jobs)", channels: common, selected: state.channel, describe: (c) => pointText(c.point, catalogue), onChange: (v) => { state.channel = v; saveQuery(); draw(); } })
      : notice("warn", null, "These jobs have no channel in common."));
    draw();
  }

  function sources() {
    const sel = state.selected.map((id) => jobs.find((j) => j.id === id)).filter(Boolean);
    return sel.map((j, i) => ({ job: j.id, channel: state.channel, label: jobLabel(j, sel), color: COLORS[i % COLORS.length], dash: DASHES[i % DASHES.length] }));
  }

  async function draw() {
    if (!state.channel) return;
    const src = sources();
    time.set(src);
    amp.set(src, { fmax: state.fmax, logx: state.logx });
    psd.set(src, { fmax: state.fmax, logx: state.logx });
    // indices side by side (car-body acceleration channels)
    const m = state.channel.match(/^carbody\.([^.]+)\.acc\.([xyz])$/);
    if (!m) {
      setChildren(table, notice("info", null, "Comfort indices are compared for car-body accelerations."));
      return;
    }
    const [, point, dir] = m;
    try {
      const sums = await Promise.all(src.map((s) => cached(`summary:${s.job}`, () => api.summary(s.job)).catch(() => null)));
      const rows = src.map((s, i) => {
        const d = sums[i]?.summary?.points?.[point]?.directions?.[dir];
        return { label: s.label, job: s.job, w: sperlingOf(d), aw: awOf(d).value, peak: d?.peaks?.max_abs ?? null, rms: d?.peaks?.rms ?? null, f: d?.dominant_peaks?.[0]?.frequency ?? null };
      });
      const ref = rows.find((r) => r.job === reference()) || rows[0];
      const rel = (a, b) => (a !== null && b !== null && b !== 0 ? (a - b) / b : null);
      const diff = (v, r) => (r === ref ? h("span", { class: "muted" }, "reference") : h("span", { class: "nowrap" }, pct(v)));
      setChildren(table, dataTable([
        { key: "label", label: "Job", format: (v, r) => h("span", {}, h("a", { href: `#/jobs/${r.job}` }, v), r === ref ? h("span", { class: "badge st-queued ref-badge" }, "reference") : null) },
        { key: "w", label: "Sperling W", num: true, value: (r) => r.w.value, format: (v, r) => h("span", {}, fixed(r.w.value), gradeChip(r.w.grade)) },
        { key: "aw", label: "a_w (m/s²)", num: true, format: (v) => fmt(v, 3) },
        { key: "peak", label: "Peak |a| (m/s²)", num: true, format: (v) => fmt(v, 3) },
        { key: "rms", label: "rms (m/s²)", num: true, format: (v) => fmt(v, 3) },
        { key: "f", label: "Dominant f (Hz)", num: true, format: (v) => fmt(v, 3) },
        { key: "dw", label: "ΔW", title: "Sperling index relative to the reference job", num: true, value: (r) => rel(r.w.value, ref.w.value), format: diff },
        { key: "daw", label: "Δa_w", title: "weighted rms relative to the reference job", num: true, value: (r) => rel(r.aw, ref.aw), format: diff },
        { key: "dp", label: "Δpeak", title: "peak relative to the reference job", num: true, value: (r) => rel(r.peak, ref.peak), format: diff },
      ], rows, { caption: `Indices of ${channelLabel(state.channel)}; differences relative to the reference, ${ref.label}` }));
    } catch (err) {
      setChildren(table, errorBox(err));
    }
  }

  main.replaceChildren(
    h("h1", {}, "Compare jobs"),
    h("div", { class: "three" },
      h("div", { class: "stack" },
        h("fieldset", { class: "card", style: { margin: 0 } }, h("legend", {}, `Jobs (up to ${MAX_JOBS})`), h("div", { class: "stack", style: { maxHeight: "340px", overflow: "auto", gap: "2px" } }, boxes)),
        h("div", { class: "card controls stack", style: { margin: 0 } }, chanBox, refBox, h("label", { for: "cmp-fmax" }, "Spectra up to (Hz)", fmaxIn),
          h("label", { class: "check" }, h("input", { type: "checkbox", id: "cmp-logx", onchange: (e) => { state.logx = e.target.checked; draw(); } }), "Logarithmic frequency axis"))),
      h("div", {}, msg, time.el, h("div", { class: "grid2" }, amp.el, psd.el), h("section", { class: "card" }, table))));
  await refresh();
  return undefined;
}
