// Contact geometry: a wheel and a rail profile placed in the track, the rigid contact points
// against the wheelset's lateral displacement Δy (a slider moves the wheel over its rail), the
// rolling-radius difference Δr(Δy) and the equivalent conicity (EN 15302) against the amplitude.
//
// Data: GET /api/v1/contact/geometry – the rows of `flexride contact table --json`, the conicity
// of `flexride contact conicity --json`, the left rail and the left wheel at Δy = 0 in track
// coordinates (mm: y from the track centre line, positive to the left; z up from the top of
// rail) and, per row, the axle height and the contact points. The wheel at row i is the wheel at
// Δy = 0 moved rigidly, as the answer's `profiles` documents: rotated by the change of roll
// about the axle centre, then shifted by Δy and by the change of the axle height. The form's
// defaults, bounds and help come from the endpoint's parameters in the OpenAPI document.

import { api, request } from "../api.js";
import { h, setChildren, notice, errorBox, fmt, loading, debounce } from "../components/dom.js";
import { plotCard, baseLayout, loadPlotly, COLORS } from "../components/plot.js";
import { replaceQuery } from "../components/nav.js";
import { placeServerErrors } from "../components/servererrors.js";

const PATH = "/api/v1/contact/geometry";
/** Form fields: query parameter, label, unit, control (number unless said). */
const FIELDS = [
  { name: "wheel", label: "Wheel profile", control: "profile", builtin: "s1002" },
  { name: "rail", label: "Rail profile", control: "profile", builtin: "60e1" },
  { name: "inclination", label: "Rail inclination", control: "select" },
  { name: "gauge_mm", label: "Track gauge", unit: "mm" },
  { name: "gauge_height_mm", label: "Gauge point below the top of rail", unit: "mm" },
  { name: "flange_back_mm", label: "Flange-back distance", unit: "mm" },
  { name: "r0_mm", label: "Nominal rolling radius r0", unit: "mm" },
  { name: "roll", label: "Solve the wheelset roll", control: "check" },
  { name: "y_max_mm", label: "Δy range ±", unit: "mm" },
  { name: "step_mm", label: "Δy step", unit: "mm" },
];
const C = { rail: "#52606d", wheel: COLORS[0], contact: COLORS[1], second: COLORS[3], dr: COLORS[0], cone: COLORS[2] };

/** The endpoint's query parameters by name, from the OpenAPI document. */
async function parameterSpecs() {
  const spec = await api.openapi();
  const op = spec?.paths?.[PATH]?.get;
  if (!op) throw new Error("This service has no contact-geometry endpoint (GET /api/v1/contact/geometry).");
  return Object.fromEntries((op.parameters || []).map((p) => [p.name, p.schema || {}]));
}

/** "; allowed: 1000 … 1700" from a parameter's schema bounds, or "". */
function rangeText(schema) {
  const lo = schema.minimum ?? schema.exclusiveMinimum;
  const hi = schema.maximum;
  if (lo === undefined || hi === undefined) return "";
  return `; allowed: ${schema.exclusiveMinimum !== undefined ? "> " : ""}${lo} … ${hi}`;
}

