// Time histories of channels from one or more jobs, decimated by the server at every zoom level
// (GET /jobs/{id}/series with t_start / t_end / max_points), and spectra (amplitude / PSD) with
// their dominant peaks labelled.

import { api } from "../api.js";
import { prettyUnit, fmt, channelLabel, parseChannel } from "./dom.js";
import { plotCard, baseLayout, onZoom, pointsFor, COLORS, DASHES } from "./plot.js";

const QUANTITY = {
  acc: "Acceleration", disp: "Displacement", rot: "Rotation", force: "Force",
  rail_disp: "Rail displacement", spin: "Spin angle", vel: "Velocity",
};

export function quantityName(channel) {
  const q = parseChannel(channel)?.quantity;
  return QUANTITY[q] || q || "Value";
}

/**
 * @typedef {{job: string, channel: string, label?: string, scale?: number, unit?: string,
 *            color?: string, dash?: string}} Source
 */

/**
 * A time-history plot. `set(sources)` draws; zooming fetches the visible range again.
 * @param {{title: string, id: string, description?: string, height?: number}} opts
 */
export function seriesPlot(opts) {
  let sources = [];
  let lastTraces = [];
  let range = null; // [t0, t1] or null
  let zoomBound = false;
  let seq = 0;
  const units = new Map();
  const card = plotCard({
    ...opts,
    csv: () => ({
      header: ["series", "time (s)", "value", "unit"],
      rows: lastTraces.flatMap((t) => t.x.map((x, i) => [t.name, x, t.y[i], t.meta?.unit || ""])),
    }),
  });

  async function fetchAll(t0, t1) {
    const byJob = new Map();
    for (const s of sources) {
      if (!byJob.has(s.job)) byJob.set(s.job, []);
      if (!byJob.get(s.job).includes(s.channel)) byJob.get(s.job).push(s.channel);
    }
    const maxPoints = pointsFor(card.plotEl, 2);
    const results = await Promise.all([...byJob].map(async ([job, chans]) => {
      const res = await api.series(job, { channels: chans, max_points: maxPoints, t_start: t0 ?? undefined, t_end: t1 ?? undefined });
      return [job, res];
    }));
    return new Map(results);
  }

  function build(data) {
    const axisUnits = [];
    let nSamples = 0;
    let decimated = false;
    let fs = null;
    const traces = sources.map((s, i) => {
      const res = data.get(s.job);
      const ch = res?.channels.find((c) => c.name === s.channel);
      if (!ch) return null;
      nSamples = Math.max(nSamples, res.n_samples);
      decimated ||= res.decimated;
      fs = res.sample_rate_hz;
      const unit = s.unit || ch.unit;
      units.set(`${s.job}|${s.channel}`, unit);
      if (!axisUnits.includes(unit)) axisUnits.push(unit);
      const scale = s.scale ?? 1;
      const ax = Math.min(axisUnits.indexOf(unit), 1);
      return {
        type: "scatter", mode: "lines", name: s.label || channelLabel(s.channel),
        x: ch.time, y: scale === 1 ? ch.values : ch.values.map((v) => (v === null ? null : v * scale)),
        yaxis: ax ? "y2" : "y", line: { width: 1.2, color: s.color || COLORS[i % COLORS.length], dash: s.dash || DASHES[0] },
        meta: { unit: prettyUnit(unit) },
        hovertemplate: `%{y:.4g} ${prettyUnit(unit)}<extra>%{fullData.name}</extra>`,
      };
    }).filter(Boolean);
    const title = (u) => {
      const names = [...new Set(sources.filter((s) => (s.unit || units.get(`${s.job}|${s.channel}`)) === u).map((s) => quantityName(s.channel)))];
      return `${names.join(", ")} (${prettyUnit(u) || "–"})`;
    };
    const layout = baseLayout("Time (s)", title(axisUnits[0]), {
      uirevision: "keep", hovermode: "x",
      xaxis: range ? { range, autorange: false } : {},
    });
    if (axisUnits.length > 1) {
      layout.yaxis2 = { title: { text: title(axisUnits[1]) }, overlaying: "y", side: "right", automargin: true, zeroline: false, showgrid: false };
      layout.margin.r = 64;
    }
    return { traces, layout, info: { nSamples, decimated, fs } };
  }

  async function draw(t0 = null, t1 = null, isCurrent = () => true) {
    const my = ++seq;
    if (!sources.length) {
      card.empty("Choose at least one channel.");
      lastTraces = [];
      return;
    }
    const data = await fetchAll(t0, t1);
    if (my !== seq || !isCurrent()) return;
    range = t0 === null ? null : [t0, t1];
    const { traces, layout, info } = build(data);
    lastTraces = traces;
    if (!traces.length) {
      card.empty("None of the chosen channels is in the results.");
      return;
    }
    await card.draw(traces, layout);
    const perTrace = Math.max(...traces.map((t) => t.x.length));
    card.setNote(`${info.nSamples.toLocaleString("en-GB")} samples${info.fs ? ` at ${fmt(info.fs)} Hz` : ""} in view; ${info.decimated ? `decimated on the server to ≤ ${perTrace.toLocaleString("en-GB")} points per channel (minimum and maximum of each bucket, so peaks stay) – zoom in for every sample.` : "every sample shown."}`);
    if (!zoomBound && card.plotEl.on) {
      zoomBound = true;
      onZoom(card.plotEl, (a, b, cur) => draw(a, b, cur));
    }
  }

  return {
    card,
    el: card.el,
    /** Set the sources and draw the whole record. */
    async set(next) {
      sources = next;
      range = null;
      card.loading();
      try {
        await draw(null, null);
      } catch (err) {
        card.error(err);
      }
    },
  };
}

