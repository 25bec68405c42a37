// The dashboard shell: hash router, navigation, service status and the "server down" banner.
// Views are ES modules under views/ loaded on demand; each exports
//   default async function render(main, ctx) → optional cleanup function
// with ctx = {params, query, signal, title(text)}.

import { api, onReachability } from "./api.js";
import { h, setChildren, errorBox } from "./components/dom.js";
import { parseHash } from "./components/nav.js";

const ROUTES = [
  { re: /^\/?$/, view: "jobs", nav: "jobs" },
  { re: /^\/jobs\/?$/, view: "jobs", nav: "jobs" },
  { re: /^\/new\/?$/, view: "newjob", nav: "new" },
  { re: /^\/studies\/new\/?$/, view: "newstudy", nav: "newstudy" },
  { re: /^\/studies\/?$/, view: "jobs", nav: "jobs", query: { tab: "studies" } },
  { re: /^\/jobs\/([^/?]+)\/?$/, view: "job", nav: "jobs", keys: ["id"] },
  { re: /^\/studies\/([^/?]+)\/?$/, view: "study", nav: "jobs", keys: ["id"] },
  { re: /^\/compare\/?$/, view: "compare", nav: "compare" },
  { re: /^\/flex\/?$/, view: "flexbody", nav: "flex" },
  { re: /^\/contact\/?$/, view: "contact", nav: "contact" },
  { re: /^\/estimate\/?$/, view: "estimate", nav: "estimate" },
];

const main = document.getElementById("main");
let current = { cleanup: null, ctrl: null };

async function route() {
  const { path, query } = parseHash();
  const match = ROUTES.map((r) => ({ r, m: path.match(r.re) })).find((x) => x.m);
  if (current.ctrl) current.ctrl.abort();
  if (typeof current.cleanup === "function") {
    try {
      current.cleanup();
    } catch (e) {
      console.warn(e);
    }
  }
  current.cleanup = null;
  const ctrl = new AbortController();
  current.ctrl = ctrl;
  for (const a of document.querySelectorAll("[data-nav]")) {
    if (match && a.dataset.nav === match.r.nav) a.setAttribute("aria-current", "page");
    else a.removeAttribute("aria-current");
  }
  if (!match) {
    document.title = "Not found – flexride";
    setChildren(main, h("h1", {}, "Page not found"), h("p", {}, "There is no view at ", h("code", {}, path), ". ", h("a", { href: "#/" }, "Back to the jobs.")));
    focusMain();
    return;
  }
  const params = Object.fromEntries((match.r.keys || []).map((k, i) => [k, decodeURIComponent(match.m[i + 1])]));
  main.setAttribute("aria-busy", "true");
  try {
    const mod = await import(`./views/${match.r.view}.js`);
    if (ctrl.signal.aborted) return;
    main.replaceChildren();
    const ctx = {
      params, query: { ...(match.r.query || {}), ...query }, signal: ctrl.signal,
      title: (t) => { document.title = `${t} – flexride`; },
    };
    const cleanup = await mod.default(main, ctx);
    if (ctrl.signal.aborted) {
      if (typeof cleanup === "function") cleanup();
      return;
    }
    current.cleanup = cleanup;
  } catch (err) {
    if (ctrl.signal.aborted) return;
    console.warn(err);
    setChildren(main, h("h1", {}, "This view could not be shown"), errorBox(err));
  } finally {
    if (!ctrl.signal.aborted) main.removeAttribute("aria-busy");
  }
  focusMain();
}

function focusMain() {
  // Move focus to the page heading for screen readers and keyboard users (not on first load).
  if (!focusMain.done) {
    focusMain.done = true;
    return;
  }
  const h1 = main.querySelector("h1");
  if (h1) {
    h1.tabIndex = -1;
    h1.focus({ preventScroll: true });
  } else main.focus({ preventScroll: true });
  window.scrollTo(0, 0);
}

// -- service status ---------------------------------------------------------------------------