/** One form field: its control, the server's message under it, and how to read it back. */
function makeField(f, schema, value) {
  const id = `contact-${f.name}`;
  const err = h("div", { class: "field-error from-server", id: `${id}-err`, "aria-live": "polite" });
  const help = h("p", { class: "help", id: `${id}-help` }, schema.description || "", rangeText(schema));
  const described = `${id}-help ${id}-err`;
  let input;
  let fileIn = null; // a profile field's file chooser (an upload to POST /profiles)
  if (f.control === "select") {
    input = h("select", { id, "aria-describedby": described }, (schema.enum || []).map((v) => h("option", { value: v, selected: v === value }, v)));
  } else if (f.control === "check") {
    input = h("input", { id, type: "checkbox", checked: String(value) !== "false", "aria-describedby": described });
  } else if (f.control === "profile") {
    input = h("input", { id, type: "text", value, list: `${id}-list`, autocomplete: "off", spellcheck: "false", "aria-describedby": described });
    fileIn = h("input", { id: `${id}-file`, type: "file", class: "sr-only", "aria-describedby": described });
  } else {
    // a text input, as the scenario form's numbers (the service checks the range)
    input = h("input", { id, type: "text", inputmode: "decimal", value: String(value), autocomplete: "off", spellcheck: "false", "aria-describedby": described });
  }
  const unit = f.unit ? h("span", { class: "unit" }, f.unit) : null;
  const el = f.control === "check"
    ? h("div", { class: "field" }, h("label", { class: "check", for: id }, input, f.label), help, err)
    : h("div", { class: "field" }, h("label", { for: id }, f.label),
      h("div", { class: "input-row" }, input, unit),
      fileIn ? h("div", { class: "upload-row" }, h("label", { for: fileIn.id, class: "btn btn-small", title: `Upload a ${f.name} profile file (SIMPACK, MiniProf or y, z text in mm); the service stores it and the field takes its id` }, `Upload a ${f.name} file…`), fileIn) : null,
      help, err, fileIn ? h("datalist", { id: `${id}-list` }, h("option", { value: f.builtin })) : null);
  const read = () => (f.control === "check" ? String(input.checked) : input.value.trim());
  return { ...f, el, input, err, help, fileIn, read };
}

/** The upload endpoint's file formats (extensions without the dot), from the OpenAPI document. */
async function uploadFormats() {
  const spec = await api.openapi();
  const param = (spec?.paths?.["/api/v1/profiles"]?.post?.parameters || []).find((p) => p.name === "format");
  return param?.schema?.enum || [];
}

/**
 * Upload `file` as a profile of the field's kind (wheel or rail): the service checks it with the
 * CLI's readers and stores it by content hash. Resolves to the stored profile's facts; a refused
 * file rejects with the service's error (its message names the line).
 */
async function uploadProfile(field, file, formats, signal) {
  const format = (file.name.match(/\.([^.]+)$/)?.[1] || "").toLowerCase();
  if (!formats.includes(format)) {
    throw new Error(`${file.name}: not a profile file the service reads (extensions: ${formats.map((x) => `.${x}`).join(", ")})`);
  }
  return api.uploadProfile(await file.arrayBuffer(), { format, kind: field.name }, { signal, timeout: 60000 });
}

/** Points of the left wheel at row i (the rigid motion of the answer's `profiles`). */
export function wheelAt(data, i) {
  const p = data.profiles;
  const dphi = (data.rows[i].roll_rad ?? 0) - p.roll_rad;
  const c = Math.cos(dphi);
  const s = Math.sin(dphi);
  const at = data.contacts[i];
  const x = new Array(p.wheel.y_mm.length);
  const y = new Array(p.wheel.y_mm.length);
  p.wheel.y_mm.forEach((wy, k) => {
    const dy = wy - p.axle_y_mm;
    const dz = p.wheel.z_mm[k] - p.axle_z_mm;
    x[k] = at.dy_mm + c * dy - s * dz;
    y[k] = at.axle_z_left_mm + s * dy + c * dz;
  });
  return { x, y };
}

/** The contact point and the other branch's point (two-point contact only) at row i. */
function pointsAt(data, i) {
  const at = data.contacts[i];
  const row = data.rows[i];
  const second = row.two_point_left && at.left_second_y_mm !== null ? [[at.left_second_y_mm], [at.left_second_z_mm]] : [[], []];
  return { contact: [[at.left_y_mm], [at.left_z_mm]], second };
}

