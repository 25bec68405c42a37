// New study: a base scenario and its axes (speeds, conditions, rigid/flexible, any parameter),
// the paper's studies as one-click presets, and the number of jobs it will create.

import { api, cached } from "../api.js";
import { h, setChildren, notice, errorBox, loading } from "../components/dom.js";
import { plainDescription, unitOf } from "../components/schema.js";
import { parseYamlOrJson } from "../components/yaml.js";
import { go } from "../components/nav.js";

/** The paper's line / excitation conditions (StudyCreate.conditions). */
export const CONDITIONS = [
  ["random-straight", "Random irregularity, straight track"],
  ["random-curve", "Random irregularity, R = 800 m curve"],
  ["corrugation", "Corrugation (short wave)"],
  ["settlement", "Settlement (long wave)"],
];
const MAX_JOBS = 256;

/** Numeric leaf paths of the scenario schema: [{path, label, unit}]. */
export function numericPaths(schema) {
  const defs = schema.$defs || {};
  const out = [];
  const resolve = (n) => (n?.$ref ? { ...defs[n.$ref.split("/").pop()], ...n, $ref: undefined } : n || {});
  function walk(node, path, depth) {
    const r = resolve(node);
    if (depth > 6) return;
    if (r.anyOf) {
      const inner = r.anyOf.find((x) => x.type === "number" || x.type === "integer");
      if (inner) out.push({ path, label: plainDescription(r), unit: unitOf(r) });
      return;
    }
    if (r.type === "number" || r.type === "integer") {
      out.push({ path, label: plainDescription(r), unit: unitOf(r) });
      return;
    }
    if (r.oneOf && r.discriminator) {
      for (const ref of Object.values(r.discriminator.mapping)) walk({ $ref: ref }, path, depth + 1);
      return;
    }
    if (r.properties) for (const [k, v] of Object.entries(r.properties)) walk(v, path ? `${path}.${k}` : k, depth + 1);
  }
  walk(schema, "", 0);
  return [...new Map(out.map((o) => [o.path, o])).values()];
}

/** "50, 60 70" → [50, 60, 70]; throws on bad numbers. */
/**
 * Options of a select from a property of the service's study schema (GET /openapi.json): its
 * `enum` in order, each labelled by the schema's `x-enum-labels`, the default selected.
 */
export function choiceOptions(prop) {
  const labels = prop?.["x-enum-labels"] || {};
  return (prop?.enum || []).map((v) => h("option", { value: v, selected: v === prop.default }, labels[v] || v));
}

/** The largest value an integer property of the schema allows (the integer branch of a nullable one). */
export function schemaMaximum(prop) {
  return (prop?.anyOf || [prop]).find((node) => node?.type === "integer")?.maximum;
}

export function parseList(text, { numeric = true } = {}) {
  const parts = String(text || "").split(/[,;\s]+/).map((x) => x.trim()).filter(Boolean);
  if (!numeric) return parts;
  return parts.map((x) => {
    const v = Number(x);
    if (!Number.isFinite(v)) throw new Error(`"${x}" is not a number`);
    return v;
  });
}

