// Plotly wrapper: lazy loading of /static/plotly.min.js (the installed plotly package's copy),
// common layout, and a plot "card" with PNG / SVG / CSV export, loading, empty and error states.

import { h, setChildren, loading, errorBox, notice, saveFile, toCsv, slug } from "./dom.js";

let plotlyPromise = null;
/** Load Plotly once (no CDN: served by the API at /static/plotly.min.js). */
export function loadPlotly() {
  if (window.Plotly) return Promise.resolve(window.Plotly);
  if (!plotlyPromise) {
    plotlyPromise = new Promise((resolve, reject) => {
      const s = document.createElement("script");
      s.src = "/static/plotly.min.js";
      s.async = true;
      s.onload = () => (window.Plotly ? resolve(window.Plotly) : reject(new Error("Plotly did not load")));
      s.onerror = () => {
        plotlyPromise = null;
        s.remove();
        reject(new Error("Plotly could not be loaded from /static/plotly.min.js (is the plotly package installed?)"));
      };
      document.head.append(s);
    });
  }
  return plotlyPromise;
}

/** Okabe–Ito palette (colour-blind safe), then a few more. */
export const COLORS = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9",
  "#000000", "#F0E442", "#7F3C8D", "#3969AC", "#80BA5A", "#E73F74"];
export const DASHES = ["solid", "dash", "dot", "dashdot", "longdash", "longdashdot"];

const FONT = "system-ui, -apple-system, 'Segoe UI', Roboto, 'Helvetica Neue', Arial, sans-serif";

/** Base layout: axis titles are required everywhere (units in brackets). */
export function baseLayout(xTitle, yTitle, extra = {}) {
  const axis = (title) => ({
    title: { text: title, standoff: 8 }, automargin: true, zeroline: false,
    gridcolor: "#e3e6ea", linecolor: "#9aa3ad", ticks: "outside", tickcolor: "#9aa3ad",
  });
  return {
    font: { family: FONT, size: 13, color: "#1f2933" },
    margin: { l: 64, r: 16, t: 16, b: 52 },
    paper_bgcolor: "#fff",
    plot_bgcolor: "#fff",
    colorway: COLORS,
    hoverlabel: { font: { family: FONT } },
    legend: { orientation: "h", y: -0.22, x: 0, yanchor: "top" },
    xaxis: { ...axis(xTitle), ...(extra.xaxis || {}) },
    yaxis: { ...axis(yTitle), ...(extra.yaxis || {}) },
    ...Object.fromEntries(Object.entries(extra).filter(([k]) => k !== "xaxis" && k !== "yaxis")),
  };
}

function pointCount(data) {
  let n = 0;
  for (const t of data || []) {
    if (t.type === "heatmap" || t.type === "surface") n += (t.z || []).reduce((a, r) => a + (r?.length || 0), 0);
    else if (t.type === "mesh3d") n += (t.x || []).length;
    else n += (t.x || t.y || t.z || t.values || []).length;
  }
  return n;
}

/**
 * A figure with a title, a toolbar and states.
 * @param {{title: string, id?: string, description?: string, height?: number, csvName?: string,
 *          csv?: () => ({header: string[], rows: any[][]}) | null}} opts
 */
