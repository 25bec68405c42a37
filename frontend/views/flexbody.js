// Flexible body: the car-body (or frame) FE mesh in 3D with its mode shapes (scaled or animated,
// frequency list), and a comfort map over the floor of a run that recorded the floor grid.
//
// Mesh source: GET /api/v1/fe/{kind} with the model parameters of a scenario's `bodies` settings
// (element_size_m, cutoff_hz, reduction), or, when the chosen job models that body as flexible,
// GET /api/v1/jobs/{id}/fe/{kind} (the job's own body). Both answer 202 while the server builds
// the model (first time only); the view polls until 200. A JSON file written by
// `flexride fe export carbody --out carbody.json` can be loaded instead. Both shapes are read:
//   export_mesh: {nodes, quads, beams, modes: [{index, frequency_hz, classification, scale_m, displacements}]}
//   plain:       {nodes: [[x,y,z]], elements: [[i,j,k,l]], frequencies: [f], modes: [[[dx,dy,dz]]]}
// The comfort map places the floor-grid points at the positions GET /jobs/{id}/channels gives.
// Calibration targets ("5.03:torsion,6.11,…") are paired with the model's modes by
// GET /api/v1/fe/carbody/pairing (flexride fe calibrate's rules: by type, then frequency).

import { api, cached } from "../api.js";
import { h, setChildren, notice, fmt, fixed, prettyUnit, dataTable } from "../components/dom.js";
import { plotCard, baseLayout, loadPlotly } from "../components/plot.js";
import { simpleSelect } from "../components/channels.js";
import { replaceQuery } from "../components/nav.js";
import { waitNote } from "../components/waiting.js";
import { sperlingOf, awOf } from "./job.js";

const KIND_LABEL = { carbody: "car body", frame: "bogie frame" };
const BODY_FIELD = { carbody: "carbody", frame: "frames" }; // scenario.bodies.<field>
const MODEL_PARAMS = ["element_size_m", "cutoff_hz", "reduction"];
const MAX_MODES = 12;

/** Measured wall time (s) of a first build of an FE model (modal reduction, 40 Hz cut-off, 12
 * mode shapes), `flexride fe export` on the 2-core development VM (Debian, Python 3.11) under a
 * load of about 7, Dec 2026: car body 184 s with 0.2 m elements (51 s CPU) and 87 s with 0.5 m
 * (18 s CPU) – a fixed part and a part growing with the number of shell elements, (0.2 m /
 * size)², fitted through both; bogie frame 23 s (5 s CPU). The dashboard's first 0.2 m build
 * took 170 s there. */
const FE_BUILD_S = { carbody: { fixed: 68, per: 116 }, frame: { fixed: 23, per: 0 } };

/** The estimated wall time (s) of a first build of `kind` with elements of `size` m. */
export function buildEstimate(kind, size) {
  const m = FE_BUILD_S[kind === "frame" ? "frame" : "carbody"];
  const s = Number(size) || 0.2;
  return m.fixed + m.per * (0.2 / s) ** 2;
}

/** The floor-grid points F<i>_<j> of a channel list's `points` as a grid: sorted xs and ys and
 * the point name at (x, y). */
export function floorGridOf(points) {
  const floor = (points || []).filter((p) => p.body === "carbody" && p.kind === "grid");
  const xs = [...new Set(floor.map((p) => p.x))].sort((a, b) => a - b);
  const ys = [...new Set(floor.map((p) => p.y))].sort((a, b) => a - b);
  const at = new Map(floor.map((p) => [`${p.x},${p.y}`, p.name]));
  return { xs, ys, n: floor.length, z: floor[0]?.z, name: (x, y) => at.get(`${x},${y}`) };
}

const sleep = (ms, signal) => new Promise((resolve) => {
  const t = setTimeout(resolve, ms);
  signal?.addEventListener("abort", () => { clearTimeout(t); resolve(); }, { once: true });
});

/** Normalise either mesh shape to {nodes, quads, tris, beams, modes: [{frequency, label, disp}]}. */
export function normaliseMesh(m) {
  if (!m || !Array.isArray(m.nodes) || !m.nodes.length) throw new Error("no nodes: expected {nodes: [[x, y, z], …], …}");
  const elements = m.quads || m.elements || [];
  const quads = [];
  const tris = [];
  for (const e of elements) {
    if (!Array.isArray(e)) continue;
    if (e.length === 4) quads.push(e);
    else if (e.length === 3) tris.push(e);
  }
  const beams = (m.beams || []).filter((b) => Array.isArray(b) && b.length === 2);
  let modes = [];
  if (Array.isArray(m.modes)) {
    modes = m.modes.map((md, k) => {
      if (Array.isArray(md)) return { frequency: m.frequencies?.[k] ?? null, label: "", disp: md, index: k + 1 };
      return { frequency: md.frequency_hz ?? md.frequency ?? m.frequencies?.[k] ?? null, label: md.classification || "", disp: md.displacements || md.shape || [], index: md.index ?? k + 1, scale: md.scale_m };
    }).filter((md) => md.disp.length === m.nodes.length);
  }
  const n = m.nodes.length;
  const bad = [...quads, ...tris, ...beams].some((e) => e.some((i) => !(i >= 0 && i < n)));
  if (bad) throw new Error("an element refers to a node that does not exist");
  return { nodes: m.nodes, quads, tris, beams, modes, units: m.units || { length: "m", frequency: "Hz" }, named: m.named_nodes || {} };
}

