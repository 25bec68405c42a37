// REST client of the flexride service (/api/v1). Every call returns parsed JSON or throws an
// ApiError that carries the HTTP status, the one-line message and the field problems (422).

export const API = "/api/v1";

export class ApiError extends Error {
  /**
   * @param {string} message one line, for people
   * @param {number} status HTTP status (0: the service could not be reached)
   * @param {Array<{loc: Array<string|number>, msg: string, type?: string, ctx?: object}>} items
   * @param {object} body the whole error body
   */
  constructor(message, status, items = [], body = null) {
    super(message);
    this.name = "ApiError";
    this.status = status;
    this.items = items;
    this.body = body;
  }

  /** True when the service did not answer at all (down, network). */
  get unreachable() {
    return this.status === 0;
  }
}

const listeners = new Set();
/** Subscribe to reachability changes: fn(true | false). */
export function onReachability(fn) {
  listeners.add(fn);
  return () => listeners.delete(fn);
}
let lastReachable = true;
function reachable(ok) {
  if (ok !== lastReachable) {
    lastReachable = ok;
    for (const fn of listeners) fn(ok);
  }
}

function qs(params) {
  const u = new URLSearchParams();
  for (const [k, v] of Object.entries(params || {})) {
    if (v === undefined || v === null || v === "") continue;
    if (Array.isArray(v)) v.forEach((x) => u.append(k, String(x)));
    else u.append(k, String(v));
  }
  const s = u.toString();
  return s ? `?${s}` : "";
}

/** Token for mutating requests when the service has one (stored by the settings prompt). */
function authHeaders() {
  const t = localStorage.getItem("flexride.token");
  return t ? { Authorization: `Bearer ${t}` } : {};
}

/**
 * Fetch JSON from the API.
 * @param {string} path path below /api/v1 (or absolute when it starts with /api)
 * @param {{method?: string, body?: any, raw?: Blob|ArrayBuffer, contentType?: string,
 *   params?: object, signal?: AbortSignal, timeout?: number, withStatus?: boolean}} opts
 *   `body` is sent as JSON, `raw` as it is (an upload); with `withStatus`, a success resolves to
 *   {status, body, retryAfter} (for endpoints that answer 202 while they work)
 */
export async function request(path, opts = {}) {
  const url = (path.startsWith("/api") ? path : API + path) + qs(opts.params);
  const init = { method: opts.method || "GET", headers: { Accept: "application/json" } };
  if (opts.body !== undefined) {
    init.body = JSON.stringify(opts.body);
    init.headers["Content-Type"] = "application/json";
  } else if (opts.raw !== undefined) { // uploaded data (a file's bytes), sent as they are
    init.body = opts.raw;
    init.headers["Content-Type"] = opts.contentType || "application/octet-stream";
  }
  if (init.method !== "GET") Object.assign(init.headers, authHeaders());
  const ctrl = new AbortController();
  const timer = setTimeout(() => ctrl.abort(new DOMException("timeout", "TimeoutError")),
    opts.timeout ?? 60000);
  if (opts.signal) {
    if (opts.signal.aborted) ctrl.abort(opts.signal.reason);
    else opts.signal.addEventListener("abort", () => ctrl.abort(opts.signal.reason), { once: true });
  }
  init.signal = ctrl.signal;
  let res;
  try {
    res = await fetch(url, init);
  } catch (err) {
    clearTimeout(timer);
    if (opts.signal?.aborted) throw err; // the caller gave up: not a service problem
    reachable(false);
    const why = err?.name === "TimeoutError" || ctrl.signal.reason?.name === "TimeoutError"
      ? "did not answer in time" : "cannot be reached";
    throw new ApiError(`The flexride service ${why} (${location.origin}). Is \`flexride serve\` running?`, 0);
  }
  clearTimeout(timer);
  reachable(true);
  if (res.status === 204) return null;
  let body = null;
  const text = await res.text();
  if (text) {
    try {
      body = JSON.parse(text);
    } catch {
      body = { detail: text.slice(0, 400) };
    }
  }
  if (!res.ok) {
    const items = Array.isArray(body?.detail) ? body.detail : [];
    let msg = body?.message || (typeof body?.detail === "string" ? body.detail : "") ||
      `${res.status} ${res.statusText}`;
    if (res.status >= 500 && res.status !== 503) msg = `Server error: ${msg}`;
    if (res.status === 401) msg = "This service needs an API token for changes (set it under ⚙ Token).";
    throw new ApiError(msg, res.status, items, body);
  }
  if (opts.withStatus) return { status: res.status, body, retryAfter: Number(res.headers.get("Retry-After")) || null };
  return body;
}

