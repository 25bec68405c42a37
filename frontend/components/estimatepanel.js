// Instant estimate: the frequency-domain comfort estimate (POST /api/v1/estimates) of the scenario
// being edited, asked again ~400 ms after each change (the request before is aborted). Whether the
// estimate applies is the service's answer (`refusal: "answer"`: 200 with applicable false and the
// reason for flange contact, a transient excitation, no random irregularity …); that, an FE model
// not built yet (409) or a busy service (503) is a note in the panel, never a form error.

import { loadPaperPoints, pointCatalogue, pointTag } from "./points.js";
import { request } from "../api.js";
import { h, setChildren, fmt, fixed, notice } from "./dom.js";

const PATH = "/estimates";
const DELAY_MS = 400;

/** The comfort table's ISO 2631 weighting of a direction (settings.iso: {z: ["Wb", "Wk"], …}). */
function isoWeight(comfort, d) {
  return comfort.settings?.iso?.[d]?.[0] || (d === "z" ? "Wb" : "Wd");
}

/** Table columns: label, unit, value of a point of the comfort table. */
function columns(comfort) {
  const dir = (p, d) => p.directions?.[d] || {};
  const wz = isoWeight(comfort, "z");
  const wy = isoWeight(comfort, "y");
  return [
    { label: "rms z", unit: "m/s²", value: (p) => fmt(dir(p, "z").rms) },
    { label: "rms y", unit: "m/s²", value: (p) => fmt(dir(p, "y").rms) },
    { label: `a_w z (${wz})`, unit: "m/s²", value: (p) => fmt(dir(p, "z").iso2631?.[wz]) },
    { label: `a_w y (${wy})`, unit: "m/s²", value: (p) => fmt(dir(p, "y").iso2631?.[wy]) },
    { label: "Sperling z", unit: "–", value: (p) => fixed(dir(p, "z").sperling) },
    { label: "Sperling y", unit: "–", value: (p) => fixed(dir(p, "y").sperling) },
    { label: "N_MV", unit: "–", value: (p) => fixed(p.nmv) },
  ];
}

function table(comfort) {
  const cols = columns(comfort);
  return h("div", { class: "table-wrap" }, h("table", { class: "data estimate-table", id: "estimate-table" },
    h("caption", { class: "sr-only" }, "Estimated comfort per point"),
    h("thead", {}, h("tr", {}, h("th", { scope: "col" }, "Point"),
      cols.map((c) => h("th", { scope: "col", class: "num" }, c.label, h("span", { class: "unit-head" }, ` (${c.unit})`))))),
    h("tbody", {}, (comfort.points || []).map((p) => h("tr", { dataset: { point: p.name } },
      h("th", { scope: "row" }, pointTag(p.name, pointCatalogue())), cols.map((c) => h("td", { class: "num" }, c.value(p))))))));
}

/** The flags (where the estimate may not hold), collapsed when there are several. */
export function flagList(flags) {
  if (!flags?.length) return h("p", { class: "small muted", id: "estimate-flags" }, "No flags: the linear estimate holds for this scenario.");
  return h("details", { class: "estimate-flags", id: "estimate-flags", open: flags.length <= 2 },
    h("summary", {}, `⚠ ${flags.length} flag${flags.length > 1 ? "s" : ""}: where the estimate may not hold`),
    h("ul", { class: "small" }, flags.map((f) => h("li", {}, f))));
}

/** The panel's note for a failed estimate. */
function failureNote(err) {
  const reason = err.items?.[0]?.msg || err.body?.message || err.message; // the item: short
  if (err.status === 422) {
    const linear = err.body?.reason || err.items?.some((i) => i.type === "LinearisationError");
    return notice("warn", null, linear ? `No linear estimate: ${reason}` : `No estimate: ${reason}`);
  }
  if (err.status === 409) return notice("warn", null, `No estimate yet: ${reason}`);
  if (err.status === 503) return notice("warn", null, `No estimate now: ${reason} The next change asks again.`);
  return notice("warn", null, `No estimate: ${reason}`);
}

/**
 * The panel. `getScenario()` gives the scenario to estimate; call `schedule()` after each
 * change. While `invalidFields()` counts fields the form marks as invalid, the panel waits
 * (the form shows why). The panel stops asking once `signal` (the view's) is aborted.
 * @returns {{el: HTMLElement, schedule: () => void, now: () => Promise<void>}}
 */
export function estimatePanel(getScenario, signal, invalidFields = () => 0) {
  loadPaperPoints().catch(() => {}); // descriptions of the points for the table (tooltips)
  const status = h("p", { class: "small muted estimate-status", id: "estimate-status", "aria-live": "polite" });
  const body = h("div", { class: "estimate-body" });
  const el = h("details", { class: "card estimate-panel", id: "estimate-panel", open: true, dataset: { state: "idle" } },
    h("summary", {}, h("span", { class: "h3" }, "Instant estimate"), h("span", { class: "small muted" }, " frequency domain, linearised model: no job needed")),
    status, body);
  let timer = null;
  let ctrl = null;
  let seq = 0;

  function setState(state, text) {
    el.dataset.state = state;
    status.textContent = text;
  }

  async function now() {
    clearTimeout(timer);
    if (ctrl) ctrl.abort();
    if (signal?.aborted) return;
    const my = ++seq;
    const sc = getScenario();
    const bad = invalidFields();
    if (bad) {
      refused(notice("info", null, `The estimate waits for the form: ${bad} field${bad > 1 ? "s" : ""} marked.`), "waiting");
      return;
    }
    ctrl = new AbortController();
    const t0 = performance.now();
    setState("loading", "Estimating…");
    body.classList.add("stale");
    try {
      const res = await request(PATH, { method: "POST", body: { scenario: sc, refusal: "answer" }, signal: ctrl.signal, timeout: 60000 });
      if (my !== seq) return;
      if (res.applicable === false) refused(notice("warn", null, `No linear estimate: ${res.reasons?.[0]?.msg || res.message}`));
      else show(res, (performance.now() - t0) / 1000);
    } catch (err) {
      if (my !== seq || err?.name === "AbortError" || signal?.aborted) return;
      refused(failureNote(err), err.status === 422 ? "refused" : "error");
    }
  }

  function refused(note, state = "refused") {
    el.removeAttribute("data-speed");
    setChildren(body, h("div", { id: "estimate-note" }, note));
    body.classList.remove("stale");
    setState(state, "");
  }

  function show(res, seconds) {
    const c = res.comfort;
    el.dataset.speed = String(c.speed_kmh);
    setChildren(body, table(c), h("p", { class: "small muted", id: "estimate-method" }, `Method: ${c.method}.`), flagList(c.flags));
    body.classList.remove("stale");
    setState("ready", `${fmt(c.speed_kmh)} km/h, ${c.track} track, answered in ${fmt(seconds, 2)} s.`);
  }

  function schedule() {
    clearTimeout(timer);
    if (ctrl) ctrl.abort(); // the answer would be stale
    setState("pending", "Estimating…");
    timer = setTimeout(now, DELAY_MS);
  }

  signal?.addEventListener("abort", () => {
    clearTimeout(timer);
    if (ctrl) ctrl.abort();
  }, { once: true });
  return { el, schedule, now };
}