function sectionTraces(data, i) {
  const w = wheelAt(data, i);
  const pts = pointsAt(data, i);
  return [
    { type: "scatter", mode: "lines", name: "rail (left)", x: data.profiles.rail.y_mm, y: data.profiles.rail.z_mm, line: { color: C.rail, width: 2 }, hovertemplate: "rail: y %{x:.2f} mm, z %{y:.2f} mm<extra></extra>" },
    { type: "scatter", mode: "lines", name: "wheel (left)", x: w.x, y: w.y, line: { color: C.wheel, width: 2 }, hovertemplate: "wheel: y %{x:.2f} mm, z %{y:.2f} mm<extra></extra>" },
    { type: "scatter", mode: "markers", name: "contact point", x: pts.contact[0], y: pts.contact[1], marker: { color: C.contact, size: 11, symbol: "circle", line: { color: "#fff", width: 1 } }, hovertemplate: "contact: y %{x:.2f} mm, z %{y:.2f} mm<extra></extra>" },
    { type: "scatter", mode: "markers", name: "second contact (two-point)", x: pts.second[0], y: pts.second[1], marker: { color: C.second, size: 11, symbol: "circle-open", line: { width: 2 } }, hovertemplate: "second contact: y %{x:.2f} mm, z %{y:.2f} mm<extra></extra>" },
  ];
}

function sectionLayout(data) {
  const p = data.profiles;
  const ys = [...p.rail.y_mm, ...p.wheel.y_mm];
  const ym = data.parameters.y_max_mm;
  const lo = Math.min(...ys) - ym - 4;
  const hi = Math.max(...ys) + ym + 4;
  return baseLayout("Lateral position from the track centre y (mm)", "Height above the top of rail z (mm)", {
    xaxis: { range: [lo, hi] },
    yaxis: { scaleanchor: "x", scaleratio: 1 },
    uirevision: `section:${lo}:${hi}`,
    margin: { l: 64, r: 16, t: 24, b: 52 },
    shapes: [{ type: "line", xref: "x", yref: "paper", x0: p.gauge_point_y_mm, x1: p.gauge_point_y_mm, y0: 0, y1: 1, line: { color: "#9aa3ad", width: 1, dash: "dot" } }],
    annotations: [{ x: p.gauge_point_y_mm, y: 1, xref: "x", yref: "paper", text: "gauge point", showarrow: false, yanchor: "bottom", font: { size: 11, color: "#52606d" } }],
  });
}

function drTraces(data, i) {
  const rows = data.rows;
  const two = rows.filter((r) => r.two_point_left || r.two_point_right);
  return [
    { type: "scatter", mode: "lines", name: "Δr", x: rows.map((r) => r.dy_mm), y: rows.map((r) => r.dr_mm), line: { color: C.dr, width: 2 }, hovertemplate: "Δy %{x:.2f} mm: Δr %{y:.3f} mm<extra></extra>" },
    { type: "scatter", mode: "markers", name: "two-point contact", x: two.map((r) => r.dy_mm), y: two.map((r) => r.dr_mm), marker: { color: C.second, size: 5, symbol: "diamond" }, hovertemplate: "two-point contact at Δy %{x:.2f} mm<extra></extra>" },
    { type: "scatter", mode: "markers", name: "current Δy", x: [rows[i].dy_mm], y: [rows[i].dr_mm], marker: { color: C.contact, size: 12, line: { color: "#fff", width: 1 } }, hovertemplate: "Δy %{x:.2f} mm: Δr %{y:.3f} mm<extra></extra>" },
  ];
}

/** The drawn profiles at row i as CSV rows. */
function sectionCsv(data, i) {
  const w = wheelAt(data, i);
  const rail = data.profiles.rail;
  return { header: ["profile", "y (mm)", "z (mm)"],
    rows: [...rail.y_mm.map((y, k) => ["rail", y, rail.z_mm[k]]), ...w.x.map((y, k) => ["wheel", y, w.y[k]])] };
}