export default async function render(main, ctx) {
  loadPlotly().catch(() => {}); // in parallel with the data
  ctx.title("Flexible body");
  const state = { kind: ctx.query.kind === "frame" ? "frame" : "carbody", mode: 0, scale: 0, animate: false, mesh: null, wire: true, gci: new Map() };
  // model parameters from the address (as the scenario's bodies settings); the server's defaults otherwise
  const params = Object.fromEntries(MODEL_PARAMS.filter((k) => ctx.query[k]).map((k) => [k, ctx.query[k]]));
  // the targets the car body is calibrated to before it is reduced (bodies.carbody.calibration; GET /fe/carbody?calibration_targets=…); "" the default body
  let calibrateTo = ctx.query.calibrate || "";
  /** The model's query: its parameters, with the calibration for the car body. */
  const modelQuery = () => ({ ...params, ...(calibrateTo && state.kind === "carbody" ? { calibration_targets: calibrateTo } : {}), max_modes: MAX_MODES });
  let animLoop = null;
  let loadSeq = 0; // a newer load supersedes the polling of an older one
  const cleanups = [];

  // -- mesh and modes ----------------------------------------------------------------------------
  const meshMsg = h("div", { "aria-live": "polite" });
  const modeList = h("div", { class: "mode-list stack", role: "group", "aria-label": "Mode shapes" });
  const card = plotCard({ title: "Mesh and mode shape", id: "plot-mesh", description: "3D view of the finite-element mesh deformed by the chosen mode shape", height: 480,
    csv: () => state.mesh && ({ header: ["node", "x (m)", "y (m)", "z (m)", "dx", "dy", "dz"], rows: state.mesh.nodes.map((p, i) => [i, ...p, ...(state.mesh.modes[state.mode]?.disp[i] || [null, null, null])]) }) });
  const scaleIn = h("input", { id: "mode-scale", type: "range", min: "0", max: "1", step: "0.01", value: "0.3", "aria-describedby": "mode-scale-value" });
  const scaleOut = h("output", { id: "mode-scale-value", for: "mode-scale" });
  const animBox = h("input", { id: "mode-animate", type: "checkbox" });
  const wireBox = h("input", { id: "mode-wire", type: "checkbox", checked: true });
  const fileIn = h("input", { id: "mesh-file", type: "file", accept: ".json,application/json", class: "sr-only" });
  const kindSel = simpleSelect("mesh-kind", "Body", [["carbody", "car body"], ["frame", "bogie frame"]], state.kind, (v) => { state.kind = v; saveQuery(); loadFromService(); });
  function saveQuery() {
    replaceQuery({ kind: state.kind, job: jobSel?.value || "", measure, ...params, targets: targetsIn.value.trim(), calibrate: calibrateTo });
  }

  // model parameters (the scenario's bodies settings: same names, units and ranges)
  const sizeIn = h("input", { id: "fe-element-size", type: "number", step: "0.05", inputmode: "decimal" });
  const cutoffIn = h("input", { id: "fe-cutoff", type: "number", step: "1", inputmode: "decimal" });
  const reductionSel = h("select", { id: "fe-reduction" }, ["modal", "guyan", "craig-bampton"].map((v) => h("option", { value: v }, v)));
  const applyBtn = h("button", { type: "submit", class: "btn btn-small", id: "fe-apply" }, "Build / load");
  const modelInfo = h("p", { class: "small muted", id: "fe-model-info", "aria-live": "polite" });
  const modelForm = h("form", { class: "stack", id: "fe-model-form", onsubmit: (e) => {
    e.preventDefault();
    params.element_size_m = sizeIn.value;
    params.cutoff_hz = cutoffIn.value;
    params.reduction = reductionSel.value;
    calibrateTo = ""; // "Build / load" is the default body; "Build calibrated" the calibrated one
    saveQuery();
    loadFromService();
  } },
  h("label", { for: "fe-element-size" }, "Element size (m)", sizeIn),
  h("label", { for: "fe-cutoff" }, "Cut-off frequency (Hz)", cutoffIn),
  h("label", { for: "fe-reduction" }, "Reduction", reductionSel),
  h("div", { class: "actions" }, applyBtn), modelInfo);
  cached("schema", api.scenarioSchema).then((schema) => {
    const props = schema?.$defs?.BodyModel?.properties || {};
    for (const [input, name] of [[sizeIn, "element_size_m"], [cutoffIn, "cutoff_hz"]]) {
      const p = props[name] || {};
      if (p.minimum !== undefined || p.exclusiveMinimum !== undefined) input.min = String(p.minimum ?? p.exclusiveMinimum);
      if (p.maximum !== undefined) input.max = String(p.maximum);
      if (!input.value && p.default !== undefined) input.value = String(p.default);
    }
    if (Array.isArray(props.reduction?.enum)) {
      const keep = reductionSel.value;
      setChildren(reductionSel, props.reduction.enum.map((v) => h("option", { value: v }, v)));
      reductionSel.value = params.reduction || (state.mesh ? keep : props.reduction.default || keep);
    }
  }).catch(() => { /* the server checks the values */ });
  // -- pairing of the modes with calibration targets ------------------------------------------
  const targetsIn = h("input", { id: "fe-targets", type: "text", value: ctx.query.targets || "", placeholder: "5.03:torsion,6.11:rhombic,8.84:first vertical bending", "aria-describedby": "fe-targets-help fe-targets-err", style: { width: "100%", maxWidth: "40em" } });
  const targetsErr = h("span", { class: "field-error from-server", id: "fe-targets-err", "aria-live": "polite" });
  const pairingOut = h("div", { id: "fe-pairing", "aria-live": "polite" });
  const pairBtn = h("button", { type: "submit", class: "btn btn-small", id: "fe-pair" }, "Pair");
  const calibrateBtn = h("button", { type: "button", class: "btn btn-small", id: "fe-calibrate", "aria-describedby": "fe-calibrate-help", onclick: () => buildCalibrated() }, "Build calibrated");
  const calibrationOut = h("p", { class: "small muted", id: "fe-calibration", "aria-live": "polite" });
  const pairForm = h("form", { class: "stack", id: "fe-pairing-form", onsubmit: (e) => { e.preventDefault(); pairModes(); } },
    h("label", { for: "fe-targets" }, "Calibration targets (Hz[:type], …)", targetsIn, targetsErr),
    h("p", { class: "help", id: "fe-targets-help" }, "Each target is paired with one of the model's lowest modes: a typed target only with a mode of its type (as the classifier names it), an untyped one with the nearest free mode; as flexride fe calibrate pairs them."),
    h("p", { class: "help", id: "fe-calibrate-help" }, "“Build calibrated” builds the car body calibrated to these targets (its panel sections and mass split updated so the paired modes meet them, as bodies.carbody.calibration does in a scenario): a job on the server, at most 30 FE evaluations (about 0.4 s each at 0.5 m elements, 5 s at 0.2 m), once per set of targets."),
    h("div", { class: "actions" }, pairBtn, calibrateBtn), calibrationOut, pairingOut);

  /** Build (or load) the car body calibrated to the targets typed in, then pair its modes. */
  function buildCalibrated() {
    targetsErr.textContent = "";
    targetsIn.removeAttribute("aria-invalid");
    const targets = targetsIn.value.trim();
    if (!targets) {
      targetsErr.textContent = "Type the targets to calibrate to, e.g. 6.5:rhombic,5.59:first vertical bending.";
      targetsIn.setAttribute("aria-invalid", "true");
      return;
    }
    calibrateTo = targets;
    saveQuery();
    loadFromService();
  }

  /** A 422 at one of the query's target parameters shown at the targets' field; true if so. */
  function targetsError(err) {
    const at = err.items?.find((i) => ["query.targets", "query.calibration_targets"].includes((i.loc || []).join(".")));
    if (!at) return false;
    targetsErr.textContent = at.msg;
    targetsIn.setAttribute("aria-invalid", "true");
    return true;
  }

  /** What the model block says about the car body's calibration (or that it is the default). */
  function showCalibration(cal) {
    if (!cal) {
      calibrationOut.textContent = state.kind === "carbody" ? "The default car body (calibrated to paper Table 1 once, fem/defaults.py)." : "";
      return;
    }
    const pairs = cal.pairs.map((p) => `${fmt(p.target_hz, 4)} Hz ${p.target_type || "any"} → mode ${p.mode} ${fmt(p.model_hz, 4)} Hz (${p.error >= 0 ? "+" : ""}${fixed(100 * p.error, 1)} %)`).join("; ");
    const values = Object.entries(cal.values).map(([k, v]) => `${k} ${fmt(cal.initial[k], 4)} → ${fmt(v, 4)}`).join(", ");
    calibrationOut.textContent = `Calibrated car body (to ${cal.targets}; ${cal.n_evaluations} of at most ${cal.max_evaluations} FE evaluations${cal.from_cache ? ", from the FE cache" : ""}; ${cal.success ? "all" : "not all"} within ±${fixed(100 * cal.tolerance, 0)} %): ${pairs}. Values: ${values}.`;
  }

  /** The pairing of the service's model (by its parameters) with the targets typed in. */
  async function pairModes() {
    targetsErr.textContent = "";
    targetsIn.removeAttribute("aria-invalid");
    const targets = targetsIn.value.trim();
    saveQuery();
    if (!targets) {
      setChildren(pairingOut);
      return;
    }
    setChildren(pairingOut, h("p", { class: "help" }, "Pairing…"));
    try {
      const r = await api.fePairing({ ...modelQuery(), targets }, { signal: ctx.signal });
      if (r.status === 202) {
        setChildren(pairingOut, h("p", { class: "help" }, "The model is being built; pair again once it is drawn."));
        return;
      }
      showPairing(r.body);
    } catch (err) {
      if (ctx.signal.aborted) return;
      if (targetsError(err)) setChildren(pairingOut);
      else setChildren(pairingOut, notice("error", "No pairing", err.message));
    }
  }

  function showPairing(body) {
    const rows = body.pairs.map((p) => ({ ...p, errorPct: p.error === null ? null : 100 * p.error }));
    const unpaired = rows.filter((p) => p.mode === null);
    setChildren(pairingOut,
      dataTable([
        { key: "target_hz", label: "Target (Hz)", num: true, format: (v) => fmt(v, 4) },
        { key: "target_type", label: "Type wanted", format: (v) => v || "any" },
        { key: "mode", label: "Mode", num: true, format: (v) => (v === null ? "none" : String(v)) },
        { key: "model_hz", label: "Model (Hz)", num: true, format: (v) => (v === null ? "–" : fmt(v, 4)) },
        { key: "errorPct", label: "Error (%)", num: true, format: (v) => (v === null ? "–" : fixed(v, 1)) },
        { key: "model_type", label: "Model mode type", format: (v) => v || "–" },
      ], rows, { caption: `Targets paired with the lowest ${body.modes_considered} elastic modes` }),
      ...unpaired.map((p) => notice("warn", `${fmt(p.target_hz, 4)} Hz not paired`, p.message)));
  }

  function showParams(m, fromJob) {
    sizeIn.value = String(m.element_size_m);
    cutoffIn.value = String(m.cutoff_hz);
    reductionSel.value = m.reduction;
    for (const el of [sizeIn, cutoffIn, reductionSel, applyBtn]) el.disabled = !!fromJob;
  }
  if (params.element_size_m) sizeIn.value = params.element_size_m;
  if (params.cutoff_hz) cutoffIn.value = params.cutoff_hz;
  if (params.reduction) reductionSel.value = params.reduction;

  function amplitude() {
    // slider 0–1 → largest displacement 0–8 % of the body's size
    const m = state.mesh;
    if (!m) return 0;
    const ext = [0, 1, 2].map((a) => {
      let lo = Infinity;
      let hi = -Infinity;
      for (const p of m.nodes) { lo = Math.min(lo, p[a]); hi = Math.max(hi, p[a]); }
      return hi - lo;
    });
    return Number(scaleIn.value) * 0.08 * Math.max(...ext);
  }

  function geometry(factor) {
    const m = state.mesh;
    const md = m.modes[state.mode];
    const x = new Array(m.nodes.length);
    const y = new Array(m.nodes.length);
    const z = new Array(m.nodes.length);
    const mag = new Array(m.nodes.length);
    for (let i = 0; i < m.nodes.length; i++) {
      const p = m.nodes[i];
      const d = md ? md.disp[i] : [0, 0, 0];
      x[i] = p[0] + factor * d[0];
      y[i] = p[1] + factor * d[1];
      z[i] = p[2] + factor * d[2];
      mag[i] = Math.hypot(d[0], d[1], d[2]);
    }
    return { x, y, z, mag };
  }

  function wireframe(g) {
    const m = state.mesh;
    const X = [];
    const Y = [];
    const Z = [];
    const seg = (a, b) => { X.push(g.x[a], g.x[b], null); Y.push(g.y[a], g.y[b], null); Z.push(g.z[a], g.z[b], null); };
    for (const q of m.quads) { seg(q[0], q[1]); seg(q[1], q[2]); seg(q[2], q[3]); seg(q[3], q[0]); }
    for (const t of m.tris) { seg(t[0], t[1]); seg(t[1], t[2]); seg(t[2], t[0]); }
    for (const b of m.beams) seg(b[0], b[1]);
    return { X, Y, Z };
  }

  function traces(factor) {
    const m = state.mesh;
    const g = geometry(factor);
    const I = [];
    const J = [];
    const K = [];
    for (const q of m.quads) { I.push(q[0], q[0]); J.push(q[1], q[2]); K.push(q[2], q[3]); }
    for (const t of m.tris) { I.push(t[0]); J.push(t[1]); K.push(t[2]); }
    const md = m.modes[state.mode];
    const out = [];
    if (I.length) {
      out.push({
        type: "mesh3d", x: g.x, y: g.y, z: g.z, i: I, j: J, k: K, intensity: g.mag, colorscale: "Viridis", cmin: 0, cmax: 1,
        showscale: !!md, colorbar: { title: { text: "relative |u|" }, len: 0.6 }, flatshading: true,
        lighting: { ambient: 0.7, diffuse: 0.6, specular: 0.05 }, name: "shell", hovertemplate: "x %{x:.2f} m, y %{y:.2f} m, z %{z:.2f} m<extra></extra>",
        opacity: 1,
      });
    }
    if (state.wire || !I.length) {
      const w = wireframe(g);
      out.push({ type: "scatter3d", mode: "lines", x: w.X, y: w.Y, z: w.Z, line: { color: "#1f2933", width: 1 }, hoverinfo: "skip", name: "edges", opacity: 0.5 });
    }
    return out;
  }

  function layout3d() {
    return {
      margin: { l: 0, r: 0, t: 0, b: 0 }, showlegend: false, uirevision: "mesh", paper_bgcolor: "#fff",
      scene: {
        aspectmode: "data",
        xaxis: { title: { text: "x (m)" } }, yaxis: { title: { text: "y (m)" } }, zaxis: { title: { text: "z (m)" } },
        camera: { eye: { x: 0.9, y: -2.1, z: 0.9 } },
      },
    };
  }

  async function drawMesh() {
    if (!state.mesh) return;
    const md = state.mesh.modes[state.mode];
    await card.draw(traces(md ? amplitude() : 0), layout3d());
    scaleOut.textContent = md ? `largest displacement ${fmt(amplitude(), 2)} m (exaggerated)` : "";
    card.setNote(md ? `Mode ${md.index}: ${fmt(md.frequency, 4)} Hz${md.label ? ` – ${md.label}` : ""}. Colour: displacement relative to the mode's largest.` : `${state.mesh.nodes.length} nodes, ${state.mesh.quads.length + state.mesh.tris.length} shell elements, ${state.mesh.beams.length} beams. No mode shapes in this file.`);
  }

  function stopAnim() {
    animLoop = null;
  }

  async function animate() {
    stopAnim();
    if (!state.animate || !state.mesh?.modes.length) return;
    const Plotly = await loadPlotly();
    const run = {};
    animLoop = run; // the current loop; stopAnim() replaces it
    const t0 = performance.now();
    const meshIdx = card.plotEl.data?.findIndex((t) => t.type === "mesh3d");
    const wireIdx = card.plotEl.data?.findIndex((t) => t.type === "scatter3d");
    // one frame after the other (no backlog when rendering is slow, e.g. software WebGL)
    while (animLoop === run && state.animate && card.el.isConnected) {
      const f = amplitude() * Math.sin(((performance.now() - t0) / 1000) * 2 * Math.PI * 0.6);
      const g = geometry(f);
      const idx = [];
      const upd = { x: [], y: [], z: [] };
      if (meshIdx >= 0) { idx.push(meshIdx); upd.x.push(g.x); upd.y.push(g.y); upd.z.push(g.z); }
      if (wireIdx >= 0) { const w = wireframe(g); idx.push(wireIdx); upd.x.push(w.X); upd.y.push(w.Y); upd.z.push(w.Z); }
      if (!idx.length) break;
      await Plotly.restyle(card.plotEl, upd, idx);
      await new Promise((r) => setTimeout(r, 60));
    }
  }
  cleanups.push(stopAnim);

  function showModes() {
    const m = state.mesh;
    if (!m.modes.length) {
      setChildren(modeList, h("p", { class: "help" }, "This file has no mode shapes."));
      return;
    }
    setChildren(modeList, m.modes.map((md, k) => h("button", {
      type: "button", class: "btn btn-small", "aria-pressed": String(k === state.mode),
      onclick: async () => {
        state.mode = k;
        for (const b of modeList.querySelectorAll("button")) b.setAttribute("aria-pressed", String(b === modeList.children[k]));
        await drawMesh();
        animate();
      },
    }, `${md.index}. ${fmt(md.frequency, 4)} Hz`, gciNote(md.index), md.label ? h("span", { class: "muted small" }, ` ${md.label}`) : null)));
  }

  /** "±x %": the mode's expected discretisation error (the build's GCI), if the service gave one. */
  function gciNote(index) {
    const g = state.gci.get(index);
    return g === undefined || g === null ? null : h("span", { class: "small gci", title: "Expected discretisation error of the frequency (grid convergence index against a coarser companion mesh)" }, ` ±${fixed(100 * g, g < 0.01 ? 2 : 1)} %`);
  }

  async function useMesh(raw, source) {
    try {
      state.mesh = normaliseMesh(raw);
    } catch (err) {
      setChildren(meshMsg, notice("error", "This is not a mesh file", err.message));
      return;
    }
    state.mode = 0;
    setChildren(meshMsg, notice("info", null, `${source}: ${state.mesh.nodes.length} nodes, ${state.mesh.quads.length + state.mesh.tris.length} shell elements, ${state.mesh.modes.length} mode shapes.`));
    showModes();
    await drawMesh();
    animate();
  }

  /** The job's settings of this body when the job models it as flexible, else null. */
  async function flexibleSettingsOf(jobId, kind) {
    if (!jobId) return null;
    const sc = await cached(`scenario:${jobId}`, () => api.jobScenario(jobId));
    const b = sc?.bodies?.[BODY_FIELD[kind]];
    return b?.model === "flexible" ? b : null;
  }

  /** Ask until the server has the model (200); null when a newer load or leaving the view ends it. */
  async function pollModel(fetcher, seq, label) {
    for (;;) {
      const r = await fetcher();
      if (seq !== loadSeq || ctx.signal.aborted) return null;
      if (r.status !== 202) return r.body;
      const b = r.body || {};
      const wait = Math.min(10, Math.max(1, r.retryAfter || b.retry_after_s || 3));
      // queued: the build job waits for a free worker (simulations and other builds share them)
      const what = b.status === "queued" ? `Waiting for a free worker to build the FE model of the ${label}` : `Building the FE model of the ${label}`;
      card.loading(`${what} on the server…`);
      const est = buildEstimate(state.kind, b.parameters?.element_size_m ?? params.element_size_m);
      setChildren(meshMsg, waitNote({
        id: "fe-building", title: "Building the FE model – first time only",
        text: `${what}: shell mesh, eigenmodes and the reduction to ${MAX_MODES} mode shapes. The model is kept, so this happens once per parameter set; checking again in ${wait} s`,
        elapsed_s: b.elapsed_s ?? 0, estimate_s: b.status === "queued" ? null : est, progress: b.status === "queued" ? null : b.progress ?? null,
        label: "FE model build",
      }));
      await sleep(wait * 1000, ctx.signal);
      if (seq !== loadSeq || ctx.signal.aborted) return null;
    }
  }

  async function loadFromService() {
    stopAnim();
    const seq = ++loadSeq;
    const kind = state.kind;
    const jobId = jobSel ? jobSel.value : (ctx.query.job || "");
    card.loading(`Loading the ${KIND_LABEL[kind]} FE model…`);
    setChildren(meshMsg);
    try {
      let jobBody = null;
      try {
        jobBody = await flexibleSettingsOf(jobId, kind);
      } catch { /* no such job: the model by its parameters */ }
      if (seq !== loadSeq) return;
      const calibrated = !jobBody && kind === "carbody" && !!calibrateTo;
      const label = jobBody ? `${KIND_LABEL[kind]} of job ${jobId.slice(0, 8)}` : calibrated ? `calibrated ${KIND_LABEL[kind]}` : KIND_LABEL[kind];
      const fetcher = jobBody
        ? () => api.jobFeModel(jobId, kind, { max_modes: MAX_MODES }, { signal: ctx.signal })
        : () => api.feModel(kind, modelQuery(), { signal: ctx.signal });
      const m = await pollModel(fetcher, seq, label);
      if (m === null) return;
      const info = m.model || {};
      showParams(info, !!jobBody);
      const src = jobBody ? `The flexible ${label}` : `The ${label} model`;
      showCalibration(info.calibration);
      const disc = info.discretisation;
      state.gci = new Map((disc?.modes || []).map((d) => [d.index, d.gci]));
      modelInfo.textContent = `${src}: ${info.reduction} reduction, cut-off ${fmt(info.cutoff_hz)} Hz, element size ${fmt(info.element_size_m)} m; ${info.n_elastic_modes} elastic modes retained.` +
        (disc ? ` ± per mode: its frequency's expected discretisation error (GCI against a ${fmt(disc.companion_element_size_m)} m companion mesh, order ${fmt(disc.assumed_order)} assumed).` : "") +
        (jobId && !jobBody ? ` Job ${jobId.slice(0, 8)} models the ${KIND_LABEL[kind]} as rigid.` : "");
      await useMesh(m, jobBody ? `Job ${jobId.slice(0, 8)} (flexible ${KIND_LABEL[kind]})` : `From the service (${KIND_LABEL[kind]})`);
      // the pairing is of models by their parameters (a job's body is fitted to its own vehicle)
      const pairable = !jobBody && kind === "carbody";
      for (const el of [targetsIn, pairBtn, calibrateBtn]) el.disabled = !pairable;
      if (!pairable) setChildren(pairingOut, h("p", { class: "help" }, "Pairing is for car-body models by their parameters (the classifier's mode types are the car body's): choose the car body and no job."));
      else if (targetsIn.value.trim()) pairModes();
    } catch (err) {
      if (seq !== loadSeq || ctx.signal.aborted) return;
      if (calibrateTo && targetsError(err)) calibrationOut.textContent = "";
      card.error(err, calibrateTo ? "The calibrated FE model could not be built" : "The FE model could not be loaded");
      setChildren(meshMsg, notice("info", "A mesh file works too",
        h("p", {}, "Export one and load it with “Load mesh JSON…”:"), h("pre", { class: "mono" }, `flexride fe export ${kind} --out ${kind}.json`)));
      setChildren(modeList, h("p", { class: "help" }, "No mesh loaded."));
    }
  }

  fileIn.addEventListener("change", async () => {
    const f = fileIn.files?.[0];
    if (!f) return;
    fileIn.value = "";
    loadSeq += 1; // a file replaces whatever the service is still building
    for (const el of [sizeIn, cutoffIn, reductionSel, applyBtn]) el.disabled = false;
    modelInfo.textContent = `Showing the file ${f.name}; “Build / load” shows the service's model again.`;
    state.gci = new Map();
    try {
      await useMesh(JSON.parse(await f.text()), f.name);
    } catch (err) {
      setChildren(meshMsg, notice("error", "The file could not be read", err.message));
    }
  });
  scaleIn.addEventListener("input", () => { if (!state.animate) drawMesh(); else scaleOut.textContent = `largest displacement ${fmt(amplitude(), 2)} m (exaggerated)`; });
  animBox.addEventListener("change", () => { state.animate = animBox.checked; if (state.animate) animate(); else { stopAnim(); drawMesh(); } });
  wireBox.addEventListener("change", async () => { state.wire = wireBox.checked; stopAnim(); await drawMesh(); animate(); });
  card.setControls(h("div", { class: "controls" },
    kindSel,
    h("label", { class: "btn", for: "mesh-file" }, "Load mesh JSON…"), fileIn,
    h("label", { for: "mode-scale" }, "Deformation scale", scaleIn, scaleOut),
    h("label", { class: "check" }, animBox, "Animate"),
    h("label", { class: "check" }, wireBox, "Edges")));

  // -- comfort map ---------------------------------------------------------------------------------
  const mapCard = plotCard({ title: "Comfort map over the floor", id: "plot-comfort-map", description: "Comfort measure at every point of the floor grid", height: 340,
    csv: () => lastMap && ({ header: ["point", "x (m)", "y (m)", lastMap.label], rows: lastMap.rows }) });
  let lastMap = null;
  let jobSel = null;
  const mapMsg = h("div");
  const MEASURES = [
    ["wz", "Sperling W vertical (–)", "W (–)"], ["wy", "Sperling W lateral (–)", "W (–)"],
    ["awz", "a_w vertical (m/s²)", "a_w (m/s²)"], ["awy", "a_w lateral (m/s²)", "a_w (m/s²)"],
    ["pz", "peak |a| vertical (m/s²)", "|a| (m/s²)"], ["py", "peak |a| lateral (m/s²)", "|a| (m/s²)"],
  ];
  let measure = ctx.query.measure || "wz";

  const jobsById = new Map();
  async function drawMap(jobId) {
    lastMap = null;
    setChildren(mapMsg);
    if (!jobId) {
      mapCard.empty("Choose a job.");
      return;
    }
    const job = jobsById.get(jobId);
    if (job && !job.has_results) {
      mapCard.empty(`Job ${jobId.slice(0, 8)} is ${job.status}: the comfort map needs its results.`);
      return;
    }
    mapCard.loading("Loading the run's summary…");
    try {
      const [sum, chans] = await Promise.all([cached(`summary:${jobId}`, () => api.summary(jobId)), cached(`channels:${jobId}`, () => api.channels(jobId))]);
      const pts = sum.summary?.points || {};
      const grid = floorGridOf(chans.points);
      if (!grid.n || !(chans.points || []).some((p) => p.kind === "grid" && pts[p.name])) {
        mapCard.empty("This run did not record the floor grid.");
        setChildren(mapMsg, notice("info", null, "Set Outputs → floor grid spacing (output.floor_grid_spacing_m, e.g. 1.0 m) and run again: ", h("a", { href: `#/new?from=${jobId}` }, "new job from this one"), "."));
        return;
      }
      const value = (p) => {
        const d = pts[p]?.directions;
        if (!d) return null;
        switch (measure) {
          case "wz": return sperlingOf(d.z).value;
          case "wy": return sperlingOf(d.y).value;
          case "awz": return awOf(d.z).value;
          case "awy": return awOf(d.y).value;
          case "pz": return d.z?.peaks?.max_abs ?? null;
          case "py": return d.y?.peaks?.max_abs ?? null;
          default: return null;
        }
      };
      const z = grid.ys.map((y) => grid.xs.map((x) => value(grid.name(x, y))));
      const rows = [];
      grid.xs.forEach((x) => grid.ys.forEach((y) => { const n = grid.name(x, y); if (n) rows.push([n, x, y, value(n)]); }));
      const label = MEASURES.find(([k]) => k === measure)[1];
      lastMap = { rows, label };
      // the paper's floor points where the server says they are
      const named = (chans.points || []).filter((p) => p.body === "carbody" && p.kind === "paper" && p.on_floor && pts[p.name]);
      const short = MEASURES.find(([k]) => k === measure)[2];
      await mapCard.draw([
        { type: "heatmap", x: grid.xs, y: grid.ys, z, colorscale: "YlOrRd", reversescale: true, zsmooth: grid.ys.length > 1 ? "best" : false,
          colorbar: { title: { text: prettyUnit(short) } }, hovertemplate: `x = %{x:.2f} m, y = %{y:.2f} m<br>${label}: %{z:.3f}<extra></extra>` },
        { type: "scatter", mode: "markers", x: named.map((p) => p.x), y: named.map((p) => p.y), text: named.map((p) => `${p.description} (x ${fmt(p.x, 3)} m, y ${fmt(p.y, 3)} m)<br>${label}: ${fixed(value(p.name), 2)}`),
          marker: { color: "#0b4f8a", size: 9, symbol: "x" }, name: "paper points", hovertemplate: "%{text}<extra></extra>" },
      ], baseLayout("Position along the car body x (m)", "Lateral position y (m)", {
        yaxis: { scaleanchor: "x", scaleratio: 1 }, showlegend: false,
        annotations: named.map((p) => ({ x: p.x, y: p.y, text: `${p.name} ${fixed(value(p.name), 2)}`, showarrow: false, yshift: 14, font: { size: 11, color: "#1f2933" }, bgcolor: "rgba(255,255,255,.85)" })),
      }));
      const vals = rows.map((r) => r[3]).filter((v) => v !== null);
      const worst = rows.reduce((a, r) => (r[3] !== null && (a === null || r[3] > a[3]) ? r : a), null);
      const spacing = grid.xs.length > 1 ? grid.xs[1] - grid.xs[0] : null;
      mapCard.setNote(`${label} on the floor grid (${rows.length} points${spacing ? `, ${fmt(spacing)} m apart along the body` : ""}, floor at ${fmt(grid.z)} m). Range ${fmt(Math.min(...vals), 3)}–${fmt(Math.max(...vals), 3)}; largest at ${worst?.[0]} (x = ${fmt(worst?.[1])} m, y = ${fmt(worst?.[2])} m).`);
    } catch (err) {
      mapCard.error(err, "No comfort map");
    }
  }

  const jobBox = h("div", { class: "controls", id: "flex-job-controls" });
  main.append(h("h1", {}, "Flexible body"), jobBox,
    h("div", { class: "three" }, h("section", { class: "card stack", "aria-labelledby": "modes-title" },
      h("h2", { id: "fe-model-title", class: "h3", style: { marginTop: 0 } }, "Model"), modelForm,
      h("h2", { id: "modes-title", class: "h3" }, "Mode shapes"), modeList),
    h("div", {}, meshMsg, card.el)),
    h("section", { class: "card stack", "aria-labelledby": "pairing-title" },
      h("h2", { id: "pairing-title", class: "h3", style: { marginTop: 0 } }, "Modes paired with calibration targets"), pairForm),
    h("h2", {}, "Comfort over the floor"), mapMsg, mapCard.el);

  // jobs: the flexible body of the chosen job (when it has one) and its comfort map
  try {
    const page = await api.jobs({ status: "succeeded", limit: 200 }, { signal: ctx.signal });
    const jobs = page.items.filter((j) => j.has_results);
    const want = ctx.query.job && jobs.some((j) => j.id === ctx.query.job) ? ctx.query.job : jobs[0]?.id || "";
    const jobLabel = (j) => `${j.name} (${j.id.slice(0, 6)})`;
    if (ctx.query.job && !jobs.some((j) => j.id === ctx.query.job)) {
      try {
        jobs.unshift(await api.job(ctx.query.job));
      } catch { /* ignore */ }
    }
    for (const j of jobs) jobsById.set(j.id, j);
    const sel = simpleSelect("flex-job", "Job", [["", "none (model by its parameters)"], ...jobs.map((j) => [j.id, jobLabel(j)])], ctx.query.job || want,
      (v) => { saveQuery(); drawMap(v); loadFromService(); });
    jobSel = sel.querySelector("select");
    setChildren(jobBox, sel, h("p", { class: "help" }, "A job whose car body or frames are flexible shows its own FE model; the comfort map needs a run that recorded the floor grid."));
    mapCard.setControls(h("div", { class: "controls" },
      simpleSelect("map-measure", "Measure", MEASURES.map(([k, l]) => [k, l]), measure, (v) => { measure = v; saveQuery(); drawMap(jobSel.value); })));
    if (jobSel.value) drawMap(jobSel.value);
    else mapCard.empty(jobs.length ? "Choose a job." : "No finished job yet.");
  } catch (err) {
    if (!ctx.signal.aborted) mapCard.error(err, "Could not list the jobs");
  }
  if (ctx.signal.aborted) return undefined;
  loadFromService();
  return () => cleanups.forEach((f) => f());
}
