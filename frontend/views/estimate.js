// Estimate sweep: the frequency-domain comfort estimate (POST /api/v1/estimates with `sweep`) of
// a preset (with optional overrides) at up to 100 values of one scenario field, drawn as one
// index against the values; each value's flags are its hover text, refused values are marked.
// The answer holds every index of every point asked for, so choosing another point, direction or
// index redraws at once without asking again.

import { api, cached, request } from "../api.js";
import { h, setChildren, notice, errorBox, fmt, loading, debounce } from "../components/dom.js";
import { plotCard, baseLayout, loadPlotly, COLORS } from "../components/plot.js";
import { replaceQuery } from "../components/nav.js";
import { placeServerErrors } from "../components/servererrors.js";
import { numericPaths } from "./newstudy.js";
import { loadPaperPoints, pointCatalogue, pointText } from "../components/points.js";

/** The paper's points (GET /schemas/points), loaded with the view. */
let POINTS = [];

const MAX_VALUES = 100;
const SUGGESTED = ["vehicle.secondary.cz", "vehicle.secondary.kz", "vehicle.primary.kz", "speed_kmh"];
/** Indices: key in the answer's series (or nmv), label, unit. */
const INDICES = [
  { key: "sperling", label: "Sperling index W (spectral form)", unit: "–" },
  { key: "sperling_filter", label: "Sperling index W (filter form)", unit: "–" },
  { key: "rms", label: "rms acceleration", unit: "m/s²" },
  { key: "iso", label: "ISO 2631 weighted rms a_w", unit: "m/s²" },
  { key: "a_p95", label: "EN 12299 a_P95", unit: "m/s²" },
  { key: "peak", label: "expected peak acceleration", unit: "m/s²" },
  { key: "nmv", label: "EN 12299 mean comfort N_MV", unit: "–" },
];
const DEFAULTS = { preset: "paper-random-straight-80", parameter: "vehicle.secondary.cz", from: "20000", to: "200000", count: "10", point: "PC", direction: "z", index: "sperling", overrides: "" };

/** `count` values from `from` to `to`, evenly spaced (≤ MAX_VALUES), or an error message. */
export function sweepValues(from, to, count) {
  const a = Number(from);
  const b = Number(to);
  const n = Number(count);
  if (![a, b].every(Number.isFinite)) return "from and to must be numbers";
  if (!Number.isInteger(n) || n < 1 || n > MAX_VALUES) return `the count must be a whole number from 1 to ${MAX_VALUES}`;
  if (n === 1) return [a];
  return Array.from({ length: n }, (_, i) => Number((a + ((b - a) * i) / (n - 1)).toPrecision(12)));
}

/** "path: value" lines → {path: value} (values read as JSON where they are, else text). */
export function parseOverrides(text) {
  const out = {};
  for (const raw of String(text || "").split("\n")) {
    const line = raw.trim();
    if (!line || line.startsWith("#")) continue;
    const i = line.search(/[:=]/);
    if (i < 1) throw new Error(`“${line}” is not “path: value”`);
    const v = line.slice(i + 1).trim();
    let val;
    try {
      val = JSON.parse(v);
    } catch {
      val = v;
    }
    out[line.slice(0, i).trim()] = val;
  }
  return out;
}

/** One labelled control with its server message under it. */
function field(name, label, input, unit = null, help = null) {
  const id = `est-${name}`;
  Object.assign(input, { id });
  const err = h("div", { class: "field-error from-server", id: `${id}-err`, "aria-live": "polite" });
  input.setAttribute("aria-describedby", `${help ? `${id}-help ` : ""}${id}-err`);
  const el = h("div", { class: "field" }, h("label", { for: id }, label),
    h("div", { class: "input-row" }, input, unit), help ? h("p", { class: "help", id: `${id}-help` }, help) : null, err);
  return { name, el, input, err };
}

const text = (value, extra = {}) => h("input", { type: "text", value, autocomplete: "off", spellcheck: "false", ...extra });
const select = (options, value) => h("select", {}, options.map(([v, l]) => h("option", { value: v, selected: v === value }, l)));

/** The values of an index along the sweep: {y, unit, label}. */
function seriesOf(data, point, dir, index) {
  if (index.key === "nmv") return data.nmv?.[point] || null;
  const s = data.series?.[point]?.[dir];
  if (!s) return null;
  if (index.key !== "iso") return s[index.key] || null;
  const w = Object.keys(s).find((k) => /^W[a-z]$/.test(k)); // Wb (z) or Wd (y)
  return w ? s[w] : null;
}