export const api = {
  health: (o) => request("/health", { timeout: 8000, ...o }),
  version: () => request("/version"),
  presets: () => request("/presets"),
  preset: (name) => request(`/presets/${encodeURIComponent(name)}`),
  scenarioSchema: () => request("/schemas/scenario"),
  paperPoints: () => request("/schemas/points"),
  studyPresets: () => request("/study-presets"),

  jobs: (params, o) => request("/jobs", { params, ...o }),
  job: (id, o) => request(`/jobs/${encodeURIComponent(id)}`, o),
  jobScenario: (id) => request(`/jobs/${encodeURIComponent(id)}/scenario`),
  submitJob: (body) => request("/jobs", { method: "POST", body }),
  cancelJob: (id) => request(`/jobs/${encodeURIComponent(id)}/cancel`, { method: "POST" }),
  deleteJob: (id) => request(`/jobs/${encodeURIComponent(id)}`, { method: "DELETE" }),

  summary: (id) => request(`/jobs/${encodeURIComponent(id)}/summary`),
  channels: (id) => request(`/jobs/${encodeURIComponent(id)}/channels`),
  series: (id, params, o) => request(`/jobs/${encodeURIComponent(id)}/series`, { params, ...o }),
  spectrum: (id, params, o) => request(`/jobs/${encodeURIComponent(id)}/spectrum`, { params, ...o }),
  psd: (id, params, o) => request(`/jobs/${encodeURIComponent(id)}/psd`, { params, ...o }),
  spectrogram: (id, params, o) =>
    request(`/jobs/${encodeURIComponent(id)}/spectrogram`, { params, ...o }),
  sperling: (id, params, o) => request(`/jobs/${encodeURIComponent(id)}/sperling`, { params, ...o }),
  correlation: (id, params, o) =>
    request(`/jobs/${encodeURIComponent(id)}/correlation`, { params, ...o }),
  downloadUrl: (id) => `${API}/jobs/${encodeURIComponent(id)}/download`,

  // a wheel or rail profile file: params {format: its extension, kind: "wheel" | "rail"}
  uploadProfile: (raw, params, o) => request("/profiles", { method: "POST", raw, params, ...o }),

  studies: (params, o) => request("/studies", { params, ...o }),
  study: (id, o) => request(`/studies/${encodeURIComponent(id)}`, o),
  submitStudy: (body) => request("/studies", { method: "POST", body }),
  cancelStudy: (id) => request(`/studies/${encodeURIComponent(id)}/cancel`, { method: "POST" }),
  deleteStudy: (id) => request(`/studies/${encodeURIComponent(id)}`, { method: "DELETE" }),

  // FE mesh and mode shapes: {status: 200, body: export} or {status: 202, body: build state,
  // retryAfter} while the server builds the model (see views/flexbody.js).
  feModel: (kind, params, o) =>
    request(`/fe/${encodeURIComponent(kind)}`, { params, withStatus: true, timeout: 30000, ...o }),
  fePairing: (params, o) => request("/fe/carbody/pairing", { params, withStatus: true, timeout: 30000, ...o }),
  jobFeModel: (id, kind, params, o) =>
    request(`/jobs/${encodeURIComponent(id)}/fe/${encodeURIComponent(kind)}`, { params, withStatus: true, timeout: 30000, ...o }),

  // Validation without creating a job: looked up in the OpenAPI document first (no 404 noise
  // from an older service), with a fallback in the view when it is missing.
  openapi: () => cached("openapi", () => request("/openapi.json")),
  validateScenario: async (body) => {
    const path = await findEndpoint("post", [/^\/api\/v1\/(jobs|scenarios?)\/(validate|check)$/]);
    if (!path) throw new ApiError("Not Found", 404);
    return request(path, { method: "POST", body, timeout: 30000 });
  },
};

/** The first path of the OpenAPI document matching one of `patterns` for `method`, or null. */
export async function findEndpoint(method, patterns) {
  let spec;
  try {
    spec = await api.openapi();
  } catch {
    return null;
  }
  for (const re of patterns) {
    for (const [path, ops] of Object.entries(spec.paths || {})) if (re.test(path) && ops[method]) return path;
  }
  return null;
}

/** True when an ApiError means "this endpoint does not exist in this service version". */
export function isMissingEndpoint(err) {
  return err instanceof ApiError && (err.status === 404 || err.status === 405) &&
    /not found|method not allowed/i.test(err.message);
}

// Small cache for immutable resources (schema, presets, finished results).
const cache = new Map();
/** Memoise a promise under `key` (dropped again when it fails). */
export function cached(key, fn) {
  if (!cache.has(key)) {
    const p = fn().catch((e) => {
      cache.delete(key);
      throw e;
    });
    cache.set(key, p);
  }
  return cache.get(key);
}
