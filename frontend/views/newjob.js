// New job: start from a preset (or a job), edit the scenario in a form generated from its JSON
// schema, or paste / upload YAML or JSON; check and submit.

import { api, cached, isMissingEndpoint, ApiError } from "../api.js";
import { h, setChildren, notice, errorBox, loading, tabs, saveFile, slug } from "../components/dom.js";
import { SchemaForm } from "../components/schemaform.js";
import { parseYamlOrJson, toYaml } from "../components/yaml.js";
import { go, replaceQuery } from "../components/nav.js";
import { estimatePanel } from "../components/estimatepanel.js";
import { solverState, compilingText, waitNote } from "../components/waiting.js";

const DEFAULT_PRESET = "paper-random-straight-80";

/** Deep merge for "preset: NAME" scenario files: mappings merge, lists and kinds replace. */
export function mergeScenario(base, over) {
  if (Array.isArray(over) || over === null || typeof over !== "object") return over;
  if (base === null || typeof base !== "object" || Array.isArray(base)) return over;
  if (over.kind !== undefined && base.kind !== undefined && over.kind !== base.kind) return over;
  const out = { ...base };
  for (const [k, v] of Object.entries(over)) out[k] = k in base ? mergeScenario(base[k], v) : v;
  return out;
}

const isObj = (v) => v !== null && typeof v === "object" && !Array.isArray(v);
const same = (a, b) => JSON.stringify(a) === JSON.stringify(b);

/**
 * The dotted-path overrides that turn `base` (a preset's scenario) into `value`: changed leaves
 * by their path; a mapping whose kind changed, lost keys or a changed list as a whole.
 */
export function overridesFrom(base, value, prefix = "") {
  const out = {};
  for (const [k, v] of Object.entries(value || {})) {
    const path = prefix ? `${prefix}.${k}` : k;
    const b = base?.[k];
    if (same(b, v)) continue;
    const whole = !isObj(v) || !isObj(b) || v.kind !== b.kind || Object.keys(b).some((x) => !(x in v));
    if (whole) out[path] = v;
    else Object.assign(out, overridesFrom(b, v, path));
  }
  return out;
}

/**
 * The name a job gets while the user has not typed one: the preset's name, with the speed it
 * ends with replaced by the form's speed, "-flexible" / "-rigid" when the body models changed and
 * "-edited" when anything else but the run length (or the name and description) did.
 */
export function followingName(baseName, base, value) {
  let name = String(baseName || "scenario");
  if (!base) return name;
  const changed = Object.keys(overridesFrom(base, value)).filter((k) => !["name", "description", "duration_s", "distance_m"].includes(k));
  const speed = value.speed_kmh;
  if (changed.includes("speed_kmh") && typeof speed === "number") {
    const tail = `-${String(base.speed_kmh)}`;
    name = name.endsWith(tail) ? `${name.slice(0, -tail.length)}-${speed}` : `${name}-${speed}kmh`;
  }
  const model = (v) => [v?.bodies?.carbody?.model, v?.bodies?.frames?.model];
  const [bm, vm] = [model(base), model(value)];
  if (!same(bm, vm)) name += vm.includes("flexible") ? "-flexible" : "-rigid";
  const rest = changed.filter((k) => k !== "speed_kmh" && !/^bodies\.(carbody|frames)(\.model)?$/.test(k));
  if (rest.length) name += "-edited";
  return name.slice(0, 80);
}

/** A scenario text → full scenario (fetching the preset it starts from, if any). */
export async function resolveScenario(data) {
  if (data === null || typeof data !== "object" || Array.isArray(data)) throw new Error("the file must hold a mapping (a scenario), not a list or a value");
  if (data.scenario && typeof data.scenario === "object") data = data.scenario; // a JobCreate body
  if (!data.preset) return data;
  const { preset, ...rest } = data;
  const base = await api.preset(preset);
  return mergeScenario(base, rest);
}