/** Hover text of value i: its flags (the first three, shortened). */
function flagText(flags) {
  if (!flags?.length) return "no flags";
  const cut = (f) => (f.length > 90 ? `${f.slice(0, 88)}…` : f);
  const more = flags.length > 3 ? `<br>… and ${flags.length - 3} more` : "";
  return `${flags.length} flag${flags.length > 1 ? "s" : ""}:<br>${flags.slice(0, 3).map(cut).join("<br>")}${more}`;
}

function traces(data, y, label) {
  const xs = data.values;
  const flagged = data.flags.map((f) => f.length > 0);
  const ok = y.map((v) => v !== null && v !== undefined);
  const valid = y.filter((v, i) => ok[i]);
  const base = valid.length ? Math.min(...valid) : 0;
  const refused = data.refused || [];
  return [
    { type: "scatter", mode: "lines+markers", name: label, x: xs, y, connectgaps: false,
      text: data.flags.map(flagText), hovertemplate: "%{x}: %{y:.4g}<br>%{text}<extra></extra>",
      line: { color: COLORS[0], width: 2 },
      marker: { size: 8, color: COLORS[0], symbol: flagged.map((f) => (f ? "circle-open" : "circle")), line: { width: 2, color: COLORS[0] } } },
    { type: "scatter", mode: "markers", name: "refused (no linear estimate)", x: refused.map((r) => r.value), y: refused.map(() => base),
      text: refused.map((r) => `refused: ${r.reason}<br>${r.message.slice(0, 120)}`), hovertemplate: "%{x}: %{text}<extra></extra>",
      marker: { size: 12, symbol: "x", color: COLORS[1] } },
  ];
}

/** Indices of the floor map: key, label, direction, index in the answer (unit from `units`). */
const FLOOR_INDICES = [
  ["sz", "Sperling index W vertical (z)", "z", "sperling"],
  ["sy", "Sperling index W lateral (y)", "y", "sperling"],
  ["awz", "ISO 2631 a_w vertical (z)", "z", "iso2631"],
  ["awy", "ISO 2631 a_w lateral (y)", "y", "iso2631"],
  ["rz", "rms acceleration vertical (z)", "z", "rms"],
  ["ry", "rms acceleration lateral (y)", "y", "rms"],
  ["nmv", "EN 12299 mean comfort N_MV", null, "nmv"],
];

/** The [y][x] values, label and unit of one floor-map index. */
function floorValues(fm, key) {
  const [, label, dir, index] = FLOOR_INDICES.find(([k]) => k === key);
  const z = dir ? fm.indices[dir][index] : fm.nmv;
  const unit = fm.units[index] === "-" ? "–" : "m/s²";
  const weight = index === "iso2631" ? ` (${fm.weightings[dir]})` : "";
  return { z, label: `${label}${weight}`, unit };
}

/** A heatmap of the floor map with the scenario's floor points (the paper's) marked. */
function floorTraces(fm, v) {
  return [
    { type: "heatmap", x: fm.x_m, y: fm.y_m, z: v.z, colorscale: "YlOrRd", reversescale: true, zsmooth: fm.y_m.length > 1 ? "best" : false,
      colorbar: { title: { text: v.unit } }, hovertemplate: `x = %{x:.2f} m, y = %{y:.2f} m<br>${v.label}: %{z:.3f} ${v.unit}<extra></extra>` },
    { type: "scatter", mode: "markers+text", name: "floor points", x: fm.points.map((p) => p.x), y: fm.points.map((p) => p.y),
      text: fm.points.map((p) => p.name), textposition: "top center", customdata: fm.points.map((p) => p.description),
      marker: { color: "#0b4f8a", size: 9, symbol: "x" }, hovertemplate: "%{customdata}<br>x = %{x:.2f} m, y = %{y:.2f} m<extra></extra>" },
  ].filter((t) => t.type === "heatmap" || fm.points.length);
}

/**
 * The comfort map over the car body's floor (POST /estimates with `floor_map`) of the form's
 * preset and overrides: one request per scenario and spacing, any index drawn from the answer.
 * `base()` gives {preset, overrides} or null.
 */