export default async function render(main, ctx) {
  ctx.title("New study");
  main.append(h("h1", {}, "New study"), loading("Loading presets and the scenario schema…"));
  let presets;
  let studyPresets;
  let schema;
  let studyFields;
  try {
    [presets, studyPresets, schema, studyFields] = await Promise.all([
      cached("presets", api.presets), cached("study-presets", api.studyPresets), cached("schema", api.scenarioSchema),
      api.openapi().then((spec) => spec?.components?.schemas?.StudyCreate?.properties || {})]);
  } catch (err) {
    setChildren(main, h("h1", {}, "New study"), errorBox(err, "The study form could not be prepared"));
    return undefined;
  }
  if (ctx.signal.aborted) return undefined;
  const paths = numericPaths(schema);
  const maxSeeds = schemaMaximum(studyFields.seeds) ?? 1; // the service's bound (MAX_SERVICE_SEEDS)

  const msg = h("div", { id: "study-message", "aria-live": "polite" });
  const countEl = h("div", { class: "count-big", id: "study-count", "aria-live": "polite" }, "1");
  const countInfo = h("p", { class: "help", id: "study-count-info" });

  // -- form fields -------------------------------------------------------------------------------
  const name = h("input", { id: "study-name", type: "text", placeholder: "e.g. speeds-random-straight", pattern: "[A-Za-z0-9][A-Za-z0-9 _.+\\-]{0,79}", autocomplete: "off" });
  const desc = h("input", { id: "study-desc", type: "text", autocomplete: "off" });
  const basePreset = h("select", { id: "study-base" }, presets.map((p) => h("option", { value: p.name, selected: p.name === "paper-metro" }, p.name)));
  const baseDesc = h("p", { class: "help" });
  const baseJob = h("input", { id: "study-base-job", type: "text", placeholder: "job id (optional)", autocomplete: "off" });
  const speeds = h("input", { id: "study-speeds", type: "text", value: "50, 60, 70, 80", inputmode: "decimal", "aria-describedby": "study-speeds-err study-speeds-help", autocomplete: "off" });
  const speedsErr = h("div", { class: "field-error", id: "study-speeds-err" });
  const condBoxes = CONDITIONS.map(([v, t]) => h("label", { class: "check" }, h("input", { type: "checkbox", name: "condition", value: v }), `${t} `, h("code", { class: "small" }, v)));
  const modelBoxes = ["rigid", "flexible"].map((m) => h("label", { class: "check" }, h("input", { type: "checkbox", name: "body_model", value: m }), `${m} car body and frames`));
  const paramRows = h("div", { class: "stack", id: "study-params" });
  const seeds = h("input", { id: "study-seeds", type: "text", value: "1", inputmode: "numeric", autocomplete: "off", "aria-describedby": "study-seeds-help study-seeds-err" });
  const seedsErr = h("div", { class: "field-error", id: "study-seeds-err" });
  const section = h("select", { id: "study-section", "aria-describedby": "study-section-help" }, choiceOptions(studyFields.section));
  const cutoff = h("select", { id: "study-cutoff", "aria-describedby": "study-cutoff-help" }, choiceOptions(studyFields.cutoff));
  const duration = h("input", { id: "study-duration", type: "text", inputmode: "decimal", value: "", placeholder: "as in the scenario", "aria-describedby": "study-duration-help study-duration-err", autocomplete: "off" });
  const durationErr = h("div", { class: "field-error", id: "study-duration-err" });
  const extra = h("textarea", { id: "study-overrides", rows: 3, class: "mono", placeholder: "solver.dt: 5.0e-5\nvehicle.carbody.mass: 38000", "aria-describedby": "study-overrides-help study-overrides-err" });
  const extraErr = h("div", { class: "field-error", id: "study-overrides-err" });
  const reuse = h("input", { id: "study-reuse", type: "checkbox", checked: true });
  const datalist = h("datalist", { id: "scenario-paths" }, paths.map((p) => h("option", { value: p.path }, `${p.label}${p.unit ? ` (${p.unit})` : ""}`)));
  const showBaseDesc = () => { baseDesc.textContent = presets.find((p) => p.name === basePreset.value)?.description || ""; };
  basePreset.addEventListener("change", showBaseDesc);
  showBaseDesc();

  function addParam(path = "", values = "") {
    const i = paramRows.children.length;
    const p = h("input", { type: "text", id: `param-path-${i}`, list: "scenario-paths", value: path, placeholder: "vehicle.secondary.kz", autocomplete: "off", oninput: () => { unitEl.textContent = unitOf(p.value); update(); } });
    const v = h("input", { type: "text", id: `param-values-${i}`, value: values, placeholder: "e.g. 300000, 341900, 400000", autocomplete: "off", oninput: update });
    const unitEl = h("span", { class: "unit" }, unitOf(path));
    const err = h("div", { class: "field-error" });
    const row = h("div", { class: "row param-row" },
      h("label", { for: p.id, class: "grow" }, "Parameter (dotted path)", p),
      h("label", { for: v.id, class: "grow" }, h("span", {}, "Values ", unitEl), v),
      h("button", { type: "button", class: "btn btn-small btn-quiet", onclick: () => { row.remove(); update(); } }, "Remove"), err);
    row._get = () => ({ path: p.value.trim(), values: v.value, err, p, v });
    paramRows.append(row);
    update();
    p.focus();
  }
  function unitOf(path) {
    const u = paths.find((x) => x.path === path.trim())?.unit;
    return u ? `(${u})` : "";
  }

  // -- request and count --------------------------------------------------------------------------
  const checked = (boxes) => boxes.map((b) => b.querySelector("input")).filter((i) => i.checked).map((i) => i.value);

  function request() {
    const problems = [];
    const req = { base: {}, reuse: reuse.checked };
    if (name.value.trim()) req.name = name.value.trim();
    if (desc.value.trim()) req.description = desc.value.trim();
    if (baseJob.value.trim()) req._baseJob = baseJob.value.trim();
    else req.base = { preset: basePreset.value };
    speedsErr.textContent = "";
    speeds.removeAttribute("aria-invalid");
    try {
      const sp = parseList(speeds.value);
      const bad = sp.find((v) => !(v > 0 && v <= 200));
      if (bad !== undefined) throw new Error(`${bad} km/h is outside the allowed range (0, 200] km/h`);
      if (new Set(sp).size !== sp.length) throw new Error("speeds must be unique");
      if (sp.length) req.speeds_kmh = sp;
    } catch (e) {
      speedsErr.textContent = e.message;
      speeds.setAttribute("aria-invalid", "true");
      problems.push(["study-speeds", `Speeds: ${e.message}`]);
    }
    const conds = checked(condBoxes);
    if (conds.length) req.conditions = conds;
    const models = checked(modelBoxes);
    if (models.length) req.body_models = models;
    const params = [];
    for (const row of paramRows.children) {
      const r = row._get();
      r.err.textContent = "";
      r.p.removeAttribute("aria-invalid");
      r.v.removeAttribute("aria-invalid");
      if (!r.path && !r.values.trim()) continue;
      if (!r.path) {
        r.err.textContent = "Give the parameter's dotted path.";
        r.p.setAttribute("aria-invalid", "true");
        problems.push([r.p.id, "A parameter has no path"]);
        continue;
      }
      let vals;
      try {
        vals = parseList(r.values);
        if (!vals.length) throw new Error("give at least one value");
      } catch (e) {
        r.err.textContent = `Values: ${e.message}`;
        r.v.setAttribute("aria-invalid", "true");
        problems.push([r.v.id, `${r.path}: ${e.message}`]);
        continue;
      }
      params.push({ path: r.path, values: vals });
    }
    if (params.length) req.parameters = params;
    seedsErr.textContent = "";
    seeds.removeAttribute("aria-invalid");
    const ns = Number(seeds.value.trim() || "1");
    if (!(Number.isInteger(ns) && ns >= 1 && ns <= maxSeeds)) {
      seedsErr.textContent = `Realisations must be a whole number from 1 to ${maxSeeds}`;
      seeds.setAttribute("aria-invalid", "true");
      problems.push(["study-seeds", "Realisations out of range"]);
    } else if (ns > 1) req.seeds = ns;
    if (section.value !== studyFields.section?.default) req.section = section.value;
    if (cutoff.value !== studyFields.cutoff?.default) req.cutoff = cutoff.value;
    const overrides = {};
    durationErr.textContent = "";
    duration.removeAttribute("aria-invalid");
    if (duration.value.trim()) {
      const d = Number(duration.value.trim());
      if (!(d > 0 && d <= 3600)) {
        durationErr.textContent = "Simulated time must be greater than 0 and at most 3600 s";
        duration.setAttribute("aria-invalid", "true");
        problems.push(["study-duration", "Simulated time out of range"]);
      } else {
        overrides.duration_s = d;
        overrides.distance_m = null;
      }
    }
    extraErr.textContent = "";
    extra.removeAttribute("aria-invalid");
    if (extra.value.trim()) {
      try {
        const o = parseYamlOrJson(extra.value);
        if (!o || typeof o !== "object" || Array.isArray(o)) throw new Error("write one \"dotted.path: value\" per line");
        Object.assign(overrides, o);
      } catch (e) {
        extraErr.textContent = e.message;
        extra.setAttribute("aria-invalid", "true");
        problems.push(["study-overrides", `Overrides: ${e.message}`]);
      }
    }
    if (Object.keys(overrides).length) req.overrides = overrides;
    return { req, problems, params };
  }

  function count(req) {
    let n = 1;
    for (const k of ["conditions", "speeds_kmh", "body_models"]) n *= (req[k] || []).length || 1;
    for (const p of req.parameters || []) n *= p.values.length;
    return n * (req.seeds || 1); // at most: a job without a random irregularity runs once
  }

  function update() {
    const { req } = request();
    const n = count(req);
    countEl.textContent = String(n);
    const parts = [
      req.conditions ? `${req.conditions.length} condition${req.conditions.length > 1 ? "s" : ""}` : "the base's line and excitation",
      req.speeds_kmh ? `${req.speeds_kmh.length} speed${req.speeds_kmh.length > 1 ? "s" : ""}` : "the base's speed",
      req.body_models ? `${req.body_models.join(" and ")} model${req.body_models.length > 1 ? "s" : ""}` : "the base's body model",
      ...(req.parameters || []).map((p) => `${p.values.length} × ${p.path}`),
      ...(req.seeds ? [`${req.seeds} irregularity realisations (at most: conditions without a random irregularity run once)`] : []),
    ];
    countInfo.textContent = `${n === 1 ? "job" : "jobs"}: ${parts.join(" × ")}.${n > MAX_JOBS ? ` More than ${MAX_JOBS} (the service's default limit, FLEXRIDE_MAX_STUDY_JOBS).` : ""}`;
    countEl.classList.toggle("fail", n > MAX_JOBS);
    submit.textContent = `Create study (${n} job${n === 1 ? "" : "s"})`;
  }

  function fill(p) {
    const r = p.request;
    name.value = r.name || p.name;
    desc.value = r.description || "";
    if (r.base?.preset) basePreset.value = r.base.preset;
    showBaseDesc();
    baseJob.value = "";
    speeds.value = (r.speeds_kmh || []).join(", ");
    for (const b of condBoxes) b.querySelector("input").checked = (r.conditions || []).includes(b.querySelector("input").value);
    for (const b of modelBoxes) b.querySelector("input").checked = (r.body_models || []).includes(b.querySelector("input").value);
    paramRows.replaceChildren();
    for (const pa of r.parameters || []) addParam(pa.path, pa.values.join(", "));
    seeds.value = String(r.seeds || 1);
    section.value = r.section || studyFields.section?.default;
    cutoff.value = r.cutoff || studyFields.cutoff?.default;
    update();
  }

  function showError(err) {
    const items = err.items || [];
    setChildren(msg, notice("error", "The server rejected the study", h("p", {}, err.message.length < 300 ? err.message : `${items.length} problems:`),
      items.length > 1 ? h("ul", {}, items.map((i) => h("li", {}, h("code", {}, (i.loc || []).filter((x) => x !== "body").join(".") || "study"), `: ${i.msg}`))) : null));
    // mark the inputs the messages name
    for (const i of items) {
      const loc = (i.loc || []).filter((x) => x !== "body").map(String);
      const text = `${loc.join(".")} ${i.msg}`;
      if (/speeds_kmh|speed_kmh/.test(text)) {
        speeds.setAttribute("aria-invalid", "true");
        speedsErr.textContent = i.msg;
      } else if (/duration_s|distance_m/.test(text)) {
        duration.setAttribute("aria-invalid", "true");
        durationErr.textContent = i.msg;
      } else if (loc[0] === "seeds") {
        seeds.setAttribute("aria-invalid", "true");
        seedsErr.textContent = i.msg;
      } else if (loc[0] === "overrides") {
        extra.setAttribute("aria-invalid", "true");
        extraErr.textContent = i.msg;
      }
    }
    msg.querySelector(".notice")?.focus?.();
  }

  async function send(body, btn) {
    btn.disabled = true;
    setChildren(msg, loading("Creating the study and queuing its jobs…"));
    try {
      if (body._baseJob) {
        const sc = await api.jobScenario(body._baseJob);
        body.base = { scenario: sc };
        delete body._baseJob;
      }
      const st = await api.submitStudy(body);
      setChildren(msg, notice("info", "Study created", `${st.n_jobs} jobs queued – opening it…`));
      go(`/studies/${st.id}`);
    } catch (err) {
      showError(err);
    } finally {
      btn.disabled = false;
    }
  }

  const submit = h("button", { type: "submit", class: "btn btn-primary", id: "submit-study" }, "Create study");
  const formEl = h("form", { novalidate: true, oninput: update, onchange: update, onsubmit: (e) => {
    e.preventDefault();
    const { req, problems } = request();
    if (problems.length) {
      setChildren(msg, notice("error", "Fix these first", h("ul", {}, problems.map(([fid, t]) => h("li", {}, h("a", { href: `#${fid}`, onclick: (ev) => { ev.preventDefault(); document.getElementById(fid)?.focus(); } }, t))))));
      document.getElementById(problems[0][0])?.focus();
      return;
    }
    send(req, submit);
  } },
  h("section", { class: "card" }, h("h2", {}, "Study"),
    h("div", { class: "row" },
      h("label", { for: "study-name", class: "grow" }, "Name", name),
      h("label", { for: "study-desc", class: "grow" }, "Description", desc))),
  h("section", { class: "card" }, h("h2", {}, "Base scenario"),
    h("div", { class: "row" },
      h("label", { for: "study-base", class: "grow" }, "Preset", basePreset),
      h("label", { for: "study-base-job" }, "or the scenario of a job", baseJob)),
    baseDesc),
  h("section", { class: "card" }, h("h2", {}, "Axes"),
    h("p", { class: "help" }, "The study runs every combination of the axes. An empty axis keeps the base scenario's value."),
    h("div", { class: "stack" },
      h("label", { for: "study-speeds" }, "Speeds (km/h)", speeds),
      h("p", { class: "help", id: "study-speeds-help" }, "Comma-separated, e.g. 50, 60, 70, 80."), speedsErr,
      h("fieldset", { class: "enumset" }, h("legend", {}, "Line and excitation conditions (paper Table 3)"), h("div", { class: "checks" }, condBoxes)),
      h("fieldset", { class: "enumset" }, h("legend", {}, "Body models (rigid against flexible, paper Table 2)"), h("div", { class: "checks" }, modelBoxes)),
      h("fieldset", { class: "enumset" }, h("legend", {}, "Any parameter"), paramRows, datalist,
        h("button", { type: "button", class: "btn btn-small", onclick: () => addParam() }, "Add parameter")),
      h("label", { for: "study-seeds" }, "Irregularity realisations per condition (seeds)", seeds),
      h("p", { class: "help", id: "study-seeds-help" }, `1–${maxSeeds}. Realisation k draws the random track with each seed + k − 1 (1: the scenario's own); the results show every index as the mean with its 95 % confidence interval (error bars). Conditions without a random irregularity run once.`), seedsErr)),
  h("section", { class: "card" }, h("h2", {}, "For every job"),
    h("div", { class: "stack" },
      h("label", { for: "study-duration" }, "Simulated time per job (s)", duration),
      h("p", { class: "help", id: "study-duration-help" }, "Sets duration_s (and clears distance_m) – a few seconds for a quick look; Sperling indices need at least 5 s."), durationErr,
      h("label", { for: "study-section" }, "Evaluated section of each run", section),
      h("p", { class: "help", id: "study-section-help" }, "Where the indices are taken: the paper report's rules (on a curve every wheelset on the circular arc; on straight track with an excitation from 30 m on, after the random profile's fade-in; a settlement over the whole run), the whole curve, or the whole run. A section shorter than 6 s of the run falls back to the whole run; the study page lists each job's section."),
      h("label", { for: "study-cutoff" }, "Elastic modes of flexible bodies", cutoff),
      h("p", { class: "help", id: "study-cutoff-help" }, "Follow the excitation: each condition's flexible car body and frames keep their modes up to at least 1.5 × its highest excitation frequency V/λ_min, rounded up to 10 Hz (70 Hz for 0.5 m corrugation up to 80 km/h), as the paper report does. As given: the base scenario's cut-off; a job that keeps fewer modes than its excitation drives says so in its notes."),
      h("label", { for: "study-overrides" }, "Other overrides (YAML: dotted.path: value)", extra),
      h("p", { class: "help", id: "study-overrides-help" }, "Applied last to every job."), extraErr,
      h("label", { class: "check" }, reuse, "Reuse stored results of identical scenarios"))),
  h("div", { class: "sticky-actions actions" }, submit, msg));

  /** The paper report preset: its runs are fixed by its plan; only quick and seeds are given. */
  const reportActions = (p) => h("div", { class: "actions", style: { marginTop: "4px" } },
    [[true, "Run quick report"], [false, `Run full report (${p.n_jobs} jobs)`]].map(([quick, label]) => h("button", {
      type: "button", class: `btn btn-small${quick ? " btn-primary" : ""}`, id: quick ? "run-report-quick" : "run-report-full",
      onclick: (e) => {
        const { req } = request();
        send({ preset: p.name, quick, seeds: req.seeds || 1, reuse: reuse.checked }, e.target);
      } }, label)),
    h("p", { class: "help" }, "Uses the realisations (seeds) set in the form; the other fields do not apply."));
  const presetCards = studyPresets.map((p) => h("div", { class: "card", style: { padding: "10px 12px", margin: "0" } },
    h("strong", {}, p.name), h("span", { class: "muted small" }, ` – ${p.n_jobs} jobs`),
    h("p", { class: "help" }, p.description),
    p.request.quick !== undefined ? reportActions(p) : h("div", { class: "actions", style: { marginTop: "4px" } },
      h("button", { type: "button", class: "btn btn-small", "aria-label": `Fill the form with ${p.name}`, onclick: () => { fill(p); setChildren(msg, notice("info", null, `Form filled from ${p.name}; adjust it or create the study.`)); submit.focus(); } }, "Fill the form"),
      h("button", { type: "button", class: "btn btn-small btn-primary", "aria-label": `Run ${p.name} now`, onclick: (e) => {
        const { req } = request();
        const body = { preset: p.name, reuse: reuse.checked };
        if (req.overrides) body.overrides = req.overrides;
        send(body, e.target);
      } }, `Run now (${p.n_jobs} jobs)`))));

  main.replaceChildren(
    h("h1", {}, "New study"),
    h("div", { class: "layout-side" }, formEl,
      h("aside", { class: "side", "aria-label": "Study size and presets" },
        h("section", { class: "card" }, h("h2", {}, "This study creates"), countEl, countInfo),
        h("section", { class: "card" }, h("h2", {}, "One-click presets"),
          h("p", { class: "help" }, "The paper's studies. “Run now” uses the simulated time and overrides set in the form, if any."),
          h("div", { class: "preset-buttons" }, presetCards)))));
  const start = ctx.query.preset && studyPresets.find((p) => p.name === ctx.query.preset);
  if (start) fill(start);
  update();
  return undefined;
}