export function plotCard(opts) {
  const plotEl = h("div", {
    class: "plot", role: "img", "aria-label": opts.description || opts.title,
    style: { height: `${opts.height || 360}px` }, dataset: { points: "0", state: "loading" },
  });
  const stateEl = h("div", { class: "plot-state" }, loading("Loading data…"));
  const note = h("p", { class: "plot-note" });
  const fname = () => slug(opts.csvName || opts.title);
  const btn = (label, title, fn) => h("button", { type: "button", class: "btn btn-small", title, onclick: fn }, label);
  const toolbar = h("div", { class: "toolbar", role: "group", "aria-label": `Export ${opts.title}` },
    btn("PNG", "Save the plot as a PNG image", () => exportImage("png")),
    btn("SVG", "Save the plot as an SVG image", () => exportImage("svg")),
    opts.csv ? btn("CSV", "Save the plotted data as CSV", () => {
      const c = opts.csv();
      if (c) saveFile(`${fname()}.csv`, toCsv(c.header, c.rows), "text/csv");
    }) : null);
  const headingId = opts.id ? `${opts.id}-title` : null;
  const el = h("section", { class: "card plot-card", id: opts.id || null, "aria-labelledby": headingId },
    h("header", { class: "card-head" }, h("h3", { id: headingId }, opts.title), toolbar),
    opts.controls || null, stateEl, plotEl, note);

  async function exportImage(format) {
    const Plotly = await loadPlotly();
    if (!plotEl.data) return;
    await Plotly.downloadImage(plotEl, { format, filename: fname(), width: plotEl.clientWidth || 1000, height: plotEl.clientHeight || 400, scale: format === "png" ? 2 : 1 });
  }

  let drawn = false;
  return {
    el, plotEl,
    setNote(text) { note.textContent = text || ""; },
    setControls(node) { el.querySelector(".card-head").after(node); },
    loading(text) {
      stateEl.hidden = false;
      setChildren(stateEl, loading(text || "Loading data…"));
      plotEl.dataset.state = "loading";
    },
    error(err, title = "Could not load this plot") {
      stateEl.hidden = false;
      setChildren(stateEl, errorBox(err, title));
      plotEl.dataset.state = "error";
      plotEl.hidden = true;
    },
    empty(text) {
      stateEl.hidden = false;
      setChildren(stateEl, notice("empty", null, text));
      plotEl.dataset.state = "empty";
      plotEl.dataset.points = "0";
      plotEl.hidden = true;
    },
    /** Draw (or update) the figure. */
    async draw(data, layout, config = {}) {
      const Plotly = await loadPlotly();
      stateEl.hidden = true;
      const wasHidden = plotEl.hidden;
      plotEl.hidden = false;
      const cfg = {
        responsive: true, displaylogo: false, scrollZoom: false,
        modeBarButtonsToRemove: ["lasso2d", "select2d", "sendDataToCloud"],
        toImageButtonOptions: { format: "png", filename: fname(), scale: 2 },
        ...config,
      };
      await Plotly.react(plotEl, data, layout, cfg);
      if (wasHidden && drawn) Plotly.Plots.resize(plotEl);
      drawn = true;
      plotEl.dataset.points = String(pointCount(data));
      plotEl.dataset.state = "ready";
      plotEl.setAttribute("aria-label", `${opts.description || opts.title}: ${data.length} trace(s), ${plotEl.dataset.points} points`);
      return plotEl;
    },
    async purge() {
      if (window.Plotly && drawn) window.Plotly.purge(plotEl);
      drawn = false;
    },
  };
}

/**
 * Keep a time plot decimated by the server at every zoom level: on zoom/pan, `fetchRange(t0, t1)`
 * is called (debounced) and must return the new traces; on autoscale, the full record.
 */
export function onZoom(plotEl, fetchRange, { axis = "xaxis", delay = 250 } = {}) {
  let timer = null;
  let seq = 0;
  plotEl.on("plotly_relayout", (ev) => {
    let t0;
    let t1;
    if (ev[`${axis}.autorange`]) {
      t0 = null;
      t1 = null;
    } else if (ev[`${axis}.range[0]`] !== undefined) {
      t0 = Number(ev[`${axis}.range[0]`]);
      t1 = Number(ev[`${axis}.range[1]`]);
    } else if (Array.isArray(ev[`${axis}.range`])) {
      [t0, t1] = ev[`${axis}.range`].map(Number);
    } else return;
    clearTimeout(timer);
    const my = ++seq;
    timer = setTimeout(async () => {
      try {
        await fetchRange(t0, t1, () => my === seq);
      } catch (e) {
        console.warn("zoom refresh failed", e); // keep the current view
      }
    }, delay);
  });
}

/** Points of a plot's width the server should send (two per pixel, for min/max buckets). */
export function pointsFor(el, factor = 2) {
  const w = el.clientWidth || 1000;
  return Math.max(200, Math.min(20000, Math.round(w * factor)));
}