/** Peak labels with their arrows stacked so that they do not overlap (greedy, in pixels). */
function placeLabels(wanted, traces, { log, logx, height, width }) {
  const ys = traces.flatMap((t) => t.y).filter((v) => v !== null && Number.isFinite(v) && (!log || v > 0));
  const xs = traces.flatMap((t) => t.x).filter((v) => Number.isFinite(v) && (!logx || v > 0));
  if (!ys.length || !xs.length) return [];
  const tx = (v) => (logx ? Math.log10(v) : v);
  const ty = (v) => (log ? Math.log10(v) : v);
  const [x0, x1] = [tx(Math.min(...xs)), tx(Math.max(...xs))];
  const [y0, y1] = [ty(Math.min(...ys)), ty(Math.max(...ys))];
  const px = (v) => ((tx(v) - x0) / (x1 - x0 || 1)) * (width - 80);
  const py = (v) => ((y1 - ty(v)) / (y1 - y0 || 1)) * (height - 90);
  const placed = [];
  const out = [];
  for (const w of wanted.sort((a, b) => b.y - a.y)) {
    const x = px(w.x);
    const yTop = py(w.y);
    let ay = null;
    for (const cand of [-16, -34, -52, -70, -88]) {
      const y = yTop + cand;
      if (y < -10) continue;
      if (!placed.some((q) => Math.abs(q.x - x) < 54 && Math.abs(q.y - y) < 15)) {
        ay = cand;
        break;
      }
    }
    if (ay === null) continue; // no room: the note below the plot lists every peak
    placed.push({ x, y: yTop + ay });
    out.push({
      x: logx ? Math.log10(w.x) : w.x, y: log ? Math.log10(w.y) : w.y, xref: "x", yref: "y",
      text: w.text, showarrow: true, arrowhead: 0, arrowcolor: w.color, ax: 0, ay,
      font: { size: 11, color: w.color }, bgcolor: "rgba(255,255,255,.85)",
    });
  }
  return out;
}

/**
 * Amplitude spectrum or PSD of sources (one request per job), peaks labelled.
 * @param {{title: string, id: string, kind: "amplitude"|"psd", description?: string, height?: number}} opts
 */