export default async function render(main, ctx) {
  ctx.title("New job");
  const q = ctx.query;
  main.append(h("h1", {}, "New job"), loading("Loading the scenario schema and presets…"));
  let schema;
  let presets;
  let initial;
  let startLabel;
  let base = null; // {preset, scenario}: what the form started from, the base of the overrides
  try {
    [schema, presets] = await Promise.all([
      cached("schema", api.scenarioSchema), cached("presets", api.presets)]);
    if (q.from) {
      initial = await api.jobScenario(q.from);
      startLabel = `a copy of job ${q.from.slice(0, 8)}`;
      const src = await api.job(q.from).catch(() => null);
      if (src?.preset && presets.some((p) => p.name === src.preset)) base = { preset: src.preset, scenario: await cached(`preset:${src.preset}`, () => api.preset(src.preset)) };
    } else {
      const name = q.preset && presets.some((p) => p.name === q.preset) ? q.preset : (presets.find((p) => p.name === DEFAULT_PRESET) || presets[0])?.name;
      initial = await cached(`preset:${name}`, () => api.preset(name));
      startLabel = `preset ${name}`;
      base = { preset: name, scenario: initial };
    }
  } catch (err) {
    setChildren(main, h("h1", {}, "New job"), errorBox(err, "The scenario form could not be prepared"));
    return undefined;
  }
  if (ctx.signal.aborted) return undefined;

  const msg = h("div", { id: "submit-message", "aria-live": "polite" });
  const form = new SchemaForm(schema, initial, { onChange: () => { yamlDirty = false; followName(); estimate.schedule(); } });
  // the job name follows the edits until the user types one
  let nameTyped = !!q.from;
  // (capture: before the form's own listener reports the change)
  form.el.addEventListener("input", (e) => { if (e.target.id === "f-name") nameTyped = true; }, true);
  function followName() {
    if (nameTyped || !base) return;
    const name = followingName(base.preset, base.scenario, form.value);
    if (name !== form.value.name) form.setField(["name"], name);
  }
  const estimate = estimatePanel(() => form.value, ctx.signal, () => form.el.querySelectorAll('[aria-invalid="true"]').length);
  let yamlDirty = false;

  // -- start from ------------------------------------------------------------------------------
  const presetSel = h("select", { id: "preset-select" },
    presets.map((p) => h("option", { value: p.name, selected: startLabel === `preset ${p.name}` }, p.name)));
  const presetDesc = h("p", { class: "help", id: "preset-desc" });
  const showDesc = () => {
    presetDesc.textContent = presets.find((p) => p.name === presetSel.value)?.description || "";
  };
  presetSel.addEventListener("change", showDesc);
  showDesc();
  const startInfo = h("p", { class: "small muted", "aria-live": "polite" }, `Form filled from ${startLabel}.`);
  const loadPreset = h("button", { type: "button", class: "btn", onclick: async () => {
    loadPreset.disabled = true;
    try {
      const sc = await cached(`preset:${presetSel.value}`, () => api.preset(presetSel.value));
      base = { preset: presetSel.value, scenario: sc };
      nameTyped = false;
      form.setValue(sc);
      estimate.schedule();
      editor.value = toYaml(sc);
      startInfo.textContent = `Form filled from preset ${presetSel.value}.`;
      replaceQuery({ preset: presetSel.value });
      setChildren(msg);
    } catch (err) {
      setChildren(msg, errorBox(err, "Could not load the preset"));
    } finally {
      loadPreset.disabled = false;
    }
  } }, "Load preset");

  // -- YAML / JSON editor ------------------------------------------------------------------------
  const editor = h("textarea", { id: "scenario-text", class: "editor", spellcheck: "false", "aria-describedby": "editor-help", oninput: () => { yamlDirty = true; } });
  editor.value = toYaml(initial);
  const fileIn = h("input", { type: "file", id: "scenario-file", accept: ".yaml,.yml,.json,application/json,text/yaml", class: "sr-only", onchange: async () => {
    const f = fileIn.files?.[0];
    if (!f) return;
    editor.value = await f.text();
    yamlDirty = true;
    setChildren(editorMsg, notice("info", null, `Loaded ${f.name}. Apply it to the form or submit it as it is.`));
    fileIn.value = "";
  } });
  const editorMsg = h("div", { "aria-live": "polite" });
  async function parseEditor() {
    try {
      const data = parseYamlOrJson(editor.value);
      const sc = await resolveScenario(data);
      const named = isObj(data) ? (isObj(data.scenario) ? data.scenario : data) : {};
      base = typeof named.preset === "string" ? { preset: named.preset, scenario: await cached(`preset:${named.preset}`, () => api.preset(named.preset)) } : null;
      if ("name" in named) nameTyped = true;
      return sc;
    } catch (err) {
      setChildren(editorMsg, err instanceof ApiError ? errorBox(err, "The preset named in the text could not be loaded") : notice("error", "The text is not a valid scenario file", h("p", {}, err.message)));
      throw err;
    }
  }

  const t = tabs([{ id: "form", label: "Form" }, { id: "text", label: "YAML / JSON" }], (id, panel) => {
    if (id === "form") panel.append(form.el);
    else {
      panel.append(
        h("p", { id: "editor-help", class: "help" }, "Paste or upload a scenario in YAML or JSON. It may start from a preset (", h("code", {}, "preset: paper-metro"), ") and give only what differs."),
        h("div", { class: "actions" },
          h("label", { class: "btn", for: "scenario-file" }, "Upload file…"), fileIn,
          h("button", { type: "button", class: "btn", onclick: async () => {
            try {
              const sc = await parseEditor();
              form.setValue(sc);
              estimate.schedule();
              setChildren(editorMsg, notice("info", null, "Applied to the form."));
              yamlDirty = false;
              t.select("form", true);
            } catch { /* shown */ }
          } }, "Apply to form"),
          h("button", { type: "button", class: "btn", onclick: () => saveFile(`${slug(form.value.name)}.yaml`, editor.value, "text/yaml") }, "Download as YAML")),
        h("label", { for: "scenario-text", class: "sr-only" }, "Scenario text"), editor, editorMsg);
    }
  }, { label: "Scenario editor" });
  t.onSelect = (id) => {
    if (id === "text" && !yamlDirty) editor.value = toYaml(form.value);
  };

  // -- submit ------------------------------------------------------------------------------------
  const reuse = h("input", { type: "checkbox", id: "reuse", checked: true });
  const submitBtn = h("button", { type: "submit", class: "btn btn-primary", id: "submit-job" }, "Submit job");
  const checkBtn = h("button", { type: "button", class: "btn", id: "check-job" }, "Check");

  function fromText() {
    return t.el.querySelector('[role="tab"][aria-selected="true"]')?.id === "tab-text";
  }

  async function currentScenario() {
    if (fromText() && yamlDirty) {
      const sc = await parseEditor();
      form.setValue(sc);
      estimate.schedule();
      yamlDirty = false;
    }
    return form.value;
  }

  function showServerError(err, title) {
    const items = err.items || [];
    if (err.status === 422 && items.length) {
      t.select("form", true);
      const unmatched = form.setServerErrors(items);
      const extra = [];
      const dtSuggested = err.body?.dt_suggested;
      if (dtSuggested) {
        extra.push(h("button", { type: "button", class: "btn btn-small", id: "use-dt", onclick: () => {
          form.value.solver = { ...(form.value.solver || {}), dt: dtSuggested };
          form.setValue(form.value);
          estimate.schedule();
          setChildren(msg, notice("info", null, `solver.dt set to ${dtSuggested} s; submit again.`));
        } }, `Use solver.dt = ${dtSuggested} s`));
      }
      setChildren(msg, notice("error", "The server rejected the scenario", h("p", {}, `${items.length} problem${items.length > 1 ? "s" : ""}; ${unmatched.length ? "see the list above the form" : "each is shown at its field"}.`), ...extra));
    } else setChildren(msg, errorBox(err, title));
  }

  /**
   * Check and Submit alike: read the scenario (from the text when it was edited), stop at the
   * problems the browser finds (marked at their fields), then run `send(scenario)` with `button`
   * disabled; the server's 422 items are shown at the fields they name, other errors under
   * `failTitle`.
   */
  async function withScenario(button, { pending, failTitle }, send) {
    setChildren(msg);
    let sc;
    try {
      sc = await currentScenario();
    } catch {
      return; // the editor shows why
    }
    const problems = form.validateAll(true);
    if (problems.length) {
      t.select("form", true);
      setChildren(msg, notice("error", `${problems.length} problem${problems.length > 1 ? "s" : ""} to fix first`, "Each is marked at its field."));
      form.focusField(problems[0].path);
      return;
    }
    button.disabled = true;
    const stopWaiting = pending ? explainWait(pending) : () => {};
    try {
      await send(sc);
    } catch (err) {
      showServerError(err, failTitle);
    } finally {
      stopWaiting();
      button.disabled = false;
    }
  }

  /**
   * While a request is pending: the pending text, the time so far and – while the service
   * compiles the solver (GET /health `solver`) – that it does, with its estimate. Returns the
   * function that stops it.
   */
  function explainWait(pending) {
    const t0 = Date.now();
    let stopped = false;
    let solver = { compiling: false, estimate_s: null };
    const show = () => {
      if (stopped) return;
      const s = (Date.now() - t0) / 1000;
      setChildren(msg, loading(s < 2 ? pending : `${pending} (${Math.round(s)} s)`),
        solver.compiling ? waitNote({ id: "submit-compiling", title: "The service is compiling the solver – first run only",
          text: `The service checks the time step with the solver's kernels and is ${compilingText(solver)}; the job is queued as soon as it is done`,
          elapsed_s: s, estimate_s: solver.estimate_s, remaining: true }) : null);
    };
    const ask = async () => {
      solver = await solverState(ctx.signal);
      show();
    };
    ask();
    const tick = setInterval(show, 1000);
    const poll = setInterval(ask, 3000);
    return () => {
      stopped = true;
      clearInterval(tick);
      clearInterval(poll);
    };
  }

  /** The request body of a scenario: its preset and the overrides when the form started from
   * one (so the job records its preset), else the whole scenario. */
  function jobBody(sc) {
    if (!base) return { scenario: sc };
    return { preset: base.preset, overrides: overridesFrom(base.scenario, sc) };
  }

  checkBtn.addEventListener("click", () => withScenario(checkBtn, { failTitle: "The scenario could not be checked" }, async (sc) => {
    try {
      const res = await api.validateScenario(jobBody(sc));
      const pf = res?.preflight;
      setChildren(msg, notice("info", "The server accepts this scenario", pf?.stability ? `${stepText(pf.stability)}; ${pf.n_dof} degrees of freedom; output at ${pf.output_rate_hz} Hz.` : null));
    } catch (err) {
      if (!isMissingEndpoint(err)) throw err;
      setChildren(msg, notice("info", "No problems found", "Checked against the scenario schema in the browser; the server checks again (with the time-step stability) when you submit."));
    }
  }));

  const submitForm = h("form", { class: "stack", novalidate: true, onsubmit: (e) => {
    e.preventDefault();
    withScenario(submitBtn, { pending: "Submitting…", failTitle: "The job could not be submitted" }, async (sc) => {
      const job = await api.submitJob({ ...jobBody(sc), reuse: reuse.checked });
      setChildren(msg, notice("info", job.reused ? "Results reused" : "Job submitted", `Job ${job.id} – opening it…`));
      go(`/jobs/${job.id}`);
    });
  } },
  h("label", { class: "check" }, reuse, "Reuse stored results of an identical scenario"),
  h("div", { class: "actions" }, submitBtn, checkBtn), msg);

  main.replaceChildren(
    h("h1", {}, "New job"),
    h("div", { class: "layout-side" },
      h("div", {}, estimate.el, t.el),
      h("aside", { class: "side", "aria-label": "Start and submit" },
        h("section", { class: "card" },
          h("h2", { class: "h3" }, "Start from"),
          h("label", { for: "preset-select" }, "Preset"), h("div", { class: "input-row" }, presetSel, loadPreset), presetDesc, startInfo),
        h("section", { class: "card" }, h("h2", { class: "h3" }, "Submit"),
          h("p", { class: "help" }, "Values are checked as you type against the schema's ranges; the server's own messages appear at the field they concern."),
          submitForm))));
  estimate.now();
  return undefined;
}

/** The time step the server chose or checked, with its stability margin, in words. */
function stepText(stab) {
  const limit = `stable up to ${stab.dt_max?.toExponential(2)} s`;
  if (stab.dt === undefined) return `Time step ${limit}`;
  const how = stab.auto ? "chosen automatically" : "as given";
  return `Time step ${stab.dt.toExponential(3)} s (${how}; ${limit}, margin ${stab.margin?.toFixed(2)})`;
}