const statusEl = document.getElementById("service-status");
const banner = document.getElementById("banner");
let healthTimer = null;

async function checkHealth() {
  clearTimeout(healthTimer);
  try {
    const hl = await api.health();
    statusEl.className = `service-status ok-${hl.status}`;
    if (hl.view === "public") { // a service with a token shows its details to operators only
      const notOk = Object.entries(hl.components || {}).filter(([, state]) => state !== "ok");
      statusEl.textContent = [`Service ${hl.status}`, ...notOk.map(([name, state]) => `${name} ${state}`)].join(" · ");
      statusEl.title = "";
      const v = await api.version();
      document.getElementById("version").textContent = `flexride ${v.flexride}`;
    } else {
      const live = (hl.workers || []).filter((w) => w.alive).length;
      statusEl.textContent = `Service ${hl.status} · ${hl.runner} runner · ${live} worker${live === 1 ? "" : "s"}`;
      statusEl.title = hl.api?.detail || "";
      document.getElementById("version").textContent = `flexride ${hl.version}`;
    }
    healthTimer = setTimeout(checkHealth, 30000);
  } catch (err) {
    if (err.status === 503 && err.body) {
      statusEl.className = "service-status ok-degraded";
      statusEl.textContent = `Service ${err.body.status || "degraded"}: ${err.body.database?.detail || ""}`;
    } else {
      statusEl.className = "service-status ok-down";
      statusEl.textContent = "Service unreachable";
    }
    healthTimer = setTimeout(checkHealth, 5000);
  }
}

onReachability((ok) => {
  if (ok) {
    const wasDown = !banner.hidden;
    banner.hidden = true;
    checkHealth();
    if (wasDown) route(); // show the current view again with fresh data
  } else {
    setChildren(banner,
      h("span", {}, "The flexride service cannot be reached. Start it with ", h("code", {}, "flexride serve"), "; this page retries every 5 s. "),
      h("button", { type: "button", class: "btn btn-small", onclick: () => checkHealth() }, "Retry now"));
    banner.hidden = false;
    statusEl.className = "service-status ok-down";
    statusEl.textContent = "Service unreachable";
    clearTimeout(healthTimer);
    healthTimer = setTimeout(checkHealth, 5000);
  }
});

// -- API token (services started with FLEXRIDE_API_TOKEN) -------------------------------------

document.getElementById("token-btn").addEventListener("click", () => {
  const input = h("input", { id: "token-input", type: "password", autocomplete: "off", value: localStorage.getItem("flexride.token") || "" });
  const dlg = h("dialog", { class: "dialog", "aria-labelledby": "token-title" },
    h("form", { method: "dialog" },
      h("h2", { id: "token-title" }, "API token"),
      h("p", {}, "Needed only when the service was started with FLEXRIDE_API_TOKEN. Kept in this browser (local storage)."),
      h("label", { for: "token-input" }, "Bearer token"), input,
      h("div", { class: "actions" },
        h("button", { class: "btn btn-primary", value: "save" }, "Save"),
        h("button", { class: "btn", value: "clear" }, "Clear"),
        h("button", { class: "btn btn-quiet", value: "cancel" }, "Cancel"))));
  dlg.addEventListener("close", () => {
    if (dlg.returnValue === "save") localStorage.setItem("flexride.token", input.value.trim());
    if (dlg.returnValue === "clear") localStorage.removeItem("flexride.token");
    dlg.remove();
  });
  document.body.append(dlg);
  dlg.showModal();
});

window.addEventListener("hashchange", route);
route().then(warmLater);
checkHealth();
// Load Plotly (4.6 MB, about a second of script evaluation) once the first view is on screen
// and the browser is idle, so that plots appear at once later.
const warm = () => import("./components/plot.js").then((m) => m.loadPlotly()).catch(() => {});
let warmed = false;
function warmLater() {
  if (warmed) return;
  warmed = true;
  setTimeout(() => (window.requestIdleCallback ? requestIdleCallback(warm, { timeout: 2000 }) : warm()), 1500);
}