/** Rows of the CSV export of the table. */
function tableCsv(data) {
  const cols = Object.keys(data.columns);
  return { header: cols, rows: data.rows.map((r) => cols.map((c) => r[c])) };
}

function readout(data, i) {
  const r = data.rows[i];
  const two = [r.two_point_left ? "left" : "", r.two_point_right ? "right" : ""].filter(Boolean).join(", ") || "no";
  const item = (k, v) => [h("dt", {}, k), h("dd", {}, v)];
  return h("dl", { class: "kv" },
    item("Δy", `${fmt(r.dy_mm, 4)} mm`), item("Δr", `${fmt(r.dr_mm, 4)} mm`), item("Δγ", `${fmt(r.dgamma_rad, 4)} rad`),
    item("Roll", `${fmt((r.roll_rad ?? NaN) * 1e3, 4)} mrad (σ = ${fmt(r.roll_coefficient, 3)})`),
    item("Contact on the wheel (s)", `left ${fmt(r.wheel_left_mm, 4)} mm, right ${fmt(r.wheel_right_mm, 4)} mm`),
    item("Contact on the rail", `left ${fmt(r.rail_left_mm, 4)} mm, right ${fmt(r.rail_right_mm, 4)} mm`),
    item("From the centre line", `left ${fmt(r.track_left_mm, 5)} mm, right ${fmt(r.track_right_mm, 5)} mm`),
    item("Two-point contact", two));
}