export function spectrumPlot(opts) {
  let lastTraces = [];
  const card = plotCard({
    ...opts,
    csv: () => ({
      header: ["series", "frequency (Hz)", opts.kind === "psd" ? "PSD" : "amplitude", "unit"],
      rows: lastTraces.flatMap((t) => t.x.map((x, i) => [t.name, x, t.y[i], t.meta?.unit || ""])),
    }),
  });

  /**
   * @param {Source[]} sources
   * @param {{fmax?: number, segment_s?: number, dynamic?: boolean, log?: boolean, logx?: boolean, peaks?: number, extra?: object[]}} p
   *   `extra`: more traces in the same units drawn over the spectra (e.g. an estimate)
   */
  async function set(sources, p = {}) {
    if (!sources.length) {
      card.empty("Choose at least one channel.");
      return;
    }
    card.loading("Computing spectra on the server…");
    try {
      const byJob = new Map();
      for (const s of sources) {
        if (!byJob.has(s.job)) byJob.set(s.job, []);
        if (!byJob.get(s.job).includes(s.channel)) byJob.get(s.job).push(s.channel);
      }
      const params = { fmax: p.fmax ?? 50, dynamic: p.dynamic ?? true, max_points: 4000 };
      if (opts.kind === "psd" && p.segment_s) params.segment_s = p.segment_s;
      const fetched = new Map(await Promise.all([...byJob].map(async ([job, channels]) => {
        const res = await (opts.kind === "psd" ? api.psd : api.spectrum)(job, { ...params, channels });
        return [job, res];
      })));
      const log = p.log ?? opts.kind === "psd";
      const peakText = [];
      const wanted = []; // labels to place: {x, y, color, text}
      let unit = "";
      let meta = null;
      const traces = sources.map((s, i) => {
        const res = fetched.get(s.job);
        const ch = res?.channels.find((c) => c.name === s.channel);
        if (!ch) return null;
        meta = res;
        unit = ch.unit;
        const color = s.color || COLORS[i % COLORS.length];
        const name = s.label || channelLabel(s.channel);
        const peaks = (ch.peaks || []).slice(0, p.peaks ?? (sources.length > 2 ? 1 : 3));
        if (peaks.length) peakText.push(`${name}: ${peaks.map((k) => `${fmt(k.frequency)} Hz`).join(", ")}`);
        for (const k of peaks) {
          if (k.value === null || k.value === undefined || (log && !(k.value > 0))) continue;
          wanted.push({ x: k.frequency, y: k.value, color, text: `${fmt(k.frequency)} Hz` });
        }
        return {
          type: "scatter", mode: "lines", name, x: res.frequencies,
          y: log ? ch.values.map((v) => (v > 0 ? v : null)) : ch.values,
          line: { width: 1.3, color, dash: s.dash || "solid" }, meta: { unit: prettyUnit(ch.unit) },
          hovertemplate: `%{x:.3g} Hz: %{y:.4g} ${prettyUnit(ch.unit)}<extra>%{fullData.name}</extra>`,
        };
      }).filter(Boolean);
      const annotations = placeLabels(wanted, traces, { log, logx: !!p.logx, height: card.plotEl.clientHeight || 300, width: card.plotEl.clientWidth || 800 });
      if (!traces.length) {
        lastTraces = traces;
        card.empty("None of the chosen channels is in the results.");
        return;
      }
      traces.push(...(p.extra || []));
      lastTraces = traces;
      const yTitle = opts.kind === "psd" ? `PSD (${prettyUnit(unit)})` : `Amplitude (${prettyUnit(unit)})`;
      await card.draw(traces, baseLayout("Frequency (Hz)", yTitle, {
        annotations, hovermode: "x",
        yaxis: { type: log ? "log" : "linear", exponentformat: "power" },
        xaxis: { type: p.logx ? "log" : "linear" },
      }));
      const how = meta ? `${meta.scaling}; Δf = ${fmt(meta.resolution_hz)} Hz${meta.n_averages > 1 ? `, ${meta.n_averages} averages` : ""}${meta.dynamic ? "; quasi-static part (< 0.3 Hz) removed" : ""}.` : "";
      card.setNote(`${how} Dominant peaks – ${peakText.join("; ") || "none found"}.`);
    } catch (err) {
      card.error(err);
    }
  }
  return { card, el: card.el, set };
}
