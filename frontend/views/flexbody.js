// Flexible body: the car-body (or frame) FE mesh in 3D with its mode shapes (scaled or animated,
// frequency list), and a comfort map over the floor of a run that recorded the floor grid.
//
// Mesh source: GET /api/v1/fe/{kind} when the service has it, else a JSON file written by
// `flexride fe export carbody --out carbody.json`. Both shapes are read:
//   export_mesh: {nodes, quads, beams, modes: [{index, frequency_hz, classification, scale_m, displacements}]}
//   plain:       {nodes: [[x,y,z]], elements: [[i,j,k,l]], frequencies: [f], modes: [[[dx,dy,dz]]]}

import { api, cached, isMissingEndpoint } from "../api.js";
import { h, setChildren, notice, fmt, fixed, prettyUnit } from "../components/dom.js";
import { plotCard, baseLayout, loadPlotly } from "../components/plot.js";
import { simpleSelect } from "../components/channels.js";
import { replaceQuery } from "../components/nav.js";
import { sperlingOf, awOf } from "./job.js";

// Floor grid of flexride.vehicle.topology.floor_grid (names F<i>_<j>).
const FLOOR_HALF_LENGTH = 9.0;
const FLOOR_HALF_WIDTH = 1.2;

export function floorGrid(spacing) {
  const lin = (a, b, n) => (n === 1 ? [a] : Array.from({ length: n }, (_, i) => a + ((b - a) * i) / (n - 1)));
  const nx = Math.floor((2 * FLOOR_HALF_LENGTH) / spacing + 1e-9) + 1;
  const ny = Math.floor((2 * FLOOR_HALF_WIDTH) / spacing + 1e-9) + 1;
  const xs = lin(-FLOOR_HALF_LENGTH, FLOOR_HALF_LENGTH, nx);
  const ys = ny > 1 ? lin(-FLOOR_HALF_WIDTH, FLOOR_HALF_WIDTH, ny) : [0];
  return { xs, ys, name: (i, j) => `F${i}_${j}` };
}

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
  const state = { kind: ctx.query.kind || "carbody", mode: 0, scale: 0, animate: false, mesh: null, wire: true };
  let animLoop = null;
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
  const kindSel = simpleSelect("mesh-kind", "Body", [["carbody", "car body"], ["frame", "bogie frame"]], state.kind, (v) => { state.kind = v; replaceQuery({ kind: v, job: jobSel?.value || "" }); loadFromService(); });

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
    }, `${md.index}. ${fmt(md.frequency, 4)} Hz`, md.label ? h("span", { class: "muted small" }, ` ${md.label}`) : null)));
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

  async function loadFromService() {
    stopAnim();
    card.loading(`Computing the ${state.kind} mesh and modes on the server (can take a while)…`);
    try {
      const m = await cached(`fe:${state.kind}`, () => api.feMesh(state.kind, { n_modes: 12 }));
      await useMesh(m, `From the service (${state.kind})`);
    } catch (err) {
      if (isMissingEndpoint(err)) {
        card.empty("Load a mesh file to see the body and its mode shapes.");
        setChildren(meshMsg, notice("info", "The service does not serve FE meshes yet",
          h("p", {}, "Export one and load it here:"), h("pre", { class: "mono" }, `flexride fe export ${state.kind} --out ${state.kind}.json`)));
        setChildren(modeList, h("p", { class: "help" }, "No mesh loaded."));
      } else card.error(err, "The mesh could not be loaded");
    }
  }

  fileIn.addEventListener("change", async () => {
    const f = fileIn.files?.[0];
    if (!f) return;
    fileIn.value = "";
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

  async function drawMap(jobId) {
    lastMap = null;
    setChildren(mapMsg);
    if (!jobId) {
      mapCard.empty("Choose a job.");
      return;
    }
    mapCard.loading("Loading the run's summary…");
    try {
      const [sum, sc] = await Promise.all([cached(`summary:${jobId}`, () => api.summary(jobId)), api.jobScenario(jobId)]);
      const spacing = sc?.output?.floor_grid_spacing_m;
      const pts = sum.summary?.points || {};
      if (!spacing || !Object.keys(pts).some((p) => /^F\d+_\d+$/.test(p))) {
        mapCard.empty("This run did not record the floor grid.");
        setChildren(mapMsg, notice("info", null, "Set Outputs → floor grid spacing (output.floor_grid_spacing_m, e.g. 1.0 m) and run again: ", h("a", { href: `#/new?from=${jobId}` }, "new job from this one"), "."));
        return;
      }
      const grid = floorGrid(spacing);
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
      const z = grid.ys.map((_, j) => grid.xs.map((__, i) => value(grid.name(i, j))));
      const rows = [];
      grid.xs.forEach((x, i) => grid.ys.forEach((y, j) => rows.push([grid.name(i, j), x, y, value(grid.name(i, j))])));
      const label = MEASURES.find(([k]) => k === measure)[1];
      lastMap = { rows, label };
      const lc = (sc.vehicle?.geometry?.bogie_centre_spacing ?? 12.6) / 2;
      const ys = sc.vehicle?.geometry?.secondary_lateral_half_spacing ?? 0.95;
      const named = [["PFB", lc, 0], ["PC", 0, 0], ["PRB", -lc, 0], ["PLA", -lc, ys], ["PRA", -lc, -ys]].filter(([p]) => pts[p]);
      const short = MEASURES.find(([k]) => k === measure)[2];
      await mapCard.draw([
        { type: "heatmap", x: grid.xs, y: grid.ys, z, colorscale: "YlOrRd", reversescale: true, zsmooth: grid.ys.length > 1 ? "best" : false,
          colorbar: { title: { text: prettyUnit(short) } }, hovertemplate: `x = %{x:.2f} m, y = %{y:.2f} m<br>${label}: %{z:.3f}<extra></extra>` },
        { type: "scatter", mode: "markers", x: named.map((n) => n[1]), y: named.map((n) => n[2]), text: named.map((n) => `${n[0]} ${fixed(value(n[0]), 2)}`),
          marker: { color: "#0b4f8a", size: 9, symbol: "x" }, name: "paper points", hovertemplate: "%{text}<extra></extra>" },
      ], baseLayout("Position along the car body x (m)", "Lateral position y (m)", {
        yaxis: { scaleanchor: "x", scaleratio: 1 }, showlegend: false,
        annotations: named.map((n) => ({ x: n[1], y: n[2], text: `${n[0]} ${fixed(value(n[0]), 2)}`, showarrow: false, yshift: 14, font: { size: 11, color: "#1f2933" }, bgcolor: "rgba(255,255,255,.85)" })),
      }));
      const vals = rows.map((r) => r[3]).filter((v) => v !== null);
      const worst = rows.reduce((a, r) => (r[3] !== null && (a === null || r[3] > a[3]) ? r : a), null);
      mapCard.setNote(`${label} on a ${fmt(spacing)} m grid (${rows.length} points, floor at ${fmt(sc.output.floor_height_m)} m). Range ${fmt(Math.min(...vals), 3)}–${fmt(Math.max(...vals), 3)}; largest at ${worst?.[0]} (x = ${fmt(worst?.[1])} m, y = ${fmt(worst?.[2])} m).`);
    } catch (err) {
      mapCard.error(err, "No comfort map");
    }
  }

  main.append(h("h1", {}, "Flexible body"),
    h("div", { class: "three" }, h("section", { class: "card", "aria-labelledby": "modes-title" }, h("h2", { id: "modes-title", class: "h3", style: { marginTop: 0 } }, "Mode shapes"), modeList),
      h("div", {}, meshMsg, card.el)),
    h("h2", {}, "Comfort over the floor"), mapMsg, mapCard.el);

  // jobs for the comfort map
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
    const sel = simpleSelect("map-job", "Job", jobs.map((j) => [j.id, jobLabel(j)]), ctx.query.job || want, (v) => { replaceQuery({ kind: state.kind, job: v, measure }); drawMap(v); });
    jobSel = sel.querySelector("select");
    mapCard.setControls(h("div", { class: "controls" }, sel,
      simpleSelect("map-measure", "Measure", MEASURES.map(([k, l]) => [k, l]), measure, (v) => { measure = v; replaceQuery({ kind: state.kind, job: jobSel.value, measure }); drawMap(jobSel.value); })));
    if (jobs.length) drawMap(jobSel.value);
    else mapCard.empty("No finished job yet.");
  } catch (err) {
    if (!ctx.signal.aborted) mapCard.error(err, "Could not list the jobs");
  }
  if (ctx.signal.aborted) return undefined;
  loadFromService();
  return () => cleanups.forEach((f) => f());
}