export default async function render(main, ctx) {
  loadPlotly().catch(() => {}); // in parallel with the data
  ctx.title("Contact geometry");
  const formMsg = h("div", { id: "contact-form-msg", "aria-live": "polite" });
  const formEl = h("form", { class: "stack", id: "contact-form", novalidate: true });
  const section = plotCard({ title: "Wheel and rail in the track", id: "plot-contact-section", height: 420,
    description: "Cross-section of the left wheel on the left rail at the chosen lateral displacement, with the contact point",
    csv: () => state.data && sectionCsv(state.data, state.i) });
  const drCard = plotCard({ title: "Rolling-radius difference Δr", id: "plot-contact-dr", height: 320, csvName: "contact-table",
    description: "Rolling-radius difference against the lateral displacement, with the current displacement marked", csv: () => state.data && tableCsv(state.data) });
  const coneCard = plotCard({ title: "Equivalent conicity (EN 15302)", id: "plot-contact-conicity", height: 320,
    description: "Equivalent conicity against the amplitude of the wheelset's lateral motion",
    csv: () => state.data && { header: ["amplitude (mm)", "tan γe (-)"], rows: state.data.conicity.map((c) => [c.amplitude_mm, c.tan_gamma_e]) } });
  const slider = h("input", { id: "contact-dy", type: "range", min: "0", max: "0", step: "1", value: "0", disabled: true, "aria-describedby": "contact-dy-value" });
  const sliderOut = h("output", { id: "contact-dy-value", for: "contact-dy" }, "–");
  const info = h("div", { id: "contact-readout" }); // the slider's value text is announced
  section.setControls(h("div", { class: "controls contact-slider" }, h("label", { for: "contact-dy" }, "Lateral displacement Δy of the wheelset (to the left)", slider, sliderOut)));
  main.append(h("h1", {}, "Contact geometry"),
    h("p", { class: "muted small" }, "Rigid contact of a wheelset on its rails against its lateral displacement Δy, as ", h("code", {}, "flexride contact table"), " computes it; move the slider to move the wheel."),
    h("div", { class: "three" },
      h("section", { class: "card", "aria-labelledby": "contact-form-title" }, h("h2", { id: "contact-form-title", class: "h3" }, "Profiles and placement"), formEl, formMsg),
      h("div", {}, section.el, h("section", { class: "card", "aria-label": "Values at the current displacement" }, info),
        h("div", { class: "grid2" }, drCard.el, coneCard.el))));

  const state = { data: null, i: 0, seq: 0, fields: [] };
  let specs;
  try {
    specs = await parameterSpecs();
  } catch (err) {
    if (!ctx.signal.aborted) setChildren(formEl, errorBox(err, "The form could not be built"));
    for (const c of [section, drCard, coneCard]) c.empty("No contact geometry.");
    return undefined;
  }
  if (ctx.signal.aborted) return undefined;
  state.fields = FIELDS.map((f) => makeField(f, specs[f.name] || {}, ctx.query[f.name] ?? specs[f.name]?.default ?? ""));
  setChildren(formEl, state.fields.map((f) => f.el),
    h("div", { class: "actions" }, h("button", { type: "submit", class: "btn btn-primary", id: "contact-apply" }, "Compute")));

  const params = () => Object.fromEntries(state.fields.map((f) => [f.name, f.read()]));
  const saveQuery = debounce(() => {
    if (!state.data || ctx.signal.aborted) return; // not on another view's address
    replaceQuery({ ...params(), dy: state.data.rows[state.i].dy_mm });
  }, 300);

  function clearErrors() {
    setChildren(formMsg);
    for (const f of state.fields) {
      f.err.textContent = "";
      f.input.removeAttribute("aria-invalid");
    }
  }

  function showErrors(err) {
    const byKey = new Map(state.fields.map((f) => [`query.${f.name}`, f]));
    if (err?.status !== 422 || !err.items?.length) {
      setChildren(formMsg, errorBox(err, "The contact geometry could not be computed"));
      return;
    }
    const { errors, unmatched } = placeServerErrors(err.items, (k) => byKey.has(k), (k) => byKey.has(k));
    for (const [key, msg] of errors) {
      const f = byKey.get(key);
      f.err.textContent = msg;
      f.input.setAttribute("aria-invalid", "true");
    }
    setChildren(formMsg, notice("error", "The service refused these parameters",
      unmatched.length ? h("ul", {}, unmatched.map((u) => h("li", {}, u.msg))) : h("p", {}, "See the marked fields.")));
  }

  async function moveTo(i) {
    const data = state.data;
    state.i = i;
    const r = data.rows[i];
    sliderOut.textContent = `Δy = ${fmt(r.dy_mm, 4)} mm`;
    slider.setAttribute("aria-valuetext", `Δy ${fmt(r.dy_mm, 4)} millimetres, Δr ${fmt(r.dr_mm, 4)} millimetres`);
    setChildren(info, readout(data, i));
    saveQuery();
    const Plotly = await loadPlotly();
    if (state.data !== data || state.i !== i) return; // a newer position or answer
    const w = wheelAt(data, i);
    const pts = pointsAt(data, i);
    await Plotly.restyle(section.plotEl, { x: [w.x, pts.contact[0], pts.second[0]], y: [w.y, pts.contact[1], pts.second[1]] }, [1, 2, 3]);
    await Plotly.restyle(drCard.plotEl, { x: [[r.dy_mm]], y: [[r.dr_mm]] }, [2]);
  }

  async function draw(data) {
    state.data = data;
    const n = data.rows.length;
    const want = Number(ctx.query.dy); // the Δy asked for (address, or kept over a new computation)
    let i = Math.floor(n / 2);
    if (ctx.query.dy !== undefined && Number.isFinite(want)) {
      i = data.rows.reduce((best, r, k) => (Math.abs(r.dy_mm - want) < Math.abs(data.rows[best].dy_mm - want) ? k : best), i);
    }
    state.i = i;
    Object.assign(slider, { max: String(n - 1), value: String(i), disabled: false });
    await section.draw(sectionTraces(data, i), sectionLayout(data));
    section.setNote(`${data.wheel_name} on ${data.rail_name}, inclination ${data.parameters.inclination}, gauge ${fmt(data.parameters.gauge_mm, 5)} mm, flange backs ${fmt(data.parameters.flange_back_mm, 5)} mm${data.parameters.roll ? "" : ", no roll"}. Equal scales on both axes; the dotted line is the gauge point.`);
    await drCard.draw(drTraces(data, i), baseLayout("Lateral displacement Δy (mm)", "Δr = r_left − r_right (mm)", { uirevision: "dr" }));
    drCard.setNote(`${n} rows, Δy from ${fmt(-data.parameters.y_max_mm)} to ${fmt(data.parameters.y_max_mm)} mm in ${fmt(data.parameters.step_mm)} mm steps (CSV: the whole table).`);
    await drawConicity(data);
    await moveTo(i);
  }

  async function drawConicity(data) {
    if (!data.conicity.length) {
      coneCard.empty(data.conicity_note || "No equivalent conicity.");
      return;
    }
    await coneCard.draw([{ type: "scatter", mode: "lines+markers", name: "tan γe", x: data.conicity.map((c) => c.amplitude_mm), y: data.conicity.map((c) => c.tan_gamma_e),
      line: { color: C.cone, width: 2 }, marker: { size: 6 }, hovertemplate: "ŷ %{x:.1f} mm: tan γe %{y:.4f}<extra></extra>" }],
    baseLayout("Amplitude ŷ of the lateral motion (mm)", "Equivalent conicity tan γe (–)", { showlegend: false, yaxis: { rangemode: "tozero" } }));
    const at3 = data.conicity.find((c) => c.amplitude_mm === 3);
    coneCard.setNote(`EN 15302 integration method, on the Δr table of “flexride contact conicity”${at3 ? `; tan γe = ${fmt(at3.tan_gamma_e, 4)} at 3 mm` : ""}.`);
  }

  async function compute() {
    const seq = ++state.seq;
    clearErrors();
    if (!state.data) for (const c of [section, drCard, coneCard]) c.loading("Computing the contact geometry…");
    setChildren(formMsg, loading("Computing the contact geometry…"));
    try {
      const data = await request(PATH, { params: params(), signal: ctx.signal, timeout: 60000 });
      if (seq !== state.seq || ctx.signal.aborted) return;
      setChildren(formMsg);
      await draw(data);
    } catch (err) {
      if (seq !== state.seq || ctx.signal.aborted) return;
      showErrors(err);
      if (!state.data) for (const c of [section, drCard, coneCard]) c.empty("Fix the parameters marked in the form and compute again.");
    }
  }

  /** Upload the chosen file of a profile field, put its id in the field and compute again. */
  async function uploadInto(f) {
    const file = f.fileIn.files?.[0];
    f.fileIn.value = ""; // the same file may be chosen again after a fix
    if (!file) return;
    clearErrors();
    setChildren(formMsg, loading(`Uploading ${file.name}…`));
    try {
      const info = await uploadProfile(f, file, await uploadFormats(), ctx.signal);
      if (ctx.signal.aborted) return;
      f.input.value = info.id;
      f.el.querySelector("datalist")?.append(h("option", { value: info.id, label: file.name }));
      setChildren(f.help, `Uploaded ${file.name}: ${info.kind} profile, ${info.format} format, ${info.points} points; used by its id ${info.id.slice(0, 12)}…`);
      compute();
    } catch (err) {
      if (ctx.signal.aborted) return;
      setChildren(formMsg);
      f.err.textContent = err?.items?.length ? err.items.map((it) => it.msg).join("; ") : err.message;
      f.input.setAttribute("aria-invalid", "true");
    }
  }

  for (const f of state.fields) f.fileIn?.addEventListener("change", () => uploadInto(f));
  slider.addEventListener("input", () => { if (state.data) moveTo(Number(slider.value)); });
  formEl.addEventListener("submit", (e) => {
    e.preventDefault();
    if (state.data) ctx.query.dy = String(state.data.rows[state.i].dy_mm); // stay at this Δy
    compute();
  });
  compute();
  return () => { state.seq += 1; };
}