function floorMapCard(base, signal) {
  const spacing = h("input", { type: "number", id: "floor-spacing", value: "1", min: "0.2", max: "5", step: "0.1", style: { width: "6em" } });
  const spacingErr = h("span", { class: "field-error from-server", id: "floor-spacing-err", "aria-live": "polite" });
  const indexSel = select(FLOOR_INDICES.map(([k, l]) => [k, l]), "sz");
  Object.assign(indexSel, { id: "floor-index" });
  const card = plotCard({ title: "Comfort over the floor", id: "plot-floor-map", height: 300, csvName: "estimate-floor-map",
    description: "Estimated comfort index over the car body's floor grid, the paper's floor points marked", csv: () => csvOf() });
  card.setControls(h("div", { class: "controls" },
    h("label", { for: "floor-spacing" }, "Grid spacing (m)", spacing, spacingErr),
    h("label", { for: "floor-index" }, "Index", indexSel)));
  const state = { data: null, ctrl: null, seq: 0, key: null };

  function csvOf() {
    const fm = state.data;
    if (!fm) return null;
    const v = floorValues(fm, indexSel.value);
    return { header: ["point", "x (m)", "y (m)", `${v.label} (${v.unit})`], rows: fm.names.flatMap((row, j) => row.map((n, i) => [n, fm.x_m[i], fm.y_m[j], v.z[j][i]])) };
  }

  async function draw() {
    const fm = state.data;
    if (!fm) return;
    const v = floorValues(fm, indexSel.value);
    await card.draw(floorTraces(fm, v), baseLayout("Position along the car body x (m, forward +)", "Across y (m, left +)", {
      yaxis: { scaleanchor: "x", scaleratio: 1 }, showlegend: false }));
    const flat = v.z.flat().filter((x) => x !== null);
    card.setNote(`${v.label} on the floor grid (${flat.length} points, ${fmt(fm.spacing_m)} m apart), range ${fmt(Math.min(...flat), 3)}–${fmt(Math.max(...flat), 3)} ${v.unit}; × the scenario's floor points. Frequency-domain estimate.`);
  }

  async function compute() {
    const b = base();
    const key = JSON.stringify([b, spacing.value]);
    // the same map, drawn or on its way (Enter fires both keydown and change: one request)
    if (!b || key === state.key) return;
    state.key = key;
    const my = ++state.seq;
    state.ctrl?.abort();
    state.ctrl = new AbortController();
    spacingErr.textContent = "";
    spacing.removeAttribute("aria-invalid");
    card.loading("Mapping the floor…");
    try {
      const body = { ...b, points: ["PC"], floor_map: { spacing_m: Number(spacing.value) }, refusal: "answer" };
      const res = await request("/estimates", { method: "POST", body, signal: state.ctrl.signal, timeout: 60000 });
      if (my !== state.seq || signal.aborted) return;
      if (res.applicable === false) {
        state.data = null;
        card.empty(`No linear estimate: ${res.message}`);
        return;
      }
      state.data = res.floor_map;
      await draw();
    } catch (err) {
      if (my !== state.seq || signal.aborted || err?.name === "AbortError") return;
      state.data = null;
      state.key = null; // the same spacing may be asked again
      const at = err.items?.find((i) => (i.loc || []).join(".").endsWith("floor_map.spacing_m"));
      if (at) {
        spacingErr.textContent = at.msg;
        spacing.setAttribute("aria-invalid", "true");
        card.empty("Choose another spacing.");
      } else card.error(err, "No floor map");
    }
  }
  spacing.addEventListener("change", compute);
  spacing.addEventListener("keydown", (e) => { if (e.key === "Enter") compute(); });
  indexSel.addEventListener("change", draw);
  signal.addEventListener("abort", () => state.ctrl?.abort(), { once: true });
  return { el: card.el, compute };
}

