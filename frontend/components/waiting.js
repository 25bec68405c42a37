// Honest waits: what the service is doing while the user waits, with an estimate from
// measurement and a progress bar where the work reports progress.
//
// The solver's state comes from GET /api/v1/health `solver: {state: "ready" | "compiling",
// estimate_s}` (a service without the field counts as ready): the numba kernels are compiled once
// per installation, by the service's workers at start-up or by the first job.

import { api } from "../api.js";
import { h, duration, progressBar } from "./dom.js";

/** The solver's state from the health answer: {compiling: boolean, estimate_s: number|null}. */
export function solverStateOf(health) {
  const s = health?.solver;
  return { compiling: s?.state === "compiling", estimate_s: typeof s?.estimate_s === "number" ? s.estimate_s : null };
}

/** Ask the service whether it is compiling the solver (never throws: unknown = ready). */
export async function solverState(signal) {
  try {
    return solverStateOf(await api.health({ signal }));
  } catch {
    return { compiling: false, estimate_s: null };
  }
}

/** "about 45 s" / "about 2 min 10 s" of an estimate, or "" when there is none. */
export function about(seconds) {
  return typeof seconds === "number" && Number.isFinite(seconds) && seconds > 0 ? `about ${duration(seconds)}` : "";
}

/** The line said while the solver compiles: "compiling the solver (first run only, about N s)",
 * N the seconds the service expects the compilation still to take. */
export function compilingText(state) {
  const est = about(state.estimate_s);
  return `compiling the solver (first run only${est ? `, ${est}` : ""})`;
}

/**
 * A note for a wait: a title, what happens, the time so far against the estimate, and a
 * progress bar when the work reports progress (fraction) – otherwise none, never a fake one.
 * `estimate_s` is the whole wait, or with `remaining` what is left of it (the solver's state).
 * @param {{id?: string, title: string, text: string, elapsed_s?: number, estimate_s?: number|null,
 *          remaining?: boolean, progress?: number|null, label?: string}} o
 */
export function waitNote(o) {
  const est = about(o.estimate_s);
  const so = typeof o.elapsed_s === "number" ? `${duration(o.elapsed_s)} so far` : "";
  const when = [so, est ? `${est} ${o.remaining ? "to go" : "in all"}` : ""].filter(Boolean).join("; ");
  return h("div", { class: "notice notice-info wait-note", role: "status", id: o.id || null },
    h("strong", {}, o.title),
    h("p", {}, o.text, when ? ` (${when}).` : ""),
    typeof o.progress === "number" ? progressBar(o.progress, o.label || o.title, "running") : null);
}