export default async function render(main, ctx) {
  loadPlotly().catch(() => {});
  ctx.title("Estimate");
  const q = { ...DEFAULTS, ...ctx.query };
  main.append(h("h1", {}, "Estimate"), loading("Loading the presets and the scenario schema…"));
  let presets;
  let paths;
  try {
    const [p, schema, paper] = await Promise.all([cached("presets", api.presets), cached("schema", api.scenarioSchema), loadPaperPoints()]);
    presets = p;
    POINTS = paper.map((x) => x.name);
    paths = numericPaths(schema);
  } catch (err) {
    setChildren(main, h("h1", {}, "Estimate"), errorBox(err, "The form could not be prepared"));
    return undefined;
  }
  if (ctx.signal.aborted) return undefined;

  const unitOfPath = (p) => paths.find((x) => x.path === p.trim())?.unit || "";
  const paramUnit = h("span", { class: "unit", id: "est-parameter-unit" }, unitOfPath(q.parameter));
  const unitBadge = () => h("span", { class: "unit" }, unitOfPath(q.parameter));
  const F = {
    preset: field("preset", "Preset", select(presets.map((p) => [p.name, p.name]), q.preset)),
    overrides: field("overrides", "Overrides (optional)", h("textarea", { rows: 3, class: "mono", spellcheck: "false" }, q.overrides), null, "One “dotted.path: value” a line, e.g. vehicle.primary.cz: 8000"),
    parameter: field("parameter", "Parameter (dotted path)", text(q.parameter, { list: "est-paths" }), paramUnit),
    from: field("from", "From", text(q.from, { inputmode: "decimal" }), unitBadge()),
    to: field("to", "To", text(q.to, { inputmode: "decimal" }), unitBadge()),
    count: field("count", "Number of values", text(q.count, { inputmode: "numeric" }), null, `At most ${MAX_VALUES}, evenly spaced from “from” to “to”.`),
  };
  const pointSel = select([...new Set([...POINTS, q.point])].map((p) => [p, pointText(p, pointCatalogue())]), q.point);
  const dirSel = select([["z", "vertical (z)"], ["y", "lateral (y)"]], q.direction);
  const indexSel = select(INDICES.map((i) => [i.key, `${i.label} (${i.unit})`]), q.index);
  const formMsg = h("div", { id: "est-form-msg", "aria-live": "polite" });
  const datalist = h("datalist", { id: "est-paths" },
    [...SUGGESTED, ...paths.map((p) => p.path).filter((p) => !SUGGESTED.includes(p))].map((p) => h("option", { value: p }, unitOfPath(p) ? `${p} (${unitOfPath(p)})` : p)));
  const formEl = h("form", { class: "stack", id: "est-form", novalidate: true },
    Object.values(F).map((f) => f.el), datalist,
    h("div", { class: "actions" }, h("button", { type: "submit", class: "btn btn-primary", id: "est-apply" }, "Estimate")), formMsg);
  const card = plotCard({ title: "Index against the parameter", id: "plot-estimate-sweep", height: 420, csvName: "estimate-sweep",
    description: "Estimated comfort index against the swept parameter", csv: () => state.data && csvOf(state.data) });
  card.setControls(h("div", { class: "controls" },
    h("label", { for: "est-point" }, "Point", Object.assign(pointSel, { id: "est-point" })),
    h("label", { for: "est-direction" }, "Direction", Object.assign(dirSel, { id: "est-direction" })),
    h("label", { for: "est-index" }, "Index", Object.assign(indexSel, { id: "est-index" }))));
  const floor = floorMapCard(() => {
    try {
      return { preset: F.preset.input.value, overrides: parseOverrides(F.overrides.input.value) };
    } catch {
      return null; // marked by the sweep's check
    }
  }, ctx.signal);
  setChildren(main, h("h1", {}, "Estimate"),
    h("p", { class: "muted small" }, "Comfort indices from the linearised vehicle–track model driven by the track spectra (", h("code", {}, "flexride estimate"), "), in about a second, for a sweep of any one scenario field; a time-domain job is the check."),
    h("div", { class: "three" },
      h("section", { class: "card", "aria-labelledby": "est-form-title" }, h("h2", { id: "est-form-title", class: "h3" }, "Scenario and sweep"), formEl),
      h("div", {}, card.el, floor.el)));

  const state = { data: null, seq: 0, ctrl: null };
  const selection = () => ({ point: pointSel.value, direction: dirSel.value, index: indexSel.value });
  const formValues = () => Object.fromEntries(Object.entries(F).map(([k, f]) => [k, f.input.value.trim()]));

  function csvOf(data) {
    const idx = INDICES.find((i) => i.key === indexSel.value);
    const y = seriesOf(data, pointSel.value, dirSel.value, idx) || [];
    return { header: [data.parameter, `${idx.label} (${idx.unit})`, "flags"], rows: data.values.map((v, i) => [v, y[i], data.flags[i].join(" | ")]) };
  }

  async function draw() {
    const data = state.data;
    if (!data) return;
    const { point, direction } = selection();
    const idx = INDICES.find((i) => i.key === indexSel.value);
    dirSel.disabled = idx.key === "nmv";
    const y = seriesOf(data, point, direction, idx);
    replaceQuery({ ...formValues(), ...selection() });
    if (!y) {
      card.empty(`No ${idx.label} at ${point}${idx.key === "nmv" ? " (N_MV is given for floor points)" : ""}.`);
      return;
    }
    const unit = unitOfPath(data.parameter);
    const dirName = idx.key === "nmv" ? "" : ` ${direction}`;
    const label = `${idx.label}${dirName} at ${point}`;
    await card.draw(traces(data, y, label), baseLayout(`${data.parameter} (${unit || "–"})`, `${idx.label}${dirName} (${idx.unit})`, { uirevision: data.parameter }));
    const n = data.refused.length;
    const flagged = data.flags.filter((f) => f.length).length;
    card.setNote(`${data.values.length} values in ${fmt(data.seconds, 2)} s; ${n ? `${n} refused (×)` : "none refused"}; ${flagged} with flags (open markers, hover for them).`);
  }

  function clearErrors() {
    setChildren(formMsg);
    for (const f of Object.values(F)) {
      f.err.textContent = "";
      f.input.removeAttribute("aria-invalid");
    }
  }

  function markField(name, msg) {
    F[name].err.textContent = msg;
    F[name].input.setAttribute("aria-invalid", "true");
  }

  /** The server's 422 items at the form's fields: sweep.parameter, sweep.values (from/to), preset, overrides (also
   * an item at the scenario path an override sets). */
  function showErrors(err) {
    if (err?.status !== 422 || !err.items?.length) {
      setChildren(formMsg, errorBox(err, "The estimate could not be computed"));
      return;
    }
    let keys = [];
    try {
      keys = Object.keys(parseOverrides(F.overrides.input.value));
    } catch { /* marked before */ }
    const at = (k) => (k.startsWith("sweep.values") ? "from" : k.startsWith("overrides") || keys.includes(k) ? "overrides"
      : { "sweep.parameter": "parameter", sweep: "parameter", preset: "preset" }[k]);
    const { errors, unmatched } = placeServerErrors(err.items, (k) => !!at(k), (k) => !!at(k));
    for (const [key, msg] of errors) markField(at(key), msg);
    setChildren(formMsg, notice(err.body?.reason ? "warn" : "error", err.body?.reason ? "No linear estimate" : "The service refused this sweep",
      unmatched.length ? h("ul", {}, unmatched.map((u) => h("li", {}, u.msg))) : h("p", {}, "See the marked fields.")));
  }

  /** The request body, or null after marking what is wrong in the browser. */
  function body() {
    const v = formValues();
    const values = sweepValues(v.from, v.to, v.count);
    if (typeof values === "string") {
      markField(Number.isInteger(Number(v.count)) && Number(v.count) >= 1 && Number(v.count) <= MAX_VALUES ? "from" : "count", values);
      return null;
    }
    let overrides;
    try {
      overrides = parseOverrides(v.overrides);
    } catch (e) {
      markField("overrides", e.message);
      return null;
    }
    const points = [...new Set([...POINTS, pointSel.value])];
    return { preset: v.preset, overrides, points, sweep: { parameter: v.parameter, values } };
  }

  async function compute() {
    const seq = ++state.seq;
    if (state.ctrl) state.ctrl.abort();
    clearErrors();
    const b = body();
    if (!b) return;
    paramUnit.textContent = unitOfPath(b.sweep.parameter);
    state.ctrl = new AbortController();
    if (!state.data) card.loading("Estimating…");
    setChildren(formMsg, loading(`Estimating at ${b.sweep.values.length} values…`));
    try {
      const data = await request("/estimates", { method: "POST", body: b, signal: state.ctrl.signal, timeout: 60000 });
      if (seq !== state.seq || ctx.signal.aborted) return;
      setChildren(formMsg);
      state.data = data;
      await draw();
    } catch (err) {
      if (seq !== state.seq || ctx.signal.aborted || err?.name === "AbortError") return;
      showErrors(err);
      if (!state.data) card.empty("Fix the marked fields and estimate again.");
    }
  }

  const later = debounce(() => { compute(); floorLater(); }, 400);
  const floorLater = debounce(floor.compute, 50);
  formEl.addEventListener("submit", (e) => {
    e.preventDefault();
    compute();
    floor.compute();
  });
  formEl.addEventListener("change", later);
  F.parameter.input.addEventListener("input", () => {
    const u = unitOfPath(F.parameter.input.value);
    paramUnit.textContent = u;
    for (const k of ["from", "to"]) F[k].el.querySelector(".unit").textContent = u;
  });
  for (const s of [pointSel, dirSel, indexSel]) s.addEventListener("change", draw);
  ctx.signal.addEventListener("abort", () => state.ctrl?.abort(), { once: true });
  compute();
  floor.compute();
  return () => { state.seq += 1; };
}
